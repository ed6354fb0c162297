//! The entire functions the new closed forms are built from, each accurate to a few ulps over the
//! whole real line: the exponential's divided differences (`phi2`, `chi`) and Stumpff's `c2`,
//! `c3`. Each is a Taylor series where its formula cancels and the formula elsewhere; the
//! switch points are chosen so that neither side loses more than about two bits.
//!
//! (The older `phi2` in `exact.rs`, which switches at 1e-2 and loses up to 2.3 digits there, is
//! kept as it is: the bits of the drag flow are pinned by golden hashes.)

/// `|x|` below which the series are used. At the switch the formulas lose at most
/// `log2(1 / 0.26)`, about 2 bits (`chi` at 1), or less.
const SERIES_BELOW: f64 = 1.0;

/// `|z|` below which Stumpff's functions use their series. The closed form of `c3` loses
/// `log2(6 / z)` bits to the cancellation `y - sin y` (1.5 bits at 4); the series at `|z| = 4`
/// has all its terms below the sum (alternating for `z > 0`, all positive for `z < 0`).
const STUMPFF_SERIES_BELOW: f64 = 4.0;

/// Horner evaluation of `sum_k coef[k] x^k`.
fn horner(coef: &[f64], x: f64) -> f64 {
    let mut acc = 0.0;
    for c in coef.iter().rev() {
        acc = acc * x + c;
    }
    acc
}

/// `1/(n + 2)!` for n = 0..=17 (the terms of `phi2`'s series; `1/19! = 8.2e-18` is the first
/// one left out, below half an ulp of `phi2(x) >= 0.3` for `|x| < 1`).
const PHI2_TERMS: [f64; 18] = {
    let mut c = [0.0; 18];
    let mut fact = 2.0;
    let mut n = 0;
    while n < 18 {
        c[n] = if n % 2 == 0 { 1.0 / fact } else { -1.0 / fact };
        fact *= (n + 3) as f64;
        n += 1;
    }
    c
};

/// `1/(n! (n + 2))` with alternating sign, n = 0..=17: the series of [`chi`]. The first term
/// left out, `1/(18! 20)`, is 7.8e-18.
const CHI_TERMS: [f64; 18] = {
    let mut c = [0.0; 18];
    let mut fact = 1.0;
    let mut n = 0;
    while n < 18 {
        let t = 1.0 / (fact * (n + 2) as f64);
        c[n] = if n % 2 == 0 { t } else { -t };
        fact *= (n + 1) as f64;
        n += 1;
    }
    c
};

/// Stumpff `c2` series `sum_k (-z)^k / (2k + 2)!`, k = 0..=12 (`4^13 / 28! = 2.2e-22`).
const C2_TERMS: [f64; 13] = stumpff_terms(2);
/// Stumpff `c3` series `sum_k (-z)^k / (2k + 3)!`, k = 0..=12.
const C3_TERMS: [f64; 13] = stumpff_terms(3);

const fn stumpff_terms(first: usize) -> [f64; 13] {
    let mut c = [0.0; 13];
    let mut fact = 1.0;
    let mut i = 2;
    while i <= first {
        fact *= i as f64;
        i += 1;
    }
    let mut k = 0;
    while k < 13 {
        c[k] = if k % 2 == 0 { 1.0 / fact } else { -1.0 / fact };
        let n = first + 2 * k;
        fact *= ((n + 1) * (n + 2)) as f64;
        k += 1;
    }
    c
}

/// `phi2(x) = (x - 1 + e^-x) / x^2 = (1 - phi1(x)) / x`, with its limit 1/2 at 0.
pub(crate) fn phi2(x: f64) -> f64 {
    if x.abs() < SERIES_BELOW {
        horner(&PHI2_TERMS, x)
    } else {
        (x + libm::expm1(-x)) / (x * x)
    }
}

/// `chi(x) = (1 - e^-x (1 + x)) / x^2 = (phi1(x) - e^-x) / x`, with its limit 1/2 at 0: the
/// response `integral_0^1 s e^(-x s) ds` of a critically damped kernel to a constant force.
pub(crate) fn chi(x: f64) -> f64 {
    if x.abs() < SERIES_BELOW {
        horner(&CHI_TERMS, x)
    } else {
        (-libm::expm1(-x) - x * libm::exp(-x)) / (x * x)
    }
}

/// Stumpff's `c2(z) = (1 - cos sqrt z) / z` (`(cosh sqrt(-z) - 1) / (-z)` for `z < 0`), 1/2 at 0.
///
/// Written with the half angle, `2 sin^2(sqrt(z) / 2) / z`, which does not cancel.
pub fn stumpff_c2(z: f64) -> f64 {
    if z.abs() < STUMPFF_SERIES_BELOW {
        horner(&C2_TERMS, z)
    } else if z > 0.0 {
        let s = libm::sin(0.5 * z.sqrt());
        2.0 * s * s / z
    } else {
        let s = libm::sinh(0.5 * (-z).sqrt());
        2.0 * s * s / -z
    }
}

/// Stumpff's `c3(z) = (sqrt z - sin sqrt z) / z^(3/2)` (`(sinh y - y) / y^3`, `y = sqrt(-z)`, for
/// `z < 0`), 1/6 at 0.
pub fn stumpff_c3(z: f64) -> f64 {
    if z.abs() < STUMPFF_SERIES_BELOW {
        horner(&C3_TERMS, z)
    } else if z > 0.0 {
        let y = z.sqrt();
        (y - libm::sin(y)) / (z * y)
    } else {
        let y = (-z).sqrt();
        (libm::sinh(y) - y) / (-z * y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference values to 17 digits from 50-digit decimal arithmetic (mpmath):
    /// `(x, phi2(x), chi(x))`.
    const PHI2_CHI: [(f64, f64, f64); 4] = [
        (1e-8, 0.499_999_998_333_333_34, 0.499_999_996_666_666_68),
        (0.5, 0.426_122_638_850_533_7, 0.360_816_041_724_199_46),
        (1.0, 0.367_879_441_171_442_32, 0.264_241_117_657_115_4),
        (-2.0, 1.097_264_024_732_662_6, 2.097_264_024_732_662_6),
    ];

    #[test]
    fn phi2_and_chi_match_high_precision_values() {
        for (x, p, c) in PHI2_CHI {
            // A few ulps: the series sum terms below the result, the formulas lose <= 2 bits.
            assert!((phi2(x) - p).abs() <= 4.0 * f64::EPSILON * p, "phi2({x})");
            assert!((chi(x) - c).abs() <= 4.0 * f64::EPSILON * c, "chi({x})");
        }
    }

    #[test]
    fn series_and_formulas_agree_at_the_switches() {
        for x in [SERIES_BELOW, -SERIES_BELOW] {
            let below = x * (1.0 - f64::EPSILON);
            for f in [phi2 as fn(f64) -> f64, chi] {
                let (a, b) = (f(below), f(x));
                // The functions' slopes are O(1) and the step is one ulp: any gap is error.
                assert!(
                    (a - b).abs() <= 8.0 * f64::EPSILON * a.abs(),
                    "{x}: {a} vs {b}"
                );
            }
        }
        for z in [STUMPFF_SERIES_BELOW, -STUMPFF_SERIES_BELOW] {
            let below = z * (1.0 - f64::EPSILON);
            for f in [stumpff_c2 as fn(f64) -> f64, stumpff_c3] {
                let (a, b) = (f(below), f(z));
                assert!(
                    (a - b).abs() <= 8.0 * f64::EPSILON * a.abs(),
                    "{z}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn stumpff_functions_reduce_to_cos_and_cosh() {
        // c2 = (1 - cos y) / y^2 at y = 3 (z = 9), and for z = -9 with cosh; c3 likewise.
        let (y, z) = (3.0f64, 9.0);
        let c2 = (1.0 - y.cos()) / z;
        let c3 = (y - y.sin()) / (z * y);
        assert!((stumpff_c2(z) - c2).abs() <= 1e-15 * c2);
        assert!((stumpff_c3(z) - c3).abs() <= 1e-14 * c3);
        let c2h = (y.cosh() - 1.0) / z;
        let c3h = (y.sinh() - y) / (z * y);
        assert!((stumpff_c2(-z) - c2h).abs() <= 1e-15 * c2h);
        assert!((stumpff_c3(-z) - c3h).abs() <= 1e-14 * c3h);
        assert_eq!((stumpff_c2(0.0), stumpff_c3(0.0)), (0.5, 1.0 / 6.0));
    }
}
