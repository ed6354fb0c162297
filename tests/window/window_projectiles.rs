//! The real projectiles in the real window: the panel's "Forces" section names each term with
//! its numbers, and the arrows (key Y) draw a spun ball's Magnus lift and a rocket's thrust in
//! their own colours.

use crate::support;

/// Runs bundled `scene` with `warm` ticks stepped first, arrows on, and returns the window's
/// exit report and its screenshot.
fn run(test: &str, scene: &str, warm: &str) -> Option<(String, volley::render::Image)> {
    let dir = support::scratch_dir(test);
    let script = dir.join("arrows.script");
    std::fs::write(&script, "wait 2\nkey Y\nwait 6\n").unwrap();
    let shot = dir.join("arrows.png");
    let args = [
        "window",
        scene,
        "--paused",
        "--warm-up-ticks",
        warm,
        "--script",
        script.to_str().unwrap(),
        "--exit-after-frames",
        "12",
        "--no-watch",
        "--screenshot",
        shot.to_str().unwrap(),
    ];
    let stdout = crate::window_smoke::window_stdout(test, &args, "1280x800")?;
    Some((stdout, volley::render::Image::load_png(&shot).unwrap()))
}

/// Pixels of the 3D view (right of the 340 px panel) within 24 levels of `colour`.
fn count_near(image: &volley::render::Image, colour: [u8; 4]) -> usize {
    let (w, h) = (image.width as usize, image.height as usize);
    (0..h)
        .flat_map(|y| (360..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = &image.rgba[(y * w + x) * 4..][..3];
            (0..3).all(|k| (i32::from(p[k]) - i32::from(colour[k])).abs() <= 24)
        })
        .count()
}

fn forces_line(stdout: &str) -> &str {
    stdout
        .lines()
        .find(|l| l.starts_with("forces: "))
        .unwrap_or_else(|| panic!("no forces line: {stdout}"))
}

#[test]
fn a_spun_ball_shows_its_lift_arrow_and_its_spin_in_the_panel() {
    let test = "a_spun_ball_shows_its_lift_arrow_and_its_spin_in_the_panel";
    let Some((stdout, image)) = run(test, "baseball", "60") else {
        return;
    };
    let forces = forces_line(&stdout);
    for says in [
        "Gravity (0, 0, -9.80665)",
        "MachDrag Table (Linear), d 73.8 mm, i 1, ICAO air from 4.6 m",
        "spin: Nathan lift, Nathan decay 30 s, Cd +0.0292/1000 rpm; launcher 2500 rpm back",
    ] {
        assert!(forces.contains(says), "`{says}` not in {forces}");
    }
    let lift = count_near(&image, volley::render::draw::LIFT);
    // A thin line some 15 px long at this scene's scale (the rocket asserts none at all).
    assert!(lift >= 5, "{lift} lift-coloured pixels");
    assert_eq!(
        count_near(&image, volley::render::draw::THRUST),
        0,
        "no motor"
    );
}

#[test]
fn a_rocket_shows_its_thrust_arrow_and_its_motor_in_the_panel() {
    let test = "a_rocket_shows_its_thrust_arrow_and_its_motor_in_the_panel";
    // 0.5 s in: the motor burns at about 4.4 N.
    let Some((stdout, image)) = run(test, "model_rocket", "30") else {
        return;
    };
    let forces = forces_line(&stdout);
    let says = "Thrust 8.817 N s over 1.86 s, 10.8 g of propellant, along the rail \
                (0.087, 0.000, 0.996) to 12 m/s, then the velocity";
    assert!(forces.contains(says), "`{says}` not in {forces}");
    let thrust = count_near(&image, volley::render::draw::THRUST);
    assert!(thrust >= 20, "{thrust} thrust-coloured pixels");
    assert_eq!(count_near(&image, volley::render::draw::LIFT), 0, "no spin");
}
