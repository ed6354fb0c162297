//! Running a window again, and saying where a failed check's runs part: the stage hashes, the
//! re-run of a window, and the search a failed check makes.
//!
//! A stage hash covers everything a stage can change: the canonical state hash
//! ([`crate::state_hash`]: tick, generator, every body's id, position, momentum, mass and
//! radius) and what it leaves out (force evaluations, energy bounds, launches, the carried
//! force, integrator, force toggles, launcher, divergence).
//!
//! When a check fails without stage hashes, the failing window is searched from its oldest
//! state still held: the restore is done again and compared with the saved state, then each
//! tick's step is run twice more from the first run's state before it, stage by stage and
//! hashed, once as the first run ran (the caller's threads) and once as the re-runs ran (their
//! threads, [`super::SyncTest::with_rerun_threads`]). The first tick where those two runs
//! part, or where both part from the first run, is reported with its stages and fields.

use xxhash_rust::xxh3::Xxh3;

use crate::body::COLUMNS;
use crate::command::Command;
use crate::forces::ForceKind;
use crate::hash::{canonical_bits, state_hash};
use crate::integrate::Integrator;
use crate::replay::diff::diff;
use crate::step::{Stage, StageBuffers};
use crate::world::{Divergence, DivergenceCause, State, World};

use super::report::{FoundBy, StageHashes, SyncMismatch};
use super::ring::{self, Frame};
use super::{StageHook, SyncTest};

/// The hash of everything a stage of a tick can change (see the module doc).
pub(super) fn stage_hash(world: &World) -> u64 {
    let mut h = Xxh3::new();
    let s = world.state();
    let mut word = |x: u64| h.update(&x.to_le_bytes());
    word(state_hash(world));
    word(s.force_evals);
    word(s.next_id);
    word(
        Integrator::ALL
            .iter()
            .position(|&i| i == s.integrator)
            .unwrap_or(usize::MAX) as u64,
    );
    word(
        ForceKind::ALL
            .iter()
            .fold(0, |m, &k| (m << 1) | u64::from(s.forces.has(k))),
    );
    let l = &s.launcher;
    let launcher = [
        l.position.x,
        l.position.y,
        l.position.z,
        l.speed,
        l.elevation_deg,
        l.azimuth_deg,
        l.mass,
        l.radius,
        l.backspin,
        l.sidespin,
    ];
    for x in launcher {
        word(canonical_bits(x));
    }
    match world.divergence() {
        None => word(0),
        Some(Divergence { tick, body, cause }) => {
            word(1);
            word(tick);
            word(body.0);
            if let DivergenceCause::EnergyGrowth { energy, bound } = cause {
                word(canonical_bits(energy));
                word(canonical_bits(bound));
            }
        }
    }
    // The columns the state hash leaves out: energy bounds and launches.
    for column in &COLUMNS[crate::body::HASHED_COLUMNS..] {
        for &x in column.get(&s.bodies) {
            word(canonical_bits(x));
        }
    }
    let carried = world.carries_force();
    word(u64::from(carried));
    if carried {
        for v in [&s.carry.x, &s.carry.y, &s.carry.z] {
            for &x in v {
                word(canonical_bits(x));
            }
        }
    }
    h.digest()
}

/// What stopped a re-run before its end.
#[derive(Clone, Debug)]
pub(super) enum Early {
    /// A command the first run applied failed in the re-run.
    Command {
        tick: u64,
        command: Command,
        error: Box<str>,
    },
    /// The re-run diverged at `tick`, before the first run did.
    Diverged { tick: u64, divergence: Divergence },
    /// With stage hashes: a stage's hash differs at the step to `tick`; the re-run stopped at
    /// the end of that step (or right after the restore, for [`Stage::Restore`]).
    Stage {
        tick: u64,
        first: Vec<(Stage, u64)>,
        rerun: Vec<(Stage, u64)>,
    },
}

/// Applies `commands`, then runs the step stage by stage, logging each stage's hash (after the
/// hook, if there is one, has seen the world).
pub(super) fn run_staged(
    world: &mut World,
    commands: &[Command],
    buffers: &mut StageBuffers,
    mut hook: Option<&mut StageHook>,
    log: &mut Vec<(Stage, u64)>,
) -> Result<(), Early> {
    let tick = world.tick();
    for command in commands {
        world.apply(command).map_err(|e| Early::Command {
            tick,
            command: *command,
            error: e.to_string().into(),
        })?;
    }
    let mut each = |stage: Stage, w: &mut World| {
        if let Some(hook) = hook.as_mut() {
            hook(stage, w);
        }
        log.push((stage, stage_hash(w)));
    };
    each(Stage::Commands, world);
    let _ = world.step_staged(buffers, &mut each);
    Ok(())
}

/// The index of the first entry where two logs of stage hashes differ (a stage missing on
/// one side counts).
fn first_difference(a: &[(Stage, u64)], b: &[(Stage, u64)]) -> Option<usize> {
    (0..a.len().max(b.len())).find(|&i| a.get(i) != b.get(i))
}

/// A re-run of a check's window, borrowing what it needs from the sync test.
pub(super) struct Rerun<'a> {
    pub(super) world: &'a mut World,
    pub(super) frames: &'a std::collections::VecDeque<Box<Frame>>,
    pub(super) first_commands: &'a [Command],
    pub(super) first_stages: &'a [(Stage, u64)],
    pub(super) first_hash: u64,
    pub(super) staged: bool,
    /// Whether the first run applied commands at some tick of the window.
    pub(super) commands: bool,
    pub(super) hook: Option<&'a mut StageHook>,
    pub(super) buffers: &'a mut StageBuffers,
    pub(super) log: &'a mut Vec<(Stage, u64)>,
}

impl Rerun<'_> {
    /// Runs ticks `from..end` from the restored world; `None` when it ran through.
    pub(super) fn run(&mut self, from: u64, end: u64) -> Option<Early> {
        if self.staged {
            if let Some(hook) = self.hook.as_mut() {
                hook(Stage::Restore, self.world);
            }
            let h = stage_hash(self.world);
            if h != self.first_hash {
                return Some(Early::Stage {
                    tick: from,
                    first: vec![(Stage::Restore, self.first_hash)],
                    rerun: vec![(Stage::Restore, h)],
                });
            }
        }
        if !self.staged && !self.commands {
            // Nothing but steps: the loop a check runs almost every tick.
            for j in from..end {
                let _ = self.world.step();
                if let Some(e) = early_divergence(self.world, j, end) {
                    return Some(e);
                }
            }
            return None;
        }
        for j in from..end {
            let (commands, expected) = if j == from {
                (self.first_commands, self.first_stages)
            } else {
                let f = &self.frames[(j - self.frames[0].tick) as usize];
                (f.commands.as_slice(), f.stages.as_slice())
            };
            if self.staged {
                self.log.clear();
                let hook = self.hook.as_deref_mut();
                if let Err(e) = run_staged(self.world, commands, self.buffers, hook, self.log) {
                    return Some(e);
                }
                if first_difference(expected, self.log).is_some() {
                    return Some(Early::Stage {
                        tick: j + 1,
                        first: expected.to_vec(),
                        rerun: self.log.clone(),
                    });
                }
            } else {
                for command in commands {
                    if let Err(e) = self.world.apply(command) {
                        return Some(Early::Command {
                            tick: j,
                            command: *command,
                            error: e.to_string().into(),
                        });
                    }
                }
                let _ = self.world.step();
            }
            if let Some(e) = early_divergence(self.world, j, end) {
                return Some(e);
            }
        }
        None
    }
}

/// What stops a re-run after its tick `j`: a divergence, unless `j` is the window's last tick
/// (`end - 1`), whose state (divergence included) the check compares with the first run's.
fn early_divergence(world: &World, j: u64, end: u64) -> Option<Early> {
    world
        .divergence()
        .filter(|_| j + 1 < end)
        .map(|d| Early::Diverged {
            tick: j + 1,
            divergence: d,
        })
}

/// Which of the two runs a search runs: as the first run ran, or as the re-runs ran.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    First,
    Rerun,
}

/// Where a failed check's runs part: the tick, the stage, the fields.
pub(super) fn locate(
    sync: &mut SyncTest,
    from: u64,
    end: u64,
    early: Option<Early>,
) -> SyncMismatch {
    let rerun_end = sync.world.snapshot();
    let mut m = SyncMismatch {
        tick: end,
        checked: end,
        restored_from: from,
        check_distance: sync.distance as u32,
        substeps: sync.world.substeps(),
        stage: None,
        stages: Vec::new(),
        found_by: FoundBy::NotReproduced,
        fields: Vec::new(),
        note: None,
    };
    let first_at = |sync: &SyncTest, tick: u64| {
        let mut s = sync.world.snapshot();
        let f = &sync.frames[(tick - sync.frames[0].tick) as usize];
        ring::full_state(f, &sync.epochs, &mut s);
        s
    };
    match early {
        Some(Early::Stage { tick, first, rerun }) => {
            m.tick = tick;
            m.found_by = FoundBy::StageHashes;
            set_stages(&mut m, &first, &rerun);
            let held = tick >= sync.frames[0].tick;
            if held {
                m.fields = diff(&first_at(sync, tick), &rerun_end);
            }
            return m;
        }
        Some(Early::Command {
            tick,
            command,
            error,
        }) => {
            m.tick = tick;
            m.stage = Some(StageHashes::unhashed(Stage::Commands));
            m.found_by = FoundBy::ReRun;
            m.note = Some(format!(
                "the re-run could not apply `{tick}: {command}`, which the first run applied: \
                 {error}"
            ));
            return m;
        }
        Some(Early::Diverged { tick, divergence }) => {
            m.tick = tick;
            m.found_by = FoundBy::ReRun;
            m.note = Some(format!(
                "the re-run {divergence}; the first run went on past tick {tick}"
            ));
            if tick >= sync.frames[0].tick {
                m.fields = diff(&first_at(sync, tick), &rerun_end);
            }
            return m;
        }
        None => {}
    }
    m.fields = diff(&first_at(sync, end), &rerun_end);
    search(sync, end, &mut m);
    m
}

fn set_stages(m: &mut SyncMismatch, first: &[(Stage, u64)], rerun: &[(Stage, u64)]) {
    m.stages = first
        .iter()
        .zip(rerun)
        .map(|(&(stage, a), &(_, b))| StageHashes {
            stage,
            first: Some(a),
            rerun: Some(b),
        })
        .collect();
    let at = first_difference(first, rerun);
    m.stage = at.map(|i| match (first.get(i), rerun.get(i)) {
        (Some(&(stage, a)), Some(&(_, b))) => StageHashes {
            stage,
            first: Some(a),
            rerun: Some(b),
        },
        (Some(&(stage, a)), None) => StageHashes {
            stage,
            first: Some(a),
            rerun: None,
        },
        (_, Some(&(stage, b))) => StageHashes {
            stage,
            first: None,
            rerun: Some(b),
        },
        (None, None) => unreachable!("a difference is at an index one side has"),
    });
}

/// The search of a failed check's window without stage hashes (see the module doc).
fn search(sync: &mut SyncTest, end: u64, m: &mut SyncMismatch) {
    let first_held = sync.frames[0].tick;
    if first_held >= end {
        return;
    }
    let template = sync.world.clone();
    let full = |sync: &SyncTest, tick: u64| {
        let mut s = template.snapshot();
        let f = &sync.frames[(tick - first_held) as usize];
        ring::full_state(f, &sync.epochs, &mut s);
        s
    };
    // The restore, as the sync test restores.
    let saved = full(sync, first_held);
    let mut restored = template.clone();
    let restore_error = match sync.restore.as_mut() {
        Some(restore) => restore(&mut restored, &saved).err(),
        None => {
            ring::load_copy(&mut restored, &sync.frames[0], &sync.epochs, u64::MAX);
            None
        }
    };
    let fields = diff(&saved, &restored.snapshot());
    if restore_error.is_some() || !fields.is_empty() {
        m.tick = first_held;
        m.stage = Some(StageHashes::unhashed(Stage::Restore));
        m.found_by = FoundBy::ReExecuted;
        m.fields = fields;
        m.note = restore_error.map(|e| format!("the restore refused the saved state: {e}"));
        return;
    }
    // Each tick's step, twice: as the first run ran it and as the re-runs ran it.
    for j in first_held..end {
        let before = full(sync, j);
        let after = full(sync, j + 1);
        let commands = sync.frames[(j - first_held) as usize].commands.clone();
        let (a_end, a_log) = run_once(sync, &template, &before, &commands, Side::First);
        let (b_end, b_log) = run_once(sync, &template, &before, &commands, Side::Rerun);
        if first_difference(&a_log, &b_log).is_some() {
            m.tick = j + 1;
            m.found_by = FoundBy::ReExecuted;
            set_stages(m, &a_log, &b_log);
            m.fields = diff(&after, &b_end);
            if m.fields.is_empty() {
                m.fields = diff(&a_end, &b_end);
            }
            return;
        }
        let fields = diff(&after, &a_end);
        if !fields.is_empty() {
            m.tick = j + 1;
            m.found_by = FoundBy::FirstRunAlone;
            set_stages(m, &a_log, &b_log);
            m.stage = None;
            m.fields = fields;
            return;
        }
    }
}

/// One more run of a tick from `before` with `commands`, stage by stage, on `side`'s threads.
fn run_once(
    sync: &mut SyncTest,
    template: &World,
    before: &State,
    commands: &[Command],
    side: Side,
) -> (State, Vec<(Stage, u64)>) {
    let mut world = template.clone();
    let mut log = Vec::new();
    let mut buffers = StageBuffers::default();
    if world.restore(before).is_err() {
        return (world.snapshot(), log);
    }
    let mut go = |world: &mut World| {
        let _ = run_staged(world, commands, &mut buffers, None, &mut log);
    };
    match (&sync.rerun, side) {
        (Some(r), Side::Rerun) => {
            world.set_threads(r.threads);
            r.pool.install(|| go(&mut world));
        }
        _ => go(&mut world),
    }
    (world.snapshot(), log)
}
