//! Level surfaces in the window (issue 38): the bundled firing range's meshes and heightfield
//! drawn as lit triangles, yellow rings where bodies struck them, and the probe naming the
//! surface and the triangle or cell; the real window under Xvfb.

use crate::support;

use glam::DVec3;

use volley::app::session::Session;
use volley::contact::Surface;
use volley::render::draw::{DrawList, DrawOptions, Lane};
use volley::render::level::{LevelKey, level_vertices};
use volley::render::probe::MarkerKind;
use volley::scene;

fn range() -> Session {
    let path = support::crate_path("assets/scenes/range.ron");
    Session::new(scene::load(&path).unwrap(), &path, Vec::new())
}

/// Every triangle the contact meets is drawn, once, where the contact meets it (to f32
/// rounding of the position relative to the origin), with a unit normal of its face.
#[test]
fn the_range_draws_every_level_triangle_where_the_contact_meets_it() {
    let s = range();
    let contacts = s.world().contacts();
    let origin = DVec3::new(25.0, 0.0, 1.0);
    let mut vertices = Vec::new();
    level_vertices(contacts, origin, &mut vertices);
    let expected: Vec<[DVec3; 3]> = contacts
        .meshes
        .iter()
        .flat_map(|m| m.triangles())
        .chain(contacts.heightfields.iter().flat_map(|h| h.triangles()))
        .collect();
    // 3 plates and the berm (12 triangles each), and the hill's 64 x 64 cells in halves.
    assert_eq!(expected.len(), 4 * 12 + 2 * 64 * 64);
    assert_eq!(vertices.len(), 3 * expected.len());
    for (k, t) in expected.iter().enumerate() {
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        for (c, p) in t.iter().enumerate() {
            let v = vertices[3 * k + c];
            let drawn = DVec3::from(v.position.map(f64::from)) + origin;
            // Within 60 m of the origin: half an f32 ulp there is under 4e-6 m.
            assert!((drawn - *p).length() < 1e-5, "triangle {k}: {drawn} vs {p}");
            let normal = DVec3::from(v.normal.map(f64::from));
            assert!(
                (normal - n).length() < 1e-6,
                "triangle {k}: {normal} vs {n}"
            );
        }
    }
    // The renderer rebuilds on a new origin or scene, and only then.
    assert_eq!(
        LevelKey::of(contacts, origin),
        LevelKey::of(contacts, origin)
    );
    assert_ne!(
        LevelKey::of(contacts, origin),
        LevelKey::of(contacts, origin + DVec3::X)
    );
    let seed = support::crate_path("assets/scenes/seed.ron");
    let seed = Session::new(scene::load(&seed).unwrap(), &seed, Vec::new());
    assert_ne!(
        LevelKey::of(contacts, origin),
        LevelKey::of(seed.world().contacts(), origin)
    );
}

/// The ball (body 0) strikes the hill at t = 1.74 s, the grenade (body 1) the berm, and the
/// bullets (bodies 2 to 4) stop on their plates: each contact is a marker naming its surface, and the draw list rings the
/// point struck, in the plane of the triangle the contact names.
#[test]
fn contacts_with_the_level_are_markers_ringed_on_the_triangle_struck() {
    let mut s = range();
    s.run_ticks(150).unwrap();
    let lane = &s.lanes()[0];
    let world = &lane.sim.world;
    let tracks = lane.history.probe.tracks();
    let ball = &tracks[0];
    let hill: Vec<_> = ball
        .markers
        .iter()
        .filter(|m| matches!(m.kind, MarkerKind::Impact(Surface::Heightfield { .. })))
        .collect();
    assert_eq!(hill.len(), 1, "{:?}", ball.markers);
    assert!((hill[0].at.t - 1.7368).abs() < 1e-4, "{}", hill[0].at.t);
    let plates: Vec<_> = tracks[2..5]
        .iter()
        .map(|t| {
            t.markers
                .iter()
                .find_map(|m| match m.kind {
                    MarkerKind::Rest(Surface::Mesh { surface, .. }) => Some(surface),
                    _ => None,
                })
                .unwrap_or_else(|| panic!("{:?}", t.markers))
        })
        .collect();
    assert_eq!(plates, [0, 1, 2]);
    // The rings: 16 segments each, in the lines after every other line the list draws.
    let draw = |markers| {
        let mut list = DrawList::default();
        let l = Lane {
            world,
            history: &lane.history,
            at: volley::render::DrawAt::interpolated(1.0),
            colour: [255, 0, 0, 255],
            judder: &[],
        };
        let options = DrawOptions {
            markers,
            ..DrawOptions::bodies(DVec3::ZERO, 60.0)
        };
        list.build(&[l], &options);
        list
    };
    let (with, without) = (draw(true), draw(false));
    let rings = (with.lines.len() - without.lines.len()) / 2 / 16;
    assert_eq!(rings, 5, "the hill, the berm and three plates");
    // The hill's ring: its vertices on the struck triangle's plane, lifted 2 % of the ring's
    // radius (4 small markers, 0.0025 of the 60 m scale each: 0.6 m) towards the ball.
    let MarkerKind::Impact(surface) = hill[0].kind else {
        unreachable!()
    };
    let t = world.contacts().triangle(surface).unwrap();
    let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
    let side = n.dot(hill[0].at.p - t[0]).signum();
    let ring_radius = 4.0 * 0.0025 * 60.0;
    let ring = &with.lines[without.lines.len()..][..32];
    for v in ring {
        let p = DVec3::from(v.position.map(f64::from));
        let lift = side * n.dot(p - t[0]);
        assert!(
            (lift - 0.02 * ring_radius).abs() < 1e-5,
            "{lift} vs {}",
            0.02 * ring_radius
        );
    }
}

/// The real window on the range: the level drawn (steel and turf in the screenshot, which I
/// looked at: docs/window-range.png), and the probe pinned on the ball's impact names the hill
/// and the cell the contact reported.
#[test]
fn a_script_pins_the_probe_on_the_hill_the_ball_struck_in_the_real_window() {
    let test = "a_script_pins_the_probe_on_the_hill_the_ball_struck_in_the_real_window";
    // The ball strikes the hill at tick 105 and the ground next at tick 250.
    let Some((probe, shot)) =
        crate::window_probe::pinned_probe(test, "range", "impact", 150, 170, &[])
    else {
        return;
    };
    assert!(
        probe.contains("body 0 (impact on hill, cell 1367.1)"),
        "{probe}"
    );
    let image = volley::render::Image::load_png(&shot).unwrap();
    let count = |f: &dyn Fn(&[u8]) -> bool| image.rgba.chunks(4).filter(|p| f(p)).count();
    // Turf: green well above red and blue; steel: grey with blue a little above red.
    let turf = count(&|p| {
        let [r, g, b] = [p[0], p[1], p[2]].map(i32::from);
        g > 70 && g > r + 20 && g > b + 20
    });
    let steel = count(&|p| {
        let [r, b] = [p[0], p[2]].map(i32::from);
        r > 90 && (5..40).contains(&(b - r))
    });
    let yellow = count(&|p| p[0] > 200 && p[1] > 170 && p[2] < 120);
    assert!(turf > 2000, "turf {turf}");
    assert!(steel > 1000, "steel {steel}");
    assert!(yellow > 10, "yellow {yellow}");
}
