//! Every scene's maximal-coordinate description. A scene that is a joint graph
//! ([`SceneType::joint_graph`]) needs none: its Cartesian model, rapier builds and read-back
//! follow from the graph ([`graph`]). The others — whose coordinates are the point (polar,
//! Cartesian, rope depths, a rolling contact) — have one file here, found through the scene's
//! type: the inverse map `q = g(z)` that reads body poses back into generalized coordinates, the
//! Cartesian constraints `Φ(z, t) = 0` and non-conservative forces, and the rapier
//! construction. [`hand_written!`] lists them; a registered scene in neither group has no
//! maximal build, which [`visit`] reports.

mod chaplygin_sleigh;
mod charged_particle;
mod driven_pendulum;
mod isotropic_oscillator;
mod kepler;
mod nonminimal_pendulum;
mod rolling_disc;
mod spring_pendulum;

use crate::cartesian::constraints::{Constraint, VelocityConstraint};
use crate::cartesian::system::AppliedForce;
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::Draft;
use lagrange::graph::GraphMechanism;
use lagrange::{Error, Scalar, State};
use lagrange_scenes::{Params, Scene, SceneType};

/// Call `$callback!` with every scene type that has a hand-written maximal description (the
/// scenes that are not joint graphs).
macro_rules! hand_written {
    ($callback:ident) => {
        $callback! {
            lagrange_scenes::Kepler,
            lagrange_scenes::IsotropicOscillator,
            lagrange_scenes::SpringPendulum,
            lagrange_scenes::DrivenPendulum,
            lagrange_scenes::ChargedParticle,
            lagrange_scenes::NonminimalPendulum,
            lagrange_scenes::ChaplyginSleigh,
            lagrange_scenes::RollingDisc
        }
    };
}

/// The resolved joint graph of `scene` with `params`, if the scene is one.
///
/// # Errors
/// Invalid parameters, or a graph that is not a mechanism.
pub(crate) fn graph(scene: &dyn Scene, params: &Params) -> Result<Option<GraphMechanism>, Error> {
    scene.joint_graph(params)?.map(GraphMechanism::new).transpose()
}

/// A scene's description in maximal coordinates: every body's full planar pose
/// `z_b = (x_b, y_b, φ_b)`, bodies in the reduced model's order.
pub(crate) trait MaximalScene: SceneType {
    /// `q = g(z)`: the generalized coordinates from the body poses at time `t`, written by hand
    /// (independently of the reduced model's poses); angles on any branch.
    fn generalized<S: Scalar>(&self, t: S, z: &[[S; 3]]) -> Vec<S>;

    /// The holonomic constraints `Φ(z, t) = 0` for bodies named `names`: exactly `3B − d`
    /// independent equations, `d` the reduced model's number of coordinates less its holonomic
    /// constraints (and less its velocity constraints written here in integrated form, if
    /// any); depths are `−y`.
    fn constraints(&self, names: &[String]) -> Vec<Constraint>;

    /// The velocity (non-holonomic) constraints `A(z) ż = 0` on the body poses; none by default.
    fn velocity_constraints(&self) -> Vec<VelocityConstraint> {
        Vec::new()
    }

    /// The non-conservative forces in Cartesian form; none by default.
    fn applied_force(&self) -> AppliedForce {
        AppliedForce::None
    }

    /// Why rapier's joints of `mode` cannot express the scene, if they cannot.
    fn rapier_unbuildable(mode: JointMode) -> Option<&'static str> {
        let _ = mode;
        None
    }

    /// How the scene is drawn (docs/animation.md): its bodies' figures and what joins them.
    fn sketch(&self) -> crate::sketch::Sketch;

    /// Write the rapier construction into `draft` (its bodies, joints, couplings and per-step
    /// forces), starting from the reduced `initial` state.
    fn rapier(&self, draft: &mut Draft, initial: &State);
}

/// Generic code to run on a scene's typed maximal description.
pub(crate) trait MaximalVisitor {
    /// What a visit returns.
    type Output;

    /// Run on the typed scene.
    fn visit<T: MaximalScene>(self, scene: T) -> Self::Output;
}

/// Whether `scene` has a maximal description: its joint graph (with `params`), or a
/// hand-written one.
///
/// # Errors
/// Invalid parameters.
pub(crate) fn has_description(scene: &dyn Scene, params: &Params) -> Result<bool, Error> {
    macro_rules! listed {
        ($($scene:ty),*) => {
            [$(<$scene as SceneType>::ID),*].contains(&scene.id())
        };
    }
    Ok(hand_written!(listed) || scene.joint_graph(params)?.is_some())
}

/// Build the typed maximal description of `scene` from `params` and run `visitor` on it.
///
/// # Errors
/// [`Error::InvalidParameter`] for invalid parameters or a scene without a hand-written
/// maximal description.
pub(crate) fn visit<V: MaximalVisitor>(scene: &dyn Scene, params: &Params, visitor: V) -> Result<V::Output, Error> {
    let id = scene.id();
    macro_rules! dispatch {
        ($($scene:ty),*) => {
            $(if id == <$scene as SceneType>::ID {
                return Ok(visitor.visit(<$scene as SceneType>::from_params(params)?));
            })*
        };
    }
    hand_written!(dispatch);
    Err(Error::InvalidParameter {
        name: "scene".into(),
        value: f64::NAN,
        why: format!("`{id}` has neither a joint graph nor a hand-written maximal description"),
    })
}

/// The angle from the downward vertical of the vector `(dx, dy)`.
fn angle_from_down<S: Scalar>(dx: S, dy: S) -> S {
    dx.atan2(-dy)
}

/// Plane polar coordinates `(r, θ)` of a particle at `(x, y)`.
fn polar<S: Scalar>(z: &[S; 3]) -> Vec<S> {
    vec![(z[0] * z[0] + z[1] * z[1]).sqrt(), z[1].atan2(z[0])]
}
