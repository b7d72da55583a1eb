//! The maximal-coordinate engines, their settings, and what a running simulation offers.

use lagrange_scenes::Params;
use std::fmt;

/// A maximal-coordinate formulation of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Engine {
    /// Cartesian body coordinates with holonomic constraints and Lagrange multipliers,
    /// integrated by the solver's adaptive integrator with projection ([`crate::cartesian`]).
    Cartesian,
    /// rapier2d-f64, bodies connected by impulse joints.
    RapierImpulse,
    /// rapier2d-f64, multibody (reduced-coordinate) joints.
    RapierMultibody,
    /// rapier2d (f32), impulse joints.
    RapierImpulseF32,
    /// rapier2d (f32), multibody joints.
    RapierMultibodyF32,
}

impl Engine {
    /// Every engine, in report order.
    pub const ALL: [Engine; 5] = [
        Engine::Cartesian,
        Engine::RapierImpulse,
        Engine::RapierMultibody,
        Engine::RapierImpulseF32,
        Engine::RapierMultibodyF32,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Engine::Cartesian => "cartesian",
            Engine::RapierImpulse => "rapier-impulse",
            Engine::RapierMultibody => "rapier-multibody",
            Engine::RapierImpulseF32 => "rapier-impulse-f32",
            Engine::RapierMultibodyF32 => "rapier-multibody-f32",
        }
    }

    /// The engine with this name.
    pub fn from_name(name: &str) -> Option<Engine> {
        Engine::ALL.into_iter().find(|e| e.name() == name)
    }

    /// Whether this is one of the rapier builds.
    pub fn is_rapier(self) -> bool {
        self != Engine::Cartesian
    }
}

impl fmt::Display for Engine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Numerical settings of a maximal build.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// rapier: the step `dt` of `PhysicsPipeline::step` (s).
    pub dt: f64,
    /// rapier: substeps per step (`num_solver_iterations`); rapier is first order in
    /// `h = dt / substeps`. Scenes driven by per-step forces use 1 whatever is asked (a force
    /// is constant over a step, and more substeps make the map non-symplectic; docs/rapier.md#the-substep-scheme).
    pub substeps: usize,
    /// Cartesian: relative and absolute tolerance of the adaptive integrator.
    pub tolerance: f64,
}

impl Default for Settings {
    /// `dt = 1/240`, 4 substeps, tolerance 1e-12.
    fn default() -> Self {
        Self { dt: 1.0 / 240.0, substeps: 4, tolerance: 1e-12 }
    }
}

/// Pose and velocity of one body in the plane: `(x, y, φ)` and `(ẋ, ẏ, φ̇)`, for the centre
/// of mass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyState {
    /// `(x, y, φ)`.
    pub pose: [f64; 3],
    /// `(ẋ, ẏ, φ̇)`.
    pub velocity: [f64; 3],
}

/// A scene running in a maximal-coordinate engine. Bodies are in the order of the reduced
/// scene's bodies (its `Mechanism::description`), so that generalized coordinates and
/// constraint forces can be read back and compared.
pub trait MaximalSimulation {
    /// Which engine.
    fn engine(&self) -> Engine;

    /// Current time.
    fn t(&self) -> f64;

    /// Advance to time `t` (rapier: whole steps of `dt`, so `t` should lie on that grid;
    /// Cartesian: exactly).
    ///
    /// # Errors
    /// A diverging or singular run.
    fn advance_to(&mut self, t: f64) -> Result<(), lagrange::Error>;

    /// Current body states.
    fn bodies(&self) -> Vec<BodyState>;

    /// Largest violation of the holonomic constraints now (m or rad), where the engine defines
    /// one; `None` where the formulation satisfies them by construction (multibody joints).
    fn constraint_violation(&self) -> Option<f64>;

    /// Constraint forces and torques `(F_x, F_y, τ)` on every body (3B), comparable to
    /// `lagrange::reaction_forces`, where the engine exposes them.
    fn constraint_forces(&mut self) -> Option<Vec<f64>>;

    /// Steps taken so far (rapier steps, or accepted integrator steps).
    fn steps(&self) -> usize;

    /// Substeps per step that the engine actually takes: rapier's `num_solver_iterations`,
    /// which is 1 for a build driven by per-step forces whatever [`Settings::substeps`] asked
    /// (its first-order error is then in `dt` itself); 1 for the Cartesian engine.
    fn substeps(&self) -> usize {
        1
    }
}

/// Why a maximal build is not available.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BuildError {
    /// The engine cannot express this scene exactly.
    #[error("{engine} cannot build {scene}: {reason}")]
    Unbuildable {
        /// The engine.
        engine: Engine,
        /// The scene id.
        scene: String,
        /// Why, in one sentence.
        reason: String,
    },
    /// Invalid parameters or state.
    #[error(transparent)]
    Invalid(#[from] lagrange::Error),
}

/// A successful build.
pub struct Built {
    /// The running simulation, at the initial state.
    pub simulation: Box<dyn MaximalSimulation>,
    /// The parameters the engine simulates: the requested ones, except for the deviations below,
    /// which the reduced reference must carry as well to be comparable.
    pub params: Params,
    /// Deviations from the requested scene that the engine needs (e.g. a compound bob for an
    /// impulse revolute joint, a massive movable pulley for a multibody), one sentence each.
    pub deviations: Vec<String>,
    /// For a joint graph built by [`build_graph`](crate::build_graph): the graph the engine
    /// simulates (the requested one with the deviations), whose reduced model is the reference.
    pub graph: Option<lagrange::graph::JointGraph>,
    /// What reads the simulation's bodies back into the reduced model's coordinates, and their
    /// energy (resolved once, with the parameters simulated).
    pub read_back: crate::maps::ReadBack,
}
