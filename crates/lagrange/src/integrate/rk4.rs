//! The classical fourth-order Runge–Kutta method, fixed step.

use super::check_step;
use super::integrator::{Grid, OnGrid, Stats};
use crate::{Dynamics, Error, State};

/// Classical RK4 on `(q, q̇)' = (q̇, a(t, q, q̇))`: global error `O(h⁴)`.
/// Buffers are allocated once in [`Rk4::new`]; [`Rk4::step`] allocates nothing.
///
/// Two ways to use it: [`step`](Self::step) advances a [`State`] the caller holds; as an
/// [`Integrator`](super::Integrator) (with the step set by [`with_step`](Self::with_step)) it holds its own state
/// on the grid `t0 + k dt`.
#[derive(Clone, Debug)]
pub struct Rk4 {
    /// Stage accelerations `k_v` (4 × n).
    accel: [Vec<f64>; 4],
    /// Stage velocities `k_q` (4 × n).
    vel: [Vec<f64>; 4],
    /// Stage coordinates (n).
    q_stage: Vec<f64>,
    /// The state and step grid of the [`Integrator`](super::Integrator) interface.
    state: State,
    grid: Grid,
    stats: Stats,
}

impl Rk4 {
    /// Buffers for `n` coordinates (the step is not set: see [`with_step`](Self::with_step)).
    pub fn new(n: usize) -> Self {
        let z = || vec![0.0; n];
        Self {
            accel: [z(), z(), z(), z()],
            vel: [z(), z(), z(), z()],
            q_stage: z(),
            state: State::new(0.0, z(), z()),
            grid: Grid::new(0.0, f64::NAN),
            stats: Stats::default(),
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

    /// Advance `state` by `h`.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a step that is not positive and finite; any error of the
    /// equations of motion.
    pub fn step<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        state: &mut State,
        h: f64,
    ) -> Result<(), Error> {
        check_step(h)?;
        let n = state.dof();
        let t = state.t;
        // Stage 1 at (t, q, q̇).
        self.vel[0].copy_from_slice(&state.qdot);
        system.accelerations(ws, t, &state.q, &state.qdot, &mut self.accel[0])?;
        // Stages 2–4: (t + c h, q + c h k_q, q̇ + c h k_v), c = ½, ½, 1.
        for (s, c) in [(1, 0.5), (2, 0.5), (3, 1.0)] {
            for i in 0..n {
                self.q_stage[i] = state.q[i] + c * h * self.vel[s - 1][i];
                self.vel[s][i] = state.qdot[i] + c * h * self.accel[s - 1][i];
            }
            system.accelerations(ws, t + c * h, &self.q_stage, &self.vel[s], &mut self.accel[s])?;
        }
        // Weights 1/6, 1/3, 1/3, 1/6.
        for i in 0..n {
            state.q[i] += h / 6.0 * (self.vel[0][i] + 2.0 * self.vel[1][i] + 2.0 * self.vel[2][i] + self.vel[3][i]);
            state.qdot[i] +=
                h / 6.0 * (self.accel[0][i] + 2.0 * self.accel[1][i] + 2.0 * self.accel[2][i] + self.accel[3][i]);
        }
        state.t = t + h;
        self.stats.steps += 1;
        self.stats.evaluations += 4;
        Ok(())
    }
}

impl OnGrid for Rk4 {
    fn grid(&self) -> (&State, &Grid, Stats) {
        (&self.state, &self.grid, self.stats)
    }

    fn grid_mut(&mut self) -> (&mut State, &mut Grid, &mut Stats) {
        (&mut self.state, &mut self.grid, &mut self.stats)
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
