//! The reduced model of joint graphs: poses, coordinates, constraints, forces and typed errors.

use super::*;
use crate::{Dynamics, Error, Mechanism, Model, Pose, State, accelerations};

fn rod(name: &str, mass: f64, length: f64) -> GraphBody {
    GraphBody::rigid(name, mass, mass * length * length / 12.0)
}

/// A double pendulum of rods with relative angles.
fn double_rod() -> JointGraph {
    JointGraph::new("double rod", 9.81)
        .with_body(rod("upper", 1.0, 1.0))
        .with_body(rod("lower", 0.7, 0.8))
        .with_joint(GraphJoint::revolute("a", GROUND, [0.0, 0.0], "upper", [0.0, 0.5]))
        .with_joint(GraphJoint::revolute("b", "upper", [0.0, -0.5], "lower", [0.0, 0.4]))
}

fn poses(mechanism: &GraphMechanism, t: f64, q: &[f64]) -> Vec<Pose<f64>> {
    let mut out = vec![Pose::default(); mechanism.description().bodies.len()];
    mechanism.poses(t, q, &mut out);
    out
}

/// `(x, y, φ)` of every body, flattened.
fn flat(poses: &[Pose<f64>]) -> Vec<f64> {
    poses.iter().flat_map(|p| p.to_array()).collect()
}

fn close(a: &[f64], b: &[f64], tolerance: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tolerance)
}

/// Forward kinematics by hand for the double rod, and the coordinates read back from the poses.
#[test]
fn poses_and_coordinates_round_trip() {
    let mechanism = GraphMechanism::new(double_rod()).unwrap();
    let q = [0.4, -0.9];
    let got = poses(&mechanism, 0.0, &q);
    let (s1, c1) = q[0].sin_cos();
    let (s2, c2) = (q[0] + q[1]).sin_cos();
    let pivot = [s1, -c1];
    let expected = [0.5 * s1, -0.5 * c1, q[0], pivot[0] + 0.4 * s2, pivot[1] - 0.4 * c2, q[0] + q[1]];
    // Round-off of a few sin/cos evaluations on unit lengths.
    assert!(close(&flat(&got), &expected, 1e-15), "{:?} vs {expected:?}", flat(&got));
    let mut back = [0.0; 2];
    mechanism.coordinates_of(&got, &mut back);
    assert!(close(&back, &q, 1e-15), "{back:?}");
    // The tree path is taken, and agrees with the assembled mass matrix path to round-off.
    let (tree, generic) = (Model::new(mechanism.clone()).unwrap(), Model::new_generic(mechanism).unwrap());
    assert!(tree.uses_tree_path());
    let (mut w1, mut w2) = (tree.workspace(), generic.workspace());
    let a = accelerations(&tree, &mut w1, 0.0, &q, &[0.3, -0.2]).unwrap().to_vec();
    let b = accelerations(&generic, &mut w2, 0.0, &q, &[0.3, -0.2]).unwrap().to_vec();
    // κ(M) ≈ 30 here: 1e-13 is a few hundred ε of O(10) accelerations.
    assert!(close(&a, &b, 1e-13), "{a:?} vs {b:?}");
}

/// The same joint listed the other way round (the tree then places its parent from its child)
/// with its angle counted clockwise describes the same motion.
#[test]
fn reversed_and_clockwise_joints_describe_the_same_motion() {
    let forward = GraphMechanism::new(double_rod()).unwrap();
    let mut graph = double_rod();
    graph.joints[0] = GraphJoint::revolute("a", "upper", [0.0, 0.5], GROUND, [0.0, 0.0]).clockwise();
    let backward = GraphMechanism::new(graph).unwrap();
    assert!(backward.is_reversed(0));
    // Reversed and clockwise: q_a = −(φ_ground − φ_upper) = φ_upper, the same coordinate.
    let q = [0.7, 0.25];
    assert!(close(&flat(&poses(&forward, 0.0, &q)), &flat(&poses(&backward, 0.0, &q)), 1e-15));
    let (m1, m2) = (Model::new(forward).unwrap(), Model::new(backward).unwrap());
    assert!(!m2.uses_tree_path(), "a reversed joint has no articulated-body form");
    let (mut w1, mut w2) = (m1.workspace(), m2.workspace());
    let a = accelerations(&m1, &mut w1, 0.0, &q, &[1.0, -0.5]).unwrap().to_vec();
    let b = accelerations(&m2, &mut w2, 0.0, &q, &[1.0, -0.5]).unwrap().to_vec();
    assert!(close(&a, &b, 1e-13), "{a:?} vs {b:?}");
}

/// A four-bar with the pin at B closing the loop: two constraint rows named after the joint,
/// zero at an assembled state, and a prismatic slider's value is its slide.
#[test]
fn loops_give_named_constraints_that_vanish_when_assembled() {
    let graph = JointGraph::new("four-bar", 9.81)
        .with_body(rod("crank", 1.0, 1.0))
        .with_body(rod("coupler", 1.0, 2.0))
        .with_body(rod("rocker", 1.0, 2.0))
        .with_joint(GraphJoint::revolute("θ2", GROUND, [0.0, 0.0], "crank", [-0.5, 0.0]))
        .with_joint(GraphJoint::revolute("θ3", "crank", [0.5, 0.0], "coupler", [-1.0, 0.0]).absolute())
        .with_joint(GraphJoint::revolute("θ4", GROUND, [2.0, 0.0], "rocker", [-1.0, 0.0]))
        .with_joint(GraphJoint::revolute("B", "coupler", [1.0, 0.0], "rocker", [1.0, 0.0]).closing());
    let mechanism = GraphMechanism::new(graph).unwrap();
    assert_eq!(mechanism.description().constraints.len(), 2);
    assert_eq!(mechanism.description().constraint_name(1), "B (y)");
    let model = Model::new(mechanism).unwrap();
    let state = model.assemble(&State::new(0.0, [1.0, 0.5, 1.5], [2.0, 0.0, 0.0]), &[true, false, false]).unwrap();
    let mut phi = [1.0; 2];
    model.mechanism().constraints(0.0, &state.q, &mut phi);
    // Gauss–Newton stops at 16 ε L (L the scale of the positions) or at its round-off band.
    assert!(phi.iter().all(|v| v.abs() < 1e-14), "{phi:?}");
    assert_eq!(state.q[0], 1.0);
}

/// The springs' and dampers' wrenches on the bodies project onto the reduced model's
/// generalized forces: `Σ_b J_bᵀ w_b = −∂V/∂q + Q`.
#[test]
fn body_wrenches_project_onto_the_generalized_forces() {
    let graph = double_rod()
        .with_force(ForceElement::Spring {
            a: Point::world([0.5, 0.2]),
            b: Point::on("lower", [0.1, -0.2]),
            stiffness: 30.0,
            rest_length: 0.4,
        })
        .with_force(ForceElement::Damper {
            a: Point::on("upper", [0.1, 0.0]),
            b: Point::on("lower", [0.0, -0.3]),
            coefficient: 2.0,
        })
        .with_force(ForceElement::JointSpring { joint: "b".into(), stiffness: 5.0, rest: 0.3 })
        .with_force(ForceElement::JointDamper { joint: "b".into(), coefficient: 0.7 })
        .with_force(ForceElement::Torque { body: "upper".into(), torque: Profile::harmonic(1.5, 2.0) })
        .with_force(ForceElement::Force {
            at: Point::on("lower", [0.2, 0.1]),
            force: [Profile::constant(0.4), Profile::ramp(0.1, -0.3)],
        });
    let mechanism = GraphMechanism::new(graph).unwrap();
    let (t, q, qdot) = (0.3, [0.4, -0.9], [0.8, 1.3]);
    // The body velocities by a dual pass of the poses.
    let dual_q: Vec<num_dual::Dual64> = q.iter().zip(&qdot).map(|(a, b)| num_dual::Dual64::new(*a, *b)).collect();
    let mut dual_poses = vec![Pose::<num_dual::Dual64>::default(); 2];
    mechanism.poses(num_dual::Dual64::new(t, 1.0), &dual_q, &mut dual_poses);
    let poses: Vec<Pose<f64>> = dual_poses.iter().map(|p| Pose::new(p.x.re, p.y.re, p.angle.re)).collect();
    let velocities: Vec<[f64; 3]> = dual_poses.iter().map(|p| [p.x.eps, p.y.eps, p.angle.eps]).collect();
    let mut wrench = vec![0.0; 6];
    mechanism.body_wrenches(t, &poses, &velocities, &mut wrench);
    // Σ J_bᵀ w_b by a dual pass per coordinate.
    let mut projected = [0.0; 2];
    for (i, p) in projected.iter_mut().enumerate() {
        let seeded: Vec<num_dual::Dual64> =
            q.iter().enumerate().map(|(j, v)| num_dual::Dual64::new(*v, if i == j { 1.0 } else { 0.0 })).collect();
        let mut d = vec![Pose::<num_dual::Dual64>::default(); 2];
        mechanism.poses(num_dual::Dual64::from(t), &seeded, &mut d);
        *p = d
            .iter()
            .enumerate()
            .map(|(b, pose)| {
                pose.x.eps * wrench[3 * b] + pose.y.eps * wrench[3 * b + 1] + pose.angle.eps * wrench[3 * b + 2]
            })
            .sum();
    }
    // The reduced model: f − (gravity's share) = −∂V/∂q + Q. Gravity off to isolate the elements.
    let mut graph = mechanism.graph().clone();
    graph.gravity = 0.0;
    let model = Model::new(GraphMechanism::new(graph).unwrap()).unwrap();
    let mut ws = model.workspace();
    let qddot = accelerations(&model, &mut ws, t, &q, &qdot).unwrap().to_vec();
    let mut mass = vec![0.0; 4];
    Dynamics::mass_matrix(&model, &mut Dynamics::workspace(&model), t, &q, &qdot, &mut mass).unwrap();
    // M q̈ = f − (convective terms); the convective terms at this q̇: run with the elements removed.
    let mut bare = model.mechanism().graph().clone();
    bare.forces.clear();
    let bare = Model::new(GraphMechanism::new(bare).unwrap()).unwrap();
    let mut wb = bare.workspace();
    let free = accelerations(&bare, &mut wb, t, &q, &qdot).unwrap().to_vec();
    let forces: Vec<f64> = (0..2).map(|i| (0..2).map(|j| mass[2 * i + j] * (qddot[j] - free[j])).sum()).collect();
    // O(10) forces through a 2 × 2 solve and back: 1e-12 is a few thousand ε.
    assert!(close(&forces, &projected, 1e-12), "reduced {forces:?} vs projected wrenches {projected:?}");
}

fn graph_error(graph: JointGraph) -> (String, String) {
    match GraphMechanism::new(graph) {
        Err(Error::InvalidGraph { element, why }) => (element, why),
        other => panic!("expected an invalid graph, got {other:?}"),
    }
}

/// Graphs that are not mechanisms are typed errors naming the element.
#[test]
fn graphs_that_are_not_mechanisms_are_typed_errors() {
    // A body without a path to the ground.
    let (element, why) = graph_error(double_rod().with_body(rod("loose", 1.0, 1.0)));
    assert_eq!(element, "body `loose`");
    assert!(why.contains("no path"), "{why}");
    // A joint to a missing body.
    let (element, why) =
        graph_error(double_rod().with_joint(GraphJoint::revolute("c", "lower", [0.0; 2], "ghost", [0.0; 2])));
    assert_eq!(element, "joint `c`");
    assert!(why.contains("`ghost`"), "{why}");
    // Every tree joint fixed: nothing moves.
    let rigid = JointGraph::new("rigid", 9.81)
        .with_body(rod("a", 1.0, 1.0))
        .with_joint(GraphJoint::fixed("weld", GROUND, [0.0; 2], "a", [0.0; 2], 0.0));
    let (_, why) = graph_error(rigid);
    assert!(why.contains("no free coordinate"), "{why}");
    // Tree joints marked in a loop.
    let mut looped = double_rod().with_joint(GraphJoint::revolute("c", "lower", [0.0, -0.4], GROUND, [1.0, -1.0]));
    for joint in &mut looped.joints {
        joint.role = Role::Tree;
    }
    let (element, why) = graph_error(looped);
    assert_eq!(element, "joint `c`");
    assert!(why.contains("closes a loop"), "{why}");
    // A negative mass, a reserved name, a non-unit axis, a coupling to a loop-closing joint.
    let mut negative = double_rod();
    negative.bodies[1].mass = -1.0;
    assert_eq!(graph_error(negative).0, "body `lower`");
    assert_eq!(graph_error(double_rod().with_body(rod(GROUND, 1.0, 1.0))).0, "body `ground`");
    let slanted = JointGraph::new("slider", 0.0).with_body(rod("s", 1.0, 1.0)).with_joint(GraphJoint::prismatic(
        "x",
        GROUND,
        [0.0; 2],
        "s",
        [0.0; 2],
        [1.0, 1.0],
    ));
    assert_eq!(graph_error(slanted).0, "joint `x`");
    let coupled = double_rod()
        .with_joint(GraphJoint::revolute("c", "lower", [0.0, -0.4], GROUND, [1.0, -1.0]).closing())
        .with_coupling("a", "c", 2.0, 0.0);
    assert!(graph_error(coupled).1.contains("must be a tree joint"));
}

/// A driven joint has no coordinate; a coupled one follows its source.
#[test]
fn driven_and_coupled_joints_follow_their_laws() {
    let graph = JointGraph::new("geared", 0.0)
        .with_body(GraphBody::rigid("support", 0.0, 0.0))
        .with_body(rod("wheel", 2.0, 1.0))
        .with_body(rod("gear", 1.0, 0.5))
        .with_joint(
            GraphJoint::prismatic("s", GROUND, [0.0; 2], "support", [0.0; 2], [1.0, 0.0])
                .driven(Profile::harmonic(0.2, 3.0)),
        )
        .with_joint(GraphJoint::revolute("w", "support", [0.0; 2], "wheel", [0.0; 2]))
        .with_joint(GraphJoint::revolute("g", "support", [1.0, 0.0], "gear", [0.0; 2]))
        .with_coupling("g", "w", -2.0, 0.1);
    let mechanism = GraphMechanism::new(graph).unwrap();
    assert_eq!(mechanism.description().coordinates.len(), 1);
    assert!(mechanism.is_rheonomic());
    let t = 0.4;
    let p = poses(&mechanism, t, &[0.3]);
    let support_x = 0.2 * (3.0 * t).sin();
    assert!(close(&p[0].to_array(), &[support_x, 0.0, 0.0], 1e-16));
    assert!(close(&p[2].to_array(), &[support_x + 1.0, 0.0, -2.0 * 0.3 + 0.1], 1e-15));
}

/// A rigid loop — a pendulum welded to a bar that is welded to the ground — leaves its pin's
/// coordinate in the reduced model but no degree of freedom: the loop locks it, and the model
/// keeps it at rest (a structure is a mechanism; at 6d4bf6b its graph was refused).
#[test]
fn a_rigid_loop_has_no_degree_of_freedom() {
    let graph = JointGraph::new("welded", 9.81)
        .with_body(rod("arm", 1.0, 1.0))
        .with_body(rod("bar", 1.0, 1.0))
        .with_joint(GraphJoint::revolute("θ", GROUND, [0.0, 0.0], "arm", [0.0, 0.5]))
        .with_joint(GraphJoint::fixed("weld", "arm", [0.0, -0.5], "bar", [0.0, 0.5], 0.0))
        .with_joint(GraphJoint::fixed("bolt", "bar", [0.0, -0.5], GROUND, [0.0, -2.0], 0.0).closing());
    let mechanism = GraphMechanism::new(graph).unwrap();
    assert_eq!(mechanism.description().coordinates.len(), 1);
    assert_eq!(mechanism.degrees_of_freedom(0.0, &[0.0]), 0);
    // A structure is a valid mechanism: it stays where the constraints put it.
    let model = Model::new(mechanism).unwrap();
    let run = crate::simulate(
        &model,
        &State::new(0.0, [0.0], [0.0]),
        1.0,
        crate::Method::Dopri5 { tol: crate::Tolerances::uniform(1e-10) },
        &crate::Output::Ends,
    )
    .unwrap();
    assert!(run.q(run.len() - 1)[0].abs() < 1e-12, "{:?}", run.q(run.len() - 1));
    // The four-bar keeps one.
    let four_bar = JointGraph::new("four-bar", 9.81)
        .with_body(rod("crank", 1.0, 1.0))
        .with_body(rod("coupler", 1.0, 2.0))
        .with_body(rod("rocker", 1.0, 2.0))
        .with_joint(GraphJoint::revolute("θ2", GROUND, [0.0, 0.0], "crank", [-0.5, 0.0]))
        .with_joint(GraphJoint::revolute("θ3", "crank", [0.5, 0.0], "coupler", [-1.0, 0.0]).absolute())
        .with_joint(GraphJoint::revolute("θ4", GROUND, [2.0, 0.0], "rocker", [-1.0, 0.0]))
        .with_joint(GraphJoint::revolute("B", "coupler", [1.0, 0.0], "rocker", [1.0, 0.0]).closing());
    let model = Model::new(GraphMechanism::new(four_bar).unwrap()).unwrap();
    let state = model.assemble(&State::new(0.0, [1.0, 0.5, 1.5], [0.0; 3]), &[true, false, false]).unwrap();
    assert_eq!(model.mechanism().degrees_of_freedom(0.0, &state.q), 1);
}

/// A parallelogram with a third parallel crank pinned to the coupler's middle: 4 coordinates
/// and 4 loop rows, of which one is dependent at every configuration, so one degree of
/// freedom. Regression: the elimination measured each pivot against its row as already
/// reduced, so a dependent row's round-off passed as a pivot and the linkage counted as locked.
#[test]
fn a_redundant_loop_row_does_not_lock_the_parallelogram() {
    let graph = JointGraph::new("parallelogram", 9.81)
        .with_body(rod("crank", 1.0, 1.0))
        .with_body(rod("coupler", 1.0, 2.0))
        .with_body(rod("rocker", 1.0, 1.0))
        .with_body(rod("third", 1.0, 1.0))
        .with_joint(GraphJoint::revolute("θ1", GROUND, [0.0, 0.0], "crank", [-0.5, 0.0]))
        .with_joint(GraphJoint::revolute("φ", "crank", [0.5, 0.0], "coupler", [-1.0, 0.0]))
        .with_joint(GraphJoint::revolute("θ2", GROUND, [2.0, 0.0], "rocker", [-0.5, 0.0]))
        .with_joint(GraphJoint::revolute("B", "coupler", [1.0, 0.0], "rocker", [0.5, 0.0]))
        .with_joint(GraphJoint::revolute("θ3", GROUND, [1.0, 0.0], "third", [-0.5, 0.0]))
        .with_joint(GraphJoint::revolute("C", "coupler", [0.0, 0.0], "third", [0.5, 0.0]));
    let mechanism = GraphMechanism::new(graph).unwrap();
    assert_eq!((mechanism.description().coordinates.len(), mechanism.description().constraints.len()), (4, 4));
    for theta in [-std::f64::consts::FRAC_PI_2, -1.0, 0.4, 2.5] {
        assert_eq!(mechanism.degrees_of_freedom(0.0, &[theta, -theta, theta, theta]), 1, "θ = {theta}");
    }
}
