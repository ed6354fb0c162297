//! The adversarial suite (issue 39, item 4): seeded cases of double crossings inside one tick,
//! tangent grazes (exact, and within rounding), roots exactly on a tick boundary, zeros at the
//! spawn, fast bodies and bodies spinning on a spring, each against a closed-form reference
//! good to 1e-12 s. What the cases are, their references and the tolerance's derivation:
//! `adversarial/cases.rs`. Asserted on every case: no miss, no duplicate, the way each
//! crossing goes, and the time within 1e-9 s (the integrators here are the seven exact under
//! constant force; on the spring, the exact integrator). The same cases go through scipy's
//! `solve_ivp` in `benches/events.rs` (`scripts/bench-events`).

mod cases;

use cases::{Case, Category, Outcome};

/// Runs every case of `category` and fails naming each case that misses, duplicates, goes the
/// wrong way or passes the goal.
fn check(category: Category) {
    let suite: Vec<Case> = cases::suite()
        .into_iter()
        .filter(|c| c.category == category)
        .collect();
    assert_eq!(suite.len(), cases::per_category(category));
    let mut total = Outcome::default();
    for case in &suite {
        let (reports, _) = cases::run(case);
        let o = cases::judge(case, &reports);
        total.expected += o.expected;
        total.misses += o.misses;
        total.duplicates += o.duplicates;
        total.wrong_way += o.wrong_way;
        total.over_goal += o.over_goal;
        total.max_error = total.max_error.max(o.max_error);
        total.problems.extend(o.problems);
    }
    eprintln!(
        "{}: {} cases, {} occurrences, {} misses, {} duplicates, {} wrong way, max time error {:.2e} s",
        category.name(),
        suite.len(),
        total.expected,
        total.misses,
        total.duplicates,
        total.wrong_way,
        total.max_error
    );
    assert!(
        total.problems.is_empty(),
        "{}: {} problems:\n{}",
        category.name(),
        total.problems.len(),
        total.problems.join("\n")
    );
    // Every case looked at something: the references are not all empty. Within rounding, a
    // touch is required only of the levels 3 or 4 ulps below the apex, 2 draws in 9 (the rest
    // may be touched or missed by the exact path: optional).
    let least = match category {
        Category::GrazeRounding => suite.len() / 6,
        _ => suite.len() / 2,
    };
    assert!(total.expected >= least, "{total:?}");
}

#[test]
fn the_suite_has_at_least_1000_cases_and_the_same_ones_every_time() {
    let a = cases::suite();
    assert!(a.len() >= 1000, "{}", a.len());
    let b = cases::suite();
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.scene_text(), y.scene_text(), "{}", x.name());
    }
    // The references are the closed form's: spot-check the stable quadratic against a root
    // that cancels in the textbook formula (b^2 >> 4ac).
    let r = cases::quadratic_roots(1.0, -1e8, 1.0);
    assert!(
        (r[0] - 1e-8).abs() <= 1e-24 && (r[1] - 1e8).abs() <= 1e-8,
        "{r:?}"
    );
}

#[test]
fn double_crossings_inside_one_tick() {
    check(Category::Double);
}

#[test]
fn tangent_grazes_exact() {
    check(Category::GrazeExact);
}

#[test]
fn tangent_grazes_within_rounding() {
    check(Category::GrazeRounding);
}

#[test]
fn roots_exactly_on_a_tick_boundary() {
    check(Category::Boundary);
}

#[test]
fn zeros_at_the_spawn() {
    check(Category::Spawn);
}

#[test]
fn fast_bodies_through_several_planes_a_tick() {
    check(Category::Fast);
}

#[test]
fn bodies_spinning_on_a_spring() {
    check(Category::Spin);
}
