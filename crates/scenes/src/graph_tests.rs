//! Every scene that is a joint graph: the graph's reduced model (`lagrange::graph`) against the
//! scene's own, hand-written one.

use crate::testing::{ENGINE_VS_CLOSED_FORM, assert_close, max_abs};
use crate::{Params, Scene, SceneType, all};
use lagrange::graph::GraphMechanism;
use lagrange::{Dynamics, Model, State};

/// Parameter changes that switch on what the defaults leave off (a torque, damping, a compound
/// bob), per scene.
const CHANGES: &[(&str, &str, f64)] = &[
    ("cart_pendulum", "bob_inertia", 0.05),
    ("double_pendulum", "inertia_2", 0.03),
    ("harmonic_oscillator", "damping", 0.4),
    ("four_bar", "torque", 1.5),
    ("slider_crank", "torque", -2.0),
    ("atwood", "pulley_inertia", 0.0),
    ("double_atwood", "lower_pulley_mass", 0.5),
    ("double_double_atwood", "pulley_a_mass", 0.3),
];

/// States around the default one: the default, then shifted coordinates and velocities (brought
/// onto the constraints with the first coordinate held, for the loops).
fn states(model: &Model<GraphMechanism>, default: &State) -> Vec<State> {
    let mut states = vec![default.clone()];
    for (k, shift) in [0.13, -0.29, 0.41].into_iter().enumerate() {
        let q: Vec<f64> = default.q.iter().enumerate().map(|(i, q)| q + shift * (1.0 + 0.3 * i as f64)).collect();
        let qdot: Vec<f64> = default.qdot.iter().enumerate().map(|(i, v)| v + shift * (0.7 - 0.2 * i as f64)).collect();
        let approximate = State::new(default.t + 0.1 * k as f64, q, qdot);
        let mut held = vec![false; default.q.len()];
        held[0] = true;
        states.push(model.assemble(&approximate, &held).expect("assembles near the default state"));
    }
    states
}

fn check(scene: &dyn Scene, params: &Params) -> usize {
    let Some(graph) = scene.joint_graph(params).unwrap() else { return 0 };
    let model = Model::new(GraphMechanism::new(graph).unwrap()).unwrap();
    let mut system = scene.build(params).unwrap();
    assert_eq!(model.coordinates(), &scene.coordinates(params).unwrap()[..], "{}: coordinates", scene.id());
    let mut ws = Dynamics::workspace(&model);
    let default = scene.default_state(params).unwrap();
    for state in states(&model, &default) {
        let expected = system.accelerations(state.t, &state.q, &state.qdot).unwrap().to_vec();
        let mut got = vec![0.0; expected.len()];
        Dynamics::accelerations(&model, &mut ws, state.t, &state.q, &state.qdot, &mut got).unwrap();
        // Two exact formulas for the same q̈ (as for the closed forms): round-off only.
        let what = format!("{}: graph q̈ vs the scene's at {state:?}", scene.id());
        assert_close(&what, &expected, &got, ENGINE_VS_CLOSED_FORM * max_abs(&expected).max(1.0));
    }
    1
}

/// The graph's reduced model has the scene's coordinates and its `q̈` at the defaults and with
/// each change in [`CHANGES`].
#[test]
fn joint_graph_reduced_models_equal_the_hand_written_ones() {
    let mut checked = Vec::new();
    for scene in all() {
        let mut params = scene.default_params();
        if check(*scene, &params) == 1 {
            checked.push(scene.id());
        }
        for &(_, name, value) in CHANGES.iter().filter(|(id, ..)| *id == scene.id()) {
            params.set(name, value).unwrap();
            check(*scene, &params);
        }
    }
    assert_eq!(
        checked,
        [
            "cart_pendulum",
            "harmonic_oscillator",
            "atwood",
            "double_atwood",
            "double_double_atwood",
            "wedge",
            "double_pendulum",
            "chain",
            "four_bar",
            "slider_crank",
            "andrews_squeezer",
            "parallelogram_chain",
            "change_point_four_bar",
            "redundant_parallelogram"
        ]
    );
}

/// The scenes that keep their own maximal builds have joint-graph twins all the same: the
/// elastic pendulum and the isotropic oscillator as a massless arm turning at the origin with the
/// mass sliding along it on a spring, the driven pendulum as a massless support on a driven
/// slide. Their reduced models
/// equal the scenes' to round-off (the scenes keep hand-written builds for rapier's sake,
/// docs/graphs.md#scenes-that-are-graphs).
#[test]
fn joint_graph_twins_of_the_other_pendulums_equal_them() {
    use lagrange::graph::{ForceElement, GROUND, GraphBody, GraphJoint, JointGraph, Point, Profile};
    let spring =
        crate::SpringPendulum::from_params(&crate::scene_of::<crate::SpringPendulum>().default_params()).unwrap();
    let spring_twin = JointGraph::new("spring twin", spring.gravity)
        .with_body(GraphBody::rigid("arm", 0.0, 0.0))
        .with_body(GraphBody::point("bob", spring.mass))
        .with_joint(GraphJoint::prismatic("r", "arm", [0.0, 0.0], "bob", [0.0, 0.0], [0.0, -1.0]))
        .with_joint(GraphJoint::revolute("θ", GROUND, [0.0, 0.0], "arm", [0.0, 0.0]).absolute())
        .with_force(ForceElement::Spring {
            a: Point::world([0.0, 0.0]),
            b: Point::on("bob", [0.0, 0.0]),
            stiffness: spring.stiffness,
            rest_length: spring.rest_length,
        });
    let driven =
        crate::DrivenPendulum::from_params(&crate::scene_of::<crate::DrivenPendulum>().default_params()).unwrap();
    let driven_twin = JointGraph::new("driven twin", driven.gravity)
        .with_body(GraphBody::rigid("support", 0.0, 0.0))
        .with_body(GraphBody::point("bob", driven.mass))
        .with_joint(
            GraphJoint::prismatic("s", GROUND, [0.0, 0.0], "support", [0.0, 0.0], [1.0, 0.0])
                .driven(Profile::harmonic(driven.amplitude, driven.drive_frequency)),
        )
        .with_joint(GraphJoint::revolute("θ", "support", [0.0, 0.0], "bob", [0.0, driven.length]).absolute());
    // The isotropic oscillator, `V = ½ k r²`: a spring of natural length 0 from the origin to
    // the particle sliding along an arm that turns at the origin (θ from the x axis).
    let isotropic =
        crate::IsotropicOscillator::from_params(&crate::scene_of::<crate::IsotropicOscillator>().default_params())
            .unwrap();
    let isotropic_twin = JointGraph::new("isotropic twin", 0.0)
        .with_body(GraphBody::rigid("arm", 0.0, 0.0))
        .with_body(GraphBody::point("particle", isotropic.mass))
        .with_joint(GraphJoint::prismatic("r", "arm", [0.0, 0.0], "particle", [0.0, 0.0], [1.0, 0.0]))
        .with_joint(GraphJoint::revolute("θ", GROUND, [0.0, 0.0], "arm", [0.0, 0.0]))
        .with_force(ForceElement::Spring {
            a: Point::world([0.0, 0.0]),
            b: Point::on("particle", [0.0, 0.0]),
            stiffness: isotropic.stiffness,
            rest_length: 0.0,
        });
    for (id, twin) in
        [("spring_pendulum", spring_twin), ("driven_pendulum", driven_twin), ("isotropic_oscillator", isotropic_twin)]
    {
        let scene = crate::find(id).unwrap();
        let params = scene.default_params();
        let model = Model::new(GraphMechanism::new(twin).unwrap()).unwrap();
        assert_eq!(model.coordinates(), &scene.coordinates(&params).unwrap()[..], "{id}: coordinates");
        let mut system = scene.build(&params).unwrap();
        let mut ws = Dynamics::workspace(&model);
        for state in states(&model, &scene.default_state(&params).unwrap()) {
            let expected = system.accelerations(state.t, &state.q, &state.qdot).unwrap().to_vec();
            let mut got = vec![0.0; expected.len()];
            Dynamics::accelerations(&model, &mut ws, state.t, &state.q, &state.qdot, &mut got).unwrap();
            let what = format!("{id}: twin q̈ vs the scene's at {state:?}");
            assert_close(&what, &expected, &got, ENGINE_VS_CLOSED_FORM * max_abs(&expected).max(1.0));
        }
    }
}
