//! Field-by-field comparison of two snapshots: which body, which field, both values, and how
//! many units in the last place apart.
//!
//! Floats compare as the hash does ([`crate::hash::canonical_bits`]): `-0.0` equals `+0.0` and
//! all NaNs are equal, so two snapshots with equal hashes never show a position or momentum
//! difference. Bodies are matched by id; a body only one side has is reported as such.

use crate::forces::ForceKind;
use crate::hash::canonical_bits;
use crate::world::{BodyId, COLUMNS, Snapshot};

/// One side of a differing field.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A float.
    F64(f64),
    /// A count, id, or generator state.
    U64(u64),
    /// A name or an on/off state.
    Text(String),
    /// The body does not exist on this side.
    Absent,
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            // `{:?}` is the shortest text that reads back to the same bits.
            Value::F64(x) => write!(f, "{x:?}"),
            Value::U64(x) => write!(f, "{x}"),
            Value::Text(t) => f.write_str(t),
            Value::Absent => f.write_str("absent"),
        }
    }
}

/// A field whose recorded and replayed values differ.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldDiff {
    /// The body, or `None` for world-level fields (tick, generator, launcher, ...).
    pub body: Option<BodyId>,
    /// The field: `p.x`, `mV.z`, `mass`, `radius`, `energy_cap`, `carry.y`, `body` (present or
    /// absent), `rng`, `next_id`, `integrator`, `force Gravity`, `launcher.speed`, ...
    pub field: String,
    /// The recording's value.
    pub recorded: Value,
    /// The replay's value.
    pub replayed: Value,
}

impl FieldDiff {
    /// Units in the last place between the two values, for finite or infinite floats.
    pub fn ulps(&self) -> Option<u64> {
        match (&self.recorded, &self.replayed) {
            (Value::F64(a), Value::F64(b)) => ulps(*a, *b),
            _ => None,
        }
    }
}

impl std::fmt::Display for FieldDiff {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.body {
            Some(id) => write!(f, "body {id} {}", self.field)?,
            None => f.write_str(&self.field)?,
        }
        write!(f, ": recorded {} replayed {}", self.recorded, self.replayed)?;
        match self.ulps() {
            Some(1) => f.write_str(" (1 ulp)"),
            Some(n) => write!(f, " ({n} ulps)"),
            None => Ok(()),
        }
    }
}

/// The number of representable doubles from `a` to `b` (0 for `-0.0` and `+0.0`), or `None` if
/// either is NaN. The bit patterns are mapped to a monotonic integer line, so the distance
/// crosses zero correctly: from the smallest negative subnormal to the smallest positive one is 2.
pub fn ulps(a: f64, b: f64) -> Option<u64> {
    if a.is_nan() || b.is_nan() {
        return None;
    }
    fn line(x: f64) -> i64 {
        let bits = x.to_bits() as i64;
        if bits < 0 { i64::MIN - bits } else { bits }
    }
    Some(line(a).abs_diff(line(b)))
}

fn same(a: f64, b: f64) -> bool {
    canonical_bits(a) == canonical_bits(b)
}

/// Every field in which `replayed` differs from `recorded`, world-level fields first, then
/// bodies in id order.
pub fn diff(recorded: &Snapshot, replayed: &Snapshot) -> Vec<FieldDiff> {
    let mut out = Vec::new();
    let mut world = |field: &str, a: Value, b: Value| {
        if a != b {
            out.push(FieldDiff {
                body: None,
                field: field.into(),
                recorded: a,
                replayed: b,
            });
        }
    };
    let (r, p) = (recorded, replayed);
    world("tick", Value::U64(r.tick), Value::U64(p.tick));
    world("next_id", Value::U64(r.next_id), Value::U64(p.next_id));
    world("rng", Value::U64(r.rng.0), Value::U64(p.rng.0));
    let name = |s: &Snapshot| Value::Text(s.integrator.name().into());
    world("integrator", name(r), name(p));
    for k in ForceKind::ALL {
        let on = |s: &Snapshot| Value::Text(if s.forces.has(k) { "on" } else { "off" }.into());
        world(&format!("force {}", k.name()), on(r), on(p));
    }
    world(
        "force_evals",
        Value::U64(r.force_evals),
        Value::U64(p.force_evals),
    );
    let launcher = |s: &Snapshot| {
        let l = &s.launcher;
        [
            l.position.x,
            l.position.y,
            l.position.z,
            l.speed,
            l.elevation_deg,
            l.azimuth_deg,
            l.mass,
            l.radius,
        ]
    };
    let names = [
        "position.x",
        "position.y",
        "position.z",
        "speed",
        "elevation",
        "azimuth",
    ];
    let names = names.iter().chain(&["mass", "radius"]);
    for ((name, a), b) in names.zip(launcher(r)).zip(launcher(p)) {
        if !same(a, b) {
            world(&format!("launcher.{name}"), Value::F64(a), Value::F64(b));
        }
    }
    diff_bodies(r, p, &mut out);
    out
}

/// The carried force's components, compared after the body columns when both sides carry one.
const CARRY_FIELDS: [&str; 3] = ["carry.x", "carry.y", "carry.z"];

/// Every compared per-body field: the state's columns ([`COLUMNS`]), then the carried force.
fn field_name(k: usize) -> &'static str {
    COLUMNS
        .get(k)
        .map_or_else(|| CARRY_FIELDS[k - COLUMNS.len()], |c| c.name)
}

/// Body `i`'s value of every field [`field_name`] names (`None` where it has none: no carry).
fn body_fields(s: &Snapshot, i: usize) -> impl Iterator<Item = Option<f64>> + '_ {
    let c = move |v: &[f64]| v.get(i).copied();
    let carry = &s.carry;
    COLUMNS.iter().map(move |col| c(col.get(&s.bodies))).chain([
        c(&carry.x),
        c(&carry.y),
        c(&carry.z),
    ])
}

/// Bodies matched by id in one merge walk over the two sorted id lists.
fn diff_bodies(r: &Snapshot, p: &Snapshot, out: &mut Vec<FieldDiff>) {
    let (mut i, mut j) = (0, 0);
    let (ri, pi) = (&r.bodies.id, &p.bodies.id);
    while i < ri.len() || j < pi.len() {
        let (a, b) = (ri.get(i), pi.get(j));
        let present = |id: BodyId, rec: bool| FieldDiff {
            body: Some(id),
            field: "body".into(),
            recorded: if rec {
                Value::Text("present".into())
            } else {
                Value::Absent
            },
            replayed: if rec {
                Value::Absent
            } else {
                Value::Text("present".into())
            },
        };
        match (a, b) {
            (Some(&x), Some(&y)) if x == y => {
                let (fa, fb) = (body_fields(r, i), body_fields(p, j));
                for (k, (va, vb)) in fa.zip(fb).enumerate() {
                    // The carried force is compared only when both sides carry one.
                    if let (Some(va), Some(vb)) = (va, vb)
                        && !same(va, vb)
                    {
                        out.push(FieldDiff {
                            body: Some(x),
                            field: field_name(k).into(),
                            recorded: Value::F64(va),
                            replayed: Value::F64(vb),
                        });
                    }
                }
                (i, j) = (i + 1, j + 1);
            }
            (Some(&x), Some(&y)) if x < y => {
                out.push(present(x, true));
                i += 1;
            }
            (Some(&x), None) => {
                out.push(present(x, true));
                i += 1;
            }
            (_, Some(&y)) => {
                out.push(present(y, false));
                j += 1;
            }
            (None, None) => unreachable!("the loop runs while one side has bodies"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ulps_count_representable_doubles_across_zero() {
        assert_eq!(ulps(1.0, 1.0), Some(0));
        assert_eq!(ulps(1.0, f64::from_bits(1.0f64.to_bits() + 3)), Some(3));
        assert_eq!(ulps(-0.0, 0.0), Some(0));
        let tiny = f64::from_bits(1);
        assert_eq!(ulps(-tiny, tiny), Some(2));
        assert_eq!(ulps(f64::MAX, f64::INFINITY), Some(1));
        assert_eq!(ulps(f64::NAN, 1.0), None);
    }
}
