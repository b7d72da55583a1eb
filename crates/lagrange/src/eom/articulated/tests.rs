//! The articulated-body algorithm against the generic assembly on the same mechanisms.

use crate::test_support::{Range, Rng, RodChain, rng};
use crate::tree::{Joint, Parent};
use crate::{Body, Description, Error, Mechanism, Model, Pose, Scalar, Tree, accelerations, mass_matrix};
use lagrange_testing::{condition_number, max_abs};
use num_dual::Dual64;

/// Condition number of the symmetric positive definite `M` (n × n, row-major).
/// `(q̈ from the tree path, q̈ from the generic path, κ(M))` at `(t, q, q̇)`.
fn both_paths<M: Mechanism + Clone>(mechanism: &M, t: f64, q: &[f64], qdot: &[f64]) -> (Vec<f64>, Vec<f64>, f64) {
    let tree = Model::new(mechanism.clone()).expect("valid");
    let generic = Model::new_generic(mechanism.clone()).expect("valid");
    assert!(tree.uses_tree_path() && !generic.uses_tree_path());
    let (mut wt, mut wg) = (tree.workspace(), generic.workspace());
    let fast = accelerations(&tree, &mut wt, t, q, qdot).expect("valid").to_vec();
    let reference = accelerations(&generic, &mut wg, t, q, qdot).expect("valid").to_vec();
    let kappa = condition_number(q.len(), mass_matrix(&generic, &mut wg, t, q, qdot).expect("valid"));
    (fast, reference, kappa)
}

/// Both paths solve `M q̈ = f` with backward-stable eliminations of a matrix assembled to a few
/// ulps, so each carries a relative error (max-norm) up to `c · ε · κ(M)`; `c = 64` is
/// `tests/src/tolerance.rs`'s `conditioned` (assembly errors of ≈ 32 ε in `M` and `f`), never
/// below 1e-12 (≈ 4500 ε of plain round-off). The observed worst case is reported below.
fn tolerance(kappa: f64) -> f64 {
    1e-12_f64.max(64.0 * f64::EPSILON * kappa)
}

fn assert_agree(what: &str, fast: &[f64], reference: &[f64], kappa: f64) -> f64 {
    let scale = max_abs(reference).max(1e-300);
    let error = fast.iter().zip(reference).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / scale;
    assert!(
        error <= tolerance(kappa),
        "{what}: relative error {error:e} > {:e} (κ = {kappa:e})\n tree    {fast:?}\n generic {reference:?}",
        tolerance(kappa)
    );
    error
}

/// Rod masses log-uniform over six decades, the first two pinned at the ends so that every
/// chain of two or more links spans exactly 1e6; lengths in [0.5, 1.5).
fn random_chain(n: usize, rng: &mut Rng) -> RodChain {
    let masses: Vec<f64> = (0..n)
        .map(|i| match i {
            0 => 1e-3,
            1 => 1e3,
            _ => 10f64.powf(rng.range(-3.0, 3.0)),
        })
        .collect();
    let lengths: Vec<f64> = (0..n).map(|_| rng.range(0.5, 1.5)).collect();
    RodChain::new(&masses, &lengths, 9.81)
}

fn random_state(n: usize, rng: &mut Rng) -> (Vec<f64>, Vec<f64>) {
    let q = (0..n).map(|_| rng.range(-std::f64::consts::PI, std::f64::consts::PI)).collect();
    let qdot = (0..n).map(|_| rng.range(-3.0, 3.0)).collect();
    (q, qdot)
}

#[test]
fn chains_match_the_generic_path_with_masses_spanning_six_decades() {
    let mut rng = rng(0xABA0_0001);
    for n in [1, 2, 4, 8, 16, 32, 64] {
        let (mut worst, mut worst_kappa) = (0.0_f64, 0.0_f64);
        for trial in 0..4 {
            let chain = random_chain(n, &mut rng);
            for _ in 0..3 {
                let (q, qdot) = random_state(n, &mut rng);
                let (fast, reference, kappa) = both_paths(&chain, 0.0, &q, &qdot);
                let error = assert_agree(&format!("N = {n}, chain {trial}"), &fast, &reference, kappa);
                worst = worst.max(error);
                worst_kappa = worst_kappa.max(kappa);
            }
        }
        println!("N = {n:2}: worst relative difference {worst:.1e}, largest κ(M) {worst_kappa:.1e}");
    }
}

/// Equal rods (the chain scene's case): well conditioned, so plain round-off.
#[test]
fn uniform_chains_match_the_generic_path_to_round_off() {
    let mut rng = rng(0xABA0_0002);
    for n in [1, 2, 4, 8, 16, 32, 64] {
        let chain = RodChain::new(&vec![1.0; n], &vec![1.0; n], 9.81);
        let (mut worst, mut worst_kappa) = (0.0_f64, 0.0_f64);
        for _ in 0..3 {
            let (q, qdot) = random_state(n, &mut rng);
            let (fast, reference, kappa) = both_paths(&chain, 0.0, &q, &qdot);
            worst = worst.max(assert_agree(&format!("uniform N = {n}"), &fast, &reference, kappa));
            worst_kappa = worst_kappa.max(kappa);
        }
        println!("uniform N = {n:2}: worst relative difference {worst:.1e}, largest κ(M) {worst_kappa:.1e}");
    }
}

/// A branched tree of every joint kind, poses written by hand: a trolley sliding along a
/// tilted rail (prismatic), an arm on it (relative revolute) carrying a sliding hand
/// (prismatic) with a bob (absolute revolute), and a pendulum on the trolley (absolute
/// revolute); a torsion spring on the arm, a spring pulling the bob to a fixed point, damping
/// on every coordinate and a drive torque on the pendulum.
#[derive(Clone, Debug)]
struct Crane {
    description: Description,
    tree: Tree,
    rail: [f64; 2],
}

impl Crane {
    fn new() -> Self {
        let rail = [0.3_f64.cos(), 0.3_f64.sin()];
        let bodies = vec![
            Body::rigid("trolley", 2.0, 0.1),
            Body::rigid("arm", 0.7, 0.05),
            Body::rigid("pendulum", 1.3, 0.02),
            Body::rigid("hand", 0.4, 0.01),
            Body::point("bob", 0.9),
        ];
        let joints = vec![
            Joint::prismatic("x", Parent::Ground, [0.2, 0.1], rail, [0.05, -0.1]),
            Joint::revolute("α", Parent::Body(0), [0.3, -0.2], [-0.4, 0.1]),
            Joint::absolute_revolute("β", Parent::Body(0), [-0.25, 0.0], [0.0, 0.8]),
            Joint::prismatic("s", Parent::Body(1), [0.4, 0.0], [1.0, 0.0], [0.0, 0.0]),
            Joint::absolute_revolute("γ", Parent::Body(3), [0.1, 0.0], [0.02, 0.5]),
        ];
        let coordinates = joints.iter().map(|j| j.coordinate.clone()).collect();
        let tree = Tree::new(joints, bodies.clone(), 9.81).expect("valid tree");
        Self { description: Description { coordinates, bodies, gravity: 9.81, ..Description::default() }, tree, rail }
    }
}

/// `R(φ) (x, y)`.
fn rotate<S: Scalar>(angle: S, x: f64, y: f64) -> (S, S) {
    let (sin, cos) = angle.sin_cos();
    (cos * x - sin * y, sin * x + cos * y)
}

impl Mechanism for Crane {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        // Trolley: anchor + x rail − child anchor, never turning.
        let (tx, ty) = (q[0] * self.rail[0] + (0.2 - 0.05), q[0] * self.rail[1] + (0.1 + 0.1));
        p[0] = Pose::new(tx, ty, S::zero());
        // Arm: pivot on the trolley, turned by α relative to it (the trolley's angle is 0).
        let (ox, oy) = rotate(q[1], -0.4, 0.1);
        let (ax, ay) = (tx + 0.3 - ox, ty - 0.2 - oy);
        p[1] = Pose::new(ax, ay, q[1]);
        // Pendulum: pivot on the trolley, absolute angle β.
        let (ox, oy) = rotate(q[2], 0.0, 0.8);
        p[2] = Pose::new(tx - 0.25 - ox, ty - oy, q[2]);
        // Hand: slides along the arm's x axis from (0.4, 0) in the arm frame.
        let (ox, oy) = rotate(q[1], 1.0, 0.0);
        let (hx, hy) = (ax + ox * (q[3] + 0.4), ay + oy * (q[3] + 0.4));
        p[3] = Pose::new(hx, hy, q[1]);
        // Bob: pivot at (0.1, 0) in the hand frame, absolute angle γ.
        let (px, py) = rotate(q[1], 0.1, 0.0);
        let (ox, oy) = rotate(q[4], 0.02, 0.5);
        p[4] = Pose::new(hx + px - ox, hy + py - oy, q[4]);
    }
    fn potential<S: Scalar>(&self, _t: S, q: &[S], p: &[Pose<S>]) -> Option<S> {
        let twist = q[1] - 0.2;
        let (dx, dy) = (p[4].x - 1.0, p[4].y + 1.0);
        Some(twist * twist * 1.5 + (dx * dx + dy * dy) * 4.0)
    }
    fn generalized_force<S: Scalar>(&self, t: S, _q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        for (f, v) in force.iter_mut().zip(qdot) {
            *f -= *v * 0.3;
        }
        force[2] += t.sin() * 0.8;
        true
    }
    fn tree(&self) -> Option<&Tree> {
        Some(&self.tree)
    }
}

#[test]
fn a_branched_tree_with_every_joint_kind_a_potential_and_forces_matches_the_generic_path() {
    let crane = Crane::new();
    let mut rng = rng(0xABA0_0003);
    for _ in 0..20 {
        let (mut q, qdot) = random_state(5, &mut rng);
        q[0] = rng.range(-2.0, 2.0);
        q[3] = rng.range(-0.3, 0.6);
        let t = rng.range(0.0, 10.0);
        let (fast, reference, kappa) = both_paths(&crane, t, &q, &qdot);
        assert_agree("crane", &fast, &reference, kappa);
    }
    // The tree alone (no potential, no forces) as a mechanism of its own.
    let (q, qdot) = random_state(5, &mut rng);
    let (fast, reference, kappa) = both_paths(&crane.tree, 0.0, &q, &qdot);
    assert_agree("crane's tree", &fast, &reference, kappa);
}

fn check_derivative<M: Mechanism + Clone>(what: &str, mechanism: &M, rng: &mut Rng) {
    let n = mechanism.description().coordinates.len();
    let (fast, generic) = (Model::new(mechanism.clone()).unwrap(), Model::new_generic(mechanism.clone()).unwrap());
    let (mut wt, mut wg) = (fast.workspace_in::<Dual64>(), generic.workspace_in::<Dual64>());
    let (q, qdot) = random_state(n, rng);
    let (dq, dv) = random_state(n, rng);
    let seed = |x: &[f64], d: &[f64]| x.iter().zip(d).map(|(a, b)| Dual64::new(*a, *b)).collect::<Vec<_>>();
    let (q, qdot, t) = (seed(&q, &dq), seed(&qdot, &dv), Dual64::new(0.7, 1.0));
    let a = accelerations(&fast, &mut wt, t, &q, &qdot).expect("valid").to_vec();
    let b = accelerations(&generic, &mut wg, t, &q, &qdot).expect("valid").to_vec();
    let (re_a, re_b): (Vec<f64>, Vec<f64>) = (a.iter().map(|d| d.re).collect(), b.iter().map(|d| d.re).collect());
    let (eps_a, eps_b): (Vec<f64>, Vec<f64>) = (a.iter().map(|d| d.eps).collect(), b.iter().map(|d| d.eps).collect());
    let mut wf = generic.workspace();
    let q_re: Vec<f64> = q.iter().map(|d| d.re).collect();
    let qdot_re: Vec<f64> = qdot.iter().map(|d| d.re).collect();
    let kappa = condition_number(n, mass_matrix(&generic, &mut wf, 0.7, &q_re, &qdot_re).expect("valid"));
    assert_agree(&format!("{what}: q̈"), &re_a, &re_b, kappa);
    // The derivative solves M δq̈ = δf − δM q̈: the same conditioning, one more product.
    assert_agree(&format!("{what}: δq̈"), &eps_a, &eps_b, 2.0 * kappa);
}

/// `q̈` in dual numbers: value and derivative along a random direction of `(q, q̇)` agree with
/// the generic path's (the tree path is differentiable like the rest of the engine).
#[test]
fn the_tree_path_is_differentiable_like_the_generic_path() {
    let mut rng = rng(0xABA0_0004);
    let chain = random_chain(8, &mut rng);
    check_derivative("chain of 8", &chain, &mut rng);
    check_derivative("crane", &Crane::new(), &mut rng);
}

/// The reaction forces run the pose passes after the tree path's `q̈`.
#[test]
fn reaction_forces_on_the_tree_path_match_the_generic_path() {
    let crane = Crane::new();
    let (tree, generic) = (Model::new(crane.clone()).unwrap(), Model::new_generic(crane).unwrap());
    let (mut wt, mut wg) = (tree.workspace(), generic.workspace());
    let (q, qdot) = random_state(5, &mut rng(0xABA0_0005));
    let a = crate::reaction_forces(&tree, &mut wt, 0.3, &q, &qdot).unwrap().to_vec();
    let b = crate::reaction_forces(&generic, &mut wg, 0.3, &q, &qdot).unwrap().to_vec();
    let kappa = condition_number(5, mass_matrix(&generic, &mut wg, 0.3, &q, &qdot).unwrap());
    assert_agree("reactions", &a, &b, kappa);
}

/// A rod turning about its own centre with no inertia moves no mass: a typed error naming the
/// coordinate, as on the generic path.
#[test]
fn a_joint_that_moves_no_mass_is_a_singular_mass_matrix_error() {
    let tree = Tree::new(
        vec![
            Joint::absolute_revolute("θ", Parent::Ground, [0.0, 0.0], [0.0, 1.0]),
            Joint::revolute("φ", Parent::Body(0), [0.0, -1.0], [0.0, 0.0]),
        ],
        vec![Body::rigid("rod", 1.0, 0.1), Body::point("dot", 2.0)],
        9.81,
    )
    .unwrap();
    let model = Model::new(tree).unwrap();
    let mut ws = model.workspace();
    match accelerations(&model, &mut ws, 0.0, &[0.3, 0.1], &[0.2, 0.0]) {
        Err(Error::SingularMassMatrix { coordinate, .. }) => assert_eq!(coordinate, "φ"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_constructor_validates_the_tree() {
    let body = || Body::point("b", 1.0);
    let pendulum = |parent| Joint::revolute("θ", parent, [0.0, 0.0], [0.0, 1.0]);
    let cases = [
        (Tree::new(vec![pendulum(Parent::Body(0))], vec![body()], 9.81), "parent of joint `θ` (body 0)"),
        (
            Tree::new(vec![pendulum(Parent::Ground), pendulum(Parent::Body(1))], vec![body(), body()], 9.81),
            "parent of joint `θ` (body 1)",
        ),
        (
            Tree::new(vec![Joint::prismatic("x", Parent::Ground, [0.0; 2], [1.0, 1.0], [0.0; 2])], vec![body()], 9.81),
            "axis of joint `x`",
        ),
        (
            Tree::new(vec![Joint::revolute("θ", Parent::Ground, [f64::NAN, 0.0], [0.0; 2])], vec![body()], 9.81),
            "parent_anchor of joint `θ`",
        ),
        (Tree::new(vec![pendulum(Parent::Ground)], vec![Body::point("b", -1.0)], 9.81), "mass of b"),
        (Tree::new(vec![], vec![], 9.81), "bodies"),
        (Tree::new(vec![pendulum(Parent::Ground)], vec![body()], f64::INFINITY), "g"),
    ];
    for (result, expected) in cases {
        assert!(
            matches!(result, Err(Error::InvalidParameter { ref name, .. }) if name == expected),
            "expected `{expected}` rejected, got {result:?}"
        );
    }
    let mismatch = Tree::new(vec![pendulum(Parent::Ground)], vec![body(), body()], 9.81);
    assert!(matches!(mismatch, Err(Error::DimensionMismatch { expected: 2, got: 1, .. })), "{mismatch:?}");
}

/// A mechanism whose declared tree contradicts its poses, bodies or gravity is rejected.
#[test]
fn a_declared_tree_that_contradicts_the_mechanism_is_rejected() {
    let chain = RodChain::new(&[1.0, 2.0], &[1.0, 0.5], 9.81);
    let mut wrong_anchor = chain.clone();
    let mut joints = chain.tree.joints().to_vec();
    joints[1].parent_anchor = [0.0, -0.4];
    wrong_anchor.tree = Tree::new(joints.clone(), chain.description.bodies.clone(), 9.81).unwrap();
    let mut relative = chain.clone();
    joints[1] = Joint::revolute("θ1", Parent::Body(0), [0.0, -0.5], [0.0, 0.25]);
    relative.tree = Tree::new(joints, chain.description.bodies.clone(), 9.81).unwrap();
    let mut heavier = chain.clone();
    heavier.description.bodies[1].mass = 3.0;
    let mut weaker = chain.clone();
    weaker.description.gravity = 1.0;
    // The message names the body whose pose differs, and the component.
    let error = Model::new(wrong_anchor.clone()).unwrap_err().to_string();
    let name = &chain.description.bodies[1].name;
    assert!(error.contains(&format!("pose of body `{name}` differs in ")), "{error}");
    assert!(["in x:", "in y:", "in angle:"].iter().any(|c| error.contains(c)), "{error}");
    for (what, mechanism) in [("anchor", wrong_anchor), ("relative angle", relative), ("mass", heavier), ("g", weaker)]
    {
        let result = Model::new(mechanism.clone());
        assert!(matches!(result, Err(Error::Inconsistent { .. })), "{what}: {result:?}");
        // The generic path does not look at the tree.
        assert!(Model::new_generic(mechanism).is_ok(), "{what}");
    }
}

/// A constant mass matrix takes precedence over a declared tree.
#[test]
fn a_constant_mass_matrix_takes_precedence_over_the_tree() {
    #[derive(Clone)]
    struct Slider(Tree, Description);
    impl Mechanism for Slider {
        fn description(&self) -> &Description {
            &self.1
        }
        fn poses<S: Scalar>(&self, t: S, q: &[S], p: &mut [Pose<S>]) {
            self.0.poses(t, q, p)
        }
        fn tree(&self) -> Option<&Tree> {
            Some(&self.0)
        }
    }
    let axis = [0.6, -0.8];
    let tree = Tree::new(
        vec![
            Joint::prismatic("x", Parent::Ground, [0.0; 2], [1.0, 0.0], [0.0; 2]),
            Joint::prismatic("s", Parent::Body(0), [0.0; 2], axis, [0.0; 2]),
        ],
        vec![Body::point("block", 2.0), Body::point("slider", 1.0)],
        9.81,
    )
    .unwrap();
    let description = tree.description().clone().with_constant_mass_matrix();
    let constant = Model::new(Slider(tree.clone(), description)).unwrap();
    assert!(constant.has_constant_mass_matrix() && !constant.uses_tree_path());
    let (fast, reference, kappa) = both_paths(&tree, 0.0, &[0.1, 0.2], &[0.3, -0.1]);
    assert_agree("slider", &fast, &reference, kappa);
}

mod clockwise;
