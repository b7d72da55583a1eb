//! Mass matrix `M = Σ_b J_bᵀ D_b J_b`, `D_b = diag(m_b, m_b, I_b)`.

use crate::linalg::{self, size::Size};
use crate::{Mechanism, Model, Scalar, Workspace};

/// Assemble `ws.mass_matrix` from `ws.jacobian` (upper triangle, mirrored).
pub(crate) fn assemble<M: Mechanism, S: Scalar, N: Size>(model: &Model<M>, ws: &mut Workspace<S>, size: N) {
    linalg::mass_matrix_sized(size, &model.mass, &model.inertia, &ws.jacobian, &mut ws.mass_matrix);
}
