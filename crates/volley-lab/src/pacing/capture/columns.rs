//! Which columns a capture's header gives: the game's clock, the display time and the
//! dropped flag, resolved by name in the order of preference the module doc lists, and the
//! helpers the refusals are written with.

use super::*;

/// Where the present time comes from.
#[derive(Clone, Copy, Debug)]
pub(super) enum Clock {
    /// A column of present times in seconds.
    Seconds(usize),
    /// A column of present times in milliseconds.
    Millis(usize),
    /// CPU start (ms) plus CPU busy (ms).
    CpuStart { start: usize, busy: usize },
}

/// Where the display time comes from.
#[derive(Clone, Copy, Debug)]
pub(super) enum Display {
    /// Milliseconds after the present.
    Until(usize),
    /// Milliseconds after the CPU start.
    Latency(usize),
    /// Milliseconds after the previous displayed frame.
    Between(usize),
}

/// The columns a capture is read from.
pub(super) struct Layout<'a> {
    pub(super) names: Vec<&'a str>,
    pub(super) application: usize,
    pub(super) clock: Clock,
    pub(super) display: Display,
    pub(super) dropped: Option<usize>,
    pub(super) displayed_time: Option<usize>,
    pub(super) frame_type: Option<usize>,
}

/// Whether `name` is its own key: already lower case.
pub(super) fn is_key(name: &str) -> bool {
    name.is_ascii() && !name.bytes().any(|b| b.is_ascii_uppercase())
}

/// Whether application `name` is the one lower-cased to `key`.
pub(super) fn same_app(name: &str, key: &str) -> bool {
    if name.is_ascii() {
        name.eq_ignore_ascii_case(key)
    } else {
        name.to_lowercase() == key
    }
}

/// A number of milliseconds for a message: at most six decimals, no trailing zeros.
pub(super) fn num(v: f64) -> String {
    let s = format!("{v:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// `text` cut to 40 characters for a message.
pub(super) fn clip(text: &str) -> String {
    if text.chars().count() <= 40 {
        text.to_string()
    } else {
        format!("{}...", text.chars().take(40).collect::<String>())
    }
}

/// `items` joined by `, `, at most `most` of them, then how many more.
pub(super) fn list(items: impl ExactSizeIterator<Item = String>, most: usize) -> String {
    let n = items.len();
    let mut out: Vec<String> = items.take(most).collect();
    if n > most {
        out.push(format!("and {} more", n - most));
    }
    out.join(", ")
}

/// The header's columns and what to read from them.
pub(super) fn layout<'a>(
    file: &str,
    names: Vec<&'a str>,
    line: usize,
) -> Result<Layout<'a>, CaptureError> {
    let err = |col: Option<usize>, message: String| CaptureError {
        file: file.to_string(),
        line: Some(line),
        column: col.map(|c| Column {
            field: c + 1,
            name: names[c].to_string(),
        }),
        message,
    };
    let find = |name: &str| -> Result<Option<usize>, CaptureError> {
        let mut hits = names
            .iter()
            .enumerate()
            .filter(|(_, n)| n.eq_ignore_ascii_case(name))
            .map(|(i, _)| i);
        let first = hits.next();
        if let (Some(a), Some(b)) = (first, hits.next()) {
            return Err(err(
                Some(b),
                format!(
                    "expected each column once, and column {} is named the same",
                    a + 1
                ),
            ));
        }
        Ok(first)
    };
    let found = || {
        list(
            names.iter().map(|n| {
                if n.is_empty() {
                    "(empty)".into()
                } else {
                    clip(n)
                }
            }),
            LIST_COLUMNS,
        )
    };
    let application = find("Application")?.ok_or_else(|| {
        err(
            None,
            format!(
                "missing column Application (the process that presented); found {}",
                found()
            ),
        )
    })?;
    let clock = if let Some(c) = find("TimeInSeconds")? {
        Clock::Seconds(c)
    } else if let Some(c) = find("TimeInMs")? {
        Clock::Millis(c)
    } else if let Some(start) = find("CPUStartTime")?.or(find("CPUStartQPCTime")?) {
        let busy = find("CPUBusy")?.or(find("MsCPUBusy")?).ok_or_else(|| {
            err(
                None,
                format!(
                    "missing column CPUBusy: with {} it gives the present call's time; found {}",
                    names[start],
                    found()
                ),
            )
        })?;
        Clock::CpuStart { start, busy }
    } else {
        for name in ["TimeInQPC", "CPUStartQPC", "QPCTime"] {
            if let Some(c) = find(name)? {
                return Err(err(
                    Some(c),
                    "expected times in seconds or milliseconds (TimeInSeconds, TimeInMs or \
                     CPUStartTime), got performance-counter ticks: the counter's frequency is \
                     not in the file; capture without --qpc_time"
                        .into(),
                ));
            }
        }
        for name in ["TimeInDateTime", "CPUStartDateTime"] {
            if let Some(c) = find(name)? {
                return Err(err(
                    Some(c),
                    "expected times in seconds or milliseconds (TimeInSeconds, TimeInMs or \
                     CPUStartTime), got calendar times; capture without --date_time"
                        .into(),
                ));
            }
        }
        return Err(err(
            None,
            format!(
                "missing column TimeInSeconds (or TimeInMs, or CPUStartTime with CPUBusy): the \
                 present calls' times; found {}",
                found()
            ),
        ));
    };
    let display = match clock {
        Clock::CpuStart { .. } => {
            find("MsUntilDisplayed")?
                .map(Display::Until)
                .or(find("DisplayLatency")?
                    .or(find("MsDisplayLatency")?)
                    .map(Display::Latency))
        }
        _ => find("MsUntilDisplayed")?.map(Display::Until),
    }
    .or(find("MsBetweenDisplayChange")?.map(Display::Between))
    .ok_or_else(|| {
        err(
            None,
            format!(
                "missing column MsUntilDisplayed (or MsBetweenDisplayChange, or DisplayLatency \
                 with CPUStartTime): when each frame was displayed; found {}",
                found()
            ),
        )
    })?;
    let displayed_time = match display {
        Display::Latency(_) => find("DisplayedTime")?,
        _ => None,
    };
    Ok(Layout {
        application,
        clock,
        display,
        dropped: find("Dropped")?,
        displayed_time,
        frame_type: find("FrameType")?,
        names,
    })
}
