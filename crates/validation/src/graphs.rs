//! Random joint graphs for the checks: trees and single loops of bodies on revolute and
//! prismatic joints with random masses, inertias, anchors and springs, each with a consistent
//! initial state — reproducible from the caller's seeded generator (`lagrange_testing::rng`).

use lagrange::graph::{ForceElement, GROUND, GraphBody, GraphJoint, GraphMechanism, JointGraph, Point, Role};
use lagrange::{Mechanism, State};
use lagrange_testing::Rng;
use rand::Rng as _;

/// A random point of the square `[−h, h]²`.
fn point(rng: &mut Rng, h: f64) -> [f64; 2] {
    [rng.random_range(-h..h), rng.random_range(-h..h)]
}

/// A random unit vector.
fn direction(rng: &mut Rng) -> [f64; 2] {
    let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
    [angle.cos(), angle.sin()]
}

/// A body with mass in `[0.5, 2]` kg and inertia in `[0.01, 0.2]` kg m².
fn body(rng: &mut Rng, i: usize) -> GraphBody {
    GraphBody::rigid(format!("b{i}"), rng.random_range(0.5..2.0), rng.random_range(0.01..0.2))
}

/// Revolute (or, with probability `prismatic`, prismatic) joint `name` from `parent` to `child`.
fn joint(rng: &mut Rng, name: String, parent: &str, child: &str, prismatic: f64) -> GraphJoint {
    let (a, c) = (point(rng, 0.5), point(rng, 0.5));
    if rng.random_bool(prismatic) {
        GraphJoint::prismatic(name, parent, a, child, c, direction(rng))
    } else {
        GraphJoint::revolute(name, parent, a, child, c)
    }
}

/// One or two springs between random points of random bodies (or the ground), stiffness
/// `[5, 30]` N/m, natural length `[0, 0.5]` m, and a torsion spring on the first joint.
fn springs(rng: &mut Rng, graph: JointGraph) -> JointGraph {
    let names: Vec<String> = graph.bodies.iter().map(|b| b.name.clone()).collect();
    let mut graph = graph;
    for _ in 0..rng.random_range(1..=2) {
        let end = |rng: &mut Rng| {
            let k = rng.random_range(0..=names.len());
            let body = if k == names.len() { GROUND.to_string() } else { names[k].clone() };
            Point { body, at: point(rng, 0.4) }
        };
        let (a, b) = (end(rng), end(rng));
        if a.body == b.body {
            continue;
        }
        graph = graph.with_force(ForceElement::Spring {
            a,
            b,
            stiffness: rng.random_range(5.0..30.0),
            rest_length: rng.random_range(0.0..0.5),
        });
    }
    let first = graph.joints[0].name.clone();
    graph.with_force(ForceElement::JointSpring { joint: first, stiffness: rng.random_range(0.5..3.0), rest: 0.1 })
}

/// A random state of `mechanism`: coordinates in `[−0.5, 0.5]`, rates in `[−0.5, 0.5]`.
fn random_state(rng: &mut Rng, mechanism: &GraphMechanism) -> State {
    let n = mechanism.description().coordinates.len();
    let q: Vec<f64> = (0..n).map(|_| rng.random_range(-0.5..0.5)).collect();
    let qdot: Vec<f64> = (0..n).map(|_| rng.random_range(-0.5..0.5)).collect();
    State::new(0.0, q, qdot)
}

/// A random tree of `bodies` bodies: body `i` hangs from the ground or an earlier body by a
/// revolute joint (a prismatic one with probability 0.3), with springs; and a random state.
///
/// # Panics
/// If `bodies` is 0.
pub fn random_tree(rng: &mut Rng, bodies: usize) -> (JointGraph, State) {
    assert!(bodies > 0, "a tree needs a body");
    let mut graph = JointGraph::new(format!("random tree of {bodies}"), 9.81);
    for i in 0..bodies {
        graph = graph.with_body(body(rng, i));
        let parent = if i == 0 {
            GROUND.to_string()
        } else {
            rng.random_range(0..=i).checked_sub(1).map_or(GROUND.to_string(), |p| format!("b{p}"))
        };
        graph = graph.with_joint(joint(rng, format!("q{i}"), &parent, &format!("b{i}"), 0.3));
    }
    let graph = springs(rng, graph);
    let mechanism = GraphMechanism::new(graph.clone()).expect("a random tree is a mechanism");
    let state = random_state(rng, &mechanism);
    (graph, state)
}

/// A random single loop of `bodies ≥ 3` bodies: a chain from the ground (revolute joints, the
/// middle ones prismatic with probability 0.25) whose last body is pinned back to the ground,
/// the pin placed where the chain's random initial configuration puts it (so the loop closes
/// there), with springs; the closing pin is the last joint. Returns the graph and a consistent
/// state (its velocities projected onto the constraints).
///
/// # Panics
/// If `bodies < 3`, or when the random configuration cannot be assembled.
pub fn random_loop(rng: &mut Rng, bodies: usize) -> (JointGraph, State) {
    assert!(bodies >= 3, "a loop of revolute joints needs three moving bodies to move");
    let mut graph = JointGraph::new(format!("random loop of {bodies}"), 9.81);
    for i in 0..bodies {
        graph = graph.with_body(body(rng, i));
        let parent = if i == 0 { GROUND.to_string() } else { format!("b{}", i - 1) };
        let prismatic = if i == 0 || i + 1 == bodies { 0.0 } else { 0.25 };
        graph = graph.with_joint(joint(rng, format!("q{i}"), &parent, &format!("b{i}"), prismatic));
    }
    // The open chain's configuration decides where the closing pin sits on the ground.
    let open = GraphMechanism::new(graph.clone()).expect("an open chain is a mechanism");
    let state = random_state(rng, &open);
    let last = bodies - 1;
    let at = point(rng, 0.5);
    let pose = open.body_pose(last, 0.0, &state.q);
    let (s, c) = pose.angle.sin_cos();
    let anchor = [pose.x + c * at[0] - s * at[1], pose.y + s * at[0] + c * at[1]];
    let mut closing = GraphJoint::revolute("closure", format!("b{last}"), at, GROUND, anchor);
    closing.role = Role::Closing;
    let graph = springs(rng, graph.with_joint(closing));
    let model = lagrange::Model::new(GraphMechanism::new(graph.clone()).expect("a loop is a mechanism"))
        .expect("the loop's model");
    let mut held = vec![false; state.q.len()];
    held[0] = true;
    let state = lagrange::Dynamics::assemble(&model, &state, &held).expect("the loop closes where it was built");
    (graph, state)
}

/// The same graph with joint `closing` as the loop-closing joint and every other joint in the
/// tree: another spanning tree of the same mechanism.
pub fn with_closing(graph: &JointGraph, closing: &str) -> JointGraph {
    let mut graph = graph.clone();
    for joint in &mut graph.joints {
        joint.role = if joint.name == closing { Role::Closing } else { Role::Tree };
    }
    graph
}
