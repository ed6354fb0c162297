//! The world's one random generator.
//!
//! The bottom layer: nothing here imports another module of the crate. The generator's state is
//! part of the world's state (hashed, snapshotted, restored), so a seeded run repeats exactly.

use serde::{Deserialize, Serialize};

/// SplitMix64 (Steele, Lea and Flood 2014; constants from Vigna's reference code): a tiny,
/// well-studied generator whose whole state is one `u64`, so it is trivially part of the hashed
/// and snapshotted world state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), from the top 53 bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [-1, 1).
    pub fn next_signed(&mut self) -> f64 {
        2.0 * self.next_f64() - 1.0
    }
}
