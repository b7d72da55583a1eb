//! Static dispatch from a scene id to its typed mechanism, for generic code that needs the
//! concrete [`Mechanism`] type (workspaces in dual numbers, a [`RawModel`](lagrange::RawModel)
//! over a [`Model`](lagrange::Model), allocation checks), which `Box<dyn System>` hides.

use crate::{Params, SceneType};
use lagrange::{Error, Mechanism};

/// A typed scene's hand-coded closed-form accelerations, without allocation (for benchmarks
/// and tests that compare the generic engine with them through a [`MechanismVisitor`]).
pub trait ClosedForm {
    /// Write the closed-form `q̈(t, q, q̇)` into `qddot`.
    ///
    /// # Panics
    /// If a slice does not have the scene's number of coordinates.
    fn closed_form_into(&self, t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]);
}

/// Generic code to run on a scene's typed mechanism (the visitor pattern: a generic method
/// cannot be called through `dyn`, so the scene calls it with its concrete type).
pub trait MechanismVisitor {
    /// What a visit returns.
    type Output;

    /// Run on the mechanism, by value.
    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) -> Self::Output;
}

/// Build the typed mechanism of the scene `id` from `params` and run `visitor` on it.
///
/// Returns `Ok(None)` for a scene that is not a body mechanism (`charged_particle`, a raw
/// [`Lagrangian`](lagrange::Lagrangian)); its parameters are still validated.
///
/// # Errors
/// [`Error::InvalidParameter`] for invalid parameters (naming the parameter), or for an unknown
/// id (named `scene`, listing the known ids).
pub fn visit_mechanism<V: MechanismVisitor>(id: &str, params: &Params, visitor: V) -> Result<Option<V::Output>, Error> {
    macro_rules! dispatch {
        ($($scene:ty),*) => {
            $(if id == <$scene as SceneType>::ID {
                return Ok(<$scene as SceneType>::from_params(params)?.visit(visitor));
            })*
        };
    }
    crate::for_each_scene!(dispatch);
    Err(unknown_scene(id))
}

/// The error for an id that names no registered scene: [`Error::InvalidParameter`] named
/// `scene`, listing the known ids.
pub fn unknown_scene(id: &str) -> Error {
    Error::InvalidParameter {
        name: "scene".into(),
        value: f64::NAN,
        why: format!("unknown scene id `{id}`; known: {}", crate::ids().join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::all;
    use lagrange::Model;

    /// Reports the mechanism's number of coordinates and whether the engine accepts it.
    struct Dof;

    impl MechanismVisitor for Dof {
        type Output = (usize, bool);

        fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) -> (usize, bool) {
            (mechanism.description().dof(), Model::new(mechanism).is_ok())
        }
    }

    #[test]
    fn every_body_scene_is_visited_with_its_own_mechanism() {
        for scene in all() {
            let params = scene.default_params();
            let visited = visit_mechanism(scene.id(), &params, Dof).unwrap();
            let n = scene.coordinates(&params).unwrap().len();
            let expected = if scene.id() == "charged_particle" { None } else { Some((n, true)) };
            assert_eq!(visited, expected, "{}", scene.id());
        }
    }

    /// For a scene that declares a kinematic tree: the largest relative difference between
    /// the articulated-body algorithm and the generic assembly over a few states.
    struct TreeAgreement<'a> {
        states: &'a [lagrange::State],
    }

    impl MechanismVisitor for TreeAgreement<'_> {
        type Output = Option<f64>;

        fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) -> Option<f64> {
            crate::testing::tree_versus_generic(mechanism, self.states)
        }
    }

    /// The chain, the double pendulum and the cart pendulum describe themselves as trees, and
    /// so do the graphs of the parallelogram chain and the redundant parallelogram (trees with
    /// loops, listed parents first); the engine accepts each tree (its forward kinematics
    /// reproduce the scene's poses) and the articulated-body algorithm (with the sparse
    /// constrained solve for the loops) agrees with the generic assembly to
    /// [`ENGINE_VS_CLOSED_FORM`](crate::testing::ENGINE_VS_CLOSED_FORM) at the default state and
    /// two moving ones (default parameters: well conditioned, a few coordinates).
    #[test]
    fn tree_scenes_run_the_articulated_body_algorithm_and_agree_with_the_generic_path() {
        let mut trees = Vec::new();
        for scene in all() {
            let params = scene.default_params();
            let initial = scene.default_state(&params).unwrap();
            let n = initial.q.len();
            let moving = |k: f64| {
                let q: Vec<f64> =
                    initial.q.iter().enumerate().map(|(i, q)| q + k * (0.7 * i as f64 + 0.3).sin()).collect();
                let qdot: Vec<f64> = (0..n).map(|i| k * (1.1 * i as f64 + 0.5).cos()).collect();
                lagrange::State::new(k, q, qdot)
            };
            // A constrained scene's moving states are brought onto its constraints: off them, a
            // redundant row's residual is inconsistent with the others and its multiplier is
            // round-off divided by the solve's shift.
            let system = scene.build(&params).unwrap();
            let onto = |state: lagrange::State| {
                if system.constraint_counts() == (0, 0) {
                    return state;
                }
                system.assemble(&state, &vec![false; n]).unwrap()
            };
            let states = [initial.clone(), onto(moving(1.0)), onto(moving(-2.0))];
            if let Some(Some(worst)) = visit_mechanism(scene.id(), &params, TreeAgreement { states: &states }).unwrap()
            {
                assert!(
                    worst <= crate::testing::ENGINE_VS_CLOSED_FORM,
                    "{}: relative difference {worst:e}",
                    scene.id()
                );
                trees.push(scene.id());
            }
        }
        trees.sort_unstable();
        assert_eq!(
            trees,
            ["cart_pendulum", "chain", "double_pendulum", "parallelogram_chain", "redundant_parallelogram"]
        );
    }

    #[test]
    fn unknown_ids_and_invalid_parameters_are_errors() {
        let params = crate::scene_of::<crate::CartPendulum>().default_params();
        let unknown = visit_mechanism("pendulum", &params, Dof).unwrap_err();
        assert!(
            matches!(unknown, Error::InvalidParameter { ref name, ref why, .. } if name == "scene" && why.contains("cart_pendulum"))
        );
        let foreign = visit_mechanism("charged_particle", &params, Dof).unwrap_err();
        assert!(matches!(foreign, Error::InvalidParameter { .. }), "{foreign}");
    }
}
