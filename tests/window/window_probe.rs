//! Markers, the probe and the arrows: PhET's dots every 0.1 s and 1 s, at the apex and at each
//! impact, where the motion puts them; the probe's readout; velocity and force arrows to scale;
//! and the real window driven by a script to hover and pin the probe under Xvfb.

use crate::support;

use glam::DVec3;

use volley::app::session::Session;
use volley::render::draw::{ArrowScale, DrawList, DrawOptions, Lane};
use volley::render::probe::{MarkerKind, Probe};
use volley::{Integrator, scene};

fn session(name: &str, compare: Vec<Integrator>) -> Session {
    let path = support::crate_path(&format!("assets/scenes/{name}.ron"));
    Session::new(scene::load(&path).unwrap(), &path, compare)
}

#[test]
fn markers_fall_every_tenth_and_second_at_the_apex_and_at_each_impact() {
    // The seed under RK4 (exact under constant gravity) at h = 0.2 s: the shot spends about
    // 5.4 s in the air from t = 5 s and then bounces.
    let mut s = session("seed", vec![Integrator::Rk4]);
    s.run_ticks(40).unwrap();
    let track = &s.lanes()[0].history.probe.tracks()[0];
    let count = |k: MarkerKind| track.markers.iter().filter(|m| m.kind == k).count();
    // 40 ticks of 0.2 s: 8 s, so marks at 0.1 .. 8.0 s: 80, of which 8 whole seconds.
    assert_eq!(count(MarkerKind::Tenth) + count(MarkerKind::Second), 80);
    assert_eq!(count(MarkerKind::Second), 8);
    for m in track
        .markers
        .iter()
        .filter(|m| m.kind == MarkerKind::Second)
    {
        let since = m.at.t - track.spawn_time;
        assert!((since - since.round()).abs() < 1e-9, "{since}");
    }
    // The apex: vz is linear in t under constant gravity, so the interpolated zero is the
    // exact apex time vz0 / g after launch (29.0000 m/s at 9.81 m/s^2), to rounding.
    let apex = track
        .markers
        .iter()
        .find(|m| m.kind == MarkerKind::Apex)
        .unwrap();
    let vz0 = 72.5001 / 2.5;
    assert!(
        (apex.at.t - track.spawn_time - vz0 / 9.81).abs() < 1e-4,
        "{:?}",
        apex.at
    );
    assert_eq!(apex.at.v.z, 0.0);
    // Then it hits the ground: one impact marker per bounce, where its centre touches the
    // ground (z = its 0.1 m radius), to within gravity over the rest of the step, g h^2 / 2.
    assert!(count(MarkerKind::Impact(volley::contact::Surface::Ground)) >= 1);
    let hit = track
        .markers
        .iter()
        .find(|m| m.kind == MarkerKind::Impact(volley::contact::Surface::Ground))
        .unwrap();
    assert!(
        (hit.at.p.z - 0.1).abs() <= 9.81 * 0.04 / 2.0,
        "{:?}",
        hit.at
    );
}

#[test]
fn the_probe_reads_state_energy_and_error_at_a_marker() {
    let mut s = session("seed", vec![Integrator::ExplicitEuler]);
    s.run_ticks(20).unwrap();
    let lane = &s.lanes()[0];
    let track = &lane.history.probe.tracks()[0];
    let apex = track
        .markers
        .iter()
        .find(|m| m.kind == MarkerKind::Apex)
        .unwrap();
    let probe = Probe::read(
        "explicit-euler",
        &lane.sim.world,
        track,
        "apex",
        apex.at,
        &lane.history.references,
    );
    // E = m |V|^2 / 2 + m g z at the apex.
    let want = 0.5 * 2.5 * apex.at.v.length_squared() + 2.5 * 9.81 * apex.at.p.z;
    assert!(
        (probe.energy - want).abs() < 1e-9 * want,
        "{} vs {want}",
        probe.energy
    );
    // Explicit Euler at 0.2 s is off the closed form by about g h t / 2 there (t ~ 3 s).
    let error = probe.error.unwrap();
    assert!(error > 1.0 && error < 5.0, "{error}");
    let lines = probe.lines();
    assert_eq!(lines[0], format!("explicit-euler body {} (apex)", track.id));
    assert!(lines[5].starts_with("|p - p_exact| = "));
}

#[test]
fn arrows_are_the_velocity_and_the_net_force_to_the_stated_scale() {
    let s = session("seed", Vec::new());
    let world = s.world();
    let lane = Lane {
        world,
        history: &s.lanes()[0].history,
        at: volley::render::DrawAt::interpolated(1.0),
        colour: [255, 0, 0, 255],
        judder: &[],
    };
    let scale = ArrowScale::of(world, 40.0);
    // 8 % of 40 m over 30 m/s is 0.107 m per m/s: 0.1 after rounding down to 1, 2 or 5.
    assert_eq!(scale.velocity, 0.1);
    let options = |vectors| DrawOptions {
        vectors,
        ..DrawOptions::bodies(DVec3::ZERO, 40.0)
    };
    let (mut without, mut with) = (DrawList::default(), DrawList::default());
    without.build(&[lane], &options(None));
    with.build(&[lane], &options(Some(scale)));
    // One body: two arrows of three strokes each, two vertices a stroke.
    assert_eq!(with.lines.len() - without.lines.len(), 12);
    let shaft = &with.lines[without.lines.len()..][..2];
    let d = DVec3::from(shaft[1].position.map(f64::from))
        - DVec3::from(shaft[0].position.map(f64::from));
    let v = world.velocity(0);
    assert!(
        (d - scale.velocity * v).length() < 1e-5,
        "{d} vs {}",
        scale.velocity * v
    );
}

#[test]
fn a_script_hovers_and_pins_the_probe_on_an_apex_in_the_real_window() {
    let test = "a_script_hovers_and_pins_the_probe_on_an_apex_in_the_real_window";
    let extra = ["--compare", "explicit-euler,rk4", "--time-scale", "4"];
    let Some((probe, shot)) = pinned_probe(test, "seed", "apex", 45, 60, &extra) else {
        return;
    };
    // Pinned on lane 0's (explicit Euler's) apex: vertical speed 0 there, and its error.
    assert!(probe.contains("explicit-euler body 0 (apex)"), "{probe}");
    assert!(
        probe.contains("V = (7.6810, 0.0000, 0.0000) m/s"),
        "{probe}"
    );
    assert!(probe.contains("|p - p_exact| = "), "{probe}");
    let image = volley::render::Image::load_png(&shot).unwrap();
    // The probe's box is drawn: a run of its light text somewhere right of the side panel.
    let light = image
        .rgba
        .chunks(4)
        .filter(|p| p[0] > 200 && p[1] > 200 && p[2] > 200)
        .count();
    assert!(light > 500, "{light}");
}

#[test]
fn over_a_bullet_the_probe_reads_its_mach_number_and_the_air() {
    // The bundled rifle: a G7 bullet at 838.2 m/s in the ICAO atmosphere with a 3 m/s crosswind.
    let mut s = session("rifle", vec![Integrator::Rk4]);
    s.run_ticks(30).unwrap();
    let lane = &s.lanes()[0];
    let track = &lane.history.probe.tracks()[0];
    let mark = &track.markers[0];
    let probe = Probe::read(
        "rk4",
        &lane.sim.world,
        track,
        "tenth",
        mark.at,
        &lane.history.references,
    );
    let (mach, density) = probe.air.expect("a Mach drag is declared");
    // Its speed through the air over the sound speed at its height, as the term computes it;
    // and the ICAO density at its height (the tabulated column's bound, 1e-9 relative).
    let drag = lane.sim.world.forces().mach_drag.clone().unwrap();
    let wind = DVec3::new(0.0, 3.0, 0.0);
    let sound = volley::Atmosphere::ICAO.at(mark.at.p.z).speed_of_sound;
    assert!(
        ((mark.at.v - wind).length() / sound - mach).abs() < 1e-8,
        "{mach}"
    );
    assert_eq!(mach, drag.mach(mark.at.p, mark.at.v));
    let icao = volley::Atmosphere::ICAO.at(mark.at.p.z).density;
    assert!(
        ((density - icao) / icao).abs() < 1e-9,
        "{density} vs {icao}"
    );
    // 0.1 s out it is still near Mach 2.3 (the peer's 770 m/s at 100 m, 0.12 s).
    assert!((2.1..2.4).contains(&mach), "{mach}");
    let last = probe.lines().pop().unwrap();
    assert_eq!(last, format!("Mach {mach:.3}, air {density:.4} kg/m^3"));
}

#[test]
fn over_a_spun_ball_and_a_rocket_the_probe_reads_the_spin_the_thrust_and_the_mass() {
    // The fly ball at its 1 s marker: Nathan's decay, exp(-age |u| / (30 s * 146.7 ft/s)), of
    // its 2500 rpm (no wind, so |u| = |V|), printed to the rpm.
    let mut s = session("baseball", vec![Integrator::Rk4]);
    s.run_ticks(90).unwrap();
    let lane = &s.lanes()[0];
    let track = &lane.history.probe.tracks()[0];
    let mark = track.markers.iter().find(|m| m.at.t >= 1.0).unwrap().at;
    let refs = &lane.history.references;
    let probe = Probe::read("rk4", &lane.sim.world, track, "second", mark, refs);
    let rpm = probe.spin.expect("a spun Mach drag is declared");
    let expected = 2500.0 * libm::exp(-mark.t * mark.v.length() / (30.0 * 146.7 * 0.3048));
    assert!(
        (rpm - expected).abs() < 1e-9 * expected,
        "{rpm} vs {expected}"
    );
    assert!(
        probe.lines().contains(&format!("spin {rpm:.0} rpm")),
        "{:?}",
        probe.lines()
    );
    assert!(probe.motor.is_none());
    // The rocket at 3 s, after burnout: no thrust, the dry mass (57.1 g less 10.8 g).
    let mut s = session("model_rocket", vec![Integrator::Rk4]);
    s.run_ticks(200).unwrap();
    let lane = &s.lanes()[0];
    let track = &lane.history.probe.tracks()[0];
    let mark = track.markers.iter().find(|m| m.at.t >= 3.0).unwrap().at;
    let refs = &lane.history.references;
    let probe = Probe::read("rk4", &lane.sim.world, track, "second", mark, refs);
    let (thrust, mass) = probe.motor.expect("a motor is declared");
    assert_eq!((thrust, mass), (0.0, 0.0571 - 0.0108));
    assert!(
        probe
            .lines()
            .contains(&"thrust 0.000 N, mass 46.30 g".to_string())
    );
    assert!(probe.spin.is_none());
    // Half a second in, the motor burns: its curve's thrust then, the mass in between.
    let mark = track.markers.iter().find(|m| m.at.t >= 0.5).unwrap().at;
    let probe = Probe::read("rk4", &lane.sim.world, track, "tenth", mark, refs);
    let (thrust, mass) = probe.motor.unwrap();
    let motor = lane.sim.world.forces().thrust.clone().unwrap();
    assert_eq!(thrust, motor.curve.thrust(mark.t));
    assert!(mass < 0.0571 && mass > 0.0463, "{mass}");
}

/// tests/data/declared_events.ron: its two declared events as markers at their own times and
/// states (RK4 is exact under constant gravity, so the closed form to the root search's
/// 1e-9 s), and the probe naming the event.
#[test]
fn declared_events_are_markers_at_their_exact_time_and_state() {
    let path = support::crate_path("tests/data/declared_events.ron");
    let mut s = Session::new(scene::load(&path).unwrap(), &path, vec![Integrator::Rk4]);
    s.run_ticks(160).unwrap();
    let lane = &s.lanes()[0];
    let track = &lane.history.probe.tracks()[0];
    let events: Vec<_> = track
        .markers
        .iter()
        .filter(|m| matches!(m.kind, MarkerKind::Declared(_)))
        .collect();
    assert_eq!(events.len(), 2, "{events:?}");
    // "10 m up", rising: 15 t - 4.905 t^2 = 10.
    let up = (15.0 - (225.0f64 - 196.2).sqrt()) / 9.81;
    assert_eq!(events[0].kind, MarkerKind::Declared(0));
    assert!((events[0].at.t - up).abs() < 1e-9, "{}", events[0].at.t);
    assert!((events[0].at.p.z - 10.0).abs() < 1e-9, "{}", events[0].at.p);
    assert!((events[0].at.v.z - (15.0 - 9.81 * up)).abs() < 1e-8);
    // "30.5 m out": t = 30.5 / 12 s, in tick 153.
    let out = 30.5 / 12.0;
    let z = 15.0 * out - 4.905 * out * out;
    assert_eq!(events[1].kind, MarkerKind::Declared(1));
    assert!((events[1].at.t - out).abs() < 1e-9, "{}", events[1].at.t);
    assert!((events[1].at.p - DVec3::new(30.5, 0.0, z)).length() < 1e-8);
    assert_eq!(events[1].at.tick, 153);
    let probe = Probe::read(
        "rk4",
        &lane.sim.world,
        track,
        "event 30.5 m out",
        events[1].at,
        &lane.history.references,
    );
    let lines = probe.lines();
    assert_eq!(lines[0], "rk4 body 0 (event 30.5 m out)");
    assert_eq!(lines[1], "tick 153, t = 2.5417 s");
    assert_eq!(lines[2], "p = (30.5000, 0.0000, 6.4384) m");
}

#[test]
fn a_script_pins_the_probe_on_a_declared_event_in_the_real_window() {
    let test = "a_script_pins_the_probe_on_a_declared_event_in_the_real_window";
    // "30.5 m out" is in tick 153: hover the last event marker after 170 frames.
    let scene = support::crate_path("tests/data/declared_events.ron");
    let Some((probe, shot)) = pinned_probe(test, scene.to_str().unwrap(), "event", 170, 190, &[])
    else {
        return;
    };
    assert!(probe.contains("body 0 (event 30.5 m out)"), "{probe}");
    assert!(probe.contains("tick 153, t = 2.5417 s"), "{probe}");
    assert!(probe.contains("p = (30.5000, 0.0000, 6.4384) m"), "{probe}");
    // The markers are drawn: magenta pixels (the event colour) in the screenshot.
    let image = volley::render::Image::load_png(&shot).unwrap();
    let magenta = image
        .rgba
        .chunks(4)
        .filter(|p| p[0] > 200 && p[1] < 140 && p[2] > 170)
        .count();
    assert!(magenta > 10, "{magenta}");
}

#[test]
fn a_script_pins_the_probe_on_the_rifle_bullet_in_the_real_window() {
    let test = "a_script_pins_the_probe_on_the_rifle_bullet_in_the_real_window";
    // The rifle's apex is near t = 1 s: hover it after 75 frames (1.25 s at 60 Hz).
    let Some((probe, _)) = pinned_probe(test, "rifle", "apex", 75, 95, &[]) else {
        return;
    };
    assert!(probe.contains("body 0 (apex)"), "{probe}");
    assert!(probe.contains("Mach "), "{probe}");
    assert!(probe.contains(" kg/m^3"), "{probe}");
}

/// Runs the real window on `scene` with a script that waits `wait` frames, hovers the last
/// marker of kind `marker` and pins the probe there, for `frames` frames in all with `extra`
/// arguments; the probe line it prints and its screenshot, or `None` where the window test is
/// skipped.
pub(crate) fn pinned_probe(
    test: &str,
    scene: &str,
    marker: &str,
    wait: u32,
    frames: u32,
    extra: &[&str],
) -> Option<(String, std::path::PathBuf)> {
    let dir = support::scratch_dir(test);
    let script = dir.join("probe.script");
    std::fs::write(
        &script,
        format!("wait {wait}\nhover marker {marker}\nwait 2\npin\nwait 10\n"),
    )
    .unwrap();
    let shot = dir.join("probe.png");
    let frames = frames.to_string();
    let mut args = vec!["window", scene, "--script", script.to_str().unwrap()];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--exit-after-frames", &frames, "--no-watch", "--screenshot"]);
    args.push(shot.to_str().unwrap());
    let stdout = crate::window_smoke::window_stdout(test, &args, "1280x800")?;
    let probe = stdout
        .lines()
        .find(|l| l.starts_with("probe: "))
        .unwrap_or_else(|| panic!("no probe line: {stdout}"))
        .to_string();
    Some((probe, shot))
}
