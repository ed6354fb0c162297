//! What the live plots show, kept for the whole run in bounded memory.
//!
//! A [`Decimated`] series keeps the minimum and maximum of each time bucket in at most
//! [`BUCKETS`] buckets: when they are full, neighbours merge in pairs and the bucket width
//! doubles. A spike survives any amount of decimation (it is some bucket's maximum), and the
//! memory is fixed: [`LaneSeries`] holds three series a lane, so a lane's plots take at most
//! `3 * BUCKETS * size_of::<Bucket>()` bytes (192 KiB; 768 KiB for four lanes) however long the
//! run. `tests/window/window_plots.rs` runs an hour at 60 Hz in four lanes against that budget.
//!
//! Per tick a lane samples, over its first [`PLOT_BODIES`] bodies: body 0's position error and
//! the largest one against the closed-form reference (bodies with one), and the relative energy
//! error `(E - E0) / scale` summed over them, with each body's `E0` and `scale` (the divergence
//! guard's: the magnitudes of its kinetic and potential terms at spawn) taken the first time it
//! is seen. The work-precision point is the lane's force evaluations per simulated second
//! against the largest position error so far.

use crate::render::reference::{BodyError, References};
use crate::world::{BodyId, World};

/// Buckets a series keeps.
pub const BUCKETS: usize = 2048;
/// Bodies a lane's plots sample each tick (the first ones, so the cost stays bounded).
pub const PLOT_BODIES: usize = 64;

/// The minimum and maximum of the samples in one time bucket.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bucket {
    /// Sim time of the bucket's first sample (s).
    pub t: f64,
    /// First tick the bucket covers.
    pub tick: u64,
    /// Smallest sample.
    pub min: f64,
    /// Largest sample.
    pub max: f64,
}

/// Min and max per time bucket, at most [`BUCKETS`] of them.
#[derive(Clone, Debug)]
pub struct Decimated {
    buckets: Vec<Bucket>,
    /// Ticks a bucket covers (a power of two).
    width: u64,
    start: Option<u64>,
}

impl Default for Decimated {
    fn default() -> Self {
        Decimated {
            buckets: Vec::with_capacity(BUCKETS),
            width: 1,
            start: None,
        }
    }
}

impl Decimated {
    /// Adds the sample `value` of `tick` (at sim time `t`); a NaN is skipped. Ticks must come in
    /// increasing order (an earlier one is ignored).
    pub fn push(&mut self, tick: u64, t: f64, value: f64) {
        if value.is_nan() {
            return;
        }
        let start = *self.start.get_or_insert(tick);
        if tick < start || self.buckets.last().is_some_and(|b| tick < b.tick) {
            return;
        }
        let slot = (tick - start) / self.width * self.width + start;
        match self.buckets.last_mut() {
            Some(b) if b.tick == slot => {
                b.min = b.min.min(value);
                b.max = b.max.max(value);
            }
            _ => {
                if self.buckets.len() == BUCKETS {
                    self.merge();
                    return self.push(tick, t, value);
                }
                self.buckets.push(Bucket {
                    t,
                    tick: slot,
                    min: value,
                    max: value,
                });
            }
        }
    }

    /// Doubles the bucket width, merging neighbours.
    fn merge(&mut self) {
        let start = self.start.unwrap_or(0);
        self.width *= 2;
        let width = self.width;
        let mut merged: Vec<Bucket> = Vec::with_capacity(BUCKETS);
        for b in &self.buckets {
            let slot = (b.tick - start) / width * width + start;
            match merged.last_mut() {
                Some(m) if m.tick == slot => {
                    m.min = m.min.min(b.min);
                    m.max = m.max.max(b.max);
                }
                _ => merged.push(Bucket { tick: slot, ..*b }),
            }
        }
        self.buckets.clear();
        self.buckets.extend_from_slice(&merged);
    }

    /// Drops the buckets that start after `tick` (the recorded future was replaced).
    pub fn truncate(&mut self, tick: u64) {
        let k = self.buckets.partition_point(|b| b.tick <= tick);
        self.buckets.truncate(k);
    }

    /// At most `points` (t, min, max) triples for drawing: runs of neighbouring buckets merged
    /// (min of mins, max of maxes), so a plot a few hundred pixels wide draws a few hundred
    /// points whatever the history holds, and a spike still shows.
    pub fn for_display(&self, points: usize) -> Vec<(f64, f64, f64)> {
        let k = self.buckets.len().div_ceil(points.max(1)).max(1);
        self.buckets
            .chunks(k)
            .map(|c| {
                let (lo, hi) = c
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), b| {
                        (l.min(b.min), h.max(b.max))
                    });
                (c[0].t, lo, hi)
            })
            .collect()
    }

    /// The buckets, oldest first.
    pub fn buckets(&self) -> &[Bucket] {
        &self.buckets
    }

    /// Ticks a bucket covers now.
    pub fn width(&self) -> u64 {
        self.width
    }

    /// The largest sample kept.
    pub fn max(&self) -> Option<f64> {
        self.buckets.iter().map(|b| b.max).reduce(f64::max)
    }

    /// Bytes the series holds, at most `BUCKETS * size_of::<Bucket>()` plus its header.
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.buckets.capacity() * std::mem::size_of::<Bucket>()
    }
}

/// One body's energy at spawn and the guard's scale for it.
#[derive(Clone, Copy, Debug)]
struct EnergyStart {
    id: BodyId,
    e0: f64,
    scale: f64,
}

/// A lane's plotted series.
#[derive(Clone, Debug, Default)]
pub struct LaneSeries {
    /// Body 0's position error (m).
    pub error_first: Decimated,
    /// The largest position error over the first bodies (m).
    pub error_max: Decimated,
    /// Relative energy error over the first bodies.
    pub energy: Decimated,
    starts: Vec<EnergyStart>,
    /// Ticks sampled.
    pub samples: u64,
    last: Option<u64>,
}

impl LaneSeries {
    /// Samples the lane's world after a tick (ticks already sampled, replayed after a seek,
    /// are skipped).
    pub fn sample(&mut self, world: &World, references: &References) {
        let tick = world.tick();
        if self.last.is_some_and(|l| tick <= l) {
            return;
        }
        self.last = Some(tick);
        self.samples += 1;
        let t = world.time();
        let n = world.bodies().len().min(PLOT_BODIES);
        let mut largest = f64::NAN;
        for i in 0..n {
            if let BodyError::Measured { position, .. } = references.error(world, i) {
                if i == 0 {
                    self.error_first.push(tick, t, position);
                }
                largest = if largest.is_nan() {
                    position
                } else {
                    largest.max(position)
                };
            }
        }
        self.error_max.push(tick, t, largest);
        let factor = world.params().guard.energy_factor;
        let (mut e, mut e0, mut scale) = (0.0, 0.0, 0.0);
        let bodies = world.bodies();
        for i in 0..n {
            let id = bodies.ids()[i];
            let now = world.energy_of(i);
            let start = match self.starts.binary_search_by_key(&id, |s| s.id) {
                Ok(k) => self.starts[k],
                Err(k) => {
                    let cap = bodies.energy_cap[i];
                    let s = EnergyStart {
                        id,
                        e0: now,
                        scale: if factor > 1.0 {
                            (cap - now) / (factor - 1.0)
                        } else {
                            now.abs()
                        },
                    };
                    if self.starts.len() < 4 * PLOT_BODIES {
                        self.starts.insert(k, s);
                    }
                    s
                }
            };
            (e, e0, scale) = (e + now, e0 + start.e0, scale + start.scale);
        }
        if n > 0 && scale > 0.0 {
            self.energy.push(tick, t, (e - e0) / scale);
        }
    }

    /// Drops what was sampled after `tick` (a new command replaced the recorded future).
    pub fn truncate(&mut self, tick: u64) {
        for s in [&mut self.error_first, &mut self.error_max, &mut self.energy] {
            s.truncate(tick);
        }
        self.last = self.last.map(|l| l.min(tick));
    }

    /// Bytes the three series hold.
    pub fn bytes(&self) -> usize {
        self.error_first.bytes()
            + self.error_max.bytes()
            + self.energy.bytes()
            + self.starts.capacity() * std::mem::size_of::<EnergyStart>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spike_survives_any_amount_of_decimation_and_the_bucket_count_stays_bounded() {
        let mut s = Decimated::default();
        let n = 60 * 3600;
        for tick in 0..n {
            let v = if tick == 123_457 {
                1e3
            } else {
                (tick % 7) as f64
            };
            s.push(tick, tick as f64 / 60.0, v);
        }
        assert!(s.buckets().len() <= BUCKETS);
        assert!(s.buckets().len() > BUCKETS / 2, "{}", s.buckets().len());
        assert_eq!(s.max(), Some(1e3));
        let spike = s.buckets().iter().find(|b| b.max == 1e3).unwrap();
        assert!(spike.tick <= 123_457 && 123_457 < spike.tick + s.width());
        assert!(
            s.buckets().iter().all(|b| b.min == 0.0),
            "every bucket spans a whole 0..6 cycle"
        );
        s.truncate(100_000);
        assert!(s.buckets().last().unwrap().tick <= 100_000);
        assert_eq!(s.max(), Some(6.0));
    }
}
