//! The two-stage Gauss–Legendre collocation method, order 4, fixed step: symplectic, symmetric
//! and A-stable (Hairer, Lubich & Wanner, *Geometric Numerical Integration*, §II.1.3 and
//! §VIII.6; Hairer & Wanner, *Solving ODE II*, §IV.5, Table 5.2).

use super::integrator::{Grid, OnGrid, Stats};
use super::newton::StageSystem;
use super::rk4::Rk4;
use super::{check_step, non_finite_quantity};
use crate::{Dynamics, Error, State};

/// `√3`.
const SQRT_3: f64 = 1.732_050_807_568_877_2;
/// Nodes `c = ½ ∓ √3/6`.
const C: [f64; 2] = [0.5 - SQRT_3 / 6.0, 0.5 + SQRT_3 / 6.0];
/// Butcher matrix (row-major).
const A: [f64; 4] = [0.25, 0.25 - SQRT_3 / 6.0, 0.25 + SQRT_3 / 6.0, 0.25];
/// Weights.
const B: [f64; 2] = [0.5, 0.5];
/// Newton iterations before a step gives up.
const NEWTON_MAX_ITERATIONS: usize = 50;
/// An iteration that has stopped making progress (two iterations without halving its best
/// scaled update) has reached the noise of the residual evaluation if its best update, or its
/// last update measured by its effect over the step (see [`Gauss4::effect`]), is below this:
/// converged. The noise is `ε` times the conditioning of the accelerations — of the mass matrix
/// (it measured 1.2e-12 on the stability suite's chain with link masses spanning 1e6) and of
/// stiff forces (`ε ω² h` on a stage velocity for a spring `ω`, relative 6e-8 to a radial
/// velocity that stays near zero at `k/m` = 1e6) — so a fixed multiple of `ε` would reject
/// well-solved stages; `√ε` is far below what a non-converging iteration reaches (the
/// predictor's error, `O(h ‖∂f/∂y‖)³`). The level reached is kept in [`Gauss4::max_residual`].
const UPDATE_NOISE_FLOOR: f64 = 1.490_116_119_384_765_6e-8;
/// Contraction `θ` above which Newton re-evaluates the Jacobian at the mean stage value and
/// refactors within the step: a Jacobian from the step's start describes a violent event
/// (a light link whipped by heavy ones) too poorly to converge in a useful number of
/// iterations, while one from inside the step restores fast convergence.
const THETA_UPDATE: f64 = 0.5;
/// Jacobian updates within one step before Newton gives up.
const MAX_JACOBIAN_UPDATES: usize = 4;
/// Largest contraction `θ` of a step after which the Jacobian is kept for the next one; a
/// slower convergence recomputes it there (fresh, `θ = O(h²)`).
const THETA_REFRESH: f64 = 1e-2;
/// RK4 substeps of a step that Newton could not take on a system with constraints among its
/// coordinates: the same order as Gauss, and at `h/4` a local error `4⁴` times below RK4's at
/// `h` (RK4's error constant is larger than Gauss's), and well inside the explicit methods'
/// range on the parallelogram chain's flat positions (RK4 alone keeps the branch there at steps
/// of 1e-2 and 2.5e-3 s).
const FALLBACK_SUBSTEPS: usize = 4;

/// Why Newton stopped without converging.
enum Failure {
    /// Not converging (iterations, last scaled update; `None`: the Newton matrix became
    /// singular at a Jacobian update).
    Newton(usize, Option<f64>),
    /// A stage value or its accelerations were not finite.
    NonFinite(String),
}

/// Gauss–Legendre of order 4 (2 stages) with fixed step on `y = (q, q̇)`: the stage equations
/// `Z_i = h Σ_j a_ij f(t + c_j h, y + Z_j)` are solved by simplified Newton with the exact AD
/// Jacobian ([`Dynamics::acceleration_jacobian`]) **to round-off** — the iteration runs until
/// its update stops decreasing at the last bits — so that the method's invariants hold to
/// round-off: quadratic invariants exactly (the energy of a linear oscillator, angular
/// momentum), energy errors bounded without drift on nonlinear ones (symplectic, symmetric).
///
/// The Newton matrix is the reduced `I − h A ⊗ ∂f/∂y` of the shared Newton step (docs/method.md#the-newton-step-shared-by-the-implicit-methods), factored
/// once and kept, with its Jacobian, for as long as the step size stays and Newton contracts
/// fast (`θ ≤ 10⁻²`); the stage values start from the extrapolated collocation polynomial of the
/// previous step. Buffers are allocated once in [`new`](Self::new); [`step`](Self::step)
/// allocates nothing.
///
/// Two ways to use it: [`step`](Self::step) advances a [`State`] the caller holds; as an
/// [`Integrator`](super::Integrator) (with the step set by [`with_step`](Self::with_step)) it holds its own state
/// on the grid `t0 + k dt`.
#[derive(Clone, Debug)]
pub struct Gauss4 {
    n: usize,
    /// `A²` (row-major 2 × 2), for the Newton matrix.
    a_squared: [f64; 4],
    /// Stage increments `Z_i`, stage-major: coordinates (2n) and velocities (2n).
    zq: Vec<f64>,
    zv: Vec<f64>,
    /// Stage accelerations `q̈(t + c_i h, Y_i)` (2n).
    accel: Vec<f64>,
    /// Newton residuals, then updates (2n each).
    rq: Vec<f64>,
    rv: Vec<f64>,
    /// One stage value `Y_i = (q, q̇)` (n each).
    q_stage: Vec<f64>,
    v_stage: Vec<f64>,
    /// Jacobian and factored Newton matrix.
    newton: StageSystem,
    /// Whether `newton.jacobian` was evaluated at the current state.
    jacobian_fresh: bool,
    /// Whether the next step must recompute the Jacobian first.
    refresh_jacobian: bool,
    /// Step the Newton matrix is factored for (NaN: not factored).
    factored_step: f64,
    /// Step of the last step, whose stage values seed the next (NaN: none).
    last_step: f64,
    /// Largest final scaled Newton update of any step so far.
    pub max_residual: f64,
    /// Counters.
    stats: Stats,
    /// RK4 for the steps Newton cannot take on a system with constraints (see
    /// [`FALLBACK_SUBSTEPS`]).
    fallback: Rk4,
    /// The state and step grid of the [`Integrator`](super::Integrator) interface.
    state: State,
    grid: Grid,
}

impl Gauss4 {
    /// Buffers for `n` coordinates (the step is not set: see [`with_step`](Self::with_step)).
    pub fn new(n: usize) -> Self {
        let z = |k: usize| vec![0.0; k];
        let mut a_squared = [0.0; 4];
        for i in 0..2 {
            for j in 0..2 {
                a_squared[i * 2 + j] = (0..2).map(|k| A[i * 2 + k] * A[k * 2 + j]).sum();
            }
        }
        Self {
            n,
            a_squared,
            zq: z(2 * n),
            zv: z(2 * n),
            accel: z(2 * n),
            rq: z(2 * n),
            rv: z(2 * n),
            q_stage: z(n),
            v_stage: z(n),
            newton: StageSystem::new(n, 2),
            jacobian_fresh: false,
            refresh_jacobian: true,
            factored_step: f64::NAN,
            last_step: f64::NAN,
            max_residual: 0.0,
            stats: Stats::default(),
            fallback: Rk4::new(n),
            state: State::new(0.0, z(n), z(n)),
            grid: Grid::new(0.0, f64::NAN),
        }
    }

    /// Work done (see [`Stats`]).
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The fixed step of the [`Integrator`](super::Integrator) interface.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a step that is not positive and finite.
    pub fn with_step(mut self, dt: f64) -> Result<Self, Error> {
        check_step(dt)?;
        self.grid.dt = dt;
        Ok(self)
    }

    /// Advance `state` by `h`. On a system with constraints among its coordinates, a step whose
    /// Newton iteration does not converge even with a fresh Jacobian — near a singular
    /// configuration (a parallelogram laid flat), where Gauss's stage values, not held on the
    /// constraints, meet accelerations that change faster than the iteration follows — is
    /// taken by RK4 substeps instead and counted in [`Stats::fallbacks`].
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a step that is not positive and finite;
    /// [`Error::DimensionMismatch`] for a state of another size; [`Error::NewtonFailed`] when
    /// Newton does not converge even with a fresh Jacobian on a system without constraints (the
    /// step is too large for the motion); [`Error::Diverged`] naming the quantity when a stage
    /// value or its accelerations stop being finite; any other error of the equations of
    /// motion.
    pub fn step<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        state: &mut State,
        h: f64,
    ) -> Result<(), Error> {
        check_step(h)?;
        let n = self.n;
        for (what, got) in [("q", state.q.len()), ("q̇", state.qdot.len())] {
            if got != n {
                return Err(Error::DimensionMismatch { what, expected: n, got });
            }
        }
        // Stage values from the previous step's collocation polynomial, or from y.
        if self.last_step == h {
            self.extrapolate();
        } else {
            self.zq.fill(0.0);
            self.zv.fill(0.0);
        }
        // Newton, retried once with a Jacobian at this state if an old one fails.
        let theta = loop {
            if self.refresh_jacobian && !self.jacobian_fresh {
                system.acceleration_jacobian(ws, state.t, &state.q, &state.qdot, &mut self.newton.jacobian)?;
                self.stats.jacobians += 1;
                self.jacobian_fresh = true;
                self.factored_step = f64::NAN;
            }
            if self.factored_step != h {
                self.stats.factorizations += 1;
                self.factored_step = f64::NAN;
                if self.newton.factor(h, &A, &self.a_squared) {
                    self.factored_step = h;
                } else if self.jacobian_fresh {
                    return self.after_newton_failure(system, ws, state, h, 0, None);
                } else {
                    self.refresh_jacobian = true;
                    continue;
                }
            }
            match self.newton(system, ws, state, h)? {
                Ok(theta) => break theta,
                Err(_) if !self.jacobian_fresh => {
                    self.refresh_jacobian = true;
                    self.zq.fill(0.0);
                    self.zv.fill(0.0);
                }
                Err(Failure::Newton(iterations, residual)) => {
                    return self.after_newton_failure(system, ws, state, h, iterations, residual);
                }
                Err(Failure::NonFinite(quantity)) => {
                    self.last_step = f64::NAN;
                    return Err(Error::Diverged {
                        t: state.t,
                        step: self.stats.steps,
                        quantity: format!("Newton did not converge: {quantity} in a stage"),
                    });
                }
            }
        };
        // y₁ = y₀ + h Σ b_i f(Y_i): velocities from the final stage values, accelerations from
        // the last evaluation (before an update at round-off level).
        for i in 0..n {
            let (mut dq, mut dv) = (0.0, 0.0);
            for s in 0..2 {
                dq += B[s] * (state.qdot[i] + self.zv[s * n + i]);
                dv += B[s] * self.accel[s * n + i];
            }
            state.q[i] += h * dq;
            state.qdot[i] += h * dv;
        }
        state.t += h;
        self.refresh_jacobian = theta > THETA_REFRESH;
        self.jacobian_fresh = false;
        self.last_step = h;
        self.stats.steps += 1;
        Ok(())
    }

    /// A step whose Newton iteration did not converge even with a fresh Jacobian: on a system
    /// without constraints among its coordinates [`Error::NewtonFailed`] (the step is too large
    /// for the motion); on one with constraints, the step taken by [`FALLBACK_SUBSTEPS`] RK4
    /// substeps and counted in [`Stats::fallbacks`]. Gauss's stage values are not held on the
    /// constraints, and where these lose rank (links aligned: a singular configuration) the
    /// accelerations between the stages change faster than the iteration follows, at any step;
    /// an explicit step needs no solve there.
    fn after_newton_failure<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        state: &mut State,
        h: f64,
        iterations: usize,
        residual: Option<f64>,
    ) -> Result<(), Error> {
        self.last_step = f64::NAN;
        self.refresh_jacobian = true;
        self.jacobian_fresh = false;
        if Dynamics::constraint_counts(system) == (0, 0) {
            return Err(Error::NewtonFailed { t: state.t, iterations, residual });
        }
        let before = self.fallback.stats().evaluations;
        let start = state.t;
        for k in 0..FALLBACK_SUBSTEPS {
            // Substeps end at `start + h k/4` (the last at `start + h` exactly: h·4/4 = h).
            let end = start + h * (k + 1) as f64 / FALLBACK_SUBSTEPS as f64;
            self.fallback.step(system, ws, state, end - state.t)?;
        }
        state.t = start + h;
        self.stats.evaluations += self.fallback.stats().evaluations - before;
        self.stats.fallbacks += 1;
        self.stats.steps += 1;
        Ok(())
    }

    /// Stage increments of the next step from the collocation polynomial `u` of this one
    /// (degree 2 through `Z(0) = 0`, `Z(c_1)`, `Z(c_2)`): `Z_i ← u(1 + c_i) − u(1)`.
    fn extrapolate(&mut self) {
        let lagrange = |j: usize, x: f64| {
            let other = C[1 - j];
            x * (x - other) / (C[j] * (C[j] - other))
        };
        let mut weights = [[0.0; 2]; 2];
        for (i, row) in weights.iter_mut().enumerate() {
            for (j, w) in row.iter_mut().enumerate() {
                *w = lagrange(j, 1.0 + C[i]) - lagrange(j, 1.0);
            }
        }
        for z in [&mut self.zq, &mut self.zv] {
            let (first, second) = z.split_at_mut(self.n);
            for (a, b) in first.iter_mut().zip(second.iter_mut()) {
                let (z1, z2) = (*a, *b);
                *a = weights[0][0] * z1 + weights[0][1] * z2;
                *b = weights[1][0] * z1 + weights[1][1] * z2;
            }
        }
    }

    /// Re-evaluate the Jacobian at the mean stage value `y + (Z₁ + Z₂)/2` (the midpoint of the
    /// step, to `O(h³)`) and refactor the Newton matrix: `Ok(Err)` if that point is not finite
    /// or the matrix is singular there.
    fn update_jacobian<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        state: &State,
        h: f64,
    ) -> Result<Result<(), Failure>, Error> {
        let n = self.n;
        for i in 0..n {
            self.q_stage[i] = state.q[i] + 0.5 * (self.zq[i] + self.zq[n + i]);
            self.v_stage[i] = state.qdot[i] + 0.5 * (self.zv[i] + self.zv[n + i]);
        }
        if let Some(quantity) = non_finite_quantity(system.coordinates(), &self.q_stage, &self.v_stage) {
            return Ok(Err(Failure::NonFinite(quantity)));
        }
        match system.acceleration_jacobian(
            ws,
            state.t + 0.5 * h,
            &self.q_stage,
            &self.v_stage,
            &mut self.newton.jacobian,
        ) {
            Ok(()) => {}
            Err(Error::NonFinite { stage, q, .. }) => {
                return Ok(Err(Failure::NonFinite(format!("non-finite {stage} at q = {q:?}"))));
            }
            Err(other) => return Err(other),
        }
        self.stats.jacobians += 1;
        self.stats.factorizations += 1;
        self.jacobian_fresh = true;
        if self.newton.factor(h, &A, &self.a_squared) {
            self.factored_step = h;
            Ok(Ok(()))
        } else {
            self.factored_step = f64::NAN;
            Ok(Err(Failure::Newton(0, None)))
        }
    }

    /// The last Newton update (in `rq`, `rv`) measured by its effect over the step: a
    /// coordinate update against the larger of the coordinate and its displacement over the
    /// step `h (|q̇| + |Z_v|)`, a velocity update by the displacement it causes, `h δv`, against
    /// the larger of `h (|q̇| + |Z_v|)` and the coordinate. Each component in its own units, and
    /// no component that stays near zero (a velocity at rest, an angle crossing zero) can
    /// make round-off look large.
    fn effect(&self, state: &State, h: f64) -> f64 {
        let n = self.n;
        let mut norm: f64 = 0.0;
        for s in 0..2 {
            for i in 0..n {
                let k = s * n + i;
                let q = state.q[i].abs() + self.zq[k].abs();
                let step = h * (state.qdot[i].abs() + self.zv[k].abs());
                let scale = q.max(step).max(f64::MIN_POSITIVE);
                norm = norm.max(self.rq[k].abs() / scale).max(h * self.rv[k].abs() / scale);
            }
        }
        norm
    }

    /// The accelerations at both stage values `(q + Z_q, q̇ + Z_v)` into `accel`:
    /// `Ok(Err(why))` for a non-finite stage value or acceleration, `Err` for other errors of
    /// the equations of motion.
    fn stage_accelerations<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        state: &State,
        h: f64,
    ) -> Result<Result<(), Failure>, Error> {
        let n = self.n;
        for s in 0..2 {
            for i in 0..n {
                self.q_stage[i] = state.q[i] + self.zq[s * n + i];
                self.v_stage[i] = state.qdot[i] + self.zv[s * n + i];
            }
            if let Some(quantity) = non_finite_quantity(system.coordinates(), &self.q_stage, &self.v_stage) {
                return Ok(Err(Failure::NonFinite(quantity)));
            }
            self.stats.evaluations += 1;
            let accel = &mut self.accel[s * n..(s + 1) * n];
            match system.accelerations(ws, state.t + C[s] * h, &self.q_stage, &self.v_stage, accel) {
                Ok(()) => {}
                Err(Error::NonFinite { stage, q, .. }) => {
                    return Ok(Err(Failure::NonFinite(format!("non-finite {stage} at q = {q:?}"))));
                }
                Err(other) => return Err(other),
            }
        }
        Ok(Ok(()))
    }

    /// The stage residuals `r = h (A ⊗ I) f(Y) − Z` into `rq`, `rv`.
    fn residuals(&mut self, state: &State, h: f64) {
        let n = self.n;
        for s in 0..2 {
            for i in 0..n {
                let (mut fq, mut fv) = (0.0, 0.0);
                for j in 0..2 {
                    fq += A[s * 2 + j] * (state.qdot[i] + self.zv[j * n + i]);
                    fv += A[s * 2 + j] * self.accel[j * n + i];
                }
                self.rq[s * n + i] = h * fq - self.zq[s * n + i];
                self.rv[s * n + i] = h * fv - self.zv[s * n + i];
            }
        }
    }

    /// Add the Newton update (`rq`, `rv`) to the stage increments; returns the size of the
    /// update relative to the stage values.
    fn apply_update(&mut self, state: &State) -> f64 {
        let n = self.n;
        let mut norm: f64 = 0.0;
        for s in 0..2 {
            for i in 0..n {
                let k = s * n + i;
                self.zq[k] += self.rq[k];
                self.zv[k] += self.rv[k];
                let scale_q = (state.q[i].abs() + self.zq[k].abs()).max(f64::MIN_POSITIVE);
                let scale_v = (state.qdot[i].abs() + self.zv[k].abs()).max(f64::MIN_POSITIVE);
                norm = norm.max(self.rq[k].abs() / scale_q).max(self.rv[k].abs() / scale_v);
            }
        }
        norm
    }

    /// Simplified Newton on the stage equations to round-off: `Ok(Ok(θ_max))` on convergence,
    /// `Ok(Err(why))` on failure, `Err` for errors of the equations of motion other than
    /// non-finite values.
    fn newton<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        state: &State,
        h: f64,
    ) -> Result<Result<f64, Failure>, Error> {
        // Scaled update of the last iteration, the best so far, and the iterations since it.
        let (mut previous, mut best, mut since_best) = (f64::NAN, f64::INFINITY, 0);
        let mut theta_max: f64 = 0.0;
        let mut updates = 0;
        // The last scaled update (finite: a non-finite one returns at once).
        let mut last = f64::INFINITY;
        for iteration in 1..=NEWTON_MAX_ITERATIONS {
            self.stats.newton_iterations += 1;
            if let Err(why) = self.stage_accelerations(system, ws, state, h)? {
                return Ok(Err(why));
            }
            self.residuals(state, h);
            self.newton.solve(h, &A, &mut self.rq, &mut self.rv);
            let norm = self.apply_update(state);
            if !norm.is_finite() {
                return Ok(Err(Failure::NonFinite("a non-finite Newton update".into())));
            }
            last = norm;
            // Converged when the update is below round-off, or when the predicted remainder
            // θ/(1 − θ) ‖δ‖ is. The scaled max-norm need not fall at every iteration (its
            // worst component changes, e.g. a velocity growing from zero), so one iteration
            // without halving the best is allowed; two in a row are either the round-off
            // plateau (converged, if the update is below it: noise fluctuates around it, and
            // can make new bests by chance) or a failure.
            if norm < 0.5 * best {
                since_best = 0;
            } else {
                since_best += 1;
            }
            best = best.min(norm);
            let effect = self.effect(state, h);
            let mut converged = norm <= f64::EPSILON;
            if iteration > 1 && !converged {
                let theta = norm / previous;
                if previous > 1e3 * f64::EPSILON {
                    // (A rate measured among round-off noise means nothing.)
                    theta_max = theta_max.max(theta);
                }
                if theta < 1.0 {
                    converged = theta / (1.0 - theta) * norm <= f64::EPSILON;
                }
                if !converged && theta > THETA_UPDATE && effect > UPDATE_NOISE_FLOOR && updates < MAX_JACOBIAN_UPDATES {
                    updates += 1;
                    // A slow rate: the next step evaluates its own Jacobian (θ > THETA_REFRESH).
                    theta_max = theta_max.max(theta);
                    if let Err(why) = self.update_jacobian(system, ws, state, h)? {
                        return Ok(Err(match why {
                            Failure::Newton(_, residual) => Failure::Newton(iteration, residual),
                            other => other,
                        }));
                    }
                    (best, since_best) = (f64::INFINITY, 0);
                    previous = f64::NAN;
                    continue;
                }
                if !converged && since_best >= 2 {
                    if best.min(effect) <= UPDATE_NOISE_FLOOR {
                        converged = true;
                    } else {
                        return Ok(Err(Failure::Newton(iteration, Some(norm))));
                    }
                }
            }
            if converged {
                self.max_residual = self.max_residual.max(norm.min(best).min(effect));
                return Ok(Ok(theta_max));
            }
            previous = norm;
        }
        // (`previous` is NaN after a Jacobian update in the last iteration: report the last
        // update measured.)
        Ok(Err(Failure::Newton(NEWTON_MAX_ITERATIONS, Some(last))))
    }
}

impl OnGrid for Gauss4 {
    fn grid(&self) -> (&State, &Grid, Stats) {
        (&self.state, &self.grid, self.stats)
    }

    fn grid_mut(&mut self) -> (&mut State, &mut Grid, &mut Stats) {
        (&mut self.state, &mut self.grid, &mut self.stats)
    }

    fn forget(&mut self) {
        self.jacobian_fresh = false;
        self.refresh_jacobian = true;
        self.factored_step = f64::NAN;
        self.last_step = f64::NAN;
    }

    fn step_state<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        state: &mut State,
        h: f64,
    ) -> Result<(), Error> {
        self.step(system, ws, state, h)
    }
}
