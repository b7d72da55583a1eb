//! A four-bar on the Grashof equality `a + b = c + d` (a change-point linkage), which lies flat
//! once per crank turn (beyond the lecture; docs/scenes.md#change_point_four_bar): the
//! constrained [`FourBar`] with these lengths, its one-coordinate reduction on the analytic
//! branch through the change point written out by hand, and the same reduction as a mechanism
//! ([`ChangePointCrank`]) for the engine.

use crate::four_bar::FourBar;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::{body_scene, delegate_mechanism};
use crate::{Conserved, Domain, SceneType};
use lagrange::graph::JointGraph;
use lagrange::{Coordinate, Description, Mechanism, Pose, Scalar, State};
use std::f64::consts::FRAC_PI_3;

/// `[a, b, c, d]`: crank, coupler, rocker, ground (m). `a + b = c + d = 4`; the crank is the
/// shortest link and next to the ground, so it turns fully (Grashof); `a ≠ c` and `b ≠ d` (no
/// parallelogram) and no two pairs of equal adjacent links (no kite), so the only flat
/// configuration is `θ2 = 0` (mod 2π), `O2–A–O4–B` on the x axis, where the circles of `B`
/// about `A` (radius `b`) and `O4` (radius `c`) touch. `c > a` and `d > a` keep `D = |O4 − A|`
/// in `[d − a, d + a] = [1, 3]`, strictly inside `(b − c, b + c) = (1, 5)` except at the change
/// point.
pub const LENGTHS: [f64; 4] = [1.0, 3.0, 2.0, 2.0];

/// Mass of each link, a uniform rod (kg).
const LINK_MASS: f64 = 1.0;

scene_params! {
    /// The four-bar of [`FourBar`] with the change-point lengths [`LENGTHS`] (crank 1 m,
    /// coupler 3 m, rocker 2 m, ground 2 m), three uniform rods of 1 kg, no torque:
    /// `q = (θ2, θ3, θ4)`, the links' absolute angles, tied by the loop closure at `B`. Once per
    /// crank turn (`θ2 = 0` mod 2π) it lies flat, where the loop's two rows become dependent
    /// and the two assembly modes (`B` left or right of the line `A → O4`) meet; continuing
    /// smoothly, it changes mode there, so `B` is on the left for `θ2 ∈ (0, 2π)` and on the
    /// right for `θ2 ∈ (2π, 4π)` (mod 4π).
    pub struct ChangePointFourBar {
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
        /// Initial angular velocity of the crank `ω0` (rad/s), counter-clockwise.
        pub crank_speed: f64 = ["ω0", "rad/s", 5.0, Domain::Finite, "initial angular velocity of the crank"],
    }
    /// The change-point four-bar under gravity `g`, started with crank speed `ω0`.
    pub fn new;
    derived {
        four_bar: FourBar = change_point_links(gravity)?,
    }
}

/// The constrained four-bar with the lengths [`LENGTHS`] and links of [`LINK_MASS`].
fn change_point_links(gravity: f64) -> Result<FourBar, lagrange::Error> {
    let [a, b, c, d] = LENGTHS;
    FourBar::new(a, b, c, d, LINK_MASS, LINK_MASS, LINK_MASS, gravity, 0.0)
}

/// The analytic branch through the change point, at crank angle `θ = θ2`, in mode `σ = ±1`
/// (`σ = 1`: `B` left of `A → O4` for `θ ∈ (0, 2π)` mod 4π): with `δ = O4 − A`, `E = |δ|²`,
/// `B = A + α δ + β δ⊥` (`δ⊥` is `δ` turned by +90°), where
/// `α = ½ + (b² − c²)/(2E)` places `B`'s foot along `δ` and
/// `β = σ sin(θ/2) √(a d ((b + c)² − E)) / E` its distance off the line. That is the usual
/// `h = √(b² − s²)` (see [`crate::four_bar::position_analysis`]) with its sign carried through
/// the change point: with `a + b = c + d`, `b² − s² = 4 a d sin²(θ/2) ((b + c)² − E) / (4 E)`,
/// whose square root is analytic as `sin(θ/2) √(…)` (never `|sin(θ/2)|`), and `(b + c)² > E`
/// everywhere for these lengths.
///
/// The derivatives by `θ` come by the chain rule through `E`, `α`, `β`; the link angles'
/// from `φ' = (v × v')/|v|²`, `φ'' = (v × v'')/|v|² − 2 (v · v')(v × v')/|v|⁴`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Branch {
    /// `A`, `A'`, `A''`.
    a: [[f64; 2]; 3],
    /// `B`, `B'`, `B''`.
    b: [[f64; 2]; 3],
    /// `θ3'`, `θ3''` (the coupler's angle along the branch).
    coupler: [f64; 2],
    /// `θ4'`, `θ4''` (the rocker's angle).
    rocker: [f64; 2],
}

/// `v` turned by +90°.
fn perp(v: [f64; 2]) -> [f64; 2] {
    [-v[1], v[0]]
}

fn cross(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[1] - u[1] * v[0]
}

fn dot(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[0] + u[1] * v[1]
}

/// `Σ_i w_i v_i`.
fn combine<const K: usize>(terms: [(f64, [f64; 2]); K]) -> [f64; 2] {
    terms.iter().fold([0.0; 2], |acc, (w, v)| [acc[0] + w * v[0], acc[1] + w * v[1]])
}

/// `(φ', φ'')` of the angle of `v(θ)` from `v`, `v'`, `v''`.
fn angle_rates(v: [f64; 2], v1: [f64; 2], v2: [f64; 2]) -> [f64; 2] {
    let norm2 = dot(v, v);
    let turn = cross(v, v1) / norm2;
    [turn, cross(v, v2) / norm2 - 2.0 * dot(v, v1) * turn / norm2]
}

/// The `(√(…), sin(θ/2))` product `w r` of `β E` and its derivative, the quantities that fix
/// the mode of a state ([`ChangePointFourBar::mode`]).
fn offset_and_rate(theta: f64) -> (f64, f64) {
    let [a, b, c, d] = LENGTHS;
    let e = a * a + d * d - 2.0 * a * d * theta.cos();
    let de = 2.0 * a * d * theta.sin();
    let r = (a * d * ((b + c) * (b + c) - e)).sqrt();
    let (w, dw) = ((0.5 * theta).sin(), 0.5 * (0.5 * theta).cos());
    (w * r, dw * r - w * a * d * de / (2.0 * r))
}

impl Branch {
    /// The branch at crank angle `theta` in mode `sigma`.
    fn at(theta: f64, sigma: f64) -> Self {
        let [a, b, c, d] = LENGTHS;
        let (s, co) = theta.sin_cos();
        // The crank tip and the ground vector δ = O4 − A, with δ' = −A', δ'' = −A'' = A.
        let pa = [a * co, a * s];
        let pa1 = [-a * s, a * co];
        let pa2 = [-a * co, -a * s];
        let delta = [d - pa[0], -pa[1]];
        let (delta1, delta2) = ([-pa1[0], -pa1[1]], [-pa2[0], -pa2[1]]);
        // E = |δ|² and its derivatives.
        let e = a * a + d * d - 2.0 * a * d * co;
        let (e1, e2) = (2.0 * a * d * s, 2.0 * a * d * co);
        // α = ½ + κ/E, κ = (b² − c²)/2.
        let kappa = 0.5 * (b * b - c * c);
        let alpha = 0.5 + kappa / e;
        let alpha1 = -kappa * e1 / (e * e);
        let alpha2 = -kappa * (e2 / (e * e) - 2.0 * e1 * e1 / (e * e * e));
        // f = σ w r with w = sin(θ/2), r = √(a d ((b + c)² − E)); β = f/E.
        let r = (a * d * ((b + c) * (b + c) - e)).sqrt();
        let r1 = -a * d * e1 / (2.0 * r);
        let r2 = -a * d * (e2 * r - e1 * r1) / (2.0 * r * r);
        let (w, w1, w2) = ((0.5 * theta).sin(), 0.5 * (0.5 * theta).cos(), -0.25 * (0.5 * theta).sin());
        let f = sigma * w * r;
        let f1 = sigma * (w1 * r + w * r1);
        let f2 = sigma * (w2 * r + 2.0 * w1 * r1 + w * r2);
        let beta = f / e;
        let beta1 = f1 / e - f * e1 / (e * e);
        let beta2 = f2 / e - 2.0 * f1 * e1 / (e * e) - f * e2 / (e * e) + 2.0 * f * e1 * e1 / (e * e * e);
        // B = A + α δ + β δ⊥ and its derivatives (the product rule, term by term).
        let (p, p1, p2) = (perp(delta), perp(delta1), perp(delta2));
        let pb = combine([(1.0, pa), (alpha, delta), (beta, p)]);
        let pb1 = combine([(1.0, pa1), (alpha1, delta), (alpha, delta1), (beta1, p), (beta, p1)]);
        let pb2 = combine([
            (1.0, pa2),
            (alpha2, delta),
            (2.0 * alpha1, delta1),
            (alpha, delta2),
            (beta2, p),
            (2.0 * beta1, p1),
            (beta, p2),
        ]);
        // The coupler B − A and the rocker B − O4.
        let coupler = angle_rates(
            [pb[0] - pa[0], pb[1] - pa[1]],
            [pb1[0] - pa1[0], pb1[1] - pa1[1]],
            [pb2[0] - pa2[0], pb2[1] - pa2[1]],
        );
        let rocker = angle_rates([pb[0] - d, pb[1]], pb1, pb2);
        Self { a: [pa, pa1, pa2], b: [pb, pb1, pb2], coupler, rocker }
    }

    /// `(θ3, θ4)` at the branch's position (atan2 of the coupler and rocker vectors).
    fn angles(&self) -> (f64, f64) {
        let [pa, pb] = [self.a[0], self.b[0]];
        ((pb[1] - pa[1]).atan2(pb[0] - pa[0]), pb[1].atan2(pb[0] - LENGTHS[3]))
    }

    /// `θ̈2` of the one-coordinate reduction `L = ½ M(θ) θ̇² − V(θ)`:
    /// `M θ̈ + ½ M' θ̇² + V' = 0` with `M = Σ m |c'|² + I φ'²` and `½ M' = Σ m c'·c'' + I φ' φ''`
    /// over the crank (centre `A/2`, `φ' = 1`), the coupler (centre `(A + B)/2`) and the
    /// rocker (centre `(O4 + B)/2`), `V' = g Σ m c'_y`.
    fn crank_acceleration(&self, rate: f64, gravity: f64) -> f64 {
        let [a, b, c, _] = LENGTHS;
        let inertia = |l: f64| LINK_MASS * l * l / 12.0;
        let half = |u: [f64; 2], v: [f64; 2]| [0.5 * (u[0] + v[0]), 0.5 * (u[1] + v[1])];
        let zero = [0.0; 2];
        // (c', c'', I, φ', φ'') of each link.
        let links = [
            (half(self.a[1], zero), half(self.a[2], zero), inertia(a), [1.0, 0.0]),
            (half(self.a[1], self.b[1]), half(self.a[2], self.b[2]), inertia(b), self.coupler),
            (half(self.b[1], zero), half(self.b[2], zero), inertia(c), self.rocker),
        ];
        let (mut mass, mut convective, mut weight) = (0.0, 0.0, 0.0);
        for (v1, v2, inertia, [turn, turn2]) in links {
            mass += LINK_MASS * dot(v1, v1) + inertia * turn * turn;
            convective += LINK_MASS * dot(v1, v2) + inertia * turn * turn2;
            weight += LINK_MASS * gravity * v1[1];
        }
        -(convective * rate * rate + weight) / mass
    }
}

impl ChangePointFourBar {
    /// `[a, b, c, d]` ([`LENGTHS`]).
    pub fn lengths(&self) -> [f64; 4] {
        LENGTHS
    }

    /// The consistent state at crank angle `θ2` and rate `θ̇2` on the analytic branch with
    /// `σ = 1` (mode by `θ2` mod 4π): `θ3`, `θ4` from `B`, `θ̇3 = θ3' θ̇2`, `θ̇4 = θ4' θ̇2` —
    /// also at the change point, where the velocity equations of [`FourBar::state_at`] are
    /// singular.
    pub fn state_at(&self, t: f64, theta_2: f64, rate: f64) -> State {
        let branch = Branch::at(theta_2, 1.0);
        let (theta_3, theta_4) = branch.angles();
        State::new(t, [theta_2, theta_3, theta_4], [rate, branch.coupler[0] * rate, branch.rocker[0] * rate])
    }

    /// The mode `σ = ±1` of a consistent state: its `B` is `A + α δ + β δ⊥` with
    /// `β E = cross(δ, B − A) = σ sin(θ2/2) r` and `d/dt (β E) = σ (sin(θ2/2) r)' θ̇2`, so
    /// `σ = sign(cross · w r + rate · (w r)' θ̇2)` (both terms have the sign of `σ`, and one of
    /// them is nonzero unless the crank is at rest at the change point: `None`).
    fn mode(&self, q: &[f64], qdot: &[f64]) -> Option<f64> {
        let [a, b, _, d] = LENGTHS;
        let (s2, c2) = q[0].sin_cos();
        let delta = [d - a * c2, -a * s2];
        let coupler = [b * q[1].cos(), b * q[1].sin()];
        let offset = cross(delta, coupler);
        let rate = cross([a * s2 * qdot[0], -a * c2 * qdot[0]], coupler) + cross(delta, perp(coupler)) * qdot[1];
        let (wr, wr1) = offset_and_rate(q[0]);
        let sign = offset * wr + rate * wr1 * qdot[0];
        (sign != 0.0).then(|| sign.signum())
    }

    /// `q̈` in closed form by the one-coordinate reduction on the state's branch: `θ̈2` from
    /// `M(θ2) θ̈2 + ½ M'(θ2) θ̇2² + V'(θ2) = 0`, then `θ̈3 = θ3' θ̈2 + θ3'' θ̇2²` and
    /// `θ̈4 = θ4' θ̈2 + θ4'' θ̇2²`, every derivative along the analytic branch written out by
    /// hand (no automatic differentiation, no engine). Regular at the change point, where the
    /// constrained form's KKT system is singular; NaN for a crank at rest there (the two modes
    /// then ask different accelerations).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 3 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 3] {
        assert!(q.len() == 3 && qdot.len() == 3, "q and q̇ must have 3 entries");
        let Some(sigma) = self.mode(q, qdot) else { return [f64::NAN; 3] };
        let branch = Branch::at(q[0], sigma);
        let alpha = branch.crank_acceleration(qdot[0], self.gravity);
        let square = qdot[0] * qdot[0];
        [
            alpha,
            branch.coupler[0] * alpha + branch.coupler[1] * square,
            branch.rocker[0] * alpha + branch.rocker[1] * square,
        ]
    }

    /// The constrained four-bar with these lengths (its hand-coded KKT solve
    /// [`FourBar::closed_form_with_multipliers`], its energy, its residuals).
    pub fn four_bar(&self) -> &FourBar {
        &self.four_bar
    }

    /// The same linkage in its crank angle alone, on the analytic branch ([`ChangePointCrank`]).
    pub fn crank_model(&self) -> ChangePointCrank {
        let description = Description {
            coordinates: vec![Coordinate::angle("θ2")],
            bodies: self.four_bar.description().bodies.clone(),
            gravity: self.gravity,
            ..Description::default()
        };
        ChangePointCrank { scene: self.clone(), description }
    }
}

delegate_mechanism!(ChangePointFourBar, four_bar);

impl SceneType for ChangePointFourBar {
    const ID: &'static str = "change_point_four_bar";
    const TITLE: &'static str = "Change-point four-bar (a + b = c + d), flat once per crank turn";
    const REFERENCE: &'static str = "docs/scenes.md#change_point_four_bar; beyond the lecture (Grashof's equality: the \
                                     loop constraints lose rank in the flat position and the linkage changes its \
                                     assembly mode there; Norton, Design of Machinery, §2.13)";
    param_table!();

    /// [`ChangePointFourBar::closed_form_accelerations`].
    fn closed_form(&self, _t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
        qddot.copy_from_slice(&self.closed_form_accelerations(q, qdot));
    }

    /// `θ2 = π/3`, `θ̇2 = ω0` (5 rad/s: the crank turns over, reaching the change point
    /// `θ2 = 2π` after about 0.95 s), the rest from [`ChangePointFourBar::state_at`].
    fn default_state(&self) -> State {
        self.state_at(0.0, FRAC_PI_3, self.crank_speed)
    }

    /// `E = T + V` ([`FourBar::energy`] with no torque).
    fn conserves_energy(&self) -> Vec<Conserved> {
        vec![Conserved::energy(self, |s, q, qdot| s.four_bar.energy(q, qdot))]
    }

    body_scene!(engine);

    /// [`FourBar`]'s graph (pins at `O2`, `A`, `O4`, the pin at `B` closing the loop) under this
    /// scene's id.
    fn joint_graph(&self) -> Option<JointGraph> {
        let mut graph = self.four_bar.joint_graph()?;
        graph.name = Self::ID.into();
        Some(graph)
    }
}

/// The change-point four-bar in its crank angle alone, `q = (θ2)`, on the analytic branch with
/// `σ = 1` (so its mode follows `θ2` mod 4π): coupler and rocker are placed from `θ2` by the
/// branch's `B = A + α δ + β δ⊥` inside the poses, which the engine differentiates. Regular at
/// the change point. Not a registered scene: the reference the constrained scene is checked
/// against through the change point.
#[derive(Clone, Debug, PartialEq)]
pub struct ChangePointCrank {
    scene: ChangePointFourBar,
    /// `θ2` alone; the four-bar's bodies and the scene's gravity, no constraints.
    description: Description,
}

impl Mechanism for ChangePointCrank {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let [a, b, c, d] = LENGTHS;
        let theta = q[0];
        // A, δ = O4 − A, E = |δ|², then B = A + α δ + β δ⊥.
        let (ax, ay) = (theta.cos() * a, theta.sin() * a);
        let (dx, dy) = (-ax + d, -ay);
        let e = dx * dx + dy * dy;
        let alpha = e.recip() * (0.5 * (b * b - c * c)) + 0.5;
        let beta = (theta * 0.5).sin() * ((-e + (b + c) * (b + c)) * (a * d)).sqrt() / e;
        let (bx, by) = (ax + dx * alpha - dy * beta, ay + dy * alpha + dx * beta);
        let (theta_3, theta_4) = ((by - ay).atan2(bx - ax), by.atan2(bx - d));
        world_from_body[0] = Pose::new(ax * 0.5, ay * 0.5, theta);
        world_from_body[1] = Pose::new((ax + bx) * 0.5, (ay + by) * 0.5, theta_3);
        world_from_body[2] = Pose::new((bx + d) * 0.5, by * 0.5, theta_4);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{ENGINE_VS_CLOSED_FORM, assert_close, max_abs};
    use lagrange::{Method, Model, Output, Tolerances, accelerations};
    use std::f64::consts::{PI, TAU};

    fn scene() -> ChangePointFourBar {
        ChangePointFourBar::from_params(&scene_of::<ChangePointFourBar>().default_params()).unwrap()
    }

    /// Crank angles in both modes, away from the change point (`θ2 = 0` mod 2π), with rates.
    fn regular_states() -> Vec<(f64, f64)> {
        let mut states = Vec::new();
        for turn in [0.0, TAU] {
            for (theta, rate) in [(FRAC_PI_3, 5.0), (2.0, -3.0), (PI, 1.0), (4.5, 0.0), (0.3, 7.0), (TAU - 0.2, -2.0)] {
                states.push((theta + turn, rate));
            }
        }
        states
    }

    /// The branch's states satisfy the loop closure and its rate (hand-coded residuals of the
    /// four-bar) to round-off: 16 ε of the lengths (sums of a few terms of size ≤ 4 m), 64 ε of
    /// the rate — including at the change point, where the branch's velocities are still
    /// well defined.
    #[test]
    fn states_on_the_branch_are_consistent_in_both_modes() {
        let s = scene();
        for (theta, rate) in regular_states().into_iter().chain([(0.0, 3.0), (TAU, -2.0), (1e-7, 1.0)]) {
            let state = s.state_at(0.0, theta, rate);
            let (phi, rates) = s.four_bar().residuals(&state.q, &state.qdot);
            assert!(max_abs(&phi) <= 16.0 * 4.0 * f64::EPSILON, "θ2 = {theta}: Φ = {phi:?}");
            assert!(max_abs(&rates) <= 64.0 * f64::EPSILON * (1.0 + rate.abs()), "θ2 = {theta}: {rates:?}");
            // B left of A → O4 on the first turn, right of it on the second.
            let branch = Branch::at(theta, 1.0);
            let side = cross(
                [LENGTHS[3] - branch.a[0][0], -branch.a[0][1]],
                [branch.b[0][0] - branch.a[0][0], branch.b[0][1] - branch.a[0][1]],
            );
            let expected = (0.5 * theta).sin().signum();
            assert!(theta.rem_euclid(TAU) < 1e-6 || side.signum() == expected, "θ2 = {theta}: side {side}");
        }
    }

    /// At regular states of both modes, three routes to `q̈` agree: the engine on the
    /// constrained scene, the hand-coded KKT solve of [`FourBar`], and this scene's hand-coded
    /// one-coordinate reduction. Bound [`ENGINE_VS_CLOSED_FORM`] relative to the largest `|q̈|`:
    /// exact formulas for the same `q̈`, a few hundred operations each, apart by round-off that
    /// the KKT system's conditioning amplifies as the change point nears (`G` loses rank as
    /// `sin(θ2/2)`); at the closest states here (0.2 rad from it) the differences measured at
    /// most 4e-15.
    #[test]
    fn engine_kkt_and_reduction_agree_away_from_the_change_point() {
        let s = scene();
        let model = Model::new(s.clone()).unwrap();
        let mut ws = model.workspace();
        for (theta, rate) in regular_states() {
            let state = s.state_at(0.0, theta, rate);
            let reduced = s.closed_form_accelerations(&state.q, &state.qdot);
            let engine = accelerations(&model, &mut ws, 0.0, &state.q, &state.qdot).unwrap().to_vec();
            let (kkt, _) = s.four_bar().closed_form_with_multipliers(&state.q, &state.qdot);
            let bound = ENGINE_VS_CLOSED_FORM * max_abs(&reduced);
            assert_close(&format!("θ2 = {theta}: KKT vs reduction"), &reduced, &kkt, bound);
            assert_close(&format!("θ2 = {theta}: engine vs reduction"), &reduced, &engine, bound);
        }
    }

    /// The hand-coded reduction against the engine on [`ChangePointCrank`] (the same
    /// reduction, differentiated by AD through the poses), also at and next to the change
    /// point: `θ̈2` to [`ENGINE_VS_CLOSED_FORM`] relative; both are regular there, a
    /// one-coordinate model with `M(θ2)` ≥ 1/3 kg m² (measured differences ≤ 1e-14).
    #[test]
    fn reduction_matches_the_one_coordinate_model_through_the_change_point() {
        let s = scene();
        let one = Model::new(s.crank_model()).unwrap();
        let mut ws = one.workspace();
        let near = [(0.0, 3.0), (TAU, -2.0), (1e-6, 4.0), (-1e-6, 4.0), (TAU + 1e-3, 1.0), (-0.05, 6.0)];
        for (theta, rate) in regular_states().into_iter().chain(near) {
            let state = s.state_at(0.0, theta, rate);
            let reduced = s.closed_form_accelerations(&state.q, &state.qdot);
            let engine = accelerations(&one, &mut ws, 0.0, &[theta], &[rate]).unwrap()[0];
            let bound = ENGINE_VS_CLOSED_FORM * reduced[0].abs().max(1.0);
            assert_close(&format!("θ2 = {theta}"), &reduced[..1], &[engine], bound);
        }
    }

    /// The closed form reads the mode off the state: the same crank angle in the other mode is
    /// the crank angle plus 2π in this one, and a crank at rest at the change point has none.
    #[test]
    fn the_mode_comes_from_the_state() {
        let s = scene();
        for (theta, rate) in [(1.0, 2.0), (4.0, -1.0), (0.0, 3.0)] {
            let other = s.state_at(0.0, theta + TAU, rate);
            let q = [theta, other.q[1], other.q[2]];
            let shifted = s.closed_form_accelerations(&other.q, &other.qdot);
            let here = s.closed_form_accelerations(&q, &other.qdot);
            // Same state up to 2π in θ2: bit-for-bit the same except sin(θ2/2) changes sign.
            assert_close(&format!("θ2 = {theta}"), &shifted, &here, 1e-13 * max_abs(&shifted).max(1.0));
        }
        assert!(s.closed_form_accelerations(&s.state_at(0.0, 0.0, 0.0).q, &[0.0; 3]).iter().all(|a| a.is_nan()));
    }

    /// `E = T + V` along the one-coordinate model over 3 s (Dop853, tol 1e-12), mapped onto the
    /// branch: constant to 1e-9 relative (the integrator's error at this tolerance over ~10³
    /// steps), through three change points.
    #[test]
    fn energy_is_conserved_through_the_change_point_by_the_one_coordinate_model() {
        let s = scene();
        let one = Model::new(s.crank_model()).unwrap();
        let start = s.default_state();
        let method = Method::Dop853 { tol: Tolerances::uniform(1e-12) };
        let run = lagrange::simulate(
            &one,
            &State::new(0.0, [start.q[0]], [start.qdot[0]]),
            3.0,
            method,
            &Output::Every(0.05),
        )
        .unwrap();
        let e0 = s.four_bar().energy(&start.q, &start.qdot);
        let mut passed = 0;
        for k in 0..run.len() {
            let state = s.state_at(run.t[k], run.q(k)[0], run.qdot(k)[0]);
            let e = s.four_bar().energy(&state.q, &state.qdot);
            assert!((e - e0).abs() <= 1e-9 * e0.abs(), "t = {}: E = {e} vs {e0}", run.t[k]);
            passed = passed.max((run.q(k)[0] / TAU).floor() as i32);
        }
        assert!(passed >= 1, "the default motion reaches the change point within 3 s");
    }

    /// The constrained scene through the change point: the engine's trajectory follows the
    /// one-coordinate model (which changes mode there) over 3 s.
    // needs the singular-configuration solver
    #[test]
    #[ignore = "needs the singular-configuration solver"]
    fn constrained_trajectory_follows_the_reduction_through_the_change_point() {
        let s = scene();
        let constrained = Model::new(s.clone()).unwrap();
        let one = Model::new(s.crank_model()).unwrap();
        let start = s.default_state();
        let (method, output) = (Method::Dop853 { tol: Tolerances::uniform(1e-12) }, Output::Every(0.05));
        let a = lagrange::simulate(&constrained, &start, 3.0, method, &output).unwrap();
        let b =
            lagrange::simulate(&one, &State::new(0.0, [start.q[0]], [start.qdot[0]]), 3.0, method, &output).unwrap();
        for k in 0..a.len() {
            let expected = s.state_at(b.t[k], b.q(k)[0], b.qdot(k)[0]);
            let wrap = |x: f64| (x + PI).rem_euclid(TAU) - PI;
            let q: Vec<f64> = a.q(k).iter().zip(&expected.q).map(|(x, y)| wrap(x - y)).collect();
            // Both runs at tol 1e-12 over ~10³ steps: 1e-8 leaves room for their global errors.
            assert!(max_abs(&q) <= 1e-8, "t = {}: {:?} vs {:?}", a.t[k], a.q(k), expected.q);
        }
    }

    /// At the change point the engine's constrained `q̈` must be the branch's.
    // needs the singular-configuration solver
    #[test]
    #[ignore = "needs the singular-configuration solver"]
    fn engine_matches_the_reduction_at_the_change_point() {
        let s = scene();
        let model = Model::new(s.clone()).unwrap();
        let mut ws = model.workspace();
        for (theta, rate) in [(0.0, 3.0), (TAU, -2.0), (1e-9, 5.0)] {
            let state = s.state_at(0.0, theta, rate);
            let reduced = s.closed_form_accelerations(&state.q, &state.qdot);
            let engine = accelerations(&model, &mut ws, 0.0, &state.q, &state.qdot).unwrap().to_vec();
            assert_close(&format!("θ2 = {theta}"), &reduced, &engine, ENGINE_VS_CLOSED_FORM * max_abs(&reduced));
        }
    }
}
