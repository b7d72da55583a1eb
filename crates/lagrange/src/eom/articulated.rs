//! Forward dynamics of a kinematic tree by the articulated-body algorithm (Featherstone,
//! *Rigid Body Dynamics Algorithms* (RBDA), §7.3, Table 7.1), in planar spatial algebra:
//! three `O(n)` passes instead of assembling and factoring `M`.
//!
//! Vectors of body `i` are expressed in a frame at its centre of mass with the world's axes
//! (RBDA's algorithm holds in any frames; these make every transform a translation and every
//! body inertia `diag(I_i, m_i, m_i)`). The motion subspace `s_i` of a joint is then a function
//! of `q`, its time derivative is still `v_i × s_i` (the axis is fixed in the child, or in the
//! parent and `(v_i − v_λ(i)) × s_i = 0`). Gravity enters as an acceleration of the ground,
//! `a_0 = −a_g = (0, 0, g)` (as in RBDA Table 7.1).
//!
//! The algorithm works in *relative* joint coordinates `r`; an absolute revolute coordinate
//! ([`AngleReference::World`](crate::tree::AngleReference)) is `q_i = r_i + φ_λ(i)`, the parent's
//! orientation — a constant linear change of coordinates `q = T⁻¹ r`, handled inside the
//! passes: `ṙ_i = q̇_i − ω_λ(i)`, `q̈_i = r̈_i + ω̇_λ(i)`, and the joint forces `τ = T⁻ᵀ Q` (pass 2).
//! A clockwise joint ([`Sense`](crate::tree::Sense)) counts its angle the other way: its
//! counter-clockwise angle is `σ_i q_i` with `σ_i = −1`, so `ṙ_i`, `τ_i` and `q̈_i` take the
//! factor `σ_i` as well (`T` gains `σ` on its diagonal; `σ_i = 1` multiplies exactly).

use super::{all_finite, kinematics, non_finite};
use crate::error::{Stage, bad_pivot};
use crate::linalg::PIVOT_RTOL;
use crate::tree::Link;
use crate::tree::spatial::{Force, Inertia, Motion, RigidInertia, Translation};
use crate::{Coordinate, Error, Mechanism, Model, Scalar, Tree, Workspace};

/// The articulated-body algorithm's scratch for one body (RBDA's symbols), filled by
/// [`solve`]; a [`Workspace`] holds one per body (`B`), none unless the model uses the tree path.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ArticulatedBody<S> {
    /// World orientation `φ_i` (orientation loop).
    angle: S,
    /// `sin φ_i` (orientation loop).
    sin: S,
    /// `cos φ_i` (orientation loop).
    cos: S,
    /// `ⁱX_λ(i)`: the offset of this body's centre of mass from its parent's (pass 1).
    child_from_parent: Translation<S>,
    /// Motion subspace `s_i` (pass 1).
    subspace: Motion<S>,
    /// Spatial velocity `v_i` (pass 1).
    velocity: Motion<S>,
    /// Velocity-product acceleration `c_i = v_i × s_i ṙ_i` (pass 1).
    bias_acceleration: Motion<S>,
    /// The body's own terms (pass 1) plus what its children pass up (pass 2).
    subtree: Subtree<S>,
    /// `U_i = I^A_i s_i` (pass 2).
    u_force: Force<S>,
    /// `1 / D_i`, `D_i = s_iᵀ U_i` (pass 2).
    inverse_d: S,
    /// `u_i = τ_i − s_iᵀ p^A_i` (pass 2).
    u: S,
    /// `X_iᵀ U_i / D_i`: `r̈_i = β_i − (X_iᵀ U_i / D_i)ᵀ a_λ(i)` (pass 2).
    acceleration_gain: Force<S>,
    /// `β_i = (u_i − U_iᵀ c_i) / D_i` (pass 2).
    acceleration_offset: S,
    /// Spatial acceleration `a_i` (pass 3).
    acceleration: Motion<S>,
}

/// What pass 2 gathers for a body from itself and the subtree below it.
#[derive(Clone, Copy, Debug)]
struct Subtree<S> {
    /// Articulated-body inertia `I^A_i`.
    articulated_inertia: Inertia<S>,
    /// Composite (rigid subtree) inertia `I^C_i`, the scale of the pivot test.
    composite_inertia: RigidInertia<S>,
    /// Articulated bias force `p^A_i`.
    bias_force: Force<S>,
    /// Joint forces `Q_k − ∂V/∂q_k` of the absolute revolute joints strictly below the body.
    absolute_force_below: S,
}

impl<S: Scalar> Subtree<S> {
    fn add_assign(&mut self, other: &Subtree<S>) {
        self.articulated_inertia.add_assign(&other.articulated_inertia);
        self.composite_inertia.add_assign(&other.composite_inertia);
        self.bias_force = self.bias_force.add(other.bias_force);
        self.absolute_force_below += other.absolute_force_below;
    }
}

impl<S: Scalar> ArticulatedBody<S> {
    pub(crate) fn zero() -> Self {
        let z = S::zero();
        Self {
            angle: z,
            sin: z,
            cos: S::one(),
            child_from_parent: Translation { x: z, y: z },
            subspace: Motion::zero(),
            velocity: Motion::zero(),
            bias_acceleration: Motion::zero(),
            subtree: Subtree {
                articulated_inertia: Inertia::zero(),
                composite_inertia: RigidInertia::body(0.0, 0.0),
                bias_force: Force::zero(),
                absolute_force_below: z,
            },
            u_force: Force::zero(),
            inverse_d: z,
            u: z,
            acceleration_gain: Force::zero(),
            acceleration_offset: z,
            acceleration: Motion::zero(),
        }
    }
}

/// `ws.qddot` by the articulated-body algorithm on `tree` (which [`Model::new`] checked against
/// the mechanism). The potential gradient, when the model has a potential, still takes `n`
/// dual passes of the poses ([`kinematics::jacobian_pass`]), and so do applied forces (their
/// pose Jacobian), `O(n B)`: cheaper than the generic path's `O(n³)` solve.
pub(crate) fn solve<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    tree: &Tree,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<(), Error> {
    // Joint-space forces Q − ∂V/∂q (+ applied forces) in the user's coordinates, into ws.rhs,
    // as the bias path adds them. Applied forces need the pose Jacobian: `n` dual passes, as
    // the potential gradient.
    let forces = model.has_potential || model.has_force || model.has_applied;
    if forces {
        ws.rhs.fill(S::zero());
        if model.has_potential || model.has_applied {
            kinematics::jacobian_pass(model, ws, t, q, true);
        }
        super::bias::add_joint_forces(model, ws, false, t, q, qdot);
    }
    let links = tree.links();
    let bodies = &mut ws.articulated[..links.len()];
    orientations(links, bodies, q);
    velocities(links, bodies, q, qdot);
    let rhs = if forces { Some(&ws.rhs[..]) } else { None };
    inertias(links, bodies, rhs, model.coordinates(), t, q)?;
    accelerations(links, bodies, model.gravity, &mut ws.qddot);
    if !all_finite(&ws.qddot) {
        return Err(non_finite(super::force_stage(model, ws).unwrap_or(Stage::Accelerations), t, q));
    }
    Ok(())
}

/// Orientations `φ_i` and their sines and cosines first: a loop without other state, so that
/// the trigonometric calls do not interrupt the recursion of the passes.
// The four passes are inlined into `solve` (`#[inline(always)]`), as one function's loops
// they were: the hot path of every tree.
#[inline(always)]
fn orientations<S: Scalar>(links: &[Link], bodies: &mut [ArticulatedBody<S>], q: &[S]) {
    for (i, link) in links.iter().enumerate() {
        let (parent_angle, parent_sin, parent_cos) = match link.parent {
            None => (S::zero(), S::zero(), S::one()),
            Some(p) => (bodies[p].angle, bodies[p].sin, bodies[p].cos),
        };
        let body = &mut bodies[i];
        if !link.revolute {
            (body.angle, body.sin, body.cos) = (parent_angle, parent_sin, parent_cos);
            continue;
        }
        let turn = q[i] * link.sense; // σ_i q_i: the joint's counter-clockwise angle
        body.angle = if link.absolute { turn } else { parent_angle + turn };
        (body.sin, body.cos) = body.angle.sin_cos();
    }
}

/// Pass 1, root to leaves (RBDA Table 7.1, first loop): relative rate ṙ_i (q̇_i − ω_λ(i) for
/// an absolute angle), offset r_i = R(φ_λ) parent_anchor − R(φ_i) child_anchor
/// (+ R(φ_λ) q_i axis), subspace s_i, v_i = X_i v_λ(i) + s_i ṙ_i, c_i = v_i × s_i ṙ_i,
/// I^A_i = I_i, p^A_i = v_i ×* I_i v_i = (0, −m ω v_y, m ω v_x).
#[inline(always)]
fn velocities<S: Scalar>(links: &[Link], bodies: &mut [ArticulatedBody<S>], q: &[S], qdot: &[S]) {
    let mut previous = Motion::zero();
    for (i, link) in links.iter().enumerate() {
        let (parent_sin, parent_cos, parent_velocity) = match link.parent {
            None => (S::zero(), S::one(), Motion::zero()),
            Some(p) if p + 1 == i => (bodies[p].sin, bodies[p].cos, previous),
            Some(p) => (bodies[p].sin, bodies[p].cos, bodies[p].velocity),
        };
        let body = &mut bodies[i];
        let turn_rate = qdot[i] * link.sense;
        let rate = if link.absolute { turn_rate - parent_velocity.angular } else { turn_rate };
        let [px, py] = link.parent_anchor;
        let (ax, ay) = if link.revolute {
            (S::from(px), S::from(py))
        } else {
            (q[i] * link.axis[0] + px, q[i] * link.axis[1] + py)
        };
        // Joint point from the parent's centre, child's centre from the joint (world axes).
        let (ax, ay) = (parent_cos * ax - parent_sin * ay, parent_sin * ax + parent_cos * ay);
        let [cx, cy] = link.child_anchor;
        let (bx, by) = (body.cos * cx - body.sin * cy, body.sin * cx + body.cos * cy);
        body.child_from_parent = Translation { x: ax - bx, y: ay - by };
        // Revolute: rotation about the joint at b from the centre; prismatic: slide along the axis.
        body.subspace = if link.revolute {
            Motion { angular: S::one(), x: by, y: -bx }
        } else {
            let [ux, uy] = link.axis;
            Motion { angular: S::zero(), x: body.cos * ux - body.sin * uy, y: body.sin * ux + body.cos * uy }
        };
        let joint_velocity = body.subspace.scale(rate);
        body.velocity = body.child_from_parent.motion(parent_velocity).add(joint_velocity);
        previous = body.velocity;
        body.bias_acceleration = body.velocity.cross_motion(joint_velocity);
        let momentum = body.velocity.angular * link.mass;
        body.subtree = Subtree {
            articulated_inertia: Inertia::body(link.mass, link.inertia),
            composite_inertia: RigidInertia::body(link.mass, link.inertia),
            bias_force: Force { torque: S::zero(), x: -(momentum * body.velocity.y), y: momentum * body.velocity.x },
            absolute_force_below: S::zero(),
        };
    }
}

/// Pass 2, leaves to root (second loop): U_i = I^A_i s_i, D_i = s_iᵀ U_i,
/// u_i = τ_i − s_iᵀ p^A_i; the parent receives I^a = I^A_i − U_i U_iᵀ / D_i and
/// p^a = p^A_i + I^a c_i + U_i u_i / D_i through X_iᵀ, transported as
/// X_iᵀ I^A_i X_i − Ũ_i Ũ_iᵀ / D_i and X_iᵀ (p^A_i + I^A_i c_i) + Ũ_i (u_i − U_iᵀ c_i) / D_i with
/// Ũ_i = X_iᵀ U_i, so that the transports do not wait for the division. The relative joint
/// forces are τ = T⁻ᵀ Q: for a revolute joint, its own Q_i plus those of every absolute
/// revolute joint below it (turning r_i turns those bodies too, though their absolute
/// coordinates stay). What a body passes to its parent stays in registers when the parent
/// is next, as in chains (reading it back from memory right after writing it stalls).
///
/// `rhs`: the joint-space forces, `None` without any.
#[inline(always)]
fn inertias<S: Scalar>(
    links: &[Link],
    bodies: &mut [ArticulatedBody<S>],
    rhs: Option<&[S]>,
    names: &[Coordinate],
    t: S,
    q: &[S],
) -> Result<(), Error> {
    let forces = rhs.is_some();
    let rhs = rhs.unwrap_or(&[]);
    let mut from_next: Option<Subtree<S>> = None;
    for i in (0..links.len()).rev() {
        let link = &links[i];
        let (head, tail) = bodies.split_at_mut(i);
        let body = &mut tail[0];
        let (s, c, x) = (body.subspace, body.bias_acceleration, body.child_from_parent);
        let mut subtree = body.subtree;
        if let Some(child) = from_next.take() {
            subtree.add_assign(&child);
        }
        let Subtree { articulated_inertia, composite_inertia, bias_force, absolute_force_below } = subtree;
        let mut tau = if forces { rhs[i] * link.sense } else { S::zero() };
        if link.revolute && forces {
            tau += absolute_force_below;
        }
        body.u_force = articulated_inertia.apply(s);
        let d = body.u_force.dot(s);
        body.inverse_d = S::one() / d;
        body.u = tau - bias_force.dot(s);
        // Pivot test: D_i relative to the rigid subtree's inertia about the joint, s_iᵀ I^C_i s_i
        // (the diagonal entry of M in relative coordinates), as in the LDLᵀ factorization.
        let diagonal = composite_inertia.quadratic(s);
        let (d, diagonal) = (d.re(), diagonal.re());
        if !(d.is_finite() && diagonal.is_finite()) {
            return Err(non_finite(Stage::Kinematics, t, q));
        }
        if !(diagonal > 0.0 && d > PIVOT_RTOL * diagonal) {
            return Err(bad_pivot(t, q, &names[i].name, d, diagonal));
        }
        // For pass 3: r̈_i = (u_i − U_iᵀ (X_i a_λ + c_i)) / D_i = β_i − (X_iᵀ U_i / D_i)ᵀ a_λ.
        let transported = x.force_to_parent(body.u_force);
        body.acceleration_gain = transported.scale(body.inverse_d);
        body.acceleration_offset = (body.u - body.u_force.dot(c)) * body.inverse_d;
        let Some(p) = link.parent else { continue };
        let passed = Subtree {
            articulated_inertia: x.inertia_to_parent(&articulated_inertia).minus_outer(transported, body.inverse_d),
            composite_inertia: x.rigid_inertia_to_parent(&composite_inertia),
            bias_force: x
                .force_to_parent(bias_force.add(articulated_inertia.apply(c)))
                .add(transported.scale(body.acceleration_offset)),
            absolute_force_below: absolute_force_below
                + if link.absolute && forces { rhs[i] * link.sense } else { S::zero() },
        };
        if p + 1 == i {
            from_next = Some(passed);
        } else {
            head[p].subtree.add_assign(&passed);
        }
    }
    Ok(())
}

/// Pass 3, root to leaves (third loop): r̈_i = (u_i − U_iᵀ a'_i) / D_i with
/// a'_i = X_i a_λ(i) + c_i, i.e. β_i − (X_iᵀ U_i / D_i)ᵀ a_λ(i); a_i = a'_i + s_i r̈_i; back to
/// the user's coordinates, q̈_i = r̈_i + ω̇_λ(i) for an absolute angle. The ground
/// accelerates upwards at g (gravity).
/// (The previous body's result is kept in registers: in chains it is the parent, and reading
/// it back from memory right after writing it stalls.)
#[inline(always)]
fn accelerations<S: Scalar>(links: &[Link], bodies: &mut [ArticulatedBody<S>], gravity: f64, qddot: &mut [S]) {
    let ground = Motion { angular: S::zero(), x: S::zero(), y: S::from(gravity) };
    let mut previous = ground;
    for (i, link) in links.iter().enumerate() {
        let parent_acceleration = match link.parent {
            None => ground,
            Some(p) if p + 1 == i => previous,
            Some(p) => bodies[p].acceleration,
        };
        let body = &mut bodies[i];
        let relative = body.acceleration_offset - body.acceleration_gain.dot(parent_acceleration);
        previous = body
            .child_from_parent
            .motion(parent_acceleration)
            .add(body.bias_acceleration)
            .add(body.subspace.scale(relative));
        body.acceleration = previous;
        qddot[i] = (if link.absolute { relative + parent_acceleration.angular } else { relative }) * link.sense;
    }
}

#[cfg(test)]
mod tests;
