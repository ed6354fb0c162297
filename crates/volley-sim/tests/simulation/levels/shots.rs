//! The seeded shots at the 1 cm plate of `hard/plate_bullet` (hard case 17): 900 m/s, 0.5 to 90
//! degrees off the face, any heading, 1 to 60 m of flight, aimed anywhere on the face's 2 m
//! square less 5 cm. Shared by the tunnelling test (`plate.rs`) and the peer benchmark
//! (`benches/levels_peer.rs`, which includes this file by path), so both fire the same shots.

use glam::DVec3;
use volley_sim::{BodySpec, Integrator, SplitMix64};

/// The plate's front face (m): its centre at x = 50, half its 1 cm thickness.
pub const FACE: f64 = 50.0 - 0.005;
/// The bullet's radius (m).
pub const R: f64 = 0.00381;

/// The seed of the shots for one integrator and step.
pub fn seed(integrator: Integrator, dt: f64) -> u64 {
    0x5eed ^ integrator as u64 ^ (dt.to_bits() << 1)
}

/// `n` shots from `seed` (through the world's own generator, so the same everywhere), each the scene's bullet `template` moved and relaunched.
pub fn plate_shots(seed: u64, n: usize, template: BodySpec) -> Vec<BodySpec> {
    let mut shot = SplitMix64(seed);
    (0..n)
        .map(|_| {
            // Grazing included: 0.5 to 90 degrees from the face, any heading about x, from 1 to
            // 60 m of flight before the face (at most 0.067 s: gravity's drop is below 2.2 cm),
            // aimed inside the face's 2 m square less 5 cm.
            let angle = (0.5 + 89.5 * shot.next_f64()).to_radians();
            let heading = std::f64::consts::TAU * shot.next_f64();
            let dir = DVec3::new(
                libm::sin(angle),
                libm::cos(angle) * libm::cos(heading),
                libm::cos(angle) * libm::sin(heading),
            );
            let aim = DVec3::new(
                FACE - R,
                1.9 * shot.next_f64() - 0.95,
                1.5 + 1.9 * shot.next_f64() - 0.95,
            );
            let before = 1.0 + 59.0 * shot.next_f64();
            BodySpec {
                position: aim - dir * before,
                velocity: 900.0 * dir,
                ..template
            }
        })
        .collect()
}
