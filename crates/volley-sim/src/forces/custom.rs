//! A game's own force term: the seam through which code outside Volley adds a force that the
//! built-in terms do not cover (a drag curve of its own, a thrust schedule, a homing pull).
//!
//! A game implements [`ForceTerm`] and registers it once with [`register`]. A scene then
//! declares it by name and version, `Custom(name: "my-game/drag", version: 1)`, in a scene file
//! or through [`Forces::custom`](super::Forces::custom) in code. Registration is what lets a
//! scene file, a saved setup or a recording name the term: parsing resolves the name in the
//! registry, so replaying a recording without the term, or with another version of it, is
//! refused with one line naming both (the recording carries its scene text, so it always
//! names the term it was made with).
//!
//! What Volley does with it:
//! - Every integrator steps it at each stage's own time, except two. `exact` has no closed
//!   form for it. Forest-Ruth solves velocity terms in closed form, so it takes only a
//!   position-only term (one whose [`ForceTerm::velocity_dependent`] is false). Implicit Euler
//!   and the implicit midpoint rule treat it explicitly.
//! - The energy guard checks only finiteness while a custom term is declared: Volley cannot
//!   know whether the term adds energy (thrust does).
//! - The stability pre-check cannot see inside it and leaves it out; the study's reference is
//!   RK4 at a finer step (the extrapolation reference passes no clock).
//! - A world without one pays nothing: the term is a slot that stays empty, and the fast-path
//!   models (gravity alone, gravity with linear drag) never test for it.

use std::sync::{Arc, RwLock};

use glam::DVec3;

/// A force a game computes itself. `Send + Sync`: a step may evaluate it on several threads
/// at once, so it must not mutate anything it reads (determinism: the same inputs, the same
/// bits).
pub trait ForceTerm: Send + Sync + std::fmt::Debug {
    /// The name scene files and recordings use for it, e.g. `my-game/drag`.
    fn name(&self) -> &str;
    /// Its version: change it whenever the force it computes changes, so a recording made
    /// with the old one is refused rather than replayed to other bits.
    fn version(&self) -> u32;
    /// Force (N) at time `t` (s, the world's clock) on a body of mass `m` (kg) at `p` (m)
    /// moving at `v` (m/s).
    fn force(&self, t: f64, p: DVec3, v: DVec3, m: f64) -> DVec3;
    /// Whether [`ForceTerm::force`] reads `v` (default true). A position-only term may be
    /// stepped by Forest-Ruth, and velocity Verlet takes its one-evaluation form.
    fn velocity_dependent(&self) -> bool {
        true
    }
    /// Force (N) on a body launched as `launch` says ([`crate::integrate::Launch`]: the
    /// world's time at its launch, its mass then, its spin then): the body's own extra state,
    /// for a term that needs its time since launch (a game's own motor, a fuse) or its spin.
    /// What Volley calls; the default is [`ForceTerm::force`]. A term that overrides it must
    /// also return true from [`ForceTerm::reads_launch`], or the launch it gets is zero.
    fn force_launched(
        &self,
        t: f64,
        p: DVec3,
        v: DVec3,
        m: f64,
        launch: &crate::body::Launch,
    ) -> DVec3 {
        let _ = launch;
        self.force(t, p, v, m)
    }
    /// Whether [`ForceTerm::force_launched`] reads the launch (default false): only then does
    /// a step load the bodies' launch columns.
    fn reads_launch(&self) -> bool {
        false
    }
}

/// A declared custom term: the shared term itself. Equal when it is the same registered term
/// (same name and version).
#[derive(Clone, Debug)]
pub struct CustomForce(pub Arc<dyn ForceTerm>);

impl PartialEq for CustomForce {
    fn eq(&self, other: &Self) -> bool {
        self.0.name() == other.0.name() && self.0.version() == other.0.version()
    }
}

impl CustomForce {
    /// Force (N) on a body of mass `w.m` launched as `w.launch` says, as
    /// [`ForceTerm::force_launched`].
    #[inline]
    pub fn force(&self, t: f64, p: DVec3, v: DVec3, w: crate::body::Mass) -> DVec3 {
        self.0.force_launched(t, p, v, w.m, &w.launch)
    }
}

/// The registered terms, in registration order (a list, not a map: nothing iterates a hash).
static REGISTRY: RwLock<Vec<Arc<dyn ForceTerm>>> = RwLock::new(Vec::new());

/// Registers `term` so scenes can name it. Registering the same name and version again
/// replaces the earlier one; another version of a registered name is kept beside it.
pub fn register(term: Arc<dyn ForceTerm>) {
    let mut list = REGISTRY.write().unwrap_or_else(|e| e.into_inner());
    list.retain(|t| !(t.name() == term.name() && t.version() == term.version()));
    list.push(term);
}

/// Why a scene's custom term could not be resolved.
#[derive(Clone, Debug, PartialEq)]
pub enum CustomForceError {
    /// No term of this name is registered.
    Unknown {
        /// The name asked for.
        name: String,
        /// The version asked for.
        version: u32,
    },
    /// The name is registered, but not at this version.
    OtherVersion {
        /// The name asked for.
        name: String,
        /// The version asked for.
        version: u32,
        /// The versions registered.
        registered: Vec<u32>,
    },
}

impl std::fmt::Display for CustomForceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CustomForceError::Unknown { name, version } => write!(
                f,
                "custom force term `{name}` (version {version}) is not registered in this \
                 program: it runs only in the game that provides it (volley_sim::register_force_term)"
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

/// The registered term `name` at `version`.
pub fn resolve(name: &str, version: u32) -> Result<CustomForce, CustomForceError> {
    let list = REGISTRY.read().unwrap_or_else(|e| e.into_inner());
    if let Some(t) = list
        .iter()
        .find(|t| t.name() == name && t.version() == version)
    {
        return Ok(CustomForce(Arc::clone(t)));
    }
    let registered: Vec<u32> = list
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
