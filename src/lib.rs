//! # Volley
//!
//! The sandbox around the simulation: the window ([`app`]), the wgpu renderer ([`render`]) and
//! the study's work-precision plot ([`plot`]). Everything that steps, records and measures lives
//! in the `volley-sim` crate, which has no GPU, window, plotting or CLI crate in its dependency
//! tree; its names are re-exported here, so `volley::World` and `volley_sim::World` are one type
//! (and `volley::world::World` is `volley_sim::internals::world::World`).

// The simulation, named rather than globbed: its game-facing surface as the crate root has it,
// and the (hidden) modules the window, the CLI, the tests and the benches reach into.
pub use volley_lab::{pacing, stability, study, table};
pub use volley_sim::internals::{
    atmosphere, body, clock, command, contact, drag, draw, exact, firing, forces, hash, integrate,
    replay, rng, scene, sim_loop, simd, step, timeline, world,
};
pub use volley_sim::{
    AimMode, AimRange, Atmosphere, Bodies, BodyId, BodySpec, BodyState, ClockError, Command,
    CommandError, CommandParseError, DEFAULT_DRAW, DEFAULT_POLICY, Detection, Divergence,
    DragTable, Draw, DrawMode, Event, EventKind, FiringError, FirstDivergence, FixedClock,
    ForceKind, Forces, FrameSource, FrameTicks, Ground, Guard, Integrator, Launcher, LoopError,
    LoopPolicy, MachDrag, ObserverError, PointMass, RealClock, RecordOptions, Recorder, Recording,
    Replay, Scene, SceneBuilder, SceneError, ScriptError, Shot, SimLoop, Spring, Stamped, Surface,
    Target, TickObserver, Timeline, VirtualClock, Volley, Wall, World, bundled_scene, load_scene,
    parse_scene, parse_scene_with, parse_script, solve_aim, state_hash,
};

/// The one line for a scene argument that names neither a file nor a bundled scene: the
/// command line's, and the browser page's for `?scene=`.
pub fn no_such_scene(arg: &str) -> String {
    format!("no scene file `{arg}` and no bundled scene of that name (see `volley scenes`)")
}

pub mod app;
pub mod palette;
pub mod platform;
pub mod plot;
pub mod render;
