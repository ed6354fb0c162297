//! One measured run: errors against the reference at the sampled ticks, events, energy drift.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::contact::{Event, EventKind, Surface};
use volley_sim::internals::forces::{ForceModel, Forces};
use volley_sim::internals::scene::Scene;
use volley_sim::internals::sim_loop::{ObserverError, SimLoop, TickObserver};
use volley_sim::internals::world::{BodyId, World};

use super::reference::{Trajectory, is_sample};
use super::{Outcome, StudyConfig, StudyError, StudyPoint};

/// Position and velocity errors of a completed run against its reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Errors {
    /// Largest body position error (m) at the final tick.
    pub final_position: f64,
    /// Largest body position error (m) over the sampled ticks.
    pub max_position: f64,
    /// Root mean square of the position error (m) over every sampled (tick, body) pair.
    pub rms_position: f64,
    /// Largest body velocity error (m/s) at the final tick.
    pub final_velocity: f64,
}

/// How the run's events compare with the reference's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EventErrors {
    /// Impacts and target passes in the reference.
    pub reference: usize,
    /// Of those, how many the run also had (the k-th of a body on the same surface or target).
    pub matched: usize,
    /// Largest |time - reference time| (s) over the matched events: impact times, target hit
    /// times when both hit, closest-approach times when neither did.
    pub max_time_error: Option<f64>,
    /// Target passes that hit in one run and missed in the other.
    pub hit_mismatches: usize,
}

/// Energy drift per time window: the largest `|E(t) - E(0)| / scale` in each, where `scale` is
/// the kinetic energy plus the magnitude of every potential term at tick 0, summed over bodies
/// (so it does not vanish when the terms cancel, as on an orbit).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyDrift {
    /// One value per window, in time order.
    pub windows: Vec<f64>,
}

impl EnergyDrift {
    /// Drift in the first window.
    pub fn first(&self) -> f64 {
        self.windows.first().copied().unwrap_or(0.0)
    }

    /// Drift in the last window.
    pub fn last(&self) -> f64 {
        self.windows.last().copied().unwrap_or(0.0)
    }
}

/// Whether the scene cannot gain or lose mechanical energy: no dissipative force terms, and
/// every surface bounces with restitution 1.
pub fn conservative(scene: &Scene) -> bool {
    let f = &scene.forces();
    let damped = f.linear_drag.is_some_and(|b| b > 0.0)
        || f.quadratic_drag.is_some_and(|c| c > 0.0)
        || f.mach_drag.is_some()
        || !f.custom.is_empty()
        || f.thrust.is_some()
        || f.spring.is_some_and(|s| s.damping > 0.0);
    let lossy = scene.ground().is_some_and(|g| g.restitution < 1.0)
        || scene.walls().iter().any(|w| w.restitution < 1.0);
    !damped && !lossy
}

/// Total energy (J) and its scale (J) of every body under `forces`.
fn energy_and_scale(world: &World, forces: &Forces) -> (f64, f64) {
    let b = world.bodies();
    let (mut energy, mut scale) = (0.0, 0.0);
    for i in 0..b.len() {
        let (p, v, m) = (b.positions().get(i), b.velocity(i), b.masses()[i]);
        let kinetic = 0.5 * m * v.length_squared();
        energy += forces.energy(p, v, m);
        scale += kinetic;
        for kind in forces.kinds() {
            let only = kinetic + forces.potential(kind, p, v, m).unwrap_or(0.0);
            scale += (only - kinetic).abs();
        }
    }
    (energy, scale)
}

struct EnergyTracker {
    e0: f64,
    scale: f64,
    ticks: u64,
    windows: Vec<f64>,
}

/// The observer of a measured run.
struct Measure<'a> {
    reference: &'a Trajectory,
    next: usize,
    sum_sq: f64,
    count: u64,
    errors: Errors,
    events: Vec<Event>,
    energy: Option<EnergyTracker>,
}

impl TickObserver for Measure<'_> {
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        self.events.extend_from_slice(world.events());
        if let Some(e) = &mut self.energy {
            let (now, _) = energy_and_scale(world, world.forces());
            let drift = (now - e.e0).abs() / e.scale.max(f64::MIN_POSITIVE);
            let n = e.windows.len();
            let w = ((world.tick() - 1) * n as u64 / e.ticks) as usize;
            let slot = &mut e.windows[w.min(n - 1)];
            *slot = slot.max(drift);
        }
        let Some(frame) = self.reference.frames.get(self.next) else {
            return Ok(());
        };
        if frame.tick != world.tick() {
            return Ok(());
        }
        self.next += 1;
        let b = world.bodies();
        let mut worst = 0.0f64;
        let mut worst_v = 0.0f64;
        for (i, p) in b.positions().iter().enumerate().take(frame.p.len()) {
            let d = (p - frame.p[i]).length();
            self.sum_sq += d * d;
            self.count += 1;
            worst = worst.max(d);
            worst_v = worst_v.max((b.velocity(i) - frame.v[i]).length());
        }
        self.errors.max_position = self.errors.max_position.max(worst);
        self.errors.final_position = worst;
        self.errors.final_velocity = worst_v;
        Ok(())
    }
}

/// Runs one (integrator, dt) with its observer and returns the point (timing not yet filled).
pub(crate) fn run_point(
    scene: &Scene,
    ticks: u64,
    stride: u64,
    reference: &Trajectory,
    config: &StudyConfig,
) -> Result<StudyPoint, StudyError> {
    debug_assert!(
        reference
            .frames
            .iter()
            .all(|f| is_sample(f.tick, ticks, stride))
    );
    let world = World::new(scene);
    let energy = conservative(scene).then(|| {
        let (e0, scale) = energy_and_scale(&world, world.forces());
        EnergyTracker {
            e0,
            scale,
            ticks,
            windows: vec![0.0; config.energy_windows],
        }
    });
    let mut measure = Measure {
        reference,
        next: 0,
        sum_sq: 0.0,
        count: 0,
        errors: Errors::default(),
        events: Vec::new(),
        energy,
    };
    let mut sim = SimLoop::new(world);
    let result = sim.run_until(
        ticks,
        &mut VirtualClock::Steady(scene.timestep()),
        &mut measure,
    );
    let outcome = match result {
        Ok(()) => Outcome::Completed,
        Err(e) => Outcome::Diverged(super::loop_error(e)?),
    };
    let errors = (outcome == Outcome::Completed).then(|| Errors {
        rms_position: (measure.sum_sq / measure.count.max(1) as f64).sqrt(),
        ..measure.errors
    });
    let sim_seconds = sim.world.tick() as f64 * scene.dt();
    Ok(StudyPoint {
        integrator: scene.integrator(),
        dt: scene.dt(),
        substeps: scene.substeps(),
        ticks,
        force_evals: sim.world.force_evals(),
        evals_per_second: sim.world.force_evals() as f64 / sim_seconds.max(f64::MIN_POSITIVE),
        wall_per_tick: None,
        repeats: 0,
        outcome,
        errors,
        events: event_errors(&measure.events, &reference.events),
        energy: measure.energy.map(|e| EnergyDrift { windows: e.windows }),
        precheck: crate::stability::Growth {
            rho: 1.0,
            stable: true,
        },
    })
}

/// What an event is about, for matching: (body, 0 ground / 1 wall / 2 target hit / 3 target
/// closest approach / 4 mesh / 5 heightfield / 6 declared event, index).
fn key(e: &Event) -> Option<(BodyId, u8, u32)> {
    match e.kind {
        EventKind::Impact {
            surface: Surface::Ground,
            ..
        } => Some((e.body, 0, 0)),
        EventKind::Impact {
            surface: Surface::Wall(i),
            ..
        } => Some((e.body, 1, i)),
        EventKind::Impact {
            surface: Surface::Mesh { surface, .. },
            ..
        } => Some((e.body, 4, surface)),
        EventKind::Impact {
            surface: Surface::Heightfield { surface, .. },
            ..
        } => Some((e.body, 5, surface)),
        EventKind::Hit { target } => Some((e.body, 2, target)),
        EventKind::Approach { target, .. } => Some((e.body, 3, target)),
        EventKind::Declared { event, .. } => Some((e.body, 6, event)),
        EventKind::Rest { .. } => None,
    }
}

fn by_key(events: &[Event]) -> BTreeMap<(BodyId, u8, u32), Vec<&Event>> {
    let mut map: BTreeMap<_, Vec<&Event>> = BTreeMap::new();
    for e in events {
        if let Some(k) = key(e) {
            map.entry(k).or_default().push(e);
        }
    }
    map
}

/// Matches the k-th event of each (body, surface or target) in `run` with the reference's k-th.
pub(crate) fn event_errors(run: &[Event], reference: &[Event]) -> EventErrors {
    let (ours, theirs) = (by_key(run), by_key(reference));
    let mut out = EventErrors::default();
    for (k, refs) in &theirs {
        out.reference += refs.len();
        let mine = ours.get(k).map_or(&[][..], Vec::as_slice);
        if k.1 == 2 {
            // A target hit by one run and missed by the other has no time error to report.
            out.hit_mismatches += mine.len().abs_diff(refs.len());
        }
        for (a, b) in mine.iter().zip(refs) {
            out.matched += 1;
            let dt = (a.time - b.time).abs();
            out.max_time_error = Some(out.max_time_error.map_or(dt, |m: f64| m.max(dt)));
        }
    }
    for (k, mine) in &ours {
        if k.1 == 2 && !theirs.contains_key(k) {
            out.hit_mismatches += mine.len();
        }
    }
    out
}
