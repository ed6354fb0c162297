use super::*;

/// Every variant prints the message it printed when study errors were strings.
#[test]
fn error_messages_are_pinned() {
    let text = "Scene(dt: 0.01, integrator: Rk4, forces: [Gravity((0, 0, -9.81)), \
                QuadraticDrag(0.1)], bodies: [(mass: 1, position: (0, 0, 1))])";
    let scene = volley_sim::internals::scene::parse(text, "inline.ron", "inline").unwrap();
    let good = StudyConfig {
        timing: false,
        until: 1.0,
        ..StudyConfig::for_scene(&scene)
    };
    assert_eq!(validate(&scene, &good), Ok(()));
    let with = |change: fn(&mut StudyConfig)| {
        let mut c = good.clone();
        change(&mut c);
        validate(&scene, &c).unwrap_err()
    };
    let no_closed_form = "`exact` needs a closed form, and force term QuadraticDrag has none (exact covers any \
         mix of Gravity, ConstantForce, LinearDrag and a Spring with rest length 0, or a \
         PointMass alone); choose another integrator";
    let cases = [
        (
            with(|c| c.integrators.clear()),
            StudyError::NoIntegrators,
            "integrators: expected at least one".to_string(),
        ),
        (
            with(|c| c.dts.clear()),
            StudyError::NoSteps,
            "dt: expected at least one step".into(),
        ),
        (
            with(|c| c.dts.push(-2.0)),
            StudyError::Value(InvalidValue {
                field: "dt".into(),
                problem: volley_sim::internals::scene::ValueProblem::NotPositive(-2.0),
            }),
            "dt: expected a finite number > 0, got -2".into(),
        ),
        (
            with(|c| c.integrators.push(Integrator::Exact)),
            StudyError::Integrator(IntegratorError::NoClosedForm(
                volley_sim::internals::forces::ForceKind::QuadraticDrag,
            )),
            format!("integrators: {no_closed_form}"),
        ),
        (
            with(|c| c.until = -1.0),
            StudyError::Until {
                start: 0.0,
                until: -1.0,
            },
            "until: expected a finite time after the scene's start 0 s, got -1".into(),
        ),
        (
            with(|c| c.tolerance = Some(0.0)),
            StudyError::Tolerance(0.0),
            "tolerance: expected a finite number > 0 (m), got 0".into(),
        ),
        (
            with(|c| c.max_samples = 0),
            StudyError::NoSamples,
            "energy windows and samples: expected at least 1".into(),
        ),
    ];
    for (error, expected, message) in cases {
        assert_eq!(error, expected);
        assert_eq!(error.to_string(), message);
    }
    // A reference that would need more substeps than a scene may have: with a ground and
    // quadratic drag the reference is RK4 at 16 times the finest dt's rate.
    let grounded = volley_sim::internals::scene::parse(
        &text.replace(
            "bodies:",
            "ground: (height: 0.0, restitution: 0.5), bodies:",
        ),
        "inline.ron",
        "inline",
    )
    .unwrap();
    let wide = StudyConfig {
        integrators: vec![Integrator::Rk4],
        dts: vec![1.0, 1e-3],
        ..good.clone()
    };
    let error = run(&grounded, &wide, &mut |_| {}).unwrap_err();
    assert_eq!(
        error.to_string(),
        "substeps: expected 1 to 10000, got 16000"
    );
    let loop_error = LoopError::Observer(volley_sim::internals::sim_loop::ObserverError(
        "disk full".into(),
    ));
    let cases = [
        (
            StudyError::Reference {
                integrator: Integrator::Rk4,
                substeps: 16,
                dt: 0.5,
                error: Box::new(loop_error.clone()),
            },
            "the rk4 reference (16 substeps per tick at dt = 0.5 s) failed: disk full; study \
             smaller steps",
        ),
        (
            StudyError::TimedRun(Box::new(loop_error.clone())),
            "a timed run failed where the measured one did not: disk full",
        ),
        (StudyError::Run(Box::new(loop_error)), "disk full"),
        (
            StudyError::Extrapolation {
                body: 3,
                error: ExtrapolationError::TooManySteps,
            },
            "the extrapolation reference failed on body 3: the reference took more than \
             1000000 steps; study a shorter span",
        ),
        (
            StudyError::Shard(Shard { index: 3, count: 3 }),
            "shard: expected I/N with 0 <= I < N, got 3/3",
        ),
    ];
    for (error, message) in cases {
        assert_eq!(error.to_string(), message);
    }
}
