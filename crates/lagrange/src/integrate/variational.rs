//! The variational midpoint integrator: discrete Euler–Lagrange equations (Marsden & West,
//! *Discrete mechanics and variational integrators*, Acta Numerica 2001, §1.2 and §3.2).
//!
//! On a system with constraints among its coordinates it is a constrained discrete
//! Euler–Lagrange method (docs/method.md#constraints): the impulse
//! `C₀ᵀ Λ` of the constraint rows at `q₀` enters the momentum equation, the holonomic rows
//! `Φ(t₁, q₁) = 0` hold at the end of the step (RATTLE in Lagrangian form, Marsden & West
//! §3.5) and the velocity rows `A(t_m, q_m) Δq/h + b = 0` at its midpoint (discrete
//! Lagrange–d'Alembert, Cortés & Martínez 2001, McLachlan & Perlmutter 2006); Newton solves for
//! `(Δq, Λ)` with the constraint rows' exact Jacobian and the Newton matrix of the momentum
//! equation kept while it contracts fast ([`REFRESH_RATE`]). The velocities read are moved onto the velocity form of
//! the constraints by RATTLE's second multiplier, which does not change the coordinates. The
//! driver does not project the state: the constraints hold at every step to the Newton
//! tolerance by the method itself.

use super::check_step;
use super::integrator::{Grid, Integrator, Stats, diverged};
use super::non_finite_quantity;
use crate::eom::constraints;
use crate::linalg as solve;
use crate::seed::{CHUNK, Lanes, lane};
use crate::{Dynamics, Error, LagrangianFunction, State};
use num_dual::{Dual64, HyperDual64};

/// Newton stops when the update is below this fraction of `‖Δq‖∞`: after such an update the
/// remaining error is of order its square (quadratic convergence), far below round-off.
const NEWTON_RTOL: f64 = 1e-10;
/// Newton iterations before giving up.
const NEWTON_MAX_ITERATIONS: usize = 50;
/// A Newton iteration that has stopped contracting (its update no longer halves) has reached
/// the round-off of its residual, and is converged, if the residual is below this fraction of
/// the magnitude of the terms it is the sum of ([`momentum_scale`]): the rounding of that sum
/// is about `ε` of it (one unit in the last place of 0.3, 0.8 ε, on the driven pendulum, see
/// [`Variational::invert_legendre`]), up to `n ε` for sums over `n` coordinates; 1e-12 leaves a
/// margin of ~4500 ε while staying 100 times below the `NEWTON_RTOL` asked of the update. A
/// stall above it is a failure.
const MOMENTUM_ROUNDOFF: f64 = 1e-12;
/// The Newton matrix is kept across iterations and steps (simplified Newton) while each
/// iteration divides the update by at least `1/REFRESH_RATE`; a slower iteration rebuilds it
/// at its iterate. Rebuilding costs one hyper-dual pass of `L` per pair of the `2n` variables,
/// an iteration with the kept matrix one per variable; at a rate of 1/4 the kept matrix
/// reaches round-off from a second-order predictor in a few more iterations than exact Newton.
const REFRESH_RATE: f64 = 0.25;
/// An iteration with a kept Newton matrix converges linearly: at rate `ρ` the error after an
/// update `u` is about `ρ/(1 − ρ) |u|`, and it stops when that is below this fraction of
/// `‖Δq‖∞` — the error that exact Newton leaves after an update of [`NEWTON_RTOL`] (its square
/// times the curvature of the equations, round-off), to a few units of round-off of `Δq`.
const LINEAR_RTOL: f64 = 1e-14;

/// The midpoint discrete Lagrangian `L_d(q₀, q₁) = h L((q₀+q₁)/2, (q₁−q₀)/h, t + h/2)` in
/// position–momentum form:
///
/// `p₀ + D₁L_d(q₀, q₁) + (h/2) Q = 0` (solved for `q₁` by Newton with an exact AD Jacobian,
/// kept across iterations and steps while each iteration divides the update by at least 4),
/// `p₁ = D₂L_d(q₀, q₁) + (h/2) Q`,
///
/// with `Q` evaluated at the midpoint. Second order, symplectic; by the discrete Noether
/// theorem the momentum of every cyclic coordinate is conserved exactly (to the Newton
/// tolerance), and the energy error stays bounded instead of drifting.
/// Buffers are allocated once; a step allocates nothing.
///
/// Its [`Stats`] count what it evaluates: one evaluation is the gradient of `L` (with the
/// generalized force) at one point — a midpoint of a step, or a state whose momenta or
/// velocities are read — as one evaluation of `q̈` is the derivatives of `L` at one state for
/// the other methods. Each Newton iteration (of a step, or of the inversion of the Legendre map
/// when velocities are read) is one such evaluation; a step's Newton matrix (a Jacobian: the
/// Hessian of `L`, with `∂Q/∂Δq` for a generalized force, and one LU factorization) is built
/// when an iteration divides the update by less than 4 and kept otherwise. Velocities
/// read through [`velocities`](Self::velocities) take a Jacobian (the Hessian's velocity block)
/// and a factorization per iteration; read by a run, one factorization of the system's mass
/// matrix.
pub struct Variational<F: LagrangianFunction> {
    n: usize,
    scratch: F::Scratch<HyperDual64>,
    /// The system's scratch for the generalized force in `f64` and along one `Δq` column.
    force_scratch: F::Scratch<f64>,
    force_dual_scratch: F::Scratch<Dual64>,
    /// Seeded midpoint coordinates and velocities (n each).
    q_seed: Vec<HyperDual64>,
    v_seed: Vec<HyperDual64>,
    /// The system's scratch and the midpoint coordinates and velocities in vector duals (n
    /// each), for the gradient alone: [`CHUNK`] of its `2n` entries per pass.
    lanes_scratch: F::Scratch<Lanes<f64>>,
    q_lanes: Vec<Lanes<f64>>,
    v_lanes: Vec<Lanes<f64>>,
    /// Gradient `(∂L/∂q, ∂L/∂q̇)` at the midpoint (2n).
    gradient: Vec<f64>,
    /// Hessian of `L` in `z = (q, q̇)` (2n × 2n).
    hessian: Vec<f64>,
    /// Newton matrix (n × n), its pivots, the residual and the update (n each).
    jacobian: Vec<f64>,
    pivots: Vec<usize>,
    /// The LU factor of the step's Newton matrix `dR/dq₁` (n × n) and its pivots, kept across
    /// iterations and steps while Newton contracts fast ([`REFRESH_RATE`]); `newton_step` is
    /// the step it was built for (NaN: none).
    newton: Vec<f64>,
    newton_pivots: Vec<usize>,
    newton_step: f64,
    /// `Δq` of the last two steps and their steps (NaN: none), for the next step's predictor.
    last_delta: Vec<f64>,
    last_step: f64,
    previous_delta: Vec<f64>,
    previous_step: f64,
    residual: Vec<f64>,
    /// Generalized force at the midpoint (n).
    force: Vec<f64>,
    /// `Σ_j |M_ij v_j|` (n): the size of the momenta's velocity part when velocities are read.
    momentum_size: Vec<f64>,
    /// Whether the system has generalized forces (learnt at the first midpoint evaluation).
    has_force: bool,
    /// Midpoint coordinates and velocities as duals along one column of `∂/∂Δq` (n each), and
    /// the generalized force in duals (n): `dQ/dΔq_j = ½ ∂Q/∂q_j + (1/h) ∂Q/∂q̇_j`.
    q_force: Vec<Dual64>,
    v_force: Vec<Dual64>,
    force_dual: Vec<Dual64>,
    /// Point at which `derivatives` evaluates: coordinates (n); its velocities are `velocity`.
    q_mid: Vec<f64>,
    /// Coordinates `q₀`, momenta `p₀` of the current state, and the Newton unknown, the
    /// increment `Δq = q₁ − q₀` (n each). Iterating on `Δq` rather than `q₁` keeps the discrete
    /// velocity `Δq/h` free of the cancellation in `(q₁ − q₀)/h`, which would cost `ε|q|/h` of
    /// momentum per step.
    q: Vec<f64>,
    p: Vec<f64>,
    delta: Vec<f64>,
    /// Latest velocity estimate `(q₁ − q₀)/h` (n), the predictor.
    velocity: Vec<f64>,
    /// Current time.
    t: f64,
    /// Start and initial velocities (read back as they are at the start), and the step grid of
    /// the [`Integrator`] interface.
    t0: f64,
    qdot0: Vec<f64>,
    grid: Grid,
    /// Counters.
    stats: Stats,
    /// Largest final Newton residual `‖p₀ + D₁L_d + (h/2)Q − Gᵀ(q₀)Λ‖∞` of any step so far.
    pub max_residual: f64,
    /// Largest constraint residual `max |Φ(t₁, q₁)|`, `max |A(t_m, q_m) v + b|` at the
    /// converged end of any step so far (0 without constraints).
    pub max_constraint_residual: f64,
    /// The buffers of the constrained step, allocated by [`begin`](Integrator::begin) for a
    /// system with constraints (`None` without: an unconstrained step does no constraint work).
    constrained: Option<Box<ConstrainedStep>>,
}

/// The buffers of a constrained step (`c = m + k` rows, `n` coordinates).
struct ConstrainedStep {
    c: usize,
    /// `C₀ = [Φ_q; A](t₀, q₀)` (c × n): the directions of the constraint impulse `C₀ᵀ Λ`.
    force_rows: Vec<f64>,
    /// The derivative of the step's constraint rows with respect to `Δq` (c × n).
    step_rows: Vec<f64>,
    /// The step's constraint residuals (c), and the holonomic residuals at `q₀` (m).
    residual: Vec<f64>,
    phi: Vec<f64>,
    /// Velocity residuals at `q₀` (c, unused by the step; read by the velocity projection).
    rate: Vec<f64>,
    /// The impulse `Λ` (c), 0 on a dependent row.
    multipliers: Vec<f64>,
    /// Rows dependent on the rows before them at `q₀` (`C₀ C₀ᵀ` factored with dependent rows),
    /// their Gram matrix (c × c), and the independent rows.
    dependent: Vec<bool>,
    gram: Vec<f64>,
    active: Vec<usize>,
    /// `X = J⁻¹ C₀ᵀ` by rows (c × n), whether it is that of the current `C₀` and `J`, the
    /// Schur complement `D X` over the independent rows and its pivots, its right-hand side (c).
    mobility: Vec<f64>,
    mobility_current: bool,
    /// The nonzero columns of one constraint row (at most n).
    nonzero: Vec<usize>,
    schur: Vec<f64>,
    pivots: Vec<usize>,
    rhs: Vec<f64>,
    /// `q₁ = q₀ + Δq` (n).
    q_end: Vec<f64>,
}

impl ConstrainedStep {
    fn new(n: usize, (m, k): (usize, usize)) -> Self {
        let c = m + k;
        Self {
            c,
            force_rows: vec![0.0; c * n],
            step_rows: vec![0.0; c * n],
            residual: vec![0.0; c],
            phi: vec![0.0; m],
            rate: vec![0.0; c],
            multipliers: vec![0.0; c],
            dependent: vec![false; c],
            gram: vec![0.0; c * c],
            active: Vec::with_capacity(c),
            mobility: vec![0.0; c * n],
            mobility_current: false,
            nonzero: Vec::with_capacity(n),
            schur: vec![0.0; c * c],
            pivots: vec![0; c],
            rhs: vec![0.0; c],
            q_end: vec![0.0; n],
        }
    }
}

impl<F: LagrangianFunction> Variational<F> {
    /// Buffers for `system`.
    pub fn new(system: &F) -> Self {
        let n = system.coordinates().len();
        let z = |k: usize| vec![0.0; k];
        let zero = HyperDual64::from(0.0);
        Self {
            n,
            scratch: system.scratch(),
            force_scratch: system.scratch(),
            force_dual_scratch: system.scratch(),
            q_seed: vec![zero; n],
            v_seed: vec![zero; n],
            lanes_scratch: system.scratch(),
            q_lanes: vec![Lanes::from_re(0.0); n],
            v_lanes: vec![Lanes::from_re(0.0); n],
            gradient: z(2 * n),
            hessian: z(4 * n * n),
            jacobian: z(n * n),
            pivots: vec![0; n],
            newton: z(n * n),
            newton_pivots: vec![0; n],
            newton_step: f64::NAN,
            last_delta: z(n),
            last_step: f64::NAN,
            previous_delta: z(n),
            previous_step: f64::NAN,
            residual: z(n),
            force: z(n),
            momentum_size: z(n),
            has_force: false,
            q_force: vec![Dual64::from(0.0); n],
            v_force: vec![Dual64::from(0.0); n],
            force_dual: vec![Dual64::from(0.0); n],
            q_mid: z(n),
            q: z(n),
            p: z(n),
            delta: z(n),
            velocity: z(n),
            t: 0.0,
            t0: 0.0,
            qdot0: z(n),
            grid: Grid::new(0.0, f64::NAN),
            stats: Stats::default(),
            max_residual: 0.0,
            max_constraint_residual: 0.0,
            constrained: None,
        }
    }

    /// The fixed step of the [`Integrator`] interface.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a step that is not positive and finite.
    pub fn with_step(mut self, dt: f64) -> Result<Self, Error> {
        check_step(dt)?;
        self.grid.dt = dt;
        Ok(self)
    }

    /// Work done since [`start`](Self::start) (see [`Stats`]).
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Current coordinates `q_k`.
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// Current discrete momenta `p_k` (equal to `∂L/∂q̇` of the continuous state they represent).
    pub fn momenta(&self) -> &[f64] {
        &self.p
    }

    /// Start from `(t, q, q̇)`: `p₀ = ∂L/∂q̇(q, q̇, t)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite state or Lagrangian.
    pub fn start(&mut self, system: &F, t: f64, q: &[f64], qdot: &[f64]) -> Result<(), Error> {
        crate::eom::check_state(self.n, t, q, Some(qdot))?;
        self.t = t;
        self.t0 = t;
        self.stats = Stats::default();
        self.max_constraint_residual = 0.0;
        self.q.copy_from_slice(q);
        self.qdot0.copy_from_slice(qdot);
        self.velocity.copy_from_slice(qdot);
        self.q_mid.copy_from_slice(q);
        self.newton_step = f64::NAN;
        self.last_step = f64::NAN;
        self.previous_step = f64::NAN;
        self.derivatives(system, t, Derivatives::Gradient);
        self.p.copy_from_slice(&self.gradient[self.n..]);
        if !crate::error::all_finite(&self.p) {
            return Err(crate::eom::non_finite(crate::error::Stage::Lagrangian, t, q));
        }
        Ok(())
    }

    /// Derivatives of `L` in `z = (q, q̇)` at `(t, q_mid, velocity)` ([`Derivatives`]): one
    /// hyper-dual pass per pair `a ≤ b` of the variables asked for (ε₁ on `z_a`, ε₂ on `z_b`),
    /// or per `a` for the gradient alone.
    fn derivatives(&mut self, system: &F, t: f64, which: Derivatives) {
        let n = self.n;
        self.stats.evaluations += 1;
        if which != Derivatives::Gradient {
            self.stats.jacobians += 1;
        }
        if which == Derivatives::Gradient {
            self.gradient_in_lanes(system, t);
            return;
        }
        let first = if which == Derivatives::Momentum { n } else { 0 };
        for (d, x) in self.q_seed.iter_mut().zip(&self.q_mid) {
            *d = HyperDual64::from(*x);
        }
        for (d, x) in self.v_seed.iter_mut().zip(&self.velocity) {
            *d = HyperDual64::from(*x);
        }
        let t = HyperDual64::from(t);
        for a in first..2 * n {
            for b in a..2 * n {
                seed(&mut self.q_seed, &mut self.v_seed, a, |d| d.eps1 = 1.0);
                seed(&mut self.q_seed, &mut self.v_seed, b, |d| d.eps2 = 1.0);
                let l = system.lagrangian_with(&mut self.scratch, t, &self.q_seed, &self.v_seed);
                seed(&mut self.q_seed, &mut self.v_seed, a, |d| d.eps1 = 0.0);
                seed(&mut self.q_seed, &mut self.v_seed, b, |d| d.eps2 = 0.0);
                if b == a {
                    self.gradient[a] = l.eps1;
                }
                self.hessian[a * 2 * n + b] = l.eps1eps2;
                self.hessian[b * 2 * n + a] = l.eps1eps2;
            }
        }
    }

    /// The gradient of `L` in `z = (q, q̇)` at `(t, q_mid, velocity)`: one vector-dual pass per
    /// [`CHUNK`] variables.
    fn gradient_in_lanes(&mut self, system: &F, t: f64) {
        let n = self.n;
        let t = Lanes::from_re(t);
        for a0 in (0..2 * n).step_by(CHUNK) {
            for (d, x) in self.q_lanes.iter_mut().zip(&self.q_mid) {
                *d = Lanes::from_re(*x);
            }
            for (d, x) in self.v_lanes.iter_mut().zip(&self.velocity) {
                *d = Lanes::from_re(*x);
            }
            let width = CHUNK.min(2 * n - a0);
            for a in a0..a0 + width {
                let d = if a < n { &mut self.q_lanes[a] } else { &mut self.v_lanes[a - n] };
                *d = d.derivative(a - a0);
            }
            let l = system.lagrangian_with(&mut self.lanes_scratch, t, &self.q_lanes, &self.v_lanes);
            for a in a0..a0 + width {
                self.gradient[a] = lane(&l, a - a0);
            }
        }
    }

    /// Set the midpoint `(q₀ + Δq/2, Δq/h)` of the current iterate and evaluate the
    /// generalized force there into `self.force` (zero when the system has none).
    fn midpoint(&mut self, system: &F, tm: f64, h: f64) {
        for i in 0..self.n {
            self.q_mid[i] = self.q[i] + 0.5 * self.delta[i];
            self.velocity[i] = self.delta[i] / h;
        }
        self.force.fill(0.0);
        self.has_force =
            system.generalized_force_with(&mut self.force_scratch, tm, &self.q_mid, &self.velocity, &mut self.force);
    }

    /// Add `(h/2) dQ/dΔq` to the Newton matrix: the generalized force at the midpoint depends
    /// on the unknown through `q_mid = q₀ + Δq/2` and `v = Δq/h`. One dual pass per column,
    /// seeding both at once. (Without it Newton only contracts by ~`c h / 2m` per iteration for
    /// a damping `c`, and fails once `c h ≳ 2m`.)
    fn add_force_jacobian(&mut self, system: &F, tm: f64, h: f64) {
        let n = self.n;
        let t = Dual64::from(tm);
        for j in 0..n {
            for i in 0..n {
                let seed = if i == j { 1.0 } else { 0.0 };
                self.q_force[i] = Dual64::new(self.q_mid[i], 0.5 * seed);
                self.v_force[i] = Dual64::new(self.velocity[i], seed / h);
            }
            self.force_dual.fill(Dual64::from(0.0));
            system.generalized_force_with(
                &mut self.force_dual_scratch,
                t,
                &self.q_force,
                &self.v_force,
                &mut self.force_dual,
            );
            for i in 0..n {
                self.newton[i * n + j] += 0.5 * h * self.force_dual[i].eps;
            }
        }
    }

    /// Advance by `h`: solve the discrete Euler–Lagrange equation for `q₁`, update `p`. It
    /// knows nothing of constraints among the coordinates: a constrained system is stepped
    /// through the [`Integrator`] interface ([`run`](super::run)), whose `advance` takes the
    /// constrained step.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a bad step, [`Error::NewtonFailed`] when Newton does not
    /// converge (step too large for the motion), [`Error::Diverged`] naming the value when one
    /// inside a Newton iteration stops being finite, [`Error::NonFinite`] when the new state is
    /// not finite.
    pub fn step(&mut self, system: &F, h: f64) -> Result<(), Error> {
        check_step(h)?;
        let t = self.t;
        let tm = t + 0.5 * h;
        let kept = self.newton_step == h;
        if let Some(residual) = retry_fresh(kept, |refresh| self.newton_unconstrained(system, h, refresh))? {
            return Err(Error::NewtonFailed { t, iterations: NEWTON_MAX_ITERATIONS, residual: Some(residual) });
        }
        self.final_momenta(system, tm, h, None);
        self.end_step(h);
        self.t = t + h;
        self.stats.steps += 1;
        if !(crate::error::all_finite(&self.q) && crate::error::all_finite(&self.p)) {
            return Err(crate::eom::non_finite(crate::error::Stage::Lagrangian, self.t, &self.q));
        }
        Ok(())
    }

    /// The predictor of a step `h`: `Δq = 2 Δq₋₁ − Δq₋₂`, the last two steps' increments
    /// extrapolated (error O(h³)) when both were steps of `h`, else `h v` with `v` the last
    /// velocity.
    fn predict(&mut self, h: f64) {
        if self.previous_step == h && self.last_step == h {
            for i in 0..self.n {
                self.delta[i] = 2.0 * self.last_delta[i] - self.previous_delta[i];
            }
        } else {
            for i in 0..self.n {
                self.delta[i] = h * self.velocity[i];
            }
        }
    }

    /// After a converged step of `h`: `q ← q + Δq`, and `Δq` kept for the next predictor.
    fn end_step(&mut self, h: f64) {
        for i in 0..self.n {
            self.q[i] += self.delta[i];
        }
        std::mem::swap(&mut self.previous_delta, &mut self.last_delta);
        self.last_delta.copy_from_slice(&self.delta);
        self.previous_step = self.last_step;
        self.last_step = h;
    }

    /// Newton on the discrete Euler–Lagrange equation of a step `h` from the predictor, with
    /// the kept Newton matrix unless `refresh` (see [`REFRESH_RATE`]). `Ok(None)` when it
    /// converged (`Δq` in `self.delta`), `Ok(Some(residual))` when it did not within
    /// [`NEWTON_MAX_ITERATIONS`].
    ///
    /// # Errors
    /// [`Error::NewtonFailed`] for a singular Newton matrix, [`Error::Diverged`] for a
    /// non-finite value inside an iteration.
    fn newton_unconstrained(&mut self, system: &F, h: f64, mut refresh: bool) -> Result<Option<f64>, Error> {
        let (t, tm) = (self.t, self.t + 0.5 * h);
        self.predict(h);
        let mut residual_norm = f64::INFINITY;
        let mut previous_update = f64::INFINITY;
        for iteration in 1..=NEWTON_MAX_ITERATIONS {
            self.stats.newton_iterations += 1;
            // Midpoint state and derivatives of L there.
            self.midpoint(system, tm, h);
            self.derivatives(system, tm, if refresh { Derivatives::Hessian } else { Derivatives::Gradient });
            self.check_finite(system, iteration)?;
            // Residual R = p₀ + (h/2) ∂L/∂q − ∂L/∂q̇ + (h/2) Q, and its size relative to the
            // magnitude of its terms.
            let relative_residual;
            (residual_norm, relative_residual) = self.momentum_residual(h, None);
            if refresh && !self.refresh_newton(system, tm, h) {
                return Err(Error::NewtonFailed { t, iterations: iteration, residual: Some(residual_norm) });
            }
            solve::lu_solve(self.n, &self.newton, &self.newton_pivots, &mut self.residual);
            self.check_update(system, iteration, "Δq")?;
            match self.apply_update(&mut previous_update, relative_residual, refresh) {
                Progress::Converged => return Ok(None),
                Progress::Iterating { slow } => refresh = slow,
            }
        }
        Ok(Some(residual_norm))
    }

    /// The residual of the discrete Euler–Lagrange equation into `self.residual`,
    /// `R = p₀ + (h/2)(∂L/∂q + Q) − ∂L/∂q̇ − C₀ᵀ Λ` at the midpoint (the impulse term with
    /// `constrained`: its rows and multipliers); returns `max |R_i|` and its largest size
    /// relative to the magnitude of the terms it is the sum of.
    fn momentum_residual(&mut self, h: f64, constrained: Option<&ConstrainedStep>) -> (f64, f64) {
        let n = self.n;
        let (mut norm, mut relative) = (0.0_f64, 0.0_f64);
        for i in 0..n {
            let mut residual = self.p[i] + 0.5 * h * (self.gradient[i] + self.force[i]) - self.gradient[n + i];
            let mut scale = self.p[i].abs()
                + 0.5 * h * (self.gradient[i].abs() + self.force[i].abs())
                + momentum_scale(&self.hessian, &self.gradient, &self.velocity, i);
            if let Some(k) = constrained {
                let impulse: f64 = (0..k.c).map(|r| k.force_rows[r * n + i] * k.multipliers[r]).sum();
                residual -= impulse;
                scale += impulse.abs();
            }
            self.residual[i] = residual;
            norm = f64::max(norm, residual.abs());
            relative = relative.max(residual.abs() / scale);
        }
        (norm, relative)
    }

    /// The Newton matrix at the current iterate, from the Hessian in `self.hessian`, factored
    /// into `self.newton` and kept for steps of `h`; `false` if it is singular.
    fn refresh_newton(&mut self, system: &F, tm: f64, h: f64) -> bool {
        self.newton_matrix(system, tm, h);
        self.stats.factorizations += 1;
        let factored = solve::lu_factor(self.n, &mut self.newton, &mut self.newton_pivots).is_ok();
        self.newton_step = if factored { h } else { f64::NAN };
        factored
    }

    /// The Newton matrix into `self.newton`: `dR/dq₁ = (h/4) L_qq + ½ L_qv − ½ L_vq − (1/h)
    /// L_vv`, `+ (h/2) dQ/dΔq` for systems with generalized forces.
    fn newton_matrix(&mut self, system: &F, tm: f64, h: f64) {
        let n = self.n;
        let m = 2 * n;
        for i in 0..n {
            for j in 0..n {
                self.newton[i * n + j] = 0.25 * h * self.hessian[i * m + j] + 0.5 * self.hessian[i * m + n + j]
                    - 0.5 * self.hessian[(n + i) * m + j]
                    - self.hessian[(n + i) * m + n + j] / h;
            }
        }
        if self.has_force {
            self.add_force_jacobian(system, tm, h);
        }
    }

    /// `Δq ← Δq − J⁻¹ R` (the solved update in `self.residual`), and whether Newton has
    /// converged: with a Newton matrix built at this iterate (`fresh`, quadratic convergence)
    /// the update below `NEWTON_RTOL` of `|Δq|`; with a kept one (linear convergence at the
    /// rate `ρ` of the last two updates) `ρ/(1 − ρ)` times the update below [`LINEAR_RTOL`] of
    /// `|Δq|`; or either at the round-off plateau (see [`MOMENTUM_ROUNDOFF`] and
    /// `invert_legendre`: a midpoint velocity passing through zero makes the tests relative to
    /// `|Δq|` smaller than the rounding of the momenta the residual is made of): the residual at
    /// round-off and the update no longer halving. An iteration is slow (the next one rebuilds
    /// the matrix) when it contracts by less than `1/REFRESH_RATE` with an update still above
    /// `NEWTON_RTOL` of `|Δq|`: below it, on the 80-window chain, the updates of a kept matrix
    /// slow down from round-off alone (1.1e-13 then 4.8e-14 of `|Δq|`, rate 0.42, with the
    /// residual at 8e-15 of its terms), and the next update shows the plateau.
    /// `previous_update` carries the last update's size between iterations.
    fn apply_update(&mut self, previous_update: &mut f64, relative_residual: f64, fresh: bool) -> Progress {
        let (mut update, mut scale) = (0.0_f64, 0.0_f64);
        for i in 0..self.n {
            self.delta[i] -= self.residual[i];
            update = update.max(self.residual[i].abs());
            scale = scale.max(self.delta[i].abs());
        }
        let rate = previous_update.is_finite().then(|| update / *previous_update);
        let linear = rate.is_some_and(|r| r < 1.0 && r / (1.0 - r) * update <= LINEAR_RTOL * scale);
        if update == 0.0 || fresh && update <= NEWTON_RTOL * scale || !fresh && linear {
            return Progress::Converged;
        }
        if update >= 0.5 * *previous_update && relative_residual <= MOMENTUM_ROUNDOFF {
            return Progress::Converged;
        }
        *previous_update = update;
        // Below `NEWTON_RTOL` of `|Δq|` a slow update is round-off, not a stale matrix.
        Progress::Iterating { slow: rate.is_some_and(|r| r > REFRESH_RATE) && update > NEWTON_RTOL * scale }
    }

    /// `p₁ = D₂L_d + (h/2) Q = (h/2)(∂L/∂q + Q) + ∂L/∂q̇` at the final midpoint, with the
    /// final residual (the impulse term with `constrained`) from the same gradient.
    fn final_momenta(&mut self, system: &F, tm: f64, h: f64, constrained: Option<&ConstrainedStep>) {
        let n = self.n;
        self.midpoint(system, tm, h);
        self.derivatives(system, tm, Derivatives::Gradient);
        let mut final_residual = 0.0_f64;
        for i in 0..n {
            let lq = self.gradient[i] + self.force[i];
            let lv = self.gradient[n + i];
            let mut residual = self.p[i] + 0.5 * h * lq - lv;
            if let Some(k) = constrained {
                residual -= (0..k.c).map(|r| k.force_rows[r * n + i] * k.multipliers[r]).sum::<f64>();
            }
            final_residual = final_residual.max(residual.abs());
            self.p[i] = 0.5 * h * lq + lv;
        }
        self.max_residual = self.max_residual.max(final_residual);
    }

    /// The continuous velocities `q̇` whose momenta `∂L/∂q̇(q, q̇, t)` equal the current `p`
    /// (Newton on the Legendre map, started from the last discrete velocity), into `qdot`.
    ///
    /// # Errors
    /// [`Error::NewtonFailed`] if the Legendre map cannot be inverted (singular `∂²L/∂q̇²`),
    /// [`Error::Diverged`] naming the value when one stops being finite.
    pub fn velocities(&mut self, system: &F, qdot: &mut [f64]) -> Result<(), Error> {
        // Keep the discrete velocity (the next step's predictor) in `delta`, which is free
        // between steps, and iterate on `velocity` from it.
        self.delta.copy_from_slice(&self.velocity);
        self.q_mid.copy_from_slice(&self.q);
        let result = self.invert_legendre(system);
        qdot.copy_from_slice(&self.velocity);
        self.velocity.copy_from_slice(&self.delta);
        result
    }

    /// Newton on `∂L/∂q̇(q_mid, velocity, t) = p`, iterating on `velocity`.
    ///
    /// It stops when the update is below `1e-13 |q̇|`, or when it has reached the round-off of
    /// the residual `∂L/∂q̇ − p`: the update no longer halves and the residual is below
    /// [`MOMENTUM_ROUNDOFF`] of the magnitude of its terms ([`momentum_scale`]). The first test
    /// alone cannot be met where a velocity passes through zero while its momentum does not:
    /// on the driven pendulum (`p = m l² θ̇ + m A ω l cos ωt cosθ`, the drive's term ≈ 0.3) at
    /// `dt` = 0.0125, t = 4.15, `θ̇` = 2.7e-4 at a turning point, the momentum's rounding
    /// (one unit in the last place of 0.3, 5.6e-17, divided by `m l²` = 1) is 2e-13 of `|θ̇|`:
    /// the residual alternated between ±5.6e-17 and `θ̇` between two values 5.6e-17 apart
    /// until Newton gave up after 50 iterations — reported with a residual of NaN, which was a
    /// placeholder in the error, not a value computed anywhere.
    fn invert_legendre(&mut self, system: &F) -> Result<(), Error> {
        let n = self.n;
        let m = 2 * n;
        let mut previous_update = f64::INFINITY;
        let mut residual_norm = f64::INFINITY;
        for iteration in 1..=NEWTON_MAX_ITERATIONS {
            self.stats.newton_iterations += 1;
            self.derivatives(system, self.t, Derivatives::Momentum);
            self.check_finite(system, iteration)?;
            residual_norm = 0.0;
            let mut relative_residual = 0.0_f64;
            for i in 0..n {
                self.residual[i] = self.gradient[n + i] - self.p[i];
                residual_norm = residual_norm.max(self.residual[i].abs());
                let scale = self.p[i].abs() + momentum_scale(&self.hessian, &self.gradient, &self.velocity, i);
                relative_residual = relative_residual.max(self.residual[i].abs() / scale);
                for j in 0..n {
                    self.jacobian[i * n + j] = self.hessian[(n + i) * m + n + j];
                }
            }
            self.stats.factorizations += 1;
            if solve::lu_factor(n, &mut self.jacobian, &mut self.pivots).is_err() {
                return Err(Error::NewtonFailed { t: self.t, iterations: iteration, residual: Some(residual_norm) });
            }
            solve::lu_solve(n, &self.jacobian, &self.pivots, &mut self.residual);
            self.check_update(system, iteration, "q̇")?;
            if legendre_update(&mut self.velocity, &self.residual, &mut previous_update, relative_residual) {
                return Ok(());
            }
        }
        Err(Error::NewtonFailed { t: self.t, iterations: NEWTON_MAX_ITERATIONS, residual: Some(residual_norm) })
    }

    /// [`Error::Diverged`] naming the first non-finite value among the point at which Newton
    /// evaluated (`q_mid`, `velocity`), the derivatives of `L` there and the generalized force,
    /// in iteration `iteration` (a wild iterate, or a blow-up of the motion; `f64::max` would
    /// drop a NaN from the residual's norm, so the values are checked one by one).
    fn check_finite(&self, system: &F, iteration: usize) -> Result<(), Error> {
        let n = self.n;
        let name = |i: usize| system.coordinates().get(i).map_or_else(|| i.to_string(), |c| c.name.clone());
        let named = |label: &str, values: &[f64]| {
            let i = values.iter().position(|v| !v.is_finite())?;
            Some(format!("{label}[{}] = {}", name(i), values[i]))
        };
        let hessian = || {
            let k = self.hessian.iter().position(|v| !v.is_finite())?;
            let (a, b) = (k / (2 * n), k % (2 * n));
            let variable = |a: usize| if a < n { name(a) } else { format!("{}̇", name(a - n)) };
            Some(format!("∂²L/∂{}∂{} = {}", variable(a), variable(b), self.hessian[k]))
        };
        let quantity = named("q", &self.q_mid)
            .or_else(|| named("q̇", &self.velocity))
            .or_else(|| named("∂L/∂q", &self.gradient[..n]))
            .or_else(|| named("∂L/∂q̇", &self.gradient[n..]))
            .or_else(|| named("Q", &self.force))
            .or_else(hessian);
        match quantity {
            None => Ok(()),
            Some(quantity) => Err(self.newton_diverged(iteration, &quantity)),
        }
    }

    /// [`Error::Diverged`] if the Newton update in `residual` (of `unknown`) is not finite: a
    /// numerically singular Newton matrix.
    fn check_update(&self, system: &F, iteration: usize, unknown: &str) -> Result<(), Error> {
        match non_finite_quantity(system.coordinates(), &self.residual, &[]) {
            None => Ok(()),
            Some(quantity) => {
                // `q[θ] = inf` from the helper names the coordinate: say what it updates.
                let quantity = format!("the update of {unknown}{}", quantity.trim_start_matches('q'));
                Err(self.newton_diverged(iteration, &quantity))
            }
        }
    }

    /// The divergence of a Newton iteration of the step from the current time.
    fn newton_diverged(&self, iteration: usize, quantity: &str) -> Error {
        Error::Diverged {
            t: self.t,
            step: self.stats.steps,
            quantity: format!("{quantity} in Newton iteration {iteration} of the variational integrator"),
        }
    }
}

impl<D: Dynamics> Variational<D> {
    /// Advance a constrained system by `h` (docs/method.md#constraints): Newton on the
    /// `n + c` equations
    ///
    /// `p₀ + D₁L_d(q₀, q₁) + (h/2) Q − C₀ᵀ Λ = 0`, `Φ(t₁, q₁) = 0`,
    /// `A(t_m, q_m) (q₁ − q₀)/h + b(t_m, q_m) = 0`,
    ///
    /// with `C₀ = [Φ_q; A](t₀, q₀)`, `q_m = (q₀ + q₁)/2`, for `(Δq, Λ)`, with the Jacobian
    /// `[[J, −C₀ᵀ], [D, 0]]` (`J` the unconstrained one, kept while it serves; `D` the exact
    /// derivative of the step's rows at each iterate,
    /// `Φ_q(t₁, q₁)` and `½ ∂(A v + b)/∂q + A/h`) eliminated by its Schur complement
    /// `D J⁻¹ C₀ᵀ`; then `p₁ = D₂L_d(q₀, q₁) + (h/2) Q`. Rows found dependent on the rows before
    /// them at `q₀` carry no impulse, and must then hold by themselves at the end of the step.
    ///
    /// # Errors
    /// As [`step`](Self::step); [`Error::InconsistentConstraints`] when a dependent row does not
    /// hold at the end of the step; [`Error::NonFinite`] for non-finite constraint rows.
    fn step_constrained(&mut self, system: &D, ws: &mut D::Workspace, h: f64) -> Result<(), Error> {
        check_step(h)?;
        let mut k = self.constrained.take().expect("a constrained run has the constrained buffers");
        let result = self.newton_constrained(system, ws, &mut k, h);
        self.constrained = Some(k);
        result
    }

    /// The impulse directions `C₀ = [Φ_q; A](t₀, q₀)` into `k.force_rows`, and which of them
    /// depend on the ones before (`C₀ C₀ᵀ` factored skipping dependent rows).
    ///
    /// # Errors
    /// Any error of the constraint rows.
    fn impulse_directions(&mut self, system: &D, ws: &mut D::Workspace, k: &mut ConstrainedStep) -> Result<(), Error> {
        let (n, c) = (self.n, k.c);
        system.constraint_rows(ws, (self.t, &self.q, &self.velocity), &mut k.force_rows, &mut k.phi, &mut k.rate)?;
        for i in 0..c {
            let row = &k.force_rows[i * n..(i + 1) * n];
            nonzero_columns(row, &mut k.nonzero);
            for l in 0..=i {
                let g = sparse_dot(row, &k.nonzero, &k.force_rows[l * n..(l + 1) * n]);
                k.gram[i * c + l] = g;
                k.gram[l * c + i] = g;
            }
        }
        constraints::factor_skipping(c, &mut k.gram, &mut k.dependent);
        k.active.clear();
        k.active.extend((0..c).filter(|&i| !k.dependent[i]));
        Ok(())
    }

    /// One constrained Newton update, with `self.residual` holding `R` and `self.newton` the
    /// factored Newton matrix `J` (kept across iterations, see [`REFRESH_RATE`]): `y = J⁻¹ R`,
    /// `X = J⁻¹ C₀ᵀ` over the independent rows (once per step and matrix), `(D X) δΛ = D y − C`
    /// with `D` the step's constraint rows at the current iterate, and leave `δΔq = y − X δΛ`
    /// in `self.residual` with `Λ` updated. `false` when the Schur complement is singular
    /// (Newton fails).
    ///
    /// # Errors
    /// Any error of the constraint rows.
    fn constrained_update(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        k: &mut ConstrainedStep,
        h: f64,
    ) -> Result<bool, Error> {
        let n = self.n;
        let (tm, t1) = (self.t + 0.5 * h, self.t + h);
        let ca = k.active.len();
        // The step's constraint rows and their derivative at the current iterate.
        for i in 0..n {
            k.q_end[i] = self.q[i] + self.delta[i];
        }
        system.step_constraint_rows(
            ws,
            (t1, &k.q_end),
            (tm, &self.q_mid, &self.velocity, h),
            &mut k.residual,
            &mut k.step_rows,
        )?;
        // y = J⁻¹ R (in `residual`), X = J⁻¹ C₀ᵀ over the independent rows.
        solve::lu_solve(n, &self.newton, &self.newton_pivots, &mut self.residual);
        if !k.mobility_current {
            for &r in &k.active {
                k.mobility[r * n..(r + 1) * n].copy_from_slice(&k.force_rows[r * n..(r + 1) * n]);
                solve::lu_solve(n, &self.newton, &self.newton_pivots, &mut k.mobility[r * n..(r + 1) * n]);
            }
            k.mobility_current = true;
        }
        // (D X) δΛ = D y − C over the independent rows; δΔq = −y + X δΛ, the products over each
        // row's nonzero columns.
        for (a, &r) in k.active.iter().enumerate() {
            let d = &k.step_rows[r * n..(r + 1) * n];
            nonzero_columns(d, &mut k.nonzero);
            for (b, &l) in k.active.iter().enumerate() {
                k.schur[a * ca + b] = sparse_dot(d, &k.nonzero, &k.mobility[l * n..(l + 1) * n]);
            }
            k.rhs[a] = sparse_dot(d, &k.nonzero, &self.residual) - k.residual[r];
        }
        if ca > 0 {
            if solve::lu_factor(ca, &mut k.schur[..ca * ca], &mut k.pivots[..ca]).is_err() {
                return Ok(false);
            }
            solve::lu_solve(ca, &k.schur[..ca * ca], &k.pivots[..ca], &mut k.rhs[..ca]);
        }
        for (a, &r) in k.active.iter().enumerate() {
            k.multipliers[r] += k.rhs[a];
            for i in 0..n {
                self.residual[i] -= k.mobility[r * n + i] * k.rhs[a];
            }
        }
        Ok(true)
    }

    /// After the step: a dependent row carries no impulse, so it must hold by itself — to the
    /// consistency tolerance of the constrained solve relative to its change over the step,
    /// plus the round-off of a row evaluated at coordinates of size `|q|` (the rows are finite
    /// here). Reads `k.residual` and `k.step_rows` at `q₁`; records the largest residual.
    ///
    /// # Errors
    /// [`Error::InconsistentConstraints`] naming the dependent row and the rows it depends on.
    fn check_dependent_rows(&mut self, system: &D, k: &ConstrainedStep, t1: f64) -> Result<(), Error> {
        let (n, c) = (self.n, k.c);
        let size = 1.0 + self.q.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        for i in 0..c {
            let d = &k.step_rows[i * n..(i + 1) * n];
            let change: f64 = d.iter().zip(&self.delta).map(|(g, x)| (g * x).abs()).sum();
            let row: f64 = d.iter().map(|g| g.abs()).sum();
            let value = k.residual[i].abs();
            self.max_constraint_residual = self.max_constraint_residual.max(value);
            if k.dependent[i]
                && value > constraints::CONSISTENT * change + constraints::POSITION_TOLERANCE * size * row.max(1.0)
            {
                return Err(Error::InconsistentConstraints {
                    t: t1,
                    q: self.q.clone(),
                    constraints: (0..c)
                        .filter(|&l| l == i || !k.dependent[l] && k.gram[i * c + l] != 0.0)
                        .map(|l| system.constraint_name(l))
                        .collect(),
                    residual: value,
                });
            }
        }
        Ok(())
    }

    fn newton_constrained(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        k: &mut ConstrainedStep,
        h: f64,
    ) -> Result<(), Error> {
        let (t, tm, t1) = (self.t, self.t + 0.5 * h, self.t + h);
        self.impulse_directions(system, ws, k)?;
        let kept = self.newton_step == h;
        if let Some(residual) =
            retry_fresh(kept, |refresh| self.newton_iterations_constrained(system, ws, k, h, refresh))?
        {
            return Err(Error::NewtonFailed { t, iterations: NEWTON_MAX_ITERATIONS, residual: Some(residual) });
        }
        self.final_momenta(system, tm, h, Some(k));
        self.end_step(h);
        system.step_constraint_rows(
            ws,
            (t1, &self.q),
            (tm, &self.q_mid, &self.velocity, h),
            &mut k.residual,
            &mut k.step_rows,
        )?;
        self.check_dependent_rows(system, k, t1)?;
        self.t = t1;
        self.stats.steps += 1;
        if !(crate::error::all_finite(&self.q) && crate::error::all_finite(&self.p)) {
            return Err(crate::eom::non_finite(crate::error::Stage::Lagrangian, self.t, &self.q));
        }
        Ok(())
    }

    /// Newton on the constrained step's equations from the predictor (`Λ = 0`: the equations
    /// are linear in it), with the kept Newton matrix unless `refresh`: as
    /// [`newton_unconstrained`](Self::newton_unconstrained), `Ok(None)` when converged.
    ///
    /// # Errors
    /// As [`newton_unconstrained`](Self::newton_unconstrained); any error of the constraint
    /// rows.
    fn newton_iterations_constrained(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        k: &mut ConstrainedStep,
        h: f64,
        mut refresh: bool,
    ) -> Result<Option<f64>, Error> {
        let (t, tm) = (self.t, self.t + 0.5 * h);
        self.predict(h);
        k.multipliers.fill(0.0);
        k.mobility_current = false;
        let mut residual_norm = f64::INFINITY;
        let mut previous_update = f64::INFINITY;
        for iteration in 1..=NEWTON_MAX_ITERATIONS {
            self.stats.newton_iterations += 1;
            self.midpoint(system, tm, h);
            self.derivatives(system, tm, if refresh { Derivatives::Hessian } else { Derivatives::Gradient });
            self.check_finite(system, iteration)?;
            let relative_residual;
            (residual_norm, relative_residual) = self.momentum_residual(h, Some(k));
            if refresh {
                if !self.refresh_newton(system, tm, h) {
                    return Err(Error::NewtonFailed { t, iterations: iteration, residual: Some(residual_norm) });
                }
                k.mobility_current = false;
            }
            if !self.constrained_update(system, ws, k, h)? {
                return Err(Error::NewtonFailed { t, iterations: iteration, residual: Some(residual_norm) });
            }
            self.check_update(system, iteration, "Δq")?;
            match self.apply_update(&mut previous_update, relative_residual, refresh) {
                Progress::Converged => return Ok(None),
                Progress::Iterating { slow } => refresh = slow,
            }
        }
        Ok(Some(residual_norm))
    }

    /// The continuous velocities `q̇` whose momenta equal the current `p`, into `qdot`, as
    /// [`velocities`](Self::velocities) but with the system's own momenta and mass matrix
    /// `M = ∂²L/∂q̇²` (taken at the last discrete velocity) instead of the Hessian of `L`:
    /// Newton on `∂L/∂q̇(q, q̇) = p` from the last discrete velocity, one update for a body
    /// model (its momenta are affine in `q̇`) and one evaluation that confirms it. Leaves the LU
    /// factor of `M` in `self.jacobian`.
    ///
    /// # Errors
    /// As [`velocities`](Self::velocities); any error of the system's momenta or mass matrix.
    fn velocities_with_mass_matrix(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        qdot: &mut [f64],
    ) -> Result<(), Error> {
        let n = self.n;
        qdot.copy_from_slice(&self.velocity);
        system.mass_matrix(ws, self.t, &self.q, qdot, &mut self.jacobian)?;
        // The size of the momenta's velocity part, |M v| row by row, for the round-off test.
        for i in 0..n {
            let row = &self.jacobian[i * n..(i + 1) * n];
            self.momentum_size[i] = row.iter().zip(qdot.iter()).map(|(m, v)| (m * v).abs()).sum::<f64>();
        }
        self.stats.factorizations += 1;
        let mut previous_update = f64::INFINITY;
        let mut residual_norm = f64::INFINITY;
        let singular = solve::lu_factor(n, &mut self.jacobian, &mut self.pivots).is_err();
        for iteration in 1..=NEWTON_MAX_ITERATIONS {
            self.stats.newton_iterations += 1;
            self.stats.evaluations += 1;
            system.momenta(ws, self.t, &self.q, qdot, &mut self.residual)?;
            residual_norm = 0.0;
            let mut relative_residual = 0.0_f64;
            for i in 0..n {
                let momentum = self.residual[i];
                self.residual[i] = momentum - self.p[i];
                residual_norm = residual_norm.max(self.residual[i].abs());
                let scale = self.p[i].abs() + momentum.abs() + self.momentum_size[i];
                relative_residual = relative_residual.max(self.residual[i].abs() / scale);
            }
            if singular {
                return Err(Error::NewtonFailed { t: self.t, iterations: iteration, residual: Some(residual_norm) });
            }
            solve::lu_solve(n, &self.jacobian, &self.pivots, &mut self.residual);
            self.check_update(system, iteration, "q̇")?;
            if legendre_update(qdot, &self.residual, &mut previous_update, relative_residual) {
                return Ok(());
            }
        }
        Err(Error::NewtonFailed { t: self.t, iterations: NEWTON_MAX_ITERATIONS, residual: Some(residual_norm) })
    }

    /// The velocities of the current state of a constrained system, on the constraints: the
    /// inversion of the Legendre map of `p` ([`velocities_with_mass_matrix`](Self::velocities_with_mass_matrix)), then the
    /// momenta moved along the constraint directions, `p − Gᵀ μ` with `G = [Φ_q; A](t, q)`,
    /// so that the velocities satisfy `Φ_q q̇ + Φ_t = 0` and `A q̇ + b = 0`:
    /// `(G M⁻¹ Gᵀ) μ = G q̇ + [Φ_t; b]`, `q̇ ← q̇ − M⁻¹ Gᵀ μ` (exact for a Lagrangian quadratic
    /// in `q̇`, as every body model's). Dependent rows carry no `μ`. The held `p` is left as it
    /// is: its component along `Gᵀ(q)` is absorbed by the next step's impulse.
    fn constrained_velocities(&mut self, system: &D, ws: &mut D::Workspace, qdot: &mut [f64]) -> Result<(), Error> {
        self.velocities_with_mass_matrix(system, ws, qdot)?;
        let mut k = self.constrained.take().expect("a constrained run has the constrained buffers");
        let result = (|| {
            let (n, c) = (self.n, k.c);
            system.constraint_rows(ws, (self.t, &self.q, qdot), &mut k.force_rows, &mut k.phi, &mut k.rate)?;
            // `jacobian` holds the LU factor of ∂²L/∂q̇² from the inversion: X = M⁻¹ Gᵀ.
            k.mobility.copy_from_slice(&k.force_rows);
            for row in k.mobility.chunks_mut(n) {
                solve::lu_solve(n, &self.jacobian, &self.pivots, row);
            }
            for i in 0..c {
                for l in 0..=i {
                    let s = dot(&k.force_rows[i * n..(i + 1) * n], &k.mobility[l * n..(l + 1) * n]);
                    k.gram[i * c + l] = s;
                    k.gram[l * c + i] = s;
                }
            }
            constraints::factor_skipping(c, &mut k.gram, &mut k.dependent);
            k.rhs.copy_from_slice(&k.rate);
            constraints::forward_skipping(c, &k.gram, &k.dependent, &mut k.rhs);
            constraints::backward_skipping(c, &k.gram, &k.dependent, &mut k.rhs);
            for r in 0..c {
                for i in 0..n {
                    qdot[i] -= k.mobility[r * n + i] * k.rhs[r];
                }
            }
            Ok(())
        })();
        self.constrained = Some(k);
        result
    }
}

/// One Newton update of the inversion of the Legendre map: `v ← v − u` with `u` the solved
/// update, and whether it has converged — the update below `1e-13 |v|` (`∂L/∂q̇` is affine in `q̇`
/// for mechanical systems: one update is exact up to round-off), or at the round-off plateau of
/// the residual (see `Variational::invert_legendre`). `previous_update` carries the last
/// update's size between iterations.
fn legendre_update(v: &mut [f64], u: &[f64], previous_update: &mut f64, relative_residual: f64) -> bool {
    let (mut update, mut scale) = (0.0_f64, 0.0_f64);
    for (vi, ui) in v.iter_mut().zip(u) {
        *vi -= ui;
        update = update.max(ui.abs());
        scale = scale.max(vi.abs());
    }
    if update <= 1e-13 * scale || update == 0.0 {
        return true;
    }
    if update >= 0.5 * *previous_update && relative_residual <= MOMENTUM_ROUNDOFF {
        return true;
    }
    *previous_update = update;
    false
}

/// A step's Newton iteration, `attempt(refresh)`, started with the kept Newton matrix when
/// `kept` (a fresh one otherwise); if that does not converge (`Ok(Some(residual))`) or fails,
/// the kept matrix may be what failed: once more with a fresh one.
fn retry_fresh(kept: bool, mut attempt: impl FnMut(bool) -> Result<Option<f64>, Error>) -> Result<Option<f64>, Error> {
    let outcome = attempt(!kept);
    if kept && !matches!(outcome, Ok(None)) { attempt(true) } else { outcome }
}

/// The columns of `row` that are not zero, into `nonzero` (a loop's constraint row involves the
/// few coordinates of its loop).
fn nonzero_columns(row: &[f64], nonzero: &mut Vec<usize>) {
    nonzero.clear();
    nonzero.extend(row.iter().enumerate().filter(|(_, g)| **g != 0.0).map(|(j, _)| j));
}

/// `Σ_j row_j x_j` over the columns `nonzero` of `row` ([`nonzero_columns`]).
fn sparse_dot(row: &[f64], nonzero: &[usize], x: &[f64]) -> f64 {
    nonzero.iter().fold(0.0, |sum, &j| sum + row[j] * x[j])
}

/// `Σ a_i b_i`.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl<D: Dynamics> Integrator<D> for Variational<D> {
    fn begin(&mut self, system: &D, _: &mut D::Workspace, initial: &State, _: f64) -> Result<(), Error> {
        check_step(self.grid.dt)?;
        let counts = Dynamics::constraint_counts(system);
        self.constrained = (counts != (0, 0)).then(|| Box::new(ConstrainedStep::new(self.n, counts)));
        self.grid = Grid::new(initial.t, self.grid.dt);
        self.start(system, initial.t, &initial.q, &initial.qdot)
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn fixed_step(&self) -> Option<f64> {
        Some(self.grid.dt)
    }

    fn proposed_step(&self) -> f64 {
        self.grid.dt
    }

    fn reached(&self, t_out: f64) -> bool {
        self.grid.reached(t_out)
    }

    fn advance(&mut self, system: &D, ws: &mut D::Workspace, t_out: f64, _: f64) -> Result<(), Error> {
        let (_, h) = self.grid.next(t_out);
        let (t, k) = (self.t, self.grid.k);
        let result =
            if self.constrained.is_some() { self.step_constrained(system, ws, h) } else { self.step(system, h) };
        result.map_err(|e| diverged(system, e, t, k))?;
        self.grid.k += 1;
        let coordinates = system.coordinates();
        let quantity = non_finite_quantity(coordinates, &self.q, &[]).or_else(|| {
            let i = self.p.iter().position(|v| !v.is_finite())?;
            let name = coordinates.get(i).map_or_else(|| i.to_string(), |c| c.name.clone());
            Some(format!("p[{name}] = {}", self.p[i]))
        });
        match quantity {
            Some(quantity) => Err(Error::Diverged { t: self.t, step: k, quantity }),
            None => Ok(()),
        }
    }

    /// The coordinates and the velocities of the current momenta (the initial velocities as
    /// given at the start); for a constrained system, the velocities on the constraints
    /// (`Variational::constrained_velocities`).
    fn read(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        t: f64,
        q: &mut [f64],
        qdot: &mut [f64],
    ) -> Result<(), Error> {
        if t == self.t0 {
            qdot.copy_from_slice(&self.qdot0);
        } else if self.constrained.is_some() {
            self.constrained_velocities(system, ws, qdot)?;
        } else {
            self.velocities_with_mass_matrix(system, ws, qdot)?;
        }
        q.copy_from_slice(&self.q);
        Ok(())
    }

    fn current(&self) -> (&[f64], &[f64]) {
        (&self.q, &self.velocity)
    }

    /// Nothing: the constrained discrete Euler–Lagrange equations satisfy the constraints to
    /// the Newton tolerance at every step, and projecting `(q, p)` would change the method (the
    /// driver does not call it, see [`keeps_constraints`](Integrator::keeps_constraints)).
    fn project(&mut self, _: &D, _: &mut D::Workspace) -> Result<(), Error> {
        Ok(())
    }

    fn keeps_constraints(&self) -> bool {
        true
    }

    fn stats(&self) -> Stats {
        Self::stats(self)
    }
}

/// The magnitude of the terms of the momentum `∂L/∂q̇_i` at velocity `v`: the value itself and
/// `Σ_j |∂²L/∂q̇_i∂q̇_j v_j|`, the size of its velocity part `M v` (for a Lagrangian quadratic
/// in `q̇`, `∂L/∂q̇ = M v + b` and `|b| ≤ |∂L/∂q̇| + |M v|`), from the gradient and Hessian of `L`
/// in `z = (q, q̇)`.
fn momentum_scale(hessian: &[f64], gradient: &[f64], v: &[f64], i: usize) -> f64 {
    let n = v.len();
    let row = &hessian[(n + i) * 2 * n + n..(n + i + 1) * 2 * n];
    gradient[n + i].abs() + row.iter().zip(v).map(|(m, v)| (m * v).abs()).sum::<f64>()
}

/// Where a Newton iteration stands after its update.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Progress {
    /// Converged.
    Converged,
    /// Not yet; `slow` when it contracted by less than `1/REFRESH_RATE`, so that the next
    /// iteration rebuilds the Newton matrix.
    Iterating { slow: bool },
}

/// Which derivatives of `L` in `z = (q, q̇)` [`Variational::derivatives`] evaluates.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Derivatives {
    /// The gradient (`2n/CHUNK` vector-dual passes).
    Gradient,
    /// The gradient and the Hessian (`n (2n + 1)` passes).
    Hessian,
    /// The momenta `∂L/∂q̇` and their block `∂²L/∂q̇²` of the Hessian (`n (n + 1)/2` passes),
    /// for the inversion of the Legendre map; the rest is left as it was.
    Momentum,
}

/// Apply `f` to variable `a` of `z = (q, q̇)`.
fn seed(q: &mut [HyperDual64], v: &mut [HyperDual64], a: usize, f: impl Fn(&mut HyperDual64)) {
    let n = q.len();
    if a < n { f(&mut q[a]) } else { f(&mut v[a - n]) }
}
