use super::*;

#[test]
fn root_finder_converges_to_ulps_on_a_quadratic() {
    // z(t) = 2 + 29 t - 4.905 t^2 crosses zero at t = (29 + sqrt(29^2 + 4 * 4.905 * 2)) / 9.81.
    let exact = (29.0 + (29.0f64 * 29.0 + 4.0 * 4.905 * 2.0).sqrt()) / 9.81;
    let z = |t: f64| 2.0 + 29.0 * t - 4.905 * t * t;
    let (root, evals) = bracketed_root(z, (1.0, z(1.0)), (10.0, z(10.0)));
    assert!((root - exact).abs() < 1e-14, "{root} vs {exact}");
    assert!(z(root) >= 0.0, "the returned point is on the lo side");
    assert!(evals < 60, "{evals} evaluations");
}
