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

use xxhash_rust::xxh3::{Xxh3, xxh3_64};

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

/// 64-bit words hashed per body: id, p, mV, mass, radius.
const WORDS_PER_BODY: usize = 9;
/// Bytes before the first body: layout tag, tick, generator state, body count.
const HEAD_BYTES: usize = HASH_LAYOUT.len() + 3 * 8;
/// Worlds with at most this many bodies are hashed in one shot from a stack buffer (XXH3's
/// short-input path); larger ones stream in blocks of this many bodies. Both give the same
/// digest: XXH3's streaming and one-shot forms agree on every input.
const BLOCK: usize = 8;

/// The canonical hash of a world's state at its current tick.
pub fn state_hash(world: &World) -> u64 {
    let b = world.bodies();
    let mut buf = [0u8; HEAD_BYTES + BLOCK * WORDS_PER_BODY * 8];
    buf[..HASH_LAYOUT.len()].copy_from_slice(HASH_LAYOUT);
    let head = [world.tick(), world.rng().0, b.len() as u64];
    let mut at = HASH_LAYOUT.len();
    for w in head {
        buf[at..at + 8].copy_from_slice(&w.to_le_bytes());
        at += 8;
    }
    if b.len() <= BLOCK {
        let end = write_bodies(world, 0..b.len(), &mut buf[at..]);
        return xxh3_64(&buf[..at + end]);
    }
    let mut h = Xxh3::new();
    h.update(&buf[..at]);
    let mut start = 0;
    while start < b.len() {
        let end = (start + BLOCK).min(b.len());
        let len = write_bodies(world, start..end, &mut buf);
        h.update(&buf[..len]);
        start = end;
    }
    h.digest()
}

/// Writes the canonical words of bodies `range` into `out`; returns the bytes written.
#[inline]
fn write_bodies(world: &World, range: std::ops::Range<usize>, out: &mut [u8]) -> usize {
    let b = world.bodies();
    let (p, mv) = (b.positions(), b.momenta());
    let mut at = 0;
    for i in range {
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
            out[at..at + 8].copy_from_slice(&w.to_le_bytes());
            at += 8;
        }
    }
    at
}

/// Formats a hash as the CLI prints it: `0x` and 16 lowercase hex digits.
pub fn hex(hash: u64) -> String {
    format!("0x{hash:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The documented byte stream, built naively and hashed in one call.
    fn reference_hash(world: &World) -> u64 {
        let b = world.bodies();
        let mut bytes = HASH_LAYOUT.to_vec();
        for w in [world.tick(), world.rng().0, b.len() as u64] {
            bytes.extend_from_slice(&w.to_le_bytes());
        }
        for i in 0..b.len() {
            let (p, mv) = (b.positions().get(i), b.momenta().get(i));
            bytes.extend_from_slice(&b.ids()[i].0.to_le_bytes());
            for x in [p.x, p.y, p.z, mv.x, mv.y, mv.z, b.masses()[i], b.radii()[i]] {
                bytes.extend_from_slice(&canonical_bits(x).to_le_bytes());
            }
        }
        xxh3_64(&bytes)
    }

    #[test]
    fn one_shot_and_streamed_hashes_follow_the_documented_stream() {
        let text = "Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0, 0, -9.81))],
            launcher: (position: (0, 0, 1), speed: 10, elevation_deg: 45, azimuth_deg: 0),
            volley: (count: 100, speed_spread: 1, angle_spread_deg: 5))";
        let scene = crate::scene::parse(text, "inline.ron", "inline").unwrap();
        let mut world = World::new(&scene);
        world.step().unwrap();
        // Around the one-shot / streaming boundary and across several blocks.
        for keep in [100, 17, 9, 8, 7, 1, 0] {
            while world.bodies().len() > keep {
                let last = *world.bodies().ids().last().unwrap();
                world.despawn(last);
            }
            assert_eq!(state_hash(&world), reference_hash(&world), "{keep} bodies");
        }
    }

    #[test]
    fn signed_zero_and_nan_payloads_are_canonical() {
        assert_eq!(canonical_bits(-0.0), canonical_bits(0.0));
        let odd_nan = f64::from_bits(0x7ff8_0000_dead_beef);
        assert_eq!(canonical_bits(odd_nan), canonical_bits(f64::NAN));
        assert_ne!(canonical_bits(1.0), canonical_bits(-1.0));
    }
}
