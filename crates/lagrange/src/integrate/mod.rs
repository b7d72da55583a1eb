//! Integrators, one per file, and the driver that records trajectories.
//!
//! | integrator | order | for | guarantee |
//! |---|---|---|---|
//! | [`Rk4`] | 4, fixed step | reference workhorse | error ratio ≈ 16 per halving |
//! | [`Dopri5`] | 5(4), adaptive, dense output | accuracy on demand | local error ≤ tolerance |
//! | [`Variational`] | 2, fixed step, implicit | long runs | cyclic momenta exact, energy error bounded |

mod dopri5;
mod driver;
mod rk4;
mod variational;

pub use dopri5::{AdaptiveStats, Dopri5};
pub use driver::{Method, Output, Stats, Trajectory, simulate};
pub use rk4::Rk4;
pub use variational::Variational;

use crate::Error;

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

pub(crate) fn check_tolerance(tol: Tolerances) -> Result<(), Error> {
    for value in [tol.rtol, tol.atol] {
        if !(value > 0.0 && value.is_finite()) {
            return Err(Error::InvalidSetting { what: "tolerance", value, why: "must be positive and finite" });
        }
    }
    if tol.rtol < 1e-15 {
        return Err(Error::InvalidSetting {
            what: "tolerance",
            value: tol.rtol,
            why: "a relative tolerance below 1e-15 is below f64 round-off",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests;
