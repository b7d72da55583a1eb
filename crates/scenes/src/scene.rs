//! The scene interfaces: [`SceneType`], implemented by every typed scene, and the object-safe
//! [`Scene`] that a generic adapter derives from it for code that picks scenes by id at run
//! time; the registry of all scenes, generated from the one list in [`for_each_scene!`](crate::for_each_scene).

use crate::checks::{check_dimensions, check_state};
use crate::{ClosedForm, Conserved, MechanismVisitor, ParamSpec, Params};
use lagrange::graph::JointGraph;
use lagrange::{Coordinate, Error, State, System};
use std::marker::PhantomData;

/// A mechanical system with named parameters, a default initial state, a simulation built by
/// the engine, and the hand-derived closed forms to check it against.
///
/// Every method that takes [`Params`] validates them (a value outside its domain, or a set
/// built for another scene, is an [`Error::InvalidParameter`] naming the parameter); methods
/// that take a state check its dimensions ([`Error::DimensionMismatch`]).
///
/// Every scene implements it through [`SceneType`]; [`scene_of`] gives the object.
pub trait Scene: Send + Sync {
    /// Short identifier (`cart_pendulum`), unique in [`all`].
    fn id(&self) -> &'static str;

    /// Human-readable title.
    fn title(&self) -> &'static str;

    /// Where the system and its closed forms come from (`docs/scenes.md#cart_pendulum; the lecture (docs/scenes.md#the-lecture)`, or
    /// `beyond the lecture` with the textbook it follows).
    fn reference(&self) -> &'static str;

    /// The span of time over which the scene is meant to be run (s), where it has one of its
    /// own (Andrews' squeezer: 0.03 s, the span of its published reference solution); `None`
    /// for scenes that run for any span. The validation report scales its horizon, saved times
    /// and steps to it.
    fn horizon(&self) -> Option<f64>;

    /// The parameter specifications, in order.
    fn params(&self) -> &'static [ParamSpec];

    /// Every parameter at its default.
    fn default_params(&self) -> Params {
        Params::defaults(self.params())
    }

    /// The generalized coordinates for these parameters (their number may depend on them).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters.
    fn coordinates(&self, params: &Params) -> Result<Vec<Coordinate>, Error>;

    /// The scene's default initial state (at `t = 0`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters.
    fn default_state(&self, params: &Params) -> Result<State, Error>;

    /// The engine's simulation of the scene: a validated [`Model`](lagrange::Model) (or
    /// [`RawModel`](lagrange::RawModel)) behind the object-safe [`System`].
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters, or whatever the engine rejects.
    fn build(&self, params: &Params) -> Result<Box<dyn System>, Error>;

    /// Hand-coded closed-form `q̈(t, q, q̇)` (no automatic differentiation, no engine), where one
    /// exists; `None` otherwise.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters, [`Error::DimensionMismatch`] for a
    /// state of the wrong size.
    fn closed_form_accelerations(
        &self,
        params: &Params,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<Vec<f64>>, Error>;

    /// The exact state at time `t` of the motion starting at `initial`, where the motion has a
    /// closed form (constant-acceleration scenes, oscillators, Kepler orbits through Kepler's
    /// equation, the charged particle); `None` otherwise, or for initial states outside the
    /// closed form's reach (unbound Kepler orbits).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters, [`Error::DimensionMismatch`] for a
    /// state of the wrong size.
    fn exact_solution(&self, params: &Params, initial: &State, t: f64) -> Result<Option<State>, Error>;

    /// The scene's constants of the motion for these parameters, in closed form, each with
    /// why it is conserved (empty for a driven or damped scene); see [`SceneType::conserves_energy`].
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters.
    fn conserved_quantities(&self, params: &Params) -> Result<Vec<Conserved>, Error>;

    /// The scene as a joint graph with `params` ([`SceneType::joint_graph`]), if it is one.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters.
    fn joint_graph(&self, params: &Params) -> Result<Option<JointGraph>, Error>;

    /// The parameters a rapier build with multibody (`multibody`) or impulse joints changes
    /// where they are 0 ([`SceneType::rapier_deviations`]).
    fn rapier_deviations(&self, multibody: bool) -> &'static [RapierDeviation];

    /// Where the bodies are at each `(t, q)` of `states` — `(x, y, φ)` per body, in the order
    /// of the system's bodies — for a scene that no maximal description reads back
    /// (`lagrange_maximal::maps::ReadBack` places the bodies of every built-in scene); `None`
    /// by default and where the coordinates place no bodies (a raw Lagrangian).
    ///
    /// # Errors
    /// Invalid parameters, or a state of the wrong size.
    fn body_poses(&self, params: &Params, states: &[(f64, &[f64])]) -> Result<Option<Vec<Vec<[f64; 3]>>>, Error> {
        let _ = (params, states);
        Ok(None)
    }
}

/// A scene as one type: its identity, its parameter table and constructor from parameters, its
/// default state, its closed-form accelerations, exact solution and constants of the motion,
/// and how the engine runs it. Implemented by every typed scene ([`CartPendulum`](crate::CartPendulum), …); the
/// object-safe [`Scene`] is derived from it ([`scene_of`]), and the registry lists the types
/// once ([`for_each_scene!`]).
///
/// The methods that describe the system to the engine ([`generalized_coordinates`],
/// [`into_system`], [`visit`]) are written by one line, `body_scene!()` for a
/// [`Mechanism`](lagrange::Mechanism) or `raw_scene!()` for a raw
/// [`Lagrangian`](lagrange::Lagrangian).
///
/// [`generalized_coordinates`]: SceneType::generalized_coordinates
/// [`into_system`]: SceneType::into_system
/// [`visit`]: SceneType::visit
pub trait SceneType: Clone + Send + Sync + Sized + 'static {
    /// Short identifier (`cart_pendulum`), unique in [`all`].
    const ID: &'static str;
    /// Human-readable title.
    const TITLE: &'static str;
    /// Where the system and its closed forms come from.
    const REFERENCE: &'static str;
    /// The scene's own span of time (s), if it has one ([`Scene::horizon`]).
    const HORIZON: Option<f64> = None;
    /// The parameter specifications, in order.
    const PARAMS: &'static [ParamSpec];

    /// The scene with the values in `params` (read by name, checked as by the typed
    /// constructor).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first parameter outside its domain, or a
    /// parameter missing from `params` (a set built for another scene).
    fn from_params(params: &Params) -> Result<Self, Error>;

    /// Write the hand-coded closed-form `q̈(t, q, q̇)` into `qddot` (no automatic
    /// differentiation, no engine); also the scene's [`ClosedForm`].
    ///
    /// # Panics
    /// If a slice does not have the scene's number of coordinates.
    fn closed_form(&self, t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]);

    /// The scene's default initial state (at `t = 0`).
    fn default_state(&self) -> State;

    /// The exact state at time `t` of the motion starting at `initial` (whose dimensions the
    /// caller has checked), where the motion has a closed form; `None` by default.
    fn exact_solution(&self, initial: &State, t: f64) -> Option<State> {
        let _ = (initial, t);
        None
    }

    /// The constants of the motion, in closed form as functions of `(t, q, q̇)` (whose
    /// dimensions [`Conserved::value`] checks): the energy where [`Invariant::Energy`] holds,
    /// the momentum of every cyclic coordinate, and the hidden ones; none by default (a driven
    /// or damped scene).
    ///
    /// [`Invariant::Energy`]: crate::Invariant::Energy
    fn conserves_energy(&self) -> Vec<Conserved> {
        Vec::new()
    }

    /// The generalized coordinates.
    fn generalized_coordinates(&self) -> &[Coordinate];

    /// The engine's simulation of the scene.
    ///
    /// # Errors
    /// Whatever the engine rejects.
    fn into_system(self) -> Result<Box<dyn System>, Error>;

    /// Run `visitor` on the scene as a [`Mechanism`](lagrange::Mechanism); `None` for a raw
    /// [`Lagrangian`](lagrange::Lagrangian).
    fn visit<V: MechanismVisitor>(self, visitor: V) -> Option<V::Output>;

    /// The scene as bodies and joints ([`JointGraph`]), with the scene's bodies in its order and
    /// its coordinates as the graph's coordinate joints (same names, order, signs and zeros), or
    /// `None` where the scene is not a joint graph (its coordinates are the point: polar,
    /// Cartesian, rope lengths) — the default. The maximal builds (Cartesian, rapier) of a scene
    /// with a graph follow from the graph (crate `lagrange-maximal`), and the graph's reduced
    /// model is checked against the scene's own.
    fn joint_graph(&self) -> Option<JointGraph> {
        None
    }

    /// The parameters a rapier build needs changed where they are 0 — with multibody joints
    /// (`multibody`) or impulse joints — as `(parameter, mass, length)`: a compound bob
    /// `I = 1e-2 m l²` for `(inertia, mass, length)` (an impulse revolute joint freezes the
    /// rotation of a body without inertia), a massive movable pulley for `(mass, "", "")` (a
    /// massless multibody link makes the mass matrix singular); docs/rapier.md. None by
    /// default. The reference a rapier run is measured against carries the same changes.
    fn rapier_deviations(multibody: bool) -> &'static [RapierDeviation] {
        let _ = multibody;
        &[]
    }
}

/// A parameter a rapier build changes where it is 0, as `(parameter, mass, length)`
/// ([`SceneType::rapier_deviations`]): `(inertia, mass, length)` for a compound bob,
/// `(mass, "", "")` for a massive pulley.
pub type RapierDeviation = (&'static str, &'static str, &'static str);

/// [`SceneType::closed_form`] from the scene's own `closed_form_accelerations(q, q̇)`.
macro_rules! closed_form {
    () => {
        fn closed_form(&self, _t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
            qddot.copy_from_slice(&self.closed_form_accelerations(q, qdot));
        }
    };
}

/// The engine-facing methods of a [`SceneType`] that is a [`Mechanism`](lagrange::Mechanism), and
/// its closed form from `closed_form_accelerations(q, q̇)` unless told `engine` (the scene then
/// writes [`SceneType::closed_form`] itself).
macro_rules! body_scene {
    () => {
        $crate::scene::closed_form!();
        $crate::scene::body_scene!(engine);
    };
    (engine) => {
        fn generalized_coordinates(&self) -> &[lagrange::Coordinate] {
            &lagrange::Mechanism::description(self).coordinates
        }

        fn into_system(self) -> Result<Box<dyn lagrange::System>, lagrange::Error> {
            Ok(Box::new(lagrange::Buffered::new(lagrange::Model::new(self)?)))
        }

        fn visit<V: $crate::MechanismVisitor>(self, visitor: V) -> Option<V::Output> {
            Some(visitor.visit(self))
        }
    };
}

/// The engine-facing methods of a [`SceneType`] that is a raw [`Lagrangian`](lagrange::Lagrangian),
/// and its closed form from `closed_form_accelerations(q, q̇)`.
macro_rules! raw_scene {
    () => {
        $crate::scene::closed_form!();

        fn generalized_coordinates(&self) -> &[lagrange::Coordinate] {
            lagrange::Lagrangian::coordinates(self)
        }

        fn into_system(self) -> Result<Box<dyn lagrange::System>, lagrange::Error> {
            Ok(Box::new(lagrange::Buffered::new(lagrange::RawModel::new(self)?)))
        }

        fn visit<V: $crate::MechanismVisitor>(self, _visitor: V) -> Option<V::Output> {
            None
        }
    };
}

/// `impl Mechanism for $scene` by the mechanism in its field `$field` (a joint graph's reduced
/// model, or another scene's mechanism): every method of the trait forwarded, so that the
/// scene is exactly that mechanism.
macro_rules! delegate_mechanism {
    ($scene:ty, $field:ident) => {
        impl lagrange::Mechanism for $scene {
            fn description(&self) -> &lagrange::Description {
                lagrange::Mechanism::description(&self.$field)
            }

            fn poses<S: lagrange::Scalar>(&self, t: S, q: &[S], world_from_body: &mut [lagrange::Pose<S>]) {
                lagrange::Mechanism::poses(&self.$field, t, q, world_from_body);
            }

            fn potential<S: lagrange::Scalar>(
                &self,
                t: S,
                q: &[S],
                world_from_body: &[lagrange::Pose<S>],
            ) -> Option<S> {
                lagrange::Mechanism::potential(&self.$field, t, q, world_from_body)
            }

            fn generalized_force<S: lagrange::Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
                lagrange::Mechanism::generalized_force(&self.$field, t, q, qdot, force)
            }

            fn applied_forces<S: lagrange::Scalar>(
                &self,
                t: S,
                q: &[S],
                qdot: &[S],
                world_from_body: &[lagrange::Pose<S>],
                loads: &mut lagrange::Loads<'_, S>,
            ) -> bool {
                lagrange::Mechanism::applied_forces(&self.$field, t, q, qdot, world_from_body, loads)
            }

            fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut lagrange::Bounds) -> bool {
                lagrange::Mechanism::admissible(&self.$field, t, q, qdot, bounds)
            }

            fn constraints<S: lagrange::Scalar>(&self, t: S, q: &[S], phi: &mut [S]) {
                lagrange::Mechanism::constraints(&self.$field, t, q, phi);
            }

            fn velocity_constraint<S: lagrange::Scalar>(&self, t: S, q: &[S], qdot: &[S], residual: &mut [S]) {
                lagrange::Mechanism::velocity_constraint(&self.$field, t, q, qdot, residual);
            }

            fn tree(&self) -> Option<&lagrange::tree::Tree> {
                lagrange::Mechanism::tree(&self.$field)
            }
        }
    };
}

pub(crate) use {body_scene, closed_form, delegate_mechanism, raw_scene};

impl<T: SceneType> ClosedForm for T {
    fn closed_form_into(&self, t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
        self.closed_form(t, q, qdot, qddot);
    }
}

/// The object-safe [`Scene`] of a [`SceneType`]: every method builds the typed scene from the
/// parameters (validating them) and asks it.
struct Registered<T>(PhantomData<fn() -> T>);

impl<T: SceneType> Registered<T> {
    const SCENE: &'static dyn Scene = &Registered::<T>(PhantomData);
}

/// The scene type `T` as a run-time [`Scene`].
pub fn scene_of<T: SceneType>() -> &'static dyn Scene {
    Registered::<T>::SCENE
}

impl<T: SceneType> Scene for Registered<T> {
    fn id(&self) -> &'static str {
        T::ID
    }

    fn title(&self) -> &'static str {
        T::TITLE
    }

    fn reference(&self) -> &'static str {
        T::REFERENCE
    }

    fn horizon(&self) -> Option<f64> {
        T::HORIZON
    }

    fn params(&self) -> &'static [ParamSpec] {
        T::PARAMS
    }

    fn coordinates(&self, params: &Params) -> Result<Vec<Coordinate>, Error> {
        Ok(T::from_params(params)?.generalized_coordinates().to_vec())
    }

    fn default_state(&self, params: &Params) -> Result<State, Error> {
        Ok(T::from_params(params)?.default_state())
    }

    fn build(&self, params: &Params) -> Result<Box<dyn System>, Error> {
        T::from_params(params)?.into_system()
    }

    fn closed_form_accelerations(
        &self,
        params: &Params,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<Vec<f64>>, Error> {
        let scene = T::from_params(params)?;
        let n = scene.generalized_coordinates().len();
        check_dimensions(n, q, qdot)?;
        let mut qddot = vec![0.0; n];
        scene.closed_form(t, q, qdot, &mut qddot);
        Ok(Some(qddot))
    }

    fn exact_solution(&self, params: &Params, initial: &State, t: f64) -> Result<Option<State>, Error> {
        let scene = T::from_params(params)?;
        check_state(scene.generalized_coordinates().len(), initial)?;
        Ok(scene.exact_solution(initial, t))
    }

    fn conserved_quantities(&self, params: &Params) -> Result<Vec<Conserved>, Error> {
        Ok(T::from_params(params)?.conserves_energy())
    }

    fn joint_graph(&self, params: &Params) -> Result<Option<JointGraph>, Error> {
        Ok(T::from_params(params)?.joint_graph())
    }

    fn rapier_deviations(&self, multibody: bool) -> &'static [RapierDeviation] {
        T::rapier_deviations(multibody)
    }
}

macro_rules! registry {
    ($($scene:ty),*) => {
        /// Every scene, in registry order.
        static ALL: &[&dyn Scene] = &[$(Registered::<$scene>::SCENE),*];
    };
}

crate::for_each_scene!(registry);

/// Every scene: `cart_pendulum`, `harmonic_oscillator`, `kepler`, `isotropic_oscillator`,
/// `atwood`, `double_atwood`, `double_double_atwood`, `wedge`, `double_pendulum`, `chain`,
/// `spring_pendulum`, `driven_pendulum`, `charged_particle`, `nonminimal_pendulum`,
/// `chaplygin_sleigh`, `rolling_disc`, `four_bar`, `slider_crank`, `andrews_squeezer`,
/// `parallelogram_chain`, `change_point_four_bar`, `redundant_parallelogram`.
pub fn all() -> &'static [&'static dyn Scene] {
    ALL
}

/// The scenes whose default motion passes a configuration where their loop constraints lose
/// rank: `parallelogram_chain` (its flat position, from t ≈ 0.21 s) and `change_point_four_bar`
/// (its change point, from t ≈ 0.95 s). A run of their default motion needs a constrained
/// solver that follows the branch through it; registry-wide checks of default runs take them
/// in tests of their own, marked `// needs the singular-configuration solver`.
pub const SINGULAR_DEFAULT_MOTION: &[&str] = &["parallelogram_chain", "change_point_four_bar"];

/// The scene with this id, if any.
pub fn find(id: &str) -> Option<&'static dyn Scene> {
    all().iter().copied().find(|scene| scene.id() == id).or_else(|| crate::graph_scene::registered(id))
}

/// The ids of all scenes, in registry order.
pub fn ids() -> Vec<&'static str> {
    all().iter().map(|scene| scene.id()).collect()
}

/// An empty joint graph named `id` with the bodies (names, masses, inertias) and gravity of
/// `mechanism`, for a scene's [`SceneType::joint_graph`].
pub(crate) fn graph_of<M: lagrange::Mechanism>(id: &str, mechanism: &M) -> JointGraph {
    let description = mechanism.description();
    let mut graph = JointGraph::new(id, description.gravity);
    graph.bodies = description
        .bodies
        .iter()
        .map(|b| lagrange::graph::GraphBody::rigid(b.name.clone(), b.mass, b.inertia))
        .collect();
    graph
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Domain;
    use std::collections::HashSet;

    #[test]
    fn registry_order_and_lookup() {
        let expected = [
            "cart_pendulum",
            "harmonic_oscillator",
            "kepler",
            "isotropic_oscillator",
            "atwood",
            "double_atwood",
            "double_double_atwood",
            "wedge",
            "double_pendulum",
            "chain",
            "spring_pendulum",
            "driven_pendulum",
            "charged_particle",
            "nonminimal_pendulum",
            "chaplygin_sleigh",
            "rolling_disc",
            "four_bar",
            "slider_crank",
            "andrews_squeezer",
            "parallelogram_chain",
            "change_point_four_bar",
            "redundant_parallelogram",
        ];
        assert_eq!(ids(), expected);
        for id in expected {
            assert_eq!(find(id).map(|s| s.id()), Some(id));
        }
        assert!(find("pendulum").is_none());
    }

    #[test]
    fn every_scene_builds_at_its_defaults_with_consistent_shapes() {
        for scene in all() {
            let params = scene.default_params();
            let coordinates = scene.coordinates(&params).unwrap();
            let state = scene.default_state(&params).unwrap();
            let mut system = scene.build(&params).unwrap();
            let n = coordinates.len();
            assert_eq!(system.coordinates(), coordinates.as_slice(), "{}", scene.id());
            assert_eq!((state.q.len(), state.qdot.len(), state.t), (n, n, 0.0), "{}", scene.id());
            let qddot = system.accelerations(state.t, &state.q, &state.qdot).unwrap().to_vec();
            assert!(qddot.iter().all(|a| a.is_finite()), "{}: {qddot:?}", scene.id());
            let closed = scene.closed_form_accelerations(&params, state.t, &state.q, &state.qdot).unwrap();
            assert_eq!(closed.map(|a| a.len()), Some(n), "{}: every scene has a closed form", scene.id());
            // Wrong sizes are errors, not panics.
            let short = &state.q[..n - 1];
            let error = scene.closed_form_accelerations(&params, 0.0, short, &state.qdot).unwrap_err();
            assert!(matches!(error, Error::DimensionMismatch { .. }), "{}: {error}", scene.id());
            let bad = State::new(0.0, short.to_vec(), state.qdot.clone());
            let error = scene.exact_solution(&params, &bad, 1.0);
            assert!(matches!(error, Ok(None) | Err(Error::DimensionMismatch { .. })), "{}: {error:?}", scene.id());
        }
    }

    #[test]
    fn parameter_names_and_symbols_are_unique_per_scene() {
        for scene in all() {
            let names: HashSet<_> = scene.params().iter().map(|s| s.name).collect();
            let symbols: HashSet<_> = scene.params().iter().map(|s| s.symbol).collect();
            assert_eq!(names.len(), scene.params().len(), "{}", scene.id());
            assert_eq!(symbols.len(), scene.params().len(), "{}", scene.id());
            for spec in scene.params() {
                assert_eq!(spec.check(spec.default), Ok(()), "{}: default of {}", scene.id(), spec.name);
                if spec.name == "gravity" {
                    assert_eq!(
                        (spec.symbol, spec.unit, spec.default, spec.domain),
                        ("g", "m/s²", 9.81, Domain::NonNegative)
                    );
                }
            }
        }
    }

    /// Values outside each domain: NaN always; then what the domain excludes.
    fn invalid_values(domain: Domain) -> Vec<f64> {
        let mut values = vec![f64::NAN, f64::INFINITY];
        match domain {
            Domain::Positive => values.extend([0.0, -1.0]),
            Domain::NonNegative => values.push(-1.0),
            Domain::Finite => {}
            Domain::OpenInterval(low, high) => values.extend([low, high]),
            Domain::Integer { min, max } => values.extend([f64::from(min) - 1.0, f64::from(max) + 1.0, 1.5]),
        }
        values
    }

    /// The typed constructors validate every parameter themselves: values that bypass
    /// `Params::set` are still rejected by `build`, `coordinates`, and the closed forms, with
    /// the parameter named.
    #[test]
    fn constructors_reject_invalid_values_naming_the_parameter() {
        for scene in all() {
            let defaults = scene.default_params();
            let state = scene.default_state(&defaults).unwrap();
            for spec in scene.params() {
                for value in invalid_values(spec.domain) {
                    let mut params = defaults.clone();
                    assert!(params.set(spec.name, value).is_err(), "{}: set {} = {value}", scene.id(), spec.name);
                    params.set_unchecked(spec.name, value);
                    let named =
                        |error: Error| matches!(error, Error::InvalidParameter { ref name, .. } if name == spec.name);
                    let what = format!("{}: {} = {value}", scene.id(), spec.name);
                    assert!(scene.build(&params).err().is_some_and(named), "{what}: build");
                    assert!(scene.coordinates(&params).err().is_some_and(named), "{what}: coordinates");
                    let closed = scene.closed_form_accelerations(&params, 0.0, &state.q, &state.qdot);
                    assert!(closed.err().is_some_and(named), "{what}: closed form");
                }
            }
        }
    }

    /// Potentials are written through the body poses, so the engine attributes their forces to
    /// the bodies: a particle whose coordinates reach the whole plane (or, for the oscillator,
    /// a line without gravity) feels no constraint force at all.
    #[test]
    fn potential_forces_are_applied_to_the_bodies_not_left_in_the_reactions() {
        for id in ["harmonic_oscillator", "kepler", "isotropic_oscillator", "spring_pendulum"] {
            let scene = find(id).unwrap();
            let params = scene.default_params();
            let mut system = scene.build(&params).unwrap();
            let state = scene.default_state(&params).unwrap();
            let qdot: Vec<f64> = state.qdot.iter().map(|v| v + 0.3).collect();
            let reactions = system.reaction_forces(0.0, &state.q, &qdot).unwrap().unwrap().to_vec();
            // The applied forces are O(1–100) N here; the reaction is their round-off.
            crate::testing::assert_close(&format!("{id}: reaction forces"), &[0.0; 3], &reactions, 1e-12);
        }
    }

    #[test]
    fn parameters_of_another_scene_are_an_error_not_a_panic() {
        let foreign = scene_of::<crate::ChargedParticle>().default_params();
        for scene in all().iter().filter(|s| s.id() != "charged_particle") {
            let error = scene.build(&foreign).err();
            assert!(matches!(error, Some(Error::InvalidParameter { .. })), "{}: {error:?}", scene.id());
        }
    }
}
