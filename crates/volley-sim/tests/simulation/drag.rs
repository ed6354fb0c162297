//! Drag against Mach: the standard tables reproduced at their points, the curve between them
//! monotone where the points are, the peer's interpolation of the same points, and bad tables
//! refused naming the point.

use volley_sim::internals::drag::{DragTable, DragTableError, standard};

#[test]
fn the_curves_pass_through_every_published_point() {
    for (table, points) in [
        (DragTable::g1(), &standard::G1[..]),
        (DragTable::g7(), &standard::G7[..]),
    ] {
        for &(mach, cd) in points {
            assert_eq!(table.cd(mach), cd, "Mach {mach}");
        }
    }
    // The values the tables print at the transonic points (py-ballisticcalc's drag_tables.py).
    assert_eq!(DragTable::g1().cd(1.0), 0.4805);
    assert_eq!(DragTable::g1().cd(1.2), 0.6393);
    assert_eq!(DragTable::g7().cd(0.0), 0.1198);
    assert_eq!(DragTable::g7().cd(1.2), 0.3884);
}

#[test]
fn between_two_points_the_curve_stays_between_their_values() {
    // Fritsch-Carlson's slopes keep each piece monotone where its two points differ and flat
    // where they are equal: no overshoot around the kink near Mach 1.
    for table in [DragTable::g1(), DragTable::g7()] {
        let points: Vec<(f64, f64)> = table.points().collect();
        for w in points.windows(2) {
            let ((m0, c0), (m1, c1)) = (w[0], w[1]);
            let (lo, hi) = (c0.min(c1), c0.max(c1));
            for k in 1..50 {
                let m = m0 + (m1 - m0) * f64::from(k) / 50.0;
                let cd = table.cd(m);
                assert!(
                    cd >= lo - 1e-15 && cd <= hi + 1e-15,
                    "Mach {m}: {cd} outside [{lo}, {hi}]"
                );
            }
        }
    }
}

#[test]
fn between_the_points_the_curve_is_the_peers() {
    // py-ballisticcalc's own PCHIP (pchip_prepare and pchip_eval, interpolation.py at commit
    // 1ce68ce) run on the same tables, printed by Python's repr: the same algorithm, evaluated
    // in another order, so they agree to rounding.
    let peer = [
        (DragTable::g1(), 0.33, 0.217775186518847),
        (DragTable::g1(), 0.96, 0.422891149743004),
        (DragTable::g1(), 1.37, 0.6623432),
        (DragTable::g7(), 0.96, 0.23809653389882637),
        (DragTable::g7(), 1.37, 0.36260313415453527),
    ];
    for (table, mach, cd) in peer {
        assert!(
            (table.cd(mach) - cd).abs() < 1e-12,
            "Mach {mach}: {} vs {cd}",
            table.cd(mach)
        );
    }
}

#[test]
fn outside_the_table_the_end_values_hold() {
    let g1 = DragTable::g1();
    assert_eq!(g1.cd(7.5), standard::G1[standard::G1.len() - 1].1);
    assert_eq!(g1.cd(-1.0), standard::G1[0].1);
}

#[test]
fn bad_tables_are_refused_naming_the_point() {
    let cases: [(&[(f64, f64)], &str); 5] = [
        (
            &[(0.0, 0.2)],
            "drag table: expected at least 2 points (Mach, Cd), got 1",
        ),
        (
            &[(0.0, 0.2), (1.0, 0.4), (0.9, 0.3)],
            "drag table: point 2 (counted from 0): Mach 0.9 is not above the previous point's 1; expected Mach \
             numbers in increasing order",
        ),
        (
            &[(0.0, 0.2), (1.0, -0.4)],
            "drag table: point 1 (counted from 0): expected a finite drag coefficient >= 0, got -0.4",
        ),
        (
            &[(f64::NAN, 0.2), (1.0, 0.4)],
            "drag table: point 0 (counted from 0): expected a finite Mach number >= 0, got NaN",
        ),
        (
            &[(0.0, 0.2), (1.0, f64::INFINITY)],
            "drag table: point 1 (counted from 0): expected a finite drag coefficient >= 0, got inf",
        ),
    ];
    for (points, message) in cases {
        let err = DragTable::new(points).unwrap_err();
        assert_eq!(err.to_string(), message);
    }
    assert_eq!(
        DragTable::new(&[(0.0, 0.2), (0.0, 0.3)]).unwrap_err(),
        DragTableError::NotIncreasing {
            index: 1,
            mach: 0.0,
            previous: 0.0
        }
    );
}

#[test]
fn straight_lines_run_between_the_points_and_through_them() {
    use volley_sim::internals::drag::Interpolation;
    for table in [DragTable::g1(), DragTable::g7(), DragTable::sphere()] {
        let points: Vec<(f64, f64)> = table.points().collect();
        for w in points.windows(2) {
            let ((m0, c0), (m1, c1)) = (w[0], w[1]);
            assert_eq!(table.cd_by(m0, Interpolation::Linear), c0);
            let mid = table.cd_by(0.5 * (m0 + m1), Interpolation::Linear);
            assert!((mid - 0.5 * (c0 + c1)).abs() < 1e-15, "Mach {m0}..{m1}");
        }
    }
    // The sphere's published points (py-ballisticcalc's TableGS).
    assert_eq!(DragTable::sphere().cd(0.0), 0.4662);
    assert_eq!(DragTable::sphere().cd(4.0), 0.928);
}
