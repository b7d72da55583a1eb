//! Dormand–Prince 5(4) with error control, dense output and stiffness detection (Hairer,
//! Nørsett & Wanner, *Solving Ordinary Differential Equations I*, §II.5, §II.6 and §II.10;
//! the `DOPRI5` code).

use super::control::{Controller, StiffnessWatch, Verdict, error_norm, first_step, step_toward};
use super::integrator::{Integrator, Stats, check_finite, diverged, rhs};
use super::{Tolerances, check_tolerance};
use crate::{Dynamics, Error, State};

// Butcher tableau (Dormand & Prince 1980).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// Error estimate: difference of the 5th- and 4th-order weights.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output of order 4 (Shampine 1986, as in DOPRI5's CONTD5).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Step-size control (DOPRI5 defaults): exponent 1/5 from the order-4 estimate, PI control
/// with `β = 0.04`, safety 0.9, `h_new ∈ [h/10, 5h]`.
const CONTROL: Controller = Controller::new(0.2, Some(0.04), 0.9, 0.2, 10.0);

/// Stiffness detection (DOPRI5, Hairer–Wanner I §II.10): `h λ ≈ h ‖k7 − k6‖ / ‖y_new − y_stage6‖`
/// (both stages sit at `t + h`); the stability boundary of DOPRI5 on the negative real axis is
/// about 3.3, so the watch fires above 3.25.
const STIFFNESS: StiffnessWatch = StiffnessWatch::new(3.25);

/// The embedded Dormand–Prince 5(4) pair with PI step control, FSAL and 4th-order dense output,
/// on `y = (q, q̇)`. The local error of each accepted step satisfies
/// `‖err_i / (atol + rtol max(|y_i|, |y_i'|))‖_rms ≤ 1`.
///
/// Hairer's stiffness test runs on every accepted step; when it fires, the time is recorded in
/// [`Stats::stiffness`], and a step-size collapse afterwards is reported as
/// [`Error::Stiff`] (pointing to the implicit integrator) rather than a bare underflow.
#[derive(Clone, Debug)]
pub struct Dopri5 {
    n: usize,
    tol: Tolerances,
    /// Current time.
    t: f64,
    /// Current state `y = (q, q̇)` (2n).
    y: Vec<f64>,
    /// Stage derivatives `k_1 … k_7` (7 × 2n); `k_1` holds `f(t, y)` (FSAL).
    k: [Vec<f64>; 7],
    /// Stage state and candidate state (2n each).
    y_stage: Vec<f64>,
    y_new: Vec<f64>,
    /// Dense-output coefficients of the last step (5 × 2n).
    dense: [Vec<f64>; 5],
    /// Start and length of the last accepted step.
    t_old: f64,
    h_old: f64,
    /// Proposed next step.
    h: f64,
    /// Step-size controller.
    control: Controller,
    /// `h λ` estimate of the last attempted step, and the stiffness test's counts.
    h_lambda: f64,
    stiffness: StiffnessWatch,
    /// Counters.
    stats: Stats,
}

impl Dopri5 {
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
            t: 0.0,
            y: z(),
            k: [z(), z(), z(), z(), z(), z(), z()],
            y_stage: z(),
            y_new: z(),
            dense: [z(), z(), z(), z(), z()],
            t_old: 0.0,
            h_old: 0.0,
            h: 0.0,
            control: CONTROL,
            h_lambda: 0.0,
            stiffness: STIFFNESS,
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

    /// Start at `(t, q, q̇)`: evaluate `f` and choose the first step (Hairer's HINIT).
    ///
    /// # Errors
    /// Any error of the equations of motion.
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
        self.t = t;
        self.t_old = t;
        self.h_old = 0.0;
        self.y[..n].copy_from_slice(q);
        self.y[n..].copy_from_slice(qdot);
        self.stats = Stats::default();
        self.control.reset();
        self.stiffness.reset();
        let [k1, k2, ..] = &mut self.k;
        let buffers = [k1.as_mut_slice(), &mut self.y_stage, k2];
        self.h = first_step((system, ws), (self.tol, h_max, 0.2), t, &self.y, buffers, &mut self.stats)?;
        Ok(())
    }

    /// Continue from a modified state `(q, q̇)` at the current time (after a projection onto
    /// constraints, say): keeps the step-size controller's state, re-evaluates `f` (the
    /// first-same-as-last stage is no longer valid).
    ///
    /// # Errors
    /// Any error of the equations of motion.
    pub fn restart<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<(), Error> {
        let n = self.n;
        self.y[..n].copy_from_slice(q);
        self.y[n..].copy_from_slice(qdot);
        let [k1, ..] = &mut self.k;
        rhs(system, ws, n, self.t, &self.y, k1)?;
        self.stats.evaluations += 1;
        Ok(())
    }

    /// Take one accepted step, never past `t_limit` (retrying rejected steps internally).
    /// Afterwards [`interpolate`](Self::interpolate) covers `[t_old, t]`.
    ///
    /// # Errors
    /// [`Error::StepSizeUnderflow`] when the step collapses, [`Error::Stiff`] instead once the
    /// stiffness test has fired; any error of the equations of motion.
    pub fn step<D: Dynamics>(&mut self, system: &D, ws: &mut D::Workspace, t_limit: f64) -> Result<(), Error> {
        let n2 = 2 * self.n;
        let n = self.n;
        loop {
            let h = step_toward(self.h, self.t, t_limit, &self.stats)?;
            let t = self.t;
            let [k1, k2, k3, k4, k5, k6, k7] = &mut self.k;
            let (y, ys) = (&self.y, &mut self.y_stage);
            // Stages 2–6.
            for i in 0..n2 {
                ys[i] = y[i] + h * A21 * k1[i];
            }
            rhs(system, ws, n, t + C2 * h, ys, k2)?;
            for i in 0..n2 {
                ys[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
            }
            rhs(system, ws, n, t + C3 * h, ys, k3)?;
            for i in 0..n2 {
                ys[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
            }
            rhs(system, ws, n, t + C4 * h, ys, k4)?;
            for i in 0..n2 {
                ys[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
            }
            rhs(system, ws, n, t + C5 * h, ys, k5)?;
            for i in 0..n2 {
                ys[i] = y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
            }
            rhs(system, ws, n, t + h, ys, k6)?;
            // 5th-order solution and k7 = f(t + h, y_new) (FSAL).
            for i in 0..n2 {
                self.y_new[i] = y[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
            }
            rhs(system, ws, n, t + h, &self.y_new, k7)?;
            self.stats.evaluations += 6;
            // Stiffness estimate h λ = h ‖k7 − k6‖ / ‖y_new − y_stage6‖ (y_stage6 still in ys).
            let (mut num, mut den) = (0.0, 0.0);
            for i in 0..n2 {
                num += (k7[i] - k6[i]).powi(2);
                den += (self.y_new[i] - ys[i]).powi(2);
            }
            self.h_lambda = StiffnessWatch::h_lambda(h, num, den);
            // Error estimate (stored in y_stage).
            for i in 0..n2 {
                ys[i] = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            }
            let err = error_norm(self.tol, &self.y_stage, &self.y, &self.y_new);
            // A non-finite error (a blow-up inside the step) retries smaller; underflow ends it.
            let h_new = match self.control.judge(err, h) {
                Verdict::Accept(h_new) => h_new,
                Verdict::Reject(h_new) => {
                    self.h = h_new;
                    self.stats.rejected += 1;
                    continue;
                }
            };
            // Accept: dense-output coefficients, then advance.
            let [k1, _, k3, k4, k5, k6, k7] = &self.k;
            for i in 0..n2 {
                let ydiff = self.y_new[i] - self.y[i];
                let bspl = h * k1[i] - ydiff;
                self.dense[0][i] = self.y[i];
                self.dense[1][i] = ydiff;
                self.dense[2][i] = bspl;
                self.dense[3][i] = ydiff - h * k7[i] - bspl;
                self.dense[4][i] = h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
            }
            self.stiffness.count(self.h_lambda, t, &mut self.stats);
            self.t_old = t;
            self.h_old = h;
            self.t = if h == t_limit - t { t_limit } else { t + h };
            std::mem::swap(&mut self.y, &mut self.y_new);
            self.k.swap(0, 6);
            self.h = h_new;
            self.stats.steps += 1;
            return Ok(());
        }
    }

    /// Dense output at `t` within the last accepted step: `q` and `q̇` (4th order).
    pub fn interpolate(&self, t: f64, q: &mut [f64], qdot: &mut [f64]) {
        let n = self.n;
        let theta = if self.h_old == 0.0 { 1.0 } else { (t - self.t_old) / self.h_old };
        let theta1 = 1.0 - theta;
        let d = &self.dense;
        for i in 0..2 * n {
            let v = d[0][i] + theta * (d[1][i] + theta1 * (d[2][i] + theta * (d[3][i] + theta1 * d[4][i])));
            if i < n {
                q[i] = v;
            } else {
                qdot[i - n] = v;
            }
        }
    }
}

impl<D: Dynamics> Integrator<D> for Dopri5 {
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

    /// One accepted step toward `t_end` (not `t_out`: [`read`](Integrator::read) interpolates).
    fn advance(&mut self, system: &D, ws: &mut D::Workspace, _: f64, t_end: f64) -> Result<(), Error> {
        let (t, k) = (self.t, self.stats.steps);
        self.step(system, ws, t_end).map_err(|e| diverged(system, e, t, k))?;
        check_finite(system, self.q(), self.qdot(), self.t, self.stats.steps)
    }

    fn read(&mut self, _: &D, _: &mut D::Workspace, t: f64, q: &mut [f64], qdot: &mut [f64]) -> Result<(), Error> {
        if t == self.t {
            q.copy_from_slice(Self::q(self));
            qdot.copy_from_slice(Self::qdot(self));
        } else {
            self.interpolate(t, q, qdot);
        }
        Ok(())
    }

    fn current(&self) -> (&[f64], &[f64]) {
        (Self::q(self), Self::qdot(self))
    }

    fn project(&mut self, system: &D, ws: &mut D::Workspace) -> Result<(), Error> {
        let n = self.n;
        let (q, qdot) = self.y.split_at_mut(n);
        system.project(ws, self.t, q, qdot)?;
        let [k1, ..] = &mut self.k;
        rhs(system, ws, n, self.t, &self.y, k1)?;
        self.stats.evaluations += 1;
        Ok(())
    }

    fn stats(&self) -> Stats {
        Self::stats(self)
    }
}
