//! Bad input never panics: errors name the file and line:column or the field, and what was
//! expected; the CLI prints one line and exits non-zero; a diverging run keeps its table.

use std::process::Command;

use proptest::prelude::*;
use volley::scene;

fn volley(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .output()
        .expect("the binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn write_scene(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("volley-bad-input-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const GOOD: &str = r#"Scene(
    dt: 0.1,
    integrator: SemiImplicitEuler,
    forces: [Gravity((0.0, 0.0, -9.81))],
    bodies: [(mass: 1.0, position: (0.0, 0.0, 1.0))],
)"#;

#[test]
fn a_syntax_error_names_file_line_and_column_in_one_line() {
    let path = write_scene("syntax.ron", &GOOD.replace("dt: 0.1,", "dt: 0.1"));
    let (code, _, err) = volley(&["headless", path.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    let expected = format!("error: {}:3:", path.display());
    assert!(err.starts_with(&expected), "{err}");
}

#[test]
fn invalid_values_name_the_field_and_what_was_expected() {
    let cases = [
        ("mass: 1.0", "mass: 0.0", "bodies[0].mass", "> 0"),
        ("mass: 1.0", "mass: -2.5", "bodies[0].mass", "> 0"),
        ("dt: 0.1", "dt: -0.1", "dt", "> 0"),
        ("dt: 0.1", "dt: NaN", "dt", "finite"),
        ("dt: 0.1", "dt: inf", "dt", "finite"),
        (
            "(0.0, 0.0, 1.0)",
            "(0.0, NaN, 1.0)",
            "bodies[0].position",
            "finite",
        ),
        ("-9.81", "-inf", "forces[0]", "finite"),
    ];
    for (from, to, field, expected) in cases {
        let err = scene::parse(&GOOD.replace(from, to), "s.ron", "s").unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{to}: {err}");
        assert!(err.message.contains(expected), "{to}: {err}");
        assert!(
            err.to_string().starts_with(&format!("s.ron: {field}: ")),
            "{err}"
        );
    }
}

#[test]
fn unknown_integrators_and_forces_are_named_with_the_alternatives() {
    let err =
        scene::parse(&GOOD.replace("SemiImplicitEuler", "Leapfrog"), "s.ron", "s").unwrap_err();
    assert!(
        err.message.contains("Leapfrog") && err.position.is_some(),
        "{err}"
    );
    assert!(
        err.message.contains("Rk4"),
        "lists what was expected: {err}"
    );
    let err = scene::parse(&GOOD.replace("Gravity(", "Antigravity("), "s.ron", "s").unwrap_err();
    assert!(
        err.message.contains("Antigravity") && err.message.contains("LinearDrag"),
        "{err}"
    );
    let (code, _, err) = volley(&["headless", "seed", "--integrator", "leapfrog"]);
    assert_eq!((code, err.lines().count()), (2, 1), "{err}");
    assert!(err.contains("explicit-euler"), "{err}");
}

/// One lane more than `volley::scene::MAX_COMPARE_LANES`.
const SEVENTEEN_LANES: &str = "rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4";

#[test]
fn cli_errors_are_one_line_with_a_nonzero_exit() {
    for args in [
        vec!["headless"],
        vec!["headless", "no-such-scene"],
        vec!["headless", "seed", "--dt", "0"],
        vec!["headless", "seed", "--ticks", "ten"],
        vec!["headless", "seed", "--expect-hash", "0xe02a9ef4a1ddb32g"],
        vec!["aim", "--from", "0,0", "--to", "1,1,1", "--speed", "3"],
        vec!["aim", "--from", "0,0,0", "--to", "1000,0,0", "--speed", "3"],
        vec!["window", "seed", "--compare", "rk4@zero"],
        vec!["window", "seed", "--compare", "rk4@0.1x0"],
        vec!["window", "seed", "--compare", "leapfrog@0.1"],
        vec!["window", "seed", "--compare", SEVENTEEN_LANES],
        vec!["headless", "seed", "--substeps", "10001"],
        vec!["warp"],
    ] {
        let (code, _, err) = volley(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    }
}

/// `exact` has no closed form under the rifle's Mach drag: a `--compare` of only lanes the scene
/// refuses is one line before the window opens (the window would run the scene's own integrator
/// instead).
#[test]
fn a_compare_list_the_scene_runs_none_of_is_refused_before_the_window_opens() {
    let (code, _, err) = volley(&["window", "rifle", "--compare", "exact,exact@0.01"]);
    assert_eq!((code, err.lines().count()), (2, 1), "{err}");
    assert!(
        err.starts_with(
            "error: --compare: none of the compared integrators can run this scene (exact: "
        ),
        "{err}"
    );
}

#[test]
fn a_diverging_run_says_where_and_keeps_the_table_printed_so_far() {
    // Explicit Euler on a stiff spring (w h = 1.67): the amplitude grows by 1.94 per step and the
    // energy passes 10x its start within two steps.
    let path = write_scene(
        "stiff.ron",
        r#"Scene(dt: 0.016666666666666666, integrator: ExplicitEuler,
            forces: [Spring(anchor: (0.0, 0.0, 0.0), stiffness: 10000.0)],
            bodies: [(mass: 1.0, position: (1.0, 0.0, 0.0))])"#,
    );
    let (code, out, err) = volley(&["headless", path.to_str().unwrap()]);
    assert_eq!(code, 3, "{err}");
    // The stability pre-check warns first (warning: lines); the failure itself is one line.
    let errors: Vec<&str> = err.lines().filter(|l| !l.starts_with("warning:")).collect();
    assert_eq!(errors.len(), 1, "{err}");
    assert!(
        errors[0].starts_with("error: diverged at tick 2 (body 0)"),
        "{err}"
    );
    let rows: Vec<&str> = out
        .lines()
        .filter(|l| !l.trim_start().starts_with("tick"))
        .collect();
    assert_eq!(rows.len(), 2, "rows for ticks 0 and 1 are kept: {out}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// Any mutation of a valid scene parses or fails with an error; nothing panics.
    #[test]
    fn mangled_scenes_never_panic(
        cut in 0usize..GOOD.len(),
        insert in "[ -~]{0,8}",
        keep in any::<bool>(),
    ) {
        let mut text = GOOD.to_string();
        let at = (0..=cut).rev().find(|i| text.is_char_boundary(*i)).unwrap_or(0);
        if keep { text.insert_str(at, &insert) } else { text.replace_range(at.., &insert) }
        let _ = scene::parse(&text, "fuzz.ron", "fuzz");
    }
}

/// One rule for counts of ticks: 0 is refused at parse time, naming the flag, exit 2.
#[test]
fn every_zero_is_refused_for_every_count_of_ticks() {
    for args in [
        vec!["headless", "seed", "--every", "0"],
        vec![
            "headless",
            "seed",
            "--frames",
            "/nonexistent",
            "--frame-every",
            "0",
        ],
        vec![
            "record",
            "seed",
            "-o",
            "/nonexistent/x.vrec",
            "--hash-every",
            "0",
        ],
        vec![
            "replay",
            "tests/data/golden.vrec",
            "--headless",
            "--every",
            "0",
        ],
    ] {
        let (code, _, err) = volley(&args);
        let flag = args[args.len() - 2];
        assert_eq!((code, err.lines().count()), (2, 1), "{args:?}: {err}");
        assert!(err.contains(flag) && err.contains('0'), "{args:?}: {err}");
    }
}

/// `--help` lists the integrator and format names from the code, not from a hand-kept list.
#[test]
fn help_lists_the_integrator_and_format_names() {
    let (code, out, _) = volley(&["headless", "--help"]);
    assert_eq!(code, 0);
    for i in volley::Integrator::ALL {
        assert!(out.contains(i.name()), "--help lacks {}: {out}", i.name());
    }
    assert!(out.contains("[possible values: table, csv, json]"), "{out}");
    let (code, _, err) = volley(&[
        "window",
        "--integrator",
        "leapfrog",
        "--exit-after-frames",
        "1",
    ]);
    assert_eq!((code, err.lines().count()), (2, 1), "{err}");
    assert!(
        err.contains("--integrator: unknown `leapfrog`") && err.contains("rk4"),
        "{err}"
    );
}

/// Bytes that are not text (invalid UTF-8 from the first byte, and a NUL) given to every reader
/// that takes a file: each refuses with exit 2, the code for bad input, in one line naming the
/// file, as for a scene. A capture once exited 4, the code for the environment.
#[test]
fn every_reader_gives_bytes_that_are_not_text_exit_2() {
    let bytes: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8 | 0x80)
        .collect();
    let file = |name: &str| {
        let path = write_scene(name, "");
        std::fs::write(&path, &bytes).unwrap();
        path.to_str().unwrap().to_string()
    };
    let (scene, script, capture) = (file("noise.ron"), file("noise.txt"), file("noise.csv"));
    let (recording, shard) = (file("noise.vrec"), file("noise.json"));
    for args in [
        vec!["headless", &scene],
        vec!["record", &scene, "-o", "/dev/null"],
        vec!["aim", &scene],
        vec!["study", &scene],
        vec!["headless", "seed", "--commands", &script],
        vec!["replay", &recording, "--verify"],
        vec!["pacing", "--capture", &capture, "--displays", "60"],
        vec!["pacing", "--merge", &shard],
        vec!["study", "--merge", &shard],
        vec!["window", "seed", "--script", &script],
        vec!["window", "seed", "--display", &capture],
    ] {
        let (code, _, err) = volley(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains("noise."), "{args:?}: {err}");
    }
}

/// Every list flag takes commas, and repeating the flag adds to the list.
#[test]
fn list_flags_take_commas_and_repeats() {
    let missing = |name: &str| {
        let dir = std::env::temp_dir().join(format!("volley-bad-input-{}", std::process::id()));
        dir.join(name).to_str().unwrap().to_string()
    };
    let (a, b) = (missing("a-missing.csv"), missing("b-missing.csv"));
    // The second file of a comma list is read (and refused by name): the list was split.
    let shipped = "assets/captures/presentmon_test_case_4.csv";
    let (code, _, err) = volley(&["pacing", "--capture", &format!("{shipped},{b}")]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("b-missing.csv") && !err.contains(shipped),
        "{err}"
    );
    let (code, _, err) = volley(&["pacing", "--capture", shipped, "--capture", &a]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("a-missing.csv"), "{err}");
    for flag in ["--merge"] {
        for sub in ["pacing", "study"] {
            let (code, _, err) = volley(&[sub, flag, &format!("{a},{b}")]);
            assert_eq!(code, 2, "{sub} {flag}: {err}");
            assert!(
                err.contains("a-missing.csv") && !err.contains(','),
                "{sub}: {err}"
            );
        }
    }
    // --compare: a lane list over two flags, `default` inside a list; too many lanes in all is
    // one refusal, so both flags were counted.
    let eight = "rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4";
    let nine = "rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4,rk4";
    let (code, _, err) = volley(&["window", "seed", "--compare", eight, "--compare", nine]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("at most 16 lanes, got 17"), "{err}");
    let (code, _, err) = volley(&[
        "window",
        "seed",
        "--compare",
        &format!("default,{eight},{nine}"),
    ]);
    assert!(err.contains("got 21"), "{code}: {err}");
}
