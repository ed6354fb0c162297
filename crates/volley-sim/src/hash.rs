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
//! A world whose declared events keep counts (events that stop after more than one occurrence)
//! hashes that digest again with the counts (`with_tallies`).
//!
//! Floats are canonicalised first: `-0.0` hashes as `+0.0` and every NaN as the quiet NaN
//! `0x7ff8_0000_0000_0000`, so states that compare equal hash equal. The hash covers everything
//! that decides the future of the bodies; settings changed by commands (integrator, force
//! toggles, launcher) are not hashed because commands are recorded beside the hashes.

use xxhash_rust::xxh3::{Xxh3, xxh3_64};

use crate::body::{Bodies, HASHED_COLUMNS};
use crate::world::World;

/// Version tag at the start of the hashed stream; bump it if the layout changes.
pub const HASH_LAYOUT: &[u8] = b"VOLLEY-STATE-v1";

/// The bit pattern hashed for `x`: `-0.0` as `+0.0`, every NaN as the canonical quiet NaN.
///
/// Integer compares on the bit pattern (`|x|` is zero, or above infinity's pattern: a NaN), so
/// the compiler picks without branching; the same results as `x == 0.0` and `x.is_nan()`.
#[inline]
pub fn canonical_bits(x: f64) -> u64 {
    const QUIET_NAN: u64 = 0x7ff8_0000_0000_0000;
    const INFINITY: u64 = 0x7ff0_0000_0000_0000;
    let bits = x.to_bits();
    let magnitude = bits & !(1 << 63);
    let bits = if magnitude == 0 { 0 } else { bits };
    if magnitude > INFINITY {
        QUIET_NAN
    } else {
        bits
    }
}

/// 64-bit words hashed per body: the id and the hashed columns (p, mV, mass, radius).
const WORDS_PER_BODY: usize = 1 + HASHED_COLUMNS;

/// The hashed columns ([`crate::body::COLUMNS`]`[..HASHED_COLUMNS]`) of bodies `r`, in their order: the one
/// list of per-body fields decides what the hash covers, as it decides what keyframes store.
#[inline(always)]
fn hashed_fields(b: &Bodies, r: std::ops::Range<usize>) -> [&[f64]; HASHED_COLUMNS] {
    std::array::from_fn(|k| &b.column(k)[r.clone()])
}
/// Bytes hashed per body.
const BODY_BYTES: usize = WORDS_PER_BODY * 8;
/// Bytes before the first body: layout tag, tick, generator state, body count.
const HEAD_BYTES: usize = HASH_LAYOUT.len() + 3 * 8;
/// Worlds of more bodies than this stream through XXH3 in blocks of [`BLOCK`] bodies; smaller
/// ones are hashed in one shot from a stack buffer just large enough (XXH3's short-input path).
/// Both give the same digest: XXH3's streaming and one-shot forms agree on every input.
const ONE_SHOT_MAX: usize = 64;
/// Bodies per streamed block: large enough that XXH3's per-update overhead is small against
/// the block, small enough to stay in L1 with the arrays it is read from.
const BLOCK: usize = 64;

/// The canonical hash of a world's state at its current tick.
///
/// This is on every recorded tick's path, so it avoids work the definition does not need:
/// small worlds fill a buffer sized for them (no zeroing of a large one), the body words are
/// written through fixed-size chunks, without a bounds check per word, and larger worlds build
/// their records 8 bodies at a time where the CPU has AVX-512 (see `write_bodies_wide`).
///
/// Two runs of a scene agree bit for bit exactly when their hashes agree (up to collisions), on
/// any machine, vector width and thread count:
///
/// ```
/// use volley_sim::{World, bundled_scene, state_hash};
///
/// let scene = bundled_scene("seed").unwrap();
/// let (mut a, mut b) = (World::new(&scene), World::new(&scene));
/// b.set_threads(2);
/// a.step_ticks(20).unwrap();
/// for _ in 0..20 {
///     b.step().unwrap();
/// }
/// assert_eq!(state_hash(&a), state_hash(&b));
/// assert_eq!(volley_sim::internals::hash::hex(state_hash(&a)).len(), 18); // 0x and 16 hex digits
/// ```
pub fn state_hash(world: &World) -> u64 {
    let h = bodies_hash(world);
    let tallies = &world.state().tallies;
    if tallies.is_empty() {
        h
    } else {
        with_tallies(h, tallies)
    }
}

/// The hash of a world whose declared events keep counts ([`crate::world::Tallies`]): XXH3-64
/// of `"VOLLEY-TALLIES-v1"`, the bodies' hash, the two lengths and every count (u64 each,
/// little-endian), so a world without counts hashes as it did before declared events.
fn with_tallies(h: u64, t: &crate::world::Tallies) -> u64 {
    let mut x = Xxh3::new();
    x.update(b"VOLLEY-TALLIES-v1");
    x.update(&h.to_le_bytes());
    x.update(&(t.per_body.len() as u64).to_le_bytes());
    x.update(&(t.run.len() as u64).to_le_bytes());
    for c in t.per_body.iter().chain(&t.run) {
        x.update(&u64::from(*c).to_le_bytes());
    }
    x.digest()
}

/// The hash of the tick, the generator and the bodies.
#[inline]
fn bodies_hash(world: &World) -> u64 {
    match world.bodies().len() {
        0..=1 => one_shot::<{ HEAD_BYTES + BODY_BYTES }>(world),
        2 => one_shot::<{ HEAD_BYTES + 2 * BODY_BYTES }>(world),
        3..=4 => one_shot::<{ HEAD_BYTES + 4 * BODY_BYTES }>(world),
        5..=8 => one_shot::<{ HEAD_BYTES + 8 * BODY_BYTES }>(world),
        9..=16 => one_shot::<{ HEAD_BYTES + 16 * BODY_BYTES }>(world),
        17..=32 => one_shot::<{ HEAD_BYTES + 32 * BODY_BYTES }>(world),
        33..=ONE_SHOT_MAX => one_shot::<{ HEAD_BYTES + ONE_SHOT_MAX * BODY_BYTES }>(world),
        _ => streamed(world),
    }
}

/// The head of the stream: layout tag, tick, generator state, body count.
fn head(world: &World) -> [u8; HEAD_BYTES] {
    let mut head = [0u8; HEAD_BYTES];
    let (tag, words) = head.split_at_mut(HASH_LAYOUT.len());
    tag.copy_from_slice(HASH_LAYOUT);
    let values = [world.tick(), world.rng().0, world.bodies().len() as u64];
    for (out, w) in words.as_chunks_mut::<8>().0.iter_mut().zip(values) {
        *out = w.to_le_bytes();
    }
    head
}

/// Hashes a world of at most `(CAP - HEAD_BYTES) / BODY_BYTES` bodies from one stack buffer.
#[inline]
fn one_shot<const CAP: usize>(world: &World) -> u64 {
    let mut buf = [0u8; CAP];
    let (head_bytes, bodies) = buf.split_at_mut(HEAD_BYTES);
    head_bytes.copy_from_slice(&head(world));
    let n = world.bodies().len();
    write_bodies(world, 0..n, bodies);
    xxh3_64(&buf[..HEAD_BYTES + n * BODY_BYTES])
}

/// Hashes a world of any size, [`BLOCK`] bodies per XXH3 update.
#[inline(never)]
fn streamed(world: &World) -> u64 {
    let mut h = Xxh3::new();
    h.update(&head(world));
    let n = world.bodies().len();
    let mut buf = [0u8; BLOCK * BODY_BYTES];
    let mut start = 0;
    while start < n {
        let end = (start + BLOCK).min(n);
        let len = write_block(world, start..end, &mut buf);
        h.update(&buf[..len]);
        start = end;
    }
    h.digest()
}

/// Writes the canonical words of bodies `range` into the start of `out` (which must hold them);
/// returns the bytes written.
#[inline]
fn write_bodies(world: &World, range: std::ops::Range<usize>, out: &mut [u8]) -> usize {
    let b = world.bodies();
    let r = range;
    let ids = &b.ids()[r.clone()];
    let fields = hashed_fields(b, r);
    let chunks = &mut out.as_chunks_mut::<BODY_BYTES>().0[..ids.len()];
    for (i, (chunk, id)) in chunks.iter_mut().zip(ids).enumerate() {
        let (id_bytes, rest) = chunk.split_at_mut(8);
        id_bytes.copy_from_slice(&id.0.to_le_bytes());
        for (word, field) in rest.as_chunks_mut::<8>().0.iter_mut().zip(fields) {
            *word = canonical_bits(field[i]).to_le_bytes();
        }
    }
    ids.len() * BODY_BYTES
}

/// [`write_bodies`] for a streamed block: whole groups of 8 bodies through
/// [`write_bodies_wide`] where the CPU allows, the rest through the scalar loop. The one-shot
/// buffers of small worlds keep the scalar loop alone (and their code as small as it was).
#[inline]
fn write_block(world: &World, range: std::ops::Range<usize>, out: &mut [u8]) -> usize {
    let b = world.bodies();
    let fields = hashed_fields(b, range.clone());
    let ids = &b.ids()[range.clone()];
    let chunks = &mut out.as_chunks_mut::<BODY_BYTES>().0[..ids.len()];
    let done = write_bodies_wide(&fields, ids, chunks);
    let rest = range.start + done..range.end;
    let tail = &mut out[done * BODY_BYTES..];
    done * BODY_BYTES + write_bodies(world, rest, tail)
}

/// Writes the records of the first bodies 8 at a time with AVX-512 where the CPU has it
/// ([`crate::simd::simd_level`]); returns how many it wrote (a multiple of 8, or 0), the rest
/// being left to the scalar loop. Integer operations only, so the bytes are the scalar loop's.
#[inline]
fn write_bodies_wide(
    fields: &[&[f64]; HASHED_COLUMNS],
    ids: &[crate::body::BodyId],
    chunks: &mut [[u8; BODY_BYTES]],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    if ids.len() >= 8 && crate::simd::simd_level() == crate::simd::SimdLevel::Avx512 {
        // SAFETY: `simd_level` only reports instruction sets the CPU has.
        return unsafe { write_bodies_avx512(fields, ids, chunks) };
    }
    let _ = (fields, ids, chunks);
    0
}

// The wide writer transposes 8 x 8 words: a ninth hashed column needs a wider block.
const _: () = assert!(
    HASHED_COLUMNS == 8,
    "write_bodies_avx512 transposes 8 hashed columns"
);

/// Eight bodies per step: each field's eight words loaded as one vector and canonicalised
/// (`-0.0` to `+0.0`, every NaN to the quiet NaN, as [`canonical_bits`]), the 8 x 8 block of
/// words transposed from field-major to body-major, and each body's eight words stored after
/// its id with one 64-byte store.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn write_bodies_avx512(
    fields: &[&[f64]; HASHED_COLUMNS],
    ids: &[crate::body::BodyId],
    chunks: &mut [[u8; BODY_BYTES]],
) -> usize {
    use std::arch::x86_64::*;
    let n = ids.len().min(chunks.len()) / 8 * 8;
    let magnitude = _mm512_set1_epi64(i64::MAX);
    let infinity = _mm512_set1_epi64(0x7ff0_0000_0000_0000);
    let quiet_nan = _mm512_set1_epi64(0x7ff8_0000_0000_0000);
    for start in (0..n).step_by(8) {
        let mut r = [_mm512_setzero_si512(); 8];
        for (row, field) in r.iter_mut().zip(fields) {
            let words: &[f64; 8] = field[start..start + 8].try_into().expect("8 words");
            // SAFETY: an unaligned load of the 64 bytes `words` holds.
            let bits = unsafe { _mm512_loadu_si512(words.as_ptr().cast()) };
            let mag = _mm512_and_si512(bits, magnitude);
            let bits =
                _mm512_maskz_mov_epi64(!_mm512_cmpeq_epi64_mask(mag, _mm512_setzero_si512()), bits);
            *row = _mm512_mask_mov_epi64(bits, _mm512_cmpgt_epi64_mask(mag, infinity), quiet_nan);
        }
        // Rows are fields, lanes are bodies. Pairs of rows interleave, then 128-bit lanes
        // gather, twice: lane b of field f ends up as word f of column b.
        let t = [
            _mm512_unpacklo_epi64(r[0], r[1]),
            _mm512_unpackhi_epi64(r[0], r[1]),
            _mm512_unpacklo_epi64(r[2], r[3]),
            _mm512_unpackhi_epi64(r[2], r[3]),
            _mm512_unpacklo_epi64(r[4], r[5]),
            _mm512_unpackhi_epi64(r[4], r[5]),
            _mm512_unpacklo_epi64(r[6], r[7]),
            _mm512_unpackhi_epi64(r[6], r[7]),
        ];
        // 0x88: lanes 0 and 2 of each source; 0xdd: lanes 1 and 3.
        let u = [
            _mm512_shuffle_i64x2::<0x88>(t[0], t[2]),
            _mm512_shuffle_i64x2::<0xdd>(t[0], t[2]),
            _mm512_shuffle_i64x2::<0x88>(t[1], t[3]),
            _mm512_shuffle_i64x2::<0xdd>(t[1], t[3]),
            _mm512_shuffle_i64x2::<0x88>(t[4], t[6]),
            _mm512_shuffle_i64x2::<0xdd>(t[4], t[6]),
            _mm512_shuffle_i64x2::<0x88>(t[5], t[7]),
            _mm512_shuffle_i64x2::<0xdd>(t[5], t[7]),
        ];
        let columns = [
            _mm512_shuffle_i64x2::<0x88>(u[0], u[4]),
            _mm512_shuffle_i64x2::<0x88>(u[2], u[6]),
            _mm512_shuffle_i64x2::<0x88>(u[1], u[5]),
            _mm512_shuffle_i64x2::<0x88>(u[3], u[7]),
            _mm512_shuffle_i64x2::<0xdd>(u[0], u[4]),
            _mm512_shuffle_i64x2::<0xdd>(u[2], u[6]),
            _mm512_shuffle_i64x2::<0xdd>(u[1], u[5]),
            _mm512_shuffle_i64x2::<0xdd>(u[3], u[7]),
        ];
        for ((chunk, id), column) in chunks[start..start + 8]
            .iter_mut()
            .zip(&ids[start..start + 8])
            .zip(columns)
        {
            let (id_bytes, words) = chunk.split_at_mut(8);
            id_bytes.copy_from_slice(&id.0.to_le_bytes());
            let words: &mut [u8; 64] = words.try_into().expect("64 bytes");
            // SAFETY: an unaligned store into the 64 bytes `words` holds.
            unsafe { _mm512_storeu_si512(words.as_mut_ptr().cast(), column) };
        }
    }
    n
}

/// Formats a hash as the CLI prints it: `0x` and 16 lowercase hex digits.
pub fn hex(hash: u64) -> String {
    format!("0x{hash:016x}")
}

/// Parses a hash as [`hex`] prints it: 16 hex digits, `0x` optional, any case. Fewer digits
/// are refused: a hash cut short in a copy is a mistake to report, not a different hash.
pub fn parse_hex(text: &str) -> Result<u64, ParseHashError> {
    let digits = text
        .strip_prefix("0x")
        .or_else(|| text.strip_prefix("0X"))
        .unwrap_or(text);
    if digits.len() != 16 {
        return Err(ParseHashError::Length(text.to_string()));
    }
    if !digits.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(ParseHashError::NotHex(text.to_string()));
    }
    u64::from_str_radix(digits, 16).map_err(|_| ParseHashError::NotHex(text.to_string()))
}

/// Why [`parse_hex`] refused a text (the text given is in each variant). Both say what a hash
/// looks like, in the same words.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ParseHashError {
    /// Not 16 digits after the optional `0x`.
    Length(String),
    /// 16 characters after the optional `0x`, not all of them hex digits.
    NotHex(String),
}

impl std::fmt::Display for ParseHashError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (ParseHashError::Length(text) | ParseHashError::NotHex(text)) = self;
        write!(
            f,
            "expected a state hash as volley prints it (0x and 16 hex digits), got `{text}`"
        )
    }
}

impl std::error::Error for ParseHashError {}

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
            volley: (count: 300, speed_spread: 1, angle_spread_deg: 5))";
        let scene = crate::scene::parse(text, "inline.ron", "inline").unwrap();
        let mut world = World::new(&scene);
        world.step().unwrap();
        // Every one-shot buffer size, the one-shot / streaming boundary, and around block edges.
        for keep in [
            300, 257, 256, 129, 128, 127, 65, 64, 63, 9, 8, 7, 5, 4, 3, 2, 1, 0,
        ] {
            while world.bodies().len() > keep {
                let last = *world.bodies().ids().last().unwrap();
                world.despawn(last);
            }
            assert_eq!(state_hash(&world), reference_hash(&world), "{keep} bodies");
        }
    }

    #[test]
    fn printed_hashes_parse_back() {
        for h in [0, 1, 0xe02a_9ef4_a1dd_b321, u64::MAX] {
            assert_eq!(parse_hex(&hex(h)), Ok(h));
        }
        assert_eq!(parse_hex("E02A9EF4A1DDB321"), Ok(0xe02a_9ef4_a1dd_b321));
        for bad in [
            "",
            "0x",
            "abc",
            "0xe02a9ef4a1ddb32",
            "0x00000000000000001",
            "0xe02a9ef4a1ddb32g",
            " 0xe02a9ef4a1ddb321",
            "+e02a9ef4a1ddb321",
        ] {
            assert!(parse_hex(bad).is_err(), "{bad:?}");
        }
        assert!(matches!(parse_hex("0xabc"), Err(ParseHashError::Length(t)) if t == "0xabc"));
        assert!(matches!(
            parse_hex("0xe02a9ef4a1ddb32g"),
            Err(ParseHashError::NotHex(_))
        ));
    }

    #[test]
    fn parse_errors_print_as_they_did() {
        for bad in ["0xabc", "0xe02a9ef4a1ddb32g"] {
            assert_eq!(
                parse_hex(bad).unwrap_err().to_string(),
                format!(
                    "expected a state hash as volley prints it (0x and 16 hex digits), got \
                     `{bad}`"
                )
            );
        }
    }

    #[test]
    fn the_wide_records_are_the_scalar_ones_for_every_kind_of_float() {
        // Signed zeros, NaNs with payloads and signs, infinities, subnormals, ordinary values,
        // in every field and every lane position of two 8-body blocks and a remainder.
        let specials = [
            0.0,
            -0.0,
            f64::NAN,
            -f64::NAN,
            f64::from_bits(0x7ff0_0000_0000_0001),
            f64::from_bits(0xfff8_dead_beef_0000),
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE / 3.0,
            -1.5,
            2.0e300,
        ];
        let n = 19;
        let columns: Vec<Vec<f64>> = (0..8)
            .map(|f| {
                (0..n)
                    .map(|i| specials[(3 * i + 5 * f) % specials.len()])
                    .collect()
            })
            .collect();
        let fields: [&[f64]; 8] = std::array::from_fn(|f| &columns[f][..]);
        let ids: Vec<crate::body::BodyId> = (0..n as u64)
            .map(|i| crate::body::BodyId(i * 0x0101_0101_0101 + 7))
            .collect();
        let mut wide = vec![[0u8; BODY_BYTES]; n];
        let done = write_bodies_wide(&fields, &ids, &mut wide);
        for (i, record) in wide.iter().enumerate().take(done) {
            let mut expected = ids[i].0.to_le_bytes().to_vec();
            for field in fields {
                expected.extend_from_slice(&canonical_bits(field[i]).to_le_bytes());
            }
            assert_eq!(record[..], expected[..], "body {i}");
        }
        if crate::simd::simd_level() == crate::simd::SimdLevel::Avx512 {
            assert_eq!(
                done, 16,
                "two whole blocks of 8, the 3 left to the scalar loop"
            );
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
