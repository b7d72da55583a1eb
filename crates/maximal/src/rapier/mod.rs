//! rapier builds of the scenes: impulse joints and multibody joints, in f64 (rapier2d-f64) and
//! f32 (rapier2d).
//!
//! Each scene is first written as a precision-independent plan (`plan.rs`: bodies with explicit mass
//! properties (or colliders whose shapes give them), joints with their anchors (loop-closing
//! ones marked), multibody couplings, per-step forces; each scene's `rapier` in `src/scenes/<scene>.rs` writes it through `scenes.rs`'s
//! draft, following docs/rapier.md#constructions-per-scene), then built by `world.rs`, one source
//! compiled twice (`double`: f64, `single`: f32). What is built:
//!
//! The scenes that are joint graphs (`cart_pendulum`, `harmonic_oscillator`, the Atwood
//! machines, `wedge`, `double_pendulum`, `chain`, `four_bar`, `slider_crank`,
//! `andrews_squeezer`, `parallelogram_chain`, `change_point_four_bar`,
//! `redundant_parallelogram`) are planned from
//! their graph by `graph.rs` (docs/graphs.md#rapier), the others by their own file in
//! `src/scenes/`; the table says what each build is.
//!
//! | scene | impulse joints | multibody joints |
//! |---|---|---|
//! | `cart_pendulum` | prismatic ground→cart (x), revolute cart→bob; compound bob (`I_b = 1e-2 m r²` if 0) | prismatic + revolute, point bob exact |
//! | `harmonic_oscillator` | prismatic (x) + per-step spring and damping forces | the same joint as a multibody |
//! | `kepler`, `isotropic_oscillator` | free body + per-step central force | revolute → massless arm → prismatic along the arm + per-step force |
//! | `spring_pendulum` | free body + per-step spring force | revolute → massless arm → prismatic along the arm + per-step spring force |
//! | `charged_particle` | free body + per-step Lorentz force | prismatic (x) → massless slider → prismatic (y) + per-step Lorentz force |
//! | `atwood` | unbuildable (no pulley or gear joint) | vertical prismatics, couplings `x₂ = l − πa − x₁`, pulley revolute `φ = x₁/a` (left out when `I = 0`) |
//! | `double_atwood` | unbuildable | prismatics, movable pulley carrying `m2`, `m3`; couplings for both ropes; massive pulley (0.5 kg if 0) |
//! | `double_double_atwood` | unbuildable | the same with two massive movable pulleys |
//! | `wedge` | prismatic ground→wedge (x), prismatic wedge→block along `(cosα, −sinα)` | the same joints |
//! | `double_pendulum` | revolute chain, compound bobs (`I = 1e-2 m l²` if 0) | revolute chain, point bobs exact |
//! | `chain` | revolute chain of rods hinged at their ends | the same joints |
//! | `driven_pendulum` | kinematic support moved to `(A sin ωt, 0)` each step, rope to the point bob (exact while the rod is in tension) | unbuildable (a prescribed motion is left out of multibody dynamics) |
//! | `four_bar` | four revolute joints (loop closed by the pin at `B`) + crank torque | tree ground→crank→coupler, ground→rocker; pin at `B` as a loop-closing impulse joint |
//! | `slider_crank` | three revolutes + prismatic slider on x + crank torque | tree ground→crank→rod, ground→slider; rod–slider pin as a loop-closing impulse joint |
//! | `andrews_squeezer` | ten revolute pins + per-step spring `C`–`D` and torque `mom` | spanning tree of seven pins; the three pins at `E` as loop-closing impulse joints |
//! | `parallelogram_chain` | `3N + 1` revolute pins | tree ground→crank `k`→coupler `k`, ground→crank `N`; the pins `B1 … BN` as loop-closing impulse joints |
//! | `change_point_four_bar` | as `four_bar` (no torque) | as `four_bar` |
//! | `redundant_parallelogram` | six revolute pins | tree ground→crank→coupler, ground→rocker, ground→third crank; the pins `B` and `C` as loop-closing impulse joints |
//! | `nonminimal_pendulum` | rope from the origin to the point bob | revolute at the origin |
//! | `rolling_disc` | ball collider on a fixed inclined cuboid with friction (contact, no joint) | the same free body |
//! | `chaplygin_sleigh` | unbuildable (no non-holonomic joint) | unbuildable |
//!
//! Every build: gravity `(0, −g)`, bodies never sleep, multibody joint damping zeroed,
//! stabilization sweeps off, speed caps off (see `world.rs`'s integration parameters).

mod double;
pub(crate) mod graph;
#[cfg(test)]
mod loop_tests;
pub(crate) mod plan;
pub(crate) mod scenes;
mod single;
#[cfg(test)]
mod tests;

use crate::{BuildError, Built, Engine, MaximalSimulation, Settings};
use lagrange::State;
use lagrange_scenes::{Params, Scene};
use plan::JointMode;

/// Build the rapier simulation of `scene` in `engine` (one of the four rapier engines),
/// starting from the reduced `initial` state. `Built::params` carries the deviations rapier
/// needs (compound bobs for impulse revolute joints, massive movable pulleys for multibody
/// couplings), each explained in `Built::deviations`.
///
/// # Errors
/// As [`crate::build`]: [`BuildError::Unbuildable`] with the reason (the Atwood machines with
/// impulse joints, the driven pendulum with multibody joints, the Cartesian engine);
/// [`BuildError::Invalid`] for invalid parameters, a state of the wrong size
/// or invalid settings.
pub fn build(
    engine: Engine,
    scene: &dyn Scene,
    params: &Params,
    initial: &State,
    settings: &Settings,
) -> Result<Built, BuildError> {
    let mode = match engine {
        Engine::RapierImpulse | Engine::RapierImpulseF32 => JointMode::Impulse,
        Engine::RapierMultibody | Engine::RapierMultibodyF32 => JointMode::Multibody,
        Engine::Cartesian => {
            let reason = "the Cartesian engine is not a rapier build".into();
            return Err(BuildError::Unbuildable { engine, scene: scene.id().into(), reason });
        }
    };
    if !(settings.dt > 0.0 && settings.dt.is_finite()) {
        return Err(lagrange::Error::InvalidSetting {
            what: "step",
            value: settings.dt,
            why: "must be positive and finite",
        }
        .into());
    }
    if settings.substeps == 0 {
        return Err(lagrange::Error::InvalidSetting { what: "substeps", value: 0.0, why: "must be at least 1" }.into());
    }
    let plan = scenes::plan(engine, mode, scene, params, initial)?;
    let (params, deviations) = (plan.params.clone(), plan.deviations.clone());
    let read_back = scene_read_back(&plan)?;
    Ok(Built { simulation: world(engine, plan, settings)?, params, deviations, graph: None, read_back })
}

/// The read-back a scene's or a graph's plan carries.
fn scene_read_back(plan: &plan::Plan) -> Result<crate::maps::ReadBack, lagrange::Error> {
    plan.read_back.clone().ok_or_else(|| lagrange::Error::Inconsistent {
        what: format!("rapier plan of {}: no read-back (a plan written by hand cannot be built)", plan.scene),
    })
}

/// The rapier world of `plan`, in the engine's precision.
fn world(engine: Engine, plan: plan::Plan, settings: &Settings) -> Result<Box<dyn MaximalSimulation>, lagrange::Error> {
    Ok(match engine {
        Engine::RapierImpulse | Engine::RapierMultibody => {
            Box::new(double::world::RapierSimulation::new(engine, plan, settings)?)
        }
        _ => Box::new(single::world::RapierSimulation::new(engine, plan, settings)?),
    })
}

/// The rapier build of a joint graph ([`crate::build_graph`]); `engine` is a rapier engine.
pub(crate) fn build_graph(
    engine: Engine,
    mechanism: lagrange::graph::GraphMechanism,
    initial: &State,
    settings: &Settings,
) -> Result<Built, BuildError> {
    let mode = match engine {
        Engine::RapierMultibody | Engine::RapierMultibodyF32 => JointMode::Multibody,
        _ => JointMode::Impulse,
    };
    let name = mechanism.graph().name.clone();
    let built = graph::plan(engine, mode, &name, &mechanism, initial)?;
    let (deviations, simulated) = (built.deviations.clone(), built.graph.clone());
    let read_back = scene_read_back(&built.plan)?;
    Ok(Built {
        simulation: world(engine, built.plan, settings)?,
        params: Params::defaults(&[]),
        deviations,
        graph: Some(simulated),
        read_back,
    })
}
