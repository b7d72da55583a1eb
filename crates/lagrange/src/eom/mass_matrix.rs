//! Mass matrix `M = Σ_b J_bᵀ D_b J_b`, `D_b = diag(m_b, m_b, I_b)`.

use crate::{Mechanism, Model, Scalar, Workspace};

/// Assemble `ws.mass_matrix` from `ws.jacobian` (upper triangle, mirrored).
pub(crate) fn assemble<M: Mechanism, S: Scalar>(model: &Model<M>, ws: &mut Workspace<S>) {
    let n = model.n;
    ws.mass_matrix.fill(S::zero());
    for b in 0..model.bodies() {
        let (m, inertia) = (model.mass[b], model.inertia[b]);
        let jx = &ws.jacobian[3 * b * n..(3 * b + 1) * n];
        let jy = &ws.jacobian[(3 * b + 1) * n..(3 * b + 2) * n];
        let ja = &ws.jacobian[(3 * b + 2) * n..(3 * b + 3) * n];
        // Translational part m (Jxᵀ Jx + Jyᵀ Jy).
        if m != 0.0 {
            for i in 0..n {
                let (xi, yi) = (jx[i] * m, jy[i] * m);
                for j in i..n {
                    ws.mass_matrix[i * n + j] += xi * jx[j] + yi * jy[j];
                }
            }
        }
        // Rotational part I Jφᵀ Jφ.
        if inertia != 0.0 {
            for i in 0..n {
                let ai = ja[i] * inertia;
                for j in i..n {
                    ws.mass_matrix[i * n + j] += ai * ja[j];
                }
            }
        }
    }
    // Mirror the upper triangle.
    for i in 0..n {
        for j in 0..i {
            ws.mass_matrix[i * n + j] = ws.mass_matrix[j * n + i];
        }
    }
}
