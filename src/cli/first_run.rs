//! `volley` with no subcommand on a machine with no display (a server, a container, a CI
//! runner): the sandbox's main job without a window, so the README's first command shows
//! something everywhere.
//!
//! What it prints, all computed here from the seed scene:
//! 1. the course slides' worked example, explicit Euler at h = 0.2 s from t = 5.00 s, as the
//!    slides print it (two decimals), with the closed form's height beside each row and the
//!    global error between them;
//! 2. the slides' one-step truncation error at h = 0.2, 0.1 and 0.01 s (`g h^2 / 2`);
//! 3. every integrator on the seed: the final position error against the closed form and the
//!    force evaluations it cost (the same run at the same step, so cost and error side by
//!    side);
//! 4. where a GPU adapter exists (a software one will do), the window's picture of the run, the
//!    four default compare lanes over the closed form's dashed arc, drawn offscreen by the
//!    renderer `volley headless --frames` uses, written as `volley-seed.png`;
//! 5. last, how to see the window.

use std::path::Path;

use glam::DVec3;
use volley::exact::closed_form;
use volley::render::{Gpu, write_picture};
use volley::{Integrator, Scene, SimLoop, VirtualClock, World};

use super::{EXIT_ENVIRONMENT, Failure, fail};

/// Where the picture goes: the working directory, as the window's screenshots do.
pub const PICTURE: &str = "volley-seed.png";

/// Runs the main job headless after the window could not open for `why`.
pub fn run(why: &str) -> Result<(), Failure> {
    let scene = volley::bundled_scene("seed").map_err(|e| fail(EXIT_ENVIRONMENT, e))?;
    println!("Volley: no display to open the window on ({why}).");
    println!("The seed scene, stepped without a window.");
    println!();
    worked_example(&scene)?;
    println!();
    truncation(&scene)?;
    println!();
    comparison(&scene)?;
    println!();
    picture(&scene);
    println!(
        "To see the window: run `volley` (`cargo run --release`) on a desktop with a display, \
         or under a virtual one: `xvfb-run -a cargo run --release -- window --exit-after-frames \
         300 --screenshot window.png`."
    );
    Ok(())
}

/// The seed's body after `ticks` of its own scene under `integrator`, with the world.
fn stepped(scene: &Scene, integrator: Integrator, ticks: u64) -> Result<World, Failure> {
    let mut scene = scene.clone();
    scene
        .set_integrator(integrator)
        .map_err(|e| fail(EXIT_ENVIRONMENT, format!("seed: {e}")))?;
    let mut sim = SimLoop::new(World::new(&scene));
    sim.run_until(ticks, &mut VirtualClock::Steady(scene.timestep()), &mut ())
        .map_err(|e| fail(EXIT_ENVIRONMENT, format!("seed: {e}")))?;
    Ok(sim.world)
}

/// The closed form of the seed's first body `t` seconds after tick 0.
fn exact(scene: &Scene, t: f64) -> Result<volley::BodyState, Failure> {
    let body = scene
        .bodies()
        .first()
        .ok_or_else(|| fail(EXIT_ENVIRONMENT, "seed: no body"))?;
    let start = volley::BodyState {
        p: body.position,
        mv: body.mass * body.velocity,
    };
    closed_form(scene.forces(), start, body.mass, t)
        .ok_or_else(|| fail(EXIT_ENVIRONMENT, "seed: no closed form"))
}

fn worked_example(scene: &Scene) -> Result<(), Failure> {
    let ticks = scene.ticks_until(scene.start_time() + scene.duration());
    println!(
        "The slides' worked example: explicit Euler at h = {} s from t = {:.2} s, a {} kg \
         projectile; position p (m), momentum mV (kg m/s), force F (N), velocity V (m/s), the \
         closed form's height z* (m) and the error |p - p*| (m).",
        scene.dt(),
        scene.start_time(),
        scene.bodies()[0].mass
    );
    println!(
        "{:>6} {:>7} {:>6} {:>7} {:>7} {:>6} {:>7} {:>6} {:>6} {:>7} {:>6} {:>6} {:>7} {:>8} {:>8}",
        "t",
        "p_x",
        "p_y",
        "p_z",
        "mV_x",
        "mV_y",
        "mV_z",
        "F_x",
        "F_y",
        "F_z",
        "V_x",
        "V_y",
        "V_z",
        "z*",
        "error"
    );
    let mut world = World::new(scene);
    for tick in 0..=ticks {
        if tick > 0 {
            world
                .step()
                .map_err(|e| fail(EXIT_ENVIRONMENT, format!("seed: {e}")))?;
        }
        let b = world.bodies();
        let s = b.state(0);
        let (f, v) = (world.force_on(0), world.velocity(0));
        let star = exact(scene, tick as f64 * world.dt())?;
        println!(
            "{:>6.2} {:>7.2} {:>6.2} {:>7.2} {:>7.2} {:>6.2} {:>7.2} {:>6.2} {:>6.2} {:>7.2} \
             {:>6.2} {:>6.2} {:>7.2} {:>8.4} {:>8.4}",
            world.time(),
            s.p.x,
            s.p.y,
            s.p.z,
            s.mv.x,
            s.mv.y,
            s.mv.z,
            f.x,
            f.y,
            f.z,
            v.x,
            v.y,
            v.z,
            star.p.z,
            (s.p - star.p).length()
        );
    }
    let g = scene.forces().gravity.map_or(0.0, DVec3::length);
    let span = ticks as f64 * scene.dt();
    println!(
        "Explicit Euler ends g T h / 2 = {:.4} m above the closed form after T = {span:.2} s: \
         each step's truncation error g h^2 / 2 accumulates linearly.",
        0.5 * g * span * scene.dt()
    );
    Ok(())
}

fn truncation(scene: &Scene) -> Result<(), Failure> {
    println!(
        "Truncation error of one explicit Euler step from the slides' start (position): the \
         step's height against the closed form's, and g h^2 / 2."
    );
    println!(
        "{:>6} {:>12} {:>12} {:>12} {:>12}",
        "h (s)", "z Euler", "z exact", "error", "g h^2 / 2"
    );
    let g = scene.forces().gravity.map_or(0.0, DVec3::length);
    for h in [0.2, 0.1, 0.01] {
        let mut s = scene.clone();
        s.set_dt(h)
            .map_err(|e| fail(EXIT_ENVIRONMENT, format!("seed: {e}")))?;
        let world = stepped(&s, Integrator::ExplicitEuler, 1)?;
        let z = world.bodies().state(0).p.z;
        let star = exact(&s, world.dt())?.p.z;
        println!(
            "{h:>6} {z:>12.4} {star:>12.4} {:>12.7} {:>12.7}",
            z - star,
            0.5 * g * h * h
        );
    }
    Ok(())
}

fn comparison(scene: &Scene) -> Result<(), Failure> {
    let ticks = scene.ticks_until(scene.start_time() + scene.duration());
    println!(
        "Every integrator on the seed at h = {} s over {ticks} ticks: the final position error \
         against the closed form, and the force evaluations the run cost (its steps, and the \
         search for the closest pass by the scene's target).",
        scene.dt()
    );
    println!(
        "{:<20} {:>14} {:>12} {:>6}  symplectic",
        "integrator", "error (m)", "evaluations", "order"
    );
    let star = exact(scene, ticks as f64 * scene.dt())?;
    for integrator in Integrator::ALL {
        let world = stepped(scene, integrator, ticks)?;
        let error = (world.bodies().state(0).p - star.p).length();
        let info = integrator.info();
        let order = match info.order {
            u32::MAX => "exact".to_string(),
            n => n.to_string(),
        };
        println!(
            "{:<20} {:>14.3e} {:>12} {:>6}  {}",
            integrator.name(),
            error,
            world.force_evals(),
            order,
            if info.symplectic { "yes" } else { "no" }
        );
    }
    Ok(())
}

/// Writes the picture where an adapter exists, and says what happened either way.
fn picture(scene: &Scene) {
    match draw(scene, Path::new(PICTURE)) {
        Ok(adapter) => println!(
            "Wrote {PICTURE}: the window's picture of the run (explicit Euler, semi-implicit \
             Euler, Verlet and RK4 over the closed form's dashed arc), drawn on {adapter}."
        ),
        Err(why) => println!("No picture: {why}."),
    }
}

/// The four default compare lanes stepped to the seed's end and drawn as the window would.
fn draw(scene: &Scene, path: &Path) -> Result<String, String> {
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let adapter = gpu.describe();
    let ticks = scene.ticks_until(scene.start_time() + scene.duration());
    let worlds = volley::app::input::DEFAULT_COMPARE
        .iter()
        .map(|&i| stepped(scene, i, 0).map_err(|f| f.message))
        .collect::<Result<Vec<_>, _>>()?;
    write_picture(gpu, worlds, ticks, (1280, 720), path).map_err(|e| e.to_string())?;
    Ok(adapter)
}
