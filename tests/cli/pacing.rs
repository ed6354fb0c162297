//! `volley pacing`: the loop lab's sweep from the command line writes every run it made, a
//! page that answers with numbers, and a plot; bad flags and captures are one line each.

use std::collections::BTreeMap;

use crate::support::{only_line, scratch_dir, volley_output, volley_stdout};

/// The CSV as one map per line, header names to fields.
fn rows(csv: &str) -> Vec<BTreeMap<String, String>> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            let fields: Vec<&str> = l.split(',').collect();
            assert_eq!(fields.len(), header.len(), "{l}");
            header
                .iter()
                .zip(fields)
                .map(|(h, f)| (h.to_string(), f.to_string()))
                .collect()
        })
        .collect()
}

fn num(row: &BTreeMap<String, String>, key: &str) -> f64 {
    row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key}: {}", row[key]))
}

#[test]
fn the_sweep_writes_every_run_the_page_and_the_plot() {
    let dir = scratch_dir("pacing-cli");
    let out = dir.to_str().unwrap();
    let stdout = volley_stdout(
        &[
            "pacing",
            "--displays",
            "59.94,144",
            "--rates",
            "60",
            "--integrators",
            "velocity-verlet,exact",
            "--subjects",
            "orbit,bounce",
            "--seconds",
            "20",
            "--out",
            out,
        ],
        &[],
    );
    // The ranking over every subject, first on stdout: on the bounce, only a draw that never
    // shows the ball inside the ground is admissible.
    assert!(
        stdout.starts_with("## Every subject: the default"),
        "{stdout}"
    );
    assert!(
        stdout.contains("**Chosen over every subject: `accumulator` with `swept`.**"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(dir.join("pacing.csv")).unwrap();
    let rows = rows(&csv);
    // Two models and the shipped capture, one rate, five policies, two integrators, two
    // subjects, two phases, five draw modes.
    assert_eq!(rows.len(), 3 * 5 * 2 * 2 * 2 * 5);
    for display in ["59.94", "144", "presentmon_test_case_4.csv (dwm.exe)"] {
        assert!(rows.iter().any(|r| r["display"] == display), "{display}");
    }
    // With the exact integrator only the loop is left: interpolation shows the orbit (radius
    // 10 m, 10 m/s) where it was `lag` ago, so its display error is the chord of the arc
    // travelled in that time, 2 R sin(v lag / 2R), plus at most the interpolated chord's sagitta
    // between ticks (R (1 - cos(v h / 2R)), 0.35 mm at 60 Hz): within 1 mm. (The capture's lag
    // includes the time the clock dropped after its long frames.)
    for r in rows.iter().filter(|r| {
        r["integrator"] == "exact"
            && r["subject"] == "orbit"
            && r["policy"] == "accumulator"
            && r["draw"] == "interpolate"
    }) {
        let arc = 10.0 * num(r, "lag_median_ms") / 1e3;
        let chord = 20.0 * (arc / 20.0).sin();
        let error = num(r, "error_median_m");
        assert!(
            (error - chord).abs() < 1e-3,
            "{}: {error} vs {chord}",
            r["display"]
        );
    }
    let page = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for needle in [
        "## On the orbit",
        "Best on the orbit: `accumulator` with `predict`/`swept`.",
        "## Through contacts and commands",
        "### 59.94",
        "### 144",
        "### presentmon_test_case_4.csv (dwm.exe)",
        "## The loop alone: the exact integrator",
        "](report.svg)",
    ] {
        assert!(page.contains(needle), "{needle}");
    }
    let svg = std::fs::read_to_string(dir.join("report.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("accumulator + predict"));
    let png = std::fs::read(dir.join("report.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}

#[test]
fn bad_flags_and_captures_are_one_line_each() {
    let dir = scratch_dir("pacing-bad");
    let out = dir.to_str().unwrap();
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "Application,TimeInSeconds\nfoo,1\n").unwrap();
    let bad = bad.to_str().unwrap();
    let cases: [(&[&str], u8, &str); 5] = [
        (
            &["--displays", "nosuch"],
            2,
            "error: --displays: unknown `nosuch`",
        ),
        (&["--rates", "0"], 2, "error: --rates: expected tick rates"),
        (
            &["--policies", "vsync"],
            2,
            "error: --policies: unknown `vsync`",
        ),
        (&["--capture", bad], 2, "missing column MsUntilDisplayed"),
        (
            &["--seconds", "0"],
            2,
            "error: --seconds: expected a number",
        ),
    ];
    for (args, code, needle) in cases {
        let mut all = vec!["pacing", "--out", out];
        all.extend_from_slice(args);
        let o = volley_output(&all, &[]);
        assert_eq!(o.status.code(), Some(i32::from(code)), "{args:?}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        let line = only_line(&stderr, "error:");
        assert!(line.contains(needle), "{args:?}: {line}");
        if args[0] == "--capture" {
            assert!(line.contains("bad.csv:1:"), "{line}");
        }
    }
    assert!(
        !dir.join("pacing.csv").exists(),
        "nothing is written on bad input"
    );
}

#[test]
fn a_sweep_run_in_shards_merges_to_the_same_files() {
    let dir = scratch_dir("pacing-shards");
    let d = dir.to_str().unwrap();
    let flags = [
        "--displays",
        "59.94",
        "--rates",
        "60",
        "--integrators",
        "velocity-verlet",
        "--seconds",
        "5",
    ];
    let run = |extra: &[&str]| {
        let mut all = vec!["pacing"];
        all.extend_from_slice(&flags);
        all.extend_from_slice(extra);
        volley_stdout(&all, &[])
    };
    let whole = dir.join("whole");
    run(&["--out", whole.to_str().unwrap()]);
    for i in 0..2 {
        let out = run(&["--shard", &format!("{i}/2"), "--out", d]);
        assert!(out.starts_with("wrote "), "{out}");
    }
    let shard = |i: usize| format!("{d}/pacing.shard-{i}-of-2.json");
    let merged = dir.join("merged");
    volley_stdout(
        &[
            "pacing",
            "--merge",
            &shard(1),
            &shard(0),
            "--out",
            merged.to_str().unwrap(),
        ],
        &[],
    );
    for file in ["pacing.csv", "report.md", "report.svg"] {
        assert_eq!(
            std::fs::read(merged.join(file)).unwrap(),
            std::fs::read(whole.join(file)).unwrap(),
            "{file}"
        );
    }
    let o = volley_output(&["pacing", "--merge", &shard(0), "--out", d], &[]);
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(
        only_line(&stderr, "error:"),
        "error: missing shard 1/2: the files given hold shards 0 of 2 (numbered from 0)"
    );
}
