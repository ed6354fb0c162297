//! The properties Volley's fuzz targets check, one function per thing Volley reads from a user.
//!
//! Each function takes the fuzzer's bytes, runs them through the same code the CLI and the
//! window run on a file, and panics only if a property fails; a refused input is a pass. The
//! cargo-fuzz targets in `fuzz_targets/` call them under libFuzzer (nightly, `scripts/fuzz`),
//! and `tests/regression.rs` calls them on every file of `regression/` with the stable
//! toolchain, so CI replays each finding without a fuzzer.
//!
//! What no property may do, on any input: panic, run past libFuzzer's per-input time limit, or
//! allocate past its `-rss_limit_mb` / `-malloc_limit_mb` (the bounds `scripts/fuzz` sets and
//! docs/limits.md states).
//!
//! The harness bounds the *stepping* it does per input (not what it parses or builds): a scene
//! may legally ask for a million bodies at ten thousand substeps, and stepping that is slow by
//! design, not a finding. So [`scene()`] builds a world only up to [`MAX_FUZZ_BODIES`] bodies and
//! steps at most [`MAX_FUZZ_BODY_STEPS`] body-steps; the library's own limits (docs/limits.md)
//! are what bounds a real run.

use std::io::Cursor;

use volley_lab::pacing::{DisplayTiming, read_capture};
use volley_lab::study::shard::{ShardResult, merge};
use volley_sim::World;
use volley_sim::internals::command::{Command, parse_script};
use volley_sim::internals::hash;
use volley_sim::internals::replay::format::{CRC_LEN, HEAD_LEN, PREAMBLE_LEN, head_check};
use volley_sim::internals::replay::{Recording, Replay};
use volley_sim::internals::scene::{self, Scene};

/// Most bodies [`scene()`] builds a world for (more are parsed and validated, not built).
pub const MAX_FUZZ_BODIES: usize = 4096;
/// Most body-steps (bodies × substeps × ticks) one input is stepped for.
pub const MAX_FUZZ_BODY_STEPS: u64 = 200_000;
/// Most force evaluations one input is stepped for, checked after each tick: an adaptive step
/// may take up to [`volley_sim::internals::integrate::DOPRI_MAX_ATTEMPTS`] attempts, so body-steps alone
/// do not bound its work.
pub const MAX_FUZZ_EVALS: u64 = 5_000_000;
/// Ticks a validated scene is stepped for, within [`MAX_FUZZ_BODY_STEPS`].
pub const SCENE_TICKS: u64 = 100;
/// Most ticks a command script or a recording is run for.
pub const RUN_TICKS: u64 = 400;

/// The scene the command-script target applies its commands to: the replay tests' scene, with
/// every kind of thing a command can touch (volley, contacts, spring, drag, events).
pub const COMMAND_SCENE: &str = include_str!("../../tests/data/replay_scene.ron");

thread_local! {
    /// Force evaluations the properties spent on this thread since [`take_evals`].
    static EVALS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// The force evaluations the properties spent on this thread since the last call: the work an
/// input cost, counted exactly, so the regression test can tell an input that hangs from one
/// that does not without timing it.
pub fn take_evals() -> u64 {
    EVALS.with(|e| e.replace(0))
}

fn spend(evals: u64) {
    EVALS.with(|e| e.set(e.get().saturating_add(evals)));
}

/// The text of an input, if it is UTF-8 (every text reader refuses anything else first).
fn text(data: &[u8]) -> Option<&str> {
    std::str::from_utf8(data).ok()
}

/// Bodies a world built from `scene` starts with.
fn body_count(scene: &Scene) -> usize {
    scene.bodies().len() + scene.volley().map_or(0, |v| v.count as usize)
}

/// Ticks of `world` that fit in [`MAX_FUZZ_BODY_STEPS`], at most `ticks`.
fn affordable_ticks(world: &World, ticks: u64) -> u64 {
    let per_tick = (world.bodies().id.len().max(1) as u64) * u64::from(world.substeps());
    ticks.min(MAX_FUZZ_BODY_STEPS / per_tick)
}

/// Steps `world` one tick at a time for up to `ticks` ticks; every state is finite until a
/// step reports a divergence, after which the world stays stopped.
pub fn step_checked(world: &mut World, ticks: u64) {
    let start = world.force_evals();
    step_counted(world, ticks, start);
    spend(world.force_evals().saturating_sub(start));
}

fn step_counted(world: &mut World, ticks: u64, start: u64) {
    for _ in 0..ticks {
        if world.force_evals() - start > MAX_FUZZ_EVALS {
            return;
        }
        let before = world.tick();
        match world.step() {
            Ok(()) => assert_finite(world),
            Err(d) => {
                assert!(
                    d.tick > before,
                    "a divergence is reported at the tick it happened"
                );
                assert_eq!(world.step(), Err(d), "a stopped world stays stopped");
                return;
            }
        }
    }
}

/// Every position and momentum of `world` is finite.
fn assert_finite(world: &World) {
    let b = world.bodies();
    for i in 0..b.id.len() {
        let (p, mv) = (b.p.get(i), b.mv.get(i));
        assert!(
            p.is_finite() && mv.is_finite(),
            "tick {}: body {} is not finite (p {p}, mV {mv}) and no divergence was reported",
            world.tick(),
            b.id[i].0
        );
    }
}

/// **Scene files and saved setups** (RON): parse and validate; a scene that validates is
/// written back by [`Scene::to_ron`] (what the window's "Save setup" writes) and must parse to
/// the same scene, then is built and stepped: no panic, and every state finite until a reported
/// divergence. The same bits from the saved setup.
pub fn scene(data: &[u8]) {
    let Some(text) = text(data) else { return };
    let Ok(scene) = scene::parse(text, "fuzz.ron", "fuzz") else {
        return;
    };
    let saved = scene.to_ron();
    let back = scene::parse(&saved, "saved.ron", "saved")
        .unwrap_or_else(|e| panic!("a saved setup does not parse back: {e}\n{saved}"));
    assert!(
        back.same_as(&scene),
        "a saved setup parses back to another scene: {back:?} vs {scene:?}"
    );
    if body_count(&scene) > MAX_FUZZ_BODIES {
        return;
    }
    let mut world = World::new(&scene);
    let ticks = affordable_ticks(
        &world,
        SCENE_TICKS.min(scene.ticks_until(scene.start_time() + scene.duration())),
    );
    step_checked(&mut world, ticks);
    let mut again = World::new(&back);
    let _ = again.step_ticks(world.tick() - again.tick());
    spend(again.force_evals());
    assert_eq!(
        hash::state_hash(&world),
        hash::state_hash(&again),
        "the saved setup steps to other bits"
    );
}

/// **Command scripts**: parse; a script that parses is applied to [`COMMAND_SCENE`]'s world at
/// its ticks (up to [`RUN_TICKS`]) with stepping in between: a refused command is an error, not
/// a panic, and leaves the world as it was; every state stays finite until a divergence.
pub fn commands(data: &[u8]) {
    let Some(text) = text(data) else { return };
    let Ok(script) = parse_script(text, "fuzz.txt") else {
        return;
    };
    for stamped in &script {
        let back: Command = stamped
            .command
            .to_string()
            .parse()
            .unwrap_or_else(|e| panic!("`{}` does not parse back: {e}", stamped.command));
        assert_eq!(
            back, stamped.command,
            "a command's script form reads back to another"
        );
    }
    let scene = scene::parse(COMMAND_SCENE, "replay_scene.ron", "replay").expect("valid");
    let mut world = World::new(&scene);
    for stamped in &script {
        if stamped.tick > RUN_TICKS {
            break;
        }
        let ticks = affordable_ticks(&world, stamped.tick - world.tick().min(stamped.tick));
        step_checked(&mut world, ticks);
        if world.tick() < stamped.tick {
            return;
        }
        let before = hash::state_hash(&world);
        if world.apply(&stamped.command).is_err() {
            assert_eq!(
                before,
                hash::state_hash(&world),
                "a refused command changed the world"
            );
        }
    }
    let ticks = affordable_ticks(&world, 20);
    step_checked(&mut world, ticks);
}

/// Rewrites every frame's head check and CRC of a recording in place, so the fuzzer's changes
/// reach the payload decoders and the record-order rules instead of stopping at a checksum
/// (the reader's checksum tests are in the test suite). Stops at the first frame that does
/// not fit; returns the bytes to read.
pub fn fix_checksums(data: &[u8]) -> Vec<u8> {
    let mut out = data.to_vec();
    let mut at = PREAMBLE_LEN;
    while at + HEAD_LEN <= out.len() {
        let kind = out[at];
        let len = u32::from_le_bytes(out[at + 1..at + 5].try_into().expect("4 bytes"));
        out[at + 5..at + 7].copy_from_slice(&head_check(kind, len).to_le_bytes());
        let end = at + HEAD_LEN + len as usize;
        if end + CRC_LEN > out.len() {
            break;
        }
        let crc = crc32fast::hash(&out[at..end]);
        out[end..end + CRC_LEN].copy_from_slice(&crc.to_le_bytes());
        at = end + CRC_LEN;
    }
    out
}

/// **Recordings**: the bytes with their checksums fixed ([`fix_checksums`]) are opened, the
/// embedded scene parsed, every keyframe decoded and restored into a world, and the replay
/// verified up to [`RUN_TICKS`] ticks past its start: each step refuses or passes, none panics.
pub fn recording(data: &[u8]) {
    let bytes = fix_checksums(data);
    let Ok(mut recording) = Recording::from_reader(Cursor::new(bytes), "fuzz.vrec") else {
        return;
    };
    let Ok(scene) = recording.scene() else { return };
    if body_count(&scene) > MAX_FUZZ_BODIES {
        return;
    }
    for i in 0..recording.keyframes().len() {
        if let Ok(mut world) = recording.world_at(i, &scene) {
            let ticks = affordable_ticks(&world, 2);
            step_checked(&mut world, ticks);
        }
    }
    let start = recording.start_tick();
    let Ok(mut replay) = Replay::start(recording, None) else {
        return;
    };
    let per_tick =
        (replay.world().bodies().id.len().max(1) as u64) * u64::from(replay.world().substeps());
    let ticks = RUN_TICKS.min(MAX_FUZZ_BODY_STEPS / per_tick);
    let evals = replay.world().force_evals();
    for tick in start..start.saturating_add(ticks) {
        let spent = replay.world().force_evals().saturating_sub(evals);
        if replay.run_to(tick + 1, &mut ()).is_err() || spent > MAX_FUZZ_EVALS {
            break;
        }
    }
    spend(replay.world().force_evals().saturating_sub(evals));
}

/// **The window's input scripts** (`--script`): parse; no panic on any text.
#[cfg(feature = "window")]
pub fn window_script(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if let Ok(steps) = volley::app::script::parse(text, "fuzz.script") {
        let mut player = volley::app::script::Player::new(steps);
        // A wait may ask for millions of frames; a few hundred show the player steps through.
        for _ in 0..256 {
            let _ = player.due();
            if player.finished() {
                break;
            }
        }
    }
}

/// **Study shard files** (`volley study --merge`): read, then merged as the one shard given.
pub fn shard(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if let Ok(part) = ShardResult::from_json(text, "fuzz.json") {
        let back = ShardResult::from_json(&part.to_json(), "back.json")
            .unwrap_or_else(|e| panic!("a shard file written back does not read: {e}"));
        assert_eq!(
            back.to_json(),
            part.to_json(),
            "a shard file reads back to another"
        );
        let _ = merge(&[("fuzz.json".to_string(), part)]);
    }
}

/// **Loop-lab shard files** (`volley pacing --merge`): a file that reads writes back to the
/// same text and reads again, and merging it alone never panics (it is refused unless it is
/// the whole sweep, and then gives one row per job).
pub fn pacing_shard(data: &[u8]) {
    use volley_lab::pacing::shard::{PacingShard, merge as merge_pacing};
    let Some(text) = text(data) else { return };
    if let Ok(part) = PacingShard::from_json(text, "fuzz.json") {
        let back = PacingShard::from_json(&part.to_json(), "back.json")
            .unwrap_or_else(|e| panic!("a pacing shard written back does not read: {e}"));
        assert_eq!(back, part, "a pacing shard reads back to another");
        if let Ok(rows) = merge_pacing(&[("fuzz.json".to_string(), part.clone())]) {
            assert_eq!(rows.len(), part.sweep.jobs(), "one row per job");
        }
    }
}

/// **PresentMon captures** (the loop lab's `--display FILE.csv`): read for the application with
/// the most rows, and for `dwm.exe` by name; a capture that reads holds at most
/// [`volley_lab::pacing::capture::MAX_CAPTURE_PRESENTS`] presents, its `sampled` times never
/// decrease from 0, and every display time is at or after its present and within
/// [`volley_lab::pacing::capture::MAX_CAPTURE_SPAN`] of the first.
pub fn capture(data: &[u8]) {
    let Some(text) = text(data) else { return };
    for application in [None, Some("dwm.exe")] {
        if let Ok(timing) = read_capture(text, "fuzz.csv", application) {
            check_timing(&timing);
        }
    }
}

fn check_timing(timing: &DisplayTiming) {
    use volley_lab::pacing::capture::{MAX_CAPTURE_PRESENTS, MAX_CAPTURE_SPAN};
    assert!(
        timing.name.starts_with("fuzz.csv ("),
        "a capture's name is its file and application: {}",
        timing.name
    );
    assert!(
        !timing.presents.is_empty(),
        "a capture that reads has presents"
    );
    assert!(timing.presents.len() <= MAX_CAPTURE_PRESENTS);
    assert_eq!(timing.presents[0].sampled, std::time::Duration::ZERO);
    let mut last = std::time::Duration::ZERO;
    for (i, p) in timing.presents.iter().enumerate() {
        assert!(p.sampled >= last, "present {i}: sampled goes backwards");
        last = p.sampled;
        if let Some(shown) = p.shown {
            assert!(shown >= p.sampled, "present {i}: shown before its sample");
            assert!(
                shown <= MAX_CAPTURE_SPAN,
                "present {i}: shown {shown:?} past the span limit"
            );
        }
    }
}

/// Drops a ball on `scene`'s level surface (above the middle of its box) and steps it for
/// [`LEVEL_TICKS`] ticks with swept contact, then again with discrete: every state finite, and
/// the world never diverges (a still surface cannot add energy).
fn drop_on_level(scene: volley_sim::SceneBuilder, bounds: volley_sim::internals::contact::Aabb) {
    use volley_sim::{BodySpec, Detection};
    let c = 0.5 * (bounds.min + bounds.max);
    let top = bounds.max.z + 1.0;
    if !(c.is_finite() && top.is_finite()) {
        return;
    }
    for detection in [Detection::Swept, Detection::Discrete] {
        let Ok(scene) = scene
            .clone()
            .gravity(glam::DVec3::new(0.0, 0.0, -9.81))
            .detection(detection)
            .body(BodySpec {
                mass: 1.0,
                radius: 0.05,
                position: glam::DVec3::new(c.x, c.y, top),
                velocity: glam::DVec3::new(0.3, 0.2, -5.0),
                spin: glam::DVec3::ZERO,
            })
            .build()
        else {
            return;
        };
        let mut world = World::new(&scene);
        step_checked(&mut world, LEVEL_TICKS);
    }
}

/// Ticks [`obj`], [`gltf`] and [`heightmap`] step a ball on what they read.
pub const LEVEL_TICKS: u64 = 60;

/// **Wavefront OBJ level meshes**: read with the scene's reader (tobj); a mesh that reads has
/// triangles whose indices are all below its vertex count and no degenerate one, builds its
/// hierarchy, and a ball dropped on it steps finite.
pub fn obj(data: &[u8]) {
    let Ok(mesh) = scene::read_obj(data, "fuzz.obj") else {
        return;
    };
    check_mesh(mesh);
}

/// **glTF 2.0 level meshes** (`.glb`, or `.gltf` JSON whose external buffers are refused here):
/// the same property as [`obj`].
pub fn gltf(data: &[u8]) {
    let mut no_files = |uri: &str| Err(scene::LevelError::new(uri, "no files while fuzzing"));
    let Ok((mesh, _)) = scene::read_gltf(data, "fuzz.glb", &mut no_files) else {
        return;
    };
    check_mesh(mesh);
}

fn check_mesh(mesh: volley_sim::MeshGeometry) {
    use volley_sim::internals::contact::is_degenerate;
    let n = mesh.vertices.len();
    for t in &mesh.triangles {
        assert!(
            t.iter().all(|&i| (i as usize) < n),
            "index past the vertices"
        );
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        assert!(!is_degenerate(a, b, c), "a degenerate triangle was kept");
    }
    if mesh.triangles.len() > 4096 {
        return; // read and checked; too big to step within the harness's budget
    }
    let surface = volley_sim::MeshSurface::new(
        "fuzz",
        volley_sim::LevelSource::Inline,
        0,
        std::sync::Arc::new(mesh.clone()),
        volley_sim::Transform::IDENTITY,
        0.5,
    );
    let bounds = surface.bounds();
    let scene =
        Scene::builder("fuzz", 1.0 / 60.0).mesh("fuzz", mesh, volley_sim::Transform::IDENTITY, 0.5);
    drop_on_level(scene, bounds);
}

/// **Heightfield PNGs** (16-bit grayscale): a PNG that reads has `columns x rows` finite
/// heights, and a ball dropped on it steps finite.
pub fn heightmap(data: &[u8]) {
    let Ok(grid) = scene::read_heightmap_png(data, "fuzz.png", 0.001) else {
        return;
    };
    assert_eq!(
        grid.heights.len() as u64,
        u64::from(grid.columns) * u64::from(grid.rows)
    );
    assert!(grid.heights.iter().all(|h| h.is_finite()));
    if grid.heights.len() > 1 << 16 {
        return;
    }
    let surface = volley_sim::HeightfieldSurface::new(
        "fuzz",
        volley_sim::LevelSource::Inline,
        0,
        std::sync::Arc::new(grid.clone()),
        0.5,
        1.0,
        volley_sim::Transform::IDENTITY,
        0.5,
    );
    let bounds = surface.bounds();
    let scene = Scene::builder("fuzz", 1.0 / 60.0).heightfield(
        "fuzz",
        grid,
        0.5,
        volley_sim::Transform::IDENTITY,
        0.5,
    );
    drop_on_level(scene, bounds);
}
