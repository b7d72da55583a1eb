//! The Newton iterations of the implicit integrators: a value that stops being finite inside
//! one is a divergence that names it, never a Newton failure with a residual of NaN.

use super::*;
use crate::{Coordinate, Lagrangian, RawModel, Scalar, State};

/// `L = ½ ẋ² − 1/x`: an attraction whose potential is infinite at `x = 0`.
struct InverseDistance {
    coordinates: [Coordinate; 1],
}

impl Lagrangian for InverseDistance {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], v: &[S]) -> S {
        v[0] * v[0] * 0.5 - q[0].recip()
    }
}

/// From `x = 1` at `ẋ = −10` with `dt = 0.2`, the predictor of the first step puts the midpoint
/// at `x = 1 − 10 · 0.1 = 0` exactly, where `∂L/∂x = 1/x²` is infinite: the error names it
/// and the Newton iteration.
#[test]
fn a_non_finite_derivative_inside_variational_newton_is_named() {
    let raw = RawModel::new(InverseDistance { coordinates: [Coordinate::length("x")] }).unwrap();
    let initial = State::new(0.0, [1.0], [-10.0]);
    let result = simulate(&raw, &initial, 1.0, Method::Variational { dt: 0.2 }, &Output::Ends);
    match result {
        Err(Error::Diverged { t, step, quantity }) => {
            assert_eq!((t, step), (0.0, 0));
            assert_eq!(quantity, "∂L/∂q[x] = inf in Newton iteration 1 of the variational integrator");
        }
        other => panic!("{other:?}"),
    }
}
