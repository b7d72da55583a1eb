//! The finite-difference fallback of [`Dynamics::acceleration_jacobian`]; the exact
//! forward-mode passes seed the state with [`crate::seed::Seeds`].

use super::Dynamics;
use crate::Error;
use crate::seed::{check_finite, check_shape};

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
