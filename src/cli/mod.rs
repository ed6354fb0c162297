//! Subcommand implementations of the `volley` binary, one file each, plus what they share.

pub mod aim;
pub mod args;
pub mod display;
pub mod first_run;
pub mod frames;
pub mod headless;
pub mod pacing;
pub mod range;
pub mod record;
pub mod replay;
pub mod scenes;
pub mod study;
pub mod synctest;
pub mod window;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use glam::DVec3;

/// A failure the CLI reports as one line, with its exit code.
pub struct Failure {
    /// Process exit code.
    pub code: u8,
    /// The line printed after `error: `.
    pub message: String,
}

/// Exit code for a replay that failed verification, a run that ended on another hash than
/// `--expect-hash`, or a sync test whose re-run parted from the first run.
pub const EXIT_MISMATCH: u8 = 1;
/// Exit code for bad input: arguments, scene, command script, recording.
pub const EXIT_INPUT: u8 = 2;
/// Exit code for a diverged simulation.
pub const EXIT_DIVERGED: u8 = 3;
/// Exit code for an environment failure: I/O, no GPU adapter, no display.
pub const EXIT_ENVIRONMENT: u8 = 4;

/// A failure with `code` and `message`.
pub fn fail(code: u8, message: impl std::fmt::Display) -> Failure {
    Failure {
        code,
        message: message.to_string(),
    }
}

/// Prints a clap error as one line (help and version print in full) and picks the exit code.
pub fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        let _ = e.print();
        return ExitCode::SUCCESS;
    }
    // clap's first line names the problem; the usage block after it is dropped.
    let rendered = e.render().to_string();
    let first = rendered
        .lines()
        .next()
        .unwrap_or("error: invalid arguments");
    eprintln!("{first} (see `volley --help`)");
    ExitCode::from(EXIT_INPUT)
}

/// Reads a text file a user gave (a command or input script, a capture, a shard file): any
/// failure, a missing file or bytes that are not UTF-8 text alike, is bad input (exit 2), as
/// for a scene or a recording, and names the file.
pub fn read_input(path: &Path) -> Result<String, Failure> {
    volley::scene::read_text(path)
        .map_err(|e| fail(EXIT_INPUT, format!("{}: cannot read: {e}", path.display())))
}

/// Parses `X,Y,Z`.
pub fn parse_vec3(text: &str) -> Result<DVec3, String> {
    let parts: Vec<f64> = text
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected X,Y,Z numbers, got `{text}`"))?;
    match parts.as_slice() {
        [x, y, z] if parts.iter().all(|v| v.is_finite()) => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(format!("expected three finite numbers X,Y,Z, got `{text}`")),
    }
}

/// Folders searched for bundled scenes: ./assets/scenes, then the crate's own.
pub fn scene_dirs() -> Vec<PathBuf> {
    vec![
        PathBuf::from("assets/scenes"),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes"),
    ]
}

/// A scene argument as a path: the file itself, or a bundled scene by name (`seed`,
/// `hard/stiff_spring`).
pub fn resolve_scene(arg: &str) -> Result<PathBuf, Failure> {
    let direct = PathBuf::from(arg);
    if direct.is_file() {
        return Ok(direct);
    }
    for dir in scene_dirs() {
        let candidate = dir.join(format!("{arg}.ron"));
        if candidate.is_file() {
            return Ok(candidate);
        }
    }
    Err(fail(EXIT_INPUT, volley::no_such_scene(arg)))
}

/// Every `.ron` file under `dir`, recursively, into `out`.
pub fn collect_ron(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            collect_ron(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "ron") {
            out.push(path);
        }
    }
    Ok(())
}
