//! A disc rolling without slipping down an incline, rolling written as a velocity constraint
//! (docs/scenes.md#rolling_disc).

use crate::checks::fixed;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::uniform_acceleration::uniformly_accelerated;
use crate::{Conserved, Domain, SceneType};
use lagrange::{Body, Coordinate, Description, Mechanism, Pose, Scalar, State};
use std::f64::consts::FRAC_PI_2;

scene_params! {
    /// A uniform disc of mass `m` and radius `R` (inertia `½ m R²` about its centre) rolling
    /// without slipping down an incline of angle `α` that descends towards −x; `q = (s, φ)`:
    /// the distance travelled down the incline and the disc's rotation (counter-clockwise).
    /// The centre is at `(−s cosα, −s sinα)`, so gravity gives `V = −m g s sinα`; rolling is
    /// the velocity constraint `ṡ − R φ̇ = 0` (integrable, but given as a velocity constraint)
    /// (docs/scenes.md#rolling_disc).
    pub struct RollingDisc {
        /// Disc mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the disc"],
        /// Disc radius `R` (m).
        pub radius: f64 = ["R", "m", 0.1, Domain::Positive, "radius of the disc"],
        /// Incline angle `α` (rad), `−π/2 < α < π/2`: 0 is flat ground (the disc rolls on at its
        /// speed), a negative angle an incline descending towards +x.
        pub incline: f64 = ["α", "rad", 0.3, Domain::OpenInterval(-FRAC_PI_2, FRAC_PI_2), "angle of the incline"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// A disc of mass `m` and radius `R` on an incline of angle `α` under gravity `g`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("s"), Coordinate::angle("φ")],
            bodies: vec![Body::rigid("disc", mass, 0.5 * mass * radius * radius)],
            gravity,
            velocity_constraints: vec!["rolling: ṡ = R φ̇".into()],
            ..Description::default()
        },
    }
}

impl RollingDisc {
    /// The disc's moment of inertia about its centre, `I = ½ m R²`.
    pub fn inertia(&self) -> f64 {
        0.5 * self.mass * self.radius * self.radius
    }

    /// The constant `(s̈, φ̈)`: `s̈ = g sinα / (1 + I/(m R²))` (`⅔ g sinα` for the uniform
    /// disc), `φ̈ = s̈ / R`, from `m s̈ + λ = m g sinα`, `I φ̈ − R λ = 0`, `s̈ = R φ̈`
    /// (docs/scenes.md#rolling_disc). The constraint's convective term vanishes (`A` is
    /// constant), so they hold at every state.
    pub fn qddot(&self) -> [f64; 2] {
        let (m, r) = (self.mass, self.radius);
        let along = self.gravity * self.incline.sin() / (1.0 + self.inertia() / (m * r * r));
        [along, along / r]
    }

    /// The multiplier `λ = m g sinα · I / (I + m R²)` (`⅓ m g sinα` for the uniform disc) of
    /// `M q̈ + Aᵀ λ = f` with `A = (1, −R)`: the constraint force is `−Aᵀλ = (−λ, R λ)`, i.e.
    /// the friction force at the contact point, of magnitude `λ`, pointing up the incline, whose
    /// moment about the centre is `R λ` (docs/scenes.md#rolling_disc).
    pub fn friction_force(&self) -> f64 {
        let (m, r, inertia) = (self.mass, self.radius, self.inertia());
        m * self.gravity * self.incline.sin() * inertia / (inertia + m * r * r)
    }

    /// `(s̈, φ̈)` in closed form (constant); see [`qddot`](Self::qddot).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        let _: ([f64; 2], [f64; 2]) = (fixed(q, "q"), fixed(qdot, "q̇"));
        self.qddot()
    }
}

impl Mechanism for RollingDisc {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (sin, cos) = self.incline.sin_cos();
        world_from_body[0] = Pose::new(-q[0] * cos, -q[0] * sin, q[1]);
    }

    /// `ṡ − R φ̇`.
    fn velocity_constraint<S: Scalar>(&self, _t: S, _q: &[S], qdot: &[S], residual: &mut [S]) {
        residual[0] = qdot[0] - qdot[1] * self.radius;
    }
}

impl SceneType for RollingDisc {
    const ID: &'static str = "rolling_disc";
    const TITLE: &'static str = "Disc rolling down an incline (rolling as a velocity constraint)";
    const REFERENCE: &'static str = "docs/scenes.md#rolling_disc; closed forms derived there";
    param_table!();

    /// At rest at `s = 0`, `φ = 0`.
    fn default_state(&self) -> State {
        State::new(0.0, [0.0, 0.0], [0.0, 0.0])
    }

    /// Uniform acceleration `q = q₀ + q̇₀ τ + ½ q̈ τ²` (`q̈` is constant at every state).
    fn exact_solution(&self, initial: &State, t: f64) -> Option<State> {
        Some(uniformly_accelerated(initial, &self.qddot(), t))
    }

    /// The energy `E = ½ m ṡ² + ½ I φ̇² − m g s sinα` (rolling friction does no work).
    fn conserves_energy(&self) -> Vec<Conserved> {
        vec![Conserved::energy(self, |s, q, v| {
            0.5 * (s.mass * v[0] * v[0] + s.inertia() * v[1] * v[1]) - s.mass * s.gravity * q[0] * s.incline.sin()
        })]
    }

    body_scene!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{assert_close, assert_engine_matches_closed_form_along, assert_exact_solution_consistent};
    use lagrange::{Method, Output, Tolerances};

    #[test]
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<RollingDisc, 2>(
            &crate::testing::PLANAR_ROWS,
            &[("m", 2.5), ("R", 0.35), ("alpha", 1.2), ("g", 1.6)],
        );
    }

    /// `λ` from the engine against `m g sinα I/(I + m R²)`, `⅓ m g sinα` for the uniform disc,
    /// and `s̈ = ⅔ g sinα`: round-off only.
    #[test]
    fn friction_force_is_the_multiplier() {
        let scene = scene_of::<RollingDisc>();
        for (m, r, alpha) in [(1.0, 0.1, 0.3), (2.5, 0.35, 1.2)] {
            let mut params = scene.default_params();
            for (key, value) in [("m", m), ("R", r), ("α", alpha)] {
                params.set(key, value).unwrap();
            }
            let disc = RollingDisc::from_params(&params).unwrap();
            let mut system = scene.build(&params).unwrap();
            let (q, qdot) = ([0.4, 4.0], [1.5, 15.0]);
            let lambda = system.constraint_multipliers(0.0, &q, &qdot).unwrap().unwrap()[0];
            let friction = m * 9.81 * alpha.sin() / 3.0;
            assert_close("λ", &[friction], &[lambda], 1e-14 * friction);
            assert_close("closed λ", &[friction], &[disc.friction_force()], 1e-15 * friction);
            assert_close("s̈", &[2.0 / 3.0 * 9.81 * alpha.sin()], &[disc.qddot()[0]], 1e-15 * 9.81);
        }
    }

    #[test]
    fn exact_solution_is_uniform_acceleration() {
        let params = scene_of::<RollingDisc>().default_params();
        for initial in [State::new(0.0, [0.0, 0.0], [0.0, 0.0]), State::new(0.4, [0.3, 2.0], [0.5, 5.0])] {
            assert_exact_solution_consistent(scene_of::<RollingDisc>(), &params, &initial, &[0.3, 1.7]);
        }
    }

    /// The engine's run (adaptive, tol 1e-12) against the exact uniform acceleration over 2 s:
    /// the integrator is exact for quadratic motion up to round-off and the projection keeps
    /// `ṡ = R φ̇`; bound 1e-12 (m, rad, and per second).
    #[test]
    fn trajectory_matches_the_exact_solution() {
        let scene = scene_of::<RollingDisc>();
        let params = scene.default_params();
        let initial = scene.default_state(&params).unwrap();
        let mut system = scene.build(&params).unwrap();
        let method = Method::Dopri5 { tol: Tolerances::uniform(1e-12) };
        let run = system.simulate(&initial, 2.0, method, &Output::Every(0.1)).unwrap();
        for k in 0..run.len() {
            let exact = scene.exact_solution(&params, &initial, run.t[k]).unwrap().unwrap();
            let what = format!("t = {}", run.t[k]);
            assert_close(&format!("{what}: q"), &exact.q, run.q(k), 1e-12);
            assert_close(&format!("{what}: q̇"), &exact.qdot, run.qdot(k), 1e-12);
            let [_, violation] = system.constraint_violation(run.t[k], run.q(k), run.qdot(k)).unwrap().unwrap();
            assert!(violation <= 1e-14, "{what}: {violation:e}");
        }
    }
}
