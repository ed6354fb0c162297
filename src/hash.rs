//! The canonical state hash: what replays compare and CI pins.
//!
//! XXH3-64 (seed 0, the `xxhash-rust` crate) over this byte stream, all integers and float bit
//! patterns little-endian:
//!
//! ```text
//! "VOLLEY-STATE-v1"  tick:u64  rng_state:u64  body_count:u64
//! per body in id order:  id:u64  p.x p.y p.z  mV.x mV.y mV.z  mass  radius   (f64 bit patterns)
//! ```
//!
//! Floats are canonicalised first: `-0.0` hashes as `+0.0` and every NaN as the quiet NaN
//! `0x7ff8_0000_0000_0000`, so states that compare equal hash equal. The hash covers everything
//! that decides the future of the bodies; settings changed by commands (integrator, force
//! toggles, launcher) are not hashed because commands are recorded beside the hashes.

use xxhash_rust::xxh3::Xxh3;

use crate::world::World;

/// Version tag at the start of the hashed stream; bump it if the layout changes.
pub const HASH_LAYOUT: &[u8] = b"VOLLEY-STATE-v1";

/// The bit pattern hashed for `x`: `-0.0` as `+0.0`, every NaN as the canonical quiet NaN.
#[inline]
pub fn canonical_bits(x: f64) -> u64 {
    if x.is_nan() {
        0x7ff8_0000_0000_0000
    } else if x == 0.0 {
        0
    } else {
        x.to_bits()
    }
}

/// The canonical hash of a world's state at its current tick.
pub fn state_hash(world: &World) -> u64 {
    let b = world.bodies();
    let mut h = Xxh3::new();
    h.update(HASH_LAYOUT);
    h.update(&world.tick().to_le_bytes());
    h.update(&world.rng().0.to_le_bytes());
    h.update(&(b.len() as u64).to_le_bytes());
    // Bodies are fed 64 at a time through a stack buffer: one `update` call per block.
    const BLOCK: usize = 64;
    const WORDS: usize = 9;
    let mut buf = [0u8; BLOCK * WORDS * 8];
    let (p, mv) = (b.positions(), b.momenta());
    let mut start = 0;
    while start < b.len() {
        let end = (start + BLOCK).min(b.len());
        let mut at = 0;
        for i in start..end {
            let words = [
                b.ids()[i].0,
                canonical_bits(p.x[i]),
                canonical_bits(p.y[i]),
                canonical_bits(p.z[i]),
                canonical_bits(mv.x[i]),
                canonical_bits(mv.y[i]),
                canonical_bits(mv.z[i]),
                canonical_bits(b.masses()[i]),
                canonical_bits(b.radii()[i]),
            ];
            for w in words {
                buf[at..at + 8].copy_from_slice(&w.to_le_bytes());
                at += 8;
            }
        }
        h.update(&buf[..at]);
        start = end;
    }
    h.digest()
}

/// Formats a hash as the CLI prints it: `0x` and 16 lowercase hex digits.
pub fn hex(hash: u64) -> String {
    format!("0x{hash:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_zero_and_nan_payloads_are_canonical() {
        assert_eq!(canonical_bits(-0.0), canonical_bits(0.0));
        let odd_nan = f64::from_bits(0x7ff8_0000_dead_beef);
        assert_eq!(canonical_bits(odd_nan), canonical_bits(f64::NAN));
        assert_ne!(canonical_bits(1.0), canonical_bits(-1.0));
    }
}
