//! The reduced model of a joint graph: a spanning tree gives the coordinates and the poses
//! (forward kinematics), loop-closing joints give the constraints, force elements give the
//! potential and the applied loads.

use super::description::{ForceElement, GROUND, JointGraph, JointType, Profile, Shape};
use super::invalid;
use super::spanning::{self, Ends, Orientation};
use crate::mechanism::Loads;
use crate::tree::{AngleReference, Joint, Parent, Tree};
use crate::{Body, Bounds, Coordinate, Description, Error, Mechanism, Pose, Scalar};
use num_dual::Dual;

/// How far a prismatic axis may be from unit length (relative).
const UNIT_AXIS_TOLERANCE: f64 = 1e-12;

/// How far a shaped body's inertia may be from its shape's (relative): round-off of the
/// shape's formula.
const SHAPE_TOLERANCE: f64 = 1e-12;

/// What sets a tree joint's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum JointValue {
    /// Generalized coordinate `q_i`.
    Coordinate(usize),
    /// A prescribed function of time.
    Driven(Profile),
    /// `ratio · value(source) + offset`.
    Coupled {
        /// The driving joint (a tree joint).
        source: usize,
        /// `ratio`.
        ratio: f64,
        /// `offset`.
        offset: f64,
    },
    /// A fixed joint: no value.
    Fixed,
}

/// A joint of the graph as the reduced model resolved it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ResolvedJoint {
    /// The parent body's index (`None`: the ground).
    pub parent: Option<usize>,
    /// The child body's index (`None`: the ground).
    pub child: Option<usize>,
    /// Whether it belongs to the spanning tree (otherwise it closes a loop).
    pub tree: bool,
    /// A tree joint that hangs its *parent* from its child (the child is nearer the ground).
    pub reversed: bool,
    /// What sets a tree joint's value; for a loop-closing joint, what its constraint rows
    /// demand beyond the joint itself (a drive or a coupling; `Fixed` when nothing more).
    pub value: JointValue,
    /// The first of its constraint rows, for a loop-closing joint.
    pub first_row: usize,
}

/// A force element with bodies resolved to indices (`None`: the ground).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Element {
    Spring { a: (Option<usize>, [f64; 2]), b: (Option<usize>, [f64; 2]), stiffness: f64, rest: f64 },
    Damper { a: (Option<usize>, [f64; 2]), b: (Option<usize>, [f64; 2]), coefficient: f64 },
    JointSpring { joint: usize, stiffness: f64, rest: f64 },
    JointDamper { joint: usize, coefficient: f64 },
    Torque { body: usize, torque: Profile },
    Force { body: usize, at: [f64; 2], force: [Profile; 2] },
}

/// The reduced model of a [`JointGraph`]: a [`Mechanism`] whose coordinates are those of the
/// spanning tree's revolute and prismatic joints (neither driven nor coupled), in the order the
/// joints are listed; whose poses come from forward kinematics along the tree; whose holonomic
/// constraints are the loop-closing joints' (2 rows for a revolute or prismatic joint, 3 for a
/// fixed one, one more for a drive or a coupling); whose potential holds the springs and whose
/// applied loads hold the dampers, torques and forces. When every body hangs from an earlier
/// body (or the ground) by a coordinate joint of its own, in the bodies' order, it also
/// declares its [`Tree`], so that [`Model::new`](crate::Model::new) runs the `O(n)`
/// articulated-body algorithm.
///
/// ```
/// use lagrange::graph::{GraphBody, GraphJoint, GraphMechanism, JointGraph};
/// use lagrange::{Model, accelerations};
///
/// // A pendulum: a rod of length 2 l hung at one end, its angle from the downward vertical.
/// let (m, l, g) = (1.5, 0.4, 9.81);
/// let graph = JointGraph::new("pendulum", g)
///     .with_body(GraphBody::rigid("rod", m, m * (2.0 * l) * (2.0 * l) / 12.0))
///     .with_joint(GraphJoint::revolute("θ", "ground", [0.0, 0.0], "rod", [0.0, l]));
/// let model = Model::new(GraphMechanism::new(graph)?)?;
/// assert!(model.uses_tree_path());
/// let mut ws = model.workspace();
/// let theta = 0.3_f64;
/// let qddot = accelerations(&model, &mut ws, 0.0, &[theta], &[0.0])?;
/// // (I + m l²) θ̈ = −m g l sinθ.
/// let expected = -m * g * l * theta.sin() / (m * (2.0 * l) * (2.0 * l) / 12.0 + m * l * l);
/// approx::assert_relative_eq!(qddot[0], expected, max_relative = 1e-13);
/// # Ok::<(), lagrange::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct GraphMechanism {
    graph: JointGraph,
    /// Coordinates, bodies, gravity and the loop-closing joints' constraint rows.
    description: Description,
    /// The joint of each coordinate.
    coordinate_joints: Vec<usize>,
    joints: Vec<ResolvedJoint>,
    /// Forward kinematics: `(joint, body it places)`, every body once, parents first.
    order: Vec<(usize, usize)>,
    /// The tree joints from the ground to each body, in order.
    paths: Vec<Vec<usize>>,
    elements: Vec<Element>,
    tree: Option<Tree>,
    has_potential: bool,
    has_loads: bool,
}

/// The world position of `at` on a body at `pose` (the ground: `pose` is `None`).
pub(crate) fn point<S: Scalar>(pose: Option<&Pose<S>>, at: [f64; 2]) -> [S; 2] {
    match pose {
        None => [S::from(at[0]), S::from(at[1])],
        Some(p) => {
            let (s, c) = p.angle.sin_cos();
            [p.x + c * at[0] - s * at[1], p.y + s * at[0] + c * at[1]]
        }
    }
}

fn rotate<S: Scalar>(angle: S, v: [f64; 2]) -> [S; 2] {
    let (s, c) = angle.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

impl GraphMechanism {
    /// Resolve `graph`: check it, choose the spanning tree, number the coordinates and the
    /// constraint rows.
    ///
    /// # Errors
    /// [`Error::InvalidGraph`] naming the body, joint, coupling or force element that makes the
    /// graph not a mechanism: a repeated or reserved name, a joint or element referring to a
    /// missing body or joint, a non-finite or negative value, a prismatic axis that is not a
    /// unit vector, a body without a path to the ground, joints marked as tree joints that form
    /// a loop, a coupling whose source is not a tree joint or that couples in a cycle, an
    /// absolute angle that the tree would have to measure backwards, or no free coordinate.
    pub fn new(graph: JointGraph) -> Result<Self, Error> {
        if !graph.gravity.is_finite() {
            return Err(invalid("gravity", format!("g = {} is not finite", graph.gravity)));
        }
        if graph.bodies.is_empty() {
            return Err(invalid(&graph.name, "has no bodies".into()));
        }
        let bodies = check_bodies(&graph)?;
        let ends = check_joints(&graph)?;
        let coupled = check_couplings(&graph)?;
        let in_tree = spanning::spanning_tree(&graph, &ends)?;
        let Orientation { reversed, order, paths } = spanning::orient(graph.bodies.len(), &ends, &in_tree);
        let Values { mut joints, coordinates, coordinate_joints } =
            joint_values(&graph, &ends, &in_tree, &reversed, &coupled)?;
        if coordinates.is_empty() {
            return Err(invalid(
                &graph.name,
                "has no free coordinate: every tree joint is fixed, driven or coupled".into(),
            ));
        }
        let row_names = number_rows(&graph, &in_tree, &coupled, &mut joints);
        let elements = resolve_forces(&graph)?;
        let has_potential = elements.iter().any(|e| matches!(e, Element::Spring { .. } | Element::JointSpring { .. }));
        let has_loads = elements.iter().any(|e| {
            matches!(
                e,
                Element::Damper { .. } | Element::JointDamper { .. } | Element::Torque { .. } | Element::Force { .. }
            )
        });
        let description = Description {
            coordinates,
            bodies,
            gravity: graph.gravity,
            constraints: row_names,
            ..Description::default()
        };
        let mut mechanism = Self {
            description,
            coordinate_joints,
            joints,
            order,
            paths,
            elements,
            tree: None,
            has_potential,
            has_loads,
            graph,
        };
        mechanism.tree = mechanism.articulated_tree()?;
        Ok(mechanism)
    }

    /// The [`Tree`] of the articulated-body path, when every body `b` hangs from an earlier body
    /// (or the ground) by a coordinate joint whose coordinate is `q_b`, in any order that lists
    /// parents first.
    fn articulated_tree(&self) -> Result<Option<Tree>, Error> {
        if self.description.coordinates.len() != self.description.bodies.len() {
            return Ok(None);
        }
        // Each body's tree joint; the bodies must be listed parents first (any such order:
        // the forward kinematics' own order is breadth first, a chain listed as written is not).
        let mut joint_of = vec![usize::MAX; self.description.bodies.len()];
        for &(j, body) in &self.order {
            joint_of[body] = j;
        }
        let mut tree_joints = Vec::with_capacity(self.description.bodies.len());
        for (b, &j) in joint_of.iter().enumerate() {
            let joint = &self.joints[j];
            let spec = &self.graph.joints[j];
            let parent = match joint.parent {
                None => Parent::Ground,
                Some(p) if p < b => Parent::Body(p),
                Some(_) => return Ok(None),
            };
            if joint.reversed || joint.value != JointValue::Coordinate(b) {
                return Ok(None);
            }
            let tree_joint = match (spec.kind, spec.angle) {
                (JointType::Revolute, AngleReference::Parent) => {
                    Joint::revolute(spec.name.clone(), parent, spec.parent_anchor, spec.child_anchor)
                }
                (JointType::Revolute, AngleReference::World) => {
                    Joint::absolute_revolute(spec.name.clone(), parent, spec.parent_anchor, spec.child_anchor)
                }
                (JointType::Prismatic { axis }, _) => {
                    Joint::prismatic(spec.name.clone(), parent, spec.parent_anchor, axis, spec.child_anchor)
                }
                (JointType::Fixed { .. }, _) => return Ok(None),
            };
            let tree_joint = if spec.sense == crate::tree::Sense::Clockwise && spec.kind == JointType::Revolute {
                tree_joint.clockwise()
            } else {
                tree_joint
            };
            tree_joints.push(tree_joint);
        }
        Tree::new(tree_joints, self.description.bodies.clone(), self.graph.gravity).map(Some)
    }

    /// The description this model was resolved from.
    pub fn graph(&self) -> &JointGraph {
        &self.graph
    }

    /// Every joint as resolved, in the description's order.
    pub(crate) fn joints(&self) -> &[ResolvedJoint] {
        &self.joints
    }

    /// The bodies joint `j` connects, `(parent, child)`, as indices (`None`: the ground).
    pub fn joint_ends(&self, j: usize) -> (Option<usize>, Option<usize>) {
        (self.joints[j].parent, self.joints[j].child)
    }

    /// Whether joint `j` belongs to the spanning tree; otherwise it closes a loop, with
    /// constraint rows of its own.
    pub fn in_tree(&self, j: usize) -> bool {
        self.joints[j].tree
    }

    /// Whether tree joint `j` runs backwards: it hangs its parent from its child, the child
    /// being nearer the ground.
    pub fn is_reversed(&self, j: usize) -> bool {
        self.joints[j].reversed
    }

    /// The body tree joint `j` places: its child, or its parent when it runs backwards
    /// ([`is_reversed`](Self::is_reversed)); `None` for the ground.
    pub fn placed_body(&self, j: usize) -> Option<usize> {
        let joint = &self.joints[j];
        if joint.reversed { joint.parent } else { joint.child }
    }

    /// The prescribed motion of joint `j`, when a drive sets it.
    pub fn drive(&self, j: usize) -> Option<Profile> {
        match self.joints[j].value {
            JointValue::Driven(profile) => Some(profile),
            _ => None,
        }
    }

    /// The coupling of joint `j`, `(source joint, ratio)`: its value is `ratio` times the
    /// source's plus an offset (a gear, a pulley).
    pub fn coupling(&self, j: usize) -> Option<(usize, f64)> {
        match self.joints[j].value {
            JointValue::Coupled { source, ratio, .. } => Some((source, ratio)),
            _ => None,
        }
    }

    /// The joint of each coordinate.
    pub fn coordinate_joints(&self) -> &[usize] {
        &self.coordinate_joints
    }

    /// The index of body `name`.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.graph.bodies.iter().position(|b| b.name == name)
    }

    /// Whether a drive moves a joint with time (a constraint that depends on `t` explicitly);
    /// time-varying torques and forces do not count.
    pub fn is_rheonomic(&self) -> bool {
        self.joints.iter().any(|j| matches!(j.value, JointValue::Driven(p) if p.varies()))
    }

    /// Whether the force elements do work beyond their potential (dampers, torques, forces).
    pub fn has_non_conservative_forces(&self) -> bool {
        self.has_loads
    }

    /// The value of tree joint `j` at `(t, q)`.
    fn value<S: Scalar, Q: Fn(usize) -> S>(&self, j: usize, t: S, q: &Q) -> S {
        match self.joints[j].value {
            JointValue::Coordinate(i) => q(i),
            JointValue::Driven(profile) => profile.at(t),
            JointValue::Coupled { source, ratio, offset } => self.value(source, t, q) * ratio + offset,
            JointValue::Fixed => S::zero(),
        }
    }

    /// The pose of the body that tree joint `j` places, from the pose of the one it hangs from
    /// (`known`; the identity for the ground) and the joint's value `v`.
    fn place<S: Scalar>(&self, j: usize, known: Pose<S>, v: S) -> Pose<S> {
        let spec = &self.graph.joints[j];
        let sign = spec.sense.sign();
        let reversed = self.joints[j].reversed;
        // Relative turn child − parent and the slide (in the parent's frame).
        let (turn, slide) = match spec.kind {
            JointType::Revolute => (v * sign, None),
            JointType::Prismatic { axis } => (S::zero(), Some(axis)),
            JointType::Fixed { angle } => (S::from(angle), None),
        };
        let slid = |anchor: [f64; 2]| -> [S; 2] {
            match slide {
                Some(axis) => [v * axis[0] + anchor[0], v * axis[1] + anchor[1]],
                None => [S::from(anchor[0]), S::from(anchor[1])],
            }
        };
        let turned = |angle: S, p: [S; 2]| -> [S; 2] {
            let (s, c) = angle.sin_cos();
            [c * p[0] - s * p[1], s * p[0] + c * p[1]]
        };
        if !reversed {
            let angle = if spec.kind == JointType::Revolute && spec.angle == AngleReference::World {
                v * sign
            } else {
                known.angle + turn
            };
            let a = turned(known.angle, slid(spec.parent_anchor));
            let c = rotate(angle, spec.child_anchor);
            Pose::new(known.x + a[0] - c[0], known.y + a[1] - c[1], angle)
        } else {
            // `known` is the description's child; place its parent.
            let angle = known.angle - turn;
            let c = rotate(known.angle, spec.child_anchor);
            let a = turned(angle, slid(spec.parent_anchor));
            Pose::new(known.x + c[0] - a[0], known.y + c[1] - a[1], angle)
        }
    }

    /// The pose of body `b` at `(t, q)` along its path from the ground.
    fn pose_of<S: Scalar, Q: Fn(usize) -> S>(&self, b: usize, t: S, q: &Q) -> Pose<S> {
        let mut pose = Pose::new(S::zero(), S::zero(), S::zero());
        for &j in &self.paths[b] {
            pose = self.place(j, pose, self.value(j, t, q));
        }
        pose
    }

    /// Pose of an end of a joint or element (`None`: the ground).
    fn end_pose<S: Scalar, Q: Fn(usize) -> S>(&self, end: Option<usize>, t: S, q: &Q) -> Option<Pose<S>> {
        end.map(|b| self.pose_of(b, t, q))
    }

    /// Joint `j`'s value from the poses of its two bodies (`None`: the ground): the relative
    /// (or absolute) angle times the sense, or the slide along the axis.
    pub fn joint_value<S: Scalar>(&self, j: usize, parent: Option<&Pose<S>>, child: Option<&Pose<S>>) -> S {
        let spec = &self.graph.joints[j];
        let angle = |p: Option<&Pose<S>>| p.map_or(S::zero(), |p| p.angle);
        match spec.kind {
            JointType::Revolute => {
                let relative = match spec.angle {
                    AngleReference::Parent => angle(child) - angle(parent),
                    AngleReference::World => angle(child),
                };
                relative * spec.sense.sign()
            }
            JointType::Prismatic { axis } => {
                let (a, c) = (point(parent, spec.parent_anchor), point(child, spec.child_anchor));
                let u = rotate(angle(parent), axis);
                (c[0] - a[0]) * u[0] + (c[1] - a[1]) * u[1]
            }
            JointType::Fixed { .. } => S::zero(),
        }
    }

    /// The generalized coordinates of body poses `world_from_body` (every body's): each
    /// coordinate joint's value ([`joint_value`](Self::joint_value)). Angles come out on the
    /// branch of the poses' angles.
    pub fn coordinates_of<S: Scalar>(&self, world_from_body: &[Pose<S>], q: &mut [S]) {
        for (qi, &j) in q.iter_mut().zip(&self.coordinate_joints) {
            let joint = &self.joints[j];
            let pose = |end: Option<usize>| end.map(|b| &world_from_body[b]);
            *qi = self.joint_value(j, pose(joint.parent), pose(joint.child));
        }
    }

    /// Write joint `j`'s constraint rows (a loop-closing joint) at `(t, q)`.
    fn closing_rows<S: Scalar, Q: Fn(usize) -> S>(&self, j: usize, t: S, q: &Q, rows: &mut [S]) {
        let joint = &self.joints[j];
        let (parent, child) = (self.end_pose(joint.parent, t, q), self.end_pose(joint.child, t, q));
        let source = |k: usize| self.value(k, t, q);
        self.residuals(j, t, parent.as_ref(), child.as_ref(), &source, rows);
    }

    /// Joint `j`'s residuals between its bodies' poses (`None`: the ground): the joint itself
    /// (revolute: the parent's anchor less the child's, x and y; prismatic: the child anchor's offset from
    /// the slide line and the relative angle; fixed: the separation and the relative angle less
    /// its angle), then its drive (`value − q(t)`) or coupling (`value − ratio · source − offset`,
    /// the source's value from `source`).
    fn residuals<S: Scalar>(
        &self,
        j: usize,
        t: S,
        parent: Option<&Pose<S>>,
        child: Option<&Pose<S>>,
        source: &dyn Fn(usize) -> S,
        rows: &mut [S],
    ) {
        let spec = &self.graph.joints[j];
        let angle = |p: Option<&Pose<S>>| p.map_or(S::zero(), |p| p.angle);
        let (a, c) = (point(parent, spec.parent_anchor), point(child, spec.child_anchor));
        let used = match spec.kind {
            JointType::Revolute => {
                rows[0] = a[0] - c[0];
                rows[1] = a[1] - c[1];
                2
            }
            JointType::Prismatic { axis } => {
                let u = rotate(angle(parent), axis);
                rows[0] = (c[0] - a[0]) * u[1] - (c[1] - a[1]) * u[0];
                rows[1] = angle(child) - angle(parent);
                2
            }
            JointType::Fixed { angle: turn } => {
                rows[0] = a[0] - c[0];
                rows[1] = a[1] - c[1];
                rows[2] = angle(child) - angle(parent) - turn;
                3
            }
        };
        match self.joints[j].value {
            JointValue::Driven(profile) => rows[used] = self.joint_value(j, parent, child) - profile.at(t),
            JointValue::Coupled { source: k, ratio, offset } => {
                rows[used] = self.joint_value(j, parent, child) - source(k) * ratio - offset;
            }
            JointValue::Coordinate(_) | JointValue::Fixed => {}
        }
    }

    /// The number of residuals of joint `j` as a constraint between two free bodies (every
    /// joint, tree or loop-closing): 2 for a revolute or prismatic joint, 3 for a fixed one, one
    /// more for a drive or a coupling — what a Cartesian model of the graph needs.
    pub fn joint_rows(&self, j: usize) -> usize {
        let base = match self.graph.joints[j].kind {
            JointType::Fixed { .. } => 3,
            _ => 2,
        };
        base + usize::from(matches!(self.joints[j].value, JointValue::Driven(_) | JointValue::Coupled { .. }))
    }

    /// The names of joint `j`'s [`joint_rows`](Self::joint_rows) residuals.
    pub fn joint_row_names(&self, j: usize) -> Vec<String> {
        let spec = &self.graph.joints[j];
        let mut names: Vec<String> = match spec.kind {
            JointType::Revolute => vec!["x", "y"],
            JointType::Prismatic { .. } => vec!["off the axis", "angle"],
            JointType::Fixed { .. } => vec!["x", "y", "angle"],
        }
        .into_iter()
        .map(|w| format!("{} ({w})", spec.name))
        .collect();
        match self.joints[j].value {
            JointValue::Driven(_) => names.push(format!("{} (drive)", spec.name)),
            JointValue::Coupled { .. } => names.push(format!("{} (coupling)", spec.name)),
            _ => {}
        }
        names
    }

    /// Joint `j`'s [`joint_rows`](Self::joint_rows) residuals at time `t` for bodies at
    /// `pose(b)`, every joint as a constraint between free bodies (the Cartesian model's
    /// `Φ(z, t)`), into `rows`.
    pub fn joint_residuals<S: Scalar>(&self, j: usize, t: S, pose: &dyn Fn(usize) -> Pose<S>, rows: &mut [S]) {
        let joint = &self.joints[j];
        let (parent, child) = (joint.parent.map(pose), joint.child.map(pose));
        let source = |k: usize| {
            let s = &self.joints[k];
            let (p, c) = (s.parent.map(pose), s.child.map(pose));
            self.joint_value(k, p.as_ref(), c.as_ref())
        };
        self.residuals(j, t, parent.as_ref(), child.as_ref(), &source, rows);
    }

    /// The pose of body `b` at `(t, q)`, by forward kinematics along its path from the ground.
    pub fn body_pose<S: Scalar>(&self, b: usize, t: S, q: &[S]) -> Pose<S> {
        self.pose_of(b, t, &|i: usize| q[i])
    }

    /// Whether body `b`'s pose is a function of time alone: every joint on its path from the
    /// ground is fixed or driven.
    pub fn is_kinematic(&self, b: usize) -> bool {
        self.paths[b].iter().all(|&j| matches!(self.joints[j].value, JointValue::Driven(_) | JointValue::Fixed))
    }

    /// The mechanism's degrees of freedom at `(t, q)`: the number of coordinates less the rank
    /// of the loop constraints' Jacobian `G = ∂Φ/∂q` there (rows whose pivot falls below 1e-10
    /// of the row's size count as dependent, as in the constrained solve). 0 means that the
    /// loops fix every coordinate: a structure (a rigid loop, a truss) or a mechanism whose
    /// motion its drives prescribe — valid mechanisms, whose coordinates follow from the
    /// constraints alone.
    pub fn degrees_of_freedom(&self, t: f64, q: &[f64]) -> usize {
        let (n, m) = (self.description.coordinates.len(), self.description.constraints.len());
        if m == 0 {
            return n;
        }
        // G by one dual pass per coordinate.
        let mut g = vec![0.0; m * n];
        let mut phi = vec![num_dual::Dual64::from(0.0); m];
        for j in 0..n {
            let seeded = |i: usize| num_dual::Dual64::new(q[i], if i == j { 1.0 } else { 0.0 });
            for (k, joint) in self.joints.iter().enumerate().filter(|(_, joint)| !joint.tree) {
                self.closing_rows(k, num_dual::Dual64::from(t), &seeded, &mut phi[joint.first_row..]);
            }
            for i in 0..m {
                g[i * n + j] = phi[i].eps;
            }
        }
        // Rank by Gaussian elimination with partial pivoting over the rows, each pivot measured
        // against its row's size before elimination (a dependent row is reduced to round-off,
        // which measured against itself would pass).
        let sizes: Vec<f64> = (0..m).map(|r| (0..n).fold(0.0_f64, |a, c| a.max(g[r * n + c].abs()))).collect();
        let mut rank = 0;
        let mut rows: Vec<usize> = (0..m).collect();
        for col in 0..n {
            let pivot = rows[rank..]
                .iter()
                .copied()
                .filter(|&r| g[r * n + col].abs() > 1e-10 * sizes[r].max(f64::MIN_POSITIVE))
                .max_by(|&a, &b| g[a * n + col].abs().total_cmp(&g[b * n + col].abs()));
            let Some(p) = pivot else { continue };
            let at = rows.iter().position(|&r| r == p).unwrap_or(rank);
            rows.swap(rank, at);
            for &r in &rows[rank + 1..] {
                let factor = g[r * n + col] / g[p * n + col];
                for c in col..n {
                    g[r * n + c] -= factor * g[p * n + c];
                }
            }
            rank += 1;
            if rank == m {
                break;
            }
        }
        n - rank
    }

    /// The tree joints in forward-kinematics order, each with the body it places: parents
    /// before children.
    pub fn tree_order(&self) -> &[(usize, usize)] {
        &self.order
    }
}

impl GraphMechanism {
    pub(crate) fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Whether the force elements include springs (a potential beyond gravity).
    pub fn has_potential(&self) -> bool {
        self.has_potential
    }
}

impl Mechanism for GraphMechanism {
    fn description(&self) -> &Description {
        &self.description
    }

    /// Forward kinematics along the spanning tree, from the ground outwards.
    fn poses<S: Scalar>(&self, t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let coordinate = |i: usize| q[i];
        for &(j, body) in &self.order {
            let joint = &self.joints[j];
            let from = if joint.reversed { joint.child } else { joint.parent };
            let known = from.map_or(Pose::new(S::zero(), S::zero(), S::zero()), |b| world_from_body[b]);
            world_from_body[body] = self.place(j, known, self.value(j, t, &coordinate));
        }
    }

    /// A spring of natural length `l₀ > 0` needs its ends apart (where they meet, the direction
    /// of its force is undefined): its length is bounded above 0, named by the spring's ends.
    fn admissible(&self, t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        if !self.elements.iter().any(|e| matches!(e, Element::Spring { rest, .. } if *rest > 0.0)) {
            return false;
        }
        // Checked after every step: the poses in a per-thread buffer, the name written only for
        // a bound that fails — no allocation on the way.
        thread_local! {
            static POSES: std::cell::RefCell<Vec<Pose<f64>>> = const { std::cell::RefCell::new(Vec::new()) };
        }
        POSES.with_borrow_mut(|poses| {
            poses.resize(self.description.bodies.len(), Pose::new(0.0, 0.0, 0.0));
            self.poses(t, q, poses);
            for (i, length) in self.spring_lengths(poses) {
                if length > 0.0 {
                    bounds.above("spring length", length, 0.0);
                } else if let ForceElement::Spring { a, b, .. } = &self.graph.forces[i] {
                    let name = format!("length of the spring from {} {:?} to {} {:?}", a.body, a.at, b.body, b.at);
                    bounds.above(&name, length, 0.0);
                }
            }
        });
        true
    }

    fn potential<S: Scalar>(&self, _t: S, _q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        self.has_potential.then(|| self.potential_at(world_from_body))
    }

    /// Dampers, torques and forces; body velocities (for the dampers) by a dual pass of the
    /// forward kinematics along `(q̇, 1)`.
    fn applied_forces<S: Scalar>(
        &self,
        t: S,
        q: &[S],
        qdot: &[S],
        world_from_body: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        if !self.has_loads {
            return false;
        }
        let twist = |b: usize| {
            let coordinate = |i: usize| Dual::new(q[i], qdot[i]);
            let pose = self.pose_of(b, Dual::new(t, S::one()), &coordinate);
            [pose.x.eps, pose.y.eps, pose.angle.eps]
        };
        self.loads_at(t, world_from_body, &twist, loads);
        true
    }

    fn constraints<S: Scalar>(&self, t: S, q: &[S], phi: &mut [S]) {
        let coordinate = |i: usize| q[i];
        for (j, joint) in self.joints.iter().enumerate().filter(|(_, joint)| !joint.tree) {
            self.closing_rows(j, t, &coordinate, &mut phi[joint.first_row..]);
        }
    }

    fn tree(&self) -> Option<&Tree> {
        self.tree.as_ref()
    }
}

// The steps of `GraphMechanism::new`, in order: check the bodies, the joints and the
// couplings; choose and orient the spanning tree (`spanning`); give every joint its value and
// number the coordinates; number the loop-closing joints' constraint rows; resolve the force
// elements.

/// The index of body `name` (`None`: the ground).
fn body_index(graph: &JointGraph, name: &str, what: &str) -> Result<Option<usize>, Error> {
    if name == GROUND {
        return Ok(None);
    }
    graph
        .bodies
        .iter()
        .position(|b| b.name == name)
        .map(Some)
        .ok_or_else(|| invalid(what, format!("refers to a body `{name}` the graph does not have")))
}

/// The index of joint `name`.
fn joint_index(graph: &JointGraph, name: &str, what: &str) -> Result<usize, Error> {
    graph
        .joints
        .iter()
        .position(|j| j.name == name)
        .ok_or_else(|| invalid(what, format!("refers to a joint `{name}` the graph does not have")))
}

/// The bodies, once their names, masses, inertias and shapes are checked.
fn check_bodies(graph: &JointGraph) -> Result<Vec<Body>, Error> {
    let mut bodies = Vec::with_capacity(graph.bodies.len());
    for (i, body) in graph.bodies.iter().enumerate() {
        let what = format!("body `{}`", body.name);
        if body.name.is_empty() || body.name == GROUND {
            return Err(invalid(&what, format!("a body may not be named `{}`", body.name)));
        }
        if graph.bodies[..i].iter().any(|b| b.name == body.name) {
            return Err(invalid(&what, "the name is used twice".into()));
        }
        for (name, value) in [("mass", body.mass), ("inertia", body.inertia)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(invalid(&what, format!("its {name} {value} must be finite and non-negative")));
            }
        }
        if let Some(shape) = body.shape {
            let size_ok = match shape {
                Shape::Disc { radius } => radius.is_finite() && radius > 0.0,
                Shape::Rectangle { half_extents: [a, b] } => a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0,
            };
            if !size_ok {
                return Err(invalid(&what, format!("its shape {shape:?} must have positive, finite sizes")));
            }
            let expected = shape.inertia(body.mass);
            if (body.inertia - expected).abs() > SHAPE_TOLERANCE * expected.max(f64::MIN_POSITIVE) {
                return Err(invalid(
                    &what,
                    format!("its inertia {} is not its shape's {expected} for mass {}", body.inertia, body.mass),
                ));
            }
        }
        bodies.push(Body::rigid(body.name.clone(), body.mass, body.inertia));
    }
    Ok(bodies)
}

/// Every joint's ends, once its name, bodies, anchors, axis and drive are checked.
fn check_joints(graph: &JointGraph) -> Result<Vec<Ends>, Error> {
    let mut ends = Vec::with_capacity(graph.joints.len());
    for (j, joint) in graph.joints.iter().enumerate() {
        let what = format!("joint `{}`", joint.name);
        if joint.name.is_empty() || graph.joints[..j].iter().any(|k| k.name == joint.name) {
            return Err(invalid(&what, "joint names must be unique and not empty".into()));
        }
        let (parent, child) = (body_index(graph, &joint.parent, &what)?, body_index(graph, &joint.child, &what)?);
        if parent == child {
            return Err(invalid(&what, format!("joins `{}` to itself", joint.parent)));
        }
        for value in joint.parent_anchor.iter().chain(&joint.child_anchor) {
            if !value.is_finite() {
                return Err(invalid(&what, format!("an anchor coordinate is {value}, not finite")));
            }
        }
        match joint.kind {
            JointType::Prismatic { axis } => {
                let norm = axis[0].hypot(axis[1]);
                let unit = (norm - 1.0).abs() <= UNIT_AXIS_TOLERANCE; // false for NaN
                if !unit {
                    return Err(invalid(&what, format!("its axis {axis:?} is not a unit vector")));
                }
            }
            JointType::Fixed { angle } if !angle.is_finite() => {
                return Err(invalid(&what, format!("its angle {angle} is not finite")));
            }
            _ => {}
        }
        if let Some(drive) = joint.drive {
            if matches!(joint.kind, JointType::Fixed { .. }) {
                return Err(invalid(&what, "a fixed joint has no coordinate to drive".into()));
            }
            drive.check(&what)?;
        }
        ends.push((parent, child));
    }
    Ok(ends)
}

/// A joint's coupling: `(source, ratio, offset)`.
type Coupling = (usize, f64, f64);

/// Per joint, its coupling to another joint, if any: one per coupled joint, between revolute
/// or prismatic joints, none on a driven joint.
fn check_couplings(graph: &JointGraph) -> Result<Vec<Option<Coupling>>, Error> {
    let mut coupled: Vec<Option<Coupling>> = vec![None; graph.joints.len()];
    for coupling in &graph.couplings {
        let what = format!("coupling of `{}` to `{}`", coupling.joint, coupling.source);
        let (j, s) = (joint_index(graph, &coupling.joint, &what)?, joint_index(graph, &coupling.source, &what)?);
        if j == s {
            return Err(invalid(&what, "couples a joint to itself".into()));
        }
        for k in [j, s] {
            if matches!(graph.joints[k].kind, JointType::Fixed { .. }) {
                return Err(invalid(&what, format!("`{}` is fixed and has no coordinate", graph.joints[k].name)));
            }
        }
        if graph.joints[j].drive.is_some() {
            return Err(invalid(&what, format!("`{}` is driven already", coupling.joint)));
        }
        if coupled[j].is_some() {
            return Err(invalid(&what, format!("`{}` is coupled twice", coupling.joint)));
        }
        if !(coupling.ratio.is_finite() && coupling.offset.is_finite()) {
            return Err(invalid(&what, "its ratio and offset must be finite".into()));
        }
        coupled[j] = Some((s, coupling.ratio, coupling.offset));
    }
    Ok(coupled)
}

/// The joints resolved, with the coordinates they carry.
struct Values {
    joints: Vec<ResolvedJoint>,
    coordinates: Vec<Coordinate>,
    /// The joint of each coordinate.
    coordinate_joints: Vec<usize>,
}

/// What sets each joint's value — a coordinate (a free tree joint, numbered in the order
/// listed), a drive, a coupling to a tree joint, or nothing — with couplings in a cycle and
/// absolute angles measured against the tree's direction refused.
fn joint_values(
    graph: &JointGraph,
    ends: &[Ends],
    in_tree: &[bool],
    reversed: &[bool],
    coupled: &[Option<Coupling>],
) -> Result<Values, Error> {
    let mut coordinates = Vec::new();
    let mut coordinate_joints = Vec::new();
    let mut joints = Vec::with_capacity(graph.joints.len());
    for (j, joint) in graph.joints.iter().enumerate() {
        let what = format!("joint `{}`", joint.name);
        let value = match (joint.kind, joint.drive, coupled[j]) {
            (JointType::Fixed { .. }, _, _) => JointValue::Fixed,
            (_, Some(profile), _) => JointValue::Driven(profile),
            (_, None, Some((source, ratio, offset))) => {
                if !in_tree[source] {
                    return Err(invalid(
                        &what,
                        format!(
                            "is coupled to `{}`, which closes a loop: a coupling's source must be a tree joint",
                            graph.joints[source].name
                        ),
                    ));
                }
                JointValue::Coupled { source, ratio, offset }
            }
            (kind, None, None) if in_tree[j] => {
                coordinates.push(match kind {
                    JointType::Prismatic { .. } => Coordinate::length(joint.name.clone()),
                    _ => Coordinate::angle(joint.name.clone()),
                });
                coordinate_joints.push(j);
                JointValue::Coordinate(coordinates.len() - 1)
            }
            _ => JointValue::Fixed,
        };
        if in_tree[j] && reversed[j] && joint.kind == JointType::Revolute && joint.angle == AngleReference::World {
            return Err(invalid(
                &what,
                format!(
                    "measures the absolute angle of `{}`, but the tree reaches `{}` first: list the joint the other way round or measure its angle from the parent",
                    joint.child, joint.child
                ),
            ));
        }
        let (parent, child) = ends[j];
        joints.push(ResolvedJoint { parent, child, tree: in_tree[j], reversed: reversed[j], value, first_row: 0 });
    }
    // Couplings in a cycle never resolve.
    let nj = joints.len();
    for j in 0..nj {
        let mut k = j;
        for _ in 0..=nj {
            match joints[k].value {
                JointValue::Coupled { source, .. } => k = source,
                _ => break,
            }
        }
        if matches!(joints[k].value, JointValue::Coupled { .. }) {
            return Err(invalid(&format!("joint `{}`", graph.joints[j].name), "is coupled in a cycle".into()));
        }
    }
    Ok(Values { joints, coordinates, coordinate_joints })
}

/// Number the loop-closing joints' constraint rows (2 for a revolute or prismatic joint, 3
/// for a fixed one, one more for a drive or a coupling), setting each one's first row and what
/// its extra row demands; returns the row count and the rows' names.
fn number_rows(
    graph: &JointGraph,
    in_tree: &[bool],
    coupled: &[Option<Coupling>],
    joints: &mut [ResolvedJoint],
) -> Vec<String> {
    let mut row_names = Vec::new();
    for (j, joint) in graph.joints.iter().enumerate() {
        if in_tree[j] {
            continue;
        }
        joints[j].first_row = row_names.len();
        let mut name = |what: &str| row_names.push(format!("{} ({what})", joint.name));
        match joint.kind {
            JointType::Revolute => ["x", "y"].iter().for_each(|w| name(w)),
            JointType::Prismatic { .. } => ["off the axis", "angle"].iter().for_each(|w| name(w)),
            JointType::Fixed { .. } => ["x", "y", "angle"].iter().for_each(|w| name(w)),
        }
        if let Some(profile) = joint.drive {
            joints[j].value = JointValue::Driven(profile);
            name("drive");
        } else if let Some((source, ratio, offset)) = coupled[j] {
            joints[j].value = JointValue::Coupled { source, ratio, offset };
            name("coupling");
        }
    }
    row_names
}

/// The force elements with their bodies and joints resolved to indices, once their values
/// are checked.
fn resolve_forces(graph: &JointGraph) -> Result<Vec<Element>, Error> {
    let mut elements = Vec::with_capacity(graph.forces.len());
    for (e, force) in graph.forces.iter().enumerate() {
        let what = format!("force element {e}");
        elements.push(resolve_force(graph, force, &what)?);
    }
    Ok(elements)
}

/// One force element resolved (`what` names it in errors).
fn resolve_force(graph: &JointGraph, force: &ForceElement, what: &str) -> Result<Element, Error> {
    let non_negative = |name: &str, value: f64| {
        if value.is_finite() && value >= 0.0 {
            Ok(())
        } else {
            Err(invalid(what, format!("its {name} {value} must be finite and non-negative")))
        }
    };
    let point = |body: &str, at: [f64; 2]| -> Result<(Option<usize>, [f64; 2]), Error> {
        let body = body_index(graph, body, what)?;
        if at.iter().all(|v| v.is_finite()) {
            Ok((body, at))
        } else {
            Err(invalid(what, format!("its point {at:?} is not finite")))
        }
    };
    let coordinate_joint = |name: &str| -> Result<usize, Error> {
        let j = joint_index(graph, name, what)?;
        if matches!(graph.joints[j].kind, JointType::Fixed { .. }) {
            return Err(invalid(what, format!("acts on `{name}`, a fixed joint without a coordinate")));
        }
        Ok(j)
    };
    let moving = |name: &str| -> Result<usize, Error> {
        body_index(graph, name, what)?.ok_or_else(|| invalid(what, "acts on the ground, which does not move".into()))
    };
    Ok(match force {
        ForceElement::Spring { a, b, stiffness, rest_length } => {
            non_negative("stiffness", *stiffness)?;
            non_negative("rest length", *rest_length)?;
            Element::Spring {
                a: point(&a.body, a.at)?,
                b: point(&b.body, b.at)?,
                stiffness: *stiffness,
                rest: *rest_length,
            }
        }
        ForceElement::Damper { a, b, coefficient } => {
            non_negative("coefficient", *coefficient)?;
            Element::Damper { a: point(&a.body, a.at)?, b: point(&b.body, b.at)?, coefficient: *coefficient }
        }
        ForceElement::JointSpring { joint, stiffness, rest } => {
            non_negative("stiffness", *stiffness)?;
            if !rest.is_finite() {
                return Err(invalid(what, format!("its rest value {rest} is not finite")));
            }
            Element::JointSpring { joint: coordinate_joint(joint)?, stiffness: *stiffness, rest: *rest }
        }
        ForceElement::JointDamper { joint, coefficient } => {
            non_negative("coefficient", *coefficient)?;
            Element::JointDamper { joint: coordinate_joint(joint)?, coefficient: *coefficient }
        }
        ForceElement::Torque { body, torque } => {
            torque.check(what)?;
            Element::Torque { body: moving(body)?, torque: *torque }
        }
        ForceElement::Force { at, force } => {
            force[0].check(what)?;
            force[1].check(what)?;
            let (body, at) = (moving(&at.body)?, point(&at.body, at.at)?.1);
            Element::Force { body, at, force: *force }
        }
    })
}
