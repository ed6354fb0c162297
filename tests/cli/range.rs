//! `volley range` end to end: the rifle's range table as docs/aiming/range-rifle.txt shows it,
//! its CSV at full precision equal to the library's rows bit for bit, and bad input as one line
//! with exit code 2.

use crate::aim::generated_doc;
use crate::support::{scratch_dir, volley_output};

/// docs/aiming/range-rifle.txt: the bundled rifle's range table every 100 m to 1000 m, as
/// `volley range` prints it (regenerated with VOLLEY_BLESS=1).
#[test]
fn the_rifles_range_table_in_the_docs_is_what_volley_range_prints() {
    let fresh = generated_doc("docs/aiming/range-rifle.txt", "range", &["range", "rifle"]);
    let rows = fresh
        .lines()
        .filter(|l| l.trim_start().starts_with(char::is_numeric))
        .count();
    assert_eq!(rows, 10, "{fresh}");
    assert!(!fresh.contains("not reached"), "{fresh}");
}

#[test]
fn the_csv_is_the_librarys_table_at_full_precision() {
    let dir = scratch_dir("range_csv");
    let csv = dir.join("rifle.csv");
    let out = volley_output(
        &[
            "range",
            "rifle",
            "--ranges",
            "50:950:150",
            "--csv",
            csv.to_str().unwrap(),
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("range_m,time_s,height_m,drop_m,windage_m,speed_mps,mach,energy_j")
    );
    let scene = volley::scene::bundled("rifle").unwrap();
    let ranges: Vec<f64> = (0..7).map(|k| 50.0 + 150.0 * f64::from(k)).collect();
    let table = volley::firing::range_table(&scene, &ranges, 120.0).unwrap();
    assert_eq!(table.rows.len(), 7);
    for (line, row) in lines.zip(&table.rows) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let want = [
            row.range,
            row.time,
            row.height,
            row.drop,
            row.windage,
            row.speed,
            row.mach.unwrap(),
            row.energy,
        ];
        for (got, want) in v.iter().zip(want) {
            assert_eq!(got.to_bits(), want.to_bits(), "{line}");
        }
    }
}

#[test]
fn a_bad_range_request_is_one_line_and_exit_2() {
    for (args, says) in [
        (vec!["range", "rifle", "--ranges", "0:100:10"], "--ranges"),
        (vec!["range", "rifle", "--ranges", "a:b"], "FROM:TO:STEP"),
        (vec!["range", "no-such-scene"], "no-such-scene"),
        (
            vec!["range", "rifle", "--max-flight-time", "0"],
            "max flight time",
        ),
    ] {
        let out = volley_output(&args, &[]);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(says) && err.trim().lines().count() == 1,
            "{args:?}: {err}"
        );
    }
}
