//! # lagrange-maximal — the same scenes in maximal coordinates
//!
//! The reduced-coordinate engine ([`lagrange`]) is checked here against two independent
//! formulations that keep every body's full planar pose `z_b = (x_b, y_b, φ_b)`:
//!
//! * [`cartesian`]: the lecture's starting point — Cartesian coordinates plus holonomic
//!   constraints `Φ(z, t) = 0`, solved with Lagrange multipliers,
//!   `M z̈ + Φ_zᵀ λ = F`, `Φ_z z̈ = −(Φ_z ż)_z ż − 2 Φ_zt ż − Φ_tt`, integrated with projection
//!   onto `Φ = 0` and `Φ̇ = 0`; the multipliers give the constraint forces;
//! * [`rapier`]: the rapier physics engine (rapier2d-f64 and rapier2d), with impulse joints
//!   and with multibody joints.
//!
//! Both start from the reduced model's body states ([`maps::ReadBack::body_states`]) and are read back
//! into generalized coordinates ([`maps::ReadBack`], carried by every [`Built`]). A scene that is a joint graph
//! (`lagrange::graph`, docs/graphs.md) needs nothing more: its Cartesian constraints, rapier
//! construction and read-back follow from the graph. The others keep a hand-written maximal
//! description (inverse map, Cartesian constraints, rapier construction), one file in
//! `src/scenes/`. [`build`] makes any engine's simulation of any scene, or says why it cannot;
//! [`build_graph`] does the same for any joint graph.

pub mod cartesian;
mod engine;
pub mod maps;
pub mod rapier;
mod scenes;
pub mod sketch;

pub use engine::{BodyState, BuildError, Built, Engine, MaximalSimulation, Settings};
pub use sketch::{Sketch, sketch};

use lagrange::State;
use lagrange::graph::{GraphMechanism, JointGraph};
use lagrange_scenes::{Params, Scene};

/// Build `scene` with `params` in `engine`, starting from the reduced `initial` state: from
/// its joint graph if it is one, otherwise from its hand-written maximal description.
///
/// ```
/// use lagrange_maximal::{Engine, Settings, build};
///
/// let scene = lagrange_scenes::find("double_pendulum").expect("a built-in scene");
/// let params = scene.default_params();
/// let initial = scene.default_state(&params)?;
/// let mut built = build(Engine::Cartesian, scene, &params, &initial, &Settings::default())?;
/// built.simulation.advance_to(0.5)?;
/// let (q, _) = built.read_back.generalized(0.5, &built.simulation.bodies(), &initial.q);
/// assert_eq!(q.len(), 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`BuildError::Unbuildable`] with the reason when the engine cannot express the scene
/// exactly, or when the scene has no maximal description (a scene of one's own that is not a
/// joint graph); [`BuildError::Invalid`] for invalid parameters, settings or state.
pub fn build(
    engine: Engine,
    scene: &dyn Scene,
    params: &Params,
    initial: &State,
    settings: &Settings,
) -> Result<Built, BuildError> {
    check_settings(engine, settings)?;
    if !scenes::has_description(scene, params)? {
        let reason = "the scene has no maximal description: it is not a joint graph, and no hand-written one \
                      (inverse map, Cartesian constraints, rapier construction) is in lagrange-maximal"
            .into();
        return Err(BuildError::Unbuildable { engine, scene: scene.id().into(), reason });
    }
    match engine {
        Engine::Cartesian => cartesian::build(scene, params, initial, settings),
        rapier_engine => rapier::build(rapier_engine, scene, params, initial, settings),
    }
}

/// Build `engine`'s simulation of the joint graph `graph`, starting from its reduced model's
/// `initial` state: the Cartesian model (every joint as constraints between body poses, the force
/// elements as body wrenches) or a rapier build (impulse joints, or multibody joints along the
/// spanning tree with the loop-closing joints as impulse joints; docs/graphs.md). Bodies are the
/// graph's, in its order; `Built::read_back` reads them back into the graph's coordinates
/// ([`maps::graph_generalized`]). `Built::graph` is the graph simulated (with the deviations rapier needs, each
/// explained in `Built::deviations`): compare with its reduced model.
///
/// ```
/// use lagrange::graph::{GROUND, GraphBody, GraphJoint, JointGraph};
/// use lagrange::State;
/// use lagrange_maximal::{Engine, Settings, build_graph};
///
/// let graph = JointGraph::new("pendulum", 9.81)
///     .with_body(GraphBody::rigid("rod", 1.0, 1.0 / 12.0))
///     .with_joint(GraphJoint::revolute("θ", GROUND, [0.0, 0.0], "rod", [0.0, 0.5]));
/// let initial = State::new(0.0, [0.5], [0.0]);
/// let mut built = build_graph(Engine::RapierMultibody, &graph, &initial, &Settings::default())?;
/// built.simulation.advance_to(0.25)?;
/// let (q, _) = built.read_back.generalized(0.25, &built.simulation.bodies(), &initial.q);
/// assert!((q[0] - 0.5).abs() > 0.05, "it swings: θ = {}", q[0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`BuildError::Unbuildable`] naming the joint or body the engine cannot take;
/// [`BuildError::Invalid`] for a graph that is not a mechanism, a bad state or bad settings. A
/// graph whose loops fix every coordinate (a truss, a fully driven linkage) is built.
pub fn build_graph(
    engine: Engine,
    graph: &JointGraph,
    initial: &State,
    settings: &Settings,
) -> Result<Built, BuildError> {
    check_settings(engine, settings)?;
    let mechanism = GraphMechanism::new(graph.clone())?;
    // A state outside the graph's region (a spring of natural length l₀ > 0 whose ends meet)
    // is named here, not met as a NaN force at the first step.
    let mut bounds = lagrange::Bounds::new();
    if initial.q.len() == lagrange::Mechanism::description(&mechanism).coordinates.len()
        && lagrange::Mechanism::admissible(&mechanism, initial.t, &initial.q, &initial.qdot, &mut bounds)
        && let Some(error) = bounds.error(initial.t)
    {
        return Err(error.into());
    }
    let params = Params::defaults(&[]);
    match engine {
        Engine::Cartesian => {
            let mechanism = std::sync::Arc::new(mechanism);
            let read_back = maps::ReadBack::graph(std::sync::Arc::clone(&mechanism));
            let states = read_back.body_states(initial)?;
            let system = cartesian::system::CartesianSystem::from_graph(&graph.name, mechanism);
            let simulation = cartesian::CartesianSimulation::new(system, &states, initial.t, settings.tolerance)?;
            let graph = Some(graph.clone());
            Ok(Built { simulation: Box::new(simulation), params, deviations: Vec::new(), graph, read_back })
        }
        rapier_engine => rapier::build_graph(rapier_engine, mechanism, initial, settings),
    }
}

fn check_settings(engine: Engine, settings: &Settings) -> Result<(), lagrange::Error> {
    let invalid = |what, value, why| Err(lagrange::Error::InvalidSetting { what, value, why });
    if engine.is_rapier() {
        if !(settings.dt > 0.0 && settings.dt.is_finite()) {
            return invalid("step", settings.dt, "must be positive and finite");
        }
        if settings.substeps == 0 {
            return invalid("substeps", 0.0, "must be at least 1");
        }
    } else if !(settings.tolerance > 0.0 && settings.tolerance.is_finite()) {
        return invalid("tolerance", settings.tolerance, "must be positive and finite");
    }
    Ok(())
}

/// The built-in scene `id`, for the unit tests.
#[cfg(test)]
pub(crate) fn scene(id: &str) -> &'static dyn lagrange_scenes::Scene {
    lagrange_scenes::find(id).unwrap_or_else(|| panic!("no built-in scene `{id}`"))
}
