//! Commands: everything that changes a simulation is a [`Command`] queued on every lane with
//! [`crate::SimLoop::push`] and applied at the next tick boundary, so recordings and replays see
//! it. An aim is commands too: each lane solves its own shot and gets its own `launch` and
//! `fire`. While replaying every command is refused; the refusal says why.

use crate::command::Command;
use crate::scene::check_integrator;
use crate::world::World;

use super::{AimNote, Change, Session, SessionError};

/// The shot on `arc` at target `target` for this world's integrator, step, forces and launcher,
/// launched at its current tick (a moving target where it is now).
fn aim_lane(
    world: &World,
    target: usize,
    arc: crate::exact::Arc,
) -> Result<crate::firing::Shot, SessionError> {
    use crate::firing::{self, Mode, Range, ShotKind};
    let scene = world
        .scene()
        .edit()
        .integrator(world.integrator())
        .forces(world.forces().clone())
        .launcher(*world.launcher())
        .build()
        .map_err(SessionError::Scene)?;
    let t = world.contacts().targets[target];
    let now = crate::contact::Target {
        center: t.center_at(world.tick() as f64 * world.dt()),
        ..t
    };
    let range = Range::new(&scene, now);
    let shots =
        firing::solve(&range, Mode::Speed(scene.launcher().speed)).map_err(SessionError::Firing)?;
    let kind = ShotKind::Arc(arc);
    let shot = shots
        .into_iter()
        .find(|s| s.kind == kind)
        .ok_or(SessionError::NoShot(kind))?;
    match shot.blocked {
        Some(b) => Err(SessionError::Blocked(kind, b)),
        None => Ok(shot),
    }
}

impl Session {
    /// While replaying, refuses `change` (it would part the run from its recording).
    pub(super) fn refuse_while_replaying(&self, change: Change) -> Result<(), SessionError> {
        match self.replay.current {
            Some(_) => Err(SessionError::Replaying(change)),
            None => Ok(()),
        }
    }

    /// Queues `command` for the next tick of every lane. An integrator switch is refused in
    /// compare mode (each lane is its integrator); every command is refused while replaying.
    pub fn push(&mut self, command: Command) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::Command(command))?;
        if let (Command::SetIntegrator(_), true) = (command, self.is_comparing()) {
            return Err(SessionError::IntegratorPerLane);
        }
        if let Command::SetIntegrator(i) = command {
            check_integrator(i, self.lanes[0].sim.world.forces())
                .map_err(SessionError::Integrator)?;
        }
        self.take_over_future();
        for lane in &mut self.lanes {
            lane.sim.push(command);
            lane.pushed += 1;
        }
        Ok(())
    }

    /// Aims every lane at the scene's target `target` on `arc` and fires: each lane solves the
    /// shot for its own integrator, dt and substeps with [`crate::firing::solve`] (speed from
    /// its launcher, the target where it is at this tick), then gets its own `launch` command
    /// with the solved angles and a `fire`, so recordings and replays see them. A lane whose
    /// solve fails fires nothing; its note says why. Refused while replaying, and for a target
    /// the scene does not have.
    pub fn aim(&mut self, arc: crate::exact::Arc, target: usize) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::Aim)?;
        if self.setup.scene.targets().get(target).is_none() {
            return Err(SessionError::NoTargetToAim(target));
        }
        self.take_over_future();
        for lane in &mut self.lanes {
            let world = &lane.sim.world;
            let outcome = aim_lane(world, target, arc);
            // The shot's id: the next one, after every body the queued commands spawn.
            let spawned: u64 = lane
                .sim
                .queued()
                .map(|c| match c.command {
                    Command::Fire | Command::Spawn(_) => 1,
                    Command::Reset => {
                        let s = world.scene();
                        s.bodies().len() as u64 + s.volley().map_or(0, |v| u64::from(v.count))
                    }
                    _ => 0,
                })
                .sum();
            let body = crate::world::BodyId(world.state().next_id + spawned);
            if let Ok(shot) = &outcome {
                lane.sim.push(Command::SetLaunch {
                    speed: Some(shot.speed),
                    elevation_deg: Some(shot.elevation_deg),
                    azimuth_deg: Some(shot.azimuth_deg),
                    position: None,
                });
                lane.sim.push(Command::Fire);
                lane.pushed += 2;
            }
            lane.aim = Some(AimNote {
                target,
                tick: lane.sim.world.tick(),
                body,
                outcome,
            });
        }
        Ok(())
    }

    /// Puts the bodies back with a `Reset` command (recordable; the tick keeps counting), which
    /// also lifts a divergence: the stopped lanes run again and a pause the divergence caused
    /// ends. In compare mode after a divergence it restarts every lane at tick 0 instead, so
    /// the lanes stay on one tick. Refused while replaying.
    pub fn reset(&mut self) -> Result<(), SessionError> {
        self.refuse_while_replaying(Change::Reset)?;
        let stopped = self.lanes.iter().any(|l| l.stopped.is_some());
        let resume = stopped && self.clock.paused_by_alarm;
        let done = if stopped && self.is_comparing() {
            self.restart(None, "reset after a divergence in compare mode")
        } else {
            for lane in &mut self.lanes {
                lane.stopped = None;
            }
            self.push(Command::Reset)
        };
        if resume {
            self.set_paused(false);
        }
        done
    }
}
