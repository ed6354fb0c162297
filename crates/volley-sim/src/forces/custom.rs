//! A game's own force terms: the seam through which code outside Volley adds forces that the
//! built-in terms do not cover (a drag curve of its own, a thrust schedule, a homing pull).
//!
//! A game implements [`ForceTerm`] and hands its terms to Volley as values: in code, through
//! [`crate::SceneBuilder::custom`]; for scene files, saved setups and recordings, in a
//! [`ForceTerms`] list it passes to [`crate::parse_scene_with`], [`crate::load_scene_with`] and
//! [`crate::Recording::scene_with`]. A scene file declares each by name and version,
//! `Custom(name: "my-game/drag", version: 1)`, and the list resolves it; a name the list lacks,
//! or another version of it, is refused with one line naming both. There is no process-wide
//! registry: two worlds in one program may hold different terms of the same name, and a
//! replay finds exactly the terms its program passes in (the recording carries its scene text,
//! so it always names the terms it was made with).
//!
//! A scene may declare several terms; they are evaluated in the order declared, after every
//! built-in term but a motor's thrust.
//!
//! What Volley does with them:
//! - Every integrator steps them at each stage's own time, except two. `exact` has no closed
//!   form for them. Forest-Ruth solves velocity terms in closed form, so it takes only terms
//!   that do not read the velocity ([`Reads::velocity`] false). Implicit Euler and the
//!   implicit midpoint rule treat them explicitly.
//! - The energy guard checks only finiteness while one is declared: Volley cannot know whether
//!   a term adds energy (thrust does).
//! - The stability pre-check cannot see inside them and leaves them out; the study's reference
//!   is RK4 at a finer step (the extrapolation reference passes no clock).
//! - A world without one pays nothing: the list is empty, and the fast-path models (gravity
//!   alone, gravity with linear drag) never test for it.

use std::sync::Arc;

use glam::DVec3;

use crate::body::Launch;

/// What a term reads beside the time, the position and the mass: declared once, in
/// [`ForceTerm::reads`], and used everywhere Volley must know it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reads {
    /// Whether the force depends on the velocity [`ForceInput::v`]. Velocity Verlet takes its
    /// one-evaluation form and Forest-Ruth accepts the term only when it does not.
    pub velocity: bool,
    /// Whether the force reads the body's launch ([`ForceInput::launch`]: the world's time at
    /// its launch, its mass then, its spin). Only then do the steps load the bodies' launch
    /// columns, and only then is `launch` given: a term that did not say so sees `None`, never
    /// a launch of zeros.
    pub launch: bool,
}

impl Reads {
    /// Position and time only.
    pub const POSITION: Reads = Reads {
        velocity: false,
        launch: false,
    };
    /// Position, time and velocity: the default.
    pub const VELOCITY: Reads = Reads {
        velocity: true,
        launch: false,
    };
}

impl Default for Reads {
    fn default() -> Self {
        Reads::VELOCITY
    }
}

/// Everything a term is given at one evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceInput {
    /// The world's clock (s) at this stage of the step.
    pub t: f64,
    /// The body's position (m).
    pub p: DVec3,
    /// Its velocity (m/s).
    pub v: DVec3,
    /// Its mass (kg).
    pub m: f64,
    /// Its launch, if the term reads it ([`Reads::launch`]); `None` otherwise.
    pub launch: Option<Launch>,
}

/// A force a game computes itself. `Send + Sync`: a step may evaluate it on several threads
/// at once, so it must not mutate anything it reads (determinism: the same inputs, the same
/// bits).
pub trait ForceTerm: Send + Sync + std::fmt::Debug {
    /// The name scene files and recordings use for it, e.g. `my-game/drag`.
    fn name(&self) -> &str;
    /// Its version: change it whenever the force it computes changes, so a recording made
    /// with the old one is refused rather than replayed to other bits.
    fn version(&self) -> u32;
    /// What the force reads beside time, position and mass (default: the velocity, not the
    /// launch). The one place a term says so.
    fn reads(&self) -> Reads {
        Reads::default()
    }
    /// The force (N) on one body.
    fn force(&self, input: &ForceInput) -> DVec3;
}

/// A declared term: the shared term itself. Equal when it is the same term by name and
/// version.
#[derive(Clone, Debug)]
pub struct CustomForce(pub Arc<dyn ForceTerm>);

impl PartialEq for CustomForce {
    fn eq(&self, other: &Self) -> bool {
        self.0.name() == other.0.name() && self.0.version() == other.0.version()
    }
}

impl CustomForce {
    /// The term's force (N) at time `t` on a body of mass `w.m` at `p` moving at `v`, given
    /// its launch if it reads it.
    #[inline]
    pub(crate) fn force(&self, t: f64, p: DVec3, v: DVec3, w: crate::body::Mass) -> DVec3 {
        let launch = self.0.reads().launch.then_some(w.launch);
        self.0.force(&ForceInput {
            t,
            p,
            v,
            m: w.m,
            launch,
        })
    }

    /// The term's name.
    pub fn name(&self) -> &str {
        self.0.name()
    }

    /// The term's version.
    pub fn version(&self) -> u32 {
        self.0.version()
    }

    /// What it reads.
    pub fn reads(&self) -> Reads {
        self.0.reads()
    }
}

/// The game's terms a program can name in scene files and recordings, in the order added (a
/// list, not a map: nothing iterates a hash). Pass it to [`crate::parse_scene_with`],
/// [`crate::load_scene_with`] and [`crate::Recording::scene_with`].
///
/// ```
/// use glam::DVec3;
/// use volley_sim::{ForceInput, ForceTerm, ForceTerms, parse_scene_with};
///
/// #[derive(Debug)]
/// struct Push;
/// impl ForceTerm for Push {
///     fn name(&self) -> &str { "my-game/push" }
///     fn version(&self) -> u32 { 1 }
///     fn force(&self, i: &ForceInput) -> DVec3 { DVec3::new(i.m, 0.0, 0.0) }
/// }
///
/// let terms = ForceTerms::new().with(Push);
/// let text = "Scene(dt: 0.01, integrator: Rk4,
///                   forces: [Custom(name: \"my-game/push\", version: 1)])";
/// let scene = parse_scene_with(text, "push.ron", "push", &terms)?;
/// assert_eq!(scene.forces().custom[0].name(), "my-game/push");
/// // Without the term, the same text is refused by name.
/// let err = volley_sim::parse_scene(text, "push.ron", "push").unwrap_err();
/// assert!(err.to_string().contains("my-game/push"), "{err}");
/// # Ok::<(), volley_sim::SceneError>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct ForceTerms {
    list: Vec<Arc<dyn ForceTerm>>,
}

impl ForceTerms {
    /// No terms.
    pub fn new() -> ForceTerms {
        ForceTerms::default()
    }

    /// The list with `term` added.
    #[must_use]
    pub fn with(mut self, term: impl ForceTerm + 'static) -> ForceTerms {
        self.add(Arc::new(term));
        self
    }

    /// Adds a shared term. The same name and version again replaces the earlier one; another
    /// version of a name is kept beside it.
    pub fn add(&mut self, term: Arc<dyn ForceTerm>) {
        self.list
            .retain(|t| !(t.name() == term.name() && t.version() == term.version()));
        self.list.push(term);
    }

    /// The terms, in the order added.
    pub fn iter(&self) -> impl Iterator<Item = &Arc<dyn ForceTerm>> {
        self.list.iter()
    }

    /// Whether the list is empty.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The term `name` at `version`.
    pub fn resolve(&self, name: &str, version: u32) -> Result<CustomForce, CustomForceError> {
        if let Some(t) = self
            .list
            .iter()
            .find(|t| t.name() == name && t.version() == version)
        {
            return Ok(CustomForce(Arc::clone(t)));
        }
        let registered: Vec<u32> = self
            .list
            .iter()
            .filter(|t| t.name() == name)
            .map(|t| t.version())
            .collect();
        Err(if registered.is_empty() {
            CustomForceError::Unknown {
                name: name.to_string(),
                version,
            }
        } else {
            CustomForceError::OtherVersion {
                name: name.to_string(),
                version,
                registered,
            }
        })
    }
}

/// Why a scene's custom term could not be resolved.
#[derive(Clone, Debug, PartialEq)]
pub enum CustomForceError {
    /// The program's [`ForceTerms`] has no term of this name.
    Unknown {
        /// The name asked for.
        name: String,
        /// The version asked for.
        version: u32,
    },
    /// The name is there, but not at this version.
    OtherVersion {
        /// The name asked for.
        name: String,
        /// The version asked for.
        version: u32,
        /// The versions the program has.
        registered: Vec<u32>,
    },
}

impl std::fmt::Display for CustomForceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CustomForceError::Unknown { name, version } => write!(
                f,
                "custom force term `{name}` (version {version}) is not in this program's terms: \
                 it runs only in the game that provides it (volley_sim::ForceTerms)"
            ),
            CustomForceError::OtherVersion {
                name,
                version,
                registered,
            } => write!(
                f,
                "custom force term `{name}` is version {version} here, and this program has \
                 version {}: a run made with one does not replay with the other",
                registered
                    .iter()
                    .map(u32::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

impl std::error::Error for CustomForceError {}
