//! Forces applied at points of bodies against closed forms, against the same force written by
//! hand as a generalized force, on the generic and the tree path.

use crate::error::Stage;
use crate::test_support::{RodChain, assert_relative};
use crate::tree::Tree;
use crate::{
    Description, Dynamics, Error, Loads, Mechanism, Method, Model, Output, Pose, Scalar, State, Tolerances,
    accelerations, reaction_forces, simulate,
};

const G: f64 = 9.81;

/// A pendulum (bob `m` on a rod `r`), pushed by a horizontal force `F` at the bob: either as an
/// applied force (`by_hand == false`) or as the hand-derived generalized force `Q = F r cos θ`.
#[derive(Clone, Debug)]
struct Pushed {
    description: Description,
    r: f64,
    push: f64,
    by_hand: bool,
}

impl Pushed {
    fn new(m: f64, r: f64, push: f64, by_hand: bool) -> Self {
        Self { description: Description::new().angle("θ").point("bob", m).gravity(G), r, push, by_hand }
    }
}

impl Mechanism for Pushed {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0].sin() * self.r, -q[0].cos() * self.r);
    }
    fn generalized_force<S: Scalar>(&self, _t: S, q: &[S], _qdot: &[S], force: &mut [S]) -> bool {
        if self.by_hand {
            force[0] += q[0].cos() * (self.push * self.r);
        }
        self.by_hand
    }
    fn applied_forces<S: Scalar>(
        &self,
        _t: S,
        _q: &[S],
        _qdot: &[S],
        _p: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        if !self.by_hand {
            loads.force_at_centre(0, [S::from(self.push), S::zero()]);
        }
        !self.by_hand
    }
}

/// One rod of [`RodChain`] (pivoted at its top end, angle `θ` = its orientation), with a force
/// `F` (world frame) at its lower tip and a torque `τ`; `generic` hides the tree.
#[derive(Clone, Debug)]
struct TippedRods {
    chain: RodChain,
    force: [f64; 2],
    torque: f64,
    generic: bool,
}

impl Mechanism for TippedRods {
    fn description(&self) -> &Description {
        self.chain.description()
    }
    fn poses<S: Scalar>(&self, t: S, q: &[S], p: &mut [Pose<S>]) {
        self.chain.poses(t, q, p);
    }
    fn applied_forces<S: Scalar>(
        &self,
        _t: S,
        _q: &[S],
        _qdot: &[S],
        _p: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        let last = self.chain.lengths.len() - 1;
        let tip = [S::zero(), S::from(-0.5 * self.chain.lengths[last])];
        loads.force(last, tip, [S::from(self.force[0]), S::from(self.force[1])]);
        loads.torque(last, S::from(self.torque));
        true
    }
    fn tree(&self) -> Option<&Tree> {
        if self.generic { None } else { self.chain.tree() }
    }
}

#[test]
fn a_horizontal_push_at_the_bob_matches_the_hand_derived_equation() -> Result<(), Error> {
    let (m, r, push) = (0.5, 1.2, 2.0);
    let model = Model::new(Pushed::new(m, r, push, false))?;
    assert!(model.has_applied_forces() && !model.has_generalized_force() && !model.conserves_energy());
    let mut ws = model.workspace();
    for theta in [-1.0, 0.0, 0.3, 2.5] {
        let qddot = accelerations(&model, &mut ws, 0.0, &[theta], &[0.7])?;
        // m r² θ̈ = −m g r sinθ + F r cosθ.
        let expected = (-m * G * r * f64::sin(theta) + push * r * f64::cos(theta)) / (m * r * r);
        assert_relative(qddot[0], expected, 1e-14);
    }
    Ok(())
}

#[test]
fn a_force_off_the_centre_of_mass_of_a_rod_adds_its_moment() -> Result<(), Error> {
    let (m, l) = (1.5, 0.8);
    let (force, torque) = ([0.7, -1.9], 0.45);
    for generic in [false, true] {
        let rod = TippedRods { chain: RodChain::new(&[m], &[l], G), force, torque, generic };
        let model = Model::new(rod)?;
        assert_eq!(model.uses_tree_path(), !generic);
        let mut ws = model.workspace();
        for theta in [-0.4, 0.0, 1.1, 3.0] {
            let qddot = accelerations(&model, &mut ws, 0.0, &[theta], &[0.3])?;
            // About the pivot: (I + m l²/4) θ̈ = −m g (l/2) sinθ + (tip × F) + τ, tip = l (sinθ, −cosθ).
            let (s, c) = f64::sin_cos(theta);
            let moment = l * s * force[1] + l * c * force[0];
            let expected = (-m * G * 0.5 * l * s + moment + torque) / (m * l * l / 12.0 + m * l * l / 4.0);
            assert_relative(qddot[0], expected, 1e-14);
        }
    }
    Ok(())
}

#[test]
fn the_tree_path_agrees_with_the_generic_path_on_a_pushed_chain() -> Result<(), Error> {
    let (masses, lengths) = ([1.0, 0.7, 1.3], [0.9, 1.1, 0.6]);
    let make =
        |generic| TippedRods { chain: RodChain::new(&masses, &lengths, G), force: [1.3, 0.4], torque: -0.8, generic };
    let (tree, generic) = (Model::new(make(false))?, Model::new(make(true))?);
    assert!(tree.uses_tree_path() && !generic.uses_tree_path());
    let (mut ws_tree, mut ws_generic) = (tree.workspace(), generic.workspace());
    let (q, qdot) = ([0.3, -0.5, 1.2], [0.4, 1.0, -0.7]);
    let a = accelerations(&tree, &mut ws_tree, 0.0, &q, &qdot)?.to_vec();
    let b = accelerations(&generic, &mut ws_generic, 0.0, &q, &qdot)?;
    for (x, y) in a.iter().zip(b) {
        assert_relative(*x, *y, 1e-12);
    }
    // Reactions: the same on both paths.
    let a = reaction_forces(&tree, &mut ws_tree, 0.0, &q, &qdot)?.to_vec();
    let b = reaction_forces(&generic, &mut ws_generic, 0.0, &q, &qdot)?;
    for (x, y) in a.iter().zip(b) {
        assert_relative(*x, *y, 1e-12);
    }
    Ok(())
}

#[test]
fn an_applied_force_equals_the_same_force_written_by_hand() -> Result<(), Error> {
    let (m, r, push) = (0.5, 1.2, 2.0);
    let applied = Model::new(Pushed::new(m, r, push, false))?;
    let by_hand = Model::new(Pushed::new(m, r, push, true))?;
    let (mut wa, mut wh) = (applied.workspace(), by_hand.workspace());
    let (q, qdot) = ([0.8], [-0.3]);
    let a = accelerations(&applied, &mut wa, 0.0, &q, &qdot)?[0];
    let h = accelerations(&by_hand, &mut wh, 0.0, &q, &qdot)?[0];
    assert_relative(a, h, 1e-15);
    // The applied force is not a reaction: the rod's pull alone remains. The hand-written Q acts
    // along θ and stays in the reaction (it cannot be attributed to a body).
    let ra = reaction_forces(&applied, &mut wa, 0.0, &q, &qdot)?.to_vec();
    let rh = reaction_forces(&by_hand, &mut wh, 0.0, &q, &qdot)?;
    assert_relative(ra[0], rh[0] - push, 1e-14);
    assert_relative(ra[1], rh[1], 1e-14);
    // The rod's pull points along the rod, towards the pivot: R × (bob − pivot) = 0.
    let (s, c) = f64::sin_cos(q[0]);
    assert!((ra[0] * (-c * r) - ra[1] * (s * r)).abs() < 1e-13, "{ra:?}");
    // The acceleration Jacobians of the implicit integrators.
    let (mut da, mut dh) = (applied.workspace(), by_hand.workspace());
    let (mut ja, mut jh) = ([0.0; 2], [0.0; 2]);
    applied.acceleration_jacobian(&mut da, 0.0, &q, &qdot, &mut ja)?;
    by_hand.acceleration_jacobian(&mut dh, 0.0, &q, &qdot, &mut jh)?;
    for (x, y) in ja.iter().zip(&jh) {
        assert_relative(*x, *y, 1e-14);
    }
    // Whole runs: the implicit SDIRK4 (acceleration Jacobian) and the variational integrator
    // (the model's Lagrangian view with its generalized forces).
    let start = State::new(0.0, [0.8], [-0.3]);
    for method in [Method::Sdirk4 { tol: Tolerances::uniform(1e-10) }, Method::Variational { dt: 1e-3 }] {
        let ta = simulate(&applied, &start, 1.0, method, &Output::Every(0.5))?;
        let th = simulate(&by_hand, &start, 1.0, method, &Output::Every(0.5))?;
        for (x, y) in ta.q.iter().zip(&th.q) {
            assert_relative(*x, *y, 1e-12);
        }
    }
    Ok(())
}

#[test]
fn a_zero_applied_force_leaves_every_number_unchanged() -> Result<(), Error> {
    let masses = [1.0, 0.7];
    let lengths = [0.9, 1.1];
    let (q, qdot) = ([0.3, -0.5], [0.4, 1.0]);
    for generic in [false, true] {
        let pushed = TippedRods { chain: RodChain::new(&masses, &lengths, G), force: [0.0; 2], torque: 0.0, generic };
        let plain = RodChain::new(&masses, &lengths, G);
        let (pushed, plain) = if generic {
            (Model::new(pushed)?, Model::new_generic(plain)?)
        } else {
            (Model::new(pushed)?, Model::new(plain)?)
        };
        assert!(pushed.has_applied_forces() && !plain.has_applied_forces());
        let (mut wp, mut wq) = (pushed.workspace(), plain.workspace());
        assert_eq!(accelerations(&pushed, &mut wp, 0.0, &q, &qdot)?, accelerations(&plain, &mut wq, 0.0, &q, &qdot)?);
        assert_eq!(
            reaction_forces(&pushed, &mut wp, 0.0, &q, &qdot)?,
            reaction_forces(&plain, &mut wq, 0.0, &q, &qdot)?
        );
    }
    Ok(())
}

#[test]
fn a_non_finite_applied_force_is_an_error_naming_its_stage() -> Result<(), Error> {
    let model = Model::new(Pushed::new(0.5, 1.2, f64::NAN, false))?;
    let error = accelerations(&model, &mut model.workspace(), 0.0, &[0.3], &[0.0]).unwrap_err();
    assert!(matches!(error, Error::NonFinite { stage: Stage::AppliedForce, .. }), "{error}");
    let rod = TippedRods {
        chain: RodChain::new(&[1.0], &[1.0], G),
        force: [f64::INFINITY, 0.0],
        torque: 0.0,
        generic: false,
    };
    let model = Model::new(rod)?;
    assert!(model.uses_tree_path());
    let error = accelerations(&model, &mut model.workspace(), 0.0, &[0.3], &[0.0]).unwrap_err();
    assert!(matches!(error, Error::NonFinite { stage: Stage::AppliedForce, .. }), "{error}");
    assert!(error.to_string().contains("applied force"), "{error}");
    Ok(())
}

/// A torque on a body the mechanism does not have.
#[derive(Debug)]
struct WrongBody(Description);

impl Mechanism for WrongBody {
    fn description(&self) -> &Description {
        &self.0
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0].sin(), -q[0].cos());
    }
    fn applied_forces<S: Scalar>(
        &self,
        _t: S,
        _q: &[S],
        _qdot: &[S],
        _p: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        loads.torque(1, S::one());
        true
    }
}

#[test]
fn an_applied_force_on_a_missing_body_is_a_construction_error() {
    let error = Model::new(WrongBody(Description::new().angle("θ").point("bob", 1.0))).unwrap_err();
    assert!(matches!(&error, Error::InvalidParameter { name, .. } if name == "applied force"), "{error}");
}

/// A block of mass `m` on a horizontal rail (`x`), pushed at a corner: constant `M`.
#[derive(Debug)]
struct PushedBlock {
    description: Description,
    push: [f64; 2],
}

impl Mechanism for PushedBlock {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0], S::zero());
    }
    fn applied_forces<S: Scalar>(
        &self,
        _t: S,
        _q: &[S],
        _qdot: &[S],
        _p: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        loads.force(0, [S::from(0.3), S::from(0.2)], [S::from(self.push[0]), S::from(self.push[1])]);
        true
    }
}

#[test]
fn a_constant_mass_matrix_takes_applied_forces_too() -> Result<(), Error> {
    let (m, push) = (2.5, [1.5, 4.0]);
    let description = Description::new().length("x").point("block", m).gravity(G).with_constant_mass_matrix();
    let model = Model::new(PushedBlock { description, push })?;
    assert!(model.has_constant_mass_matrix());
    let mut ws = model.workspace();
    assert_relative(accelerations(&model, &mut ws, 0.0, &[0.4], &[1.0])?[0], push[0] / m, 1e-15);
    // The rail carries the weight minus the push's vertical part.
    let reaction = reaction_forces(&model, &mut ws, 0.0, &[0.4], &[1.0])?;
    assert_relative(reaction[1], m * G - push[1], 1e-15);
    Ok(())
}
