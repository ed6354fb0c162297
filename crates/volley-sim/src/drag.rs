//! Drag coefficient against Mach number: a table of (Mach, Cd) points and the curve through
//! them, for drag that changes across the speed of sound (the curve
//! [`crate::forces::MachDrag`] reads).
//!
//! # Interpolation
//! Between the points, the monotone piecewise cubic Hermite interpolant (PCHIP) of Fritsch and
//! Carlson ("Monotone piecewise cubic interpolation", SIAM J. Numer. Anal. 17, 1980), with the
//! slopes SciPy's `PchipInterpolator` and py-ballisticcalc use: at an interior point the weighted
//! harmonic mean of the neighbouring secants (zero where they differ in sign or one is zero), at
//! the ends the three-point formula, set to zero if its sign is not the first secant's and
//! limited to three times that secant. The curve passes through every point, is C1, and never
//! overshoots a run of points that rises or falls, so the kink a table has near Mach 1 stays a
//! kink rather than a wiggle. Outside the table the end values hold (a table from Mach 0 to 5
//! covers every projectile Volley models).
//!
//! The standard G1 and G7 functions are [`DragTable::g1`] and [`DragTable::g7`]
//! ([`standard`] has the points and their source); a scene may give its own table, checked by
//! [`DragTable::new`].

pub mod standard;

use std::sync::OnceLock;

/// Why a table of points is not a drag curve. Displays as `drag table: PROBLEM`, naming the
/// point by its index from 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DragTableError {
    /// Fewer than two points.
    TooFewPoints(usize),
    /// A Mach number that is negative or not finite.
    InvalidMach {
        /// The point.
        index: usize,
        /// Its Mach number.
        mach: f64,
    },
    /// A Mach number not above the one before it.
    NotIncreasing {
        /// The point.
        index: usize,
        /// Its Mach number.
        mach: f64,
        /// The previous point's.
        previous: f64,
    },
    /// A drag coefficient that is negative or not finite.
    InvalidCd {
        /// The point.
        index: usize,
        /// Its coefficient.
        cd: f64,
    },
}

impl std::fmt::Display for DragTableError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("drag table: ")?;
        match self {
            DragTableError::TooFewPoints(n) => {
                write!(f, "expected at least 2 points (Mach, Cd), got {n}")
            }
            DragTableError::InvalidMach { index, mach } => write!(
                f,
                "point {index} (counted from 0): expected a finite Mach number >= 0, got {mach}"
            ),
            DragTableError::NotIncreasing {
                index,
                mach,
                previous,
            } => write!(
                f,
                "point {index} (counted from 0): Mach {mach} is not above the previous point's {previous}; \
                 expected Mach numbers in increasing order"
            ),
            DragTableError::InvalidCd { index, cd } => write!(
                f,
                "point {index} (counted from 0): expected a finite drag coefficient >= 0, got {cd}"
            ),
        }
    }
}

impl std::error::Error for DragTableError {}

/// A drag curve: its points and the PCHIP slope at each.
#[derive(Clone, Debug, PartialEq)]
pub struct DragTable {
    mach: Vec<f64>,
    cd: Vec<f64>,
    slope: Vec<f64>,
    /// The segment holding the start of each of [`CELLS`] equal cells from the first Mach
    /// number to the last: a lookup starts there and walks on (one step or none for the
    /// standard tables) instead of a binary search, whose unpredictable branches cost more
    /// than the curve itself in the force loop.
    first_segment: Vec<u32>,
    /// Cells per unit Mach.
    cells_per_mach: f64,
    /// [`DragTable::rate_bound`], computed once.
    rate_bound: f64,
}

/// Cells in a table's segment index: finer than the closest points of the standard tables
/// (0.025 Mach apart over Mach 0 to 5), so most cells lie inside one segment.
const CELLS: usize = 512;

impl DragTable {
    /// The curve through `points` (Mach, Cd): at least two, Mach numbers finite, >= 0 and
    /// strictly increasing, coefficients finite and >= 0.
    pub fn new(points: &[(f64, f64)]) -> Result<DragTable, DragTableError> {
        if points.len() < 2 {
            return Err(DragTableError::TooFewPoints(points.len()));
        }
        for (index, &(mach, cd)) in points.iter().enumerate() {
            if !(mach.is_finite() && mach >= 0.0) {
                return Err(DragTableError::InvalidMach { index, mach });
            }
            if index > 0 && mach <= points[index - 1].0 {
                return Err(DragTableError::NotIncreasing {
                    index,
                    mach,
                    previous: points[index - 1].0,
                });
            }
            if !(cd.is_finite() && cd >= 0.0) {
                return Err(DragTableError::InvalidCd { index, cd });
            }
        }
        let mach: Vec<f64> = points.iter().map(|p| p.0).collect();
        let cd: Vec<f64> = points.iter().map(|p| p.1).collect();
        let slope = slopes(&mach, &cd);
        let span = mach[mach.len() - 1] - mach[0];
        let cells_per_mach = CELLS as f64 / span;
        let first_segment = (0..CELLS)
            .map(|c| {
                let start = mach[0] + c as f64 / cells_per_mach;
                (mach.partition_point(|&x| x <= start) - 1).min(mach.len() - 2) as u32
            })
            .collect();
        // Between two points the curve's slope is at most 3 times the secant's (PCHIP's
        // limit; the straight line's is the secant), at Mach numbers up to the segment's end.
        let cd_max = cd.iter().copied().fold(0.0, f64::max);
        let stretch = (0..mach.len() - 1)
            .map(|i| mach[i + 1] * 3.0 * ((cd[i + 1] - cd[i]) / (mach[i + 1] - mach[i])).abs())
            .fold(0.0, f64::max);
        Ok(DragTable {
            mach,
            cd,
            slope,
            first_segment,
            cells_per_mach,
            rate_bound: 2.0 * cd_max + stretch,
        })
    }

    /// The standard G1 drag function (`standard::G1`).
    pub fn g1() -> &'static DragTable {
        static G1: OnceLock<DragTable> = OnceLock::new();
        G1.get_or_init(|| DragTable::new(&standard::G1).expect("the G1 table is a valid table"))
    }

    /// The standard G7 drag function (`standard::G7`).
    pub fn g7() -> &'static DragTable {
        static G7: OnceLock<DragTable> = OnceLock::new();
        G7.get_or_init(|| DragTable::new(&standard::G7).expect("the G7 table is a valid table"))
    }

    /// The GS sphere drag function (`standard::SPHERE`).
    pub fn sphere() -> &'static DragTable {
        static SPHERE: OnceLock<DragTable> = OnceLock::new();
        SPHERE.get_or_init(|| {
            DragTable::new(&standard::SPHERE).expect("the sphere table is a valid table")
        })
    }

    /// A bound on `2 Cd + M |dCd/dM|` over the whole curve, PCHIP or straight lines between
    /// the points: how fast the drag `Cd(M) |u| u` can change with the velocity through the
    /// air, per unit of `|u|` (the derivative's norm is at most `|u| (2 Cd + M Cd')`). The
    /// event search's curvature margin under a Mach drag takes it from here.
    pub fn rate_bound(&self) -> f64 {
        self.rate_bound
    }

    /// The points, in order.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.mach.iter().copied().zip(self.cd.iter().copied())
    }

    /// The drag coefficient at `mach`: the PCHIP curve between the points, the end values
    /// outside them.
    #[inline]
    pub fn cd(&self, mach: f64) -> f64 {
        self.cd_by(mach, Interpolation::Pchip)
    }

    /// The drag coefficient at `mach` by `interpolation` between the points, the end values
    /// outside them.
    #[inline]
    pub fn cd_by(&self, mach: f64, interpolation: Interpolation) -> f64 {
        let n = self.mach.len();
        if mach <= self.mach[0] {
            return self.cd[0];
        }
        if mach >= self.mach[n - 1] {
            return self.cd[n - 1];
        }
        // The segment [x_i, x_{i+1}) holding `mach`: from its cell's first segment, walking on.
        // `mach` is inside the table here, so the cell (truncated) is in range.
        let cell = (((mach - self.mach[0]) * self.cells_per_mach) as usize).min(CELLS - 1);
        let mut i = self.first_segment[cell] as usize;
        // Rounding in the cell's bounds can put a point between `mach` and its cell's start.
        while mach < self.mach[i] {
            i -= 1;
        }
        while mach >= self.mach[i + 1] {
            i += 1;
        }
        let h = self.mach[i + 1] - self.mach[i];
        let t = (mach - self.mach[i]) / h;
        let (y0, y1) = (self.cd[i], self.cd[i + 1]);
        if interpolation == Interpolation::Linear {
            return y0 + t * (y1 - y0);
        }
        let (m0, m1) = (self.slope[i] * h, self.slope[i + 1] * h);
        // Cubic Hermite basis.
        let t2 = t * t;
        let t3 = t2 * t;
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        h00 * y0 + h10 * m0 + h01 * y1 + h11 * m1
    }
}

/// How a [`DragTable`] runs between its points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Interpolation {
    /// Fritsch-Carlson's monotone cubic (the module doc): smooth, py-ballisticcalc's choice.
    #[default]
    Pchip,
    /// Straight lines between the points: a kink at each, JBM's choice (its published
    /// trajectories match it, not the cubic; see the ballistics tests).
    Linear,
}

/// Fritsch-Carlson slopes at every point (see the module doc).
fn slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let delta: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
    if n == 2 {
        return vec![delta[0]; 2];
    }
    let mut m = vec![0.0; n];
    for i in 1..n - 1 {
        let (d0, d1) = (delta[i - 1], delta[i]);
        if d0 != 0.0 && d1 != 0.0 && d0.signum() == d1.signum() {
            let w1 = 2.0 * h[i] + h[i - 1];
            let w2 = h[i] + 2.0 * h[i - 1];
            m[i] = (w1 + w2) / (w1 / d0 + w2 / d1);
        }
    }
    let end = |h0: f64, h1: f64, d0: f64, d1: f64| {
        let s = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
        if s.signum() != d0.signum() || d0 == 0.0 {
            0.0
        } else if s.abs() > 3.0 * d0.abs() {
            3.0 * d0
        } else {
            s
        }
    };
    m[0] = end(h[0], h[1], delta[0], delta[1]);
    m[n - 1] = end(h[n - 2], h[n - 3], delta[n - 2], delta[n - 3]);
    m
}
