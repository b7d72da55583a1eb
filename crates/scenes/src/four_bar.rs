//! Four-bar linkage (crank-rocker) in its three link angles with two loop-closure constraints
//! (beyond the lecture; docs/scenes.md#four_bar), and the same mechanism in its crank angle
//! alone ([`FourBarCrank`]), the coupler and rocker placed by the closed-form position analysis.

use crate::linkage::{LinkBody, Linkage, Point, solve2};
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, Invariant, SceneType};
use lagrange::graph::{ForceElement, GROUND, GraphJoint, JointGraph, Profile};
use lagrange::{Body, Coordinate, Description, Error, Loads, Mechanism, Pose, Scalar, State};
use std::f64::consts::FRAC_PI_3;

scene_params! {
    /// A crank-rocker four-bar linkage: ground pivots `O2 = (0, 0)` and `O4 = (d, 0)`, crank
    /// `O2 → A` of length `a`, coupler `A → B` of length `b`, rocker `O4 → B` of length `c`,
    /// all uniform rods (centre of mass at the midpoint, inertia `m L²/12`); gravity along −y
    /// and an optional constant torque `τ` on the crank. `q = (θ2, θ3, θ4)`, the links' absolute
    /// angles from +x, tied by the loop closure
    /// `a cos θ2 + b cos θ3 − c cos θ4 − d = 0`, `a sin θ2 + b sin θ3 − c sin θ4 = 0`.
    pub struct FourBar {
        /// Crank length `a` (m).
        pub crank: f64 = ["a", "m", 0.2, Domain::Positive, "crank length O2A"],
        /// Coupler length `b` (m).
        pub coupler: f64 = ["b", "m", 0.6, Domain::Positive, "coupler length AB"],
        /// Rocker length `c` (m).
        pub rocker: f64 = ["c", "m", 0.5, Domain::Positive, "rocker length O4B"],
        /// Ground length `d` (m).
        pub ground: f64 = ["d", "m", 0.5, Domain::Positive, "distance between the ground pivots O2O4"],
        /// Crank mass `m2` (kg).
        pub mass_2: f64 = ["m2", "kg", 1.0, Domain::Positive, "mass of the crank (uniform rod)"],
        /// Coupler mass `m3` (kg).
        pub mass_3: f64 = ["m3", "kg", 2.0, Domain::Positive, "mass of the coupler (uniform rod)"],
        /// Rocker mass `m4` (kg).
        pub mass_4: f64 = ["m4", "kg", 1.5, Domain::Positive, "mass of the rocker (uniform rod)"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
        /// Constant torque `τ` on the crank (N m), counter-clockwise.
        pub torque: f64 = ["τ", "N m", 0.0, Domain::Finite, "constant torque on the crank"],
    }
    /// A four-bar linkage with link lengths `a`, `b`, `c`, `d`, masses `m2`, `m3`, `m4`, gravity
    /// `g` and crank torque `τ`; the links must close at some crank angle (the default state
    /// starts at `θ2 = π/3` where they close there, else at the crank angle in `(0, π)` that puts
    /// `|O4 − A|` in the middle of the range the coupler and rocker span).
    pub fn new;
    derived {
        start: f64 = starting_angle([crank, coupler, rocker, ground])?,
        description: Description = Description {
            coordinates: vec![Coordinate::angle("θ2"), Coordinate::angle("θ3"), Coordinate::angle("θ4")],
            bodies: rods([crank, coupler, rocker], [mass_2, mass_3, mass_4]),
            gravity,
            constraints: vec!["loop closure at B (x)".into(), "loop closure at B (y)".into()],
            ..Description::default()
        },
        linkage: Linkage = linkage([crank, coupler, rocker, ground], [mass_2, mass_3, mass_4], gravity, torque),
    }
}

/// The three links as uniform rods (`I = m L²/12`), in the order crank, coupler, rocker.
fn rods(lengths: [f64; 3], masses: [f64; 3]) -> Vec<Body> {
    let rod = |name: &str, m: f64, l: f64| Body::rigid(name, m, m * l * l / 12.0);
    vec![
        rod("crank", masses[0], lengths[0]),
        rod("coupler", masses[1], lengths[1]),
        rod("rocker", masses[2], lengths[2]),
    ]
}

/// The hand-coded linkage of the closed form: the three rods' centres and angles, the loop
/// `A + b e(θ3) − O4 − c e(θ4) = 0`, the torque on `θ2`.
fn linkage(lengths: [f64; 4], masses: [f64; 3], gravity: f64, torque: f64) -> Linkage {
    let [a, b, c, d] = lengths;
    let (k2, k3, k4) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let body = |mass: f64, length: f64, centre: Point, angle: [f64; 3]| LinkBody {
        mass,
        inertia: mass * length * length / 12.0,
        centre,
        angle: angle.to_vec(),
    };
    Linkage {
        bodies: vec![
            body(masses[0], a, Point::at(0.0, 0.0).arm(&k2, [a / 2.0, 0.0]), k2),
            body(masses[1], b, Point::at(0.0, 0.0).arm(&k2, [a, 0.0]).arm(&k3, [b / 2.0, 0.0]), k3),
            body(masses[2], c, Point::at(d, 0.0).arm(&k4, [c / 2.0, 0.0]), k4),
        ],
        gravity,
        loops: vec![Point::at(-d, 0.0).arm(&k2, [a, 0.0]).arm(&k3, [b, 0.0]).arm(&k4, [-c, 0.0])],
        torque: (k2.to_vec(), torque),
        spring: None,
    }
}

/// `(θ3, θ4)` from `θ2` by the closed-form position analysis: `B` is where the circle of radius
/// `b` about `A = a e(θ2)` meets the circle of radius `c` about `O4 = (d, 0)`, on the side of the
/// line `A → O4` turned counter-clockwise (for the crank-rocker: `B` above the ground line,
/// `0 < θ4 < π`). With `δ = O4 − A`, `D = |δ|`, the foot of `B` on that line is `s = (D² + b² −
/// c²)/(2D)` from `A` and `B` is `h = √(b² − s²)` off it. NaN where the links cannot close.
pub fn position_analysis<S: Scalar>(lengths: [f64; 4], theta_2: S) -> (S, S) {
    let [a, b, c, d] = lengths;
    let (ax, ay) = (theta_2.cos() * a, theta_2.sin() * a);
    let (dx, dy) = (-ax + d, -ay);
    let dist2 = dx * dx + dy * dy;
    let dist = dist2.sqrt();
    let along = (dist2 + b * b - c * c) / (dist * 2.0);
    let h = (-(along * along) + b * b).sqrt();
    let (ux, uy) = (dx / dist, dy / dist);
    let (bx, by) = (ax + ux * along - uy * h, ay + uy * along + ux * h);
    ((by - ay).atan2(bx - ax), by.atan2(bx - d))
}

/// The crank angle the default state starts at: `π/3` where the links close there (away from
/// a lock position: `B` strictly off the line `A O4`), else the angle in `(0, π)` where the
/// distance `|O4 − A| = √(a² + d² − 2 a d cos θ2)` is the middle of the range the coupler and
/// rocker can span, `(|b − c|, b + c)`, within the range the crank reaches, `[|d − a|, d + a]`.
///
/// # Errors
/// [`Error::InvalidParameter`] naming the four lengths when the two ranges do not overlap: the
/// links close at no crank angle.
fn starting_angle(lengths: [f64; 4]) -> Result<f64, Error> {
    let [a, b, c, d] = lengths;
    let reach = |theta: f64| (d - a * theta.cos()).hypot(a * theta.sin());
    let closes = |dist: f64| (b - c).abs() < dist && dist < b + c;
    if closes(reach(FRAC_PI_3)) {
        return Ok(FRAC_PI_3);
    }
    let (low, high) = ((b - c).abs().max((d - a).abs()), (b + c).min(d + a));
    let middle = 0.5 * (low + high);
    let cosine = (a * a + d * d - middle * middle) / (2.0 * a * d);
    let theta = cosine.clamp(-1.0, 1.0).acos();
    if low < high && closes(reach(theta)) {
        return Ok(theta);
    }
    Err(Error::InvalidParameter {
        name: "a, b, c, d".into(),
        value: a,
        why: format!(
            "the links a = {a}, b = {b}, c = {c}, d = {d} close at no crank angle: the crank reaches \
             |O4 − A| from |d − a| = {} to d + a = {}, the coupler and rocker span |b − c| = {} to b + c = {}",
            (d - a).abs(),
            d + a,
            (b - c).abs(),
            b + c
        ),
    })
}

impl FourBar {
    /// `(θ3, θ4)` at crank angle `θ2` by the closed-form position analysis
    /// ([`position_analysis`]).
    pub fn assemble(&self, theta_2: f64) -> (f64, f64) {
        position_analysis(self.lengths(), theta_2)
    }

    /// The consistent state at crank angle `θ2` and rate `θ̇2`: `(θ3, θ4)` by
    /// [`position_analysis`], `(θ̇3, θ̇4)` from the velocity constraints
    /// `[[−b sin θ3, c sin θ4], [b cos θ3, −c cos θ4]] (θ̇3, θ̇4) = (a sin θ2, −a cos θ2) θ̇2`
    /// by Cramer's rule.
    pub fn state_at(&self, t: f64, theta_2: f64, rate: f64) -> State {
        let [a, b, c, _] = self.lengths();
        let (theta_3, theta_4) = self.assemble(theta_2);
        let (s2, c2, s3, c3, s4, c4) =
            (theta_2.sin(), theta_2.cos(), theta_3.sin(), theta_3.cos(), theta_4.sin(), theta_4.cos());
        let [w3, w4] = solve2(-b * s3, c * s4, b * c3, -c * c4, a * s2 * rate, -a * c2 * rate);
        State::new(t, [theta_2, theta_3, theta_4], [rate, w3, w4])
    }

    /// `(q̈, λ)` in closed form: `M q̈ + Gᵀ λ = f`, `G q̈ = −γ` assembled by hand from the rods'
    /// centres (sums of rotating arms: velocities and convective accelerations by the chain
    /// rule written out) and solved as one dense KKT system; `λ` in the order of the
    /// constraints (x, then y, of the loop closure at `B`).
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

    /// The energy function `T + V − τ θ2` (kinetic, gravity, and the constant torque's
    /// potential), conserved along every motion.
    pub fn energy(&self, q: &[f64], qdot: &[f64]) -> f64 {
        self.linkage.energy(q, qdot)
    }

    /// The loop-closure residuals `Φ(q)` and their rates `G q̇` (hand-coded).
    pub fn residuals(&self, q: &[f64], qdot: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.linkage.residuals(q, qdot)
    }

    /// `[a, b, c, d]`.
    pub fn lengths(&self) -> [f64; 4] {
        [self.crank, self.coupler, self.rocker, self.ground]
    }

    /// The same linkage in its crank angle alone ([`FourBarCrank`]).
    pub fn crank_model(&self) -> FourBarCrank {
        let description = Description {
            coordinates: vec![Coordinate::angle("θ2")],
            bodies: self.description.bodies.clone(),
            gravity: self.gravity,
            ..Description::default()
        };
        FourBarCrank { scene: self.clone(), description }
    }
}

/// The rods' poses: midpoints and link angles.
fn four_bar_poses<S: Scalar>(lengths: [f64; 4], theta: [S; 3], world_from_body: &mut [Pose<S>]) {
    let [a, b, c, d] = lengths;
    let [theta_2, theta_3, theta_4] = theta;
    let (ax, ay) = (theta_2.cos() * a, theta_2.sin() * a);
    world_from_body[0] = Pose::new(theta_2.cos() * (a / 2.0), theta_2.sin() * (a / 2.0), theta_2);
    world_from_body[1] = Pose::new(ax + theta_3.cos() * (b / 2.0), ay + theta_3.sin() * (b / 2.0), theta_3);
    world_from_body[2] = Pose::new(theta_4.cos() * (c / 2.0) + d, theta_4.sin() * (c / 2.0), theta_4);
}

impl Mechanism for FourBar {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        four_bar_poses(self.lengths(), [q[0], q[1], q[2]], world_from_body);
    }

    /// `A + b e(θ3) − O4 − c e(θ4) = 0`, x then y.
    fn constraints<S: Scalar>(&self, _t: S, q: &[S], phi: &mut [S]) {
        let [a, b, c, d] = self.lengths();
        phi[0] = q[0].cos() * a + q[1].cos() * b - q[2].cos() * c - d;
        phi[1] = q[0].sin() * a + q[1].sin() * b - q[2].sin() * c;
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

impl SceneType for FourBar {
    const ID: &'static str = "four_bar";
    const TITLE: &'static str = "Four-bar linkage (crank-rocker), closed loop";
    const REFERENCE: &'static str =
        "docs/scenes.md#four_bar; beyond the lecture (closed kinematic loop, two holonomic constraints)";
    param_table!();

    /// [`FourBar::closed_form_with_multipliers`].
    fn closed_form(&self, _t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
        qddot.copy_from_slice(&self.closed_form_with_multipliers(q, qdot).0);
    }

    /// `θ2 = π/3` (or, for links that do not close there, the crank angle in `(0, π)` that puts
    /// `|O4 − A|` in the middle of the range the coupler and rocker span), `θ̇2 = 6 rad/s`, the rest from [`FourBar::state_at`].
    fn default_state(&self) -> State {
        self.state_at(0.0, self.start, 6.0)
    }

    /// `E = T + V` without torque; with a constant torque `τ`, `E − τ θ2` (its work is
    /// `τ Δθ2`), which the engine does not derive (it sees an applied force).
    fn conserves_energy(&self) -> Vec<Conserved> {
        let energy = |s: &Self, q: &[f64], qdot: &[f64]| s.energy(q, qdot);
        if self.torque == 0.0 {
            vec![Conserved::energy(self, energy)]
        } else {
            vec![Conserved::new(
                self,
                "E − τ θ2",
                "a constant torque's work is τ Δθ2",
                Invariant::Other,
                move |s, _, q, qdot| energy(s, q, qdot),
            )]
        }
    }

    body_scene!(engine);

    /// Pins at `O2`, `A` and `O4` as tree joints (the coupler's angle absolute), the pin at `B`
    /// between coupler and rocker closing the loop; the crank torque.
    fn joint_graph(&self) -> Option<JointGraph> {
        let [a, b, c, d] = self.lengths();
        let mut graph = crate::scene::graph_of(Self::ID, self)
            .with_joint(GraphJoint::revolute("θ2", GROUND, [0.0, 0.0], "crank", [-a / 2.0, 0.0]))
            .with_joint(GraphJoint::revolute("θ3", "crank", [a / 2.0, 0.0], "coupler", [-b / 2.0, 0.0]).absolute())
            .with_joint(GraphJoint::revolute("θ4", GROUND, [d, 0.0], "rocker", [-c / 2.0, 0.0]))
            .with_joint(GraphJoint::revolute("B", "coupler", [b / 2.0, 0.0], "rocker", [c / 2.0, 0.0]).closing());
        if self.torque != 0.0 {
            graph =
                graph.with_force(ForceElement::Torque { body: "crank".into(), torque: Profile::constant(self.torque) });
        }
        Some(graph)
    }
}

/// The four-bar in its crank angle alone, `q = (θ2)`: the coupler and rocker angles come from
/// the closed-form position analysis ([`position_analysis`]) inside the poses, so the engine
/// differentiates through it. Not a registered scene: the reference the constrained
/// [`FourBar`] is checked against.
#[derive(Clone, Debug, PartialEq)]
pub struct FourBarCrank {
    scene: FourBar,
    /// `θ2` alone; the scene's bodies and gravity, no constraints.
    description: Description,
}

impl FourBarCrank {
    /// The constrained scene it reduces.
    pub fn scene(&self) -> &FourBar {
        &self.scene
    }
}

impl Mechanism for FourBarCrank {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let lengths = self.scene.lengths();
        let (theta_3, theta_4) = position_analysis(lengths, q[0]);
        four_bar_poses(lengths, [q[0], theta_3, theta_4], world_from_body);
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

    fn scene() -> FourBar {
        FourBar::from_params(&scene_of::<FourBar>().default_params()).unwrap()
    }

    /// The crank angles of the two toggle positions, where crank and coupler are collinear
    /// (`|O2 B| = a + b`, extended, and `b − a`, folded; the rocker is at an extreme): `B` on the
    /// circle of radius `c` about `O4` at distance `ρ` from `O2` has polar angle
    /// `acos((ρ² + d² − c²)/(2 ρ d))`; the crank points along it (extended) or against it (folded).
    fn toggle_angles(s: &FourBar) -> [f64; 2] {
        let [a, b, c, d] = s.lengths();
        let polar = |rho: f64| ((rho * rho + d * d - c * c) / (2.0 * rho * d)).acos();
        [polar(a + b), polar(b - a) + std::f64::consts::PI]
    }

    /// States along the crank's turn, including both toggle positions and states 1e-6 rad
    /// from them, and the crank collinear with the ground (`θ2 = 0`, `π`).
    fn crank_states() -> Vec<(f64, f64)> {
        let pi = std::f64::consts::PI;
        let mut states = vec![(FRAC_PI_3, 6.0), (2.0, -3.0), (4.5, 1.0), (0.0, 10.0), (pi, -7.0)];
        for toggle in toggle_angles(&scene()) {
            states.extend([(toggle, 5.0), (toggle - 1e-6, -4.0), (toggle + 1e-6, 3.0)]);
        }
        states
    }

    /// The default state and `state_at` are consistent: `Φ` and `G q̇` at round-off.
    #[test]
    fn default_state_is_consistent() {
        let s = scene();
        for (theta, rate) in crank_states() {
            let state = s.state_at(0.0, theta, rate);
            let (phi, rate_residual) = s.residuals(&state.q, &state.qdot);
            assert!(max_abs(&phi) <= 8.0 * f64::EPSILON, "{phi:?}");
            assert!(max_abs(&rate_residual) <= 32.0 * f64::EPSILON * rate.abs(), "{rate_residual:?}");
            assert!(0.0 < state.q[2] && state.q[2] < std::f64::consts::PI, "branch 0 < θ4 < π: {state:?}");
        }
        assert_eq!(s.default_state(), s.state_at(0.0, FRAC_PI_3, 6.0));
    }

    /// The engine's constrained `q̈` and `λ`, the hand-coded KKT closed form, and the crank's
    /// `θ̈2` of the one-coordinate model agree to round-off. Bound: `1e3 ε` relative to the
    /// largest `|q̈|`. Each route is a few hundred operations on O(1) numbers; the constrained
    /// solves lose up to their condition number, which for these lengths stays below 1e2 even
    /// at the toggle positions (these are not singular for the constrained form: the
    /// transmission angle between coupler and rocker stays far from 0 and π for this
    /// crank-rocker, so `G` keeps full rank), and the one-coordinate model's poses
    /// go through the position analysis' square root (its argument ≥ 0.03 here).
    #[test]
    fn constrained_closed_form_and_one_coordinate_model_agree() {
        for torque in [0.0, 2.5] {
            let mut s = scene();
            if torque != 0.0 {
                s = FourBar::new(0.2, 0.6, 0.5, 0.5, 1.0, 2.0, 1.5, 9.81, torque).unwrap();
            }
            let constrained = Model::new(s.clone()).unwrap();
            let one = Model::new(s.crank_model()).unwrap();
            let (mut wc, mut wo) = (constrained.workspace(), one.workspace());
            for (theta, rate) in crank_states() {
                let state = s.state_at(0.0, theta, rate);
                let engine = accelerations(&constrained, &mut wc, 0.0, &state.q, &state.qdot).unwrap().to_vec();
                let lambda =
                    constraint_multipliers(&constrained, &mut wc, 0.0, &state.q, &state.qdot).unwrap().to_vec();
                let (closed, closed_lambda) = s.closed_form_with_multipliers(&state.q, &state.qdot);
                let crank = accelerations(&one, &mut wo, 0.0, &[theta], &[rate]).unwrap()[0];
                let scale = max_abs(&closed);
                let bound = 1e3 * f64::EPSILON * scale;
                assert_close(&format!("θ2 = {theta}: engine vs closed form"), &closed, &engine, bound);
                assert_close(&format!("θ2 = {theta}: one coordinate"), &[closed[0]], &[crank], bound);
                let lambda_bound = 1e3 * f64::EPSILON * max_abs(&closed_lambda);
                assert_close(&format!("θ2 = {theta}: λ"), &closed_lambda, &lambda, lambda_bound);
            }
        }
    }

    /// Over 2 s from the default state the constrained model (RK4 dt 1e-4, projected after
    /// every step) and the one-coordinate model (RK4 at the same step) give the same crank
    /// angle to 1e-10: both are 4th-order, with errors ≈ 1e-12 at this step.
    #[test]
    fn trajectories_agree_over_two_seconds() {
        let s = scene();
        let constrained = Model::new(s.clone()).unwrap();
        let one = Model::new(s.crank_model()).unwrap();
        let start = s.default_state();
        let (output, method) = (Output::Every(0.1), Method::Rk4 { dt: 1e-4 });
        let a = lagrange::simulate(&constrained, &start, 2.0, method, &output).unwrap();
        let b =
            lagrange::simulate(&one, &State::new(0.0, [start.q[0]], [start.qdot[0]]), 2.0, method, &output).unwrap();
        let worst = (0..a.len()).map(|k| (a.q(k)[0] - b.q(k)[0]).abs()).fold(0.0, f64::max);
        assert!(worst <= 1e-10, "{worst:e}");
        // The rocker too, against the position analysis of the one-coordinate crank angle.
        let rocker = (0..a.len()).map(|k| (a.q(k)[2] - s.assemble(b.q(k)[0]).1).abs()).fold(0.0, f64::max);
        assert!(rocker <= 1e-10, "{rocker:e}");
    }

    /// The energy function (with a torque: `T + V − τ θ2`) along RK4 runs at dt = 4e-3 and
    /// 1e-3: its drift falls as dt⁴ (ratio 4⁴ = 256 within a factor 4; measured 666 without
    /// torque and 576 with it — one halving alone wobbles between 15 and 38 at these steps,
    /// where the torque drives the crank to 40 rad/s) and stays below 1e-8 relative at
    /// dt = 1e-3 (measured 9.1e-10 without torque).
    #[test]
    fn energy_is_conserved_to_the_order_of_rk4() {
        for torque in [0.0, 2.5] {
            let s = FourBar::new(0.2, 0.6, 0.5, 0.5, 1.0, 2.0, 1.5, 9.81, torque).unwrap();
            let model = Model::new(s.clone()).unwrap();
            let start = s.default_state();
            let e0 = s.energy(&start.q, &start.qdot);
            let drift = |dt: f64| {
                let run = lagrange::simulate(&model, &start, 2.0, Method::Rk4 { dt }, &Output::Every(0.1)).unwrap();
                (0..run.len()).map(|k| (s.energy(run.q(k), run.qdot(k)) - e0).abs()).fold(0.0, f64::max)
            };
            let (coarse, finest) = (drift(4e-3), drift(1e-3));
            eprintln!("τ = {torque}: drift {coarse:e} at dt = 4e-3, {finest:e} at 1e-3 (E0 = {e0})");
            let ratio = coarse / finest;
            assert!((64.0..=1024.0).contains(&ratio), "τ = {torque}: drift {coarse:e} → {finest:e}, ratio {ratio}");
            // With the torque the crank speeds up (to ~40 rad/s in 2 s): only the order is checked.
            assert!(torque != 0.0 || finest <= 1e-8 * e0.abs().max(1.0), "τ = {torque}: {finest:e}");
        }
    }
}
