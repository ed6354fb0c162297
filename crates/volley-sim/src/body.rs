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
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BodyState {
    /// Position p (m).
    pub p: DVec3,
    /// Linear momentum mV (kg m/s).
    pub mv: DVec3,
}

/// A body's mass and its reciprocal, computed once at spawn, and what was fixed at its launch.
///
/// The hot loop forms `V = mV * (1/m)`: a multiply instead of a divide per component. The
/// launch values are read only by the terms that need them (a spin's lift, a motor's thrust);
/// the loop fills them only when such a term is declared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mass {
    /// Mass m (kg).
    pub m: f64,
    /// 1 / m (1/kg).
    pub inv: f64,
    /// The body's launch.
    pub launch: Launch,
}

/// What is fixed when a body is launched (spawned): the clock, its mass then, and its spin.
///
/// Not state that a step changes, so not in the state hash: every value follows from the scene
/// and the commands (docs/physics.md, "Spin: Magnus lift, spin drag and decay" and "Thrust: a motor
/// with its mass falling").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Launch {
    /// The world's time at launch (s): a motor's clock starts here, a spin decays from here.
    pub time: f64,
    /// The mass at launch (kg), propellant included.
    pub mass: f64,
    /// Angular velocity at launch (rad/s, world axes).
    pub spin: DVec3,
}

impl Mass {
    /// A mass and its reciprocal, launched at time 0 without spin.
    #[inline(always)]
    pub fn new(m: f64) -> Mass {
        Mass::launched(
            m,
            Launch {
                time: 0.0,
                mass: m,
                spin: DVec3::ZERO,
            },
        )
    }

    /// A mass and its reciprocal with its launch.
    #[inline(always)]
    pub fn launched(m: f64, launch: Launch) -> Mass {
        Mass {
            m,
            inv: 1.0 / m,
            launch,
        }
    }
}

impl BodyState {
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

    pub(crate) fn resize(&mut self, n: usize) {
        self.x.resize(n, 0.0);
        self.y.resize(n, 0.0);
        self.z.resize(n, 0.0);
    }

    /// Number of vectors.
    #[inline]
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are none.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Copies all vectors from `other` (reusing this one's allocation).
    #[inline]
    pub fn copy_from(&mut self, other: &Vec3s) {
        self.x.clone_from(&other.x);
        self.y.clone_from(&other.y);
        self.z.clone_from(&other.z);
    }

    /// Iterates over the vectors.
    #[inline]
    pub fn iter(&self) -> impl ExactSizeIterator<Item = DVec3> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }
}

/// All bodies, structure of arrays, in id order.
///
/// The f64 columns are listed once, in `COLUMNS` (names) and [`Bodies::column`] (fields):
/// the state hash, the keyframe codec and the replay's field diff all go through that list, so
/// a new per-body field is a field here, its name and arm there, and its value in
/// `Bodies::push` (docs/contributing.md). A world's
/// bodies are read-only from outside the crate (`World::bodies`); a [`crate::world::State`]'s
/// are plain data that [`crate::World::restore`] validates.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bodies {
    /// Ids, strictly increasing.
    pub id: Vec<BodyId>,
    /// Positions p (m).
    pub p: Vec3s,
    /// Momenta mV (kg m/s).
    pub mv: Vec3s,
    /// Masses (kg), each > 0.
    pub mass: Vec<f64>,
    /// 1 / mass, computed at spawn (and on restore) so the hot loop multiplies instead of
    /// dividing. Derived, so in no column list: never stored, hashed or compared.
    pub(crate) inv_mass: Vec<f64>,
    /// Radii (m), each >= 0.
    pub radius: Vec<f64>,
    /// Energy above which the guard stops the run, per body (J).
    pub energy_cap: Vec<f64>,
    /// Launch times (s): [`Launch::time`].
    pub launch_time: Vec<f64>,
    /// Masses at launch (kg): [`Launch::mass`].
    pub launch_mass: Vec<f64>,
    /// Spins at launch (rad/s): [`Launch::spin`].
    pub spin: Vec3s,
}

/// One f64 column of [`Bodies`]: its name in reports and its place in `COLUMNS`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Column {
    /// The name the replay's field diff prints (`p.x`, `mV.z`, `mass`).
    pub name: &'static str,
    /// Its index in `COLUMNS`, which [`Bodies::column`] maps to the field.
    pub index: usize,
}

impl Column {
    /// The column of a set of bodies.
    #[inline(always)]
    pub fn get(self, b: &Bodies) -> &Vec<f64> {
        b.column(self.index)
    }

    /// The same column, to write (decoding a keyframe, editing a [`crate::world::State`]).
    #[inline(always)]
    pub fn get_mut(self, b: &mut Bodies) -> &mut Vec<f64> {
        b.column_mut(self.index)
    }
}

/// Every f64 column of [`Bodies`] that is state, in the order keyframes store them. The first
/// [`HASHED_COLUMNS`] are what the state hash covers after each body's id; the rest (the guard's
/// bound, derived from the scene and the start state, and the [`Launch`], fixed at spawn from
/// the scene and the commands) are stored and compared, not hashed.
/// [`Bodies::column`] maps each index to its field.
pub const COLUMNS: [Column; 14] = {
    let names = [
        "p.x",
        "p.y",
        "p.z",
        "mV.x",
        "mV.y",
        "mV.z",
        "mass",
        "radius",
        "energy_cap",
        "launch.time",
        "launch.mass",
        "spin.x",
        "spin.y",
        "spin.z",
    ];
    let mut out = [Column { name: "", index: 0 }; 14];
    let mut i = 0;
    while i < names.len() {
        out[i] = Column {
            name: names[i],
            index: i,
        };
        i += 1;
    }
    out
};

/// How many of `COLUMNS`, from the first, the state hash covers.
pub const HASHED_COLUMNS: usize = 8;

/// Where the [`Launch`] columns sit in `COLUMNS`: the last five.
pub const LAUNCH_COLUMNS: std::ops::Range<usize> = 9..14;

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
    #[inline]
    pub fn ids(&self) -> &[BodyId] {
        &self.id
    }

    /// Positions (m).
    #[inline]
    pub fn positions(&self) -> &Vec3s {
        &self.p
    }

    /// Momenta (kg m/s).
    #[inline]
    pub fn momenta(&self) -> &Vec3s {
        &self.mv
    }

    /// Masses (kg).
    #[inline]
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }

    /// Radii (m).
    #[inline]
    pub fn radii(&self) -> &[f64] {
        &self.radius
    }

    /// Velocity (m/s) of the body at storage index `i`, formed as the integrators form it.
    #[inline]
    pub fn velocity(&self, i: usize) -> DVec3 {
        self.mv.get(i) * self.inv_mass[i]
    }

    /// The launch of the body at storage index `i`.
    #[inline]
    pub fn launch(&self, i: usize) -> Launch {
        Launch {
            time: self.launch_time[i],
            mass: self.launch_mass[i],
            spin: self.spin.get(i),
        }
    }

    /// Mass, reciprocal and launch of the body at storage index `i`, as the step forms them.
    #[inline]
    pub(crate) fn mass_of(&self, i: usize) -> Mass {
        Mass {
            m: self.mass[i],
            inv: self.inv_mass[i],
            launch: self.launch(i),
        }
    }

    /// State of the body at storage index `i`.
    #[inline]
    pub fn state(&self, i: usize) -> BodyState {
        BodyState {
            p: self.p.get(i),
            mv: self.mv.get(i),
        }
    }

    /// Storage index of a body, by binary search over the sorted ids.
    #[inline]
    pub fn index_of(&self, id: BodyId) -> Option<usize> {
        self.id.binary_search(&id).ok()
    }

    /// Appends a body with momentum `mass * velocity` and no energy bound yet (infinite): one
    /// value per entry of `COLUMNS`, in its order.
    pub(crate) fn push(
        &mut self,
        id: BodyId,
        position: DVec3,
        velocity: DVec3,
        radius: f64,
        launch: Launch,
    ) {
        let mass = launch.mass;
        let mv = mass * velocity;
        let values = [
            position.x,
            position.y,
            position.z,
            mv.x,
            mv.y,
            mv.z,
            mass,
            radius,
            f64::INFINITY,
            launch.time,
            launch.mass,
            launch.spin.x,
            launch.spin.y,
            launch.spin.z,
        ];
        for (column, value) in COLUMNS.iter().zip(values) {
            column.get_mut(self).push(value);
        }
        self.id.push(id);
        self.inv_mass.push(1.0 / mass);
    }

    /// Removes the body at storage index `i`, keeping the order of the rest.
    pub(crate) fn remove(&mut self, i: usize) {
        for column in &COLUMNS {
            column.get_mut(self).remove(i);
        }
        self.id.remove(i);
        self.inv_mass.remove(i);
    }

    /// Removes every body.
    pub(crate) fn clear(&mut self) {
        for column in &COLUMNS {
            column.get_mut(self).clear();
        }
        self.id.clear();
        self.inv_mass.clear();
    }

    /// Recomputes `1 / mass` for every body, as at spawn (after the masses were assigned).
    pub(crate) fn recompute_inv_mass(&mut self) {
        self.inv_mass.clear();
        self.inv_mass.extend(self.mass.iter().map(|m| 1.0 / m));
    }

    /// Column `k` of `COLUMNS`. With a constant `k` (the hash's unrolled loop) this is a
    /// plain field access.
    #[inline(always)]
    pub fn column(&self, k: usize) -> &Vec<f64> {
        match k {
            0 => &self.p.x,
            1 => &self.p.y,
            2 => &self.p.z,
            3 => &self.mv.x,
            4 => &self.mv.y,
            5 => &self.mv.z,
            6 => &self.mass,
            7 => &self.radius,
            8 => &self.energy_cap,
            9 => &self.launch_time,
            10 => &self.launch_mass,
            11 => &self.spin.x,
            12 => &self.spin.y,
            13 => &self.spin.z,
            _ => unreachable!("COLUMNS has 14 entries"),
        }
    }

    /// Column `k` of `COLUMNS`, to write.
    #[inline(always)]
    pub fn column_mut(&mut self, k: usize) -> &mut Vec<f64> {
        match k {
            0 => &mut self.p.x,
            1 => &mut self.p.y,
            2 => &mut self.p.z,
            3 => &mut self.mv.x,
            4 => &mut self.mv.y,
            5 => &mut self.mv.z,
            6 => &mut self.mass,
            7 => &mut self.radius,
            8 => &mut self.energy_cap,
            9 => &mut self.launch_time,
            10 => &mut self.launch_mass,
            11 => &mut self.spin.x,
            12 => &mut self.spin.y,
            13 => &mut self.spin.z,
            _ => unreachable!("COLUMNS has 14 entries"),
        }
    }

    /// Whether every body's launch is the canonical one a world whose terms never read it
    /// gives (time 0, the mass column's mass, no spin), bit for bit: then a keyframe leaves the
    /// launch columns out.
    pub fn launch_is_canonical(&self) -> bool {
        (0..self.len()).all(|i| {
            self.launch_time[i].to_bits() == 0
                && self.launch_mass[i].to_bits() == self.mass[i].to_bits()
                && [self.spin.x[i], self.spin.y[i], self.spin.z[i]]
                    .iter()
                    .all(|x| x.to_bits() == 0)
        })
    }

    /// Sets every body's launch to the canonical one ([`Bodies::launch_is_canonical`]).
    pub(crate) fn canonical_launch(&mut self) {
        let n = self.len();
        self.launch_time.clear();
        self.launch_time.resize(n, 0.0);
        self.launch_mass.clone_from(&self.mass);
        self.spin.x.clear();
        self.spin.y.clear();
        self.spin.z.clear();
        self.spin.resize(n);
    }

    /// Whether every column has one entry per id.
    pub fn lengths_agree(&self) -> bool {
        let n = self.id.len();
        COLUMNS.iter().all(|c| c.get(self).len() == n)
    }
}
