//! Bodies: stable ids, the per-body state `<mV, p>` and mass, and the structure-of-arrays
//! columns the world keeps them in.
//!
//! The bottom layer: nothing here imports another module of the crate. Bodies are stored in id
//! order, one array per component (`x`, `y`, `z` of position and momentum, mass, radius), so the
//! per-body loop streams through memory and vectorises. Ids are handed out in spawn order and
//! never reused; despawning keeps the order of the rest (an ordered removal), so "in id order"
//! and "in storage order" are the same thing everywhere.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The mechanical state of one body in the seed's form: momentum and position.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyState {
    /// Position p (m).
    pub p: DVec3,
    /// Linear momentum mV (kg m/s).
    pub mv: DVec3,
}

/// A body's mass and its reciprocal, computed once at spawn.
///
/// The hot loop forms `V = mV * (1/m)`: a multiply instead of a divide per component.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mass {
    /// Mass m (kg).
    pub m: f64,
    /// 1 / m (1/kg).
    pub inv: f64,
}

impl Mass {
    /// A mass and its reciprocal.
    #[inline(always)]
    pub fn new(m: f64) -> Mass {
        Mass { m, inv: 1.0 / m }
    }
}

impl BodyState {
    /// Velocity V = mV / m (m/s), as the integrators form it.
    #[inline(always)]
    pub fn velocity(&self, w: Mass) -> DVec3 {
        self.mv * w.inv
    }

    /// Whether every component is finite.
    #[inline(always)]
    pub fn is_finite(&self) -> bool {
        self.p.is_finite() && self.mv.is_finite()
    }
}

/// Stable identifier of a body: assigned in spawn order from 0, never reused.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
pub struct BodyId(pub u64);

impl std::fmt::Display for BodyId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// Three parallel arrays of f64: a vector field in structure-of-arrays form.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Vec3s {
    /// x components.
    pub x: Vec<f64>,
    /// y components.
    pub y: Vec<f64>,
    /// z components.
    pub z: Vec<f64>,
}

impl Vec3s {
    /// The vector at `i`.
    #[inline(always)]
    pub fn get(&self, i: usize) -> DVec3 {
        DVec3::new(self.x[i], self.y[i], self.z[i])
    }

    /// Overwrites the vector at `i`.
    #[inline(always)]
    pub fn set(&mut self, i: usize, v: DVec3) {
        self.x[i] = v.x;
        self.y[i] = v.y;
        self.z[i] = v.z;
    }

    fn push(&mut self, v: DVec3) {
        self.x.push(v.x);
        self.y.push(v.y);
        self.z.push(v.z);
    }

    fn remove(&mut self, i: usize) {
        self.x.remove(i);
        self.y.remove(i);
        self.z.remove(i);
    }

    fn clear(&mut self) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
    }

    pub(crate) fn resize(&mut self, n: usize) {
        self.x.resize(n, 0.0);
        self.y.resize(n, 0.0);
        self.z.resize(n, 0.0);
    }

    /// Number of vectors.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Copies all vectors from `other` (reusing this one's allocation).
    pub fn copy_from(&mut self, other: &Vec3s) {
        self.x.clone_from(&other.x);
        self.y.clone_from(&other.y);
        self.z.clone_from(&other.z);
    }

    /// Iterates over the vectors.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = DVec3> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }
}

/// All bodies, structure of arrays, in id order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bodies {
    pub(crate) id: Vec<BodyId>,
    pub(crate) p: Vec3s,
    pub(crate) mv: Vec3s,
    pub(crate) mass: Vec<f64>,
    /// 1 / mass, computed once at spawn so the hot loop multiplies instead of dividing.
    pub(crate) inv_mass: Vec<f64>,
    pub(crate) radius: Vec<f64>,
    /// Energy above which the guard stops the run, per body (J).
    pub(crate) energy_cap: Vec<f64>,
}

impl Bodies {
    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// Whether there are no bodies.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Ids in storage (= id) order.
    pub fn ids(&self) -> &[BodyId] {
        &self.id
    }

    /// Positions (m).
    pub fn positions(&self) -> &Vec3s {
        &self.p
    }

    /// Momenta (kg m/s).
    pub fn momenta(&self) -> &Vec3s {
        &self.mv
    }

    /// Masses (kg).
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }

    /// Radii (m).
    pub fn radii(&self) -> &[f64] {
        &self.radius
    }

    /// Velocity (m/s) of the body at storage index `i`, formed as the integrators form it.
    pub fn velocity(&self, i: usize) -> DVec3 {
        self.mv.get(i) * self.inv_mass[i]
    }

    /// State of the body at storage index `i`.
    pub fn state(&self, i: usize) -> BodyState {
        BodyState {
            p: self.p.get(i),
            mv: self.mv.get(i),
        }
    }

    /// Storage index of a body, by binary search over the sorted ids.
    pub fn index_of(&self, id: BodyId) -> Option<usize> {
        self.id.binary_search(&id).ok()
    }

    /// Appends a body with momentum `mass * velocity` and no energy bound yet.
    pub(crate) fn push(
        &mut self,
        id: BodyId,
        position: DVec3,
        velocity: DVec3,
        mass: f64,
        radius: f64,
    ) {
        self.id.push(id);
        self.p.push(position);
        self.mv.push(mass * velocity);
        self.mass.push(mass);
        self.inv_mass.push(1.0 / mass);
        self.radius.push(radius);
        self.energy_cap.push(f64::INFINITY);
    }

    pub(crate) fn remove(&mut self, i: usize) {
        self.id.remove(i);
        self.p.remove(i);
        self.mv.remove(i);
        self.mass.remove(i);
        self.inv_mass.remove(i);
        self.radius.remove(i);
        self.energy_cap.remove(i);
    }

    pub(crate) fn clear(&mut self) {
        self.id.clear();
        self.p.clear();
        self.mv.clear();
        self.mass.clear();
        self.inv_mass.clear();
        self.radius.clear();
        self.energy_cap.clear();
    }
}
