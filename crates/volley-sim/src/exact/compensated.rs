//! Double-double arithmetic (Dekker, Knuth): a value as an unevaluated sum `hi + lo` of two
//! f64, about 106 bits. Used only to evaluate a Kepler orbit's energy to far below an ulp, so
//! that the `exact` step can put rounding back on the energy the exact flow conserves.
//!
//! No `mul_add`: the exact product comes from Dekker's split, so every platform gives the same
//! bits. Inputs are assumed below about 1e300 in size (the split overflows beyond); callers
//! check that the result is finite.

use glam::DVec3;

/// `hi + lo` with `|lo| <= ulp(hi) / 2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dd {
    pub(crate) hi: f64,
    pub(crate) lo: f64,
}

/// `a + b` exactly, as `s + e` (Knuth's two-sum).
fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    Dd { hi: s, lo: e }
}

/// `a + b` exactly when `|a| >= |b|` (Dekker's fast two-sum).
fn quick_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd {
        hi: s,
        lo: b - (s - a),
    }
}

/// Dekker's split of `a` into two halves of 26 bits each.
fn split(a: f64) -> (f64, f64) {
    const SPLITTER: f64 = 134_217_729.0; // 2^27 + 1
    let c = SPLITTER * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// `a b` exactly, as `p + e` (Dekker's two-product, without a fused multiply-add).
fn two_prod(a: f64, b: f64) -> Dd {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    Dd { hi: p, lo: e }
}

impl Dd {
    pub(crate) fn from(a: f64) -> Dd {
        Dd { hi: a, lo: 0.0 }
    }

    pub(crate) fn add(self, b: Dd) -> Dd {
        let s = two_sum(self.hi, b.hi);
        let t = two_sum(self.lo, b.lo);
        let u = quick_two_sum(s.hi, s.lo + t.hi);
        quick_two_sum(u.hi, u.lo + t.lo)
    }

    pub(crate) fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    pub(crate) fn mul(self, b: Dd) -> Dd {
        let p = two_prod(self.hi, b.hi);
        quick_two_sum(p.hi, p.lo + (self.hi * b.lo + self.lo * b.hi))
    }

    pub(crate) fn div(self, b: Dd) -> Dd {
        // One Newton correction of the f64 quotient: q + (a - q b) / b.
        let q = self.hi / b.hi;
        let r = self.add(b.mul(Dd::from(q)).neg());
        let q2 = r.hi / b.hi;
        quick_two_sum(q, q2)
    }

    pub(crate) fn sqrt(self) -> Dd {
        if self.hi <= 0.0 {
            return Dd::from(self.hi.max(0.0).sqrt());
        }
        // One Newton correction of the f64 root: s + (a - s^2) / (2 s).
        let s = self.hi.sqrt();
        let r = self.add(two_prod(s, s).neg());
        quick_two_sum(s, r.hi / (2.0 * s))
    }
}

/// `|a|^2` in double-double.
fn length_squared(a: [Dd; 3]) -> Dd {
    a[0].mul(a[0]).add(a[1].mul(a[1])).add(a[2].mul(a[2]))
}

/// The energy per unit mass `|mv|^2 / (2 m^2) - mu / |p - center|` of the f64 state `(p, mv)`,
/// to about 1e-30 of its terms.
pub(crate) fn kepler_energy(p: DVec3, mv: DVec3, m: f64, center: DVec3, mu: f64) -> Dd {
    let x = [0, 1, 2].map(|i| two_sum(p[i], -center[i]));
    let r = length_squared(x).sqrt();
    let u = [0, 1, 2].map(|i| Dd::from(mv[i]));
    let m2 = two_prod(m, m);
    let kinetic = length_squared(u).div(m2).mul(Dd::from(0.5));
    kinetic.add(Dd::from(mu).div(r).neg())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_and_sums_are_exact() {
        // (1 + 2^-30)^2 = 1 + 2^-29 + 2^-60: the last term is below an f64 ulp of 1.
        let a = 1.0 + 2f64.powi(-30);
        let p = two_prod(a, a);
        assert_eq!((p.hi, p.lo), (1.0 + 2f64.powi(-29), 2f64.powi(-60)));
        let s = two_sum(1.0, 2f64.powi(-60));
        assert_eq!((s.hi, s.lo), (1.0, 2f64.powi(-60)));
    }

    #[test]
    fn division_and_root_are_good_to_far_below_an_ulp() {
        // 1/3 and sqrt(2) to 1e-30: checked by multiplying back in double-double.
        let third = Dd::from(1.0).div(Dd::from(3.0));
        let back = third.mul(Dd::from(3.0)).add(Dd::from(-1.0));
        assert!(back.hi.abs() < 1e-30, "{back:?}");
        let root = Dd::from(2.0).sqrt();
        let sq = root.mul(root).add(Dd::from(-2.0));
        assert!(sq.hi.abs() < 1e-30, "{sq:?}");
    }
}
