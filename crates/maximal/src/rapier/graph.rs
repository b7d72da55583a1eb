//! The rapier plan of a joint graph, written generically: one rapier body per graph body, one
//! rapier joint per graph joint (impulse joints throughout, or multibody joints along the
//! spanning tree with the loop-closing joints as impulse joints), couplings as multibody
//! couplings, the force elements applied per step, bodies driven from the ground as kinematic
//! bodies (docs/graphs.md#rapier).

use super::plan::{BodySpec, Coupling, JointKind, JointMode, JointSpec, Motion, Plan, StepForces};
use super::scenes::{COMPOUND_BOB, NO_PULLEY_JOINT, NO_RHEONOMIC_MULTIBODY};
use crate::{BuildError, Engine, maps};
use lagrange::State;
use lagrange::graph::{ForceElement, GraphMechanism, JointType, Shape};
use lagrange::tree::AngleReference;
use lagrange_scenes::Params;
use std::sync::Arc;

/// A graph's plan, with what it changed in the graph.
pub(crate) struct GraphPlan {
    /// The plan.
    pub plan: Plan,
    /// One sentence per change of the graph (compound bodies for impulse revolute joints).
    pub deviations: Vec<String>,
    /// The graph rapier simulates (with those changes).
    pub graph: lagrange::graph::JointGraph,
    /// The bodies whose inertia was changed, with the new inertia.
    pub inertias: Vec<(String, f64)>,
}

/// Mass and inertia of a shaped body from parry's mass properties of its shape at the density
/// that gives the body's mass.
fn parry_mass_properties(shape: Shape, mass: f64) -> (f64, f64) {
    use rapier2d_f64::parry::shape::{Ball, Cuboid, Shape as _};
    let density = mass / shape.area();
    let properties = match shape {
        Shape::Disc { radius } => Ball::new(radius).mass_properties(density),
        Shape::Rectangle { half_extents: [a, b] } => {
            Cuboid::new(rapier2d_f64::math::Vector::new(a, b)).mass_properties(density)
        }
    };
    (properties.mass(), properties.principal_inertia())
}

/// The plan of `mechanism` (named `name`) in `mode`, from the reduced `initial` state.
///
/// # Errors
/// [`BuildError::Unbuildable`] naming the joint or body rapier cannot take: couplings with
/// impulse joints, drives with multibody joints, a drive between two moving bodies, a massless
/// body with impulse joints, a coupling on a loop-closing joint or on an absolute angle;
/// [`BuildError::Invalid`] for a state of the wrong size.
pub(crate) fn plan(
    engine: Engine,
    mode: JointMode,
    name: &str,
    mechanism: &GraphMechanism,
    initial: &State,
) -> Result<GraphPlan, BuildError> {
    let unbuildable = |reason: String| BuildError::Unbuildable { engine, scene: name.into(), reason };
    check_expressible(mode, mechanism).map_err(unbuildable)?;
    let states = maps::graph_body_states(mechanism, initial)?;
    let PlannedBodies { bodies, deviations, inertias, simulated } =
        plan_bodies(mode, mechanism, &states).map_err(unbuildable)?;
    let (specs, plan_joint, sign) = plan_joints(mechanism, &bodies);
    let couplings = plan_couplings(mechanism, &bodies, &specs, &plan_joint, &sign);
    let graph = mechanism.graph();
    let simulated_graph = simulated.clone();
    let simulated = Arc::new(GraphMechanism::new(simulated)?);
    let plan = Plan {
        scene: name.into(),
        mode,
        params: Params::defaults(&[]),
        read_back: Some(crate::maps::ReadBack::graph(Arc::clone(&simulated))),
        deviations: deviations.clone(),
        gravity: graph.gravity,
        reduced_bodies: graph.bodies.len(),
        bodies,
        joints: specs,
        couplings,
        forces: step_forces(graph),
        t0: initial.t,
        graph: Some(simulated),
    };
    Ok(GraphPlan { plan, deviations, graph: simulated_graph, inertias })
}

/// What rapier's joints of `mode` cannot express in the graph, as a sentence: a driven joint
/// in a multibody or on a body that also moves by itself, a coupling between impulse joints,
/// in a loop, or on an absolute angle.
fn check_expressible(mode: JointMode, mechanism: &GraphMechanism) -> Result<(), String> {
    let graph = mechanism.graph();
    for (j, spec) in graph.joints.iter().enumerate() {
        let driven = mechanism.drive(j).is_some();
        match mechanism.coupling(j) {
            _ if driven && mode == JointMode::Multibody => {
                return Err(format!("joint `{}` is driven: {NO_RHEONOMIC_MULTIBODY}", spec.name));
            }
            _ if driven
                && (!mechanism.in_tree(j) || !mechanism.placed_body(j).is_none_or(|b| mechanism.is_kinematic(b))) =>
            {
                return Err(format!(
                    "joint `{}` drives a body that also moves by itself: rapier has no joint with a prescribed \
                     coordinate, and only bodies driven from the ground become kinematic bodies",
                    spec.name
                ));
            }
            Some((source, _)) => {
                if mode == JointMode::Impulse {
                    return Err(format!("joint `{}` is coupled: {NO_PULLEY_JOINT}", spec.name));
                }
                if !mechanism.in_tree(j) {
                    return Err(format!(
                        "joint `{}` is coupled but closes a loop: rapier couples multibody coordinates only",
                        spec.name
                    ));
                }
                for k in [j, source] {
                    let s = &graph.joints[k];
                    if s.kind == JointType::Revolute
                        && s.angle == AngleReference::World
                        && mechanism.joint_ends(k).0.is_some()
                    {
                        return Err(format!(
                            "the coupling of joint `{}` acts on `{}`, an absolute angle, but rapier couples relative \
                             joint coordinates",
                            spec.name, s.name
                        ));
                    }
                }
            }
            None => {}
        }
    }
    Ok(())
}

/// The rapier bodies of a graph, with what they change in it.
struct PlannedBodies {
    bodies: Vec<BodySpec>,
    deviations: Vec<String>,
    inertias: Vec<(String, f64)>,
    /// The graph with the changed inertias.
    simulated: lagrange::graph::JointGraph,
}

/// The ground, then one rapier body per graph body: mass and inertia from its shape, a
/// compound body for an impulse revolute joint on a body without inertia, a multibody link
/// left out where it moves no mass.
fn plan_bodies(
    mode: JointMode,
    mechanism: &GraphMechanism,
    states: &[crate::BodyState],
) -> Result<PlannedBodies, String> {
    let graph = mechanism.graph();
    let joints = 0..graph.joints.len();
    let mut deviations = Vec::new();
    let mut inertias = Vec::new();
    let mut simulated = graph.clone();
    let mut bodies = vec![BodySpec::ground()];
    for (b, body) in graph.bodies.iter().enumerate() {
        let kinematic = mechanism.is_kinematic(b);
        let (mass, mut inertia) = match body.shape {
            Some(shape) => parry_mass_properties(shape, body.mass),
            None => (body.mass, body.inertia),
        };
        if mode == JointMode::Impulse && !kinematic {
            if mass == 0.0 {
                return Err(format!(
                    "body `{}` has no mass, which rapier's impulse joints read as an infinite mass",
                    body.name
                ));
            }
            // The farthest revolute anchor from the centre of a body without inertia.
            let arm = joints
                .clone()
                .map(|j| (mechanism.joint_ends(j), &graph.joints[j]))
                .filter(|(_, spec)| spec.kind == JointType::Revolute)
                .filter_map(|((parent, child), spec)| {
                    if child == Some(b) {
                        Some(spec.child_anchor)
                    } else if parent == Some(b) {
                        Some(spec.parent_anchor)
                    } else {
                        None
                    }
                })
                .fold(0.0_f64, |l, a| l.max(a[0].hypot(a[1])));
            if inertia == 0.0 && arm > 0.0 {
                inertia = COMPOUND_BOB * mass * arm * arm;
                simulated.bodies[b].inertia = inertia;
                inertias.push((body.name.clone(), inertia));
                deviations.push(format!(
                    "body `{}` has inertia {inertia:e} kg m² = {COMPOUND_BOB:e} m l² (l = {arm} m, its farthest pin) \
                     instead of 0: an impulse revolute joint freezes the rotation of a body without inertia",
                    body.name
                ));
            }
        }
        // A body without mass or inertia moved by a coupled joint alone (an Atwood pulley
        // without inertia) would be a multibody link that moves no mass: left out.
        let touching = joints
            .clone()
            .filter(|&j| matches!(mechanism.joint_ends(j), (p, c) if p == Some(b) || c == Some(b)))
            .count();
        let derived = mode == JointMode::Multibody
            && mass == 0.0
            && inertia == 0.0
            && touching == 1
            && joints.clone().any(|j| {
                mechanism.in_tree(j)
                    && mechanism.joint_ends(j).1 == Some(b)
                    && !mechanism.is_reversed(j)
                    && mechanism.coupling(j).is_some()
            });
        bodies.push(BodySpec {
            motion: if derived {
                Motion::Derived { body: b }
            } else if kinematic {
                Motion::Kinematic { body: b }
            } else {
                Motion::Dynamic
            },
            mass,
            inertia,
            initial: states[b],
            reduced: Some(b),
            collider: None,
        });
    }
    Ok(PlannedBodies { bodies, deviations, inertias, simulated })
}

/// The rapier joints: the tree parents first (turned to hang each body from the one nearer the
/// ground), then the loop-closing joints; joints between bodies that do not move by themselves
/// (the ground, kinematic bodies) are left out. Returns the joints, each graph joint's plan
/// joint, and the sign of its coordinate in rapier's (−1 where turned).
fn plan_joints(mechanism: &GraphMechanism, bodies: &[BodySpec]) -> (Vec<JointSpec>, Vec<Option<usize>>, Vec<f64>) {
    let graph = mechanism.graph();
    let count = graph.joints.len();
    let plan_body = |end: Option<usize>| end.map_or(0, |b| b + 1);
    let moves = |end: Option<usize>| end.is_some_and(|b| !mechanism.is_kinematic(b));
    let mut specs = Vec::new();
    let mut plan_joint = vec![None; count];
    let mut sign = vec![1.0; count];
    let order: Vec<usize> =
        mechanism.tree_order().iter().map(|&(j, _)| j).chain((0..count).filter(|&j| !mechanism.in_tree(j))).collect();
    for j in order {
        let ((parent, child), spec) = (mechanism.joint_ends(j), &graph.joints[j]);
        let left_out = |end: Option<usize>| end.is_some_and(|b| matches!(bodies[b + 1].motion, Motion::Derived { .. }));
        if (!moves(parent) && !moves(child)) || left_out(parent) || left_out(child) {
            continue;
        }
        let kind = match spec.kind {
            JointType::Revolute => JointKind::Revolute,
            JointType::Prismatic { axis } => JointKind::Prismatic { axis },
            JointType::Fixed { angle } => JointKind::Fixed { angle },
        };
        let mut joint_spec = JointSpec {
            parent: plan_body(parent),
            child: plan_body(child),
            anchor_parent: spec.parent_anchor,
            anchor_child: spec.child_anchor,
            kind,
            closing: !mechanism.in_tree(j),
        };
        if mechanism.in_tree(j) && mechanism.is_reversed(j) {
            std::mem::swap(&mut joint_spec.parent, &mut joint_spec.child);
            std::mem::swap(&mut joint_spec.anchor_parent, &mut joint_spec.anchor_child);
            if let JointKind::Fixed { angle } = kind {
                joint_spec.kind = JointKind::Fixed { angle: -angle };
            }
            sign[j] = -1.0;
        }
        plan_joint[j] = Some(specs.len());
        specs.push(joint_spec);
    }
    (specs, plan_joint, sign)
}

/// The multibody couplings, in rapier's coordinates of the turned joints, with the offset from
/// the initial state.
fn plan_couplings(
    mechanism: &GraphMechanism,
    bodies: &[BodySpec],
    specs: &[JointSpec],
    plan_joint: &[Option<usize>],
    sign: &[f64],
) -> Vec<Coupling> {
    let mut couplings = Vec::new();
    for j in 0..mechanism.graph().joints.len() {
        if let Some((source, ratio)) = mechanism.coupling(j)
            && let (Some(to), Some(from)) = (plan_joint[j], plan_joint[source])
        {
            let coordinate = |k: usize| {
                let spec: &JointSpec = &specs[k];
                spec.coordinate(&bodies[spec.parent].initial, &bodies[spec.child].initial).0
            };
            let coeff = sign[j] * sign[source] * ratio;
            couplings.push(Coupling { from, to, coeff, offset: coordinate(to) - coeff * coordinate(from) });
        }
    }
    couplings
}

/// The graph's force elements: applied per step where they vary, in every substep where they
/// are constant.
fn step_forces(graph: &lagrange::graph::JointGraph) -> StepForces {
    let varying = graph.forces.iter().any(|f| match f {
        ForceElement::Torque { torque, .. } => torque.varies(),
        ForceElement::Force { force, .. } => force[0].varies() || force[1].varies(),
        _ => true,
    });
    StepForces { graph_varying: varying, graph_constant: !varying && !graph.forces.is_empty(), ..StepForces::default() }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// parry's mass properties of a shape agree with the graph's own formulas (the reduced
    /// model's), to round-off.
    #[test]
    fn parry_mass_properties_are_the_shapes() {
        for shape in [Shape::Disc { radius: 0.3 }, Shape::Rectangle { half_extents: [0.4, 0.15] }] {
            let mass = 2.5;
            let (m, i) = parry_mass_properties(shape, mass);
            assert!((m - mass).abs() <= 1e-14 * mass, "{shape:?}: mass {m}");
            let expected = shape.inertia(mass);
            assert!((i - expected).abs() <= 1e-14 * expected, "{shape:?}: inertia {i} vs {expected}");
        }
    }
}
