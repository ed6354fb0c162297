//! The state table sink: the seed's columns per body, as an aligned table, CSV or JSON lines.
//!
//! Columns: tick, body id, t (s), p (m), mV (kg m/s), F (N, the net force at that state), V
//! (m/s). Rows stream out as ticks complete, so a run stopped by a divergence or an error keeps
//! every row before it. CSV and JSON carry full precision (each float in the shortest form that
//! reads back to the same bits); the aligned table rounds to `precision` decimals. Events and the
//! summary follow the same format: `event ...` lines in the table, `# event ...` comment lines in
//! CSV, `{"event": ...}` objects in JSON.

use std::io::Write;

use volley_sim::internals::contact::{Event, EventKind, EventSpec};
use volley_sim::internals::sim_loop::{ObserverError, TickObserver};
use volley_sim::internals::world::World;

/// Output format of the state table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Aligned columns for reading.
    Table,
    /// Comma-separated values with a header.
    Csv,
    /// One JSON object per line.
    Json,
}

impl Format {
    /// Every format with its command-line name, in the order `--help` lists them.
    pub const ALL: [(Format, &'static str); 3] = [
        (Format::Table, "table"),
        (Format::Csv, "csv"),
        (Format::Json, "json"),
    ];

    /// The command-line name (`table`, `csv`, `json`).
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(f, _)| *f == self)
            .map_or("table", |(_, n)| n)
    }

    /// The format of a command-line name, if it is one.
    pub fn from_name(name: &str) -> Option<Format> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(f, _)| *f)
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The end-of-run line: what ran and the state hash.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Summary {
    /// Ticks stepped.
    pub ticks: u64,
    /// Sim time (s) at the last tick.
    pub time: f64,
    /// Canonical state hash at the last tick, as `0x` + 16 hex digits.
    pub hash: String,
    /// Bodies alive.
    pub bodies: usize,
    /// Integrator at the end.
    pub integrator: String,
    /// Timestep (s).
    pub dt: f64,
    /// Force evaluations.
    pub force_evals: u64,
}

impl Summary {
    /// The summary of a world as it is now.
    pub fn of(world: &World) -> Summary {
        Summary {
            ticks: world.tick(),
            time: world.time(),
            hash: volley_sim::internals::hash::hex(volley_sim::internals::hash::state_hash(world)),
            bodies: world.bodies().len(),
            integrator: world.integrator().name().to_string(),
            dt: world.dt(),
            force_evals: world.force_evals(),
        }
    }
}

/// Writes rows every `every` ticks, plus events as they happen.
pub struct TableWriter<W: Write> {
    out: W,
    format: Format,
    every: u64,
    precision: usize,
    rows: bool,
}

const COLUMNS: [&str; 15] = [
    "tick", "body", "t", "p_x", "p_y", "p_z", "mV_x", "mV_y", "mV_z", "F_x", "F_y", "F_z", "V_x",
    "V_y", "V_z",
];

fn io(e: std::io::Error) -> ObserverError {
    ObserverError(format!("cannot write the table: {e}"))
}

impl<W: Write> TableWriter<W> {
    /// A writer; `every` is clamped to at least 1; `rows: false` writes events and the summary
    /// only.
    pub fn new(out: W, format: Format, every: u64, precision: usize, rows: bool) -> Self {
        TableWriter {
            out,
            format,
            every: every.max(1),
            precision,
            rows,
        }
    }

    /// The header (table and CSV formats).
    pub fn header(&mut self) -> Result<(), ObserverError> {
        if !self.rows {
            return Ok(());
        }
        match self.format {
            Format::Table => {
                let w = self.width();
                let mut line = format!("{:>6} {:>5}", COLUMNS[0], COLUMNS[1]);
                for c in &COLUMNS[2..] {
                    line += &format!(" {c:>w$}");
                }
                writeln!(self.out, "{line}").map_err(io)
            }
            Format::Csv => writeln!(self.out, "{}", COLUMNS.join(",")).map_err(io),
            Format::Json => Ok(()),
        }
    }

    fn width(&self) -> usize {
        (self.precision + 7).max(9)
    }

    /// One row per body for the world's current tick.
    pub fn rows(&mut self, world: &World) -> Result<(), ObserverError> {
        let b = world.bodies();
        for i in 0..b.len() {
            let (p, mv) = (b.positions().get(i), b.momenta().get(i));
            let (f, v) = (world.force_on(i), world.velocity(i));
            let (tick, id, t) = (world.tick(), b.ids()[i].0, world.time());
            let line = match self.format {
                Format::Table => {
                    let (w, d) = (self.width(), self.precision);
                    let mut line = format!("{tick:>6} {id:>5} {t:>w$.d$}");
                    for x in [p, mv, f, v].iter().flat_map(|v| v.to_array()) {
                        line += &format!(" {x:>w$.d$}");
                    }
                    line
                }
                Format::Csv => {
                    let mut line = format!("{tick},{id},{t}");
                    for x in [p, mv, f, v].iter().flat_map(|v| v.to_array()) {
                        line += &format!(",{x}");
                    }
                    line
                }
                Format::Json => serde_json::json!({
                    "tick": tick, "body": id, "t": t,
                    "p": p.to_array(), "mV": mv.to_array(), "F": f.to_array(), "V": v.to_array(),
                })
                .to_string(),
            };
            writeln!(self.out, "{line}").map_err(io)?;
        }
        Ok(())
    }

    /// The events of the world's last tick.
    pub fn events(&mut self, events: &[Event]) -> Result<(), ObserverError> {
        self.events_of(events, &[])
    }

    /// The events of the world's last tick, declared ones named from `specs` (the scene's
    /// events).
    pub fn events_of(
        &mut self,
        events: &[Event],
        specs: &[EventSpec],
    ) -> Result<(), ObserverError> {
        for e in events {
            let line = match self.format {
                Format::Table => format!("event {}", describe_in(e, specs)),
                Format::Csv => format!("# event {}", describe_in(e, specs)),
                Format::Json => match (e.kind, specs.get(declared_index(e))) {
                    (EventKind::Declared { .. }, Some(spec)) => {
                        serde_json::json!({ "event": e, "name": spec.label() }).to_string()
                    }
                    _ => serde_json::json!({ "event": e }).to_string(),
                },
            };
            writeln!(self.out, "{line}").map_err(io)?;
        }
        Ok(())
    }

    /// [`TickObserver::after_tick`]'s writes: the events, then the row if `row`.
    #[cold]
    #[inline(never)]
    fn write_tick(&mut self, world: &World, row: bool) -> Result<(), ObserverError> {
        self.events_of(world.events(), world.declared_events().specs())?;
        if row {
            self.rows(world)?;
        }
        Ok(())
    }

    /// The summary line.
    pub fn summary(&mut self, s: &Summary) -> Result<(), ObserverError> {
        let text = format!(
            "summary: ticks={} time={} s hash={} bodies={} integrator={} dt={} s force_evals={}",
            s.ticks, s.time, s.hash, s.bodies, s.integrator, s.dt, s.force_evals
        );
        let line = match self.format {
            Format::Table => text,
            Format::Csv => format!("# {text}"),
            Format::Json => serde_json::json!({ "summary": s }).to_string(),
        };
        writeln!(self.out, "{line}").map_err(io)?;
        self.out.flush().map_err(io)
    }

    /// Flushes the output.
    pub fn flush(&mut self) -> Result<(), ObserverError> {
        self.out.flush().map_err(io)
    }
}

impl<W: Write> TickObserver for TableWriter<W> {
    /// Every tick: the tick's events, if it had any, and a row every `every` ticks. The writes
    /// are out of line (`TableWriter::write_tick`), so a tick with neither costs two tests.
    #[inline]
    fn after_tick(&mut self, world: &World) -> Result<(), ObserverError> {
        let row = self.rows && world.tick().is_multiple_of(self.every);
        if row || !world.events().is_empty() {
            self.write_tick(world, row)?;
        }
        Ok(())
    }

    /// The next row's tick; none without rows (events come only from contacts and declared
    /// events, and the loop steps worlds with either tick by tick).
    fn next_needed_tick(&self, tick: u64) -> u64 {
        if self.rows {
            volley_sim::internals::sim_loop::next_multiple(tick, self.every)
        } else {
            u64::MAX
        }
    }
}

/// The index of a declared event's declaration (past every index otherwise).
fn declared_index(e: &Event) -> usize {
    match e.kind {
        EventKind::Declared { event, .. } => event as usize,
        _ => usize::MAX,
    }
}

/// One line describing an event, for people; a declared event named by its declaration in
/// `specs` (the scene's events), by its index without it.
pub fn describe_in(e: &Event, specs: &[EventSpec]) -> String {
    if let EventKind::Declared {
        event,
        direction,
        graze,
        state,
    } = e.kind
    {
        let head = format!("tick {} t={:.9} s body {}", e.tick, e.time, e.body);
        let name = specs
            .get(event as usize)
            .map_or_else(|| format!("event {event}"), EventSpec::label);
        let (p, mv) = (state.p, state.mv);
        return format!(
            "{head}: {name} {}{} at p=({:.6}, {:.6}, {:.6}) m, mV=({:.6}, {:.6}, {:.6}) kg m/s",
            direction.name(),
            if graze { " (graze)" } else { "" },
            p.x,
            p.y,
            p.z,
            mv.x,
            mv.y,
            mv.z
        );
    }
    describe(e)
}

/// One line describing an event, for people.
pub fn describe(e: &Event) -> String {
    let head = format!("tick {} t={:.9} s body {}", e.tick, e.time, e.body);
    match e.kind {
        EventKind::Impact {
            surface,
            normal_speed,
            depth,
        } => {
            let on = surface.to_string();
            format!("{head}: impact on {on} at {normal_speed:.6} m/s, penetration {depth:.6} m")
        }
        EventKind::Rest { surface } => format!("{head}: came to rest on {surface}"),
        EventKind::Hit { target } => format!("{head}: HIT target {target}"),
        EventKind::Approach {
            target,
            distance,
            hit,
        } => format!(
            "{head}: closest approach to target {target}: {distance:.6} m{}",
            if hit { " (hit)" } else { " (miss)" }
        ),
        EventKind::Declared { .. } => describe_in(e, &[]),
    }
}
