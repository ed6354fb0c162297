//! The peer: rapier3d-f64 stepping the bench scene's free bodies under gravity at the same dt.
//!
//! Each rapier body is dynamic, has no collider (so no broad or narrow phase work) and carries
//! the Volley body's mass as additional mass (a rapier body without colliders is massless and
//! gravity, applied as a force `m g`, would not move it); sleeping is off. Rapier integrates with
//! semi-implicit Euler, so Volley's semi-implicit Euler is the like-for-like speed comparison;
//! the position error of every contender against the closed form `p0 + v0 t + g t^2 / 2` after
//! [`ERROR_TICKS`] ticks is reported beside the speed.

use criterion::{BenchmarkId, Criterion, Throughput};
use glam::DVec3;
use rapier3d_f64::prelude::{PhysicsWorld, RigidBodyBuilder, RigidBodyHandle, Vector};
use volley::{Integrator, World};

use crate::scenes::BenchScene;
use crate::sized;

/// Body counts compared with the peer.
pub const PEER_SIZES: [u64; 2] = [1_000, 100_000];

/// Ticks after which positions are compared with the closed form: 1 s at 60 Hz.
pub const ERROR_TICKS: u64 = 60;

/// Volley's contenders in the error table.
pub const VOLLEY_ERROR_INTEGRATORS: [Integrator; 3] = [
    Integrator::SemiImplicitEuler,
    Integrator::ExplicitEuler,
    Integrator::VelocityVerlet,
];

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

/// Benchmarks `peer/rapier3d-f64/N` and, beside it, `peer/volley-semi-implicit-euler/N`.
pub fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("peer");
    for n in PEER_SIZES {
        sized(&mut group, n);
        group.sample_size(10);
        group.throughput(Throughput::Elements(n));
        let world = || BenchScene::Gravity.world(n, Integrator::SemiImplicitEuler, 1);
        let mut peer = None;
        group.bench_function(BenchmarkId::new("rapier3d-f64", n), |b| {
            let peer = peer.get_or_insert_with(|| Peer::like(&world()));
            b.iter(|| peer.step())
        });
        drop(peer);
        let mut volley = None;
        group.bench_function(BenchmarkId::new("volley-semi-implicit-euler", n), |b| {
            let volley = volley.get_or_insert_with(world);
            b.iter(|| volley.step().expect("the bench scene does not diverge"))
        });
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
    let start = BenchScene::Gravity.world(n, Integrator::SemiImplicitEuler, 1);
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
        who: "rapier3d-f64".into(),
        max_error: max_error(&|i| peer.position(i)),
    }];
    for integrator in VOLLEY_ERROR_INTEGRATORS {
        let mut world = BenchScene::Gravity.world(n, integrator, 1);
        for _ in 0..ERROR_TICKS {
            world.step().expect("the bench scene does not diverge");
        }
        out.push(PeerError {
            who: format!("volley {integrator}"),
            max_error: max_error(&|i| world.bodies().positions().get(i)),
        });
    }
    out
}
