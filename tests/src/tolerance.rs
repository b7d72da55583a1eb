//! Every tolerance of the integration tests, with where its size comes from.

/// Machine epsilon.
pub const EPS: f64 = f64::EPSILON;

/// Relative agreement of two exact formulas for the same quantity evaluated in floating point
/// at a well-conditioned state (engine vs closed form, raw vs body path): each side carries a
/// few tens of rounding errors (assembly sums over bodies and coordinates, a small solve), so
/// 1e-12 ≈ 4500 ε leaves a margin of two orders of magnitude.
pub const ROUNDOFF: f64 = 1e-12;

/// Round-off bound for a solve with a mass matrix of condition number `kappa`: the perturbation
/// bound `‖δx‖/‖x‖ ≤ κ (‖δM‖/‖M‖ + ‖δf‖/‖f‖)` with assembly errors of order 32 ε for each of
/// `M` and `f` (sums of a few dozen products), never below [`ROUNDOFF`].
pub fn conditioned(kappa: f64) -> f64 {
    ROUNDOFF.max(64.0 * EPS * kappa)
}

/// Central finite differences with step `h ≈ ε^(1/3) ≈ 6e-6` (relative): truncation
/// `h² f'''/6 ≈ 6e-12` and cancellation `ε/h ≈ 4e-11` of the function's scale; 1e-8 relative
/// allows derivatives two orders of magnitude larger than the function.
pub const FINITE_DIFFERENCE: f64 = 1e-8;

/// Step of the central finite differences above.
pub const FD_STEP: f64 = 6e-6;
