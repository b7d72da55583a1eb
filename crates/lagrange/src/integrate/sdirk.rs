//! An L-stable singly diagonally implicit Runge–Kutta method of order 4 with an embedded
//! order-3 error estimate: SDIRK4 of Hairer & Wanner, *Solving Ordinary Differential
//! Equations II*, §IV.6, Table 6.5 (`γ = 1/4`, 5 stages; their `SDIRK4` code), for stiff
//! problems.

use super::control::{Controller, Verdict, error_norm, first_step};
use super::integrator::{Integrator, Stats, check_finite, diverged, rhs};
use super::newton::StageSystem;
use super::{Tolerances, check_tolerance, non_finite_quantity};
use crate::{Dynamics, Error, State};

/// Stages.
const STAGES: usize = 5;
/// The diagonal `γ`.
const GAMMA: f64 = 0.25;
/// Nodes `c_i`.
const C: [f64; STAGES] = [0.25, 0.75, 11.0 / 20.0, 0.5, 1.0];
/// Strictly lower part of the Butcher matrix (`a_ii = γ`).
const A: [[f64; STAGES]; STAGES] = [
    [0.0; STAGES],
    [0.5, 0.0, 0.0, 0.0, 0.0],
    [17.0 / 50.0, -1.0 / 25.0, 0.0, 0.0, 0.0],
    [371.0 / 1360.0, -137.0 / 2720.0, 15.0 / 544.0, 0.0, 0.0],
    [25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0, 0.0],
];
/// Weights of the order-4 solution: the last row (stiffly accurate, `y₁ = Y₅`).
const B: [f64; STAGES] = [25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0, 0.25];
/// Weights of the embedded order-3 solution.
const B_HAT: [f64; STAGES] = [59.0 / 48.0, -17.0 / 96.0, 225.0 / 32.0, -85.0 / 12.0, 0.0];

/// Step-size control (as Hairer's SDIRK4: `h_new ∈ [h/5, 8h]`, safety 0.9, exponent 1/4 from the
/// order-3 estimate, no PI memory).
const CONTROL: Controller = Controller::new(0.25, None, 0.9, 0.2, 8.0);
/// A proposed step within `[1, 1.2] h` keeps `h` (and the factorization), as in RADAU5.
const KEEP_STEP: f64 = 1.2;
/// Newton iterations per stage before the step is retried.
const NEWTON_MAX_ITERATIONS: usize = 10;
/// Contraction `θ` above which Newton is diverging.
const NEWTON_DIVERGING: f64 = 0.99;
/// Largest contraction `θ` of a step after which the Jacobian is kept for the next step; a
/// slower convergence recomputes it there (one Jacobian costs about `2n` evaluations, an extra
/// Newton iteration per stage costs 5).
const THETA_REFRESH: f64 = 0.1;

/// Why the last attempt at a step failed.
#[derive(Clone, Debug)]
enum Failure {
    /// The error test.
    Accuracy,
    /// Newton did not converge (iterations, last scaled update; `None`: the Newton matrix was
    /// singular).
    Newton(usize, Option<f64>),
    /// A stage value or its accelerations were not finite.
    NonFinite(String),
}

/// SDIRK4 (Hairer & Wanner II, Table IV.6.5) on `y = (q, q̇)`, `y' = f(t, y) = (q̇, q̈)`:
/// L-stable (stiffly accurate and A-stable, `R(∞) = 0`), order 4 with an embedded order-3
/// estimate and step-size control and rejection like [`Dopri5`](super::Dopri5).
///
/// Each stage `Y_i = y + h Σ_{j<i} a_ij F_j + γ h f(t + c_i h, Y_i)` is solved by simplified
/// Newton with one LU factorization of `I − γ h ∂f/∂y` per step, shared by all five stages (in
/// the reduced form of the shared Newton step, docs/method.md#the-newton-step-shared-by-the-implicit-methods), with the exact AD Jacobian
/// [`Dynamics::acceleration_jacobian`]. The Jacobian is kept from step to step while Newton
/// contracts fast (`θ ≤ 0.1`), recomputed when it slows, and recomputed at once when Newton
/// fails with an old one; a Newton failure with a fresh Jacobian halves the step. Newton starts
/// from the previous step's cubic Hermite interpolant, extrapolated, and stops at RADAU5's
/// criterion `η ‖δ‖ ≤ min(0.03, √rtol)` in the tolerance-scaled norm. The error
/// estimate `h Σ (b_i − b̂_i) F_i` is filtered by `(I − γ h ∂f/∂y)⁻¹` (Shampine's device, as in
/// RADAU5) so that stiff components do not reject every step.
///
/// Output is stage-exact: [`step`](Self::step) lands on a given time instead of interpolating.
/// (An interpolant built from `f` at the step ends, such as cubic Hermite, would carry the
/// stiff part of `q̈` — `ω²` times an `O(tol)` deviation — into the velocities.)
///
/// Buffers are allocated once in [`new`](Self::new); [`step`](Self::step) allocates nothing.
#[derive(Clone, Debug)]
pub struct Sdirk4 {
    n: usize,
    tol: Tolerances,
    /// Newton stopping bound on the scaled update, relative to the tolerance.
    newton_tolerance: f64,
    /// Current time.
    t: f64,
    /// Current state `y = (q, q̇)` (2n).
    y: Vec<f64>,
    /// `f(t, y)` at the current state (2n): an evaluation at the start, then the last stage's.
    derivative: Vec<f64>,
    /// State and `f` at the start of the last accepted step (2n each) and its length (0: none),
    /// for the predictor.
    y_old: Vec<f64>,
    derivative_old: Vec<f64>,
    h_old: f64,
    /// Stage derivatives `F_1 … F_5` (5 × 2n).
    stage_derivative: [Vec<f64>; STAGES],
    /// Stage increment `Z = Y_i − y`, the Newton unknown (2n).
    z: Vec<f64>,
    /// Known part of the stage, `h Σ_{j<i} a_ij F_j` (2n).
    explicit: Vec<f64>,
    /// Stage value `Y_i` (2n) and `f` there (2n).
    y_stage: Vec<f64>,
    f_stage: Vec<f64>,
    /// Newton residual, then update (2n: q part, q̇ part).
    update: Vec<f64>,
    /// Candidate state (2n) and filtered error estimate (2n).
    y_new: Vec<f64>,
    error: Vec<f64>,
    /// Tolerance scale `atol + rtol |y_i|` at the start of the step (2n), for Newton.
    scale: Vec<f64>,
    /// Jacobian and factored Newton matrix.
    newton: StageSystem,
    /// Whether `newton.jacobian` was evaluated at the current `(t, y)`.
    jacobian_fresh: bool,
    /// Whether the next step must recompute the Jacobian first.
    refresh_jacobian: bool,
    /// The step the Newton matrix is factored for (NaN: not factored).
    factored_step: f64,
    /// Convergence-rate memory `η = θ/(1 − θ)` (Hairer's FACCON).
    eta: f64,
    /// Proposed next step.
    h: f64,
    /// Step-size controller.
    control: Controller,
    /// Counters.
    stats: Stats,
}

impl Sdirk4 {
    /// An integrator for `n` coordinates with the given tolerances.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for non-positive or non-finite tolerances.
    pub fn new(n: usize, tol: Tolerances) -> Result<Self, Error> {
        check_tolerance(tol)?;
        let z = || vec![0.0; 2 * n];
        Ok(Self {
            n,
            tol,
            // RADAU5's FNEWT: Newton errors well below the tolerance (the stage derivatives
            // F = (Z − known)/(γh) carry a Newton error in Z into y amplified by |A⁻¹| ≈ 30,
            // so 0.03 would cost a factor ~40 in accuracy), never below round-off.
            newton_tolerance: (10.0 * f64::EPSILON / tol.rtol).max(0.03_f64.min(tol.rtol.sqrt())),
            t: 0.0,
            y: z(),
            derivative: z(),
            y_old: z(),
            derivative_old: z(),
            h_old: 0.0,
            stage_derivative: [z(), z(), z(), z(), z()],
            z: z(),
            explicit: z(),
            y_stage: z(),
            f_stage: z(),
            update: z(),
            y_new: z(),
            error: z(),
            scale: z(),
            newton: StageSystem::new(n, 1),
            jacobian_fresh: false,
            refresh_jacobian: true,
            factored_step: f64::NAN,
            eta: 1.0,
            h: 0.0,
            control: CONTROL,
            stats: Stats::default(),
        })
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Current coordinates.
    pub fn q(&self) -> &[f64] {
        &self.y[..self.n]
    }

    /// Current velocities.
    pub fn qdot(&self) -> &[f64] {
        &self.y[self.n..]
    }

    /// Step size proposed for the next step.
    pub fn proposed_step(&self) -> f64 {
        self.h
    }

    /// Work done since [`start`](Self::start) (see [`Stats`]).
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Start at `(t, q, q̇)`: evaluate `f` and choose the first step (Hairer's HINIT for order 4).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a state of another size; any error of the equations of
    /// motion.
    pub fn start<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        h_max: f64,
    ) -> Result<(), Error> {
        let n = self.n;
        for (what, got) in [("q", q.len()), ("q̇", qdot.len())] {
            if got != n {
                return Err(Error::DimensionMismatch { what, expected: n, got });
            }
        }
        self.t = t;
        self.y[..n].copy_from_slice(q);
        self.y[n..].copy_from_slice(qdot);
        self.stats = Stats::default();
        self.h_old = 0.0;
        self.jacobian_fresh = false;
        self.refresh_jacobian = true;
        self.factored_step = f64::NAN;
        self.eta = 1.0;
        self.control.reset();
        let buffers = [self.derivative.as_mut_slice(), &mut self.y_stage, &mut self.f_stage];
        self.h = first_step((system, ws), (self.tol, h_max, 0.25), t, &self.y, buffers, &mut self.stats)?;
        Ok(())
    }

    /// Take one accepted step, never past `t_limit` (retrying rejected steps internally); a
    /// step shortened to land on `t_limit` does not shrink the next proposal.
    ///
    /// # Errors
    /// When the step collapses below round-off of `t`: [`Error::NewtonFailed`] if Newton kept
    /// failing, [`Error::Diverged`] (naming the quantity) if stage values stopped being finite,
    /// [`Error::StepSizeUnderflow`] if the error test kept failing. Any error of the equations
    /// of motion other than a non-finite value (those shrink the step).
    pub fn step<D: Dynamics>(&mut self, system: &D, ws: &mut D::Workspace, t_limit: f64) -> Result<(), Error> {
        let mut failure = Failure::Accuracy;
        loop {
            let proposed = self.h;
            let mut h = proposed;
            if self.t + h >= t_limit || self.t + 1.01 * h >= t_limit {
                h = t_limit - self.t;
            }
            if h.abs() <= 10.0 * f64::EPSILON * self.t.abs().max(1.0) {
                return Err(self.collapse(failure, h));
            }
            // Jacobian at (t, y) when asked for; factor I − γh ∂f/∂y for this step (singular
            // only when 1/(γh) is an eigenvalue of ∂f/∂y: a smaller step avoids it).
            if self.refresh_jacobian && !self.jacobian_fresh {
                self.update_jacobian(system, ws)?;
            }
            if self.factored_step != h && !self.factor(h) {
                self.h = 0.5 * h;
                self.stats.rejected += 1;
                self.control.rejected();
                failure = Failure::Newton(0, None);
                continue;
            }
            // Stages; a Newton failure retries with a fresh Jacobian, or else half the step.
            match self.stages(system, ws, h)? {
                Ok(theta) => {
                    if self.finish(h, t_limit, theta) {
                        if h < proposed {
                            self.h = self.h.max(proposed);
                        }
                        return Ok(());
                    }
                    failure = Failure::Accuracy;
                }
                Err(why) => {
                    if !self.jacobian_fresh {
                        self.update_jacobian(system, ws)?;
                        self.factored_step = f64::NAN;
                    } else {
                        self.h = 0.5 * h;
                        self.stats.rejected += 1;
                        self.control.rejected();
                    }
                    failure = why;
                }
            }
        }
    }

    /// The error for a step that collapsed after `failure`.
    fn collapse(&self, failure: Failure, h: f64) -> Error {
        match failure {
            Failure::Accuracy => Error::StepSizeUnderflow { t: self.t, h },
            Failure::Newton(iterations, residual) => Error::NewtonFailed { t: self.t, iterations, residual },
            Failure::NonFinite(quantity) => Error::Diverged {
                t: self.t,
                step: self.stats.steps,
                quantity: format!("Newton did not converge: {quantity} in a stage, at every step down to h = {h:e}"),
            },
        }
    }

    /// Evaluate `∂f/∂y` at the current state.
    fn update_jacobian<D: Dynamics>(&mut self, system: &D, ws: &mut D::Workspace) -> Result<(), Error> {
        let n = self.n;
        system.acceleration_jacobian(ws, self.t, &self.y[..n], &self.y[n..], &mut self.newton.jacobian)?;
        self.stats.jacobians += 1;
        self.jacobian_fresh = true;
        self.refresh_jacobian = false;
        self.factored_step = f64::NAN;
        Ok(())
    }

    /// Factor the Newton matrix for step `h`; `false` if it is singular.
    fn factor(&mut self, h: f64) -> bool {
        self.stats.factorizations += 1;
        let regular = self.newton.factor(h, &[GAMMA], &[GAMMA * GAMMA]);
        self.factored_step = if regular { h } else { f64::NAN };
        regular
    }

    /// Solve the five stages with step `h`: `Ok(Ok(θ_max))` on convergence, `Ok(Err(why))`
    /// when Newton failed, `Err` for errors of the equations of motion that no smaller step
    /// can cure.
    fn stages<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        h: f64,
    ) -> Result<Result<f64, Failure>, Error> {
        let n2 = 2 * self.n;
        for i in 0..n2 {
            self.scale[i] = self.tol.atol + self.tol.rtol * self.y[i].abs();
        }
        let mut theta_max: f64 = 0.0;
        for stage in 0..STAGES {
            // Known part h Σ_{j<i} a_ij F_j.
            self.explicit.fill(0.0);
            for j in 0..stage {
                let a = h * A[stage][j];
                for (e, f) in self.explicit.iter_mut().zip(&self.stage_derivative[j]) {
                    *e += a * f;
                }
            }
            self.predict(stage, h);
            let t_stage = self.t + C[stage] * h;
            if let Err(why) = self.stage_newton(system, ws, t_stage, h, &mut theta_max)? {
                return Ok(Err(why));
            }
            // F_i = (Z − explicit) / (γh): the stage derivative the converged Z implies.
            for i in 0..n2 {
                self.stage_derivative[stage][i] = (self.z[i] - self.explicit[i]) / (GAMMA * h);
            }
        }
        Ok(Ok(theta_max))
    }

    /// Simplified Newton on one stage, `G(Z) = Z − explicit − γh f(t_stage, y + Z) = 0`, from
    /// the predicted `Z`; the largest contraction rate seen goes into `theta_max`. `Ok(Err(why))`
    /// when Newton failed, `Err` for errors of the equations of motion.
    fn stage_newton<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        t_stage: f64,
        h: f64,
        theta_max: &mut f64,
    ) -> Result<Result<(), Failure>, Error> {
        let (n, n2) = (self.n, 2 * self.n);
        let mut previous_norm = f64::NAN;
        let mut converged = false;
        for iteration in 1..=NEWTON_MAX_ITERATIONS {
            self.stats.newton_iterations += 1;
            for i in 0..n2 {
                self.y_stage[i] = self.y[i] + self.z[i];
            }
            if let Some(quantity) = non_finite_quantity(system.coordinates(), &self.y_stage[..n], &self.y_stage[n..]) {
                return Ok(Err(Failure::NonFinite(quantity)));
            }
            self.stats.evaluations += 1;
            match rhs(system, ws, n, t_stage, &self.y_stage, &mut self.f_stage) {
                Ok(()) => {}
                Err(Error::NonFinite { stage, q, .. }) => {
                    return Ok(Err(Failure::NonFinite(format!("non-finite {stage} at q = {q:?}"))));
                }
                Err(other) => return Err(other),
            }
            for i in 0..n2 {
                self.update[i] = self.explicit[i] + GAMMA * h * self.f_stage[i] - self.z[i];
            }
            let (rq, rv) = self.update.split_at_mut(n);
            self.newton.solve(h, &[GAMMA], rq, rv);
            let mut norm = 0.0;
            for i in 0..n2 {
                self.z[i] += self.update[i];
                norm += (self.update[i] / self.scale[i]).powi(2);
            }
            let norm = (norm / n2 as f64).sqrt();
            if !norm.is_finite() {
                return Ok(Err(Failure::NonFinite("a non-finite Newton update".into())));
            }
            // Convergence test (Hairer): η ‖δ‖ ≤ κ with η = θ/(1 − θ), or the remembered
            // η^0.8 on the first iteration; give up when diverging or too slow to make it.
            if iteration > 1 {
                let theta = norm / previous_norm;
                *theta_max = theta_max.max(theta);
                if theta >= NEWTON_DIVERGING {
                    return Ok(Err(Failure::Newton(iteration, Some(norm))));
                }
                let remaining = (NEWTON_MAX_ITERATIONS - iteration) as i32;
                if theta.powi(remaining) / (1.0 - theta) * norm > self.newton_tolerance {
                    return Ok(Err(Failure::Newton(iteration, Some(norm))));
                }
                self.eta = theta / (1.0 - theta);
            } else {
                self.eta = self.eta.max(f64::EPSILON).powf(0.8);
            }
            if self.eta * norm <= self.newton_tolerance || norm == 0.0 {
                converged = true;
                break;
            }
            previous_norm = norm;
        }
        if !converged {
            return Ok(Err(Failure::Newton(NEWTON_MAX_ITERATIONS, Some(previous_norm))));
        }
        Ok(Ok(()))
    }

    /// Starting value of stage `Z`: the cubic Hermite interpolant of the last step (through
    /// `y`, `f` at both of its ends) extrapolated to `t + c_i h`, error `O(h⁴)`; on the first
    /// step `c_i h F_{i−1}` (with `F_0 = f(t, y)`).
    fn predict(&mut self, stage: usize, h: f64) {
        if self.h_old > 0.0 {
            let s = 1.0 + C[stage] * h / self.h_old;
            let (s2, s3) = (s * s, s * s * s);
            let (h00, h10, h01, h11) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, 3.0 * s2 - 2.0 * s3, s3 - s2);
            let h_old = self.h_old;
            for i in 0..2 * self.n {
                let u = h00 * self.y_old[i]
                    + h10 * h_old * self.derivative_old[i]
                    + h01 * self.y[i]
                    + h11 * h_old * self.derivative[i];
                self.z[i] = u - self.y[i];
            }
        } else {
            let previous = if stage == 0 { &self.derivative } else { &self.stage_derivative[stage - 1] };
            for (z, f) in self.z.iter_mut().zip(previous) {
                *z = C[stage] * h * f;
            }
        }
    }

    /// Error test of the solved step; on acceptance advance and return `true`.
    fn finish(&mut self, h: f64, t_limit: f64, theta: f64) -> bool {
        let (n, n2) = (self.n, 2 * self.n);
        // y₁ = Y₅ (stiffly accurate); error h Σ (b_i − b̂_i) F_i filtered by (I − γh ∂f/∂y)⁻¹.
        for i in 0..n2 {
            self.y_new[i] = self.y[i] + self.z[i];
            self.error[i] = (0..STAGES).map(|s| h * (B[s] - B_HAT[s]) * self.stage_derivative[s][i]).sum();
        }
        let (eq, ev) = self.error.split_at_mut(n);
        self.newton.solve(h, &[GAMMA], eq, ev);
        let err = error_norm(self.tol, &self.error, &self.y, &self.y_new);
        let mut h_new = match self.control.judge(err, h) {
            Verdict::Accept(h_new) => h_new,
            Verdict::Reject(h_new) => {
                self.h = h_new;
                self.stats.rejected += 1;
                return false;
            }
        };
        // Accept: advance, choose the next step.
        self.refresh_jacobian = theta > THETA_REFRESH;
        if !self.refresh_jacobian && (h..=KEEP_STEP * h).contains(&h_new) {
            h_new = h;
        }
        std::mem::swap(&mut self.y_old, &mut self.y);
        std::mem::swap(&mut self.y, &mut self.y_new);
        std::mem::swap(&mut self.derivative_old, &mut self.derivative);
        self.derivative.copy_from_slice(&self.stage_derivative[STAGES - 1]);
        self.h_old = h;
        self.t = if h == t_limit - self.t { t_limit } else { self.t + h };
        self.h = h_new;
        self.jacobian_fresh = false;
        self.stats.steps += 1;
        true
    }
}

impl<D: Dynamics> Integrator<D> for Sdirk4 {
    fn begin(&mut self, system: &D, ws: &mut D::Workspace, initial: &State, t_end: f64) -> Result<(), Error> {
        let span = (t_end - initial.t).max(f64::MIN_POSITIVE);
        self.start(system, ws, initial.t, &initial.q, &initial.qdot, span)
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn proposed_step(&self) -> f64 {
        self.h
    }

    fn reached(&self, t_out: f64) -> bool {
        self.t >= t_out
    }

    /// One accepted step landing on `t_out` at the latest: no interpolation of stiff velocities.
    fn advance(&mut self, system: &D, ws: &mut D::Workspace, t_out: f64, _: f64) -> Result<(), Error> {
        let (t, k) = (self.t, self.stats.steps);
        self.step(system, ws, t_out).map_err(|e| diverged(system, e, t, k))?;
        check_finite(system, self.q(), self.qdot(), self.t, self.stats.steps)
    }

    fn read(&mut self, _: &D, _: &mut D::Workspace, _: f64, q: &mut [f64], qdot: &mut [f64]) -> Result<(), Error> {
        q.copy_from_slice(Self::q(self));
        qdot.copy_from_slice(Self::qdot(self));
        Ok(())
    }

    fn current(&self) -> (&[f64], &[f64]) {
        (Self::q(self), Self::qdot(self))
    }

    fn project(&mut self, system: &D, ws: &mut D::Workspace) -> Result<(), Error> {
        let n = self.n;
        let (q, qdot) = self.y.split_at_mut(n);
        system.project(ws, self.t, q, qdot)?;
        rhs(system, ws, n, self.t, &self.y, &mut self.derivative)?;
        self.stats.evaluations += 1;
        Ok(())
    }

    fn stats(&self) -> Stats {
        Self::stats(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tableau satisfies the order conditions: order 4 for `b`, order 3 for `b̂`, and
    /// `c_i = Σ_j a_ij`; its stability function vanishes at infinity (L-stability).
    #[test]
    fn tableau_has_orders_four_and_three_and_is_l_stable() {
        let a = |i: usize, j: usize| if i == j { GAMMA } else { A[i][j] };
        for i in 0..STAGES {
            let row: f64 = (0..STAGES).map(|j| a(i, j)).sum();
            assert!((row - C[i]).abs() < 1e-15, "c_{i}");
        }
        // Order conditions up to 4 (Butcher trees), as vectors g with Σ b_i g_i = value.
        let product = |f: &dyn Fn(usize) -> f64| -> [f64; STAGES] { std::array::from_fn(f) };
        let ac = product(&|i| (0..STAGES).map(|j| a(i, j) * C[j]).sum());
        let conditions: [(&str, [f64; STAGES], f64, usize); 8] = [
            ("Σb = 1", [1.0; STAGES], 1.0, 1),
            ("Σbc = 1/2", C, 0.5, 2),
            ("Σbc² = 1/3", product(&|i| C[i] * C[i]), 1.0 / 3.0, 3),
            ("Σb(Ac) = 1/6", ac, 1.0 / 6.0, 3),
            ("Σbc³ = 1/4", product(&|i| C[i].powi(3)), 0.25, 4),
            ("Σbc(Ac) = 1/8", product(&|i| C[i] * ac[i]), 0.125, 4),
            ("Σb(Ac²) = 1/12", product(&|i| (0..STAGES).map(|j| a(i, j) * C[j] * C[j]).sum()), 1.0 / 12.0, 4),
            ("Σb(A(Ac)) = 1/24", product(&|i| (0..STAGES).map(|j| a(i, j) * ac[j]).sum()), 1.0 / 24.0, 4),
        ];
        let sum = |w: &[f64; STAGES], g: &[f64; STAGES]| (0..STAGES).map(|i| w[i] * g[i]).sum::<f64>();
        for (name, g, value, order) in &conditions {
            assert!((sum(&B, g) - value).abs() < 1e-14, "b: {name}");
            if *order <= 3 {
                assert!((sum(&B_HAT, g) - value).abs() < 1e-14, "b̂: {name}");
            }
        }
        // Stability function at z → −∞: R(z) = 1 + z bᵀ (I − z A)⁻¹ 1 → 1 − bᵀ A⁻¹ 1 = 0
        // (stiffly accurate: bᵀ = e₅ᵀ A). Check at z = −1e8 by forward substitution.
        let z = -1e8;
        let mut g = [0.0; STAGES];
        for i in 0..STAGES {
            let known: f64 = (0..i).map(|j| A[i][j] * g[j]).sum();
            g[i] = (1.0 + z * known) / (1.0 - z * GAMMA);
        }
        let r = 1.0 + z * (0..STAGES).map(|i| B[i] * g[i]).sum::<f64>();
        assert!(r.abs() < 1e-6, "R(−1e8) = {r}");
    }
}
