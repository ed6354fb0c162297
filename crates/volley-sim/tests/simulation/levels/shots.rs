//! The seeded shots at the 1 cm plate of `hard/plate_bullet` (hard case 17): 900 m/s, 0.5 to 90
//! degrees off the face, any heading, 1 to 60 m of flight, aimed anywhere on the face's 2 m
//! square less 5 cm. Shared by the tunnelling test (`plate.rs`) and the peer benchmark
//! (`benches/levels_peer.rs`, which includes this file by path), so both fire the same shots.

use glam::DVec3;
use volley_sim::{BodySpec, Integrator};

/// The plate's front face (m): its centre at x = 50, half its 1 cm thickness.
pub const FACE: f64 = 50.0 - 0.005;
/// The bullet's radius (m).
pub const R: f64 = 0.00381;

/// A small seeded generator for the shots (splitmix64), so the count is the same everywhere.
pub struct Shots(pub u64);

impl Shots {
    /// The next number in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The seed of the shots for one integrator and step.
pub fn seed(integrator: Integrator, dt: f64) -> u64 {
    0x5eed ^ integrator as u64 ^ (dt.to_bits() << 1)
}

/// `n` shots from `seed`, each the scene's bullet `template` moved and relaunched.
pub fn plate_shots(seed: u64, n: usize, template: BodySpec) -> Vec<BodySpec> {
    let mut shot = Shots(seed);
    (0..n)
        .map(|_| {
            // Grazing included: 0.5 to 90 degrees from the face, any heading about x, from 1 to
            // 60 m of flight before the face (at most 0.067 s: gravity's drop is below 2.2 cm),
            // aimed inside the face's 2 m square less 5 cm.
            let angle = (0.5 + 89.5 * shot.next()).to_radians();
            let heading = std::f64::consts::TAU * shot.next();
            let dir = DVec3::new(
                libm::sin(angle),
                libm::cos(angle) * libm::cos(heading),
                libm::cos(angle) * libm::sin(heading),
            );
            let aim = DVec3::new(
                FACE - R,
                1.9 * shot.next() - 0.95,
                1.5 + 1.9 * shot.next() - 0.95,
            );
            let before = 1.0 + 59.0 * shot.next();
            BodySpec {
                position: aim - dir * before,
                velocity: 900.0 * dir,
                ..template
            }
        })
        .collect()
}
