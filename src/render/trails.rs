//! Trails: the last [`TRAIL_SAMPLES`] positions of each body, one sample per tick, in a ring.
//!
//! The ring is a table of rows, one row per tick, each row holding one sample per body slot
//! (slot = storage index). Recording a tick writes one contiguous row and moves the head; nothing
//! is shifted or reallocated. The GPU holds a copy of the same table and receives only the rows
//! written since its last upload (it remembers the ring's [`TrailRing::id`] and
//! [`TrailRing::rows_written`]); the trail shader walks back from the head row. A slot whose body changes (a reset, a despawn shifting the order) restarts
//! its trail at that tick.
//!
//! Only the first [`TRAIL_BODIES`] bodies get trails: beyond a few thousand they become a blur
//! that costs memory (16 bytes x 128 samples per body) and fill rate without showing anything.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::DVec3;

use crate::world::{BodyId, World};

/// Samples per trail (one per tick): 2.1 s at 60 Hz, 25.6 s at the seed's 0.2 s.
pub const TRAIL_SAMPLES: usize = 128;
/// Most bodies that get a trail (the first ones in id order).
pub const TRAIL_BODIES: usize = 2048;
/// Most trail segments drawn per frame, over all bodies and lanes: a few bodies get their whole
/// trail, a crowd gets shorter ones (at least [`MIN_TRAIL_SEGMENTS`]). Lines are the software
/// rasteriser's slowest primitive: 1000 full trails cost 16 ms a frame on lavapipe.
pub const TRAIL_SEGMENT_BUDGET: usize = 65_536;
/// Shortest trail drawn (segments) however many bodies share the budget.
pub const MIN_TRAIL_SEGMENTS: usize = 8;

/// Segments to draw per trail when `trails` trails share the budget.
pub fn segments_per_trail(trails: usize) -> u32 {
    let fair = TRAIL_SEGMENT_BUDGET / trails.max(1);
    fair.clamp(MIN_TRAIL_SEGMENTS, TRAIL_SAMPLES - 1) as u32
}
/// Smallest row width allocated (slots); rows grow in powers of two from here.
const MIN_STRIDE: usize = 16;

/// One sample: a position relative to the render origin (m); `w` is unused padding so a sample
/// is a WGSL `vec4<f32>`.
pub type Sample = [f32; 4];

/// The ring of recent positions.
#[derive(Debug)]
pub struct TrailRing {
    id: u64,
    origin: DVec3,
    stride: usize,
    samples: Vec<Sample>,
    slot_ids: Vec<Option<BodyId>>,
    births: Vec<u64>,
    used: usize,
    head: usize,
    tick: u64,
    rows_written: u64,
}

/// Source of [`TrailRing::id`]s.
static NEXT_RING: AtomicU64 = AtomicU64::new(1);

impl TrailRing {
    /// An empty ring storing positions relative to `origin`.
    pub fn new(origin: DVec3) -> TrailRing {
        TrailRing {
            id: NEXT_RING.fetch_add(1, Ordering::Relaxed),
            origin,
            stride: 0,
            samples: Vec::new(),
            slot_ids: Vec::new(),
            births: Vec::new(),
            used: 0,
            head: TRAIL_SAMPLES - 1,
            tick: 0,
            rows_written: 0,
        }
    }

    /// Records the world's positions as the newest row.
    pub fn record(&mut self, world: &World) {
        let bodies = world.bodies();
        let n = bodies.len().min(TRAIL_BODIES);
        self.ensure_stride(n);
        self.head = (self.head + 1) % TRAIL_SAMPLES;
        self.tick = world.tick();
        self.rows_written += 1;
        let row = self.head * self.stride;
        let p = bodies.positions();
        for (i, &id) in bodies.ids()[..n].iter().enumerate() {
            if self.slot_ids[i] != Some(id) {
                self.slot_ids[i] = Some(id);
                self.births[i] = self.tick;
            }
            let rel = (p.get(i) - self.origin).as_vec3();
            self.samples[row + i] = [rel.x, rel.y, rel.z, 0.0];
        }
        for slot in &mut self.slot_ids[n..self.used.max(n)] {
            *slot = None;
        }
        self.used = n;
    }

    fn ensure_stride(&mut self, n: usize) {
        if n <= self.stride {
            return;
        }
        let stride = n.next_power_of_two().max(MIN_STRIDE);
        let mut samples = vec![[0.0; 4]; stride * TRAIL_SAMPLES];
        for row in 0..TRAIL_SAMPLES {
            let old = &self.samples[row * self.stride..(row + 1) * self.stride];
            samples[row * stride..row * stride + self.stride].copy_from_slice(old);
        }
        self.samples = samples;
        self.slot_ids.resize(stride, None);
        self.births.resize(stride, 0);
        self.stride = stride;
    }

    /// Samples a trail of `slot` holds: ticks since its body took the slot, plus one, at most
    /// [`TRAIL_SAMPLES`]; 0 for an empty slot.
    pub fn count(&self, slot: usize) -> u32 {
        match self.slot_ids.get(slot) {
            Some(Some(_)) => {
                let span = (self.tick - self.births[slot] + 1).min(TRAIL_SAMPLES as u64);
                // Never more rows than were recorded since the ring was created.
                span.min(self.rows_written) as u32
            }
            _ => 0,
        }
    }

    /// Slots in use (bodies with a trail).
    pub fn used(&self) -> usize {
        self.used
    }

    /// Slots per row (the allocated width).
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Index of the newest row.
    pub fn head(&self) -> usize {
        self.head
    }

    /// The render origin samples are relative to.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// The whole table, row after row.
    pub fn samples(&self) -> &[Sample] {
        &self.samples
    }

    /// The sample of `slot` `age` rows before the head (0 = newest).
    pub fn sample(&self, slot: usize, age: usize) -> Sample {
        let row = (self.head + TRAIL_SAMPLES - age % TRAIL_SAMPLES) % TRAIL_SAMPLES;
        self.samples[row * self.stride + slot]
    }

    /// Rows recorded since the ring was created.
    pub fn rows_written(&self) -> u64 {
        self.rows_written
    }

    /// An id no other ring in this process has: a copy knows when it follows another ring.
    pub fn id(&self) -> u64 {
        self.id
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_few_trails_are_whole_and_a_crowd_shares_the_budget() {
        assert_eq!(segments_per_trail(0), (TRAIL_SAMPLES - 1) as u32);
        assert_eq!(segments_per_trail(1), (TRAIL_SAMPLES - 1) as u32);
        assert_eq!(segments_per_trail(1000), 65);
        assert_eq!(segments_per_trail(TRAIL_BODIES), 32);
        assert_eq!(segments_per_trail(1 << 20), MIN_TRAIL_SEGMENTS as u32);
    }
}
