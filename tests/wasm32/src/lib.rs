//! The determinism suite as one function, [`suite`], that runs the same code natively, in a
//! wasm32 build and in an aarch64 build: every bundled scene under every integrator it accepts,
//! and the golden recording's verify. `tests/same_bits.rs` runs it all three ways (the wasm
//! build in Node, built by `scripts/wasm32`; `examples/suite.rs` built for
//! aarch64-unknown-linux-gnu by `scripts/aarch64`, under qemu-aarch64) and requires the same
//! lines; docs/physics.md, "Determinism", says what it guards against.
//!
//! In the wasm build the report is exported as text: `volley_suite()` runs the suite and
//! returns a pointer to it, `volley_suite_len()` its length in bytes. The module imports
//! nothing, so a bare `WebAssembly.instantiate` runs it (tests/wasm32/run.mjs).

use std::io::Cursor;
use std::time::Duration;

use volley_sim::internals::clock::VirtualClock;
use volley_sim::internals::hash::hex;
use volley_sim::{Integrator, Recording, Replay, SimLoop, World, parse_scene, state_hash};

include!(concat!(env!("OUT_DIR"), "/scenes.rs"));

/// The golden recording (tests/data/golden.vrec): a scene with bounces, a wall, a target, a
/// spring, drag, a seeded volley, and every kind of command.
const GOLDEN: &[u8] = include_bytes!("../../data/golden.vrec");

/// The level golden recording (tests/data/levels_golden.vrec): meshes from OBJ, glTF and inline,
/// a heightfield from a PNG (read from the copies the sim crate ships: no file system here).
const LEVEL_GOLDEN: &[u8] = include_bytes!("../../data/levels_golden.vrec");

/// The most ticks a scene is stepped: enough for every contact, command and divergence the
/// bundled scenes reach early, short enough for a debug wasm build in Node.
pub const MAX_TICKS: u64 = 300;

/// Scenes whose every tick is a bench's worth of bodies are stepped for fewer ticks: the
/// bundled `volley` scene's 10 000 bodies for this many.
const CROWD_TICKS: u64 = 20;
const CROWD: usize = 1000;

/// One line per run, in a fixed order: `scene integrator ticks=N hash=0x...`, or the line
/// that says how the run ended early (a refusal of the integrator, a divergence with its
/// tick), then the level golden recording's verify and the golden recording's.
pub fn suite() -> Vec<String> {
    let mut lines = Vec::new();
    for (name, text) in SCENES {
        let file = format!("assets/scenes/{name}.ron");
        let scene = match parse_scene(text, &file, name) {
            Ok(scene) => scene,
            Err(e) => {
                lines.push(format!("{name} unreadable: {e}"));
                continue;
            }
        };
        let limit = if scene.body_count() >= CROWD {
            CROWD_TICKS
        } else {
            MAX_TICKS
        };
        let ticks = scene
            .ticks_until(scene.start_time() + scene.duration())
            .min(limit);
        for integrator in Integrator::ALL {
            lines.push(format!(
                "{name} {integrator} {}",
                run(&scene, integrator, ticks)
            ));
        }
    }
    lines.push(format!(
        "levels_golden.vrec {}",
        golden("tests/data/levels_golden.vrec", LEVEL_GOLDEN)
    ));
    lines.push(format!(
        "golden.vrec {}",
        golden("tests/data/golden.vrec", GOLDEN)
    ));
    lines
}

/// `ticks` ticks of `scene` under `integrator` on a steady clock, as one line's tail.
fn run(scene: &volley_sim::Scene, integrator: Integrator, ticks: u64) -> String {
    let mut scene = scene.clone();
    if let Err(e) = scene.set_integrator(integrator) {
        return format!("refused: {e}");
    }
    let frame: Duration = scene.timestep();
    let mut sim = SimLoop::new(World::new(&scene));
    let ended = sim.run_until(ticks, &mut VirtualClock::Steady(frame), &mut ());
    let at = sim.world.tick();
    let hash = hex(state_hash(&sim.world));
    match ended {
        Ok(()) => format!("ticks={at} hash={hash}"),
        Err(e) => format!("ended at tick {at} hash={hash}: {e}"),
    }
}

/// A golden recording re-simulated and checked at every stored hash and keyframe.
fn golden(label: &str, bytes: &'static [u8]) -> String {
    let recording = match Recording::from_reader(Cursor::new(bytes), label) {
        Ok(r) => r,
        Err(e) => return format!("unreadable: {e}"),
    };
    let footer = recording.footer().map(|f| hex(f.final_hash));
    let mut replay = match Replay::start(recording, None) {
        Ok(r) => r,
        Err(e) => return format!("refused: {e}"),
    };
    if let Err(e) = replay.run_to(u64::MAX, &mut ()) {
        return format!("failed: {e}");
    }
    let verdict = match replay.first_divergence() {
        Some(d) => format!("diverged: {}", d.report(Some(3)).replace('\n', " | ")),
        None => "verified".to_string(),
    };
    format!(
        "{verdict} hashes={} keyframes={} final={} footer={}",
        replay.hashes_checked(),
        replay.keyframes_checked(),
        hex(state_hash(replay.world())),
        footer.as_deref().unwrap_or("none")
    )
}

#[cfg(target_arch = "wasm32")]
mod export {
    use std::sync::OnceLock;

    static REPORT: OnceLock<String> = OnceLock::new();

    fn report() -> &'static str {
        REPORT.get_or_init(|| {
            let mut text = super::suite().join("\n");
            text.push('\n');
            text
        })
    }

    /// Runs the suite (once) and returns a pointer to its report, UTF-8 text.
    #[unsafe(no_mangle)]
    pub extern "C" fn volley_suite() -> *const u8 {
        report().as_ptr()
    }

    /// The report's length in bytes.
    #[unsafe(no_mangle)]
    pub extern "C" fn volley_suite_len() -> usize {
        report().len()
    }
}
