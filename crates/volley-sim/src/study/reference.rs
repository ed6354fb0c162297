//! The references a study measures against, best first:
//!
//! 1. **Closed form** ([`crate::exact::closed_form`]) at every sampled tick, when the scene has
//!    no contacts and every body's forces have one (any mix of gravity, constant force, linear
//!    drag and a zero-rest-length spring with any damping; or a lone point mass, unless a body
//!    on a radial orbit reaches its centre).
//! 2. **Exact flow**: the scene run with [`Integrator::Exact`] at the same dt, when every force
//!    term has a closed form but the scene has contacts: each step evaluates the closed form and
//!    impacts are solved inside the step, so the whole piecewise trajectory is exact to rounding.
//! 3. **RK4 reference**: the scene run with RK4 at `R` substeps per tick, `R >= 16` chosen so
//!    the reference step is at most 1/16 of the finest dt studied. Its own error is estimated
//!    from a second run at `R / 2` (twice its step): for a fourth-order method the error of the
//!    finer run is about `|fine - coarse| / 15` (Richardson).
//!
//! Every reference runs through [`SimLoop`] like the runs it judges, and samples the same ticks.

use glam::DVec3;

use crate::clock::VirtualClock;
use crate::contact::Event;
use crate::integrate::{BodyState, Integrator};
use crate::scene::Scene;
use crate::sim_loop::{ObserverError, SimLoop, TickObserver};
use crate::world::World;

use super::StudyError;

/// Which reference was used, and what it is worth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceKind {
    /// `exact::closed_form` at each tick time.
    ClosedForm,
    /// The `exact` integrator at the same dt, impacts solved inside the step.
    ExactFlow,
    /// RK4 at `substeps` per tick (step `step` s); `error_estimate` (m) is the Richardson
    /// estimate of its largest position error.
    Rk4 {
        /// Substeps per tick.
        substeps: u32,
        /// Its step (s).
        step: f64,
        /// Estimated largest position error of the reference itself (m).
        error_estimate: f64,
    },
}

/// Body positions and velocities at one tick.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// The tick.
    pub tick: u64,
    /// Positions (m), in body order.
    pub p: Vec<DVec3>,
    /// Velocities (m/s), in body order.
    pub v: Vec<DVec3>,
}

/// A reference trajectory at one dt: sampled frames and every event.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// What it is.
    pub kind: ReferenceKind,
    /// The dt (s) it serves.
    pub dt: f64,
    /// Frames at the sampled ticks (every `stride`-th, and the final one).
    pub frames: Vec<Frame>,
    /// Events, in tick order.
    pub events: Vec<Event>,
}

impl Reference {
    /// One line on what the reference is and how good it is.
    pub fn describe(&self) -> String {
        match self.kind {
            ReferenceKind::ClosedForm => "closed form (exact::closed_form at each tick)".into(),
            ReferenceKind::ExactFlow => {
                "closed form (the exact integrator: closed-form flow per step, impacts solved \
                 inside the step)"
                    .into()
            }
            ReferenceKind::Rk4 {
                substeps,
                step,
                error_estimate,
            } => format!(
                "RK4 at h = {step:.3e} s ({substeps} substeps per tick); its own error, from a \
                 run at 2h: about {error_estimate:.1e} m"
            ),
        }
    }

    /// The reference's own error estimate (m): 0 for the closed forms.
    pub fn error_estimate(&self) -> f64 {
        match self.kind {
            ReferenceKind::Rk4 { error_estimate, .. } => error_estimate,
            _ => 0.0,
        }
    }
}

/// Whether `tick` is sampled in a run of `ticks` with `stride`.
pub(crate) fn is_sample(tick: u64, ticks: u64, stride: u64) -> bool {
    tick.is_multiple_of(stride) || tick == ticks
}

/// The frame of a world as it is now.
pub(crate) fn frame_of(world: &World) -> Frame {
    let b = world.bodies();
    Frame {
        tick: world.tick(),
        p: b.positions().iter().collect(),
        v: (0..b.len()).map(|i| b.velocity(i)).collect(),
    }
}

/// Records sampled frames and all events of a run.
struct Recorder {
    ticks: u64,
    stride: u64,
    frames: Vec<Frame>,
    events: Vec<Event>,
}

impl TickObserver for Recorder {
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.events.extend_from_slice(world.events());
        if is_sample(world.tick(), self.ticks, self.stride) {
            self.frames.push(frame_of(world));
        }
        Ok(())
    }
}

/// Builds the best reference for `scene` (already at the dt it serves) over `ticks`.
/// `finest` is the smallest dt of the study (it sets the RK4 reference's step).
pub(crate) fn build(
    scene: &Scene,
    ticks: u64,
    stride: u64,
    finest: f64,
) -> Result<Reference, StudyError> {
    let world = World::new(scene);
    if world.contacts().is_empty()
        && let Some(frames) = closed_form_frames(&world, ticks, stride)
    {
        return Ok(Reference {
            kind: ReferenceKind::ClosedForm,
            dt: scene.dt(),
            frames,
            events: Vec::new(),
        });
    }
    if scene.forces.without_closed_form().is_none() {
        let (frames, events) = record(scene, Integrator::Exact, 1, ticks, stride)?;
        return Ok(Reference {
            kind: ReferenceKind::ExactFlow,
            dt: scene.dt(),
            frames,
            events,
        });
    }
    let dt = scene.dt();
    let r = (16.0 * dt / finest).ceil().max(16.0);
    let r = (r as u32).div_ceil(2) * 2;
    let (frames, events) = record(scene, Integrator::Rk4, r, ticks, stride)?;
    let (coarse, _) = record(scene, Integrator::Rk4, r / 2, ticks, stride)?;
    let difference = frames
        .iter()
        .zip(&coarse)
        .flat_map(|(a, b)| a.p.iter().zip(&b.p).map(|(x, y)| (*x - *y).length()))
        .fold(0.0, f64::max);
    Ok(Reference {
        kind: ReferenceKind::Rk4 {
            substeps: r,
            step: dt / f64::from(r),
            error_estimate: difference / 15.0,
        },
        dt,
        frames,
        events,
    })
}

fn closed_form_frames(world: &World, ticks: u64, stride: u64) -> Option<Vec<Frame>> {
    let b = world.bodies();
    let starts: Vec<(BodyState, f64)> = (0..b.len()).map(|i| (b.state(i), b.masses()[i])).collect();
    let forces = world.forces();
    let at = |tick: u64| -> Option<Frame> {
        let t = tick as f64 * world.dt();
        let states = starts
            .iter()
            .map(|(s, m)| crate::exact::closed_form(forces, *s, *m, t).map(|s1| (s1, *m)))
            .collect::<Option<Vec<_>>>()?;
        Some(Frame {
            tick,
            p: states.iter().map(|(s, _)| s.p).collect(),
            v: states.iter().map(|(s, m)| s.mv / *m).collect(),
        })
    };
    (1..=ticks)
        .filter(|&t| is_sample(t, ticks, stride))
        .map(at)
        .collect()
}

fn record(
    scene: &Scene,
    integrator: Integrator,
    substeps: u32,
    ticks: u64,
    stride: u64,
) -> Result<(Vec<Frame>, Vec<Event>), StudyError> {
    let mut s = scene.clone();
    s.set_integrator(integrator)
        .map_err(StudyError::Integrator)?;
    s.set_substeps(substeps).map_err(StudyError::Value)?;
    let mut sim = SimLoop::new(World::new(&s));
    let mut recorder = Recorder {
        ticks,
        stride,
        frames: Vec::new(),
        events: Vec::new(),
    };
    sim.run_until(ticks, &mut VirtualClock::Steady(s.timestep), &mut recorder)
        .map_err(|e| StudyError::Reference {
            integrator,
            substeps,
            dt: s.dt(),
            error: Box::new(e),
        })?;
    Ok((recorder.frames, recorder.events))
}
