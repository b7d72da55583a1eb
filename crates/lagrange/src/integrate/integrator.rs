//! The stepping trait every integrator implements, its one statistics type, and the step grid
//! of the fixed-step methods.

use super::{check_step, non_finite_quantity};
use crate::{Dynamics, Error, State};

/// Work counters of an integrator, and of a run.
///
/// One evaluation is one evaluation of the dynamics at one state: `q̈` in `f64` for the
/// Runge–Kutta methods; the gradient of `L` (with its Hessian when Newton needs it) at one
/// midpoint or state for [`Variational`](super::Variational). A counter a method has no use
/// for stays 0.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (error test failed, or Newton failed and the step was halved): the
    /// error-controlled methods.
    pub rejected: usize,
    /// Evaluations of the dynamics (see above).
    pub evaluations: usize,
    /// Newton iterations (implicit methods).
    pub newton_iterations: usize,
    /// Evaluations of a Newton Jacobian: the acceleration Jacobian `∂q̈/∂(q, q̇)` (`2n` dual
    /// passes each) for the implicit Runge–Kutta methods, the Hessian of `L` for the
    /// variational integrator.
    pub jacobians: usize,
    /// LU factorizations of a Newton matrix (implicit methods).
    pub factorizations: usize,
    /// The start of the accepted step at which the explicit adaptive method's stiffness test
    /// first fired ([`Dopri5`](super::Dopri5) only; `None` otherwise). The integration goes on;
    /// only a later failure says so.
    pub stiffness: Option<f64>,
    /// Steps taken another way than the method's own ([`Gauss4`](super::Gauss4) only): steps
    /// on a system with constraints among its coordinates whose Newton iteration did not
    /// converge (near a singular configuration), each taken by explicit RK4 substeps.
    pub fallbacks: usize,
}

/// One stepping interface over all integrators, as the driver
/// ([`run`](super::run)) uses them: start at a state, step toward an output time, read the
/// state there (by dense output where the method has one), and report the work done.
///
/// Every step is checked: an evaluation that stops being finite within a step, or a state that
/// is not finite after it, is reported as [`Error::Diverged`] naming the quantity.
pub trait Integrator<D: Dynamics> {
    /// Start at `initial` for a run that ends at `t_end` (the adaptive methods choose their
    /// first step from the span); resets the statistics.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a step that was never set or is invalid; any error of the
    /// equations of motion at the initial state.
    fn begin(&mut self, system: &D, ws: &mut D::Workspace, initial: &State, t_end: f64) -> Result<(), Error>;

    /// Current time.
    fn t(&self) -> f64;

    /// The fixed step (`None` for the error-controlled methods). A fixed-step method steps on
    /// the grid `t0 + k dt` and takes one shorter last step to an output time off the grid.
    fn fixed_step(&self) -> Option<f64> {
        None
    }

    /// The length of the next step, as far as it is known.
    fn proposed_step(&self) -> f64;

    /// Whether the integration has reached `t_out`, so that [`read`](Self::read) can give the
    /// state there.
    fn reached(&self, t_out: f64) -> bool;

    /// Take one step toward `t_out`, which is not yet [`reached`](Self::reached), never past
    /// `t_end`.
    ///
    /// # Errors
    /// [`Error::Diverged`] when the state or a stage stops being finite; any error of the
    /// method ([`Error::NewtonFailed`], [`Error::StepSizeUnderflow`], [`Error::Stiff`], …) or of
    /// the equations of motion.
    fn advance(&mut self, system: &D, ws: &mut D::Workspace, t_out: f64, t_end: f64) -> Result<(), Error>;

    /// The state at `t`, a time [`reached`](Self::reached) and not before the last step: the
    /// current state, or the dense output within the last step where the method has one.
    ///
    /// # Errors
    /// The variational integrator's [`Error::NewtonFailed`] when its Legendre map cannot be
    /// inverted.
    fn read(&mut self, system: &D, ws: &mut D::Workspace, t: f64, q: &mut [f64], qdot: &mut [f64])
    -> Result<(), Error>;

    /// The state `(q, q̇)` the method holds at [`t`](Self::t), after its last accepted step
    /// (or at the start), without computing anything: what the driver checks against the
    /// admissible region after every step. The velocities are the method's own: for the
    /// variational integrator, its discrete velocity `Δq/h` of the last step (the initial
    /// velocities at the start), which [`read`](Self::read) would refine by a Newton solve.
    fn current(&self) -> (&[f64], &[f64]);

    /// Work done since [`begin`](Self::begin).
    fn stats(&self) -> Stats;

    /// Project the held state onto the system's constraints
    /// ([`Dynamics::project`]) and refresh what the method derives from it (an `f` carried
    /// over from the step). The driver calls it after every accepted step of a constrained
    /// system.
    ///
    /// # Errors
    /// Any error of the projection or of the equations of motion.
    fn project(&mut self, system: &D, ws: &mut D::Workspace) -> Result<(), Error>;

    /// Whether the method satisfies the constraints by itself (the variational integrator's
    /// constrained discrete Euler–Lagrange equations): the driver then neither projects its
    /// state after a step nor the samples it reads, and the recorded violation is the
    /// method's own. `false` (the default): the driver projects.
    fn keeps_constraints(&self) -> bool {
        false
    }
}

/// A fixed-step method that holds its own [`State`] on a [`Grid`] ([`Rk4`](super::Rk4),
/// [`Gauss4`](super::Gauss4)): the one [`Integrator`] implementation below serves them all.
pub(crate) trait OnGrid {
    /// The state on the grid, the grid and the counters.
    fn grid(&self) -> (&State, &Grid, Stats);
    /// The same, to change.
    fn grid_mut(&mut self) -> (&mut State, &mut Grid, &mut Stats);
    /// Forget what an earlier run left (a Newton matrix), at [`Integrator::begin`].
    fn forget(&mut self) {}
    /// Advance `state` by `h`: the method's own `step`.
    fn step_state<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        state: &mut State,
        h: f64,
    ) -> Result<(), Error>;
}

impl<D: Dynamics, M: OnGrid> Integrator<D> for M {
    fn begin(&mut self, _: &D, _: &mut D::Workspace, initial: &State, _: f64) -> Result<(), Error> {
        let (state, grid, stats) = self.grid_mut();
        check_step(grid.dt)?;
        state.clone_from(initial);
        *grid = Grid::new(initial.t, grid.dt);
        *stats = Stats::default();
        self.forget();
        Ok(())
    }

    fn t(&self) -> f64 {
        self.grid().0.t
    }

    fn fixed_step(&self) -> Option<f64> {
        Some(self.grid().1.dt)
    }

    fn proposed_step(&self) -> f64 {
        self.grid().1.dt
    }

    fn reached(&self, t_out: f64) -> bool {
        self.grid().1.reached(t_out)
    }

    fn advance(&mut self, system: &D, ws: &mut D::Workspace, t_out: f64, _: f64) -> Result<(), Error> {
        let (current, grid, _) = self.grid_mut();
        let ((t, h), k) = (grid.next(t_out), grid.k);
        let mut state = std::mem::replace(current, State { t, q: Vec::new(), qdot: Vec::new() });
        state.t = t;
        let result = self.step_state(system, ws, &mut state, h).map_err(|e| diverged(system, e, t, k));
        let (current, grid, _) = self.grid_mut();
        *current = state;
        result?;
        grid.k += 1;
        check_finite(system, &current.q, &current.qdot, current.t, k)
    }

    fn read(&mut self, _: &D, _: &mut D::Workspace, _: f64, q: &mut [f64], qdot: &mut [f64]) -> Result<(), Error> {
        let state = self.grid().0;
        q.copy_from_slice(&state.q);
        qdot.copy_from_slice(&state.qdot);
        Ok(())
    }

    fn current(&self) -> (&[f64], &[f64]) {
        let state = self.grid().0;
        (&state.q, &state.qdot)
    }

    fn project(&mut self, system: &D, ws: &mut D::Workspace) -> Result<(), Error> {
        let state = self.grid_mut().0;
        system.project(ws, state.t, &mut state.q, &mut state.qdot)
    }

    fn stats(&self) -> Stats {
        self.grid().2
    }
}

/// The step grid of a fixed-step method: steps number `k` starts at `t0 + k dt` (no
/// accumulated round-off in the time); an output time off the grid is reached by one shorter
/// step from the grid point before it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Grid {
    pub(crate) t0: f64,
    pub(crate) dt: f64,
    /// Steps taken.
    pub(crate) k: usize,
}

impl Grid {
    pub(crate) fn new(t0: f64, dt: f64) -> Self {
        Self { t0, dt, k: 0 }
    }

    /// Whole steps from `t0` to `t_out`, and whether `t_out` lies on the grid (within 1e-9 of a
    /// step, relative).
    pub(crate) fn position(t0: f64, dt: f64, t_out: f64) -> (usize, bool) {
        let exact = (t_out - t0) / dt;
        let target = exact.round();
        let on_grid = (exact - target).abs() <= 1e-9 * exact.max(1.0);
        (if on_grid { target as usize } else { exact.floor() as usize }, on_grid)
    }

    /// Whether the steps taken reach `t_out`.
    pub(crate) fn reached(&self, t_out: f64) -> bool {
        let (whole, on_grid) = Self::position(self.t0, self.dt, t_out);
        self.k >= if on_grid { whole } else { whole + 1 }
    }

    /// Start and length of the next step toward `t_out`.
    pub(crate) fn next(&self, t_out: f64) -> (f64, f64) {
        let t = self.t0 + self.k as f64 * self.dt;
        let (whole, _) = Self::position(self.t0, self.dt, t_out);
        if self.k < whole { (t, self.dt) } else { (t, t_out - t) }
    }
}

/// The state after a step must be finite; the error names the first coordinate that is not.
pub(crate) fn check_finite<D: Dynamics>(system: &D, q: &[f64], v: &[f64], t: f64, step: usize) -> Result<(), Error> {
    match non_finite_quantity(system.coordinates(), q, v) {
        None => Ok(()),
        Some(quantity) => Err(Error::Diverged { t, step, quantity }),
    }
}

/// A non-finite evaluation during a run is a divergence of the run: name the coordinate of the
/// stage state that blew up when it is one, or else the stage of the evaluation.
pub(crate) fn diverged<D: Dynamics>(system: &D, error: Error, t: f64, step: usize) -> Error {
    match error {
        Error::NonFinite { stage, q, .. } => {
            let quantity = match non_finite_quantity(system.coordinates(), &q, &[]) {
                Some(named) => format!("{named} within the step"),
                None if stage == crate::error::Stage::State => "q̇ non-finite within the step".to_string(),
                None => format!("non-finite {stage} at q = {q:?} within the step"),
            };
            Error::Diverged { t, step, quantity }
        }
        other => other,
    }
}

/// The first-order form `f(t, y) = (q̇, a(t, q, q̇))` of the equations of motion, with
/// `y = (q, q̇)` of `n` coordinates each, into `out` (the adaptive Runge–Kutta methods).
pub(crate) fn rhs<D: Dynamics>(
    system: &D,
    ws: &mut D::Workspace,
    n: usize,
    t: f64,
    y: &[f64],
    out: &mut [f64],
) -> Result<(), Error> {
    let (q, v) = y.split_at(n);
    let (dq, dv) = out.split_at_mut(n);
    dq.copy_from_slice(v);
    system.accelerations(ws, t, q, v, dv)
}
