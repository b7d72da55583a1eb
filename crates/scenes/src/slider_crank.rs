//! Slider-crank mechanism with a flywheel in `(φ, ψ, x)` with two loop-closure constraints
//! (beyond the lecture; docs/scenes.md#slider_crank), and the same mechanism in its crank angle
//! alone ([`SliderCrankCrank`]), `ψ = asin(−r sin φ / l)`.

use crate::linkage::{LinkBody, Linkage, Point};
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, Invariant, SceneType};
use lagrange::graph::{ForceElement, GROUND, GraphJoint, JointGraph, Profile};
use lagrange::{Body, Coordinate, Description, Error, Loads, Mechanism, Pose, Scalar, State};

scene_params! {
    /// A slider-crank: crank pivoted at the origin, length `r`, a uniform rod of mass `m_c`
    /// with a massless flywheel of inertia `J` about the pivot (centre of mass at `r/2`,
    /// inertia `m_c r²/12 + J` about it); connecting rod of length `l` (uniform, mass `m_r`)
    /// from the crank pin `P = r e(φ)` to the slider, a point mass `m_s` at `(x, 0)` on the
    /// x axis. `q = (φ, ψ, x)`: crank angle, connecting-rod angle (absolute, from +x), slider
    /// position, tied by `r cos φ + l cos ψ − x = 0`, `r sin φ + l sin ψ = 0`. Gravity along −y
    /// and an optional constant torque `τ` on the crank.
    pub struct SliderCrank {
        /// Crank length `r` (m).
        pub crank: f64 = ["r", "m", 0.1, Domain::Positive, "crank length"],
        /// Connecting-rod length `l` (m), longer than the crank.
        pub rod: f64 = ["l", "m", 0.4, Domain::Positive, "connecting-rod length (l > r)"],
        /// Crank mass `m_c` (kg).
        pub crank_mass: f64 = ["m_c", "kg", 0.5, Domain::Positive, "mass of the crank (uniform rod)"],
        /// Flywheel inertia `J` about the crank pivot (kg m²).
        pub flywheel: f64 = ["J", "kg m²", 0.01, Domain::NonNegative, "inertia of the flywheel on the crank"],
        /// Connecting-rod mass `m_r` (kg).
        pub rod_mass: f64 = ["m_r", "kg", 0.8, Domain::Positive, "mass of the connecting rod (uniform rod)"],
        /// Slider mass `m_s` (kg).
        pub slider_mass: f64 = ["m_s", "kg", 1.2, Domain::Positive, "mass of the slider (point mass)"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
        /// Constant torque `τ` on the crank (N m), counter-clockwise.
        pub torque: f64 = ["τ", "N m", 0.0, Domain::Finite, "constant torque on the crank"],
    }
    /// A slider-crank with crank `r`, rod `l > r`, masses `m_c`, `m_r`, `m_s`, flywheel `J`,
    /// gravity `g` and crank torque `τ`.
    pub fn new;
    derived {
        _rod_longer: () = check_rod(crank, rod)?,
        description: Description = Description {
            coordinates: vec![Coordinate::angle("φ"), Coordinate::angle("ψ"), Coordinate::length("x")],
            bodies: vec![
                Body::rigid("crank", crank_mass, crank_mass * crank * crank / 12.0 + flywheel),
                Body::rigid("rod", rod_mass, rod_mass * rod * rod / 12.0),
                Body::point("slider", slider_mass),
            ],
            gravity,
            constraints: vec!["rod end at the slider (x)".into(), "rod end at the slider (y)".into()],
            ..Description::default()
        },
        linkage: Linkage = linkage(crank, rod, &description.bodies, gravity, torque),
    }
}

/// `l > r`, so that the rod reaches the axis at every crank angle with `cos ψ > 0`.
fn check_rod(crank: f64, rod: f64) -> Result<(), Error> {
    if rod > crank {
        return Ok(());
    }
    Err(Error::InvalidParameter {
        name: "rod".into(),
        value: rod,
        why: format!("the connecting rod must be longer than the crank (r = {crank}) for the crank to turn fully"),
    })
}

/// The hand-coded linkage of the closed form.
fn linkage(r: f64, l: f64, bodies: &[Body], gravity: f64, torque: f64) -> Linkage {
    let (kphi, kpsi) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let body = |b: &Body, centre: Point, angle: [f64; 3]| LinkBody {
        mass: b.mass,
        inertia: b.inertia,
        centre,
        angle: angle.to_vec(),
    };
    Linkage {
        bodies: vec![
            body(&bodies[0], Point::at(0.0, 0.0).arm(&kphi, [r / 2.0, 0.0]), kphi),
            body(&bodies[1], Point::at(0.0, 0.0).arm(&kphi, [r, 0.0]).arm(&kpsi, [l / 2.0, 0.0]), kpsi),
            body(&bodies[2], Point::at(0.0, 0.0).slide(2, [1.0, 0.0]), [0.0; 3]),
        ],
        gravity,
        loops: vec![Point::at(0.0, 0.0).arm(&kphi, [r, 0.0]).arm(&kpsi, [l, 0.0]).slide(2, [-1.0, 0.0])],
        torque: (kphi.to_vec(), torque),
        spring: None,
    }
}

/// `(ψ, x)` from `φ`: `ψ = asin(−r sin φ / l)` (the branch `cos ψ > 0`),
/// `x = r cos φ + l cos ψ`.
pub fn position_analysis<S: Scalar>(crank: f64, rod: f64, phi: S) -> (S, S) {
    let psi = (phi.sin() * (-crank / rod)).asin();
    (psi, phi.cos() * crank + psi.cos() * rod)
}

impl SliderCrank {
    /// The consistent state at crank angle `φ` and rate `φ̇`: `(ψ, x)` by
    /// [`position_analysis`], `ψ̇ = −r cos φ φ̇ / (l cos ψ)`, `ẋ = −r sin φ φ̇ − l sin ψ ψ̇`.
    pub fn state_at(&self, t: f64, phi: f64, rate: f64) -> State {
        let (r, l) = (self.crank, self.rod);
        let (psi, x) = position_analysis(r, l, phi);
        let psi_rate = -r * phi.cos() * rate / (l * psi.cos());
        let x_rate = -r * phi.sin() * rate - l * psi.sin() * psi_rate;
        State::new(t, [phi, psi, x], [rate, psi_rate, x_rate])
    }

    /// `(q̈, λ)` in closed form: the dense KKT system assembled by hand from the bodies'
    /// centres (rotating arms and the slide), as for [`FourBar`](crate::FourBar).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 3 entries.
    pub fn closed_form_with_multipliers(&self, q: &[f64], qdot: &[f64]) -> ([f64; 3], [f64; 2]) {
        assert!(q.len() == 3 && qdot.len() == 3, "q and q̇ must have 3 entries");
        match self.linkage.accelerations(q, qdot) {
            Some((a, l)) => ([a[0], a[1], a[2]], [l[0], l[1]]),
            None => ([f64::NAN; 3], [f64::NAN; 2]),
        }
    }

    /// The energy function `T + V − τ φ`, conserved along every motion.
    pub fn energy(&self, q: &[f64], qdot: &[f64]) -> f64 {
        self.linkage.energy(q, qdot)
    }

    /// The loop-closure residuals `Φ(q)` and their rates `G q̇` (hand-coded).
    pub fn residuals(&self, q: &[f64], qdot: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.linkage.residuals(q, qdot)
    }

    /// The same mechanism in its crank angle alone ([`SliderCrankCrank`]).
    pub fn crank_model(&self) -> SliderCrankCrank {
        let description = Description {
            coordinates: vec![Coordinate::angle("φ")],
            bodies: self.description.bodies.clone(),
            gravity: self.gravity,
            ..Description::default()
        };
        SliderCrankCrank { scene: self.clone(), description }
    }
}

/// The bodies' poses: crank centre at `r/2` along the crank, rod midpoint, slider at `(x, 0)`.
fn slider_crank_poses<S: Scalar>(r: f64, l: f64, q: [S; 3], world_from_body: &mut [Pose<S>]) {
    let [phi, psi, x] = q;
    let (px, py) = (phi.cos() * r, phi.sin() * r);
    world_from_body[0] = Pose::new(phi.cos() * (r / 2.0), phi.sin() * (r / 2.0), phi);
    world_from_body[1] = Pose::new(px + psi.cos() * (l / 2.0), py + psi.sin() * (l / 2.0), psi);
    world_from_body[2] = Pose::point(x, S::zero());
}

impl Mechanism for SliderCrank {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        slider_crank_poses(self.crank, self.rod, [q[0], q[1], q[2]], world_from_body);
    }

    /// `P + l e(ψ) − (x, 0) = 0`, x then y.
    fn constraints<S: Scalar>(&self, _t: S, q: &[S], phi: &mut [S]) {
        let (r, l) = (self.crank, self.rod);
        phi[0] = q[0].cos() * r + q[1].cos() * l - q[2];
        phi[1] = q[0].sin() * r + q[1].sin() * l;
    }

    /// The torque `τ` on the crank (none when `τ = 0`).
    fn applied_forces<S: Scalar>(
        &self,
        _t: S,
        _q: &[S],
        _qdot: &[S],
        _world_from_body: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        if self.torque == 0.0 {
            return false;
        }
        loads.torque(0, S::from(self.torque));
        true
    }
}

impl SceneType for SliderCrank {
    const ID: &'static str = "slider_crank";
    const TITLE: &'static str = "Slider-crank with flywheel, closed loop";
    const REFERENCE: &'static str =
        "docs/scenes.md#slider_crank; beyond the lecture (closed kinematic loop, two holonomic constraints)";
    param_table!();

    /// [`SliderCrank::closed_form_with_multipliers`].
    fn closed_form(&self, _t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
        qddot.copy_from_slice(&self.closed_form_with_multipliers(q, qdot).0);
    }

    /// `φ = 0.3`, `φ̇ = 20 rad/s`, the rest from [`SliderCrank::state_at`].
    fn default_state(&self) -> State {
        self.state_at(0.0, 0.3, 20.0)
    }

    /// `E = T + V` without torque; with a constant torque `τ`, `E − τ φ`.
    fn conserves_energy(&self) -> Vec<Conserved> {
        let energy = |s: &Self, q: &[f64], qdot: &[f64]| s.energy(q, qdot);
        if self.torque == 0.0 {
            vec![Conserved::energy(self, energy)]
        } else {
            vec![Conserved::new(
                self,
                "E − τ φ",
                "a constant torque's work is τ Δφ",
                Invariant::Other,
                move |s, _, q, qdot| energy(s, q, qdot),
            )]
        }
    }

    body_scene!(engine);

    /// Pins at the origin and at the crank pin `P` (the rod's angle absolute), the slider on a
    /// prismatic joint along x, the rod–slider pin closing the loop; the crank torque.
    fn joint_graph(&self) -> Option<JointGraph> {
        let (r, l) = (self.crank, self.rod);
        let mut graph = crate::scene::graph_of(Self::ID, self)
            .with_joint(GraphJoint::revolute("φ", GROUND, [0.0, 0.0], "crank", [-r / 2.0, 0.0]))
            .with_joint(GraphJoint::revolute("ψ", "crank", [r / 2.0, 0.0], "rod", [-l / 2.0, 0.0]).absolute())
            .with_joint(GraphJoint::prismatic("x", GROUND, [0.0, 0.0], "slider", [0.0, 0.0], [1.0, 0.0]))
            .with_joint(GraphJoint::revolute("rod–slider pin", "rod", [l / 2.0, 0.0], "slider", [0.0, 0.0]).closing());
        if self.torque != 0.0 {
            graph =
                graph.with_force(ForceElement::Torque { body: "crank".into(), torque: Profile::constant(self.torque) });
        }
        Some(graph)
    }
}

/// The slider-crank in its crank angle alone, `q = (φ)`: `ψ` and `x` from
/// [`position_analysis`] inside the poses. Not a registered scene: the reference the
/// constrained [`SliderCrank`] is checked against.
#[derive(Clone, Debug, PartialEq)]
pub struct SliderCrankCrank {
    scene: SliderCrank,
    /// `φ` alone; the scene's bodies and gravity, no constraints.
    description: Description,
}

impl SliderCrankCrank {
    /// The constrained scene it reduces.
    pub fn scene(&self) -> &SliderCrank {
        &self.scene
    }
}

impl Mechanism for SliderCrankCrank {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (r, l) = (self.scene.crank, self.scene.rod);
        let (psi, x) = position_analysis(r, l, q[0]);
        slider_crank_poses(r, l, [q[0], psi, x], world_from_body);
    }

    fn applied_forces<S: Scalar>(
        &self,
        t: S,
        q: &[S],
        qdot: &[S],
        world_from_body: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        self.scene.applied_forces(t, q, qdot, world_from_body, loads)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{assert_close, max_abs};
    use lagrange::{Method, Model, Output, accelerations, constraint_multipliers};

    fn scene(torque: f64) -> SliderCrank {
        SliderCrank::new(0.1, 0.4, 0.5, 0.01, 0.8, 1.2, 9.81, torque).unwrap()
    }

    /// Crank angles around the turn, with the dead centres (`φ = 0`, `π`: crank and rod
    /// collinear) and states 1e-6 rad from them.
    fn crank_states() -> Vec<(f64, f64)> {
        let pi = std::f64::consts::PI;
        vec![
            (0.3, 20.0),
            (1.7, -5.0),
            (4.0, 12.0),
            (0.0, 15.0),
            (1e-6, -3.0),
            (pi, 8.0),
            (pi + 1e-6, -9.0),
            (pi / 2.0, 1.0),
        ]
    }

    #[test]
    fn default_state_is_consistent() {
        let s = scene(0.0);
        assert_eq!(s, SliderCrank::from_params(&scene_of::<SliderCrank>().default_params()).unwrap());
        for (phi, rate) in crank_states() {
            let state = s.state_at(0.0, phi, rate);
            let (residual, rate_residual) = s.residuals(&state.q, &state.qdot);
            assert!(max_abs(&residual) <= 8.0 * f64::EPSILON, "{residual:?}");
            assert!(max_abs(&rate_residual) <= 32.0 * f64::EPSILON * rate.abs() * s.crank, "{rate_residual:?}");
            assert!(state.q[1].cos() > 0.0);
        }
        assert_eq!(s.default_state(), s.state_at(0.0, 0.3, 20.0));
    }

    /// Engine (constraint solve), hand-coded KKT and the one-coordinate model agree to
    /// `1e3 ε` relative to the largest `|q̈|` (`λ`: to the largest `|λ|`): a few hundred
    /// operations each, and the constrained solve's condition number stays below 1e2 (the rod
    /// keeps `cos ψ ≥ √(1 − (r/l)²) ≈ 0.97`, so `G` has full rank with singular values ≥ 0.09).
    #[test]
    fn constrained_closed_form_and_one_coordinate_model_agree() {
        for torque in [0.0, -1.5] {
            let s = scene(torque);
            let constrained = Model::new(s.clone()).unwrap();
            let one = Model::new(s.crank_model()).unwrap();
            let (mut wc, mut wo) = (constrained.workspace(), one.workspace());
            for (phi, rate) in crank_states() {
                let state = s.state_at(0.0, phi, rate);
                let engine = accelerations(&constrained, &mut wc, 0.0, &state.q, &state.qdot).unwrap().to_vec();
                let lambda =
                    constraint_multipliers(&constrained, &mut wc, 0.0, &state.q, &state.qdot).unwrap().to_vec();
                let (closed, closed_lambda) = s.closed_form_with_multipliers(&state.q, &state.qdot);
                let crank = accelerations(&one, &mut wo, 0.0, &[phi], &[rate]).unwrap()[0];
                let bound = 1e3 * f64::EPSILON * max_abs(&closed);
                assert_close(&format!("φ = {phi}: engine vs closed form"), &closed, &engine, bound);
                assert_close(&format!("φ = {phi}: one coordinate"), &[closed[0]], &[crank], bound);
                let lambda_bound = 1e3 * f64::EPSILON * max_abs(&closed_lambda);
                assert_close(&format!("φ = {phi}: λ"), &closed_lambda, &lambda, lambda_bound);
            }
        }
    }

    /// Over 2 s from the default state (the crank turns about 6 times) the constrained model
    /// and the one-coordinate model, both by RK4 at dt = 2e-5 (the constrained one projected
    /// after every step), give crank angles and slider positions within 1e-10 (each is within
    /// about 1e-11 of the exact motion at this step).
    #[test]
    fn trajectories_agree_over_two_seconds() {
        let s = scene(0.0);
        let constrained = Model::new(s.clone()).unwrap();
        let one = Model::new(s.crank_model()).unwrap();
        let start = s.default_state();
        let (output, method) = (Output::Every(0.1), Method::Rk4 { dt: 2e-5 });
        let a = lagrange::simulate(&constrained, &start, 2.0, method, &output).unwrap();
        let b =
            lagrange::simulate(&one, &State::new(0.0, [start.q[0]], [start.qdot[0]]), 2.0, method, &output).unwrap();
        let worst = (0..a.len()).map(|k| (a.q(k)[0] - b.q(k)[0]).abs()).fold(0.0, f64::max);
        assert!(worst <= 1e-10, "{worst:e}");
        let slider = (0..a.len())
            .map(|k| (a.q(k)[2] - position_analysis(s.crank, s.rod, b.q(k)[0]).1).abs())
            .fold(0.0, f64::max);
        assert!(slider <= 1e-10, "{slider:e}");
    }

    /// `T + V − τ φ` along RK4 runs: drift falls as dt⁴ (ratio 16 within a factor 2).
    #[test]
    fn energy_is_conserved_to_the_order_of_rk4() {
        for torque in [0.0, -1.5] {
            let s = scene(torque);
            let model = Model::new(s.clone()).unwrap();
            let start = s.default_state();
            let e0 = s.energy(&start.q, &start.qdot);
            let drift = |dt: f64| {
                let run = lagrange::simulate(&model, &start, 1.0, Method::Rk4 { dt }, &Output::Every(0.05)).unwrap();
                (0..run.len()).map(|k| (s.energy(run.q(k), run.qdot(k)) - e0).abs()).fold(0.0, f64::max)
            };
            let (coarse, fine) = (drift(2e-3), drift(1e-3));
            let ratio = coarse / fine;
            assert!((8.0..=32.0).contains(&ratio), "τ = {torque}: drift {coarse:e} → {fine:e}, ratio {ratio}");
        }
    }

    #[test]
    fn a_rod_shorter_than_the_crank_is_rejected() {
        let error = SliderCrank::new(0.4, 0.1, 0.5, 0.01, 0.8, 1.2, 9.81, 0.0).unwrap_err();
        assert!(matches!(error, Error::InvalidParameter { ref name, .. } if name == "rod"), "{error}");
    }
}
