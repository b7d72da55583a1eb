//! Step-size control of the error-controlled integrators ([`Dopri5`](super::Dopri5),
//! [`Sdirk4`](super::Sdirk4)), written once: the error norm, the first step (Hairer's
//! `HINIT`), and the controller that accepts or rejects a step and proposes the next one
//! (Hairer, Nørsett & Wanner, *Solving ODE I*, §II.4 and the `DOPRI5` code; Hairer & Wanner,
//! *Solving ODE II*, §IV.8 and the `SDIRK4` code).

use super::Tolerances;
use super::integrator::{Stats, rhs};
use crate::{Dynamics, Error};

/// Hairer's `HINIT` for a method whose error is `O(h^{1/exponent})`, at `(t, y)` (`y = (q, q̇)`
/// of `n` coordinates each), at most `h_max`: evaluates `f0 = f(t, y)` and, from the trial step
/// `h` of [`trial_step`], `f1 = f(t + h, y + h f0)` (with `y1 = y + h f0`), counting both in
/// `stats`, and returns the first step of [`initial_step`].
pub(crate) fn first_step<D: Dynamics>(
    (system, ws): (&D, &mut D::Workspace),
    (tol, h_max, exponent): (Tolerances, f64, f64),
    t: f64,
    y: &[f64],
    [f0, y1, f1]: [&mut [f64]; 3],
    stats: &mut Stats,
) -> Result<f64, Error> {
    let n = y.len() / 2;
    rhs(system, ws, n, t, y, f0)?;
    stats.evaluations += 1;
    let trial = trial_step(tol, y, f0, h_max);
    let h = trial.0;
    for i in 0..2 * n {
        y1[i] = y[i] + h * f0[i];
    }
    rhs(system, ws, n, t + h, y1, f1)?;
    stats.evaluations += 1;
    Ok(initial_step(tol, y, f0, f1, trial, h_max, exponent))
}

/// The scaled root-mean-square norm `‖e_i / (atol + rtol max(|y_i|, |y'_i|))‖_rms` of an error
/// estimate `e` of a step from `y0` to `y1`: a step is acceptable when it is at most 1.
pub(crate) fn error_norm(tol: Tolerances, e: &[f64], y0: &[f64], y1: &[f64]) -> f64 {
    let mut sum = 0.0;
    for i in 0..e.len() {
        let sk = tol.atol + tol.rtol * y0[i].abs().max(y1[i].abs());
        sum += (e[i] / sk).powi(2);
    }
    (sum / e.len() as f64).sqrt()
}

/// The first trial step of `HINIT`, from `‖y‖` and `‖f(t0, y)‖` (scaled), at most `h_max`;
/// with the squared scaled norm of `f`, for [`initial_step`].
fn trial_step(tol: Tolerances, y: &[f64], f0: &[f64], h_max: f64) -> (f64, f64) {
    let scale = |i: usize| tol.atol + tol.rtol * y[i].abs();
    let (mut dnf, mut dny) = (0.0, 0.0);
    for i in 0..y.len() {
        dnf += (f0[i] / scale(i)).powi(2);
        dny += (y[i] / scale(i)).powi(2);
    }
    let h = if dnf <= 1e-10 || dny <= 1e-10 { 1e-6 } else { (dny / dnf).sqrt() * 0.01 };
    (h.min(h_max), dnf)
}

/// The first step of `HINIT` for a method whose error is `O(h^{1/exponent})`: from the trial
/// step `h` and `dnf` of [`trial_step`], and `f1 = f(t0 + h, y + h f0)` (an estimate of `‖f'‖`).
fn initial_step(
    tol: Tolerances,
    y: &[f64],
    f0: &[f64],
    f1: &[f64],
    (h, dnf): (f64, f64),
    h_max: f64,
    exponent: f64,
) -> f64 {
    let scale = |i: usize| tol.atol + tol.rtol * y[i].abs();
    let mut der2 = 0.0;
    for i in 0..y.len() {
        der2 += ((f1[i] - f0[i]) / scale(i)).powi(2);
    }
    let der2 = der2.sqrt() / h;
    let der12 = der2.max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 { (h * 1e-3).max(1e-6) } else { (0.01 / der12).powf(exponent) };
    (100.0 * h).min(h1).min(h_max)
}

/// The decision on a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Verdict {
    /// Keep the step; the next one is proposed.
    Accept(f64),
    /// Redo the step with this length.
    Reject(f64),
}

/// The step-size controller: the factor `safety · err^(−exponent)` (PI-controlled, with the
/// previous accepted error to the power `β`, when `beta` is given), bounded to
/// `[fac_min, fac_max]`; no growth right after a rejection; a non-finite error (a blow-up
/// within the step) retries with `fac_min · h`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Controller {
    /// Exponent `1/(q + 1)` of the error, `q` the order of the embedded estimate.
    exponent: f64,
    /// PI control (Gustafsson): `β` of the previous error, as in `DOPRI5`; `None`: the plain
    /// controller of `SDIRK4`.
    beta: Option<f64>,
    safety: f64,
    fac_min: f64,
    fac_max: f64,
    /// Last accepted error (PI memory).
    err_old: f64,
    /// Whether the last attempt was rejected.
    last_rejected: bool,
}

impl Controller {
    /// A controller with the given exponent, PI `β` (or none), safety factor and bounds of the
    /// step factor.
    pub(crate) const fn new(exponent: f64, beta: Option<f64>, safety: f64, fac_min: f64, fac_max: f64) -> Self {
        Self { exponent, beta, safety, fac_min, fac_max, err_old: 1e-4, last_rejected: false }
    }

    /// Forget the history (a new integration).
    pub(crate) fn reset(&mut self) {
        self.err_old = 1e-4;
        self.last_rejected = false;
    }

    /// Note a step rejected for another reason than its error (Newton failed, say).
    pub(crate) fn rejected(&mut self) {
        self.last_rejected = true;
    }

    /// Judge a step of length `h` with error norm `err`.
    pub(crate) fn judge(&mut self, err: f64, h: f64) -> Verdict {
        if !err.is_finite() {
            self.last_rejected = true;
            return Verdict::Reject(h * self.fac_min);
        }
        let mut h_new = match self.beta {
            Some(beta) => {
                let fac11 = err.powf(self.exponent - beta * 0.75);
                if err > 1.0 {
                    self.last_rejected = true;
                    return Verdict::Reject(h / (1.0 / self.fac_min).min(fac11 / self.safety));
                }
                let fac = (fac11 / self.err_old.powf(beta) / self.safety).clamp(1.0 / self.fac_max, 1.0 / self.fac_min);
                self.err_old = err.max(1e-4);
                h / fac
            }
            None => {
                let fac = (self.safety * err.max(1e-10).powf(-self.exponent)).clamp(self.fac_min, self.fac_max);
                if err > 1.0 {
                    self.last_rejected = true;
                    return Verdict::Reject(h * fac.min(1.0));
                }
                h * fac
            }
        };
        if self.last_rejected {
            h_new = h_new.min(h);
        }
        self.last_rejected = false;
        Verdict::Accept(h_new)
    }
}

/// The step `h` from `t` toward `t_limit`: the proposed `h`, or the rest of the way when that is
/// at most 1 % longer; an error when it has collapsed to round-off of `t`
/// ([`Error::Stiff`] once the stiffness watch has fired, [`Error::StepSizeUnderflow`] otherwise).
pub(crate) fn step_toward(h: f64, t: f64, t_limit: f64, stats: &Stats) -> Result<f64, Error> {
    let h = if t + h >= t_limit || t + 1.01 * h >= t_limit { t_limit - t } else { h };
    if h.abs() <= 10.0 * f64::EPSILON * t.abs().max(1.0) {
        return Err(if stats.stiffness.is_some() { Error::Stiff { t, h } } else { Error::StepSizeUnderflow { t, h } });
    }
    Ok(h)
}

/// Hairer's stiffness test of the explicit pairs (*Solving ODE I*, §II.10): `h λ` is estimated on
/// every accepted step from two stages at the same time (`h ‖f(y₁) − f(Y)‖ / ‖y₁ − Y‖`, a
/// Lipschitz estimate of `f` along the step); the problem is declared stiff when it exceeds the
/// method's stability boundary on the negative real axis (less a margin) on 15 accepted steps,
/// the count restarting after 6 accepted steps in a row below it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StiffnessWatch {
    /// The bound on `h λ`.
    limit: f64,
    /// Accepted steps above the bound, and accepted steps in a row below it.
    stiff_steps: usize,
    non_stiff_steps: usize,
}

impl StiffnessWatch {
    const STIFF_STEPS: usize = 15;
    const NON_STIFF_RESET: usize = 6;

    pub(crate) const fn new(limit: f64) -> Self {
        Self { limit, stiff_steps: 0, non_stiff_steps: 0 }
    }

    /// Forget the counts (a new integration).
    pub(crate) fn reset(&mut self) {
        (self.stiff_steps, self.non_stiff_steps) = (0, 0);
    }

    /// `h λ` from the squared norms of the two stages' difference in `f` and in the state.
    pub(crate) fn h_lambda(h: f64, f_difference: f64, y_difference: f64) -> f64 {
        if y_difference > 0.0 { h.abs() * (f_difference / y_difference).sqrt() } else { 0.0 }
    }

    /// Count an accepted step starting at `t` with estimate `h_lambda`; the first time the test
    /// fires, its time goes into [`Stats::stiffness`].
    pub(crate) fn count(&mut self, h_lambda: f64, t: f64, stats: &mut Stats) {
        if h_lambda > self.limit {
            self.non_stiff_steps = 0;
            self.stiff_steps += 1;
            if self.stiff_steps == Self::STIFF_STEPS && stats.stiffness.is_none() {
                stats.stiffness = Some(t);
            }
        } else {
            self.non_stiff_steps += 1;
            if self.non_stiff_steps == Self::NON_STIFF_RESET {
                self.stiff_steps = 0;
            }
        }
    }
}
