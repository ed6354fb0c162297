use super::*;

/// PresentMon's `Tests/Gold/test_case_4_v1.csv` (MIT, see assets/captures/README.md).
const SHIPPED: &str = include_str!("../../../../../assets/captures/presentmon_test_case_4.csv");
const SHIPPED_PATH: &str = "assets/captures/presentmon_test_case_4.csv";

fn refuse(text: &str, app: Option<&str>) -> String {
    read_capture(text, "cap.csv", app).unwrap_err().to_string()
}

/// The shipped capture's rows of `app`, straight from its text: (TimeInSeconds,
/// msBetweenPresents, Dropped) by a plain split at the header's positions.
fn raw_rows(app: &str) -> Vec<(f64, f64, bool)> {
    let mut lines = SHIPPED.trim_start_matches('\u{feff}').lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let (t, bp, d) = (at("TimeInSeconds"), at("msBetweenPresents"), at("Dropped"));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[0] == app)
        .map(|f| (f[t].parse().unwrap(), f[bp].parse().unwrap(), f[d] == "1"))
        .collect()
}

#[test]
fn the_shipped_capture_reads_back_its_frame_count_and_mean_interval() {
    for app in ["dwm.exe", "Presenter.exe"] {
        let raw = raw_rows(app);
        let timing = read_capture(SHIPPED, SHIPPED_PATH, Some(app)).unwrap();
        assert_eq!(timing.name, format!("presentmon_test_case_4.csv ({app})"));
        assert_eq!(timing.presents.len(), raw.len(), "{app}");
        // The mean loop delta is the mean of msBetweenPresents after the first row
        // (whose interval reaches back before the capture).
        let mean_raw: f64 = raw[1..].iter().map(|r| r.1).sum::<f64>() / (raw.len() - 1) as f64;
        let deltas: Vec<Duration> = timing.deltas(Duration::ZERO).skip(1).collect();
        let mean = deltas.iter().map(|d| d.as_secs_f64() * 1e3).sum::<f64>() / deltas.len() as f64;
        // The first row of each new Presenter.exe process counts the gap before it in the
        // clock, not in its msBetweenPresents (that is its own process's previous present).
        let span = (raw.last().unwrap().0 - raw[0].0) * 1e3 / (raw.len() - 1) as f64;
        assert!((mean - span).abs() < 1e-6, "{app}: {mean} vs {span}");
        if app == "dwm.exe" {
            assert!(
                (mean - mean_raw).abs() < 1e-3,
                "{app}: {mean} vs {mean_raw}"
            );
        }
        let dropped = raw.iter().filter(|r| r.2).count();
        assert_eq!(
            timing.presents.iter().filter(|p| p.shown.is_none()).count(),
            dropped,
            "{app}"
        );
    }
    // Without an application, the one with the most rows: the compositor's 116.
    let default = read_capture(SHIPPED, SHIPPED_PATH, None).unwrap();
    assert_eq!(default.name, "presentmon_test_case_4.csv (dwm.exe)");
    assert_eq!(default.presents.len(), 116);
}

#[test]
fn the_shipped_capture_has_its_hitch_and_its_display_times() {
    let timing = read_capture(SHIPPED, SHIPPED_PATH, Some("DWM.EXE")).unwrap();
    let longest = timing.deltas(Duration::ZERO).max().unwrap();
    // dwm.exe's longest msBetweenPresents, at TimeInSeconds 2.7066409.
    assert_eq!(longest, Duration::from_nanos(420_329_000));
    // The first row: present at 0.5515869 s, shown 16.108 ms later.
    assert_eq!(timing.presents[0].sampled, Duration::ZERO);
    assert_eq!(
        timing.presents[0].shown,
        Some(Duration::from_nanos(16_108_000))
    );
    for p in &timing.presents {
        assert!(p.shown.is_none_or(|s| s >= p.sampled));
    }
}

const V1: &str = "Application,ProcessID,Dropped,TimeInSeconds,msBetweenPresents,\
                  msUntilDisplayed,msBetweenDisplayChange\n\
                  game.exe,1,0,1.000,16.0,20.0,16.0\n\
                  game.exe,1,1,1.016,16.0,0.0,0.0\n\
                  other.exe,2,0,1.020,16.0,5.0,16.0\n\
                  game.exe,1,0,1.032,16.0,21.5,33.0\n";

fn ms(v: f64) -> Duration {
    Duration::from_nanos((v * 1e6).round() as u64)
}

#[test]
fn present_times_drive_the_clock_and_until_displayed_the_display() {
    let t = read_capture(V1, "dir/cap.csv", Some("game.exe")).unwrap();
    assert_eq!(t.name, "cap.csv (game.exe)");
    let got: Vec<(Duration, Option<Duration>)> =
        t.presents.iter().map(|p| (p.sampled, p.shown)).collect();
    assert_eq!(
        got,
        vec![
            (ms(0.0), Some(ms(20.0))),
            (ms(16.0), None),
            (ms(32.0), Some(ms(53.5))),
        ]
    );
}

#[test]
fn column_order_extra_columns_case_whitespace_bom_and_crlf_do_not_matter() {
    let text = "\u{feff} Extra , MSUNTILDISPLAYED ,timeinseconds,Dropped,application,More\r\n\
                x,20.0,1.000,0,game.exe,y\r\n\
                \r\n\
                x,0,1.016,1,GAME.EXE,y\r\n\
                x,21.5,1.032,0,game.exe,y\r\n";
    let a = read_capture(V1, "cap.csv", Some("game.exe")).unwrap();
    let b = read_capture(text, "cap.csv", Some("Game.exe")).unwrap();
    assert_eq!(a.presents, b.presents);
}

#[test]
fn display_change_intervals_are_accumulated_from_the_least_latency_frame() {
    // No MsUntilDisplayed: shown every 16 ms, then 33 ms, after the first displayed frame;
    // the third frame's latency is the least (1 ms against 4), so it is put at its present.
    let text = "Application,TimeInSeconds,MsBetweenDisplayChange\n\
                g,1.000,16.0\n\
                g,1.016,NA\n\
                g,1.020,16.0\n\
                g,1.052,33.0\n";
    let t = read_capture(text, "cap.csv", None).unwrap();
    let shown: Vec<Option<Duration>> = t.presents.iter().map(|p| p.shown).collect();
    assert_eq!(
        shown,
        vec![Some(ms(4.0)), None, Some(ms(20.0)), Some(ms(53.0))]
    );
}

#[test]
fn a_2x_header_reads_cpu_start_plus_busy_and_display_latency() {
    // PresentMon 2.0 to 2.3's columns (test_case_4_v2.csv's, in milliseconds): the
    // present is CPUStartTime + CPUBusy, the display CPUStartTime + DisplayLatency;
    // DisplayedTime NA is a dropped frame; a generated frame is skipped.
    let text = "Application,ProcessID,FrameType,CPUStartTime,FrameTime,CPUBusy,CPUWait,\
                DisplayLatency,DisplayedTime\n\
                g,1,Application,100.0,16.0,10.0,6.0,30.0,16.7\n\
                g,1,AMD AFMF,108.0,8.0,1.0,0.0,25.0,8.0\n\
                g,1,Application,116.0,16.0,12.0,4.0,NA,NA\n\
                g,1,Application,132.0,16.0,9.5,6.5,29.0,16.7\n";
    let t = read_capture(text, "cap.csv", None).unwrap();
    let got: Vec<(Duration, Option<Duration>)> =
        t.presents.iter().map(|p| (p.sampled, p.shown)).collect();
    assert_eq!(
        got,
        vec![
            (ms(0.0), Some(ms(20.0))),
            (ms(18.0), None),
            (ms(31.5), Some(ms(51.0))),
        ]
    );
    // 2.3.1 and later: TimeInMs and MsUntilDisplayed, NA for not displayed.
    let text = "Application,FrameType,TimeInMs,MsBetweenPresents,MsBetweenDisplayChange,\
                MsUntilDisplayed,CPUStartTime\n\
                g,Application,500.0,16.0,NA,20.0,490.0\n\
                g,Application,516.0,16.0,NA,NA,506.0\n";
    let t = read_capture(text, "cap.csv", None).unwrap();
    assert_eq!(t.presents[1].sampled, ms(16.0));
    assert_eq!(t.presents[0].shown, Some(ms(20.0)));
    assert_eq!(t.presents[1].shown, None);
}

#[test]
fn performance_counter_and_calendar_times_are_refused_naming_the_column() {
    // The header of PresentMon's current Tests/Gold/test_case_4.csv (--qpc_time).
    let header = "Application,ProcessID,SwapChainAddress,PresentRuntime,SyncInterval,\
                  PresentFlags,AllowsTearing,PresentMode,FrameType,TimeInQPC,\
                  MsBetweenSimulationStart,MsBetweenPresents,MsBetweenDisplayChange,\
                  MsInPresentAPI,MsRenderPresentLatency,MsUntilDisplayed,MsPCLatency,\
                  CPUStartQPC,MsBetweenAppStart,MsCPUBusy\n";
    let e = refuse(header, None);
    assert!(
        e.starts_with("cap.csv:1:10: TimeInQPC: expected times in seconds"),
        "{e}"
    );
    assert!(e.contains("--qpc_time"), "{e}");
    let e = refuse("Application,TimeInDateTime,MsUntilDisplayed\n", None);
    assert!(e.starts_with("cap.csv:1:2: TimeInDateTime: "), "{e}");
}

#[test]
fn a_missing_column_is_named_with_what_was_found() {
    let e = refuse("Application,ProcessID,MsUntilDisplayed\ng,1,2\n", None);
    assert_eq!(
        e,
        "cap.csv:1: missing column TimeInSeconds (or TimeInMs, or CPUStartTime with \
         CPUBusy): the present calls' times; found Application, ProcessID, MsUntilDisplayed"
    );
    let e = refuse("ProcessID,TimeInSeconds,MsUntilDisplayed\n1,2,3\n", None);
    assert!(
        e.starts_with("cap.csv:1: missing column Application"),
        "{e}"
    );
    assert!(
        e.ends_with("found ProcessID, TimeInSeconds, MsUntilDisplayed"),
        "{e}"
    );
    let e = refuse("Application,TimeInSeconds,msBetweenPresents\ng,1,2\n", None);
    assert!(
        e.starts_with("cap.csv:1: missing column MsUntilDisplayed"),
        "{e}"
    );
    let e = refuse("Application,CPUStartTime,DisplayLatency\ng,1,2\n", None);
    assert!(
        e.starts_with("cap.csv:1: missing column CPUBusy: with CPUStartTime"),
        "{e}"
    );
    let e = refuse(
        "Application,TimeInSeconds,MsUntilDisplayed,timeinseconds\n",
        None,
    );
    assert!(
        e.starts_with("cap.csv:1:4: timeinseconds: expected each column once"),
        "{e}"
    );
}

#[test]
fn bad_fields_are_refused_naming_the_line_and_the_column() {
    let h = "Application,Dropped,TimeInSeconds,MsUntilDisplayed\n";
    let cases = [
        (
            "g,0,abc,1\n",
            "cap.csv:2:3: TimeInSeconds: expected a number of seconds, got `abc`",
        ),
        (
            "g,0,-1,1\n",
            "cap.csv:2:3: TimeInSeconds: expected a time of 0 seconds or more, got -1",
        ),
        (
            "g,0,NaN,1\n",
            "cap.csv:2:3: TimeInSeconds: expected a finite number of seconds, got `NaN`",
        ),
        (
            "g,0,inf,1\n",
            "cap.csv:2:3: TimeInSeconds: expected a finite number of seconds, got `inf`",
        ),
        (
            "g,0,,1\n",
            "cap.csv:2:3: TimeInSeconds: expected a number of seconds, got an empty field",
        ),
        (
            "g,0,NA,1\n",
            "cap.csv:2:3: TimeInSeconds: expected a number of seconds, got NA",
        ),
        (
            "g,0,1,-0.5\n",
            "cap.csv:2:4: MsUntilDisplayed: expected a time of 0 milliseconds or more, got -0.5",
        ),
        (
            "g,0,1,x\n",
            "cap.csv:2:4: MsUntilDisplayed: expected a number of milliseconds, got `x`",
        ),
        (
            "g,2,1,1\n",
            "cap.csv:2:2: Dropped: expected 0 (displayed) or 1 (dropped), got `2`",
        ),
        (
            "g,0\n",
            "cap.csv:2:3: TimeInSeconds: missing: the row has 2 fields, the header 4",
        ),
        (
            "g,0,1\n",
            "cap.csv:2:4: MsUntilDisplayed: missing: the row has 3 fields, the header 4",
        ),
        (
            "g,0,1,1\ng,0,0.5,1\n",
            "cap.csv:3:3: TimeInSeconds: times go backwards: the present at 500 ms is earlier \
             than line 2's at 1000 ms",
        ),
        (
            "g,0,1e307,1\n",
            "cap.csv:2:3: TimeInSeconds: expected a capture of at most 604800 s (a week) from \
             its first present, got a time past any finite one",
        ),
        (
            "g,0,0,1\ng,0,700000,1\n",
            "cap.csv:3:3: TimeInSeconds: expected a capture of at most 604800 s (a week) from \
             its first present, got one of 700000.001 s",
        ),
    ];
    for (rows, want) in cases {
        assert_eq!(refuse(&format!("{h}{rows}"), None), want, "{rows}");
    }
    // A row of another application is not checked past its Application field.
    let t = read_capture(&format!("{h}g,0,1,1\nh,0,x\n"), "cap.csv", Some("g")).unwrap();
    assert_eq!(t.presents.len(), 1);
    // 2.x: a display before the present.
    let e = refuse(
        "Application,CPUStartTime,CPUBusy,DisplayLatency\ng,10,5,4\n",
        None,
    );
    assert!(
        e.starts_with("cap.csv:2:4: DisplayLatency: expected a latency of at least"),
        "{e}"
    );
}

#[test]
fn empty_files_and_files_without_rows_are_refused() {
    assert_eq!(
        refuse("", None),
        "cap.csv: empty file: expected a PresentMon CSV header (Application,...,TimeInSeconds,...)"
    );
    assert!(refuse("\u{feff}\r\n\n", None).starts_with("cap.csv: empty file"));
    assert_eq!(
        refuse("Application,TimeInSeconds,MsUntilDisplayed\r\n", None),
        "cap.csv:2: no data rows: expected one row per present after the header on line 1"
    );
    // Only generated frames: nothing of the game's loop.
    let e = refuse(
        "Application,FrameType,TimeInMs,MsUntilDisplayed\ng,AMD AFMF,1,1\n",
        None,
    );
    assert!(e.starts_with("cap.csv:2: no data rows"), "{e}");
}

#[test]
fn another_application_only_is_refused_listing_what_is_present() {
    assert_eq!(
        refuse(V1, Some("notepad.exe")),
        "cap.csv: no rows of application `notepad.exe`: the capture has game.exe (3 rows), \
         other.exe (1 rows)"
    );
    let e = read_capture(SHIPPED, SHIPPED_PATH, Some("game.exe"))
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "assets/captures/presentmon_test_case_4.csv: no rows of application `game.exe`: the \
         capture has dwm.exe (116 rows), Presenter.exe (76 rows)"
    );
}

#[test]
fn the_size_and_present_limits_are_refused_naming_them() {
    let big = " ".repeat(MAX_TEXT_BYTES as usize + 1);
    assert_eq!(
        refuse(&big, None),
        "cap.csv: cannot read: longer than 256 MiB, the most a capture may be"
    );
    // The present cap, checked at a small limit (read_capture passes MAX_CAPTURE_PRESENTS,
    // ten million: 60 MB of the shortest rows, too slow for a unit test in the dev profile).
    assert_eq!(MAX_CAPTURE_PRESENTS, 10_000_000);
    let text = "Application,TimeInMs,MsUntilDisplayed\ng,1,1\nh,1,1\ng,2,1\ng,3,1\n";
    assert_eq!(
        read_limited(text, "cap.csv", Some("g"), 3)
            .unwrap()
            .presents
            .len(),
        3
    );
    let e = read_limited(text, "cap.csv", Some("g"), 2)
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "cap.csv:5: expected at most 2 presents of g in a capture"
    );
}
