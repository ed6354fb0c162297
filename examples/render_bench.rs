//! Frame time of the renderer for 1, 1e3, 1e4 and 1e5 bodies, offscreen at 1280 x 720 on
//! whatever adapter wgpu finds; prints the Markdown table of BENCHMARKS.md's "Rendering"
//! section.
//!
//! ```text
//! cargo run --release --example render_bench [-- FRAMES [REPEATS]]   # default 30 frames, 3 runs
//! WGPU_BACKEND=gl cargo run --release --example render_bench   # llvmpipe instead of lavapipe
//! ```
//!
//! Each body count is a volley from the launcher (speed 30 m/s +- 3, elevation 60 +- 15 and
//! azimuth +- 15 degrees, seeded) at 60 Hz, stepped 30 ticks so the bodies are spread in the
//! air with full-length trails to draw. Per frame the world steps one tick (not timed), then
//! the timed frame: build the draw list and upload it (CPU), encode and submit the render
//! pass, and wait until the GPU has finished. Trails and ghosts are on, as in the window; the
//! last column is the same frame with both off (the spheres alone).

use std::time::{Duration, Instant};

use volley::clock::VirtualClock;
use volley::render::{
    DrawOptions, Gpu, OFFSCREEN_FORMAT, OffscreenTarget, OrbitCamera, Renderer, SceneBounds,
    TickHistory, View, Viewport, integrator_colour,
};
use volley::{SimLoop, World, scene};

const SIZE: (u32, u32) = (1280, 720);

fn volley_scene(count: u32) -> scene::Scene {
    let text = format!(
        "Scene(name: \"volley {count}\", dt: 0.0166666667, duration: 6, integrator: SemiImplicitEuler,
               forces: [Gravity((0, 0, -9.81))], ground: (height: 0, restitution: 0.6),
               launcher: (position: (0, 0, 1), speed: 30, elevation_deg: 60, azimuth_deg: 0),
               volley: (count: {count}, speed_spread: 3, angle_spread_deg: 15), seed: 7)"
    );
    scene::parse(&text, "bench.ron", "bench").expect("the bench scene is valid")
}

fn percentile(sorted: &[Duration], p: f64) -> f64 {
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i].as_secs_f64() * 1e3
}

/// One timed frame: (prepare to GPU finished, prepare alone).
fn frame(
    gpu: &Gpu,
    renderer: &mut Renderer,
    target: &OffscreenTarget,
    lane: volley::render::Lane<'_>,
    view: &View,
    options: &DrawOptions,
) -> (Duration, Duration) {
    let start = Instant::now();
    renderer.prepare(gpu, &[lane], view, options);
    let prepared = start.elapsed();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.encode(&mut encoder, target.view());
    gpu.queue.submit([encoder.finish()]);
    gpu.wait();
    (start.elapsed(), prepared)
}

/// One row's measurements in one run (ms): frame median, frame p90, CPU median, spheres-only
/// median.
type Row = [f64; 4];

fn measure(
    gpu: &Gpu,
    renderer: &mut Renderer,
    target: &OffscreenTarget,
    count: u32,
    frames: usize,
) -> Row {
    let scene = volley_scene(count);
    let bounds = SceneBounds::of_scene(&scene);
    let mut world = World::new(&scene);
    world.set_threads(1);
    let mut sim = SimLoop::new(world);
    let mut history = TickHistory::new(&sim.world, bounds.center());
    let mut clock = VirtualClock::Steady(scene.timestep());
    sim.run_until(30, &mut clock, &mut history).unwrap();
    let options = DrawOptions::picture(bounds.center(), bounds.radius());
    let spheres_only = DrawOptions {
        trails: false,
        ghosts: false,
        ..options
    };
    let view = View {
        camera: OrbitCamera::framing(&bounds, f64::from(SIZE.0) / f64::from(SIZE.1)),
        viewport: Viewport::full(SIZE.0, SIZE.1),
        target_size: SIZE,
    };
    let (mut total, mut cpu, mut bare) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..frames + 3 {
        let next = sim.world.tick() + 1;
        sim.run_until(next, &mut clock, &mut history).unwrap();
        let lane = volley::render::Lane {
            world: &sim.world,
            history: &history,
            at: volley::render::DrawAt::interpolated(0.5),
            colour: integrator_colour(sim.world.integrator()),
            judder: &[],
        };
        let (time, prepared) = frame(gpu, renderer, target, lane, &view, &options);
        let (alone, _) = frame(gpu, renderer, target, lane, &view, &spheres_only);
        if k >= 3 {
            total.push(time);
            cpu.push(prepared);
            bare.push(alone);
        }
    }
    for v in [&mut total, &mut cpu, &mut bare] {
        v.sort();
    }
    [
        percentile(&total, 0.5),
        percentile(&total, 0.9),
        percentile(&cpu, 0.5),
        percentile(&bare, 0.5),
    ]
}

fn main() {
    let arg = |i: usize, default: usize| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(default)
    };
    let (frames, repeats) = (arg(1, 30), arg(2, 3).max(1));
    let gpu = match Gpu::headless() {
        Ok(gpu) => gpu,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(4);
        }
    };
    let mut renderer = Renderer::new(&gpu, OFFSCREEN_FORMAT);
    let target = OffscreenTarget::new(&gpu, SIZE, OFFSCREEN_FORMAT);
    let counts = [1u32, 1_000, 10_000, 100_000];
    let mut runs: Vec<Vec<Row>> = vec![Vec::new(); counts.len()];
    for _ in 0..repeats {
        for (k, &count) in counts.iter().enumerate() {
            runs[k].push(measure(&gpu, &mut renderer, &target, count, frames));
        }
    }
    println!(
        "Adapter: {}; {} x {} px; {frames} frames per row after 3 warm-up frames; the whole \
         table run {repeats} times: median of the runs (min to max).\n",
        gpu.describe(),
        SIZE.0,
        SIZE.1
    );
    println!(
        "| bodies | frame, median (ms) | frame, p90 (ms) | of which CPU build + upload (ms) | \
         fps | spheres only, median (ms) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|");
    for (k, count) in counts.iter().enumerate() {
        let column = |c: usize| {
            let mut v: Vec<f64> = runs[k].iter().map(|r| r[c]).collect();
            v.sort_by(f64::total_cmp);
            (v[v.len() / 2], v[0], v[v.len() - 1])
        };
        let cell = |c: usize| {
            let (mid, lo, hi) = column(c);
            format!("{mid:.1} ({lo:.1} to {hi:.1})")
        };
        let (median, _, _) = column(0);
        println!(
            "| {count} | {} | {} | {:.2} | {:.0} | {} |",
            cell(0),
            cell(1),
            column(2).0,
            1e3 / median,
            cell(3)
        );
    }
}
