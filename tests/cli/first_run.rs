//! `volley` alone on a machine with no display (a server, a container, CI): the README's first
//! command runs the main job headless and exits 0, while `volley window` there keeps its exit 4.

use std::process::Command;

use crate::support;

/// `volley ARGS` with no display in the environment, run in `dir`.
fn without_display(args: &[&str], dir: &std::path::Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_volley"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

#[test]
fn volley_alone_without_a_display_prints_the_seed_and_the_comparison_and_exits_0() {
    let test = "volley_alone_without_a_display_prints_the_seed_and_the_comparison_and_exits_0";
    let dir = support::scratch_dir("first-run");
    let out = without_display(&[], &dir);
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The slides' table, row for row as they print it (seed/000's "Computing Solution Over
    // Time": t, p, mV, F, V at two decimals), each row followed by the closed form's height.
    for row in [
        "5.00 10.00 0.00 2.00 19.20 0.00 72.50 0.00 0.00 -24.53 7.68 0.00 29.00",
        "5.20 11.54 0.00 7.80 19.20 0.00 67.60 0.00 0.00 -24.53 7.68 0.00 27.04",
        "5.40 13.07 0.00 13.21 19.20 0.00 62.69 0.00 0.00 -24.53 7.68 0.00 25.08",
        "5.60 14.61 0.00 18.22 19.20 0.00 57.79 0.00 0.00 -24.53 7.68 0.00 23.11",
        "10.40 51.48 0.00 20.87 19.20 0.00 -59.93 0.00 0.00 -24.53 7.68 0.00 -23.97",
    ] {
        assert!(
            stdout.lines().any(|l| l
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
                .starts_with(row)),
            "no row `{row}`:\n{stdout}"
        );
    }
    // The slides' truncation errors: the numerical and exact heights after one step, and
    // their difference g h^2 / 2 = 0.1962, 0.04905, 0.0004905 m.
    for (h, z, exact, error) in [
        ("0.2", "7.8000", "7.6038", "0.1962000"),
        ("0.1", "4.9000", "4.8510", "0.0490500"),
        ("0.01", "2.2900", "2.2895", "0.0004905"),
    ] {
        let words = format!("{h} {z} {exact} {error} {error}");
        assert!(
            stdout
                .lines()
                .any(|l| l.split_whitespace().collect::<Vec<_>>().join(" ") == words),
            "no truncation row `{words}`:\n{stdout}"
        );
    }
    // Every integrator, with its final error and its cost. Explicit and semi-implicit Euler end
    // g T h / 2 = 9.81 * 5.4 * 0.2 / 2 = 5.2974 m off; the methods exact under constant force
    // end at rounding (1e-12 m is some thousand ulps of the 50 m positions).
    for integrator in volley::Integrator::ALL {
        let line = stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(integrator.name()))
            .unwrap_or_else(|| panic!("no line for {integrator}:\n{stdout}"));
        let words: Vec<&str> = line.split_whitespace().collect();
        let error: f64 = words[1].parse().unwrap();
        let evals: u64 = words[2].parse().unwrap();
        use volley::Integrator::*;
        match integrator {
            ExplicitEuler | SemiImplicitEuler | ImplicitEuler => {
                assert!((error - 5.2974).abs() < 1e-3, "{line}")
            }
            _ => assert!(error < 1e-12, "{line}"),
        }
        assert_eq!(evals == 0, integrator == Exact, "{line}");
    }
    let last = stdout.lines().last().unwrap();
    assert!(
        last.starts_with("To see the window:") && last.contains("xvfb-run"),
        "{last}"
    );
    // The picture: written where an adapter exists (CI installs one), with each of the four
    // lanes in its colour.
    let picture = dir.join("volley-seed.png");
    if stdout.contains("No picture:") {
        return support::unavailable(test, "no GPU adapter for the picture");
    }
    assert!(stdout.contains("Wrote volley-seed.png"), "{stdout}");
    let image = volley::render::Image::load_png(&picture).unwrap();
    assert_eq!((image.width, image.height), (1280, 720));
    for integrator in volley::app::input::DEFAULT_COMPARE {
        let c = volley::palette::integrator(integrator);
        let near = (0..image.height)
            .flat_map(|y| (0..image.width).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let p = image.pixel(x, y);
                (0..3).all(|k| (i32::from(p[k]) - i32::from(c[k])).abs() <= 24)
            })
            .count();
        // Verlet lies under RK4 on the exact arc: only its end dot shows, a few pixels.
        assert!(near >= 4, "{integrator}: {near} pixels of its colour");
    }
}

#[test]
fn volley_window_without_a_display_keeps_exit_4_and_one_line() {
    let dir = support::scratch_dir("window-no-display");
    let out = without_display(&["window"], &dir);
    assert_eq!(out.status.code(), Some(4));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = support::only_line(&stderr, "error:");
    assert!(line.contains("display"), "{line}");
    assert!(out.stdout.is_empty());
}
