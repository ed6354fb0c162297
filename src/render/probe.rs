//! What the probe reads and the markers show, for the first [`PROBE_BODIES`] bodies of a lane.
//!
//! Each such body keeps its last [`TRACK_SAMPLES`] ticks (tick, position, velocity: the trail
//! with the state behind it) and its markers, PhET's dots: every 0.1 s and every 1 s of sim time
//! since it spawned, at the apex (where the vertical velocity changes sign from up to down) and
//! at each impact, and at each of the scene's declared events. A marker between two ticks sits where the straight segment between them is at
//! the marker's time (the apex: where the vertical velocity, linear between the ticks, is 0), so
//! the dots lie on the drawn trail. An impact marker is at the contact's own time, back from the
//! tick's end along the velocity after the bounce. A declared event's marker is the event's own
//! time and state (found on the integrator's path inside the step, docs/physics.md "Declared
//! events"), so it can sit a little off the straight trail between two ticks. A body keeps its
//! last [`MARKERS`] markers.
//!
//! The probe ([`Probe`]) is what is read at a picked sample or marker: tick, sim time, p, V,
//! |V|, the energy and the error against the body's closed-form reference there.

use std::collections::VecDeque;

use glam::DVec3;

use crate::contact::{EventKind, Surface};
use crate::forces::ForceModel;
use crate::world::{BodyId, World};

/// Bodies with markers and probe samples (the first ones in id order).
pub const PROBE_BODIES: usize = 16;
/// Ticks of state kept per body for the probe.
pub const TRACK_SAMPLES: usize = 128;
/// Markers kept per body.
pub const MARKERS: usize = 512;
/// Interval of the small markers (s of sim time).
pub const TENTH: f64 = 0.1;

/// What a marker marks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkerKind {
    /// A multiple of 0.1 s since spawn.
    Tenth,
    /// A whole second since spawn.
    Second,
    /// The top of the arc.
    Apex,
    /// A bounce, on the surface it names.
    Impact(Surface),
    /// A contact that ended the bounce (the contact stage's rest event: the bounce fell below
    /// one step of gravity's speed, as it does at any speed on a surface of restitution 0), on
    /// the surface it names.
    Rest(Surface),
    /// A declared event of the scene: its index in the scene's events.
    Declared(u32),
}

/// A point of a body's path with its state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// The tick (for a marker between ticks, the one after it).
    pub tick: u64,
    /// Sim time (s).
    pub t: f64,
    /// Position (m).
    pub p: DVec3,
    /// Velocity (m/s).
    pub v: DVec3,
}

/// A marker: its kind and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marker {
    /// What it marks.
    pub kind: MarkerKind,
    /// Where and when.
    pub at: Sample,
}

/// One body's recent samples and markers.
#[derive(Clone, Debug)]
pub struct Track {
    /// The body.
    pub id: BodyId,
    /// Mass (kg), for the energy.
    pub mass: f64,
    /// Sim time it was first seen (s).
    pub spawn_time: f64,
    /// The last ticks, oldest first.
    pub samples: VecDeque<Sample>,
    /// The markers, oldest first.
    pub markers: VecDeque<Marker>,
}

/// The tracks of a lane's first bodies.
#[derive(Clone, Debug, Default)]
pub struct ProbeHistory {
    tracks: Vec<Track>,
    last: Option<u64>,
}

fn lerp(a: DVec3, b: DVec3, f: f64) -> DVec3 {
    a + f * (b - a)
}

impl ProbeHistory {
    /// Takes a tick in (ticks already seen, replayed after a seek, are skipped). A body's
    /// track starts at its spawn as `references` recorded it (its state and time then).
    pub fn record(&mut self, world: &World, references: &crate::render::References) {
        let tick = world.tick();
        if self.last.is_some_and(|l| tick <= l) {
            return;
        }
        self.last = Some(tick);
        let bodies = world.bodies();
        let n = bodies.len().min(PROBE_BODIES);
        let ids = &bodies.ids()[..n];
        self.tracks.retain(|t| ids.contains(&t.id));
        let t = world.time();
        for (i, &id) in ids.iter().enumerate() {
            let now = Sample {
                tick,
                t,
                p: bodies.state(i).p,
                v: world.velocity(i),
            };
            let k = match self.tracks.binary_search_by_key(&id, |t| t.id) {
                Ok(k) => k,
                Err(k) => {
                    let mass = bodies.masses()[i];
                    let mut samples = VecDeque::with_capacity(TRACK_SAMPLES);
                    let spawn_time = match references.get(id) {
                        Some(r) if r.spawn_tick < tick => {
                            samples.push_back(Sample {
                                tick: r.spawn_tick,
                                t: r.spawn_time,
                                p: r.state.p,
                                v: r.state.mv / r.mass,
                            });
                            r.spawn_time
                        }
                        _ => t,
                    };
                    self.tracks.insert(
                        k,
                        Track {
                            id,
                            mass,
                            spawn_time,
                            samples,
                            markers: VecDeque::new(),
                        },
                    );
                    k
                }
            };
            let track = &mut self.tracks[k];
            if let Some(&before) = track.samples.back() {
                track.mark_between(before, now);
            }
            if track.samples.len() == TRACK_SAMPLES {
                track.samples.pop_front();
            }
            track.samples.push_back(now);
        }
        for e in world.events() {
            if let EventKind::Declared { event, state, .. } = e.kind
                && let Ok(k) = self.tracks.binary_search_by_key(&e.body, |t| t.id)
            {
                // The event's own state; the mass the body has now (a motor's changes).
                let mass = bodies
                    .index_of(e.body)
                    .map_or(self.tracks[k].mass, |i| bodies.masses()[i]);
                let at = Sample {
                    tick: e.tick,
                    t: e.time,
                    p: state.p,
                    v: state.mv / mass,
                };
                self.tracks[k].push(Marker {
                    kind: MarkerKind::Declared(event),
                    at,
                });
                continue;
            }
            let contact = match e.kind {
                EventKind::Impact { surface, .. } => Some(MarkerKind::Impact(surface)),
                EventKind::Rest { surface } => Some(MarkerKind::Rest(surface)),
                _ => None,
            };
            if let Some(kind) = contact
                && let Ok(k) = self.tracks.binary_search_by_key(&e.body, |t| t.id)
                && let Some(&end) = self.tracks[k].samples.back()
            {
                // At the contact's own time: back from the tick's end along the velocity after
                // it (gravity over the rest of the step is left out: under g h^2 / 2).
                let back = (end.t - e.time).max(0.0);
                let at = Sample {
                    t: e.time,
                    p: end.p - back * end.v,
                    ..end
                };
                self.tracks[k].push(Marker { kind, at });
            }
        }
    }

    /// Every track, by id.
    pub fn tracks(&self) -> &[Track] {
        &self.tracks
    }

    /// Forgets every sample after a seek (markers stay: they are where the run went).
    pub fn after_seek(&mut self) {
        for t in &mut self.tracks {
            t.samples.clear();
        }
    }
}

impl Track {
    fn push(&mut self, marker: Marker) {
        if self.markers.len() == MARKERS {
            self.markers.pop_front();
        }
        self.markers.push_back(marker);
    }

    /// The markers between two consecutive samples: the 0.1 s and 1 s marks passed, and the
    /// apex if the vertical velocity turned from up to down.
    fn mark_between(&mut self, a: Sample, b: Sample) {
        let span = b.t - a.t;
        if span <= 0.0 {
            return;
        }
        // Marks by whole tenths since spawn, counted in integers so no mark is skipped or
        // doubled by rounding: mark k is at spawn + k / 10 s.
        let tenths = |t: f64| ((t - self.spawn_time) / TENTH + 1e-9).floor() as i64;
        for k in tenths(a.t) + 1..=tenths(b.t) {
            let at_t = self.spawn_time + k as f64 * TENTH;
            let f = ((at_t - a.t) / span).clamp(0.0, 1.0);
            let kind = if k % 10 == 0 {
                MarkerKind::Second
            } else {
                MarkerKind::Tenth
            };
            self.push(Marker {
                kind,
                at: Sample {
                    tick: b.tick,
                    t: at_t,
                    p: lerp(a.p, b.p, f),
                    v: lerp(a.v, b.v, f),
                },
            });
        }
        if a.v.z > 0.0 && b.v.z <= 0.0 {
            let f = a.v.z / (a.v.z - b.v.z);
            self.push(Marker {
                kind: MarkerKind::Apex,
                at: Sample {
                    tick: b.tick,
                    t: a.t + f * span,
                    p: lerp(a.p, b.p, f),
                    v: lerp(a.v, b.v, f),
                },
            });
        }
    }
}

/// What the probe reads at a picked point of a lane's body.
#[derive(Clone, Debug, PartialEq)]
pub struct Probe {
    /// The lane's integrator name.
    pub lane: String,
    /// The body.
    pub body: BodyId,
    /// What was picked: "body", "trail", or a marker's kind.
    pub what: String,
    /// The state there.
    pub at: Sample,
    /// Mechanical energy there (J).
    pub energy: f64,
    /// Position error against the body's closed-form reference there (m), if it has one.
    pub error: Option<f64>,
    /// With a Mach drag declared: the Mach number (speed through the air over the speed of
    /// sound there) and the air's density (kg/m^3) there.
    pub air: Option<(f64, f64)>,
    /// With a spun Mach drag: the body's spin there (rpm), decayed since its launch.
    pub spin: Option<f64>,
    /// With a motor: its thrust (N) and the body's mass (kg) there.
    pub motor: Option<(f64, f64)>,
}

impl Probe {
    /// Reads `at` of `track` in `world`'s lane, with the reference from `references`.
    pub fn read(
        lane: &str,
        world: &World,
        track: &Track,
        what: &str,
        at: Sample,
        references: &crate::render::References,
    ) -> Probe {
        let energy = world.forces().energy(at.p, at.v, track.mass);
        let error = references.get(track.id).and_then(|r| {
            let since = at.t - r.spawn_time;
            r.ends_after(world.dt())
                .is_none_or(|end| since <= end)
                .then(|| r.exact_at(since))
                .flatten()
                .map(|exact| (at.p - exact.p).length())
        });
        let air = world
            .forces()
            .mach_drag
            .as_ref()
            .map(|d| (d.mach(at.p, at.v), d.air.at(at.p.z).0));
        let b = world.bodies();
        let launch = b.index_of(track.id).map(|i| b.launch(i));
        let spin =
            world.forces().spun_drag().zip(launch).map(|(d, l)| {
                d.spin_at(at.t, at.p, at.v, l).length() / crate::forces::RAD_S_PER_RPM
            });
        let motor = world.forces().thrust.as_ref().zip(launch).map(|(m, l)| {
            let age = at.t - l.time;
            (m.force(age, at.v).length(), m.mass_at(age, l.mass))
        });
        Probe {
            lane: lane.to_string(),
            body: track.id,
            what: what.to_string(),
            at,
            energy,
            error,
            air,
            spin,
            motor,
        }
    }

    /// The probe's lines, as the window shows them.
    pub fn lines(&self) -> Vec<String> {
        let a = &self.at;
        let mut out = vec![
            format!("{} body {} ({})", self.lane, self.body, self.what),
            format!("tick {}, t = {:.4} s", a.tick, a.t),
            format!("p = ({:.4}, {:.4}, {:.4}) m", a.p.x, a.p.y, a.p.z),
            format!(
                "V = ({:.4}, {:.4}, {:.4}) m/s, |V| = {:.4} m/s",
                a.v.x,
                a.v.y,
                a.v.z,
                a.v.length()
            ),
            format!("E = {:.6e} J", self.energy),
        ];
        out.push(match self.error {
            Some(e) => format!("|p - p_exact| = {e:.4e} m"),
            None => "no closed-form reference here".to_string(),
        });
        if let Some((mach, density)) = self.air {
            out.push(format!("Mach {mach:.3}, air {density:.4} kg/m^3"));
        }
        if let Some(rpm) = self.spin {
            out.push(format!("spin {rpm:.0} rpm"));
        }
        if let Some((thrust, mass)) = self.motor {
            out.push(format!("thrust {thrust:.3} N, mass {:.2} g", mass * 1e3));
        }
        out
    }
}
