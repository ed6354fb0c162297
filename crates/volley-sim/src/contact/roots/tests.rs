use super::*;

/// The plane `z = 0` for a sphere of radius `r`: the value is `z - r`.
struct Floor {
    r: f64,
    asked: u32,
}

impl BallCrossing for Floor {
    fn value(&mut self, s: &BodyState) -> f64 {
        s.p.z - self.r
    }
    fn possible(&mut self, center: DVec3, radius: f64) -> bool {
        self.asked += 1;
        center.z - radius <= self.r
    }
    fn resolution(&self) -> f64 {
        self.r
    }
}

/// Semi-implicit Euler's partial step under gravity `g` from `(p0, v0)`: the path of curvature
/// `2 g`, the one the bound is tight for.
fn semi_implicit(p0: DVec3, v0: DVec3, g: DVec3) -> impl FnMut(f64) -> BodyState {
    move |tau| {
        let v = v0 + tau * g;
        BodyState {
            p: p0 + tau * v,
            mv: v,
        }
    }
}

fn on(c: &mut Floor) -> OnBall<'_, Floor> {
    OnBall {
        crossing: c,
        inv_m: 1.0,
    }
}

fn point(path: &mut impl FnMut(f64) -> BodyState, c: &mut Floor, tau: f64) -> PathPoint {
    let s = path(tau);
    PathPoint {
        tau,
        s,
        value: c.value(&s),
    }
}

/// The dip `z = 0.06 - tau + 10 tau^2` (semi-implicit Euler from z = 0.06 at -1 m/s under
/// +10 m/s^2): lowest at tau = 0.05, z = 0.035, and above 0.06 again after tau = 0.1.
fn dip() -> impl FnMut(f64) -> BodyState {
    semi_implicit(
        DVec3::new(0.0, 0.0, 0.06),
        DVec3::new(3.0, 0.0, -1.0),
        DVec3::new(0.0, 0.0, 10.0),
    )
}

#[test]
fn a_dip_between_the_ends_of_the_step_is_found_at_its_first_root() {
    let mut path = dip();
    // Radius 0.04: the dip goes 5 mm below it, and both ends of the 0.2 s step are above it.
    let mut c = Floor { r: 0.04, asked: 0 };
    let (a, b) = (point(&mut path, &mut c, 0.0), point(&mut path, &mut c, 0.2));
    assert!(a.value > 0.0 && b.value > 0.0);
    let (lo, hi) = first_root(&mut path, a, b, &mut on(&mut c)).expect("the dip reaches z = r");
    // 10 tau^2 - tau + 0.02 = 0: the first root is (1 - sqrt(0.2)) / 20; the second, 0.0724,
    // must not be the one found.
    let exact = (1.0 - 0.2f64.sqrt()) / 20.0;
    assert!(
        (lo.tau - exact).abs() <= 4.0 * f64::EPSILON,
        "{} vs {exact}",
        lo.tau
    );
    assert!(lo.value >= 0.0 && hi.value <= 0.0 && hi.tau < 0.05);
}

#[test]
fn a_dip_that_stays_above_the_radius_is_cleared_in_a_few_pieces() {
    let mut path = dip();
    // Radius 0.03: the lowest point (0.035) misses by 5 mm.
    let mut c = Floor { r: 0.03, asked: 0 };
    let (a, b) = (point(&mut path, &mut c, 0.0), point(&mut path, &mut c, 0.2));
    assert!(first_root(&mut path, a, b, &mut on(&mut c)).is_none());
    // A piece is cleared once its ball (half its chord plus its margin, 10 T^2 for length T)
    // stays above z = 0.03: the chord runs at about 3 m/s, so pieces of about 1/320 s (6
    // halvings) near the lowest point, two pieces asked about per level, and their siblings:
    // 45 asked when written; a search that split everywhere would ask thousands.
    assert!(c.asked <= 64, "asked {} times", c.asked);
}

#[test]
fn a_tangent_touch_ends_at_the_depth_limit_without_a_root() {
    let mut path = dip();
    let mut c = Floor { r: 0.035, asked: 0 };
    let (a, b) = (point(&mut path, &mut c, 0.0), point(&mut path, &mut c, 0.2));
    // The lowest point is 0.035 to rounding: found as a root at tau = 0.05 or not at all, and
    // either way the search ends (at most MAX_DEPTH pieces down one branch, and their
    // siblings).
    if let Some((lo, _)) = first_root(&mut path, a, b, &mut on(&mut c)) {
        assert!((lo.tau - 0.05).abs() < 1e-6, "{}", lo.tau);
    }
    assert!(c.asked < 10 * MAX_DEPTH, "asked {} times", c.asked);
}

#[test]
fn the_margin_bounds_the_sag_of_semi_implicit_euler_exactly() {
    // Semi-implicit Euler's path sags 2 |g| T^2 / 8 below its chord at the middle; the margin
    // without its safety factor is exactly that.
    let g = DVec3::new(0.0, 0.0, -9.81);
    let mut path = semi_implicit(DVec3::ZERO, DVec3::new(10.0, 0.0, 5.0), g);
    let (a, m, b) = (path(0.0), path(0.05), path(0.1));
    let sag = (0.5 * (a.p + b.p) - m.p).length();
    let bound = margin(&a, &b, 1.0, 0.1) / SAFETY;
    assert!((sag - bound).abs() <= 1e-12, "{sag} vs {bound}");
}
