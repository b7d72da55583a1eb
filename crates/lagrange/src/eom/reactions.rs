//! Constraint (reaction) forces on the bodies.

use super::{accelerations, check_state};
use crate::{Error, Mechanism, Model, Scalar, Workspace};
use num_dual::Dual;

/// The constraint force and torque `(F_x, F_y, τ)` on every body (3B, body-major), borrowed
/// from the workspace: `R_b = D_b p̈_b − F_b^gravity − w_b + ∂V/∂p_b`, with `p̈_b = J_b q̈ + γ_b`
/// and `w_b` the wrench of the forces applied to the body ([`Mechanism::applied_forces`]).
///
/// This is what the eliminated constraints (rods, ropes, inclines, rails) exert on the body:
/// the rope tension on an Atwood mass, the normal force on the block. Forces the mechanism
/// writes through the body poses in its potential, and its applied forces, are subtracted; the
/// parts of `V` written directly in `q` and the generalized forces `Q` act along coordinates,
/// cannot be attributed to one body, and therefore remain in the reaction.
///
/// With constraints among the coordinates ([`Mechanism::constraints`]), `q̈` is the constrained
/// one, so `R_b` also carries the constraints' forces: where a constraint is the coincidence of
/// a point of one body with a point of another (a four-bar's closing pin `B_coupler − B_rocker
/// = 0`), its multipliers are that pin's force, `−λ` on the first body and `+λ` on the second
/// ([`constraint_multipliers`](crate::constraint_multipliers), docs/method.md#constraints).
pub fn reaction_forces<'w, M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &'w mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<&'w [S], Error> {
    check_state(model.n, t, q, Some(qdot))?;
    let n = model.n;
    accelerations(model, ws, t, q, qdot)?;
    if model.constant.is_some() {
        ws.jacobian.copy_from_slice(&ws.constant_jacobian);
        ws.convective.fill(S::zero());
    } else if model.uses_tree {
        // The articulated-body algorithm does not form J and γ: the pose passes do.
        super::kinematics::jacobian_pass(model, ws, t, q, false);
        super::kinematics::velocity_pass(model, ws, t, q, qdot);
    }
    // ∂V/∂p_b: one dual pass of the potential per pose component, q held fixed.
    ws.potential_pose_gradient.fill(S::zero());
    if model.has_potential {
        super::kinematics::position_pass(model, ws, t, q);
        let t_dual = Dual::from_re(t);
        for r in 0..3 * model.description().bodies.len() {
            let (b, c) = (r / 3, r % 3);
            let set = |pose: &mut crate::Pose<Dual<S>>, eps: S| match c {
                0 => pose.x.eps = eps,
                1 => pose.y.eps = eps,
                _ => pose.angle.eps = eps,
            };
            set(&mut ws.poses_dual[b], S::one());
            if let Some(v) = model.mechanism.potential(t_dual, &ws.q_dual, &ws.poses_dual) {
                ws.potential_pose_gradient[r] = v.eps;
            }
            set(&mut ws.poses_dual[b], S::zero());
        }
    }
    // R_b = D_b (J_b q̈ + γ_b) − F_b + ∂V/∂p_b.
    for r in 0..3 * model.description().bodies.len() {
        let (b, c) = (r / 3, r % 3);
        let mut accel = ws.convective[r];
        for j in 0..n {
            accel += ws.jacobian[r * n + j] * ws.qddot[j];
        }
        let inertia = if c == 2 { model.inertia[b] } else { model.mass[b] };
        let gravity = if c == 1 { -model.mass[b] * model.gravity } else { 0.0 };
        let applied = if model.has_applied { ws.applied_wrench[r] } else { S::zero() };
        ws.reaction[r] = accel * inertia - gravity - applied + ws.potential_pose_gradient[r];
    }
    Ok(&ws.reaction)
}
