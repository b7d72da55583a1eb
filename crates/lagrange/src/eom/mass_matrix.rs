//! Mass matrix `M = Σ_b J_bᵀ D_b J_b`, `D_b = diag(m_b, m_b, I_b)`.

use crate::{Mechanism, Model, Scalar, Workspace};

/// Assemble `ws.mass_matrix` from `ws.jacobian` (upper triangle, mirrored).
pub(crate) fn assemble<M: Mechanism, S: Scalar>(model: &Model<M>, ws: &mut Workspace<S>) {
    let n = model.n;
    let mm = &mut ws.mass_matrix;
    mm.fill(S::zero());
    for ((block, &m), &inertia) in ws.jacobian.chunks_exact(3 * n).zip(&model.mass).zip(&model.inertia) {
        let (jx, rest) = block.split_at(n);
        let (jy, ja) = rest.split_at(n);
        for (i, row) in mm.chunks_exact_mut(n).enumerate() {
            // Translational part m (Jxᵀ Jx + Jyᵀ Jy), upper triangle.
            if m != 0.0 {
                let (xi, yi) = (jx[i] * m, jy[i] * m);
                for ((entry, &xj), &yj) in row[i..].iter_mut().zip(&jx[i..]).zip(&jy[i..]) {
                    *entry += xi * xj + yi * yj;
                }
            }
            // Rotational part I Jφᵀ Jφ.
            if inertia != 0.0 {
                let ai = ja[i] * inertia;
                for (entry, &aj) in row[i..].iter_mut().zip(&ja[i..]) {
                    *entry += ai * aj;
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
