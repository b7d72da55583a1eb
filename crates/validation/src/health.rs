//! A run's check of itself: every constant of the motion its scene declares, and its
//! constraints, against the error its own method, tolerance or step can be expected to make.
//!
//! A run that passes says nothing of chaos (two runs of a double pendulum part however well
//! each keeps its energy); a run that fails did not resolve the motion — a tolerance too loose,
//! a step too large for the fastest rate the motion reaches, a blow-up — and its numbers are
//! not to be trusted. `lagrange simulate` exits 1 on a failed check (0 with a warning under
//! `--allow-drift`).
//!
//! **The expected error.** [`expected_error`] bounds the error of the state relative to its
//! size, `e`:
//! - error-controlled methods (adaptive, DOP853, implicit) keep each step's local error below
//!   `tol` relative to the state; in the worst case the steps' errors add up: `e = 10 N tol`
//!   over `N` steps (a factor 5 over `2 N tol` for the dense output between steps and for
//!   states of order one, where the absolute part of the tolerance counts as much);
//! - fixed steps: an order-`p` method's local error is `O((ω h)^{p+1})` with `ω` the fastest
//!   rate of the motion ([`fastest_rate`], the largest over 64 samples spread over the run). RK4 is not
//!   symplectic, its errors accumulate: `e = 10 N (ω h)⁵`. The variational (order 2) and Gauss
//!   (order 4) integrators are symplectic: their error in a constant of the motion stays
//!   bounded, `e = 10 (ω h)^p`, however long the run; plus `10 N ε` for round-off.
//!
//! Whatever these allow, `e` is capped at [`LARGEST_RELATIVE_DRIFT`]: the estimates lose their
//! meaning once `ω h` approaches 1 or `N tol` a thousandth.
//!
//! **A constant of the motion** `I` ([`Conserved`]) may drift by `e S`, where
//! `S = Σ_i |∂I/∂y_i| (1 + |y_i|)` over `y = (q, q̇)` (central differences, the largest over 64
//! samples spread over the run; an angle counts up to π, since an error of a radian means the same after any number
//! of turns): how much errors of relative size `e` in every component of the state move `I`.
//! This includes `E − τ θ` and the other integrals of forced scenes, which the engine's energy
//! function does not see.
//!
//! **The constraints** may be violated by `max(e, 1e-9) (1 + max |y|)`: the projected
//! integrators hold them to round-off; the variational one to its Newton tolerance.

use lagrange::{Method, System, Trajectory};
use lagrange_scenes::{Conserved, Params, Scene};

/// The largest drift of a constant of the motion, relative to its scale `S`, that any run
/// passes, whatever its method's error estimate allows: a drift of `δ S` means a relative
/// error of the state of at least `δ`, and at a thousandth the trajectory is already visibly
/// wrong (measured: Andrews' squeezer by RK4 at its default step 1e-3 drifts 7e-3 of `S` and
/// ends 1.3 rad off; the driven four-bar at tol 1e-3, 8e-2 and 22 % off in speed), while the
/// estimates above overstate `e` by the ratio of a row-sum norm to the spectral radius.
pub const LARGEST_RELATIVE_DRIFT: f64 = 1e-3;

/// The smallest bound on the constraint violation relative to the state's size: above the
/// Newton tolerance of the implicit and variational methods (1e-12 … 1e-10) with a margin.
pub const CONSTRAINT_FLOOR: f64 = 1e-9;

/// Samples at which the fastest rate of the motion and the constants' scales are evaluated
/// (evenly spread over the run, and its last).
const SPREAD_SAMPLES: usize = 64;

/// One quantity a run failed to keep.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// What drifted: a constant's symbol (`E`, `E − τ θ₂`) or `max |Φ|`, `max |Φ̇|`.
    pub quantity: String,
    /// Its largest drift over the samples (absolute, in its own units).
    pub drift: f64,
    /// The bound it exceeded.
    pub bound: f64,
    /// The first sample time at which it was beyond the bound.
    pub since: f64,
}

impl std::fmt::Display for Finding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // The time to 12 significant digits: a sample time `k · every` carries the rounding of
        // the product (`2.9185000000000003`).
        let since: f64 = format!("{:.11e}", self.since).parse().unwrap_or(self.since);
        write!(
            f,
            "{} drifted by {:.3e} (bound {:.2e}), beyond its bound from t = {since}",
            self.quantity, self.drift, self.bound
        )
    }
}

/// What a run's check of itself found.
#[derive(Clone, Debug, PartialEq)]
pub struct Health {
    /// The expected relative error `e` of the run ([`expected_error`]).
    pub expected: f64,
    /// The quantities checked, by name.
    pub checked: Vec<String>,
    /// The ones beyond their bound; empty for a healthy run.
    pub findings: Vec<Finding>,
}

impl Health {
    /// Whether every check passed.
    pub fn is_healthy(&self) -> bool {
        self.findings.is_empty()
    }
}

/// The fastest rate of the motion at `(t, q, q̇)`, `ω` (1/s): from the acceleration Jacobian,
/// `√‖∂q̈/∂q‖∞ + ‖∂q̈/∂q̇‖∞` — the row-sum norms bound the spectral radii, so this bounds the
/// frequency of the stiffest linearized mode plus its damping rate. `None` where the Jacobian
/// cannot be evaluated.
pub fn fastest_rate(system: &mut dyn System, t: f64, q: &[f64], qdot: &[f64]) -> Option<f64> {
    let n = q.len();
    let jacobian = system.acceleration_jacobian(t, q, qdot).ok()?;
    let row_sum = |columns: std::ops::Range<usize>| {
        (0..n).map(|i| columns.clone().map(|j| jacobian[i * 2 * n + j].abs()).sum::<f64>()).fold(0.0, f64::max)
    };
    let rate = row_sum(0..n).sqrt() + row_sum(n..2 * n);
    rate.is_finite().then_some(rate)
}

/// The relative error `e` a run of `method` over `steps` steps is expected to stay below, with
/// `rate` the fastest rate of its motion (needed by the fixed-step methods only; `None` gives
/// [`LARGEST_RELATIVE_DRIFT`]). See the module's documentation.
pub fn expected_error(method: Method, steps: usize, rate: Option<f64>) -> f64 {
    let n = steps.max(1) as f64;
    let round_off = 10.0 * n * f64::EPSILON;
    let fixed = |power: i32, accumulates: bool| {
        rate.map_or(LARGEST_RELATIVE_DRIFT, |w| {
            let dt = match method {
                Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt } => dt,
                Method::Dopri5 { .. } | Method::Dop853 { .. } | Method::Sdirk4 { .. } => 0.0,
            };
            10.0 * if accumulates { n } else { 1.0 } * (w * dt).powi(power) + round_off
        })
    };
    let e = match method {
        Method::Dopri5 { tol } | Method::Dop853 { tol } | Method::Sdirk4 { tol } => 10.0 * n * tol.rtol.max(tol.atol),
        Method::Rk4 { .. } => fixed(5, true),
        Method::Variational { .. } => fixed(2, false),
        Method::Gauss4 { .. } => fixed(4, false),
    };
    if e.is_finite() { e.min(LARGEST_RELATIVE_DRIFT) } else { LARGEST_RELATIVE_DRIFT }
}

/// `value > bound`, or NaN (a NaN drift is beyond any bound).
fn beyond(value: f64, bound: f64) -> bool {
    value.is_nan() || value > bound
}

/// The scale `S = Σ_i |∂I/∂y_i| (1 + |y_i|)` of a constant `I` at `(t, q, q̇)` (central
/// differences with steps `1e-6 (1 + |y_i|)`; an angle's `|y_i|` counts up to π); non-finite
/// values count as zero.
fn sensitivity(quantity: &Conserved, angles: &[bool], t: f64, q: &[f64], qdot: &[f64]) -> f64 {
    let n = q.len();
    let mut y: Vec<f64> = q.iter().chain(qdot).copied().collect();
    let mut total = 0.0;
    for i in 0..y.len() {
        let (yi, h) = (y[i], 1e-6 * (1.0 + y[i].abs()));
        let mut at = |v: f64| {
            y[i] = v;
            let value = quantity.value(t, &y[..n], &y[n..]).unwrap_or(f64::NAN);
            y[i] = yi;
            value
        };
        let slope = ((at(yi + h) - at(yi - h)) / (2.0 * h)).abs();
        // An angle's error means the same at any number of turns: its size counts up to π.
        let size = if i < n && angles[i] { yi.abs().min(std::f64::consts::PI) } else { yi.abs() };
        if slope.is_finite() {
            total += slope * (1.0 + size);
        }
    }
    total
}

/// Check `run` (a run of `system`, built from `scene` with `params`, by `method`) against every
/// constant of the motion the scene declares and against its constraints. The run must have
/// recorded its samples from the initial state on.
///
/// # Errors
/// The scene's, when its constants cannot be built with `params`.
pub fn check(
    scene: &dyn Scene,
    params: &Params,
    system: &mut dyn System,
    method: Method,
    run: &Trajectory,
) -> Result<Health, lagrange::Error> {
    let samples = run.len();
    let mut health = Health { expected: 0.0, checked: Vec::new(), findings: Vec::new() };
    if samples == 0 {
        return Ok(health);
    }
    // The rate and the constants' scales vary with the motion, smoothly: read at a bounded set of
    // samples spread over the run (each costs a Jacobian, or 4n evaluations of a constant).
    let stride = samples.div_ceil(SPREAD_SAMPLES).max(1);
    let spread = || (0..samples).step_by(stride).chain(std::iter::once(samples - 1));
    let rate = if method.kind().is_fixed_step() {
        spread()
            .map(|k| fastest_rate(system, run.t[k], run.q(k), run.qdot(k)))
            .try_fold(0.0_f64, |m, r| r.map(|r| m.max(r)))
    } else {
        None
    };
    let e = expected_error(method, run.stats.steps, rate);
    health.expected = e;
    let angles: Vec<bool> =
        scene.coordinates(params)?.iter().map(|c| c.kind == lagrange::CoordinateKind::Angle).collect();
    for quantity in scene.conserved_quantities(params)? {
        let value = |k: usize| quantity.value(run.t[k], run.q(k), run.qdot(k)).unwrap_or(f64::NAN);
        let start = value(0);
        let scale =
            spread().map(|k| sensitivity(&quantity, &angles, run.t[k], run.q(k), run.qdot(k))).fold(0.0, f64::max);
        let bound = e * scale;
        // A NaN drift is beyond any bound.
        let drifts: Vec<f64> = (0..samples).map(|k| (value(k) - start).abs()).collect();
        health.checked.push(quantity.symbol.clone());
        if let Some(k) = drifts.iter().position(|&d| beyond(d, bound)) {
            let drift = drifts.iter().fold(0.0_f64, |m, &d| if d.is_nan() { f64::INFINITY } else { m.max(d) });
            health.findings.push(Finding { quantity: quantity.symbol.clone(), drift, bound, since: run.t[k] });
        }
    }
    if !run.violation.is_empty() {
        let size = |k: usize| 1.0 + run.q(k).iter().chain(run.qdot(k)).fold(0.0_f64, |m, v| m.max(v.abs()));
        for (row, name) in ["max |Φ|", "max |Φ̇|"].into_iter().enumerate() {
            health.checked.push(name.to_string());
            let bound_at = |k: usize| e.max(CONSTRAINT_FLOOR) * size(k);
            let worst = (0..samples)
                .map(|k| run.violation[k][row])
                .fold(0.0_f64, |m, v| if v.is_nan() { f64::INFINITY } else { m.max(v) });
            if let Some(k) = (0..samples).find(|&k| beyond(run.violation[k][row], bound_at(k))) {
                let bound = (0..samples).map(bound_at).fold(0.0_f64, f64::max);
                health.findings.push(Finding { quantity: name.to_string(), drift: worst, bound, since: run.t[k] });
            }
        }
    }
    Ok(health)
}

/// `ω h` below which a collapsed explicit step is not held back by stability (whose limit is
/// `ω h ≈ 3.3` for Dormand–Prince): a factor 100 below it.
pub const STIFF_STEP: f64 = 0.033;

/// Why a run failed, as its samples show, when the error it stopped with is not the whole
/// story ([`diagnose`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Cause {
    /// The run had already left what its scene declares ([`check`]) before it stopped: the
    /// divergence is the cause, the failure its consequence.
    DivergedFirst {
        /// What had drifted.
        findings: Vec<Finding>,
    },
    /// The step collapsed (`h` at `t`) far below the explicit method's stability limit for the
    /// motion's fastest rate there (`rate`, 1/s; `rate h` below [`STIFF_STEP`]): not
    /// stiffness, whatever the stiffness test said — the motion is not resolved there (a
    /// singular configuration, a discontinuity, a tolerance too loose for the motion).
    NotStiff {
        /// Where the run stopped.
        t: f64,
        /// The last step.
        h: f64,
        /// The fastest rate of the motion there ([`fastest_rate`]).
        rate: f64,
    },
}

/// Why the run of `system` (built from `scene` with `params`) by `method` stopped with `error`,
/// read from the samples `partial` it recorded from the initial state on: a run that had
/// already left its constants of the motion diverged first; a step that collapsed far below
/// the explicit stability limit of the motion's fastest rate is not stiffness. `None` when the
/// error is all there is to say (an error that is not a failure of the integration, too few
/// samples, nothing found).
pub fn diagnose(
    scene: &dyn Scene,
    params: &Params,
    system: &mut dyn System,
    method: Method,
    partial: &Trajectory,
    error: &lagrange::Error,
) -> Option<Cause> {
    use lagrange::Error;
    let integration = matches!(
        error,
        Error::StepSizeUnderflow { .. }
            | Error::Stiff { .. }
            | Error::TooManySteps { .. }
            | Error::NewtonFailed { .. }
            | Error::Diverged { .. }
    );
    if !integration || partial.len() < 2 {
        return None;
    }
    if let Ok(health) = check(scene, params, system, method, partial)
        && !health.is_healthy()
    {
        return Some(Cause::DivergedFirst { findings: health.findings });
    }
    if let Error::Stiff { t, h } | Error::StepSizeUnderflow { t, h } = *error {
        let last = partial.len() - 1;
        if let Some(rate) = fastest_rate(system, partial.t[last], partial.q(last), partial.qdot(last))
            && rate * h < STIFF_STEP
        {
            return Some(Cause::NotStiff { t, h, rate });
        }
    }
    None
}
