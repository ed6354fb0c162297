//! The adversarial cases of declared events (issue 39, item 4), shared by the test
//! (`tests/simulation/declared/adversarial.rs`) and the bench (`benches/events.rs`, which also
//! exports them for scipy's `solve_ivp`). Self-contained: only `volley_sim` and std.
//!
//! Each case is one scene of one body (mass 1, so `mv` is the velocity bit for bit) with its
//! declared events and, for each event, its reference occurrences: times since the spawn from
//! a closed form, each with the way it goes and the time tolerance derived for it.
//!
//! ## The references
//! - Under gravity alone (`a` constant) every function but the closest approach is, up to a
//!   positive factor, the quadratic `f(t) = c + b t + a t^2`: a plane's `n . p - d` (`c = n .
//!   p0 - d`, `b = n . v0`, `a = n . g / 2`), the apex's `V.z` (`a = 0`), and for a speed
//!   `|V|^2 - s^2` (`c = |v0|^2 - s^2`, `b = 2 v0 . g`, `a = |g|^2`), whose sign is that of
//!   `|V| - s`. Its roots are computed stably (`q = -(b + sign(b) sqrt(b^2 - 4ac)) / 2`, roots
//!   `q / a` and `c / q`: no cancellation), each to a few ulps of its size, so to well under
//!   1e-12 s for the roots here (all below 100 s).
//! - On a zero-rest-length spring alone, `p(t) = anchor + r0 cos(w t) + (v0 / w) sin(w t)`,
//!   `w = sqrt(k)`: a plane's function is `R cos(w t - phi) - e`, its roots `(phi +- acos(e /
//!   R) + 2 pi j) / w`. The generator keeps `|e / R| <= 0.9`, where acos's condition number
//!   `1 / sqrt(1 - x^2)` is at most 2.3, so each root is good to a few ulps of `w t`: under
//!   1e-13 s for `w t < 200`.
//!
//! ## The tolerance
//! The integrators exact under constant force follow the closed form on their sub-step path,
//! but each tick's sums round: after `k` ticks the position is off by at most about `k`
//! roundings of the largest term, `dp <= 4 k eps P` with `P` the largest of `|p|`, `|v| T`,
//! `|g| T^2` met (and the velocity by `4 k eps (|v| + |g| T)`). The root finder stops within
//! rounding of the computed function, `dg <= 8 eps (|p| + |d|)` (events/search.rs,
//! `rounding`), so a simple root at which the function moves at rate `r = |f'(t*)|` is found
//! within `dt <= (dp + dg) / r`. The generator computes this bound for each occurrence, with
//! a factor 4 on top, and rejects draws (re-draws) whose bound passes 1e-10 s; the test then
//! asserts the goal, 1e-9 s, ten times that. A graze's time is the root of `n . V`
//! (rate `|n . g|`), bounded the same way from the velocity's rounding. On the spring, the
//! exact integrator's step is the rotation by `w h` evaluated in f64: its error after `k`
//! ticks is `O(k eps R)` and the same bound holds with `r = w R sin` at the root (at least
//! `0.43 w R` with `|e / R| <= 0.9`).
//!
//! ## Misses and duplicates
//! A case's reported occurrences of each event are matched, in time order, to its references
//! within `MATCH` s (1e-6 s: far wider than any bound, far narrower than the gaps between
//! references, which the generator keeps above 1e-4 s): a reference left unmatched is a miss,
//! a report left unmatched a duplicate.

#![allow(dead_code)]

use volley_sim::{Event, EventDirection, EventKind, Integrator, Scene, World};

/// The schemes exact under constant force (the 1e-9 s goal is for them), as basic.rs lists.
pub const EXACT_UNDER_GRAVITY: [Integrator; 7] = [
    Integrator::VelocityVerlet,
    Integrator::Midpoint,
    Integrator::Rk4,
    Integrator::Exact,
    Integrator::ForestRuth,
    Integrator::Dopri5,
    Integrator::ImplicitMidpoint,
];

/// The seed of the suite.
pub const SEED: u64 = 0x5EED_0039_AD7E_5A11;

/// The goal for the time error (s).
pub const GOAL: f64 = 1e-9;

/// The generator's own cap on a reference's derived bound (s): a tenth of the goal.
pub const BOUND_CAP: f64 = 1e-10;

/// How near (s) a report must be to a reference to be its occurrence.
pub const MATCH: f64 = 1e-6;

/// Smallest gap (s) the generator leaves between two references of one event.
pub const MIN_GAP: f64 = 1e-4;

const EPS: f64 = f64::EPSILON;

/// The crate's SplitMix64 (Steele, Lea and Flood 2014), the world's own generator.
#[derive(Clone, Debug)]
pub struct Rng(volley_sim::SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(volley_sim::SplitMix64(seed))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in [0, 1), 53 bits.
    pub fn unit(&mut self) -> f64 {
        self.0.next_f64()
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    pub fn sign(&mut self) -> f64 {
        if self.next_u64() & 1 == 0 { 1.0 } else { -1.0 }
    }

    /// A unit vector, uniform on the sphere.
    pub fn unit_vec(&mut self) -> [f64; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

/// The categories of the suite.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Category {
    /// Two crossings of one altitude or plane inside one tick (a body near its apex).
    Double,
    /// An altitude exactly at the apex height (dyadic numbers: exact in binary).
    GrazeExact,
    /// An altitude at the apex height as computed, and a few ulps either side.
    GrazeRounding,
    /// A root exactly at a tick boundary: the level is the closed form at `t = k dt`.
    Boundary,
    /// A function exactly zero at the spawn (`t = 0`, any start time).
    Spawn,
    /// Fast bodies (300 to 3000 m/s), several planes crossed inside one tick.
    Fast,
    /// Bodies spinning round a spring's anchor, many crossings per tick.
    Spin,
}

impl Category {
    pub const ALL: [Category; 7] = [
        Category::Double,
        Category::GrazeExact,
        Category::GrazeRounding,
        Category::Boundary,
        Category::Spawn,
        Category::Fast,
        Category::Spin,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Category::Double => "double crossing in one tick",
            Category::GrazeExact => "tangent graze, exact",
            Category::GrazeRounding => "tangent graze, within rounding",
            Category::Boundary => "root on a tick boundary",
            Category::Spawn => "zero at the spawn (t = 0)",
            Category::Fast => "fast body, several planes a tick",
            Category::Spin => "spinning on a spring",
        }
    }

    pub fn key(self) -> &'static str {
        match self {
            Category::Double => "double",
            Category::GrazeExact => "graze_exact",
            Category::GrazeRounding => "graze_rounding",
            Category::Boundary => "boundary",
            Category::Spawn => "spawn",
            Category::Fast => "fast",
            Category::Spin => "spin",
        }
    }
}

/// The function an event watches, in the reference's terms.
#[derive(Clone, Copy, Debug)]
pub enum Cond {
    /// `n . p - d`, `n` unit (an altitude when `n = z`).
    Plane { n: [f64; 3], d: f64 },
    /// `V.z`.
    Apex,
    /// `|V| - s`.
    Speed(f64),
}

/// One reference occurrence: time since the spawn (s), the way it goes (`None`: a graze,
/// either way), and its derived bound (s).
#[derive(Clone, Copy, Debug)]
pub struct Expected {
    pub t: f64,
    pub direction: Option<EventDirection>,
    pub bound: f64,
    /// Within rounding either way: a touch reported here is this occurrence, none is no miss.
    pub optional: bool,
}

/// One declared event of a case.
#[derive(Clone, Debug)]
pub struct Watch {
    pub cond: Cond,
    /// As the scene declares it.
    pub when: String,
    pub direction: EventDirection,
    /// `Body(n)`: the body leaves at the n-th occurrence.
    pub stop: Option<u32>,
    pub expected: Vec<Expected>,
}

/// One case.
#[derive(Clone, Debug)]
pub struct Case {
    pub index: usize,
    pub category: Category,
    pub integrator: Integrator,
    pub dt: f64,
    pub start: f64,
    pub ticks: u64,
    /// Gravity (m/s^2), or zero.
    pub g: [f64; 3],
    /// A zero-rest-length spring `(anchor, stiffness)`, or none.
    pub spring: Option<([f64; 3], f64)>,
    pub p0: [f64; 3],
    pub v0: [f64; 3],
    pub watches: Vec<Watch>,
    /// Only the count is checked, not the time (none here: every case has a reference to
    /// 1e-12; kept for the report).
    pub counts_only: bool,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn at(p0: [f64; 3], v0: [f64; 3], g: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|i| p0[i] + v0[i] * t + 0.5 * g[i] * t * t)
}

fn vel(v0: [f64; 3], g: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|i| v0[i] + g[i] * t)
}

/// The real roots of `c + b t + a t^2`, ascending, computed without cancellation.
pub fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    if a == 0.0 {
        return if b == 0.0 { vec![] } else { vec![-c / b] };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return vec![];
    }
    let sign = if b >= 0.0 { 1.0 } else { -1.0 };
    let q = -0.5 * (b + sign * disc.sqrt());
    if q == 0.0 {
        // b = 0 and c = 0: a double root at 0.
        return vec![0.0];
    }
    let (r1, r2) = (q / a, c / q);
    let mut r = vec![r1.min(r2), r1.max(r2)];
    r.dedup();
    r
}

impl Case {
    pub fn name(&self) -> String {
        format!(
            "case {} ({}, {:?}, seed {SEED:#x})",
            self.index,
            self.category.key(),
            self.integrator
        )
    }

    /// The horizon (s since the spawn).
    pub fn horizon(&self) -> f64 {
        self.ticks as f64 * self.dt
    }

    pub fn scene_text(&self) -> String {
        let v = |a: [f64; 3]| format!("({:?}, {:?}, {:?})", a[0], a[1], a[2]);
        let mut forces = Vec::new();
        if self.g != [0.0; 3] {
            forces.push(format!("Gravity({})", v(self.g)));
        }
        if let Some((anchor, k)) = self.spring {
            forces.push(format!("Spring(anchor: {}, stiffness: {k:?})", v(anchor)));
        }
        let events: Vec<String> = self
            .watches
            .iter()
            .map(|w| {
                let stop = match w.stop {
                    Some(n) => format!(", stop: Body({n})"),
                    None => String::new(),
                };
                format!("(when: {}, direction: {:?}{stop})", w.when, w.direction)
            })
            .collect();
        format!(
            "Scene(dt: {:?}, start_time: {:?}, integrator: {:?}, forces: [{}],
                   bodies: [(mass: 1.0, position: {}, launch: Velocity({}))],
                   events: [{}])",
            self.dt,
            self.start,
            self.integrator,
            forces.join(", "),
            v(self.p0),
            v(self.v0),
            events.join(", ")
        )
    }

    pub fn scene(&self) -> Scene {
        volley_sim::parse_scene(&self.scene_text(), "adversarial.ron", "adversarial")
            .unwrap_or_else(|e| panic!("{}: {e}", self.name()))
    }
}

/// One report: event index, time since the spawn, direction, graze.
#[derive(Clone, Copy, Debug)]
pub struct Report {
    pub event: usize,
    pub t: f64,
    pub direction: EventDirection,
    pub graze: bool,
}

/// Runs a case: every declared event reported over its ticks, and the world's force
/// evaluations for the search.
pub fn run(case: &Case) -> (Vec<Report>, u64) {
    let mut world = World::new(&case.scene());
    let mut out = Vec::new();
    for _ in 0..case.ticks {
        world
            .step()
            .unwrap_or_else(|e| panic!("{}: {e:?}", case.name()));
        out.extend(world.events().iter().filter_map(|e: &Event| match e.kind {
            EventKind::Declared {
                event,
                direction,
                graze,
                ..
            } => Some(Report {
                event: event as usize,
                t: e.time - case.start,
                direction,
                graze,
            }),
            _ => None,
        }));
    }
    (out, world.event_evals())
}

/// What a case's reports come to against its references.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    pub expected: usize,
    pub misses: usize,
    pub duplicates: usize,
    /// Largest time error of a matched occurrence (s).
    pub max_error: f64,
    /// Matched occurrences whose way (rising, falling) is wrong.
    pub wrong_way: usize,
    /// Matched occurrences whose time error passes the goal.
    pub over_goal: usize,
    /// Lines saying what went wrong, naming the case.
    pub problems: Vec<String>,
}

/// Matches reports to references, per event, in time order (see the module's comment).
pub fn judge(case: &Case, reports: &[Report]) -> Outcome {
    let mut o = Outcome::default();
    for (i, w) in case.watches.iter().enumerate() {
        let mine: Vec<&Report> = reports.iter().filter(|r| r.event == i).collect();
        let mut used = vec![false; mine.len()];
        o.expected += w.expected.iter().filter(|e| !e.optional).count();
        for e in &w.expected {
            let hit = mine
                .iter()
                .enumerate()
                .filter(|(j, r)| !used[*j] && (r.t - e.t).abs() <= MATCH)
                .min_by(|x, y| (x.1.t - e.t).abs().total_cmp(&(y.1.t - e.t).abs()));
            match hit {
                None if e.optional => {}
                None => {
                    o.misses += 1;
                    o.problems.push(format!(
                        "{}: event {i} ({}): missed the occurrence at t = {:?} s ({:?}); reports {:?}",
                        case.name(),
                        w.when,
                        e.t,
                        e.direction,
                        mine
                    ));
                }
                Some((j, r)) => {
                    used[j] = true;
                    let err = (r.t - e.t).abs();
                    o.max_error = o.max_error.max(err);
                    if err > GOAL {
                        o.over_goal += 1;
                        o.problems.push(format!(
                            "{}: event {i} ({}): at t = {:?} s, error {err:.3e} s > {GOAL:e} (derived bound {:.1e})",
                            case.name(),
                            w.when,
                            e.t,
                            e.bound
                        ));
                    }
                    if let Some(d) = e.direction
                        && d != r.direction
                    {
                        o.wrong_way += 1;
                        o.problems.push(format!(
                            "{}: event {i} ({}): at t = {:?} s went {:?}, reported {:?}",
                            case.name(),
                            w.when,
                            e.t,
                            d,
                            r.direction
                        ));
                    }
                }
            }
        }
        for (j, r) in mine.iter().enumerate() {
            if !used[j] {
                o.duplicates += 1;
                o.problems.push(format!(
                    "{}: event {i} ({}): extra report {r:?}; references {:?}",
                    case.name(),
                    w.when,
                    w.expected
                ));
            }
        }
    }
    o
}

/// The derived bound (s) of a simple root at `t` of a function moving at rate `rate`, on a
/// path of size `size` (m, or m/s for a velocity function) after `ticks` ticks.
fn bound(ticks: f64, size: f64, rate: f64) -> f64 {
    // dp <= 4 k eps P, dg <= 8 eps P; times 4.
    4.0 * (4.0 * (ticks + 1.0) + 8.0) * EPS * size / rate.abs()
}

/// The references of `cond` under gravity from `(p0, v0)` over `(0, horizon]` (and `t = 0`
/// where the function is exactly zero there), filtered by `direction`; `None` when a root's
/// bound passes the cap or two roots are closer than `MIN_GAP`, or one is within `MIN_GAP`
/// of the horizon's end (the draw is then redrawn).
fn gravity_refs(
    cond: Cond,
    p0: [f64; 3],
    v0: [f64; 3],
    g: [f64; 3],
    dt: f64,
    horizon: f64,
    direction: EventDirection,
) -> Option<Vec<Expected>> {
    let (a, b, c) = coefficients(cond, p0, v0, g);
    let mut out = Vec::new();
    let mut last: Option<f64> = None;
    for t in quadratic_roots(a, b, c) {
        if t < 0.0 || t > horizon {
            continue;
        }
        if t == 0.0 && c != 0.0 {
            continue;
        }
        if horizon - t < MIN_GAP {
            return None;
        }
        if let Some(l) = last
            && t - l < MIN_GAP
        {
            return None;
        }
        last = Some(t);
        let mut rate = b + 2.0 * a * t;
        if rate == 0.0 {
            // A double root (a touch): the grazes are built by hand, not here.
            return None;
        }
        if t == 0.0 && rate == 0.0 {
            rate = a;
        }
        let way = if rate > 0.0 {
            EventDirection::Rising
        } else {
            EventDirection::Falling
        };
        let size = match cond {
            Cond::Plane { d, .. } => {
                norm(at(p0, v0, g, t)).max(norm(p0)) + d.abs() + norm(v0) * t + norm(g) * t * t
            }
            Cond::Apex => norm(v0) + norm(g) * t,
            Cond::Speed(s) => norm(v0) + norm(g) * t + s,
        };
        // The speed's quadratic is |V|^2 - s^2: its rate is 2 |V| times the speed's.
        let rate_of_g = match cond {
            Cond::Speed(s) => rate / (2.0 * s.max(1e-300)),
            _ => rate,
        };
        let bd = bound(t / dt, size, rate_of_g);
        if bd > BOUND_CAP {
            return None;
        }
        if direction.counts(way) {
            out.push(Expected {
                t,
                direction: Some(way),
                bound: bd,
                optional: false,
            });
        }
    }
    Some(out)
}

/// `(a, b, c)` of the quadratic whose sign is the function's (module comment).
fn coefficients(cond: Cond, p0: [f64; 3], v0: [f64; 3], g: [f64; 3]) -> (f64, f64, f64) {
    match cond {
        Cond::Plane { n, d } => (0.5 * dot(n, g), dot(n, v0), dot(n, p0) - d),
        Cond::Apex => (0.0, g[2], v0[2]),
        Cond::Speed(s) => (dot(g, g), 2.0 * dot(v0, g), dot(v0, v0) - s * s),
    }
}

fn plane_when(n: [f64; 3], d: f64) -> String {
    // A point of the plane: d n (n unit as drawn; Volley normalises it again, within an ulp,
    // and its d is then within an ulp or two of this one: far inside every bound).
    plane_at(n, d, [d * n[0], d * n[1], d * n[2]])
}

fn plane_at(n: [f64; 3], d: f64, point: [f64; 3]) -> String {
    if n == [0.0, 0.0, 1.0] {
        format!("Altitude({d:?})")
    } else {
        format!(
            "Plane(point: ({:?}, {:?}, {:?}), normal: ({:?}, {:?}, {:?}))",
            point[0], point[1], point[2], n[0], n[1], n[2]
        )
    }
}

fn pick_direction(rng: &mut Rng) -> EventDirection {
    match rng.below(4) {
        0 => EventDirection::Rising,
        1 => EventDirection::Falling,
        _ => EventDirection::Either,
    }
}

/// A dt: half the time a dyadic one (exact in binary), else any in [lo, hi].
fn pick_dt(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    if rng.below(2) == 0 {
        let mut d = 1.0;
        while d > hi {
            d *= 0.5;
        }
        let choices: Vec<f64> = (0..6)
            .map(|i| d / f64::from(1u32 << i))
            .filter(|x| *x >= lo)
            .collect();
        choices[rng.below(choices.len() as u64) as usize]
    } else {
        rng.range(lo, hi)
    }
}

fn start_time(rng: &mut Rng) -> f64 {
    match rng.below(3) {
        0 => 0.0,
        1 => rng.range(0.0, 100.0),
        _ => 2.0,
    }
}

fn empty(category: Category, index: usize, integrator: Integrator) -> Case {
    Case {
        index,
        category,
        integrator,
        dt: 0.0,
        start: 0.0,
        ticks: 0,
        g: [0.0; 3],
        spring: None,
        p0: [0.0; 3],
        v0: [0.0; 3],
        watches: Vec::new(),
        counts_only: false,
    }
}

/// A plane's normal: vertical (an altitude) half the time, else tilted at most 60 degrees
/// from the vertical (so that gravity bends the path back through it).
fn pick_normal(rng: &mut Rng) -> [f64; 3] {
    if rng.below(2) == 0 {
        [0.0, 0.0, 1.0]
    } else {
        loop {
            let n = rng.unit_vec();
            if n[2] > 0.5 {
                return n;
            }
        }
    }
}

fn gravity(rng: &mut Rng) -> [f64; 3] {
    [0.0, 0.0, -rng.range(2.0, 30.0)]
}

/// Draws case `index` of `category` until its references pass the generator's checks.
fn draw(category: Category, index: usize, integrator: Integrator, rng: &mut Rng) -> Case {
    loop {
        if let Some(c) = try_draw(category, index, integrator, rng) {
            return c;
        }
    }
}

fn try_draw(
    category: Category,
    index: usize,
    integrator: Integrator,
    rng: &mut Rng,
) -> Option<Case> {
    let mut case = empty(category, index, integrator);
    case.start = start_time(rng);
    match category {
        Category::Double => {
            // Two roots t1 < t2 inside tick k: the body's rate along n is zero at their
            // midpoint, and the plane is where it is at t1.
            let dt = pick_dt(rng, 0.05, 1.0);
            let g = gravity(rng);
            let n = pick_normal(rng);
            let k = rng.below(20);
            let (u, w) = (rng.range(0.02, 0.49), rng.range(0.51, 0.98));
            let (t1, t2) = ((k as f64 + u) * dt, (k as f64 + w) * dt);
            let ng = dot(n, g);
            // n . v(tm) = 0 at tm = (t1 + t2) / 2: choose v0 along n for that, plus a
            // sideways part.
            let tm = 0.5 * (t1 + t2);
            let side = rng.unit_vec();
            let sn = dot(side, n);
            let side = [0, 1, 2].map(|i| (side[i] - sn * n[i]) * rng.range(0.0, 20.0));
            let v0 = [0, 1, 2].map(|i| side[i] - ng * tm * n[i]);
            let p0 = [
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
                rng.range(0.0, 5.0),
            ];
            let d = dot(n, at(p0, v0, g, t1));
            case.dt = dt;
            case.g = g;
            case.p0 = p0;
            case.v0 = v0;
            case.ticks = k + 2 + rng.below(3);
            let direction = pick_direction(rng);
            let cond = Cond::Plane { n, d };
            let expected = gravity_refs(cond, p0, v0, g, dt, case.horizon(), direction)?;
            // Both roots must be the tick's (the reference is recomputed, not assumed).
            let all = gravity_refs(cond, p0, v0, g, dt, case.horizon(), EventDirection::Either)?;
            if all.len() != 2 || (all[0].t / dt).floor() != (all[1].t / dt).floor() {
                return None;
            }
            case.watches.push(Watch {
                cond,
                when: plane_when(n, d),
                direction,
                stop: None,
                expected,
            });
        }
        Category::GrazeExact | Category::GrazeRounding => {
            // Straight up at vz under g: the apex vz^2 / (2 g) at vz / g. Exact: g = 2^i,
            // vz = g ta with ta dyadic, so the apex height and time are exact in binary.
            let dt = pick_dt(rng, 0.01, 0.5);
            let exact = category == Category::GrazeExact;
            let (gz, vz, z0) = if exact {
                let gz = f64::from(1u32 << (1 + rng.below(5)));
                let ta = (1 + rng.below(64)) as f64 / 16.0;
                (gz, gz * ta, (rng.below(64) as f64) / 4.0)
            } else {
                (
                    rng.range(2.0, 30.0),
                    rng.range(1.0, 30.0),
                    rng.range(-5.0, 5.0),
                )
            };
            let vx = if rng.below(2) == 0 {
                0.0
            } else {
                rng.range(-10.0, 10.0)
            };
            let top = z0 + vz * vz / (2.0 * gz);
            let mut optional = false;
            let level = if exact {
                top
            } else {
                // The apex as computed, or up to 4 ulps either side: all within rounding of
                // the path's values (Volley's rounding there is 8 eps |z| per term).
                let ulps = rng.below(9) as i64 - 4;
                // `top` is the apex to about 2 ulps (three roundings): a level 3 or 4 ulps
                // below it is certainly touched (crossed twice within rounding: one touch to
                // report), one 2 ulps below to 4 above may be touched or missed by the exact
                // path, so a touch there is optional.
                optional = ulps >= -2;
                let mut l = top;
                for _ in 0..ulps.abs() {
                    l = if ulps > 0 { l.next_up() } else { l.next_down() };
                }
                l
            };
            let ta = vz / gz;
            case.dt = dt;
            case.g = [0.0, 0.0, -gz];
            case.p0 = [0.0, 0.0, z0];
            case.v0 = [vx, 0.0, vz];
            case.ticks = (ta / dt).ceil() as u64 + 2;
            // A graze's time is the root of V.z, at rate g; its values are velocities.
            let bd = bound(ta / dt, vz + vx.abs(), gz);
            if bd > BOUND_CAP {
                return None;
            }
            case.watches.push(Watch {
                cond: Cond::Plane {
                    n: [0.0, 0.0, 1.0],
                    d: level,
                },
                when: plane_when([0.0, 0.0, 1.0], level),
                direction: EventDirection::Either,
                stop: None,
                expected: vec![Expected {
                    t: ta,
                    direction: None,
                    bound: bd,
                    optional,
                }],
            });
        }
        Category::Boundary => {
            // The level is the closed form at t = k dt: a root on the end of tick k (and the
            // others the quadratic has). A dyadic dt half the time, so k dt is exact too.
            let dt = pick_dt(rng, 0.01, 0.25);
            let g = gravity(rng);
            let k = 1 + rng.below(40);
            let tk = k as f64 * dt;
            let v0 = [
                rng.range(-20.0, 20.0),
                rng.range(-20.0, 20.0),
                rng.range(-5.0, 40.0),
            ];
            let p0 = [
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
                rng.range(0.0, 5.0),
            ];
            let pk = at(p0, v0, g, tk);
            let vk = vel(v0, g, tk);
            let cond = match rng.below(3) {
                0 => {
                    let n = pick_normal(rng);
                    Cond::Plane { n, d: dot(n, pk) }
                }
                1 => Cond::Speed(norm(vk)),
                _ => {
                    // The apex on the boundary: v0.z = -g.z k dt (exact with a dyadic dt and
                    // an integer g, else within rounding).
                    let gz = -((1 + rng.below(30)) as f64);
                    case.g = [0.0, 0.0, gz];
                    case.v0 = [v0[0], v0[1], -gz * tk];
                    Cond::Apex
                }
            };
            if !matches!(cond, Cond::Apex) {
                case.g = g;
                case.v0 = v0;
            }
            case.dt = dt;
            case.p0 = p0;
            case.ticks = k + 1 + rng.below(30);
            let direction = pick_direction(rng);
            let expected = gravity_refs(cond, p0, case.v0, case.g, dt, case.horizon(), direction)?;
            let all = gravity_refs(
                cond,
                p0,
                case.v0,
                case.g,
                dt,
                case.horizon(),
                EventDirection::Either,
            )?;
            // The boundary root must be one of them, within its bound.
            if !all
                .iter()
                .any(|e| (e.t - tk).abs() <= e.bound.max(4.0 * EPS * tk))
            {
                return None;
            }
            let when = match cond {
                Cond::Plane { n, d } => plane_when(n, d),
                Cond::Speed(s) => format!("Speed({s:?})"),
                Cond::Apex => "Apex".to_string(),
            };
            case.watches.push(Watch {
                cond,
                when,
                direction,
                stop: None,
                expected,
            });
        }
        Category::Spawn => {
            let dt = pick_dt(rng, 0.005, 0.2);
            let g = gravity(rng);
            let p0 = [
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
                rng.range(0.0, 5.0),
            ];
            let mut v0 = [
                rng.range(-20.0, 20.0),
                rng.range(-20.0, 20.0),
                rng.range(-10.0, 30.0),
            ];
            let cond = match rng.below(4) {
                0 => Cond::Plane {
                    n: [0.0, 0.0, 1.0],
                    d: p0[2],
                },
                1 => {
                    let n = pick_normal(rng);
                    // d as Volley computes it for a plane through p0 (its normal is n again
                    // to an ulp; the function at the spawn is then exactly 0 if the ulp
                    // agrees, which the check below makes sure of).
                    Cond::Plane { n, d: dot(n, p0) }
                }
                2 => {
                    v0[2] = 0.0;
                    Cond::Apex
                }
                _ => Cond::Speed(norm(v0)),
            };
            if let Cond::Plane { n, .. } = cond
                && n != [0.0, 0.0, 1.0]
            {
                let len = norm(n);
                let nn = n.map(|x| x / len);
                let m = glam::DVec3::from_array(n).normalize_or_zero().to_array();
                if nn != n || m != n {
                    return None;
                }
            }
            case.dt = dt;
            case.g = g;
            case.p0 = p0;
            case.v0 = v0;
            case.ticks = 1 + rng.below(300);
            let direction = pick_direction(rng);
            let expected = gravity_refs(cond, p0, v0, g, dt, case.horizon(), direction)?;
            let (.., c) = coefficients(cond, p0, v0, g);
            if c != 0.0 {
                return None;
            }
            let when = match cond {
                // Through the spawn point itself, so that Volley's `n . p0 - n . point` is 0.
                Cond::Plane { n, d } => plane_at(n, d, p0),
                Cond::Speed(s) => format!("Speed({s:?})"),
                Cond::Apex => "Apex".to_string(),
            };
            case.watches.push(Watch {
                cond,
                when,
                direction,
                stop: None,
                expected,
            });
        }
        Category::Fast => {
            // 300 to 3000 m/s through three planes spaced less than a tick's travel.
            let dt = pick_dt(rng, 0.005, 0.1);
            let g = gravity(rng);
            let speed = rng.range(300.0, 3000.0);
            let dir = rng.unit_vec();
            let v0 = dir.map(|x| x * speed);
            let p0 = [
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
                rng.range(0.0, 5.0),
            ];
            case.dt = dt;
            case.g = g;
            case.p0 = p0;
            case.v0 = v0;
            case.ticks = 2 + rng.below(40);
            let horizon = case.horizon();
            let step = speed * dt * rng.range(0.1, 0.5);
            let first = rng.range(0.0, 0.5) * speed * horizon;
            // Planes square to the path at its start, tilted up to 60 degrees from it.
            let n = loop {
                let m = rng.unit_vec();
                let c = dot(m, dir);
                if c > 0.5 {
                    break m;
                }
            };
            for j in 0..3 {
                let d = dot(n, p0) + first + j as f64 * step;
                let cond = Cond::Plane { n, d };
                let direction = pick_direction(rng);
                let expected = gravity_refs(cond, p0, v0, g, dt, horizon, direction)?;
                case.watches.push(Watch {
                    cond,
                    when: plane_when(n, d),
                    direction,
                    stop: None,
                    expected,
                });
            }
        }
        Category::Spin => {
            // Round a spring's anchor (rest length 0, no gravity): the closed form is a
            // rotation. The exact integrator's step is that rotation, so its times are
            // checked to the goal; it is the only one of the seven exact on a spring.
            let w = rng.range(2.0, 60.0);
            let k = w * w;
            let w = k.sqrt();
            let dt = pick_dt(rng, 0.01, 0.2);
            let anchor = [
                rng.range(-5.0, 5.0),
                rng.range(-5.0, 5.0),
                rng.range(0.0, 5.0),
            ];
            let r = rng.range(0.5, 20.0);
            let u = rng.unit_vec();
            let e2 = rng.unit_vec();
            let ue = dot(u, e2);
            let mut v = [0, 1, 2].map(|i| e2[i] - ue * u[i]);
            let vl = norm(v);
            if vl < 0.1 {
                return None;
            }
            let ecc = rng.range(0.2, 1.0);
            v = v.map(|x| x / vl * r * w * ecc);
            let r0 = u.map(|x| x * r);
            case.integrator = Integrator::Exact;
            case.dt = dt;
            case.spring = Some((anchor, k));
            case.p0 = [0, 1, 2].map(|i| anchor[i] + r0[i]);
            case.v0 = v;
            case.ticks = 2 + rng.below(30);
            let horizon = case.horizon();
            if w * horizon > 200.0 {
                case.ticks = (200.0 / (w * dt)).floor().max(2.0) as u64;
            }
            let horizon = case.horizon();
            for _ in 0..2 {
                let n = rng.unit_vec();
                // n . (p - anchor) = A cos(wt) + B sin(wt) = R cos(wt - phi).
                let (a, b) = (dot(n, r0), dot(n, v) / w);
                let big = a.hypot(b);
                if big < 0.1 {
                    return None;
                }
                let e = big * rng.range(-0.9, 0.9);
                let d = dot(n, anchor) + e;
                let phi = b.atan2(a);
                let x = (e / big).acos();
                let mut roots = Vec::new();
                let jmax = (w * horizon / std::f64::consts::TAU).ceil() as i64 + 1;
                for j in -1..=jmax {
                    for s in [-1.0, 1.0] {
                        let t = (phi + s * x + std::f64::consts::TAU * j as f64) / w;
                        if t > 0.0 && t <= horizon {
                            roots.push(t);
                        }
                    }
                }
                roots.sort_by(f64::total_cmp);
                let mut expected = Vec::new();
                let direction = pick_direction(rng);
                for (i, &t) in roots.iter().enumerate() {
                    if horizon - t < MIN_GAP || (i > 0 && t - roots[i - 1] < MIN_GAP) {
                        return None;
                    }
                    // Rate: -R w sin(w t - phi).
                    let rate = -big * w * (w * t - phi).sin();
                    let size = r + d.abs() + norm(anchor);
                    let bd = bound(t / dt, size, rate);
                    if bd > BOUND_CAP {
                        return None;
                    }
                    let way = if rate > 0.0 {
                        EventDirection::Rising
                    } else {
                        EventDirection::Falling
                    };
                    if direction.counts(way) {
                        expected.push(Expected {
                            t,
                            direction: Some(way),
                            bound: bd,
                            optional: false,
                        });
                    }
                }
                case.watches.push(Watch {
                    cond: Cond::Plane { n, d },
                    when: plane_when(n, d),
                    direction,
                    stop: None,
                    expected,
                });
            }
        }
    }
    // A stop count on some single-event cases: the body leaves at its n-th occurrence, so the
    // references end there.
    if case.watches.len() == 1
        && !matches!(category, Category::GrazeExact | Category::GrazeRounding)
        && case.watches[0].expected.len() >= 2
        && rng.below(4) == 0
    {
        let w = &mut case.watches[0];
        let n = 1 + rng.below(w.expected.len() as u64 - 1) as u32;
        w.stop = Some(n);
        w.expected.truncate(n as usize);
    }
    Some(case)
}

/// How many cases of each category the suite has.
pub fn per_category(category: Category) -> usize {
    match category {
        Category::Double => 220,
        Category::GrazeExact => 110,
        Category::GrazeRounding => 110,
        Category::Boundary => 220,
        Category::Spawn => 180,
        Category::Fast => 140,
        Category::Spin => 80,
    }
}

/// The whole suite, in a fixed order from [`SEED`]; each category from its own stream, the
/// integrators taken in turn.
pub fn suite() -> Vec<Case> {
    let mut out = Vec::new();
    for (ci, category) in Category::ALL.into_iter().enumerate() {
        let mut rng = Rng::new(SEED ^ (ci as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        for i in 0..per_category(category) {
            let integrator = EXACT_UNDER_GRAVITY[i % EXACT_UNDER_GRAVITY.len()];
            out.push(draw(category, out.len(), integrator, &mut rng));
        }
    }
    out
}
