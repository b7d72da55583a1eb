//! Forces and torques applied at points of bodies, as generalized forces `Σ_b J_bᵀ w_b`.

use crate::mechanism::{Loads, project};
use crate::pose::Pose;
use crate::{Mechanism, Model, Scalar, Workspace};

/// Fill `ws.applied_wrench` and `ws.applied_force` and add the latter to `ws.rhs`. Reads the
/// body poses `ws.position` and the pose Jacobian `jacobian` (3B × n), which the caller filled.
pub(crate) fn add<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    constant_jacobian: bool,
    t: S,
    q: &[S],
    qdot: &[S],
) {
    let n = model.n;
    for (b, pose) in ws.applied_poses.iter_mut().enumerate() {
        *pose = Pose::new(ws.position[3 * b], ws.position[3 * b + 1], ws.position[3 * b + 2]);
    }
    ws.applied_wrench.fill(S::zero());
    let mut loads = Loads::new(&ws.applied_poses, &mut ws.applied_wrench);
    model.mechanism.applied_forces(t, q, qdot, &ws.applied_poses, &mut loads);
    let jacobian = if constant_jacobian { &ws.constant_jacobian } else { &ws.jacobian };
    project(jacobian, &ws.applied_wrench, n, &mut ws.applied_force);
    for (r, f) in ws.rhs.iter_mut().zip(&ws.applied_force) {
        *r += *f;
    }
}

#[cfg(test)]
mod tests;
