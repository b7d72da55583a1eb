//! Every tolerance of the checks (the integration tests and the report's stability cases), with
//! where its size comes from.

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

/// The engine's `q̈` against a scene's closed form at one state, to the round-off bound of two
/// exact formulas at the mass matrix's condition number ([`conditioned`]); serialized, it is
/// `agreement` in `lagrange accel --json`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Agreement {
    /// `max_i |q̈_i − closed_i| / max_i |closed_i|` (absolute when the closed form is 0).
    pub difference: f64,
    /// The round-off bound `max(1e-12, 64 ε κ(M))`.
    pub bound: f64,
    /// `κ(M)` at the state.
    pub condition_number: f64,
    /// `difference <= bound` (a NaN difference or bound is a disagreement).
    pub agrees: bool,
}

impl Agreement {
    /// Compare `qddot` with `closed_form` at the mass matrix's condition number `kappa`.
    pub fn of(qddot: &[f64], closed_form: &[f64], kappa: f64) -> Agreement {
        let bound = conditioned(kappa);
        let scale = lagrange_testing::max_abs(closed_form);
        let residual = lagrange_testing::max_abs_diff(qddot, closed_form);
        let difference = if scale == 0.0 { residual } else { residual / scale };
        Agreement { difference, bound, condition_number: kappa, agrees: difference <= bound }
    }
}

/// Central finite differences with step `h ≈ ε^(1/3) ≈ 6e-6` (relative): truncation
/// `h² f'''/6 ≈ 6e-12` and cancellation `ε/h ≈ 4e-11` of the function's scale; 1e-8 relative
/// allows derivatives two orders of magnitude larger than the function.
pub const FINITE_DIFFERENCE: f64 = 1e-8;

/// Step of the central finite differences above.
pub const FD_STEP: f64 = 6e-6;

/// A measured stability limit against the linear theory on a *linear* problem (the undamped or
/// over-damped oscillator, the spring pendulum swinging only radially): the quantity the
/// bisection watches (energy, or the fast mode's amplitude) is multiplied by exactly
/// `|R(z)|^N` in `N` steps, so the sign of `|R| − 1` is read off to round-off and the bisection
/// brackets the boundary to its own width, 1e-12; 1e-9 leaves three orders of margin for
/// `N ε`-sized round-off in the ratio.
pub const LINEAR_STABILITY_LIMIT: f64 = 1e-9;

/// A measured stability limit against the linear theory where the criterion or the problem is
/// not exactly linear (1 %): the spring pendulum swinging (its radial frequency moves
/// by `O(θ̇²/ω²)`, 4e-3 at `k/m = 1e2`), rapier's oscillator (the criterion "energy grows two-fold
/// between the first and last tenth of the run" triggers `O(1/N)` beyond the boundary), a
/// growth threshold of 2 (`ln 2 / (14 N)` beyond it for RK4). Measured deviations: ≤ 2e-4.
pub const STABILITY_LIMIT: f64 = 1e-2;

/// Relative energy error per step of a method that conserves the quadratic energy of a linear
/// oscillator exactly (Gauss–Legendre, the implicit midpoint/variational rule): each step
/// rounds `q` and `q̇` (`ε/2` relative each, doubled in the quadratic energy) and the Newton
/// solve leaves a residual at round-off: at most 4ε per step, accumulating at worst linearly.
pub const QUADRATIC_INVARIANT_PER_STEP: f64 = 4.0 * EPS;

/// [`QUADRATIC_INVARIANT_PER_STEP`] for Gauss–Legendre at `ω h`: its stage equations
/// `(I − h A ⊗ J) δ = r` have a condition number growing like `(ω h)²` once `ω h ≫ 1`, and a
/// backward-stable solve leaves a relative error of that times ε in the stages, hence in the
/// step (measured: 5e-9 per step at ω h = 1e4, 1.8e-10 at 1e3, i.e. ≤ 0.5 ε (ω h)²).
pub fn gauss_energy_per_step(omega_h: f64) -> f64 {
    QUADRATIC_INVARIANT_PER_STEP * (omega_h * omega_h).max(1.0)
}
