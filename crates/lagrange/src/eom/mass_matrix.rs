//! Mass matrix `M = Σ_b J_bᵀ D_b J_b`, `D_b = diag(m_b, m_b, I_b)`.

use super::size::Size;
use crate::{Mechanism, Model, Scalar, Workspace};

/// Assemble `ws.mass_matrix` from `ws.jacobian` (upper triangle, mirrored).
pub(crate) fn assemble<M: Mechanism, S: Scalar, N: Size>(model: &Model<M>, ws: &mut Workspace<S>, size: N) {
    let n = size.get();
    let (mm, jac) = (&mut ws.mass_matrix[..n * n], &ws.jacobian[..]);
    mm.fill(S::zero());
    for (b, (&m, &inertia)) in model.mass.iter().zip(&model.inertia).enumerate() {
        let rows = &jac[3 * b * n..3 * (b + 1) * n];
        // Translational part m (Jxᵀ Jx + Jyᵀ Jy), upper triangle.
        if m != 0.0 {
            for i in 0..n {
                let (xi, yi) = (rows[i] * m, rows[n + i] * m);
                for j in i..n {
                    mm[i * n + j] += xi * rows[j] + yi * rows[n + j];
                }
            }
        }
        // Rotational part I Jφᵀ Jφ.
        if inertia != 0.0 {
            for i in 0..n {
                let ai = rows[2 * n + i] * inertia;
                for j in i..n {
                    mm[i * n + j] += ai * rows[2 * n + j];
                }
            }
        }
    }
    // Mirror the upper triangle.
    for i in 1..n {
        for j in 0..i {
            mm[i * n + j] = mm[j * n + i];
        }
    }
}
