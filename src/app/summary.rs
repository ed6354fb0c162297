//! What a window run leaves behind: the closing summary the command line prints (frames,
//! timings, recordings, the replay's verdict) and each lane as the window closed, for tests and
//! scripted demos.

use super::{App, panel, session};
use crate::integrate::Integrator;

/// What a window run drew, for a closing summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunSummary {
    /// Frames presented.
    pub frames: u64,
    /// The adapter, as [`crate::render::Gpu::describe`] gives it.
    pub adapter: String,
    /// Median time between frames (ms), over the frames of a run with a frame limit (empty
    /// otherwise, to keep a long session's memory flat).
    pub interval_ms: Option<f64>,
    /// Median time spent on a frame (ms): stepping, the panel, drawing, presenting.
    pub work_ms: Option<f64>,
    /// Median CPU time of the UI in a frame (ms): the panel and plots laid out and tessellated.
    pub ui_ms: Option<f64>,
    /// Median number of triangles egui's meshes had in a frame: what a software rasteriser
    /// pays for the panel and plots (besides their area), counted, so it does not vary with the
    /// machine's load.
    pub ui_triangles: Option<usize>,
    /// The recordings made in the window, oldest first (the last one ended when it closed).
    pub recordings: Vec<session::recording::FinishedRecording>,
    /// Where the last replay stood when it ended or the window closed.
    pub replay: Option<session::replaying::ReplayVerdict>,
    /// Each lane as the window closed: for tests and scripted demos.
    pub lanes: Vec<LaneReport>,
    /// What the probe read when the window closed, if it was on something.
    pub probe: Option<Vec<String>>,
    /// The loop as the window closed: policy, draw mode, frames, cadence, swings and the
    /// measured body's display error ([`session::pacing`]).
    pub pacing: String,
    /// The panel's "Forces" lines as the window closed, an inactive term marked `(off)`.
    pub forces: Vec<String>,
}

/// A lane as the window closed.
#[derive(Clone, Debug, PartialEq)]
pub struct LaneReport {
    /// The lane's integrator.
    pub integrator: Integrator,
    /// Its tick.
    pub tick: u64,
    /// Its bodies.
    pub bodies: usize,
    /// Each body's closest pass by each target.
    pub passes: Vec<crate::render::history::Pass>,
    /// Its last aim.
    pub aim: Option<session::AimNote>,
    /// Its launcher.
    pub launcher: crate::scene::Launcher,
    /// Its dt (s) and substeps.
    pub dt: f64,
    /// Its integrator steps per tick.
    pub substeps: u32,
    /// Its force evaluations per simulated second so far.
    pub evals_per_second: f64,
    /// The targets' centres now.
    pub targets: Vec<glam::DVec3>,
}

impl std::fmt::Display for LaneReport {
    /// `lane NAME: tick N, B bodies`, then a line per pass and the aim.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "lane {}: tick {}, {} bodies, dt {} s x{}, {:.1} force evaluations per sim second",
            self.integrator.name(),
            self.tick,
            self.bodies,
            self.dt,
            self.substeps,
            self.evals_per_second
        )?;
        let l = &self.launcher;
        write!(
            f,
            "\n  launcher at ({:.4}, {:.4}, {:.4}), speed {:.4} m/s, elevation {:.4} deg, azimuth \
             {:.4} deg",
            l.position.x, l.position.y, l.position.z, l.speed, l.elevation_deg, l.azimuth_deg
        )?;
        for (i, c) in self.targets.iter().enumerate() {
            write!(f, "\n  target {i} at ({:.4}, {:.4}, {:.4})", c.x, c.y, c.z)?;
        }
        if let Some(note) = &self.aim {
            match &note.outcome {
                Ok(s) => write!(
                    f,
                    "\n  aim at target {} from tick {}: {} elevation {:.4} deg azimuth {:.4} deg \
                     speed {:.4} m/s{}",
                    note.target,
                    note.tick,
                    s.kind.label(),
                    s.elevation_deg,
                    s.azimuth_deg,
                    s.speed,
                    s.textbook.map_or(String::new(), |t| format!(
                        ", textbook misses by {:.4} m",
                        t.miss
                    ))
                )?,
                Err(why) => write!(f, "\n  aim at target {}: {why}", note.target)?,
            }
        }
        for p in &self.passes {
            write!(
                f,
                "\n  body {} passed target {} at {:e} m (t = {:.4} s){}",
                p.body,
                p.target,
                p.distance,
                p.time,
                if p.hit { ", hit" } else { "" }
            )?;
        }
        Ok(())
    }
}

impl App {
    /// The closing summary of this run.
    pub(super) fn summary(&self) -> RunSummary {
        let median = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied()
        };
        let timings = &self.timing.timings;
        RunSummary {
            frames: self.timing.stats.frames,
            adapter: self.timing.stats.adapter.clone(),
            // The first interval includes opening the window and the device.
            interval_ms: median(&mut timings.iter().skip(1).map(|t| t.0).collect()),
            work_ms: median(&mut timings.iter().map(|t| t.1).collect()),
            ui_ms: median(&mut timings.iter().map(|t| t.2).collect()),
            ui_triangles: median(&mut timings.iter().map(|t| t.3 as f64).collect())
                .map(|t| t as usize),
            recordings: self.session.recordings().to_vec(),
            replay: self.session.replay_verdict(),
            probe: self.ui.probe.as_ref().map(|p| p.lines()),
            pacing: self.pacing_line(),
            forces: {
                let world = self.session.world();
                panel::forces::lines(&world.params().declared, world.forces(), world.launcher())
                    .into_iter()
                    .map(|(line, on)| if on { line } else { format!("{line} (off)") })
                    .collect()
            },
            lanes: self
                .session
                .lanes()
                .iter()
                .map(|l| LaneReport {
                    integrator: l.sim.world.integrator(),
                    tick: l.sim.world.tick(),
                    bodies: l.sim.world.bodies().len(),
                    passes: l.history.passes.all().to_vec(),
                    aim: l.aim.clone(),
                    launcher: *l.sim.world.launcher(),
                    dt: l.sim.world.dt(),
                    substeps: l.sim.world.substeps(),
                    evals_per_second: l.evals_per_second().unwrap_or(0.0),
                    targets: {
                        let w = &l.sim.world;
                        let since = w.tick() as f64 * w.dt();
                        w.contacts()
                            .targets
                            .iter()
                            .map(|t| t.center_at(since))
                            .collect()
                    },
                })
                .collect(),
        }
    }

    /// The closing summary's pacing line.
    fn pacing_line(&self) -> String {
        let s = &self.session;
        let log = s.pacing();
        let mode = s.draw_mode();
        let when = if log.display_times {
            "at display time"
        } else {
            "at the frames' samples"
        };
        let error = match (log.median_error(mode, f64::INFINITY), &log.note) {
            (Some(e), _) => format!("median display error {:.4} mm {when}", e * 1e3),
            (None, Some(why)) => format!("no display error: {why}"),
            (None, None) => "no display error".into(),
        };
        let inside = log.inside();
        format!(
            "pacing: {} + {} on {}, body {}, ticks/frame {}, 0-2 swings {}, {error}, inside a \
             surface {} of {} frames (deepest {:.1} mm)",
            s.policy().name(),
            mode.name(),
            self.ui.panel.frames_note,
            log.body,
            log.cadence(),
            log.swings(),
            inside.frames,
            inside.of,
            inside.deepest * 1e3,
        )
    }
}
