//! Integrators, one per file, behind one stepping trait, and the driver that runs them.
//!
//! Every integrator implements [`Integrator`]: [`begin`](Integrator::begin) at a state,
//! [`advance`](Integrator::advance) one step toward an output time,
//! [`read`](Integrator::read) the state there (by dense output where the method has one:
//! [`Dopri5`]), and report its work as one [`Stats`]. The driver [`run`] is one loop over the
//! output times writing [`Sample`]s into a [`Sink`] (a [`Trajectory`] is one; the energy is
//! evaluated only for a sink that asks for it); [`simulate`] runs a [`Method`] into a
//! [`Trajectory`]. Each integrator also keeps its own lower-level calls (`step`, `start`, …)
//! for callers that drive it themselves.
//!
//! [`Method`] names an integrator with its step or tolerance and parses and prints itself
//! (`rk4:0.001`, `dopri5:1e-10`); [`MethodKind::ALL`] is the one list of the methods, which
//! the command line and the validation report reuse.
//!
//! | integrator | order | for | guarantee |
//! |---|---|---|---|
//! | [`Rk4`] | 4, fixed step | reference workhorse | error ratio ≈ 16 per halving |
//! | [`Dopri5`] | 5(4), adaptive, dense output | accuracy on demand | local error ≤ tolerance |
//! | [`Dop853`] | 8(5,3), adaptive, dense output of order 7 | tight tolerances (1e-10 and below) | local error ≤ tolerance, order 8 |
//! | [`Variational`] | 2, fixed step, implicit | long runs | cyclic momenta exact, energy error bounded |
//! | [`Gauss4`] | 4, fixed step, implicit (Gauss–Legendre) | long runs | symplectic, A-stable; quadratic invariants to round-off |
//! | [`Sdirk4`] | 4(3), adaptive, L-stable implicit | stiff scenes | stable at `ω h ≫ 1`, stiff modes damped, error tracks tolerance |
//!
//! The implicit methods solve their stages by simplified Newton with the exact AD Jacobian
//! [`Dynamics::acceleration_jacobian`](crate::Dynamics::acceleration_jacobian), in the reduced
//! form (docs/method.md#the-newton-step-shared-by-the-implicit-methods). The error-controlled methods ([`Dopri5`], [`Sdirk4`]) share one step-size
//! controller: the scaled error norm, the first step and PI control. [`Dopri5`] watches for stiffness (Hairer's test) and says so when it
//! fails ([`Error::Stiff`]).

mod control;
mod dop853;
mod dopri5;
mod driver;
mod gauss;
mod integrator;
mod method;
pub(crate) mod newton;
mod rk4;
mod sdirk;
mod variational;

pub use dop853::Dop853;
pub use dopri5::Dopri5;
pub use driver::{Output, Sample, Sink, Trajectory, run, simulate, simulate_into};
pub use gauss::Gauss4;
pub(crate) use integrator::Grid;
pub use integrator::{Integrator, Stats};
pub use method::{Method, MethodKind, ParseMethodError};
pub use rk4::Rk4;
pub use sdirk::Sdirk4;
pub use variational::Variational;

use crate::{Coordinate, Error};

/// Relative and absolute tolerances of an adaptive integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

impl Tolerances {
    /// The same value for both.
    pub fn uniform(tol: f64) -> Self {
        Self { rtol: tol, atol: tol }
    }
}

pub(crate) fn check_step(h: f64) -> Result<(), Error> {
    if h > 0.0 && h.is_finite() {
        Ok(())
    } else {
        Err(Error::InvalidSetting { what: "step", value: h, why: "must be positive and finite" })
    }
}

/// The smallest relative tolerance accepted, `10 ε ≈ 2.2e-15`: one step of any method rounds
/// its result by about `ε |y|`, so an error estimate below a few `ε` is rounding noise that the
/// step-size control would chase, and the implicit method's Newton test already stops at `10 ε`
/// in the tolerance-scaled norm ([`Sdirk4`]) — a tolerance at or below it asks for iterates no
/// more accurate than the tolerance itself (Hairer and Wanner's RADAU5 refuses the same range).
pub const MIN_RELATIVE_TOLERANCE: f64 = 10.0 * f64::EPSILON;

/// Positive, finite tolerances whose relative part lies in `[10 ε, 1)`
/// ([`MIN_RELATIVE_TOLERANCE`]): at 1 and above a step may be wrong by the size of the state
/// itself, so no digit of the result is correct.
pub(crate) fn check_tolerance(tol: Tolerances) -> Result<(), Error> {
    for value in [tol.rtol, tol.atol] {
        if !(value > 0.0 && value.is_finite()) {
            return Err(Error::InvalidSetting { what: "tolerance", value, why: "must be positive and finite" });
        }
    }
    if tol.rtol >= 1.0 {
        return Err(Error::InvalidSetting {
            what: "tolerance",
            value: tol.rtol,
            why: "a relative tolerance must lie in [2.2e-15, 1): at 1 and above a step may be wrong by the whole \
                  state, so no digit of the result is correct",
        });
    }
    if tol.rtol < MIN_RELATIVE_TOLERANCE {
        return Err(Error::InvalidSetting {
            what: "tolerance",
            value: tol.rtol,
            why: "a relative tolerance must lie in [2.2e-15, 1): below 10 ε ≈ 2.2e-15 the error estimate is f64 \
                  rounding noise, which no step size can reduce",
        });
    }
    Ok(())
}

/// The first non-finite entry of a state, named: `q[θ] = inf`, `q̇[x] = NaN`.
pub(crate) fn non_finite_quantity(coordinates: &[Coordinate], q: &[f64], qdot: &[f64]) -> Option<String> {
    let name = |i: usize| coordinates.get(i).map_or_else(|| i.to_string(), |c| c.name.clone());
    if let Some(i) = q.iter().position(|v| !v.is_finite()) {
        return Some(format!("q[{}] = {}", name(i), q[i]));
    }
    let i = qdot.iter().position(|v| !v.is_finite())?;
    Some(format!("q̇[{}] = {}", name(i), qdot[i]))
}

#[cfg(test)]
mod tests;
