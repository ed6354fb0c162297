//! A scene built in code: [`Scene::builder`] and [`SceneBuilder`].
//!
//! A builder starts from the defaults a scene file gets (velocity Verlet, one substep, 10 s,
//! no forces, no contacts, seed 0) and sets what a game names. [`SceneBuilder::build`] writes
//! the scene as scene-file text and reads it back through [`super::parse`], so a built scene is
//! validated by the same checks, with the same errors (naming the field), as a file, and its
//! [`Scene::source`] is a scene file that a recording can embed and `volley headless` can open.

use glam::DVec3;

use super::*;
use crate::contact::{HeightGrid, LevelSource, MeshGeometry, Transform};

/// The label a built scene's errors and source name as its file.
pub const BUILT: &str = "<built in code>";

/// A scene under construction; see [`Scene::builder`].
#[derive(Clone, Debug)]
#[must_use = "a builder does nothing until `build` is called"]
pub struct SceneBuilder {
    scene: Scene,
    dt: f64,
    /// The game's own terms added with [`SceneBuilder::custom`], which `build` resolves.
    terms: ForceTerms,
}

impl Scene {
    /// A scene named `name` stepping every `dt` seconds, with a scene file's defaults, to be set
    /// up in code:
    ///
    /// ```
    /// use glam::DVec3;
    /// use volley_sim::{BodySpec, Ground, Scene};
    /// use volley_sim::Integrator;
    ///
    /// let scene = Scene::builder("shot", 1.0 / 60.0)
    ///     .integrator(Integrator::Rk4)
    ///     .gravity(DVec3::new(0.0, 0.0, -9.81))
    ///     .quadratic_drag(0.001)
    ///     .ground(Ground { height: 0.0, restitution: 0.5 })
    ///     .body(BodySpec {
    ///         mass: 0.145,
    ///         radius: 0.037,
    ///         position: DVec3::new(0.0, 0.0, 1.8),
    ///         velocity: DVec3::new(30.0, 0.0, 10.0),
    ///         spin: DVec3::ZERO,
    ///     })
    ///     .build()?;
    /// assert_eq!(scene.bodies().len(), 1);
    /// // The source is a scene file that reads back to the same scene.
    /// let again = volley_sim::parse_scene(scene.source(), "again.ron", "shot")?;
    /// assert_eq!(again.to_ron(), scene.to_ron());
    ///
    /// // A bad value is the error a file would give, naming the field.
    /// let err = Scene::builder("bad", 0.01).gravity(DVec3::NAN).build().unwrap_err();
    /// assert!(err.to_string().contains("forces[0]"), "{err}");
    /// # Ok::<(), volley_sim::SceneError>(())
    /// ```
    pub fn builder(name: &str, dt: f64) -> SceneBuilder {
        let defaults = format!(
            "Scene(name: {name:?}, dt: 0.01, integrator: VelocityVerlet, bodies: [])",
            name = name.escape_debug().to_string()
        );
        let scene = parse(&defaults, BUILT, name)
            .expect("the builder's defaults are a valid scene for any name");
        SceneBuilder {
            scene,
            dt,
            terms: ForceTerms::new(),
        }
    }
}

impl Scene {
    /// A builder seeded with this scene (its values, its game's own terms), for a change that
    /// is checked again as a whole: `build` writes the edited scene as scene-file text, reads
    /// it back with the same checks as a file, and makes that text the new scene's
    /// [`Scene::source`], so a recording of the edited scene replays as it ran.
    ///
    /// ```
    /// use volley_sim::{Ground, bundled_scene};
    ///
    /// let bounce = bundled_scene("bounce")?;
    /// let softer = bounce
    ///     .edit()
    ///     .ground(Ground { height: 0.0, restitution: 0.3 })
    ///     .build()?;
    /// assert_eq!(softer.ground().unwrap().restitution, 0.3);
    /// assert!(softer.source().contains("restitution: 0.3"));
    /// // A bad value is refused as a file's would be, naming the field.
    /// let err = bounce.edit().ground(Ground { height: 0.0, restitution: 2.0 }).build();
    /// assert!(err.unwrap_err().to_string().contains("ground.restitution"));
    /// # Ok::<(), volley_sim::SceneError>(())
    /// ```
    pub fn edit(&self) -> SceneBuilder {
        let mut terms = ForceTerms::new();
        for c in &self.forces.custom {
            terms.add(std::sync::Arc::clone(&c.0));
        }
        SceneBuilder {
            scene: self.clone(),
            dt: self.dt(),
            terms,
        }
    }
}

impl SceneBuilder {
    /// The scene's short name.
    pub fn name(mut self, name: &str) -> Self {
        self.scene.name = name.to_string();
        self
    }

    /// The timestep (s), rounded to whole nanoseconds when built.
    pub fn dt(mut self, dt: f64) -> Self {
        self.dt = dt;
        self
    }

    /// One line on what the scene shows.
    pub fn description(mut self, text: &str) -> Self {
        self.scene.description = text.to_string();
        self
    }

    /// The integrator.
    pub fn integrator(mut self, integrator: Integrator) -> Self {
        self.scene.integrator = integrator;
        self
    }

    /// Integrator steps per tick.
    pub fn substeps(mut self, substeps: u32) -> Self {
        self.scene.substeps = substeps;
        self
    }

    /// The adaptive integrator's tolerance.
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.scene.tolerance = tolerance;
        self
    }

    /// Sim time (s) of tick 0.
    pub fn start_time(mut self, t: f64) -> Self {
        self.scene.start_time = t;
        self
    }

    /// Sim time (s) a headless run covers.
    pub fn duration(mut self, t: f64) -> Self {
        self.scene.duration = t;
        self
    }

    /// Seed of the world's random number generator.
    pub fn seed(mut self, seed: u64) -> Self {
        self.scene.seed = seed;
        self
    }

    /// Every force term at once (a game's own among them are resolved by the terms
    /// themselves: they are kept for `build`).
    pub fn forces(mut self, forces: Forces) -> Self {
        for c in &forces.custom {
            self.terms.add(std::sync::Arc::clone(&c.0));
        }
        self.scene.forces = forces;
        self
    }

    /// Gravity, `F = m g` (m/s^2).
    pub fn gravity(mut self, g: DVec3) -> Self {
        self.scene.forces.gravity = Some(g);
        self
    }

    /// A constant force on every body (N).
    pub fn constant_force(mut self, f: DVec3) -> Self {
        self.scene.forces.constant = Some(f);
        self
    }

    /// Linear drag, `F = -b v` (kg/s).
    pub fn linear_drag(mut self, b: f64) -> Self {
        self.scene.forces.linear_drag = Some(b);
        self
    }

    /// Quadratic drag, `F = -c |v| v` (kg/m).
    pub fn quadratic_drag(mut self, c: f64) -> Self {
        self.scene.forces.quadratic_drag = Some(c);
        self
    }

    /// A spring to an anchor.
    pub fn spring(mut self, spring: Spring) -> Self {
        self.scene.forces.spring = Some(spring);
        self
    }

    /// Attraction to a point mass.
    pub fn point_mass(mut self, point_mass: PointMass) -> Self {
        self.scene.forces.point_mass = Some(point_mass);
        self
    }

    /// Drag against a Mach-dependent curve in the air and the wind ([`MachDrag::new`]).
    pub fn mach_drag(mut self, drag: MachDrag) -> Self {
        self.scene.forces.mach_drag = Some(drag);
        self
    }

    /// A motor on every body ([`Thrust::new`]).
    pub fn thrust(mut self, thrust: Thrust) -> Self {
        self.scene.forces.thrust = Some(thrust);
        self
    }

    /// One more of the game's own terms, evaluated after those added before it. The built
    /// scene holds the term itself; its file text names it, so [`crate::parse_scene_with`]
    /// and a replay find it again in the program's [`ForceTerms`].
    pub fn custom(mut self, term: impl crate::forces::ForceTerm + 'static) -> Self {
        let term: std::sync::Arc<dyn crate::forces::ForceTerm> = std::sync::Arc::new(term);
        self.terms.add(std::sync::Arc::clone(&term));
        self.scene
            .forces
            .custom
            .push(crate::forces::CustomForce(term));
        self
    }

    /// The ground plane.
    pub fn ground(mut self, ground: Ground) -> Self {
        self.scene.ground = Some(ground);
        self
    }

    /// No ground plane.
    pub fn no_ground(mut self) -> Self {
        self.scene.ground = None;
        self
    }

    /// These walls instead of the scene's.
    pub fn walls(mut self, walls: Vec<Wall>) -> Self {
        self.scene.walls = walls;
        self
    }

    /// These targets instead of the scene's.
    pub fn targets(mut self, targets: Vec<Target>) -> Self {
        self.scene.targets = targets;
        self
    }

    /// These bodies at tick 0 instead of the scene's.
    pub fn bodies(mut self, bodies: Vec<BodySpec>) -> Self {
        self.scene.bodies = bodies;
        self
    }

    /// No volley.
    pub fn no_volley(mut self) -> Self {
        self.scene.volley = None;
        self
    }

    /// The lanes the window opens in compare mode.
    pub fn compare(mut self, lanes: Vec<CompareLane>) -> Self {
        self.scene.compare = lanes;
        self
    }

    /// One more wall.
    pub fn wall(mut self, wall: Wall) -> Self {
        self.scene.walls.push(wall);
        self
    }

    /// One more target.
    pub fn target(mut self, target: Target) -> Self {
        self.scene.targets.push(target);
        self
    }

    /// A static triangle mesh, `name` in events, placed by `transform`, bouncing with
    /// `restitution`. Its geometry is written into the scene's source (a recording embeds it),
    /// so a big mesh belongs in a file that a scene file names instead.
    pub fn mesh(
        mut self,
        name: &str,
        geometry: MeshGeometry,
        transform: Transform,
        restitution: f64,
    ) -> Self {
        let geometry = std::sync::Arc::new(geometry);
        self.scene.meshes.push(MeshSurface::new(
            name,
            LevelSource::Inline,
            geometry.content_hash(),
            geometry,
            transform,
            restitution,
        ));
        self
    }

    /// A heightfield of `grid` (heights in metres) with samples `cell_size` metres apart,
    /// placed by `transform`; written into the scene's source like [`SceneBuilder::mesh`].
    pub fn heightfield(
        mut self,
        name: &str,
        grid: HeightGrid,
        cell_size: f64,
        transform: Transform,
        restitution: f64,
    ) -> Self {
        let grid = std::sync::Arc::new(grid);
        self.scene.heightfields.push(HeightfieldSurface::new(
            name,
            LevelSource::Inline,
            grid.content_hash(),
            grid,
            cell_size,
            1.0,
            transform,
            restitution,
        ));
        self
    }

    /// Swept or discrete contact detection.
    pub fn detection(mut self, detection: Detection) -> Self {
        self.scene.detection = detection;
        self
    }

    /// One more body at tick 0 (ids in the order they are added).
    pub fn body(mut self, body: BodySpec) -> Self {
        self.scene.bodies.push(body);
        self
    }

    /// Where fired projectiles start and how they are launched.
    pub fn launcher(mut self, launcher: Launcher) -> Self {
        self.scene.launcher = launcher;
        self
    }

    /// Extra bodies fired at tick 0 with seeded spread.
    pub fn volley(mut self, volley: Volley) -> Self {
        self.scene.volley = Some(volley);
        self
    }

    /// The divergence guard.
    pub fn guard(mut self, guard: Guard) -> Self {
        self.scene.guard = guard;
        self
    }

    /// One more declared event (events are named by the order they are added):
    ///
    /// ```
    /// use volley_sim::{EventCondition, EventSpec, EventStop, bundled_scene};
    ///
    /// let rifle = bundled_scene("rifle")?
    ///     .edit()
    ///     .event(EventSpec::new(EventCondition::Downrange(300.0)).named("300 m"))
    ///     .event(EventSpec::new(EventCondition::Mach(1.0)).falling().stopping(EventStop::Run(1)))
    ///     .build()?;
    /// assert_eq!(rifle.events().len(), 2);
    /// // A bad declaration is refused naming the field, as in a file.
    /// let bad = rifle.edit().event(EventSpec::new(EventCondition::ClosestToTarget(7))).build();
    /// assert!(bad.unwrap_err().to_string().contains("events[2].when"));
    /// # Ok::<(), volley_sim::SceneError>(())
    /// ```
    pub fn event(mut self, event: EventSpec) -> Self {
        self.scene.events.push(event);
        self
    }

    /// The declared events, replacing any.
    pub fn events(mut self, events: Vec<EventSpec>) -> Self {
        self.scene.events = events;
        self
    }

    /// The scene, checked as a scene file is: written as one and read back, so every error is
    /// the file's (naming the field) and [`Scene::source`] is that file.
    ///
    /// Every build reads the whole scene again, level surfaces included: an inline mesh's
    /// triangles are parsed from the text and a file's re-read, and each surface's hierarchy
    /// is built anew, even by an edit that only changes bodies. On a scene with a big mesh
    /// (a callgrind run of `benches/levels_peer.rs` spent most of its instructions here, on two
    /// builds of a 100 352-triangle inline terrain), build once and add bodies to the running
    /// world with [`crate::World::spawn`], which shares the scene's surfaces.
    pub fn build(self) -> Result<Scene, SceneError> {
        let SceneBuilder {
            mut scene,
            dt,
            terms,
        } = self;
        scene.timestep = timestep_from_secs("dt", dt).map_err(|e| SceneError {
            file: BUILT.to_string(),
            position: None,
            message: e.problem.to_string(),
            field: Some(e.field),
        })?;
        let text = format!(
            "// The scene `{}`, built in code with volley_sim::SceneBuilder.\n{}\n",
            scene.name.escape_debug(),
            scene.ron_body()
        );
        let files = LevelFiles {
            dir: scene.level_dir.clone(),
        };
        parse_levels_in(&text, BUILT, &scene.name, &terms, &files)
    }
}
