//! Mass matrix `M = Σ_b J_bᵀ D_b J_b`, `D_b = diag(m_b, m_b, I_b)`.

use crate::linalg::{self, size::Size};
use crate::{Mechanism, Model, Scalar, Workspace};
use std::any::Any;

/// Assemble `ws.mass_matrix` from `ws.jacobian` (upper triangle, mirrored). In `f64` with more
/// than four coordinates, only each body's nonzero columns of `J` enter (exact zeros, so the
/// same `M`); in dual numbers a zero real part may carry a derivative, so every column does.
pub(crate) fn assemble<M: Mechanism, S: Scalar, N: Size>(model: &Model<M>, ws: &mut Workspace<S>, size: N) {
    let n = size.get();
    if n > 4
        && let (Some(jacobian), Some(out)) = (
            (&ws.jacobian as &dyn Any).downcast_ref::<Vec<f64>>(),
            (&mut ws.mass_matrix as &mut dyn Any).downcast_mut::<Vec<f64>>(),
        )
    {
        linalg::mass_matrix_sparse(n, &model.mass, &model.inertia, jacobian, out, &mut ws.columns);
        return;
    }
    linalg::mass_matrix_sized(size, &model.mass, &model.inertia, &ws.jacobian, &mut ws.mass_matrix);
}
