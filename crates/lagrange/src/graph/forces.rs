//! The force elements of a joint graph as functions of the body poses and velocities, for the
//! reduced model (potential and applied loads) and for the maximal builds (body wrenches).

use super::mechanism::{Element, GraphMechanism, point as world};
use crate::mechanism::Loads;
use crate::{Pose, Scalar};
use num_dual::Dual64;

/// Velocity of the material point at world position `x` of a body at `pose` moving with
/// `twist = (ẋ, ẏ, φ̇)` (`None`: the ground, at rest).
fn point_velocity<S: Scalar>(pose: Option<&Pose<S>>, twist: Option<[S; 3]>, x: [S; 2]) -> [S; 2] {
    match (pose, twist) {
        (Some(p), Some(v)) => [v[0] - v[2] * (x[1] - p.y), v[1] + v[2] * (x[0] - p.x)],
        _ => [S::zero(), S::zero()],
    }
}

/// `v` in the frame of a body at `pose` (the ground's frame is the world's).
fn to_body<S: Scalar>(pose: Option<&Pose<S>>, x: [S; 2]) -> [S; 2] {
    match pose {
        None => x,
        Some(p) => {
            let (s, c) = p.angle.sin_cos();
            let (dx, dy) = (x[0] - p.x, x[1] - p.y);
            [c * dx + s * dy, -s * dx + c * dy]
        }
    }
}

impl GraphMechanism {
    /// The springs of natural length `l₀ > 0` whose ends meet: `(index among the force
    /// elements, length)` of each, where the direction of the spring's force is undefined.
    pub(crate) fn spring_lengths(&self, poses: &[Pose<f64>]) -> impl Iterator<Item = (usize, f64)> {
        let pose = move |end: Option<usize>| end.map(|b| &poses[b]);
        self.elements().iter().enumerate().filter_map(move |(i, element)| match *element {
            Element::Spring { a, b, rest, .. } if rest > 0.0 => {
                let (xa, xb) = (world(pose(a.0), a.1), world(pose(b.0), b.1));
                Some((i, (xb[0] - xa[0]).hypot(xb[1] - xa[1])))
            }
            _ => None,
        })
    }

    /// The springs' potential `V(t, poses)` (joint springs through their joints' values).
    pub(crate) fn potential_at<S: Scalar>(&self, poses: &[Pose<S>]) -> S {
        let pose = |end: Option<usize>| end.map(|b| &poses[b]);
        let mut value = S::zero();
        for element in self.elements() {
            match *element {
                Element::Spring { a, b, stiffness, rest } => {
                    let (xa, xb) = (world(pose(a.0), a.1), world(pose(b.0), b.1));
                    let (dx, dy) = (xb[0] - xa[0], xb[1] - xa[1]);
                    let squared = dx * dx + dy * dy;
                    if rest == 0.0 {
                        // ½ k L²: smooth where the ends meet (the length's derivative is not).
                        value += squared * (0.5 * stiffness);
                    } else {
                        let stretch = squared.sqrt() - rest;
                        value += stretch * stretch * (0.5 * stiffness);
                    }
                }
                Element::JointSpring { joint, stiffness, rest } => {
                    let resolved = &self.joints()[joint];
                    let q = self.joint_value(joint, pose(resolved.parent), pose(resolved.child)) - rest;
                    value += q * q * (0.5 * stiffness);
                }
                _ => {}
            }
        }
        value
    }

    /// Add the dampers', torques' and forces' loads at time `t` for bodies at `poses` moving
    /// with `twist(b)`.
    pub(crate) fn loads_at<S: Scalar>(
        &self,
        t: S,
        poses: &[Pose<S>],
        twist: &dyn Fn(usize) -> [S; 3],
        loads: &mut Loads<'_, S>,
    ) {
        let pose = |end: Option<usize>| end.map(|b| &poses[b]);
        let velocity = |end: Option<usize>| end.map(twist);
        for element in self.elements() {
            match *element {
                Element::Damper { a, b, coefficient } => {
                    let (pa, pb) = (pose(a.0), pose(b.0));
                    let (xa, xb) = (world(pa, a.1), world(pb, b.1));
                    let (va, vb) = (point_velocity(pa, velocity(a.0), xa), point_velocity(pb, velocity(b.0), xb));
                    let (dx, dy) = (xb[0] - xa[0], xb[1] - xa[1]);
                    let length = (dx * dx + dy * dy).sqrt();
                    if length.re() == 0.0 {
                        continue;
                    }
                    let e = [dx / length, dy / length];
                    let rate = (vb[0] - va[0]) * e[0] + (vb[1] - va[1]) * e[1];
                    let f = [e[0] * rate * -coefficient, e[1] * rate * -coefficient];
                    if let Some(body) = b.0 {
                        loads.force(body, [S::from(b.1[0]), S::from(b.1[1])], f);
                    }
                    if let Some(body) = a.0 {
                        loads.force(body, [S::from(a.1[0]), S::from(a.1[1])], [-f[0], -f[1]]);
                    }
                }
                Element::JointDamper { joint, coefficient } => {
                    self.joint_damper(joint, coefficient, poses, twist, loads);
                }
                Element::Torque { body, torque } => loads.torque(body, torque.at(t)),
                Element::Force { body, at, force } => {
                    loads.force(body, [S::from(at[0]), S::from(at[1])], [force[0].at(t), force[1].at(t)]);
                }
                Element::Spring { .. } | Element::JointSpring { .. } => {}
            }
        }
    }

    /// A damper on joint `j`'s value `v`: the generalized force `−c v̇` along `v`, as a torque
    /// pair (revolute) or a force pair at the child's anchor along the axis (prismatic).
    fn joint_damper<S: Scalar>(
        &self,
        j: usize,
        coefficient: f64,
        poses: &[Pose<S>],
        twist: &dyn Fn(usize) -> [S; 3],
        loads: &mut Loads<'_, S>,
    ) {
        let resolved = &self.joints()[j];
        let spec = &self.graph().joints[j];
        let (parent, child) = (resolved.parent, resolved.child);
        // The value's rate along the bodies' motion: a dual pass over the poses.
        let dual = |end: Option<usize>| {
            end.map(|b| {
                let (p, v) = (poses[b], twist(b));
                Pose::new(
                    num_dual::Dual::new(p.x, v[0]),
                    num_dual::Dual::new(p.y, v[1]),
                    num_dual::Dual::new(p.angle, v[2]),
                )
            })
        };
        let (dp, dc) = (dual(parent), dual(child));
        let rate = self.joint_value(j, dp.as_ref(), dc.as_ref()).eps;
        let generalized = rate * -coefficient;
        match spec.kind {
            super::JointType::Revolute => {
                let sign = spec.sense.sign();
                if let Some(c) = child {
                    loads.torque(c, generalized * sign);
                }
                if spec.angle == crate::tree::AngleReference::Parent
                    && let Some(p) = parent
                {
                    loads.torque(p, -generalized * sign);
                }
            }
            super::JointType::Prismatic { axis } => {
                let pose = |end: Option<usize>| end.map(|b| &poses[b]);
                let u = {
                    let angle = pose(parent).map_or(S::zero(), |p| p.angle);
                    let (s, c) = angle.sin_cos();
                    [c * axis[0] - s * axis[1], s * axis[0] + c * axis[1]]
                };
                let f = [u[0] * generalized, u[1] * generalized];
                let x = world(pose(child), spec.child_anchor);
                if let Some(c) = child {
                    loads.force(c, [S::from(spec.child_anchor[0]), S::from(spec.child_anchor[1])], f);
                }
                if let Some(p) = parent {
                    loads.force(p, to_body(pose(parent), x), [-f[0], -f[1]]);
                }
            }
            super::JointType::Fixed { .. } => {}
        }
    }

    /// The springs' potential energy for bodies at `poses` (J).
    pub fn force_potential(&self, poses: &[Pose<f64>]) -> f64 {
        self.potential_at(poses)
    }

    /// The gradient of the springs' potential in every body's pose, `∂V/∂(x_b, y_b, φ_b)` (3B,
    /// written into `gradient`), one dual pass per pose component; zero without springs.
    pub fn potential_gradient(&self, poses: &[Pose<f64>], gradient: &mut [f64]) {
        gradient.fill(0.0);
        if !self.has_potential() {
            return;
        }
        let mut dual: Vec<Pose<Dual64>> =
            poses.iter().map(|p| Pose::new(Dual64::from(p.x), Dual64::from(p.y), Dual64::from(p.angle))).collect();
        for b in 0..poses.len() {
            for c in 0..3 {
                set_eps(&mut dual[b], c, 1.0);
                gradient[3 * b + c] = self.potential_at(&dual).eps;
                set_eps(&mut dual[b], c, 0.0);
            }
        }
    }

    /// The force elements' wrench `(F_x, F_y, τ)` on every body (3B, added to `wrench`) at time
    /// `t`, for bodies at `poses` moving with `velocities` (`(ẋ, ẏ, φ̇)` of each centre of
    /// mass): the springs' `−∂V/∂(x_b, y_b, φ_b)` ([`potential_gradient`](Self::potential_gradient))
    /// and the dampers', torques' and forces' loads — what an engine that integrates bodies
    /// applies.
    pub fn body_wrenches(&self, t: f64, poses: &[Pose<f64>], velocities: &[[f64; 3]], wrench: &mut [f64]) {
        if self.has_potential() {
            let mut gradient = vec![0.0; wrench.len()];
            self.potential_gradient(poses, &mut gradient);
            wrench.iter_mut().zip(&gradient).for_each(|(w, g)| *w -= g);
        }
        if self.has_non_conservative_forces() {
            let twist = |b: usize| velocities[b];
            let mut loads = Loads::new(poses, wrench);
            self.loads_at(t, poses, &twist, &mut loads);
        }
    }
}

fn set_eps(pose: &mut Pose<Dual64>, component: usize, eps: f64) {
    match component {
        0 => pose.x.eps = eps,
        1 => pose.y.eps = eps,
        _ => pose.angle.eps = eps,
    }
}
