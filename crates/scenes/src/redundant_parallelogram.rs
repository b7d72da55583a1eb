//! A parallelogram four-bar with a third, parallel crank pinned to the middle of its coupler:
//! a joint graph whose loop constraints are redundant everywhere (beyond the lecture;
//! docs/scenes.md#redundant_parallelogram). Its motion is one pendulum, solved exactly in
//! Jacobi elliptic functions (`pendulum.rs`).

use crate::linkage::{LinkBody, Linkage, Point};
use crate::params::{GRAVITY, param_table, scene_params};
use crate::pendulum::ParallelBranch;
use crate::scene::{body_scene, delegate_mechanism};
use crate::{Conserved, Domain, SceneType};
use lagrange::State;
use lagrange::graph::{GROUND, GraphBody, GraphJoint, GraphMechanism, JointGraph};
use std::f64::consts::FRAC_PI_2;

/// Mass of each of the four links (kg).
const LINK_MASS: f64 = 1.0;

scene_params! {
    /// A parallelogram four-bar — crank (1 m) pivoted at `(0, 0)`, coupler (2 m) from its tip
    /// to the tip of the rocker (1 m) pivoted at `(2, 0)` — and a third crank (1 m) pivoted
    /// midway at `(1, 0)`, its tip pinned to the coupler's middle; uniform rods of 1 kg
    /// (inertia `m l²/12`). `q = (θ1, φ, θ2, θ3)`: the crank's absolute angle from +x, the
    /// coupler's angle relative to the crank, the rocker's and the third crank's absolute
    /// angles. The pins `B` (coupler end on the rocker) and `C` (coupler middle on the third
    /// crank) close the loops: 4 rows of rank 3, one redundant at every configuration (the
    /// coupler's middle already moves on the unit circle about `(1, 0)`), and one more in the
    /// flat position.
    ///
    /// The scene is the reduced model of its joint graph ([`GraphMechanism`]).
    pub struct RedundantParallelogram {
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
        /// Initial angular velocity of the cranks `ω0` (rad/s), counter-clockwise.
        pub crank_speed: f64 = ["ω0", "rad/s", 4.0, Domain::Finite, "initial angular velocity of the cranks"],
    }
    /// The parallelogram with a redundant third crank under gravity `g`, started with crank
    /// speed `ω0`.
    pub fn new;
    derived {
        mechanism: GraphMechanism = GraphMechanism::new(redundant_graph(gravity))?,
        linkage: Linkage = redundant_linkage(gravity),
        branch: ParallelBranch = ParallelBranch { cranks: vec![0, 2, 3], couplers: vec![1], omega_squared: 1.25 * gravity },
    }
}

/// Uniform rod of length `l`.
fn rod(name: &str, l: f64) -> GraphBody {
    GraphBody::rigid(name, LINK_MASS, LINK_MASS * l * l / 12.0)
}

/// The joint graph: the four-bar's pins (crank `θ1`, coupler `φ` on the crank's tip, rocker
/// `θ2`, then the pin `B` of the coupler's end on the rocker, which closes the first loop), then
/// the third crank `θ3` and its pin `C` on the coupler's middle, which closes the second.
fn redundant_graph(gravity: f64) -> JointGraph {
    JointGraph::new(RedundantParallelogram::ID, gravity)
        .with_body(rod("crank", 1.0))
        .with_body(rod("coupler", 2.0))
        .with_body(rod("rocker", 1.0))
        .with_body(rod("third crank", 1.0))
        .with_joint(GraphJoint::revolute("θ1", GROUND, [0.0, 0.0], "crank", [-0.5, 0.0]).absolute())
        .with_joint(GraphJoint::revolute("φ", "crank", [0.5, 0.0], "coupler", [-1.0, 0.0]))
        .with_joint(GraphJoint::revolute("θ2", GROUND, [2.0, 0.0], "rocker", [-0.5, 0.0]).absolute())
        .with_joint(GraphJoint::revolute("B", "coupler", [1.0, 0.0], "rocker", [0.5, 0.0]))
        .with_joint(GraphJoint::revolute("θ3", GROUND, [1.0, 0.0], "third crank", [-0.5, 0.0]).absolute())
        .with_joint(GraphJoint::revolute("C", "coupler", [0.0, 0.0], "third crank", [0.5, 0.0]))
}

/// The hand-coded linkage (for the energy and the residuals): centres `½ e(θ1)`,
/// `e(θ1) + e(θ1 + φ)`, `(2, 0) + ½ e(θ2)`, `(1, 0) + ½ e(θ3)`; loops
/// `e(θ1) + 2 e(θ1 + φ) − (2, 0) − e(θ2)` and `e(θ1) + e(θ1 + φ) − (1, 0) − e(θ3)`.
fn redundant_linkage(gravity: f64) -> Linkage {
    let (k1, k2, k3, coupler) =
        ([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 0.0, 0.0]);
    let body = |length: f64, centre: Point, angle: [f64; 4]| LinkBody {
        mass: LINK_MASS,
        inertia: LINK_MASS * length * length / 12.0,
        centre,
        angle: angle.to_vec(),
    };
    let tip = |x: f64| Point::at(x, 0.0).arm(&k1, [1.0, 0.0]);
    Linkage {
        bodies: vec![
            body(1.0, Point::at(0.0, 0.0).arm(&k1, [0.5, 0.0]), k1),
            body(2.0, tip(0.0).arm(&coupler, [1.0, 0.0]), coupler),
            body(1.0, Point::at(2.0, 0.0).arm(&k2, [0.5, 0.0]), k2),
            body(1.0, Point::at(1.0, 0.0).arm(&k3, [0.5, 0.0]), k3),
        ],
        gravity,
        loops: vec![
            tip(-2.0).arm(&coupler, [2.0, 0.0]).arm(&k2, [-1.0, 0.0]),
            tip(-1.0).arm(&coupler, [1.0, 0.0]).arm(&k3, [-1.0, 0.0]),
        ],
        torque: (vec![0.0; 4], 0.0),
        spring: None,
    }
}

impl RedundantParallelogram {
    /// The consistent state with every crank at `θ` turning at `θ̇`, the coupler horizontal
    /// (`φ = −θ`, `φ̇ = −θ̇`).
    pub fn state_at(&self, t: f64, theta: f64, rate: f64) -> State {
        State::new(t, [theta, -theta, theta, theta], [rate, -rate, rate, rate])
    }

    /// `ω² = 5g/4` of the pendulum `ψ̈ = −ω² sin ψ`, `ψ = θ + π/2`: on the branch
    /// `T = ½ I θ̇²` with `I = 3 · m l²/3 + m l² = 2` kg m² (three unit cranks about their
    /// pivots, the coupler translating on unit circles) and `V = m g sin θ (3 · ½ + 1)`.
    pub fn omega_squared(&self) -> f64 {
        self.branch.omega_squared
    }

    /// `T + V` from the rods' centres and angles.
    pub fn energy(&self, q: &[f64], qdot: &[f64]) -> f64 {
        self.linkage.energy(q, qdot)
    }

    /// The loop-closure residuals `Φ(q)` and their rates `G q̇` (hand-coded; pin `B`, then `C`).
    pub fn residuals(&self, q: &[f64], qdot: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.linkage.residuals(q, qdot)
    }
}

delegate_mechanism!(RedundantParallelogram, mechanism);

impl SceneType for RedundantParallelogram {
    const ID: &'static str = "redundant_parallelogram";
    const TITLE: &'static str = "Parallelogram with a redundant third crank";
    const REFERENCE: &'static str = "docs/scenes.md#redundant_parallelogram; beyond the lecture (loop constraints \
                                     redundant everywhere; the pendulum in Jacobi elliptic functions, Lawden, \
                                     Elliptic Functions and Applications, §5.2)";
    param_table!();

    /// On the parallelogram branch, `θ̈ = −ω² cos θ` for the three cranks and `−θ̈` for the
    /// coupler's relative angle. The linkage has no other branch it can move along (off it the
    /// third crank locks the four-bar), so elsewhere NaN.
    fn closed_form(&self, _t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
        if self.branch.contains(q, qdot) {
            self.branch.accelerations(q, qddot);
        } else {
            qddot.fill(f64::NAN);
        }
    }

    /// The cranks 0.5 rad counter-clockwise from hanging (`θ = −π/2 + 0.5`), turning at `ω0`
    /// (4 rad/s by default: a libration of amplitude `ψ_max = 2 asin(√(C/(4ω²)))` ≈ 1.34 rad
    /// with `C = ω0² + 4ω² sin²(0.25)`, 0.23 rad short of the flat position at ±π/2 from the
    /// bottom). Off the bottom, so that `q̈(0) ≠ 0`: from the bottom the first-order error of
    /// a symplectic Euler step (rapier's), which is proportional to `q̈(0)`, would vanish.
    fn default_state(&self) -> State {
        self.state_at(0.0, -FRAC_PI_2 + 0.5, self.crank_speed)
    }

    /// From a state on the parallelogram branch, the pendulum's exact motion; `None` off it.
    fn exact_solution(&self, initial: &State, t: f64) -> Option<State> {
        self.branch.exact(initial, t)
    }

    /// `E = T + V` ([`RedundantParallelogram::energy`]).
    fn conserves_energy(&self) -> Vec<Conserved> {
        vec![Conserved::energy(self, |s, q, qdot| s.energy(q, qdot))]
    }

    body_scene!(engine);

    /// The scene's own graph ([`GraphMechanism::graph`]).
    fn joint_graph(&self) -> Option<JointGraph> {
        Some(self.mechanism.graph().clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{ENGINE_VS_CLOSED_FORM, assert_close, assert_exact_solution_consistent, max_abs};
    use lagrange::{Mechanism, Method, Model, Output, Tolerances, accelerations};
    use lagrange_testing::max_abs_diff;

    fn scene(speed: f64) -> RedundantParallelogram {
        RedundantParallelogram::new(9.81, speed).unwrap()
    }

    /// Crank angles on the branch away from the flat position, with rates (the default state
    /// first).
    const AWAY_FROM_FLAT: [(f64, f64); 6] =
        [(-FRAC_PI_2 + 0.5, 4.0), (-FRAC_PI_2, 4.0), (-1.0, -3.0), (2.5, 0.5), (-2.8, 6.0), (1.2, 0.0)];

    /// Two pins close the loops; of their 4 rows the rank is 3 at every configuration of the
    /// branch (one redundant), 2 in the flat position.
    #[test]
    fn one_loop_row_is_redundant_everywhere() {
        let s = scene(4.0);
        let joints = &s.mechanism.graph().joints;
        let closing: Vec<&str> =
            (0..joints.len()).filter(|&j| !s.mechanism.in_tree(j)).map(|j| joints[j].name.as_str()).collect();
        assert_eq!(closing, ["B", "C"]);
        assert_eq!(s.description().constraints.len(), 4);
        for (theta, _) in AWAY_FROM_FLAT {
            let q = s.state_at(0.0, theta, 0.0).q;
            assert_eq!(s.mechanism.degrees_of_freedom(0.0, &q), 1, "θ = {theta}: n − rank G = 4 − 3");
        }
        // Flat (θ = 0): the loops' x rows vanish. (At θ = π they are round-off, sin π ≈ 1e-16,
        // which a rank test relative to each row's own size cannot tell from a row.)
        let q = s.state_at(0.0, 0.0, 0.0).q;
        assert_eq!(s.mechanism.degrees_of_freedom(0.0, &q), 2, "flat: rank G = 2");
    }

    /// The branch's states satisfy the loops to round-off (8 ε of the lengths, 8 ε of the rate).
    #[test]
    fn states_on_the_branch_are_consistent() {
        let s = scene(4.0);
        for (theta, rate) in AWAY_FROM_FLAT {
            let state = s.state_at(0.0, theta, rate);
            let (phi, rates) = s.residuals(&state.q, &state.qdot);
            assert!(max_abs(&phi) <= 8.0 * f64::EPSILON, "θ = {theta}: Φ = {phi:?}");
            assert!(max_abs(&rates) <= 8.0 * f64::EPSILON * rate.abs(), "θ = {theta}: {rates:?}");
        }
    }

    /// The engine resolves the redundant row and agrees with the pendulum on the branch away
    /// from the flat position, to [`ENGINE_VS_CLOSED_FORM`] relative: 4 coordinates, a Schur
    /// complement whose independent rows are well conditioned there (measured differences
    /// ≤ 4e-15).
    #[test]
    fn engine_matches_the_pendulum_on_the_branch() {
        for gravity in [9.81, 1.6] {
            let s = RedundantParallelogram::new(gravity, 4.0).unwrap();
            let model = Model::new(s.clone()).unwrap();
            let mut ws = model.workspace();
            for (theta, rate) in AWAY_FROM_FLAT {
                let state = s.state_at(0.0, theta, rate);
                let engine = accelerations(&model, &mut ws, 0.0, &state.q, &state.qdot).unwrap().to_vec();
                let mut closed = [0.0; 4];
                s.closed_form(0.0, &state.q, &state.qdot, &mut closed);
                // By hand: θ̈ = −(5g/4) cos θ.
                let alpha = -1.25 * gravity * theta.cos();
                assert_eq!(closed, [alpha, -alpha, alpha, alpha]);
                let bound = ENGINE_VS_CLOSED_FORM * max_abs(&closed).max(1.0);
                assert_close(&format!("g = {gravity}, θ = {theta}"), &closed, &engine, bound);
            }
        }
    }

    /// Off the branch there is no closed form (and no motion): NaN.
    #[test]
    fn off_the_branch_the_closed_form_is_nan() {
        let s = scene(4.0);
        let mut closed = [0.0; 4];
        s.closed_form(0.0, &[0.3, -0.3, 0.3, 0.5], &[0.0; 4], &mut closed);
        assert!(closed.iter().all(|a| a.is_nan()), "{closed:?}");
        assert!(s.exact_solution(&State::new(0.0, [0.3, -0.3, 0.3, 0.5], [0.0; 4]), 1.0).is_none());
    }

    /// The exact solution starts at the initial state and its derivatives are `q̇` and the
    /// closed-form `q̈` ([`assert_exact_solution_consistent`]): the default libration, and a
    /// rotation through the flat position (`ω0 = 9 rad/s`: `C` ≈ 84 > `4ω²` ≈ 49).
    #[test]
    fn exact_solution_is_consistent_with_the_closed_form() {
        let scene = scene_of::<RedundantParallelogram>();
        for speed in [4.0, 9.0] {
            let mut params = scene.default_params();
            params.set("ω0", speed).unwrap();
            let initial = scene.default_state(&params).unwrap();
            assert_exact_solution_consistent(scene, &params, &initial, &[0.05, 0.4, 1.3, 2.9]);
        }
    }

    /// The default libration never reaches the flat position: Dop853 at `tol = 1e-12` follows
    /// the exact solution over 3 s to 1e-9 (the integrator's global error at this tolerance,
    /// see `parallelogram_chain`), the redundant row resolved at every stage.
    #[test]
    fn engine_follows_the_exact_solution() {
        let s = scene(4.0);
        let initial = s.default_state();
        let model = Model::new(s.clone()).unwrap();
        let method = Method::Dop853 { tol: Tolerances::uniform(1e-12) };
        let run = lagrange::simulate(&model, &initial, 3.0, method, &Output::Every(0.1)).unwrap();
        let mut worst: f64 = 0.0;
        for k in 0..run.len() {
            let exact = s.exact_solution(&initial, run.t[k]).unwrap();
            worst = worst.max(max_abs_diff(&exact.q, run.q(k))).max(max_abs_diff(&exact.qdot, run.qdot(k)));
        }
        eprintln!("redundant_parallelogram: engine vs exact over 3 s, worst {worst:e}");
        assert!(worst <= 1e-9, "{worst:e}");
    }

    /// Turning over, the linkage passes the flat position, where a second row drops out.
    // needs the singular-configuration solver
    #[test]
    #[ignore = "needs the singular-configuration solver"]
    fn engine_follows_the_exact_solution_through_the_flat_position() {
        let s = scene(9.0);
        let initial = s.default_state();
        let model = Model::new(s.clone()).unwrap();
        let method = Method::Dop853 { tol: Tolerances::uniform(1e-12) };
        let run = lagrange::simulate(&model, &initial, 3.0, method, &Output::Every(0.05)).unwrap();
        let mut worst: f64 = 0.0;
        for k in 0..run.len() {
            let exact = s.exact_solution(&initial, run.t[k]).unwrap();
            worst = worst.max(max_abs_diff(&exact.q, run.q(k))).max(max_abs_diff(&exact.qdot, run.qdot(k)));
        }
        // The estimate of the libration test, over ~4 turns: 1e-8.
        assert!(worst <= 1e-8, "engine vs exact through the flat position, worst {worst:e}");
    }
}
