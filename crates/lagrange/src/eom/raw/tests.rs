//! Construction of a raw model turns silent wrong answers into typed errors, as for a body
//! model: a Lagrangian that is not finite, that loses a derivative, or whose `∂²L/∂q̇²` is not
//! positive definite.

use crate::error::{Derived, Stage};
use crate::test_support::{Charge, Spring, cart, driven};
use crate::{Coordinate, Error, Lagrangian, Model, RawModel, Scalar};

/// A charge in the plane in a magnetic field `B(t) = B₀ (1 + ½ sin ωt)` along `z` and an
/// electric potential `φ = ½ k x²`: `L = ½ m |v|² + (e B(t)/2)(x ẏ − y ẋ) − e φ(x)`. Each flag
/// makes it read the real part of one variable, as a user might by mistake (`x\u{307}` is `ẋ`,
/// the name of `x`'s velocity in the error).
#[derive(Debug)]
struct FieldCharge {
    coordinates: [Coordinate; 2],
    reads: Option<&'static str>,
}

impl FieldCharge {
    fn new(reads: Option<&'static str>) -> Self {
        Self { coordinates: [Coordinate::length("x"), Coordinate::length("y")], reads }
    }
}

impl Lagrangian for FieldCharge {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn lagrangian<S: Scalar>(&self, t: S, q: &[S], qdot: &[S]) -> S {
        let (m, e, b0, omega, k) = (2.0, 0.5, 3.0, 1.5, 4.0);
        let field = match self.reads {
            Some("t") => S::from(b0 * (1.0 + 0.5 * (t.re() * omega).sin())),
            _ => ((t * omega).sin() * 0.5 + 1.0) * b0,
        };
        let x = if self.reads == Some("x") { S::from(q[0].re()) } else { q[0] };
        let vx = if self.reads == Some("x\u{307}") { S::from(qdot[0].re()) } else { qdot[0] };
        let kinetic = (vx * qdot[0] + qdot[1] * qdot[1]) * (0.5 * m);
        kinetic + field * (q[0] * qdot[1] - q[1] * qdot[0]) * (0.5 * e) - x * x * (0.5 * e * k)
    }
}

#[test]
fn a_lagrangian_that_reads_the_real_part_is_an_error_naming_the_variable() {
    for variable in ["t", "x", "x\u{307}"] {
        let error = RawModel::new(FieldCharge::new(Some(variable))).unwrap_err();
        assert!(
            matches!(&error, Error::LostDerivative { of: Derived::Lagrangian, variable: v, .. } if v == variable),
            "{variable}: {error}"
        );
        let message = error.to_string();
        assert!(message.contains("the Lagrangian") && message.contains(&format!("`{variable}.re()`")), "{message}");
    }
    // Reading every variable as the scalar it is passes.
    let raw = RawModel::new(FieldCharge::new(None)).unwrap();
    assert!(!raw.is_autonomous());
}

/// `L = ½ m ẋ² + s ½ m ẏ² + (x ẏ − y ẋ)`: kinetic terms of mixed sign (`s = −1`), or no
/// kinetic term along `y` (`s = 0`).
#[derive(Debug)]
struct Signs {
    coordinates: [Coordinate; 2],
    s: f64,
}

impl Lagrangian for Signs {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], qdot: &[S]) -> S {
        qdot[0] * qdot[0] * 0.5 + qdot[1] * qdot[1] * (0.5 * self.s) + q[0] * qdot[1] - q[1] * qdot[0]
    }
}

fn signs(s: f64) -> Signs {
    Signs { coordinates: [Coordinate::length("x"), Coordinate::length("y")], s }
}

#[test]
fn mixed_kinetic_signs_are_indefinite_and_a_missing_one_singular() {
    let error = RawModel::new(signs(-1.0)).unwrap_err();
    assert!(
        matches!(&error, Error::IndefiniteMassMatrix { coordinate, pivot, diagonal, .. }
            if coordinate == "y" && *pivot == -1.0 && *diagonal == -1.0),
        "{error}"
    );
    let error = RawModel::new(signs(0.0)).unwrap_err();
    assert!(matches!(&error, Error::SingularMassMatrix { coordinate, .. } if coordinate == "y"), "{error}");
    assert!(RawModel::new(signs(1.0)).is_ok());
}

/// `L = ½ ẋ² − ln(x − 2)`: not defined (NaN) for `x < 2`, where the probe states are.
#[derive(Debug)]
struct Infinite([Coordinate; 1]);

impl Lagrangian for Infinite {
    fn coordinates(&self) -> &[Coordinate] {
        &self.0
    }
    fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], qdot: &[S]) -> S {
        qdot[0] * qdot[0] * 0.5 - (q[0] - 2.0).ln()
    }
}

#[test]
fn a_lagrangian_that_is_not_finite_is_an_error() {
    let error = RawModel::new(Infinite([Coordinate::length("x")])).unwrap_err();
    assert!(matches!(error, Error::NonFinite { stage: Stage::Lagrangian, .. }), "{error}");
}

/// The raw models the crate's tests use all pass the checks: the charge in a magnetic field
/// and the Lagrangians of body models (scleronomic, rheonomic, damped).
#[test]
fn the_existing_raw_models_still_construct() {
    let xy = [Coordinate::length("x"), Coordinate::length("y")];
    for (m, e_b) in [(2.0, 3.0), (1.0, 0.0), (0.5, -4.0)] {
        RawModel::new(Charge { coordinates: xy.clone(), m, e_b }).unwrap();
    }
    RawModel::new(Model::new(cart(2.0, 1.0, 1.3)).unwrap()).unwrap();
    RawModel::new(Model::new(driven()).unwrap()).unwrap();
    RawModel::new(Model::new(Spring::new(1.5, 7.0, 0.3)).unwrap()).unwrap();
}
