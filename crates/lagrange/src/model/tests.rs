//! Construction turns silent wrong answers into typed errors.

use crate::error::Derived;
use crate::test_support::{Driven, cart, driven};
use crate::{Coordinate, Description, Error, Mechanism, Model, Pose, Scalar};

/// The cart pendulum's poses, forgetting the cart.
#[derive(Debug)]
struct WithoutCart(Description, f64);

impl Mechanism for WithoutCart {
    fn description(&self) -> &Description {
        &self.0
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[1] = Pose::point(q[0] + q[1].sin() * self.1, -q[1].cos() * self.1);
    }
}

#[test]
fn a_body_the_poses_forget_is_an_error_naming_it() {
    let whole = cart(2.0, 1.0, 1.5);
    let error = Model::new(WithoutCart(whole.description.clone(), 1.5)).unwrap_err();
    assert!(matches!(&error, Error::UnwrittenPose { body, component: "x", .. } if body == "cart"), "{error}");
    assert!(error.to_string().contains("body `cart`"), "{error}");
    // The whole mechanism is fine.
    assert!(Model::new(whole).is_ok());
}

/// The driven pendulum's poses, reading the real part of the time or of the angle.
#[derive(Debug)]
struct ReadsRealPart {
    driven: Driven,
    time: bool,
}

impl Mechanism for ReadsRealPart {
    fn description(&self) -> &Description {
        &self.driven.description
    }
    fn poses<S: Scalar>(&self, t: S, q: &[S], p: &mut [Pose<S>]) {
        let d = &self.driven;
        let pivot =
            if self.time { S::from((t.re() * d.omega).sin() * d.amplitude) } else { (t * d.omega).sin() * d.amplitude };
        let theta = if self.time { q[0] } else { S::from(q[0].re()) };
        p[0] = Pose::point(pivot + theta.sin() * d.r, -theta.cos() * d.r);
    }
}

#[test]
fn poses_that_read_the_real_part_are_an_error_naming_body_component_and_variable() {
    let d = Driven::new();
    let error = Model::new(ReadsRealPart { driven: d.clone(), time: true }).unwrap_err();
    assert!(
        matches!(&error, Error::LostDerivative { of: Derived::Pose { body, component: "x" }, variable, exact, .. }
            if body == "bob" && variable == "t" && *exact == 0.0),
        "{error}"
    );
    let error = Model::new(ReadsRealPart { driven: d, time: false }).unwrap_err();
    assert!(
        matches!(&error, Error::LostDerivative { of: Derived::Pose { body, component: "x" }, variable, .. }
            if body == "bob" && variable == "θ"),
        "{error}"
    );
    // Reading the time as the scalar it is passes.
    assert!(Model::new(driven()).is_ok());
}

/// The cart pendulum's poses with the pendulum's angle read as a constant in the bob's `y`
/// only (its `x` keeps the derivative): one dropped entry among four.
#[derive(Debug)]
struct CartDropsAngleInY(Description, f64);

impl Mechanism for CartDropsAngleInY {
    fn description(&self) -> &Description {
        &self.0
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0], S::zero());
        p[1] = Pose::point(q[0] + q[1].sin() * self.1, -S::from(q[1].re().cos()) * self.1);
    }
}

/// The test of the poses' derivatives runs along one direction mixing every coordinate; a
/// single dropped entry of the Jacobian among several coordinates and bodies is still found,
/// and named by body, component and coordinate.
#[test]
fn one_lost_entry_among_several_coordinates_is_named() {
    let whole = cart(2.0, 1.0, 1.5);
    let error = Model::new(CartDropsAngleInY(whole.description.clone(), 1.5)).unwrap_err();
    assert!(
        matches!(&error, Error::LostDerivative { of: Derived::Pose { body, component: "y" }, variable, .. }
            if body == "bob" && variable == "θ"),
        "{error}"
    );
}

/// A Lagrangian whose kinetic term is negative: `L = −½ q̇²`.
#[derive(Debug)]
struct NegativeKinetic([Coordinate; 1]);

impl crate::Lagrangian for NegativeKinetic {
    fn coordinates(&self) -> &[Coordinate] {
        &self.0
    }
    fn lagrangian<S: Scalar>(&self, _t: S, _q: &[S], qdot: &[S]) -> S {
        -(qdot[0] * qdot[0] * 0.5)
    }
}

#[test]
fn a_negative_definite_raw_lagrangian_is_refused_at_construction_as_indefinite() {
    let error = crate::RawModel::new(NegativeKinetic([Coordinate::length("x")])).unwrap_err();
    assert!(
        matches!(&error, Error::IndefiniteMassMatrix { coordinate, pivot, .. } if coordinate == "x" && *pivot == -1.0),
        "{error}"
    );
    let message = error.to_string();
    assert!(message.contains("indefinite") && !message.contains("not independent"), "{message}");
}

#[test]
fn the_energy_function_and_the_total_energy_differ_for_a_rheonomic_mechanism() {
    // The driven pendulum without its spring and damper: h = T + V − ẋ_p m r θ̇ cosθ − m ẋ_p².
    let model = Model::new(Driven { k: 0.0, c: 0.0, ..Driven::new() }).unwrap();
    let mut ws = model.workspace();
    let (t, q, qdot) = (0.3, [0.4], [0.7]);
    let h = crate::energy_function(&model, &mut ws, t, &q, &qdot).unwrap();
    let e = crate::total_energy(&model, &mut ws, t, &q, &qdot).unwrap();
    let d = Driven::new();
    let (m, r) = (d.m, d.r);
    let xdot_p = d.amplitude * d.omega * (d.omega * t).cos();
    // h = q̇ p − L = T + V − (ẋ_p² m + ẋ_p m r θ̇ cosθ), since p = m r² θ̇ + m r ẋ_p cosθ.
    let expected = e - m * xdot_p * (xdot_p + r * qdot[0] * q[0].cos());
    approx::assert_relative_eq!(h, expected, max_relative = 1e-14);
    assert!((h - e).abs() > 0.01);
}

#[test]
fn the_body_and_raw_paths_answer_to_the_same_names() -> Result<(), Error> {
    let model = Model::new(cart(2.0, 1.0, 1.5))?;
    let raw = crate::RawModel::new(Model::new(cart(2.0, 1.0, 1.5))?)?;
    let (t, q, qdot) = (0.0, [0.2, 0.7], [-0.4, 0.9]);
    let (mut ws, mut raw_ws) = (model.workspace(), raw.workspace());
    // Each function, the same spelling for both models, agrees to round-off.
    let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| (a - b).abs() <= 1e-14 * b.abs().max(1.0));
    let body = crate::mass_matrix(&model, &mut ws, t, &q, &qdot)?.to_vec();
    assert!(close(crate::mass_matrix(&raw, &mut raw_ws, t, &q, &qdot)?, &body), "{body:?}");
    let body = crate::accelerations(&model, &mut ws, t, &q, &qdot)?.to_vec();
    assert!(close(crate::accelerations(&raw, &mut raw_ws, t, &q, &qdot)?, &body), "{body:?}");
    let body = crate::momenta(&model, &mut ws, t, &q, &qdot)?.to_vec();
    assert!(close(crate::momenta(&raw, &mut raw_ws, t, &q, &qdot)?, &body), "{body:?}");
    let body =
        [crate::energy_function(&model, &mut ws, t, &q, &qdot)?, crate::lagrangian(&model, &mut ws, t, &q, &qdot)?];
    let raw_values =
        [crate::energy_function(&raw, &mut raw_ws, t, &q, &qdot)?, crate::lagrangian(&raw, &mut raw_ws, t, &q, &qdot)?];
    assert!(close(&raw_values, &body), "{raw_values:?} vs {body:?}");
    // Both check q̇, also where the body path does not use it.
    for short in
        [crate::mass_matrix(&model, &mut ws, t, &q, &[0.0]), crate::mass_matrix(&raw, &mut raw_ws, t, &q, &[0.0])]
    {
        assert!(matches!(short, Err(Error::DimensionMismatch { .. })));
    }
    // Both allocate a workspace in any scalar.
    let (mut dual, mut raw_dual) = (model.workspace_in::<num_dual::Dual64>(), raw.workspace_in::<num_dual::Dual64>());
    let lift = |x: &[f64]| x.iter().map(|&v| num_dual::Dual64::from(v)).collect::<Vec<_>>();
    let (qd, vd) = (lift(&q), lift(&qdot));
    let a = crate::accelerations(&model, &mut dual, t.into(), &qd, &vd)?[0].re;
    let b = crate::accelerations(&raw, &mut raw_dual, t.into(), &qd, &vd)?[0].re;
    assert!((a - b).abs() <= 1e-14 * a.abs().max(1.0), "{a} vs {b}");
    Ok(())
}
