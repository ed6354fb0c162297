//! The keyframe record: a [`Snapshot`] of the world, streamed to the file without allocating.

use std::io::{self, Write};

use glam::DVec3;

use crate::body::LAUNCH_COLUMNS;
use crate::forces::{ForceKind, Forces};
use crate::integrate::Integrator;
use crate::scene::Launcher;
use crate::world::{BodyId, COLUMNS, Snapshot, SplitMix64, Vec3s};

use super::format::{
    CRC_LEN, DecodeError, FORMAT_VERSION, HEAD_LEN, Kind, Reader, Words, frame_head,
};

/// Bytes of a keyframe before its body arrays.
pub const KEYFRAME_FIXED: usize = 3 * 8 + 5 + 10 * 8 + 8 + 8;

/// Bytes per body in a keyframe: the id and one float per column ([`COLUMNS`]; without the
/// launch columns when every launch is canonical), plus 3 with a carried force.
fn per_body(carry: bool, launch: bool) -> usize {
    let columns = COLUMNS.len() - if launch { 0 } else { LAUNCH_COLUMNS.len() };
    (1 + columns + if carry { 3 } else { 0 }) * 8
}

/// Payload length of a keyframe of `n` bodies, with a carried force and the launch columns or
/// not, if it fits a frame.
pub fn keyframe_len(n: usize, carry: bool, launch: bool) -> Option<u32> {
    n.checked_mul(per_body(carry, launch))
        .and_then(|b| b.checked_add(KEYFRAME_FIXED))
        .and_then(|l| u32::try_from(l).ok())
}

/// Bytes the event tallies add to a keyframe ([`crate::world::Tallies`]): two lengths and a
/// word per count; none without tallies.
fn tallies_len(t: &crate::world::Tallies) -> Option<usize> {
    if t.is_empty() {
        return Some(0);
    }
    t.per_body
        .len()
        .checked_add(t.run.len())
        .and_then(|w| w.checked_add(2))
        .and_then(|w| w.checked_mul(8))
}

/// Writes a keyframe frame, streaming the body arrays through the CRC: no allocation.
///
/// Payload: `tick next_id rng:u64  integrator:u8 forces_mask:u16 has_carry:u8 flags:u8
/// launcher
/// (position xyz, speed, elevation, azimuth, mass, radius, backspin, sidespin):10 f64
/// force_evals n:u64`, then arrays of n: ids, then every column of [`COLUMNS`] in its order
/// (p, mV, mass, radius, energy_cap, and launch time and mass and spin if the flags' bit 0, has
/// launch, is set: left out when every body's launch is canonical,
/// [`crate::body::Bodies::launch_is_canonical`]), and carry x y z if has_carry. With the flags'
/// bit 1, has tallies (a scene whose declared events stop after more than one occurrence,
/// [`crate::world::Tallies`]), then `per_body_len:u64 run_len:u64` and the counts as u64 words:
/// the per-body ones, then the run's. A keyframe without tallies is byte for byte what it was
/// before declared events; a build before them refuses one with tallies (its flags above 1).
pub fn encode_keyframe(out: &mut impl Write, s: &Snapshot) -> io::Result<u64> {
    let carry = !s.carry.is_empty();
    let launch = !s.bodies.launch_is_canonical();
    let tallies = !s.tallies.is_empty();
    let n = s.bodies.id.len();
    let too_large = || {
        io::Error::other(format!(
            "a keyframe of {n} bodies is too large for format v{FORMAT_VERSION}"
        ))
    };
    let len = keyframe_len(n, carry, launch)
        .zip(tallies_len(&s.tallies))
        .and_then(|(l, t)| u32::try_from(l as usize + t).ok())
        .ok_or_else(too_large)?;
    let mut w = CrcWrite::new(out);
    w.put(&frame_head(Kind::Keyframe, len))?;
    let mut fixed = Words::default();
    let integrator = Integrator::ALL.iter().position(|i| *i == s.integrator);
    let mask = ForceKind::ALL
        .iter()
        .enumerate()
        .filter(|(_, k)| s.forces.has(**k))
        .fold(0u16, |m, (_, k)| m | (1 << (*k as u16)));
    let l = &s.launcher;
    fixed.u64(s.tick).u64(s.next_id).u64(s.rng.0);
    fixed
        .u8(integrator.unwrap_or(0) as u8)
        .u16(mask)
        .u8(carry as u8)
        .u8(launch as u8 | (tallies as u8) << 1);
    for x in [
        l.position.x,
        l.position.y,
        l.position.z,
        l.speed,
        l.elevation_deg,
    ] {
        fixed.f64(x);
    }
    fixed.f64(l.azimuth_deg).f64(l.mass).f64(l.radius);
    fixed.f64(l.backspin).f64(l.sidespin);
    fixed.u64(s.force_evals).u64(n as u64);
    w.put(fixed.bytes())?;
    w.words(s.bodies.id.iter().map(|id| id.0))?;
    for column in COLUMNS
        .iter()
        .filter(|c| launch || !LAUNCH_COLUMNS.contains(&c.index))
    {
        w.words(column.get(&s.bodies).iter().map(|x| x.to_bits()))?;
    }
    if carry {
        for a in [&s.carry.x, &s.carry.y, &s.carry.z] {
            w.words(a.iter().map(|x| x.to_bits()))?;
        }
    }
    if tallies {
        let t = &s.tallies;
        w.words([t.per_body.len() as u64, t.run.len() as u64].into_iter())?;
        w.words(t.per_body.iter().chain(&t.run).map(|&c| u64::from(c)))?;
    }
    w.finish()?;
    Ok((HEAD_LEN + len as usize + CRC_LEN) as u64)
}

/// Reads a keyframe's payload into `s` (reusing its buffers); `declared` are the scene's force
/// terms, whose values the active ones take. Checks the structure (sizes, tags, increasing ids,
/// active terms declared); [`crate::World::restore`] checks the rest against the scene.
pub fn decode_keyframe(
    payload: &[u8],
    declared: &Forces,
    s: &mut Snapshot,
) -> Result<(), DecodeError> {
    let mut r = Reader::new(payload);
    (s.tick, s.next_id, s.rng) = (r.u64()?, r.u64()?, SplitMix64(r.u64()?));
    let (integrator, mask, carry, flags) = (r.u8()?, r.u16()?, r.u8()?, r.u8()?);
    let (launch, tallies) = (flags & 1, flags >> 1);
    s.integrator = *Integrator::ALL
        .get(usize::from(integrator))
        .ok_or(DecodeError::IntegratorTag(integrator))?;
    if mask >> ForceKind::ALL.len() != 0 || carry > 1 || flags > 3 {
        return Err(DecodeError::MaskOrCarry {
            mask,
            carry,
            launch: flags,
        });
    }
    let active = |k: ForceKind| mask & (1 << (k as u16)) != 0;
    if let Some(k) = ForceKind::ALL
        .into_iter()
        .find(|&k| active(k) && !declared.has(k))
    {
        return Err(DecodeError::UndeclaredForce(k));
    }
    s.forces = declared.filtered(active);
    let mut f = [0.0; 10];
    for x in &mut f {
        *x = r.f64()?;
    }
    s.launcher = Launcher {
        position: DVec3::new(f[0], f[1], f[2]),
        speed: f[3],
        elevation_deg: f[4],
        azimuth_deg: f[5],
        mass: f[6],
        radius: f[7],
        backspin: f[8],
        sidespin: f[9],
    };
    s.force_evals = r.u64()?;
    let n = r.u64()?;
    let bodies_len = usize::try_from(n)
        .ok()
        .and_then(|n| keyframe_len(n, carry == 1, launch == 1));
    let fits = match bodies_len {
        Some(l) if tallies == 0 => l as usize == payload.len(),
        // The tallies' lengths sit at the end of the body part: read them there.
        Some(l) => payload
            .get(l as usize..l as usize + 16)
            .and_then(|w| {
                let word = |k: usize| {
                    u64::from_le_bytes(w[k..k + 8].try_into().ok()?)
                        .try_into()
                        .ok()
                };
                let (a, b): (usize, usize) = (word(0)?, word(8)?);
                a.checked_add(b)?
                    .checked_mul(8)?
                    .checked_add(l as usize + 16)
            })
            .is_some_and(|total| total == payload.len()),
        None => false,
    };
    if !fits {
        return Err(DecodeError::BodyCount {
            bodies: n,
            len: payload.len(),
        });
    }
    let n = n as usize;
    let b = &mut s.bodies;
    b.id.clear();
    b.id.extend(r.take_u64s(n)?.map(BodyId));
    if !b.id.windows(2).all(|w| w[0] < w[1]) {
        return Err(DecodeError::IdsNotIncreasing);
    }
    for column in COLUMNS
        .iter()
        .filter(|c| launch == 1 || !LAUNCH_COLUMNS.contains(&c.index))
    {
        let a = column.get_mut(b);
        a.clear();
        a.extend(r.take_u64s(n)?.map(f64::from_bits));
    }
    if launch == 0 {
        b.canonical_launch();
    }
    b.recompute_inv_mass();
    if carry == 1 {
        read_vec3s(&mut r, n, &mut s.carry)?;
    } else {
        read_vec3s(&mut r, 0, &mut s.carry)?;
    }
    s.tallies.per_body.clear();
    s.tallies.run.clear();
    if tallies == 1 {
        let (a, b) = (r.u64()? as usize, r.u64()? as usize);
        let count = |w: u64| u32::try_from(w).map_err(|_| DecodeError::Tally(w));
        for w in r.take_u64s(a)? {
            s.tallies.per_body.push(count(w)?);
        }
        for w in r.take_u64s(b)? {
            s.tallies.run.push(count(w)?);
        }
    }
    r.end()
}

fn read_vec3s(r: &mut Reader, n: usize, v: &mut Vec3s) -> Result<(), DecodeError> {
    for c in [&mut v.x, &mut v.y, &mut v.z] {
        c.clear();
        c.extend(r.take_u64s(n)?.map(f64::from_bits));
    }
    Ok(())
}

/// A writer that feeds every byte through a CRC-32 and appends it at the end.
struct CrcWrite<'a, W: Write> {
    out: &'a mut W,
    crc: crc32fast::Hasher,
    buf: [u8; 4096],
}

impl<'a, W: Write> CrcWrite<'a, W> {
    fn new(out: &'a mut W) -> Self {
        CrcWrite {
            out,
            crc: crc32fast::Hasher::new(),
            buf: [0; 4096],
        }
    }

    fn put(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.crc.update(bytes);
        self.out.write_all(bytes)
    }

    /// Writes 64-bit words little-endian, 512 at a time through a stack buffer.
    fn words(&mut self, words: impl Iterator<Item = u64>) -> io::Result<()> {
        let mut at = 0;
        for w in words {
            self.buf[at..at + 8].copy_from_slice(&w.to_le_bytes());
            at += 8;
            if at == self.buf.len() {
                self.crc.update(&self.buf);
                self.out.write_all(&self.buf)?;
                at = 0;
            }
        }
        self.crc.update(&self.buf[..at]);
        self.out.write_all(&self.buf[..at])
    }

    fn finish(self) -> io::Result<()> {
        let crc = self.crc.finalize();
        self.out.write_all(&crc.to_le_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyframes_that_do_not_decode_say_why() {
        let text = "Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0, 0, -9.81))],
            bodies: [(mass: 1, position: (0, 0, 1)), (mass: 2, position: (1, 0, 1))])";
        let scene = crate::scene::parse(text, "inline.ron", "inline").unwrap();
        let world = crate::World::new(&scene);
        let mut frame = Vec::new();
        encode_keyframe(&mut frame, &world.snapshot()).unwrap();
        let payload = &frame[HEAD_LEN..frame.len() - CRC_LEN];
        let mut s = world.snapshot();
        decode_keyframe(payload, &scene.forces, &mut s).unwrap();
        assert_eq!(s, world.snapshot());

        let decode = |bytes: &[u8], declared: &Forces| {
            decode_keyframe(bytes, declared, &mut world.snapshot()).unwrap_err()
        };
        let mut bad = payload.to_vec();
        bad[24] = 99;
        assert_eq!(decode(&bad, &scene.forces), DecodeError::IntegratorTag(99));
        assert_eq!(
            decode(payload, &Forces::default()),
            DecodeError::UndeclaredForce(ForceKind::Gravity)
        );
        assert_eq!(
            decode(&payload[..10], &scene.forces),
            DecodeError::Truncated { len: 10 }
        );
        let long = [payload, &[0; 8]].concat();
        assert_eq!(
            decode(&long, &scene.forces),
            DecodeError::BodyCount {
                bodies: 2,
                len: payload.len() + 8
            }
        );
    }
}
