//! The per-body loop runs in the widest vector instruction set the CPU has (baseline, AVX2,
//! AVX-512; `volley::step::simd_level`). A replay recorded on one machine must verify on any
//! other, so every version must produce the same bits. These tests run the CLI with
//! `VOLLEY_SIMD` capping the choice and compare the state hashes it prints. On a CPU without
//! AVX2 every run takes the baseline path and the comparison is trivially equal, and without
//! AVX-512 the `avx512` runs take the AVX2 loop: each test says so on stderr, past the test
//! harness's capture ([`check_widths`]). Under `CI=true` a test fails if the CPU has a width
//! but the dispatch would not run it. `scripts/test` also runs this file in release, where the
//! loops are actually vectorised.

use crate::support;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Once;

use volley::Integrator;
use volley::simd::{SimdLevel, simd_level_for};

/// Whether this CPU has AVX2 and AVX-512 (`avx512f`), as the dispatch detects them.
fn cpu_widths() -> (bool, bool) {
    #[cfg(target_arch = "x86_64")]
    {
        (
            std::arch::is_x86_feature_detected!("avx2"),
            std::arch::is_x86_feature_detected!("avx512f"),
        )
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        (false, false)
    }
}

/// Checks, before a test compares the widths, which loop each `VOLLEY_SIMD` cap runs here (the
/// child process's `simd_level` is `simd_level_for` of its `VOLLEY_SIMD`). A width this CPU
/// lacks is said once per test binary on stderr, written past the harness's capture so it
/// shows in a passing run: its runs compare a narrower loop with the baseline. A width the CPU
/// has that the dispatch does not choose under its cap leaves that loop untested: said on
/// stderr, and a failure under `CI=true`.
fn check_widths() {
    static SAID: Once = Once::new();
    let (avx2, avx512) = cpu_widths();
    let ci = std::env::var("CI").is_ok_and(|v| v == "true");
    let mut wrong = Vec::new();
    let mut missing = Vec::new();
    for (cap, level, name, has) in [
        ("baseline", SimdLevel::Baseline, "the baseline", true),
        ("avx2", SimdLevel::Avx2, "AVX2", avx2),
        ("avx512", SimdLevel::Avx512, "AVX-512 (avx512f)", avx512),
    ] {
        let chosen = simd_level_for(Some(cap));
        if !has {
            missing.push(format!(
                "SIMD: this CPU has no {name}: the VOLLEY_SIMD={cap} runs take the {chosen:?} \
                 loop, so the {level:?} loop is NOT compared with the baseline on this machine"
            ));
        } else if chosen != level {
            wrong.push(format!(
                "SIMD: this CPU has {name} but under VOLLEY_SIMD={cap} the dispatch runs the \
                 {chosen:?} loop, so the {level:?} loop is not tested"
            ));
        }
    }
    SAID.call_once(|| {
        let mut err = std::io::stderr().lock();
        for line in missing.iter().chain(&wrong) {
            let _ = writeln!(err, "{line}");
        }
    });
    assert!(!ci || wrong.is_empty(), "CI=true: {}", wrong.join("; "));
}

/// What `volley headless SCENE --no-table ARGS` prints with `VOLLEY_SIMD=simd`: the events and
/// the summary line with the state hash.
fn output(simd: &str, scene: &Path, args: &[&str]) -> String {
    let scene = scene.to_str().expect("a UTF-8 path");
    let all: Vec<&str> = ["headless", scene, "--no-table"]
        .into_iter()
        .chain(args.iter().copied())
        .collect();
    let stdout = support::volley_stdout(&all, &[("VOLLEY_SIMD", simd)]);
    let last = stdout.lines().last().expect("a summary line");
    assert!(last.starts_with("summary:"), "{last}");
    stdout
}

/// Asserts that every instruction set prints the same events and summary (hash included) for
/// every integrator.
fn same_for_every_width(scene: &Path, ticks: &str) {
    check_widths();
    for integrator in Integrator::ALL {
        let args = ["--ticks", ticks, "--integrator", integrator.name()];
        let baseline = output("baseline", scene, &args);
        assert_eq!(output("avx2", scene, &args), baseline, "{integrator}");
        assert_eq!(output("avx512", scene, &args), baseline, "{integrator}");
    }
}

#[test]
fn gravity_only_bodies_step_to_the_same_bits_at_every_vector_width() {
    same_for_every_width(Path::new("assets/scenes/bench/gravity.ron"), "120");
}

#[test]
fn drag_bodies_step_to_the_same_bits_at_every_vector_width() {
    same_for_every_width(Path::new("assets/scenes/bench/drag.ron"), "120");
}

/// A volley of 37 bodies (not a multiple of any vector width) bouncing off the ground and a
/// wall and passing targets: the contact stage runs inside the vectorised loop.
const CONTACT_SCENE: &str = r#"Scene(
    dt: 0.02,
    integrator: ExplicitEuler,
    forces: [Gravity((0.0, 0.0, -9.81)), LinearDrag(0.05)],
    ground: (height: 0.0, restitution: 0.7),
    walls: [(point: (12.0, 0.0, 0.0), normal: (1.0, 0.0, 0.0), thickness: 0.1, restitution: 0.9)],
    targets: [(center: (8.0, 0.0, 4.0), radius: 1.0), (center: (4.0, 0.0, 2.0), radius: 0.5)],
    launcher: (position: (0.0, 0.0, 0.5), speed: 14.0, elevation_deg: 40.0, azimuth_deg: 0.0),
    volley: (count: 37, speed_spread: 3.0, angle_spread_deg: 10.0),
    seed: 11,
)"#;

#[test]
fn contacts_and_events_give_the_same_bits_at_every_vector_width() {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("simd_contacts.ron");
    std::fs::write(&path, CONTACT_SCENE).expect("the test's temp dir is writable");
    same_for_every_width(&path, "400");
}

/// More bodies than `STREAMING_MIN_BODIES`, so the vector loops take their streaming form
/// (recomputing `1 / m` instead of loading it) while the baseline loop loads it: still the same
/// bits. Ground contacts included, so the contact stage runs inside the streaming loop too.
#[test]
fn streaming_worlds_give_the_same_bits_as_the_baseline_loop() {
    let count = volley::step::STREAMING_MIN_BODIES + 1000;
    let text = format!(
        r#"Scene(
            dt: 0.05,
            integrator: ExplicitEuler,
            forces: [Gravity((0.0, 0.0, -9.81)), LinearDrag(0.05)],
            ground: (height: 0.0, restitution: 0.7),
            launcher: (position: (0.0, 0.0, 0.2), speed: 3.0, elevation_deg: -20.0, azimuth_deg: 0.0),
            volley: (count: {count}, speed_spread: 1.0, angle_spread_deg: 30.0),
            seed: 5,
        )"#
    );
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("simd_streaming.ron");
    std::fs::write(&path, text).expect("the test's temp dir is writable");
    check_widths();
    for integrator in [
        Integrator::ExplicitEuler,
        Integrator::VelocityVerlet,
        Integrator::Rk4,
    ] {
        let args = ["--ticks", "3", "--integrator", integrator.name()];
        let baseline = output("baseline", &path, &args);
        assert!(
            baseline.contains("impact on ground"),
            "the ground is hit: {baseline:.200}"
        );
        assert_eq!(output("avx512", &path, &args), baseline, "{integrator}");
        assert_eq!(output("avx2", &path, &args), baseline, "{integrator}");
    }
}
