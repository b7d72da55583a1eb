//! Scenes that declare a constant mass matrix really have one: at random configurations and
//! times the full assembly (declaration withheld) gives the stored `M`, a zero convective term,
//! and the same accelerations.

use lagrange::{Description, Mechanism, Model, Pose, Scalar, State};
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, visit_mechanism};
use lagrange_tests::{max_abs, max_abs_diff, rng, sampling, tolerance};

/// The same mechanism without the declaration: the engine assembles everything.
#[derive(Clone)]
struct Undeclared<M> {
    mechanism: M,
    /// The mechanism's coordinates, bodies and gravity, nothing else declared.
    description: Description,
}

impl<M: Mechanism> Undeclared<M> {
    fn new(mechanism: M) -> Self {
        let of = mechanism.description();
        let description = Description {
            coordinates: of.coordinates.clone(),
            bodies: of.bodies.clone(),
            gravity: of.gravity,
            ..Description::default()
        };
        Self { mechanism, description }
    }
}

impl<M: Mechanism> Mechanism for Undeclared<M> {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, t: S, q: &[S], p: &mut [Pose<S>]) {
        self.mechanism.poses(t, q, p)
    }
    fn potential<S: Scalar>(&self, t: S, q: &[S], p: &[Pose<S>]) -> Option<S> {
        self.mechanism.potential(t, q, p)
    }
    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], v: &[S], f: &mut [S]) -> bool {
        self.mechanism.generalized_force(t, q, v, f)
    }
}

struct Check<'a> {
    states: &'a [State],
}

impl MechanismVisitor for Check<'_> {
    type Output = bool;

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) -> bool {
        if !mechanism.description().constant_mass_matrix {
            return false;
        }
        let declared = Model::new(mechanism.clone()).expect("valid");
        let assembled = Model::new(Undeclared::new(mechanism)).expect("valid");
        assert!(declared.has_constant_mass_matrix() && !assembled.has_constant_mass_matrix());
        let (mut wd, mut wa) = (declared.workspace(), assembled.workspace());
        for s in self.states {
            let stored = lagrange::mass_matrix(&declared, &mut wd, s.t, &s.q, &s.qdot).expect("valid").to_vec();
            let full = lagrange::mass_matrix(&assembled, &mut wa, s.t, &s.q, &s.qdot).expect("valid").to_vec();
            assert!(max_abs_diff(&stored, &full) <= tolerance::ROUNDOFF * max_abs(&stored), "M {stored:?} vs {full:?}");
            let a = lagrange::accelerations(&declared, &mut wd, s.t, &s.q, &s.qdot).expect("valid").to_vec();
            let b = lagrange::accelerations(&assembled, &mut wa, s.t, &s.q, &s.qdot).expect("valid").to_vec();
            assert!(max_abs_diff(&a, &b) <= tolerance::ROUNDOFF * max_abs(&a).max(1e-300), "q̈ {a:?} vs {b:?}");
            // The convective term of the full assembly vanishes identically (affine poses).
            assert!(wa.convective.iter().all(|g| *g == 0.0), "γ = {:?}", wa.convective);
        }
        true
    }
}

#[test]
fn declared_constant_mass_matrices_are_constant() {
    let mut declared = Vec::new();
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(8000 + index as u64);
        let params = sampling::regular_params(*scene, &mut rng);
        let states: Vec<State> = (0..10).map(|k| sampling::state(*scene, &params, &mut rng, k)).collect();
        if visit_mechanism(scene.id(), &params, Check { states: &states }).expect("valid") == Some(true) {
            declared.push(scene.id());
        }
    }
    // The lecture's scenes with affine kinematics.
    for id in ["harmonic_oscillator", "atwood", "double_atwood", "double_double_atwood", "wedge"] {
        assert!(declared.contains(&id), "{id} does not declare a constant mass matrix ({declared:?})");
    }
}

#[test]
fn a_false_declaration_is_refused() {
    /// A pendulum that wrongly claims a constant mass matrix.
    #[derive(Clone)]
    struct Liar {
        description: Description,
    }
    impl Mechanism for Liar {
        fn description(&self) -> &Description {
            &self.description
        }
        fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
            p[0] = Pose::point(q[0].sin(), -q[0].cos());
        }
    }
    let liar = Liar { description: Description::new().angle("θ").point("bob", 1.0).with_constant_mass_matrix() };
    assert!(matches!(Model::new(liar), Err(lagrange::Error::Inconsistent { .. })));
}
