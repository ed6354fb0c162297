//! Picking what is under the pointer for the probe: a lane's first bodies, their recent path
//! and their markers, nearest in screen space within a few pixels.

use std::borrow::Cow;

use crate::app::session::Session;
use crate::render::probe::{MarkerKind, Probe, Sample, Track};
use crate::render::{OrbitCamera, Viewport};

/// How near the pointer (physical px) a point must be to be picked.
pub const PICK_RADIUS: f32 = 12.0;

/// The nearest body, path sample or marker to `at` (physical px) within `radius`, read as a
/// probe; markers win ties over the path, bodies over both.
pub fn pick(
    session: &Session,
    camera: &OrbitCamera,
    viewport: &Viewport,
    at: (f32, f32),
    radius: f32,
) -> Option<Probe> {
    let mut best: Option<(f32, usize, &Track, Cow<'static, str>, Sample)> = None;
    for (k, lane) in session.lanes().iter().enumerate() {
        let world = &lane.sim.world;
        for track in lane.history.probe.tracks() {
            let mut consider = |what: Cow<'static, str>, s: Sample, bias: f32| {
                let Some(px) = camera.project(s.p, viewport) else {
                    return;
                };
                let d = ((px.x - at.0).powi(2) + (px.y - at.1).powi(2)).sqrt() - bias;
                if d <= radius && best.as_ref().is_none_or(|b| d < b.0) {
                    best = Some((d, k, track, what, s));
                }
            };
            if let Some(i) = world.bodies().index_of(track.id) {
                let now = Sample {
                    tick: world.tick(),
                    t: world.time(),
                    p: world.bodies().state(i).p,
                    v: world.velocity(i),
                };
                consider(Cow::Borrowed("body"), now, 2.0);
            }
            for m in &track.markers {
                consider(marker_label(m.kind, world), m.at, 1.0);
            }
            for s in &track.samples {
                consider(Cow::Borrowed("trail"), *s, 0.0);
            }
        }
    }
    let (_, k, track, what, s) = best?;
    let lane = &session.lanes()[k];
    let name = lane.sim.world.integrator().name();
    Some(Probe::read(
        name,
        &lane.sim.world,
        track,
        &what,
        s,
        &lane.history.references,
    ))
}

/// The script's and the probe's name of a marker kind.
pub fn marker_name(kind: MarkerKind) -> &'static str {
    match kind {
        MarkerKind::Tenth => "0.1 s marker",
        MarkerKind::Second => "1 s marker",
        MarkerKind::Apex => "apex",
        MarkerKind::Impact(_) => "impact",
        MarkerKind::Rest(_) => "rest",
        MarkerKind::Declared(_) => "event",
    }
}

/// What the probe calls a marker: its name, a declared event's label after `event`, and after
/// `impact` or `rest` the surface hit by its scene name and, on a level surface, the triangle or cell
/// (`impact on steel plate, triangle 5`, `impact on hill, cell 1234.1`).
fn marker_label(kind: MarkerKind, world: &crate::world::World) -> Cow<'static, str> {
    use crate::contact::Surface;
    match kind {
        MarkerKind::Impact(surface) | MarkerKind::Rest(surface) => {
            let what = marker_name(kind);
            let Some(name) = world.contacts().surface_name(surface) else {
                return Cow::Borrowed(what);
            };
            Cow::Owned(match surface {
                Surface::Mesh { triangle, .. } => format!("{what} on {name}, triangle {triangle}"),
                Surface::Heightfield { cell, triangle, .. } => {
                    format!("{what} on {name}, cell {cell}.{triangle}")
                }
                Surface::Ground | Surface::Wall(_) => format!("{what} on {name}"),
            })
        }
        MarkerKind::Declared(i) => match world.declared_events().specs().get(i as usize) {
            Some(spec) => Cow::Owned(format!("event {}", spec.label())),
            None => Cow::Borrowed("event"),
        },
        _ => Cow::Borrowed(marker_name(kind)),
    }
}

/// Where (physical px) lane 0's body `n` is drawn now, for the script's `hover body N`.
pub fn body_on_screen(
    session: &Session,
    camera: &OrbitCamera,
    viewport: &Viewport,
    n: usize,
) -> Option<(f32, f32)> {
    let world = session.world();
    let p = world.bodies().positions().iter().nth(n)?;
    camera.project(p, viewport).map(|v| (v.x, v.y))
}

/// Where lane 0's body 0's last marker of `kind` is drawn, for `hover marker KIND`.
pub fn marker_on_screen(
    session: &Session,
    camera: &OrbitCamera,
    viewport: &Viewport,
    kind: MarkerKind,
) -> Option<(f32, f32)> {
    let track = session.lanes()[0].history.probe.tracks().first()?;
    let same = |m: MarkerKind| match (m, kind) {
        (MarkerKind::Declared(_), MarkerKind::Declared(_))
        | (MarkerKind::Impact(_), MarkerKind::Impact(_))
        | (MarkerKind::Rest(_), MarkerKind::Rest(_)) => true,
        _ => m == kind,
    };
    let m = track.markers.iter().rev().find(|m| same(m.kind))?;
    camera.project(m.at.p, viewport).map(|v| (v.x, v.y))
}
