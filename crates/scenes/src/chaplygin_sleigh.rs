//! The Chaplygin sleigh: a rigid body on a knife edge, one velocity (non-holonomic) constraint
//! (docs/scenes.md#chaplygin_sleigh).

use crate::checks::fixed;
use crate::params::{param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, SceneType};
use lagrange::{Body, Coordinate, Description, Mechanism, Pose, Scalar, State};

/// Gauss–Legendre points per panel of the position quadrature in [`ChaplyginSleigh::exact_solution`].
const QUADRATURE_POINTS: usize = 12;

/// A velocity-constraint residual `|−sinφ ẋ + cosφ ẏ + a φ̇|` above this, relative to the
/// speeds, makes the initial state off the constraint: the exact solution is then not given.
const CONSISTENT: f64 = 1e-12;

scene_params! {
    /// A rigid body of mass `m` and inertia `I` about its centre of mass `C = (x, y)`, heading
    /// `φ`, in a horizontal plane (no gravity); body axis `e = (cosφ, sinφ)`, normal
    /// `n = (−sinφ, cosφ)`. A knife edge at `P = C + a e` lets `P` move only along `e`:
    /// `v_P · n = 0`, i.e. the velocity constraint `−sinφ ẋ + cosφ ẏ + a φ̇ = 0`;
    /// `q = (x, y, φ)` (docs/scenes.md#chaplygin_sleigh).
    pub struct ChaplyginSleigh {
        /// Mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the sleigh"],
        /// Moment of inertia `I` about the centre of mass (kg m²).
        pub inertia: f64 = ["I", "kg m²", 0.1, Domain::Positive, "moment of inertia about the centre of mass"],
        /// Offset `a` of the knife edge ahead of the centre of mass along the body axis (m).
        pub offset: f64 = ["a", "m", 0.5, Domain::Finite, "distance of the knife edge ahead of the centre of mass"],
    }
    /// A sleigh with mass `m`, inertia `I` and knife-edge offset `a`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("x"), Coordinate::length("y"), Coordinate::angle("φ")],
            bodies: vec![Body::rigid("sleigh", mass, inertia)],
            velocity_constraints: vec!["knife edge: v_P · n = 0".into()],
            ..Description::default()
        },
    }
}

/// The sleigh's motion in its body frame at time `τ` after the start: forward speed `u`,
/// angular velocity `ω` and heading `φ` (docs/scenes.md#chaplygin_sleigh).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SleighMotion {
    /// Forward speed `u = v_C · e = v_P · e` (m/s).
    pub speed: f64,
    /// Angular velocity `ω = φ̇` (rad/s).
    pub angular_velocity: f64,
    /// Heading `φ` (rad).
    pub heading: f64,
}

impl ChaplyginSleigh {
    /// `q̈` and the multiplier `λ` of `M q̈ + Aᵀ λ = 0`, `A q̈ = −γ` with `M = diag(m, m, I)`,
    /// `A = (−sinφ, cosφ, a)` and `γ = (∂(A q̇)/∂q) q̇ = −u ω`, `u = ẋ cosφ + ẏ sinφ`, at any
    /// state: `q̈ = −M⁻¹Aᵀλ` in `A q̈ = u ω` gives `λ = −u ω / (1/m + a²/I)`, then
    /// `ẍ = λ sinφ / m`, `ÿ = −λ cosφ / m`, `φ̈ = −a λ / I` (the knife edge pushes on `P`
    /// with the force `−λ n`).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 3 entries.
    pub fn accelerations_and_multiplier(&self, q: &[f64], qdot: &[f64]) -> ([f64; 3], f64) {
        let [_, _, phi] = fixed(q, "q");
        let [vx, vy, omega] = fixed(qdot, "q̇");
        let (m, inertia, a) = (self.mass, self.inertia, self.offset);
        let (sin, cos) = phi.sin_cos();
        let speed = vx * cos + vy * sin;
        let lambda = -speed * omega * m * inertia / (inertia + m * a * a);
        ([lambda * sin / m, -lambda * cos / m, -a * lambda / inertia], lambda)
    }

    /// `(ẍ, ÿ, φ̈)` in closed form; see [`accelerations_and_multiplier`](Self::accelerations_and_multiplier).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 3 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 3] {
        self.accelerations_and_multiplier(q, qdot).0
    }

    /// `J = I + m a²`, the inertia about the knife edge.
    fn inertia_about_edge(&self) -> f64 {
        self.inertia + self.mass * self.offset * self.offset
    }

    /// The forward speed `u`, angular velocity `ω` and heading `φ` a time `tau` after the state
    /// `(u₀, ω₀, φ₀)`, exactly. With `J = I + m a²` the equations are `u̇ = −a ω²` and
    /// `J ω̇ = m a u ω`, the energy `E = ½ m u² + ½ J ω²` is conserved, and with
    /// `U = √(2E/m)`, `k = m a U / J`, `c = atanh(u₀/U)`, `w = c − k τ`:
    /// `u = U tanh w`, `ω = sgn(ω₀) √(m/J) U sech w`,
    /// `φ = φ₀ + sgn(ω₀) (√(J/m)/a) (gd c − gd w)` (`gd w = 2 atan(tanh(w/2))`, the
    /// Gudermannian). Special cases: `ω₀ = 0` is straight motion at `u₀`, `a = 0` turning at
    /// constant `u₀` and `ω₀` (docs/scenes.md#chaplygin_sleigh).
    pub fn motion(&self, speed: f64, angular_velocity: f64, heading: f64, tau: f64) -> SleighMotion {
        let (m, a) = (self.mass, self.offset);
        let j = self.inertia_about_edge();
        if angular_velocity == 0.0 {
            return SleighMotion { speed, angular_velocity, heading };
        }
        if a == 0.0 {
            return SleighMotion { speed, angular_velocity, heading: heading + angular_velocity * tau };
        }
        let limit = (speed * speed + j / m * angular_velocity * angular_velocity).sqrt();
        let rate = m * a * limit / j;
        let start = (speed / limit).atanh();
        let w = start - rate * tau;
        let gudermannian = |w: f64| 2.0 * (0.5 * w).tanh().atan();
        let sign = angular_velocity.signum();
        SleighMotion {
            speed: limit * w.tanh(),
            angular_velocity: sign * (m / j).sqrt() * limit / w.cosh(),
            heading: heading + sign * (j / m).sqrt() / a * (gudermannian(start) - gudermannian(w)),
        }
    }

    /// `(ẋ, ẏ, φ̇)` of the motion: `v_C = u e − a ω n`.
    fn velocity(&self, motion: SleighMotion) -> [f64; 3] {
        let (sin, cos) = motion.heading.sin_cos();
        let (u, omega, a) = (motion.speed, motion.angular_velocity, self.offset);
        [u * cos + a * omega * sin, u * sin - a * omega * cos, omega]
    }
}

impl Mechanism for ChaplyginSleigh {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        world_from_body[0] = Pose::new(q[0], q[1], q[2]);
    }

    /// `v_P · n = −sinφ ẋ + cosφ ẏ + a φ̇`.
    fn velocity_constraint<S: Scalar>(&self, _t: S, q: &[S], qdot: &[S], residual: &mut [S]) {
        let (sin, cos) = q[2].sin_cos();
        residual[0] = -sin * qdot[0] + cos * qdot[1] + qdot[2] * self.offset;
    }
}

impl SceneType for ChaplyginSleigh {
    const ID: &'static str = "chaplygin_sleigh";
    const TITLE: &'static str = "Chaplygin sleigh (knife edge, one velocity constraint)";
    const REFERENCE: &'static str = "docs/scenes.md#chaplygin_sleigh; closed forms and the exact solution derived there (cf. Bloch, Nonholonomic Mechanics and Control, ch. 1)";
    param_table!();

    /// `x = y = φ = 0`, `ẋ = 1`, `φ̇ = 2`, `ẏ = −a φ̇` from the constraint.
    fn default_state(&self) -> State {
        State::new(0.0, [0.0, 0.0, 0.0], [1.0, -self.offset * 2.0, 2.0])
    }

    /// `u`, `ω`, `φ` from [`ChaplyginSleigh::motion`] (exact), the velocities from them, and
    /// the position `C(t) = C₀ + ∫ v_C dt` by composite Gauss–Legendre quadrature of those
    /// exact velocities (the position has no closed form in general): panels no wider than
    /// `π/(4k)` (an eighth of the strip of analyticity of `tanh`, `sech` and `gd`) and
    /// `0.5/max|ω|`, 12 points each, converged to round-off. `None` for an initial state off
    /// the constraint.
    fn exact_solution(&self, initial: &State, t: f64) -> Option<State> {
        let ([x0, y0, phi0], [vx, vy, omega0]) = (fixed(&initial.q, "q"), fixed(&initial.qdot, "q̇"));
        let (sin, cos) = phi0.sin_cos();
        let residual = -sin * vx + cos * vy + self.offset * omega0;
        let speeds = vx.abs().max(vy.abs()).max((self.offset * omega0).abs());
        if residual.abs() > CONSISTENT * speeds {
            return None;
        }
        let u0 = vx * cos + vy * sin;
        let tau = t - initial.t;
        let at = |s: f64| self.velocity(self.motion(u0, omega0, phi0, s));
        // Panel width from the motion's time scales.
        let j = self.inertia_about_edge();
        let limit = (u0 * u0 + j / self.mass * omega0 * omega0).sqrt();
        let rate = (self.mass * self.offset * limit / j).abs();
        let turning = (self.mass / j).sqrt() * limit + omega0.abs();
        let mut width = tau.abs();
        if rate > 0.0 {
            width = width.min(std::f64::consts::FRAC_PI_4 / rate);
        }
        if turning > 0.0 {
            width = width.min(0.5 / turning);
        }
        let panels = if width > 0.0 { (tau.abs() / width).ceil().max(1.0) } else { 1.0 };
        // Panels are a small count of a bounded time scale: the cast is exact.
        let (x, y) = gauss_legendre(at, tau, panels as usize);
        let motion = self.motion(u0, omega0, phi0, tau);
        Some(State::new(t, [x0 + x, y0 + y, motion.heading], self.velocity(motion)))
    }

    /// The energy `E = ½ m (ẋ² + ẏ²) + ½ I φ̇²` (the knife edge does no work).
    fn conserves_energy(&self) -> Vec<Conserved> {
        vec![Conserved::energy(self, |s, _q, v| 0.5 * (s.mass * (v[0] * v[0] + v[1] * v[1]) + s.inertia * v[2] * v[2]))]
    }

    body_scene!();
}

/// `(∫₀^τ v_x, ∫₀^τ v_y)` of `velocity(s) = (v_x, v_y, …)` by `panels` panels of
/// [`QUADRATURE_POINTS`]-point Gauss–Legendre.
fn gauss_legendre(velocity: impl Fn(f64) -> [f64; 3], tau: f64, panels: usize) -> (f64, f64) {
    let (nodes, weights) = legendre_nodes();
    let width = tau / panels as f64;
    let (mut x, mut y) = (0.0, 0.0);
    for p in 0..panels {
        let middle = (p as f64 + 0.5) * width;
        for (node, weight) in nodes.iter().zip(&weights) {
            let v = velocity(middle + 0.5 * width * node);
            x += 0.5 * width * weight * v[0];
            y += 0.5 * width * weight * v[1];
        }
    }
    (x, y)
}

/// The nodes and weights of [`QUADRATURE_POINTS`]-point Gauss–Legendre on `[−1, 1]`: Newton's
/// iteration on `P_n` from Chebyshev guesses, to round-off.
fn legendre_nodes() -> ([f64; QUADRATURE_POINTS], [f64; QUADRATURE_POINTS]) {
    let n = QUADRATURE_POINTS;
    let (mut nodes, mut weights) = ([0.0; QUADRATURE_POINTS], [0.0; QUADRATURE_POINTS]);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let k = k as f64;
                (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
            }
            derivative = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let step = p1 / derivative;
            x -= step;
            if step.abs() <= 1e-16 {
                break;
            }
        }
        nodes[i] = x;
        weights[i] = 2.0 / ((1.0 - x * x) * derivative * derivative);
    }
    (nodes, weights)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{assert_close, assert_engine_matches_closed_form_along, assert_exact_solution_consistent};
    use lagrange::{Method, Output, Tolerances};

    #[test]
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<ChaplyginSleigh, 3>(
            &[
                (0.5, [0.3, -0.2, 0.7], [1.2, -0.5, 0.4]),
                (1.0, [2.0, 1.9, -2.5], [-3.0, 2.0, 1.1]),
                (3.0, [4.5, -0.7, 4.0], [0.7, 0.1, -2.0]),
            ],
            &[("m", 2.5), ("I", 0.03), ("a", -0.3), ("a", 0.0)],
        );
    }

    /// The quadrature's nodes and weights integrate `x^k` exactly to degree `2n − 1`.
    #[test]
    fn gauss_legendre_is_exact_for_polynomials() {
        let (nodes, weights) = legendre_nodes();
        for k in 0..2 * QUADRATURE_POINTS as i32 {
            let sum: f64 = nodes.iter().zip(&weights).map(|(x, w)| w * x.powi(k)).sum();
            let exact = if k % 2 == 0 { 2.0 / f64::from(k + 1) } else { 0.0 };
            assert!((sum - exact).abs() <= 1e-15, "x^{k}: {sum} vs {exact}");
        }
    }

    /// `dq/dt = q̇` and `dq̇/dt = q̈` along the exact solution, for the default sleigh, a
    /// knife edge behind the centre (`a < 0`), and the special cases `a = 0`, `ω₀ = 0`.
    #[test]
    fn exact_solution_is_consistent() {
        let scene = scene_of::<ChaplyginSleigh>();
        for (changes, initial) in [
            (vec![], State::new(0.0, [0.0, 0.0, 0.0], [1.0, -1.0, 2.0])),
            (vec![("a", -0.3), ("I", 0.05)], State::new(0.4, [0.3, -1.0, 0.8], [-0.3, 0.0, 1.5])),
            (vec![("a", 0.0)], State::new(0.0, [0.0, 1.0, 0.5], [0.5_f64.cos(), 0.5_f64.sin(), -1.3])),
            (vec![], State::new(0.0, [0.0, 0.0, 0.2], [0.2_f64.cos(), 0.2_f64.sin(), 0.0])),
        ] {
            let mut params = scene.default_params();
            for (key, value) in changes {
                params.set(key, value).unwrap();
            }
            let mut initial = initial;
            // ẏ from the constraint where the row above leaves it free.
            let (sin, cos) = initial.q[2].sin_cos();
            let a = params.get("offset");
            let along = initial.qdot[0] * cos + initial.qdot[1] * sin;
            initial.qdot[0] = along * cos + a * initial.qdot[2] * sin;
            initial.qdot[1] = along * sin - a * initial.qdot[2] * cos;
            assert_exact_solution_consistent(scene, &params, &initial, &[0.3, 1.7, 4.0]);
        }
        // Off the constraint: no exact solution.
        let params = scene.default_params();
        let off = State::new(0.0, [0.0, 0.0, 0.0], [1.0, 0.0, 2.0]);
        assert_eq!(scene.exact_solution(&params, &off, 1.0).unwrap(), None);
    }

    /// The tanh law itself: `u → −U` (the knife edge ends up trailing the centre), `ω → 0`,
    /// energy `½ m u² + ½ J ω²` constant, and `u̇ = −a ω²`, `J ω̇ = m a u ω` by central
    /// differences.
    #[test]
    fn speed_follows_the_tanh_law() {
        let sleigh = ChaplyginSleigh::new(1.0, 0.1, 0.5).unwrap();
        let j = sleigh.inertia_about_edge();
        let energy = |s: SleighMotion| 0.5 * (s.speed * s.speed + j * s.angular_velocity * s.angular_velocity);
        let e0 = energy(sleigh.motion(1.0, 2.0, 0.0, 0.0));
        let limit = (2.0 * e0).sqrt();
        let late = sleigh.motion(1.0, 2.0, 0.0, 40.0);
        assert_close("u(∞)", &[-limit], &[late.speed], 1e-12);
        assert!(late.angular_velocity.abs() < 1e-12, "{late:?}");
        for tau in [0.1, 0.9, 2.5] {
            let s = sleigh.motion(1.0, 2.0, 0.0, tau);
            assert_close("E", &[e0], &[energy(s)], 1e-14);
            let h = 1e-4;
            let (p, m) = (sleigh.motion(1.0, 2.0, 0.0, tau + h), sleigh.motion(1.0, 2.0, 0.0, tau - h));
            let du = (p.speed - m.speed) / (2.0 * h);
            let dw = (p.angular_velocity - m.angular_velocity) / (2.0 * h);
            let dphi = (p.heading - m.heading) / (2.0 * h);
            assert_close("u̇", &[-0.5 * s.angular_velocity * s.angular_velocity], &[du], 1e-7);
            assert_close("J ω̇", &[0.5 * s.speed * s.angular_velocity], &[j * dw], 1e-7);
            assert_close("φ̇", &[s.angular_velocity], &[dphi], 1e-7);
        }
    }

    /// The engine (adaptive, tol 1e-13, projection after every step) against the exact
    /// solution over 6 s, sampled every 0.1 s: forward speed and angular velocity to 1e-10
    /// (measured 8e-13), positions and heading to 1e-10; the velocity constraint at
    /// round-off; the energy constant to 1e-12 relative.
    #[test]
    fn engine_follows_the_exact_solution() {
        let scene = scene_of::<ChaplyginSleigh>();
        let params = scene.default_params();
        let sleigh = ChaplyginSleigh::from_params(&params).unwrap();
        let initial = sleigh.default_state();
        let mut system = scene.build(&params).unwrap();
        let method = Method::Dopri5 { tol: Tolerances::uniform(1e-13) };
        let run = system.simulate(&initial, 6.0, method, &Output::Every(0.1)).unwrap();
        let energy = |v: &[f64]| 0.5 * (v[0] * v[0] + v[1] * v[1] + 0.1 * v[2] * v[2]);
        let e0 = energy(&initial.qdot);
        let (mut worst_rates, mut worst_q): (f64, f64) = (0.0, 0.0);
        for k in 0..run.len() {
            let (q, qdot) = (run.q(k), run.qdot(k));
            let exact = sleigh.motion(1.0, 2.0, 0.0, run.t[k]);
            let speed = qdot[0] * q[2].cos() + qdot[1] * q[2].sin();
            let what = format!("t = {}", run.t[k]);
            let rates = [exact.speed, exact.angular_velocity];
            worst_rates = worst_rates.max(assert_close(&format!("{what}: u, ω"), &rates, &[speed, qdot[2]], 1e-10));
            let state = scene.exact_solution(&params, &initial, run.t[k]).unwrap().unwrap();
            worst_q = worst_q.max(assert_close(&format!("{what}: q"), &state.q, q, 1e-10));
            assert_close(&format!("{what}: q̇"), &state.qdot, qdot, 1e-10);
            let [_, violation] = system.constraint_violation(run.t[k], q, qdot).unwrap().unwrap();
            assert!(violation <= 1e-14, "{what}: violation {violation:e}");
            assert_close(&format!("{what}: E"), &[e0], &[energy(qdot)], 1e-12 * e0);
        }
        eprintln!("sleigh vs exact over 6 s: u, ω to {worst_rates:.1e}, q to {worst_q:.1e}");
    }
}
