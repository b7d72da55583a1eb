//! The acceleration Jacobian `∂q̈/∂(q, q̇)`: forward-mode AD column by column, and the
//! finite-difference fallback of [`Dynamics::acceleration_jacobian`].

use super::Dynamics;
use crate::Error;
use crate::eom::non_finite;
use crate::error::Stage;
use num_dual::Dual64;

/// What the tangent passes of a Jacobian need besides the `f64` workspace: the workspace `W`
/// of the evaluation in `Dual64` and the seeded state. An `f64` workspace holds one (boxed),
/// allocated by [`Dynamics::new_workspace`] or by the first Jacobian.
#[derive(Clone, Debug)]
pub(crate) struct Tangent<W> {
    /// The evaluation's workspace in `Dual64`.
    pub(crate) workspace: W,
    /// The seeded state.
    pub(crate) seeds: Seeds,
}

impl<W> Tangent<W> {
    pub(crate) fn new(workspace: W, n: usize) -> Box<Self> {
        Box::new(Self { workspace, seeds: Seeds::new(n) })
    }
}

/// Seeded copies of the state for the tangent passes, allocated once.
#[derive(Clone, Debug)]
pub(crate) struct Seeds {
    /// Coordinates as duals (n); one of them (or of `qdot`) carries `ε = 1` during a pass.
    q: Vec<Dual64>,
    /// Velocities as duals (n).
    qdot: Vec<Dual64>,
    /// `∂q̈/∂x_j` of the current pass: column `j` of the Jacobian (n).
    column: Vec<f64>,
}

impl Seeds {
    pub(crate) fn new(n: usize) -> Self {
        let zero = Dual64::from_re(0.0);
        Self { q: vec![zero; n], qdot: vec![zero; n], column: vec![0.0; n] }
    }

    /// Fill `jacobian` (n × 2n, row-major) with `2n` tangent passes: pass `j` seeds
    /// `x_j = (q, q̇)_j` and `tangent(t, q, q̇, column)` writes the `ε` parts of `q̈` into `column`.
    pub(crate) fn jacobian(
        &mut self,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
        mut tangent: impl FnMut(Dual64, &[Dual64], &[Dual64], &mut [f64]) -> Result<(), Error>,
    ) -> Result<(), Error> {
        let n = self.q.len();
        check_shape(n, q, qdot, jacobian)?;
        // Unseeded state.
        for (d, &x) in self.q.iter_mut().zip(q) {
            *d = Dual64::from_re(x);
        }
        for (d, &x) in self.qdot.iter_mut().zip(qdot) {
            *d = Dual64::from_re(x);
        }
        let t = Dual64::from_re(t);
        // One pass per column: seed, evaluate, unseed, scatter.
        for j in 0..2 * n {
            let seed = if j < n { &mut self.q[j] } else { &mut self.qdot[j - n] };
            seed.eps = 1.0;
            let result = tangent(t, &self.q, &self.qdot, &mut self.column);
            let seed = if j < n { &mut self.q[j] } else { &mut self.qdot[j - n] };
            seed.eps = 0.0;
            result?;
            for i in 0..n {
                jacobian[i * 2 * n + j] = self.column[i];
            }
        }
        check_finite(t.re, q, jacobian)
    }
}

fn check_shape(n: usize, q: &[f64], qdot: &[f64], jacobian: &[f64]) -> Result<(), Error> {
    if q.len() != n {
        return Err(Error::DimensionMismatch { what: "q", expected: n, got: q.len() });
    }
    if qdot.len() != n {
        return Err(Error::DimensionMismatch { what: "q̇", expected: n, got: qdot.len() });
    }
    if jacobian.len() != 2 * n * n {
        return Err(Error::DimensionMismatch {
            what: "acceleration Jacobian",
            expected: 2 * n * n,
            got: jacobian.len(),
        });
    }
    Ok(())
}

fn check_finite(t: f64, q: &[f64], jacobian: &[f64]) -> Result<(), Error> {
    if crate::error::all_finite(jacobian) { Ok(()) } else { Err(non_finite(Stage::Jacobian, t, q)) }
}

/// Central differences of the `f64` accelerations, column by column (the default of
/// [`Dynamics::acceleration_jacobian`]): step `ε^{1/3} max(|x_j|, 1)`, truncation and
/// cancellation errors both about `ε^{2/3}` of the scale.
pub(super) fn finite_differences<D: Dynamics + ?Sized>(
    system: &D,
    ws: &mut D::Workspace,
    t: f64,
    q: &[f64],
    qdot: &[f64],
    jacobian: &mut [f64],
) -> Result<(), Error> {
    let n = system.dof();
    check_shape(n, q, qdot, jacobian)?;
    let (mut q_moved, mut qdot_moved) = (q.to_vec(), qdot.to_vec());
    let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
    for j in 0..2 * n {
        let x = if j < n { q[j] } else { qdot[j - n] };
        let step = f64::EPSILON.cbrt() * x.abs().max(1.0);
        let (up, down) = (x + step, x - step);
        for (moved, out) in [(up, &mut plus), (down, &mut minus)] {
            if j < n {
                q_moved[j] = moved;
            } else {
                qdot_moved[j - n] = moved;
            }
            system.accelerations(ws, t, &q_moved, &qdot_moved, out)?;
        }
        if j < n {
            q_moved[j] = x;
        } else {
            qdot_moved[j - n] = x;
        }
        for i in 0..n {
            jacobian[i * 2 * n + j] = (plus[i] - minus[i]) / (up - down);
        }
    }
    check_finite(t, q, jacobian)
}
