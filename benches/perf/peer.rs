//! The peer: rapier3d-f64 stepping the bench scene's free bodies under gravity at the same dt.
//!
//! Each rapier body is dynamic, has no collider (so no broad or narrow phase work) and carries
//! the Volley body's mass as additional mass (a rapier body without colliders is massless and
//! gravity, applied as a force `m g`, would not move it); sleeping is off. Rapier integrates with
//! semi-implicit Euler in `num_solver_iterations` (default 4) substeps of each step, so Volley's
//! semi-implicit Euler at 1 substep is the like-for-like speed comparison per step, and at
//! [`RAPIER_SUBSTEPS`] substeps the like-for-like accuracy; the position error of every
//! contender against the closed form `p0 + v0 t + g t^2 / 2` after [`ERROR_TICKS`] ticks is
//! reported beside the speed.

use std::fmt::Write as _;

use criterion::{BenchmarkId, Criterion, Throughput};
use glam::DVec3;
use rapier3d_f64::prelude::{PhysicsWorld, RigidBodyBuilder, RigidBodyHandle, Vector};
use volley::{Integrator, World};

use crate::scenes::BenchScene;
use crate::sized;
use crate::tables::{Results, opt, sig, size_name};

/// Body counts compared with the peer.
pub const PEER_SIZES: [u64; 2] = [1_000, 100_000];

/// Ticks after which positions are compared with the closed form: 1 s at 60 Hz.
pub const ERROR_TICKS: u64 = 60;

/// Substeps rapier takes per step with default parameters (`num_solver_iterations`).
pub const RAPIER_SUBSTEPS: u32 = 4;

/// Volley's contenders in the error table: integrator and substeps.
pub const VOLLEY_CONTENDERS: [(Integrator, u32); 4] = [
    (Integrator::SemiImplicitEuler, 1),
    (Integrator::SemiImplicitEuler, RAPIER_SUBSTEPS),
    (Integrator::ExplicitEuler, 1),
    (Integrator::VelocityVerlet, 1),
];

/// A Volley world of the gravity bench scene with `n` bodies, `integrator` and `substeps`.
fn volley(n: u64, integrator: Integrator, substeps: u32) -> World {
    let mut scene = BenchScene::Gravity.load(n, integrator);
    scene
        .set_substeps(substeps)
        .expect("a positive substep count");
    World::new(&scene)
}

/// The benchmark function name of a Volley contender.
pub fn contender_name(integrator: Integrator, substeps: u32) -> String {
    match substeps {
        1 => format!("volley-{integrator}"),
        n => format!("volley-{integrator}-{n}-substeps"),
    }
}

/// Rapier's world holding the same bodies as a Volley world.
pub struct Peer {
    world: PhysicsWorld,
    handles: Vec<RigidBodyHandle>,
}

fn vector(v: DVec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

impl Peer {
    /// The bodies of `volley` (positions, velocities, masses), its gravity and step.
    pub fn like(volley: &World) -> Peer {
        let mut world = PhysicsWorld::new();
        let g = volley.forces().gravity.unwrap_or(DVec3::ZERO);
        world.gravity = vector(g);
        world.integration_parameters.dt = volley.dt();
        let b = volley.bodies();
        let handles = (0..b.len())
            .map(|i| {
                let body = RigidBodyBuilder::dynamic()
                    .translation(vector(b.positions().get(i)))
                    .linvel(vector(b.velocity(i)))
                    .additional_mass(b.masses()[i])
                    .can_sleep(false);
                world.insert_body(body)
            })
            .collect();
        Peer { world, handles }
    }

    /// One rapier step.
    pub fn step(&mut self) {
        self.world.step();
    }

    /// Position of body `i` (m).
    pub fn position(&self, i: usize) -> DVec3 {
        let t = self.world.bodies[self.handles[i]].translation();
        DVec3::new(t.x, t.y, t.z)
    }
}

/// Benchmarks `peer/rapier3d-f64/N` and, beside it, Volley's semi-implicit Euler at one and at
/// [`RAPIER_SUBSTEPS`] substeps.
pub fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("peer");
    for n in PEER_SIZES {
        sized(&mut group, n);
        group.sample_size(10);
        group.throughput(Throughput::Elements(n));
        let mut peer = None;
        group.bench_function(BenchmarkId::new("rapier3d-f64", n), |b| {
            let peer = peer
                .get_or_insert_with(|| Peer::like(&volley(n, Integrator::SemiImplicitEuler, 1)));
            b.iter(|| peer.step())
        });
        drop(peer);
        for substeps in [1, RAPIER_SUBSTEPS] {
            let integrator = Integrator::SemiImplicitEuler;
            let mut world = None;
            let id = BenchmarkId::new(contender_name(integrator, substeps), n);
            group.bench_function(id, |b| {
                let world = world.get_or_insert_with(|| volley(n, integrator, substeps));
                b.iter(|| world.step().expect("the bench scene does not diverge"))
            });
        }
    }
    group.finish();
}

/// Largest position error (m) over the bodies of a contender after [`ERROR_TICKS`] ticks.
#[derive(Clone, Debug)]
pub struct PeerError {
    /// Who: `rapier3d-f64` or `volley <integrator>`.
    pub who: String,
    /// Max over bodies of |p - p_exact| (m).
    pub max_error: f64,
}

/// The closed form of a free body under constant gravity.
fn exact(p0: DVec3, v0: DVec3, g: DVec3, t: f64) -> DVec3 {
    p0 + v0 * t + g * (0.5 * t * t)
}

/// Position errors of rapier and of Volley's contenders at `n` bodies.
pub fn errors(n: u64) -> Vec<PeerError> {
    let start = volley(n, Integrator::SemiImplicitEuler, 1);
    let g = start.forces().gravity.unwrap_or(DVec3::ZERO);
    let t = ERROR_TICKS as f64 * start.dt();
    let b = start.bodies();
    let reference: Vec<DVec3> = (0..b.len())
        .map(|i| exact(b.positions().get(i), b.velocity(i), g, t))
        .collect();
    let max_error = |position: &dyn Fn(usize) -> DVec3| {
        (0..reference.len())
            .map(|i| (position(i) - reference[i]).length())
            .fold(0.0, f64::max)
    };
    let mut peer = Peer::like(&start);
    for _ in 0..ERROR_TICKS {
        peer.step();
    }
    let mut out = vec![PeerError {
        who: format!("rapier3d-f64 (semi-implicit Euler, {RAPIER_SUBSTEPS} substeps)"),
        max_error: max_error(&|i| peer.position(i)),
    }];
    for (integrator, substeps) in VOLLEY_CONTENDERS {
        let mut world = volley(n, integrator, substeps);
        for _ in 0..ERROR_TICKS {
            world.step().expect("the bench scene does not diverge");
        }
        out.push(PeerError {
            who: match substeps {
                1 => format!("Volley {integrator}"),
                k => format!("Volley {integrator}, {k} substeps"),
            },
            max_error: max_error(&|i| world.bodies().positions().get(i)),
        });
    }
    out
}

/// Name of the rapier-against-Volley pair at `n` bodies.
pub fn paired_name(n: u64) -> String {
    format!("rapier-vs-volley/{n}")
}

/// Rapier against Volley's semi-implicit Euler (one substep), timed interleaved.
pub fn paired() -> Vec<crate::paired::Pair> {
    PEER_SIZES
        .iter()
        .map(|&n| {
            let mut world = volley(n, Integrator::SemiImplicitEuler, 1);
            let mut peer = Peer::like(&world);
            crate::paired::compare(
                &paired_name(n),
                || peer.step(),
                || world.step().expect("the bench scene does not diverge"),
            )
        })
        .collect()
}

/// The peer's tables: speed, paired speed, and the position errors.
pub fn table(md: &mut String, r: &Results) -> bool {
    let semi = Integrator::SemiImplicitEuler;
    let _ = writeln!(
        md,
        "\n### Peer: rapier3d-f64, free bodies under gravity at the same dt\n"
    );
    let _ = writeln!(
        md,
        "Rapier 0.36 with default parameters: dynamic bodies without colliders, additional mass = \
         Volley's mass, sleeping off, `PhysicsWorld::step`, which integrates semi-implicit Euler in \
         {RAPIER_SUBSTEPS} substeps (`num_solver_iterations`). Volley: `World::step`, semi-implicit \
         Euler, one thread, at 1 substep (the same per-step method) and at {RAPIER_SUBSTEPS} (the \
         same accuracy). The issue's goal: at least 300× faster per body-step.\n"
    );
    let _ = writeln!(
        md,
        "| N | rapier ns/body-step | Volley ns/body-step | faster by | paired, best rounds | goal | Volley, {RAPIER_SUBSTEPS} substeps | faster by |\n|---:|---:|---:|---:|---:|---|---:|---:|"
    );
    let mut complete = true;
    for n in PEER_SIZES {
        let rapier = r.per(&format!("peer/rapier3d-f64/{n}"), n);
        let one = r.per(&format!("peer/{}/{n}", contender_name(semi, 1)), n);
        let sub = r.per(
            &format!("peer/{}/{n}", contender_name(semi, RAPIER_SUBSTEPS)),
            n,
        );
        complete &= rapier.is_some() && one.is_some() && sub.is_some();
        let speedup = |v: Option<f64>| rapier.zip(v).map(|(a, b)| a / b);
        let pair = r.pair(&paired_name(n));
        let goal = match pair.map(|p| p.ratio).or(speedup(one)) {
            Some(x) if x >= 300.0 => "≥ 300×: met",
            Some(_) => "≥ 300×: **missed**",
            None => "",
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {goal} | {} | {} |",
            size_name(n),
            opt(rapier, sig),
            opt(one, sig),
            opt(speedup(one), |x| format!("{x:.0}×")),
            pair.map_or_else(
                || "-".into(),
                |p| format!("{:.0}× (median {:.0}×)", p.ratio, p.median)
            ),
            opt(sub, sig),
            opt(speedup(sub), |x| format!("{x:.0}×"))
        );
    }
    if !complete {
        return false;
    }
    let _ = writeln!(
        md,
        "\nLargest position error over the bodies against the closed form `p0 + v0 t + g t²/2` \
         after {ERROR_TICKS} ticks (t = 1 s). Semi-implicit and explicit Euler are off by \
         `g t h / 2` = 0.0818 m at h = 1/60 s, a quarter of that with 4 substeps; velocity Verlet \
         is exact for constant force up to rounding.\n"
    );
    let tables: Vec<_> = PEER_SIZES.iter().map(|&n| errors(n)).collect();
    let heads: Vec<String> = PEER_SIZES
        .iter()
        .map(|n| format!("N = {}", size_name(*n)))
        .collect();
    let _ = writeln!(
        md,
        "| contender | {} |\n|---|{}",
        heads.join(" | "),
        "---:|".repeat(PEER_SIZES.len())
    );
    for row in 0..tables[0].len() {
        let cells: Vec<String> = tables
            .iter()
            .map(|t| format!("{:.3e} m", t[row].max_error))
            .collect();
        let _ = writeln!(md, "| {} | {} |", tables[0][row].who, cells.join(" | "));
    }
    true
}
