//! The references a study measures against, best first:
//!
//! 1. **Closed form** ([`volley_sim::internals::exact::closed_form`]) at every sampled tick, when the scene has
//!    no contacts and every body's forces have one (any mix of gravity, constant force, linear
//!    drag and a zero-rest-length spring with any damping; or a lone point mass, unless a body
//!    on a radial orbit reaches its centre).
//! 2. **Exact flow**: the scene run with [`Integrator::Exact`] at the same dt, when every force
//!    term has a closed form but the scene has contacts: each step evaluates the closed form and
//!    impacts are solved inside the step, so the whole piecewise trajectory is exact to rounding.
//! 3. **Extrapolation** ([`volley_sim::internals::exact::extrapolate`], adaptive Gragg-Bulirsch-Stoer) when the
//!    scene has no contacts but a force term without a closed form (quadratic drag, a spring of
//!    nonzero rest length, a point mass with other terms): each body is advanced from one
//!    sampled tick to the next to a relative tolerance of [`EXTRAPOLATION_TOLERANCE`], far below
//!    any error a studied setting makes, and the reference reports its own error estimate, the
//!    largest over bodies of the sum of its accepted steps' estimates.
//! 4. **RK4 reference** when the scene has contacts and a force term without a closed form, or
//!    a game's own term (whose force may read the clock, which the extrapolation does not
//!    pass): the extrapolation knows no contacts (its macro steps would step over an impact), so the scene
//!    runs with RK4 at `R` substeps per tick, `R >= 16` chosen so the reference step is at most
//!    1/16 of the finest dt studied, impacts found by the loop's own contact search. Its own
//!    error is estimated from a second run at `R / 2` (twice its step): for a fourth-order
//!    method the error of the finer run is about `|fine - coarse| / 15` (Richardson).
//!
//! The closed form and the extrapolation are evaluated at each sampled tick's time; the exact
//! flow and RK4 run through [`SimLoop`] like the runs they judge, and sample the same ticks.
//! A report keeps only a [`Reference`] (what it was, how good, how large the motion); the
//! trajectory itself ([`Trajectory`]) lives only while the runs at its dt are measured.

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::contact::Event;
use volley_sim::internals::integrate::{BodyState, Integrator};
use volley_sim::internals::scene::Scene;
use volley_sim::internals::sim_loop::{ObserverError, SimLoop, TickObserver};
use volley_sim::internals::world::World;

use super::StudyError;

/// Relative tolerance of the extrapolation reference, per step and component
/// (`tolerance * (1 + |y|)`): the window's numerical reference uses the same. Summed over the
/// steps of a run it stays orders of magnitude below the error of RK4 at the finest dt a study
/// usually takes; the report prints the estimate, so a study that gets near it says so.
pub const EXTRAPOLATION_TOLERANCE: f64 = 1e-12;

/// Which reference was used, and what it is worth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum ReferenceKind {
    /// `exact::closed_form` at each tick time.
    ClosedForm,
    /// The `exact` integrator at the same dt, impacts solved inside the step.
    ExactFlow,
    /// `exact::extrapolate` to each sampled tick time, at `tolerance`.
    Extrapolation {
        /// Relative tolerance per step and component.
        tolerance: f64,
        /// The reference's own estimate of its error (m, or m/s: the max norm over position
        /// and velocity components), summed over its steps; the largest over bodies.
        error_estimate: f64,
    },
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

/// What a report says about the reference at one dt: its kind and worth, and the size of the
/// motion it traced (for the rounding floor).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reference {
    /// What it is.
    pub kind: ReferenceKind,
    /// The dt (s) it serves.
    pub dt: f64,
    /// Largest body distance from the origin (m) over the sampled frames, at least 1.
    pub extent: f64,
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
pub struct Trajectory {
    /// What it is.
    pub reference: Reference,
    /// Frames at the sampled ticks (every `stride`-th, and the final one).
    pub frames: Vec<Frame>,
    /// Events, in tick order.
    pub events: Vec<Event>,
}

impl Trajectory {
    fn new(kind: ReferenceKind, dt: f64, frames: Vec<Frame>, events: Vec<Event>) -> Trajectory {
        let extent = frames
            .iter()
            .flat_map(|f| f.p.iter().map(|p| p.length()))
            .fold(1.0, f64::max);
        Trajectory {
            reference: Reference { kind, dt, extent },
            frames,
            events,
        }
    }
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
            ReferenceKind::Extrapolation {
                tolerance,
                error_estimate,
            } => format!(
                "extrapolation (adaptive Gragg-Bulirsch-Stoer, exact::extrapolate, relative \
                 tolerance {tolerance:.0e} per step); its own error estimate: about \
                 {error_estimate:.1e} m"
            ),
            ReferenceKind::Rk4 {
                substeps,
                step,
                error_estimate,
            } => format!(
                "RK4 at h = {step:.3e} s ({substeps} substeps per tick; the scene has contacts, \
                 which the extrapolation reference does not handle); its own error, from a run \
                 at 2h: about {error_estimate:.1e} m"
            ),
        }
    }

    /// The reference's own error estimate (m): 0 for the closed forms.
    pub fn error_estimate(&self) -> f64 {
        match self.kind {
            ReferenceKind::Rk4 { error_estimate, .. }
            | ReferenceKind::Extrapolation { error_estimate, .. } => error_estimate,
            ReferenceKind::ClosedForm | ReferenceKind::ExactFlow => 0.0,
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
) -> Result<Trajectory, StudyError> {
    let world = World::new(scene);
    let dt = scene.dt();
    let no_contacts = world.contacts().is_empty();
    if no_contacts && let Some(frames) = closed_form_frames(&world, ticks, stride) {
        return Ok(Trajectory::new(
            ReferenceKind::ClosedForm,
            dt,
            frames,
            Vec::new(),
        ));
    }
    if scene.forces().without_closed_form().is_none() {
        let (frames, events) = record(scene, Integrator::Exact, 1, ticks, stride)?;
        return Ok(Trajectory::new(
            ReferenceKind::ExactFlow,
            dt,
            frames,
            events,
        ));
    }
    // The extrapolation's derivative knows no clock and no launch, so the terms that read them
    // (a game's own, a spin, a motor) take the RK4 reference.
    if no_contacts && !scene.forces().timed() {
        let (frames, error_estimate) =
            extrapolation_frames(&world, ticks, stride, EXTRAPOLATION_TOLERANCE)?;
        let kind = ReferenceKind::Extrapolation {
            tolerance: EXTRAPOLATION_TOLERANCE,
            error_estimate,
        };
        return Ok(Trajectory::new(kind, dt, frames, Vec::new()));
    }
    let r = (16.0 * dt / finest).ceil().max(16.0);
    let r = (r as u32).div_ceil(2) * 2;
    let (fine, coarse) = rayon::join(
        || record(scene, Integrator::Rk4, r, ticks, stride),
        || record(scene, Integrator::Rk4, r / 2, ticks, stride),
    );
    let ((frames, events), (coarse, _)) = (fine?, coarse?);
    let difference = frames
        .iter()
        .zip(&coarse)
        .flat_map(|(a, b)| a.p.iter().zip(&b.p).map(|(x, y)| (*x - *y).length()))
        .fold(0.0, f64::max);
    let kind = ReferenceKind::Rk4 {
        substeps: r,
        step: dt / f64::from(r),
        error_estimate: difference / 15.0,
    };
    Ok(Trajectory::new(kind, dt, frames, events))
}

/// Every body advanced by [`volley_sim::internals::exact::extrapolate`] from one sampled tick's time to the
/// next (bodies in parallel, each on its own), and the largest over bodies of the summed error
/// estimates.
fn extrapolation_frames(
    world: &World,
    ticks: u64,
    stride: u64,
    tolerance: f64,
) -> Result<(Vec<Frame>, f64), StudyError> {
    let b = world.bodies();
    let forces = world.forces();
    let samples: Vec<u64> = (1..=ticks)
        .filter(|&t| is_sample(t, ticks, stride))
        .collect();
    let body = |i: usize| -> Result<(Vec<BodyState>, f64), StudyError> {
        let m = b.masses()[i];
        let (mut state, mut time, mut estimate) = (b.state(i), 0.0, 0.0);
        let mut states = Vec::with_capacity(samples.len());
        for &tick in &samples {
            let t = tick as f64 * world.dt();
            let (next, e) =
                volley_sim::internals::exact::extrapolate(forces, state, m, t - time, tolerance)
                    .map_err(|error| StudyError::Extrapolation {
                        body: b.ids()[i].0,
                        error,
                    })?;
            (state, time, estimate) = (next, t, estimate + e);
            states.push(state);
        }
        Ok((states, estimate))
    };
    // Collected in body order, and the first error in body order wins: the outcome does not
    // depend on the scheduling.
    let per_body: Vec<Result<(Vec<BodyState>, f64), StudyError>> =
        (0..b.len()).into_par_iter().map(body).collect();
    let per_body = per_body.into_iter().collect::<Result<Vec<_>, _>>()?;
    let masses = b.masses();
    let frames = samples
        .iter()
        .enumerate()
        .map(|(k, &tick)| Frame {
            tick,
            p: per_body.iter().map(|(s, _)| s[k].p).collect(),
            v: per_body
                .iter()
                .zip(masses.iter())
                .map(|((s, _), m)| s[k].mv / *m)
                .collect(),
        })
        .collect();
    let estimate = per_body.iter().map(|(_, e)| *e).fold(0.0, f64::max);
    Ok((frames, estimate))
}

fn closed_form_frames(world: &World, ticks: u64, stride: u64) -> Option<Vec<Frame>> {
    let b = world.bodies();
    let starts: Vec<(BodyState, f64)> = (0..b.len()).map(|i| (b.state(i), b.masses()[i])).collect();
    let forces = world.forces();
    let at = |tick: u64| -> Option<Frame> {
        let t = tick as f64 * world.dt();
        let states = starts
            .iter()
            .map(|(s, m)| {
                volley_sim::internals::exact::closed_form(forces, *s, *m, t).map(|s1| (s1, *m))
            })
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
    sim.run_until(
        ticks,
        &mut VirtualClock::Steady(s.timestep()),
        &mut recorder,
    )
    .map_err(|e| StudyError::Reference {
        integrator,
        substeps,
        dt: s.dt(),
        error: Box::new(e),
    })?;
    Ok((recorder.frames, recorder.events))
}
