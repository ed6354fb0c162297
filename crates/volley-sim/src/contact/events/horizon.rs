//! How many steps a body's declared events are sure to stay quiet, so the step can skip their
//! search until then (docs/physics.md, "Declared events", "Horizons").
//!
//! Only in a world whose every force is a constant field (gravity and a constant force,
//! [`crate::forces::ConstantField`]): there each body's acceleration `a` is the same at every
//! instant, and every scheme's path through the points the search looks at (whole steps and
//! the partial steps from a step's start) is the closed form's, `V(t) = V0 + a t` and `P(t) =
//! P0 + V0 t + a t^2 / 2`, but for the Euler schemes' positions, which stray from it by at
//! most `|a| (h t / 2 + h^2 / 2)` (`h` the step; a partial step of `tau` moves by `V tau` or
//! `(V + a tau) tau`). So from a body's state after a step:
//! - a plane's function `g = n . P - d` is the quadratic `g0 + (n . V0) t + (n . a) t^2 / 2`
//!   within `|n . a| (h t + 3 h^2)` (twice the Euler schemes' stray and more);
//! - the apex's `V.z` is `V0.z + a.z t`, a speed `|V0 + a t| - s`, exactly: every scheme's
//!   velocity moves by `a tau` over a (partial) step under a constant field, the Euler schemes'
//!   too;
//! - each within a further millionth of the sizes involved, for rounding (a search resolves
//!   rounding at a few ulps, and the state's own rounding drifts by an ulp or so a step).
//!
//! The first time any of them could come within that band of zero is the first root of a
//! quadratic; the whole steps before it are skipped. At the end of the last of them the
//! function is still the band from zero, a millionth of its sizes, which no rounding of the
//! time or of the state over [`MAX_STEPS`] steps reaches. (A half-step band on the velocity
//! and one step fewer, as this first shipped, searched each body about three times per event
//! in a busy window; now once or twice.)
//!
//! The Mach number (the air changes with height) and the closest approach (its function is a
//! product) get no horizon: a world that declares one searches every body every step, as it
//! would without horizons. A horizon is a cache, never state: a skipped search is one that
//! would have found nothing, so the events, the bits and the hashes are the same with and
//! without it (tested over every integrator). It is dropped whenever anything but a step
//! changes the bodies or the forces (a command, a restore); a spawn adds a body due at once.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use glam::DVec3;

use super::{EventSet, Test};
use crate::body::BodyId;
use crate::integrate::BodyState;

/// The most steps one horizon skips: rounding drifts with the steps taken, so a body is looked
/// at again at least this often.
pub(crate) const MAX_STEPS: u64 = 1024;

/// What the step needs to keep horizons.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Horizon<'a> {
    /// This step's number since tick 0 (`tick * substeps + k`).
    pub step: u64,
    /// The forces: a constant field.
    pub field: &'a crate::forces::ConstantField,
    /// The column of step numbers from which each body is searched again ([`Due`]).
    pub due: &'a [AtomicU64],
    /// Per block of [`DUE_BLOCK`] bodies, at most the least of the block's entries ([`Due`]).
    pub blocks: &'a [AtomicU64],
    /// Whether the scene has something to hit ([`crate::contact::Contacts::has_surfaces`]).
    pub surfaces: bool,
}

/// Bodies per block of [`Due`]'s summary.
pub(crate) const DUE_BLOCK: usize = 64;

/// Per body (by storage index), the step number from which its declared events are searched
/// again. Each body's entry is read and written only by the thread stepping that body, so the
/// atomics (relaxed: plain loads and stores) only let the chunks share one column through the
/// step's context, which every chunk borrows, instead of splitting it with the chunks.
///
/// Beside it, per block of [`DUE_BLOCK`] bodies (storage indices `k * DUE_BLOCK ..`), a lower
/// bound of the block's entries: a step before it passes the whole block over with one load.
/// It is a cache of the column and only ever too low: whoever lowers an entry lowers its
/// block's bound with it (`fetch_min`, which two chunks sharing a block may both do, in either
/// order, to the same result); only the thread whose chunk holds the whole block sets it to the
/// block's least entry. So which bodies are searched never depends on it.
#[derive(Debug, Default)]
pub(crate) struct Due {
    column: Vec<AtomicU64>,
    blocks: Vec<AtomicU64>,
}

fn copy(v: &[AtomicU64]) -> Vec<AtomicU64> {
    v.iter().map(|d| AtomicU64::new(d.load(Relaxed))).collect()
}

impl Clone for Due {
    fn clone(&self) -> Due {
        Due {
            column: copy(&self.column),
            blocks: copy(&self.blocks),
        }
    }
}

impl Due {
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.column.len()
    }

    /// Every horizon void.
    pub(crate) fn clear(&mut self) {
        self.column.clear();
        self.blocks.clear();
    }

    /// `n` bodies, every one due at once.
    pub(crate) fn reset(&mut self, n: usize) {
        self.column.clear();
        self.column.resize_with(n, || AtomicU64::new(0));
        self.blocks.clear();
        self.blocks
            .resize_with(n.div_ceil(DUE_BLOCK), || AtomicU64::new(0));
    }

    /// A body added at the end, due at once.
    pub(crate) fn push(&mut self) {
        self.column.push(AtomicU64::new(0));
        let k = (self.column.len() - 1) / DUE_BLOCK;
        if k == self.blocks.len() {
            self.blocks.push(AtomicU64::new(0));
        } else {
            self.blocks[k].store(0, Relaxed);
        }
    }

    /// Body `i` removed, the others kept in order: the blocks from `i`'s on hold other bodies
    /// now, and are due at once.
    pub(crate) fn remove(&mut self, i: usize) {
        self.column.remove(i);
        self.blocks.truncate(self.column.len().div_ceil(DUE_BLOCK));
        for b in self.blocks.iter().skip(i / DUE_BLOCK) {
            b.store(0, Relaxed);
        }
    }

    /// The column, for the step.
    #[inline]
    pub(crate) fn column(&self) -> &[AtomicU64] {
        &self.column
    }

    /// The blocks' bounds, for the step.
    #[inline]
    pub(crate) fn blocks(&self) -> &[AtomicU64] {
        &self.blocks
    }

    /// Body `i`'s entry.
    #[cfg(test)]
    pub(crate) fn get(&self, i: usize) -> u64 {
        self.column[i].load(Relaxed)
    }
}

impl Horizon<'_> {
    /// Sets body `i`'s (storage index) entry to `next`, lowering its block's bound to it.
    #[inline]
    pub(crate) fn set_due(&self, i: usize, next: u64) {
        self.due[i].store(next, Relaxed);
        self.blocks[i / DUE_BLOCK].fetch_min(next, Relaxed);
    }
}

/// Relative rounding allowance of a horizon (see the module's docs).
const ROUNDING: f64 = 1e-6;

/// The first `t > 0` at which `c0 + c1 t + c2 t^2` reaches zero, given `c0 > 0`; infinite if
/// it never does.
#[inline]
fn first_zero(c0: f64, c1: f64, c2: f64) -> f64 {
    if c2 == 0.0 {
        return if c1 < 0.0 { -c0 / c1 } else { f64::INFINITY };
    }
    let disc = c1 * c1 - 4.0 * c2 * c0;
    if disc < 0.0 {
        // Never zero: the quadratic keeps c0's sign.
        return f64::INFINITY;
    }
    // The roots are q / c2 and c0 / q with q = -(c1 + sign(c1) sqrt(disc)) / 2, the form that
    // does not cancel; the first positive one.
    let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
    let roots = [q / c2, if q != 0.0 { c0 / q } else { f64::INFINITY }];
    roots
        .into_iter()
        .filter(|r| *r > 0.0)
        .fold(f64::INFINITY, f64::min)
}

/// The first time `x0 + r t + b t^2`, now `x0`, could come within `band` of zero; 0 if it is
/// within it now.
#[inline]
fn time_to_band(x0: f64, r: f64, b: f64, band: f64) -> f64 {
    let gap = x0.abs() - band;
    if gap <= 0.0 {
        return 0.0;
    }
    // On the side of x0's sign: the distance from the band's near edge.
    let sign = x0.signum();
    first_zero(gap, sign * r, sign * b)
}

/// How many whole steps of `h` after this one the events of `set` on body `id` at state `s`
/// (1/mass `inv`, constant acceleration `a`) cannot occur in: 0 when they might in the next.
pub(crate) fn quiet_steps(
    set: &EventSet,
    id: BodyId,
    s: &BodyState,
    inv: f64,
    a: DVec3,
    h: f64,
) -> u64 {
    let v = s.mv * inv;
    let mut t = f64::INFINITY;
    for watch in set.watches() {
        if watch.body.is_some_and(|b| b != id) {
            continue;
        }
        let tw = match watch.test {
            Test::Linear { n, d } => {
                // g0 + r t + A t^2 / 2 against a band growing as |A| (h t + 3 h^2): its near
                // edge moves at `|A| h` more.
                let size = s.p.abs().max_element() + d.abs() + v.length() * h;
                let (r, accel) = (n.dot(v), n.dot(a));
                let g0 = n.dot(s.p) - d;
                let band = 3.0 * accel.abs() * h * h + ROUNDING * size;
                let gap = g0.abs() - band;
                if gap <= 0.0 {
                    0.0
                } else {
                    let sign = g0.signum();
                    first_zero(gap, sign * r - accel.abs() * h, 0.5 * sign * accel)
                }
            }
            Test::Apex => {
                let band = ROUNDING * v.abs().max_element();
                time_to_band(v.z, a.z, 0.0, band)
            }
            Test::Speed(speed) => {
                // |V0 + a t|^2 = u0^2 + 2 (V0 . a) t + |a|^2 t^2 against (speed -+ band)^2.
                let u0 = v.length();
                let band = ROUNDING * (u0 + speed.abs());
                let (c1, c2) = (2.0 * v.dot(a), a.length_squared());
                if u0 > speed + band {
                    let edge = speed + band;
                    first_zero(u0 * u0 - edge * edge, c1, c2)
                } else if u0 < speed - band {
                    let edge = speed - band;
                    first_zero(edge * edge - u0 * u0, -c1, -c2)
                } else {
                    0.0
                }
            }
            Test::Mach { .. } | Test::Closest { .. } => 0.0,
        };
        t = t.min(tw);
        if t <= h {
            return 0;
        }
    }
    // Whole steps inside `t`: at the end of the last of them the function is still a band
    // (a millionth of its sizes) from zero, more than any rounding of `t / h` or of the
    // state over the steps skipped (an ulp or so a step, at most `MAX_STEPS`).
    let steps = (t / h).floor();
    if steps >= MAX_STEPS as f64 {
        MAX_STEPS
    } else if steps >= 1.0 {
        steps as u64
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::events::{EventCondition, EventSpec};

    fn set(conditions: &[EventCondition]) -> EventSet {
        let specs: Vec<EventSpec> = conditions.iter().map(|c| EventSpec::new(*c)).collect();
        EventSet::prepare(&specs, (DVec3::ZERO, 0.0), &[], None)
    }

    #[test]
    fn a_plane_far_ahead_is_quiet_until_the_bound_could_reach_it() {
        // 100 m below a plane, rising at 1 m/s, no acceleration: 1e4 steps, over the cap.
        let s = BodyState {
            p: DVec3::ZERO,
            mv: DVec3::Z,
        };
        let h = 0.01;
        let q = quiet_steps(
            &set(&[EventCondition::Altitude(100.0)]),
            BodyId(0),
            &s,
            1.0,
            DVec3::ZERO,
            h,
        );
        assert_eq!(q, MAX_STEPS, "100 s is more than the cap");
        let q = quiet_steps(
            &set(&[EventCondition::Altitude(0.05)]),
            BodyId(0),
            &s,
            1.0,
            DVec3::ZERO,
            h,
        );
        // 0.05 m at 1 m/s is 5 steps; the rounding allowance (6e-8 m) leaves 4.99999, whose
        // floor is 4.
        assert_eq!(q, 4);
    }

    #[test]
    fn a_body_on_or_near_a_zero_is_due_at_once() {
        let s = BodyState {
            p: DVec3::new(0.0, 0.0, 5.0),
            mv: DVec3::new(3.0, 0.0, 0.0),
        };
        let g = DVec3::new(0.0, 0.0, -9.81);
        for c in [
            EventCondition::Altitude(5.0),
            EventCondition::Apex,
            EventCondition::Speed(3.0),
            EventCondition::Mach(1.0),
        ] {
            assert_eq!(
                quiet_steps(&set(&[c]), BodyId(0), &s, 1.0, g, 1.0 / 60.0),
                0,
                "{c}"
            );
        }
    }

    #[test]
    fn an_apex_is_quiet_for_the_whole_steps_of_the_rise() {
        // 9.81 m/s up under 9.81 m/s^2: the apex is 1 s away.
        let s = BodyState {
            p: DVec3::ZERO,
            mv: DVec3::new(0.0, 0.0, 9.81),
        };
        let h = 0.01;
        let q = quiet_steps(
            &set(&[EventCondition::Apex]),
            BodyId(0),
            &s,
            1.0,
            DVec3::new(0.0, 0.0, -9.81),
            h,
        );
        // 1 s to the apex, less the band (a millionth of the velocity): 0.999999 s, 99.9999
        // steps, whose floor is 99: the step that ends on the apex is searched.
        assert_eq!(q, 99);
    }

    /// Runs `scene` for `ticks` with and without horizons, `commands` applied before the ticks
    /// they name: the same events, bit for bit, and the same state hash at every tick. Returns
    /// how many body-steps the horizons skipped.
    fn same_with_and_without(scene: &str, ticks: u64, commands: &[(u64, crate::Command)]) -> u64 {
        let scene = crate::parse_scene(scene, "test.ron", "test").expect("the test scene parses");
        let mut on = crate::World::new(&scene);
        let mut off = crate::World::new(&scene);
        off.scratch.horizons_off = true;
        let mut skipped = 0u64;
        for tick in 0..ticks {
            for (at, c) in commands {
                if *at == tick {
                    on.apply(c).expect("the command applies");
                    off.apply(c).expect("the command applies");
                }
            }
            let step = on.state.tick * u64::from(on.params.substeps);
            skipped += (0..on.scratch.due.len())
                .filter(|&i| on.scratch.due.get(i) > step)
                .count() as u64;
            let (a, b) = (on.step(), off.step());
            assert_eq!(a, b, "tick {tick}");
            assert_eq!(on.events(), off.events(), "tick {tick}");
            assert_eq!(
                crate::state_hash(&on),
                crate::state_hash(&off),
                "tick {tick}"
            );
        }
        assert!(
            (0..off.scratch.due.len()).all(|i| off.scratch.due.get(i) == 0),
            "the world without horizons kept none"
        );
        skipped
    }

    /// A volley of 200 under gravity with the tick-cost bench's 4 events, under every
    /// integrator: every event is found where the full search finds it.
    #[test]
    fn horizons_change_no_event_and_no_hash() {
        for integrator in crate::Integrator::ALL {
            let scene = launched_volley(
                &format!("dt: 0.016666667, integrator: {integrator:?}"),
                "speed: 20.0, elevation_deg: 45.0",
                "count: 200, speed_spread: 2.0, angle_spread_deg: 5.0), seed: 6",
                "(when: Altitude(5.0)), (when: Apex), (when: Downrange(20.0)), (when: Speed(15.0))",
            );
            let skipped = same_with_and_without(&scene, 240, &[]);
            // The bench's volley is quiet most of its flight: the horizons skip most searches.
            assert!(
                skipped > 200 * 240 / 2,
                "{integrator}: skipped only {skipped}"
            );
        }
    }

    /// The bands' edges: apexes exactly on tick boundaries (8 m/s^2 and ticks of 1/64 s, so
    /// the apex time `vz / 8` is a whole tick), and speed events whose threshold is the
    /// minimum speed, at the apex (a tangent on a tick boundary), or a few ulps above or below
    /// it, under every integrator: the search with horizons finds what the full search finds.
    #[test]
    fn horizons_keep_tangents_and_roots_on_tick_boundaries() {
        for integrator in crate::Integrator::ALL {
            let bodies: Vec<String> = (0..16)
                .map(|k| {
                    let vx = 15.0 + [0.0, 1e-13, -1e-13, 4e-15][k % 4];
                    let vz = (8 + k) as f64 / 8.0;
                    format!("(mass: 1, position: (0, 0, 0), launch: Velocity(({vx:?}, 0, {vz:?})))")
                })
                .collect();
            let scene = format!(
                "Scene(dt: 0.015625, integrator: {integrator:?},
                       forces: [Gravity((0.0, 0.0, -8.0))], bodies: [{}],
                       events: [(when: Apex), (when: Speed(15.0)), (when: Altitude(0.25))])",
                bodies.join(", ")
            );
            let skipped = same_with_and_without(&scene, 80, &[]);
            assert!(
                skipped > 16 * 80 / 2,
                "{integrator}: skipped only {skipped}"
            );
        }
    }

    /// A volley under gravity from the launcher at (0, 0, 1): the scene's `head` (dt,
    /// integrator), the launch, the volley's fields up to its seed, and the events.
    fn launched_volley(head: &str, launch: &str, volley: &str, events: &str) -> String {
        format!(
            "Scene({head}, forces: [Gravity((0.0, 0.0, -9.81))],
               launcher: (position: (0.0, 0.0, 1.0), {launch},
                          azimuth_deg: 0.0, mass: 1.0, radius: 0.1),
               volley: ({volley}, events: [{events}])"
        )
    }

    /// With nothing to hit, the bodies step apart from the search ([`DUE_BLOCK`]'s summary
    /// passes quiet blocks over): spawns, despawns (the blocks after it due at once) and
    /// commands, against the full search.
    #[test]
    fn horizon_blocks_follow_spawns_and_despawns() {
        use crate::{BodyId, Command};
        let scene = launched_volley(
            "dt: 0.02, integrator: VelocityVerlet",
            "speed: 25.0, elevation_deg: 50.0",
            "count: 150, speed_spread: 3.0, angle_spread_deg: 8.0), seed: 11",
            "(when: Altitude(12.0)), (when: Apex), (when: Downrange(30.0))",
        );
        let commands = [
            (10, Command::Despawn(BodyId(5))),
            (20, Command::Fire),
            (21, Command::Despawn(BodyId(100))),
            (30, Command::Fire),
            (55, Command::Despawn(BodyId(0))),
        ];
        let skipped = same_with_and_without(&scene, 200, &commands);
        assert!(skipped > 150 * 200 / 2, "skipped only {skipped}");
    }

    /// Two threads, whose chunks meet inside a block of the summary (16500 is not a multiple of
    /// 64): the shared block's bodies are looked at one by one, and the events and bits are
    /// the full search's.
    #[test]
    fn horizon_blocks_shared_by_two_chunks() {
        let scene = launched_volley(
            "dt: 0.05, integrator: SemiImplicitEuler",
            "speed: 20.0, elevation_deg: 45.0",
            "count: 33000, speed_spread: 2.0, angle_spread_deg: 5.0), seed: 6",
            "(when: Altitude(5.0)), (when: Apex)",
        );
        let scene = crate::parse_scene(&scene, "test.ron", "test").expect("the test scene parses");
        let mut on = crate::World::new(&scene);
        let mut off = crate::World::new(&scene);
        on.set_threads(2);
        off.set_threads(2);
        off.scratch.horizons_off = true;
        // Two chunks: at least two threads and twice the smallest chunk.
        const { assert!(33000 >= 2 * crate::step::PARALLEL_MIN_CHUNK) };
        let mut reported = 0;
        for tick in 0..60 {
            let (a, b) = (on.step(), off.step());
            assert_eq!(a, b, "tick {tick}");
            assert_eq!(on.events(), off.events(), "tick {tick}");
            reported += on.events().len();
        }
        assert_eq!(crate::state_hash(&on), crate::state_hash(&off));
        assert!(reported >= 33000, "only {reported} events");
    }

    /// Bounces on a ground, a constant force, substeps, an event on one body, a plane, and
    /// bodies fired, despawned and a force switched off mid-run.
    #[test]
    fn horizons_follow_bounces_spawns_despawns_and_commands() {
        use crate::{BodyId, Command, ForceKind};
        let scene = "Scene(dt: 0.02, substeps: 3, integrator: Rk4,
               forces: [Gravity((0.0, 0.0, -9.81)), ConstantForce((0.5, 0.0, 0.0))],
               ground: (height: 0.0, restitution: 0.6),
               launcher: (position: (0.0, 0.0, 1.0), speed: 15.0, elevation_deg: 60.0,
                          azimuth_deg: 10.0, mass: 2.0, radius: 0.1),
               volley: (count: 50, speed_spread: 3.0, angle_spread_deg: 10.0), seed: 3,
               events: [(when: Altitude(3.0), direction: Falling), (when: Apex),
                        (when: Plane(point: (5.0, 0.0, 0.0), normal: (1.0, 0.2, 0.0))),
                        (when: Speed(4.0), body: 7)])";
        let commands = [
            (40, Command::Fire),
            (41, Command::Fire),
            (60, Command::Despawn(BodyId(3))),
            (
                90,
                Command::SetForce {
                    kind: ForceKind::ConstantForce,
                    enabled: false,
                },
            ),
            (120, Command::Fire),
        ];
        let skipped = same_with_and_without(scene, 400, &commands);
        assert!(skipped > 0, "no search was skipped");
    }
}
