//! Andrews' squeezing mechanism: seven bodies in seven angles with six loop-closure
//! constraints, a spring and a driving torque (beyond the lecture; docs/scenes.md#andrews_squeezer),
//! written from the bodies' poses, with the published reference values of the standard test
//! problem.

use crate::linkage::{LinkBody, Linkage, Point};
use crate::params::{param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, Invariant, SceneType};
use lagrange::graph::{self, ForceElement, GROUND, GraphJoint, JointGraph, Profile};
use lagrange::{Body, Coordinate, Description, Error, Loads, Mechanism, Pose, Scalar, State};

/// The consistent initial angles `(β, Θ, γ, Φ, δ, Ω, ε)` at `t = 0` (at rest), as published
/// with the test problem (docs/scenes.md#andrews_squeezer).
// The digits as published (rounded to the nearest f64 on reading).
#[allow(clippy::excessive_precision)]
pub const INITIAL_ANGLES: [f64; 7] = [
    -0.0617138900142764496358948458001,
    0.0,
    0.455279819163070380255912382449,
    0.222668390165885884674473185609,
    0.487364979543842550225598953530,
    -0.222668390165885884674473185609,
    1.23054744454982119249735015568,
];

/// The published consistent initial accelerations `q̈(0)`.
// The digits as published (rounded to the nearest f64 on reading).
#[allow(clippy::excessive_precision)]
pub const PUBLISHED_INITIAL_ACCELERATIONS: [f64; 7] =
    [14222.4439199541138705911625887, -10666.8329399655854029433719415, 0.0, 0.0, 0.0, 0.0, 0.0];

/// The published consistent initial multipliers `λ(0)` (convention `M q̈ + Gᵀ λ = f`,
/// `G = ∂Φ/∂q`; `λ(1:2)` is the force of the connecting rod K2 on K3 at E, and so on).
// The digits as published (rounded to the nearest f64 on reading).
#[allow(clippy::excessive_precision)]
pub const PUBLISHED_INITIAL_MULTIPLIERS: [f64; 6] =
    [98.5668703962410896057654982170, -6.12268834425566265503114393122, 0.0, 0.0, 0.0, 0.0];

/// The published solution at `t = 0.03` (angles, then angular rates), computed with PSIDE at
/// `rtol = atol = 1e-14`; accurate to about 3e-10 relative.
pub const PUBLISHED_AT_0_03: [[f64; 7]; 2] = [
    [
        15.81077119629904,
        -15.75637105984298,
        0.04082224013073101,
        -0.5347301163226948,
        0.5244099658805304,
        0.5347301163226948,
        1.048080741042263,
    ],
    [
        1139.920302151208,
        -1424.379294994111,
        11.03291221937134,
        19.29337464421385,
        0.5735699284790808,
        -19.29337464421385,
        0.3231791658026955,
    ],
];

scene_params! {
    /// Andrews' squeezing mechanism: seven rigid bodies K1 … K7 in the plane (no gravity), a
    /// crank K1 driven by a constant torque `mom`, a spring from the fixed point C to the point
    /// D of K3. `q = (β, Θ, γ, Φ, δ, Ω, ε)`; `Θ`, `Φ`, `Ω` are relative angles: the bodies' angles
    /// are `β`, `β + Θ`, `γ`, `Φ + δ`, `δ`, `Ω + ε`, `ε`. Six constraints: the point E reached
    /// through K3, through K5 and K4, and through K7 and K6 coincides with E at the end of the
    /// connecting rod K2. Parameters are named as in the test problem; lengths in m, masses in
    /// kg, inertias in kg m².
    pub struct AndrewsSqueezer {
        /// Mass of K1 (crank).
        pub m1: f64 = ["m1", "kg", 0.04325, Domain::Positive, "mass of K1 (crank)"],
        /// Mass of K2 (connecting rod).
        pub m2: f64 = ["m2", "kg", 0.00365, Domain::Positive, "mass of K2 (connecting rod)"],
        /// Mass of K3.
        pub m3: f64 = ["m3", "kg", 0.02373, Domain::Positive, "mass of K3 (triangle pivoted at B)"],
        /// Mass of K4.
        pub m4: f64 = ["m4", "kg", 0.00706, Domain::Positive, "mass of K4 (rod G–E)"],
        /// Mass of K5.
        pub m5: f64 = ["m5", "kg", 0.07050, Domain::Positive, "mass of K5 (triangle pivoted at A)"],
        /// Mass of K6.
        pub m6: f64 = ["m6", "kg", 0.00706, Domain::Positive, "mass of K6 (rod H–E)"],
        /// Mass of K7.
        pub m7: f64 = ["m7", "kg", 0.05498, Domain::Positive, "mass of K7 (triangle pivoted at A)"],
        /// Inertia of K1 about its centre of mass.
        pub i1: f64 = ["i1", "kg m²", 2.194e-6, Domain::Positive, "inertia of K1 about its centre"],
        /// Inertia of K2.
        pub i2: f64 = ["i2", "kg m²", 4.410e-7, Domain::Positive, "inertia of K2 about its centre"],
        /// Inertia of K3.
        pub i3: f64 = ["i3", "kg m²", 5.255e-6, Domain::Positive, "inertia of K3 about its centre"],
        /// Inertia of K4.
        pub i4: f64 = ["i4", "kg m²", 5.667e-7, Domain::Positive, "inertia of K4 about its centre"],
        /// Inertia of K5.
        pub i5: f64 = ["i5", "kg m²", 1.169e-5, Domain::Positive, "inertia of K5 about its centre"],
        /// Inertia of K6.
        pub i6: f64 = ["i6", "kg m²", 5.667e-7, Domain::Positive, "inertia of K6 about its centre"],
        /// Inertia of K7.
        pub i7: f64 = ["i7", "kg m²", 1.912e-5, Domain::Positive, "inertia of K7 about its centre"],
        /// x of the fixed pivot A (of K5 and K7).
        pub xa: f64 = ["xa", "m", -0.06934, Domain::Finite, "x of the fixed pivot A"],
        /// y of A.
        pub ya: f64 = ["ya", "m", -0.00227, Domain::Finite, "y of the fixed pivot A"],
        /// x of the fixed pivot B (of K3).
        pub xb: f64 = ["xb", "m", -0.03635, Domain::Finite, "x of the fixed pivot B"],
        /// y of B.
        pub yb: f64 = ["yb", "m", 0.03273, Domain::Finite, "y of the fixed pivot B"],
        /// x of the spring's fixed end C.
        pub xc: f64 = ["xc", "m", 0.014, Domain::Finite, "x of the spring's fixed end C"],
        /// y of C.
        pub yc: f64 = ["yc", "m", 0.072, Domain::Finite, "y of the spring's fixed end C"],
        /// Length of K2 from P1 to E.
        pub d: f64 = ["d", "m", 0.028, Domain::Positive, "length of K2, P1 to E"],
        /// Centre of mass of K2 from P1.
        pub da: f64 = ["da", "m", 0.0115, Domain::NonNegative, "centre of mass of K2 from P1"],
        /// Length of K4 from G to E.
        pub e: f64 = ["e", "m", 0.02, Domain::Positive, "length of K4, G to E"],
        /// Centre of mass of K4 from E.
        pub ea: f64 = ["ea", "m", 0.01421, Domain::NonNegative, "centre of mass of K4 from E"],
        /// Crank length O to P1.
        pub rr: f64 = ["rr", "m", 0.007, Domain::Positive, "crank length, O to P1"],
        /// Centre of mass of K1 from O.
        pub ra: f64 = ["ra", "m", 0.00092, Domain::NonNegative, "centre of mass of K1 from O"],
        /// Distance B to E on K3.
        pub ss: f64 = ["ss", "m", 0.035, Domain::Positive, "distance B to E on K3"],
        /// Centre of mass of K3 along its axis.
        pub sa: f64 = ["sa", "m", 0.01874, Domain::NonNegative, "centre of mass of K3 along e(γ)"],
        /// Centre of mass of K3 across its axis.
        pub sb: f64 = ["sb", "m", 0.01043, Domain::NonNegative, "centre of mass of K3 along e⊥(γ)"],
        /// Spring point D of K3 across its axis.
        pub sc: f64 = ["sc", "m", 0.018, Domain::NonNegative, "spring point D of K3 along e⊥(γ)"],
        /// Spring point D of K3 along its axis.
        pub sd: f64 = ["sd", "m", 0.02, Domain::NonNegative, "spring point D of K3 along e(γ)"],
        /// Centre of mass of K5 along its axis.
        pub ta: f64 = ["ta", "m", 0.02308, Domain::NonNegative, "centre of mass of K5 along e(δ)"],
        /// Centre of mass of K5 across its axis.
        pub tb: f64 = ["tb", "m", 0.00916, Domain::NonNegative, "centre of mass of K5 along e⊥(δ)"],
        /// Distance A to H on K7.
        pub u: f64 = ["u", "m", 0.04, Domain::Positive, "distance A to H on K7"],
        /// Centre of mass of K7 along its axis.
        pub ua: f64 = ["ua", "m", 0.01228, Domain::NonNegative, "centre of mass of K7 along e(ε)"],
        /// Centre of mass of K7 across its axis.
        pub ub: f64 = ["ub", "m", 0.00449, Domain::NonNegative, "centre of mass of K7 along e⊥(ε)"],
        /// Length of K6 from H to E.
        pub zf: f64 = ["zf", "m", 0.02, Domain::Positive, "length of K6, H to E"],
        /// Distance A to G on K5.
        pub zt: f64 = ["zt", "m", 0.04, Domain::Positive, "distance A to G on K5"],
        /// Centre of mass of K6 from E.
        pub fa: f64 = ["fa", "m", 0.01421, Domain::NonNegative, "centre of mass of K6 from E"],
        /// Driving torque on K1 (N m).
        pub mom: f64 = ["mom", "N m", 0.033, Domain::Finite, "driving torque on the crank K1"],
        /// Spring stiffness (N/m).
        pub c0: f64 = ["c0", "N/m", 4530.0, Domain::NonNegative, "stiffness of the spring C–D"],
        /// Spring natural length (m).
        pub l0: f64 = ["l0", "m", 0.07785, Domain::NonNegative, "natural length of the spring C–D"],
    }
    /// Andrews' squeezer with every parameter of the test problem, in its order.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: ["β", "Θ", "γ", "Φ", "δ", "Ω", "ε"].map(Coordinate::angle).to_vec(),
            bodies: vec![
                Body::rigid("K1", m1, i1),
                Body::rigid("K2", m2, i2),
                Body::rigid("K3", m3, i3),
                Body::rigid("K4", m4, i4),
                Body::rigid("K5", m5, i5),
                Body::rigid("K6", m6, i6),
                Body::rigid("K7", m7, i7),
            ],
            constraints: (0..6).map(constraint_name).collect(),
            ..Description::default()
        },
        initial: [f64; 7] = INITIAL_ANGLES,
    }
    finish = AndrewsSqueezer::assembled;
}

/// The name of loop-closure row `i` (0 to 5) of [`Mechanism::constraints`]: the test problem's
/// `g1` … `g6`, `E` through K3, K4, K6, each x then y.
fn constraint_name(i: usize) -> String {
    let through = ["K3", "K4", "K6"][i / 2];
    format!("g{}: E through {through} ({})", i + 1, ["x", "y"][i % 2])
}

/// Unit coefficient vectors of the body angles in `q`.
const K_BETA: [f64; 7] = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
const K_BETA_THETA: [f64; 7] = [1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0];
const K_GAMMA: [f64; 7] = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
const K_PHI_DELTA: [f64; 7] = [0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0];
const K_DELTA: [f64; 7] = [0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0];
const K_OMEGA_EPSILON: [f64; 7] = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0];
const K_EPSILON: [f64; 7] = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];

/// `e(a) = (cos a, sin a)`.
fn e<S: Scalar>(a: S) -> [S; 2] {
    [a.cos(), a.sin()]
}

/// `e⊥(a) = (sin a, −cos a)`.
fn e_perp<S: Scalar>(a: S) -> [S; 2] {
    [a.sin(), -a.cos()]
}

/// `p + s u`.
fn add<S: Scalar>(p: [S; 2], s: f64, u: [S; 2]) -> [S; 2] {
    [p[0] + u[0] * s, p[1] + u[1] * s]
}

impl AndrewsSqueezer {
    /// The scene with its initial angles on its loops: [`INITIAL_ANGLES`] where they close the
    /// loops to round-off (the test problem's geometry), otherwise `β` of [`INITIAL_ANGLES`]
    /// held and the other six angles brought onto the constraints from there by the engine's
    /// assembly (smallest change).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the loop that does not close when the geometry
    /// cannot be assembled at that `β`.
    fn assembled(mut self) -> Result<Self, Error> {
        let (residual, _) = self.residuals(&INITIAL_ANGLES, &[0.0; 7]);
        // The published angles close the standard loops to a few ε of their lengths (~0.03 m).
        let scale = 0.1;
        if residual.iter().all(|r| r.abs() <= 64.0 * f64::EPSILON * scale) {
            return Ok(self);
        }
        let model = lagrange::Model::new(self.clone())?;
        let start = State::new(0.0, INITIAL_ANGLES, [0.0; 7]);
        let mut held = [false; 7];
        held[0] = true;
        match lagrange::assemble(&model, &start, &held) {
            Ok(state) => {
                self.initial.copy_from_slice(&state.q);
                Ok(self)
            }
            Err(Error::AssemblyFailed { constraint, residual, .. }) => {
                // Named by the lengths that differ from the test problem's: those are what the
                // user changed, and what keeps the loops open.
                let s = &self;
                let lengths = [
                    ("xa", s.xa),
                    ("ya", s.ya),
                    ("xb", s.xb),
                    ("yb", s.yb),
                    ("xc", s.xc),
                    ("yc", s.yc),
                    ("d", s.d),
                    ("da", s.da),
                    ("e", s.e),
                    ("ea", s.ea),
                    ("rr", s.rr),
                    ("ra", s.ra),
                    ("ss", s.ss),
                    ("sa", s.sa),
                    ("sb", s.sb),
                    ("sc", s.sc),
                    ("sd", s.sd),
                    ("ta", s.ta),
                    ("tb", s.tb),
                    ("u", s.u),
                    ("ua", s.ua),
                    ("ub", s.ub),
                    ("zf", s.zf),
                    ("zt", s.zt),
                    ("fa", s.fa),
                ];
                let changed: Vec<(&str, f64)> = lengths
                    .into_iter()
                    .filter(|(name, value)| PARAMS.iter().any(|p| p.name == *name && p.default != *value))
                    .collect();
                let (name, value) = match changed.as_slice() {
                    [(name, value)] => ((*name).to_string(), *value),
                    [] => ("geometry (xa … fa)".to_string(), f64::NAN),
                    many => (many.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", "), many[0].1),
                };
                Err(Error::InvalidParameter {
                    name,
                    value,
                    why: format!(
                        "with these lengths the squeezer's loops do not close at β = {}: {constraint} is left \
                         {residual:.3e} m apart",
                        INITIAL_ANGLES[0]
                    ),
                })
            }
            Err(e) => Err(e),
        }
    }

    /// The squeezer with the test problem's parameters (the defaults of [`PARAMS`]).
    pub fn standard() -> Self {
        Self::from_table(&crate::Params::defaults(PARAMS)).expect("the test problem's parameters are valid")
    }

    /// The hand-coded linkage of the closed form (built per call: the closed forms are
    /// references, not the fast path) (a sum of rotating arms per point, in the
    /// notation of docs/scenes.md#andrews_squeezer; `e⊥(a) = R(a)(0, −1)`).
    fn build_linkage(&self) -> Linkage {
        let a = Point::at(self.xa, self.ya);
        let e_point = |p: Point| p.arm(&K_BETA, [self.rr, 0.0]).arm(&K_BETA_THETA, [-self.d, 0.0]);
        let body = |mass: f64, inertia: f64, centre: Point, angle: [f64; 7]| LinkBody {
            mass,
            inertia,
            centre,
            angle: angle.to_vec(),
        };
        let bodies = vec![
            body(self.m1, self.i1, Point::at(0.0, 0.0).arm(&K_BETA, [self.ra, 0.0]), K_BETA),
            body(
                self.m2,
                self.i2,
                Point::at(0.0, 0.0).arm(&K_BETA, [self.rr, 0.0]).arm(&K_BETA_THETA, [-self.da, 0.0]),
                K_BETA_THETA,
            ),
            body(self.m3, self.i3, Point::at(self.xb, self.yb).arm(&K_GAMMA, [self.sa, -self.sb]), K_GAMMA),
            body(
                self.m4,
                self.i4,
                a.clone().arm(&K_DELTA, [self.zt, 0.0]).arm(&K_PHI_DELTA, [0.0, -(self.e - self.ea)]),
                K_PHI_DELTA,
            ),
            body(self.m5, self.i5, a.clone().arm(&K_DELTA, [self.ta, -self.tb]), K_DELTA),
            body(
                self.m6,
                self.i6,
                a.clone().arm(&K_EPSILON, [0.0, -self.u]).arm(&K_OMEGA_EPSILON, [self.zf - self.fa, 0.0]),
                K_OMEGA_EPSILON,
            ),
            body(self.m7, self.i7, a.clone().arm(&K_EPSILON, [self.ua, -self.ub]), K_EPSILON),
        ];
        let loops = vec![
            e_point(Point::at(-self.xb, -self.yb)).arm(&K_GAMMA, [0.0, self.ss]),
            e_point(Point::at(-self.xa, -self.ya)).arm(&K_DELTA, [-self.zt, 0.0]).arm(&K_PHI_DELTA, [0.0, self.e]),
            e_point(Point::at(-self.xa, -self.ya))
                .arm(&K_EPSILON, [0.0, self.u])
                .arm(&K_OMEGA_EPSILON, [-self.zf, 0.0]),
        ];
        let d = Point::at(self.xb, self.yb).arm(&K_GAMMA, [self.sd, -self.sc]);
        Linkage {
            bodies,
            gravity: 0.0,
            loops,
            torque: (K_BETA.to_vec(), self.mom),
            spring: Some(([self.xc, self.yc], d, self.c0, self.l0)),
        }
    }

    /// `(q̈, λ)` in closed form: `M q̈ + Gᵀ λ = f`, `G q̈ = −γ` assembled by hand from the
    /// bodies' centres, the loop-closure points, the spring and the torque (rotating arms,
    /// their velocities and convective accelerations written out), solved as one dense KKT
    /// system (13 × 13).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 7 entries.
    pub fn closed_form_with_multipliers(&self, q: &[f64], qdot: &[f64]) -> ([f64; 7], [f64; 6]) {
        assert!(q.len() == 7 && qdot.len() == 7, "q and q̇ must have 7 entries");
        match self.build_linkage().accelerations(q, qdot) {
            Some((a, l)) => (std::array::from_fn(|i| a[i]), std::array::from_fn(|i| l[i])),
            None => ([f64::NAN; 7], [f64::NAN; 6]),
        }
    }

    /// The energy function `T + c0 (L − l0)²/2 − mom β`, conserved along every motion.
    pub fn energy(&self, q: &[f64], qdot: &[f64]) -> f64 {
        self.build_linkage().energy(q, qdot)
    }

    /// The loop-closure residuals `g(q)` (the test problem's order) and their rates `G q̇`.
    pub fn residuals(&self, q: &[f64], qdot: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.build_linkage().residuals(q, qdot)
    }

    /// `E = rr e(β) − d e(β + Θ)`, the end of the connecting rod.
    fn point_e<S: Scalar>(&self, q: &[S]) -> [S; 2] {
        add(add([S::zero(), S::zero()], self.rr, e(q[0])), -self.d, e(q[0] + q[1]))
    }
}

impl Mechanism for AndrewsSqueezer {
    fn description(&self) -> &Description {
        &self.description
    }

    /// The centres of mass and angles of K1 … K7 (docs/scenes.md#andrews_squeezer).
    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (beta, theta, gamma, phi, delta, omega, epsilon) = (q[0], q[1], q[2], q[3], q[4], q[5], q[6]);
        let origin = [S::zero(), S::zero()];
        let a = [S::from(self.xa), S::from(self.ya)];
        let b = [S::from(self.xb), S::from(self.yb)];
        let pose = |p: [S; 2], angle: S| Pose::new(p[0], p[1], angle);
        let k1 = add(origin, self.ra, e(beta));
        let p1 = add(origin, self.rr, e(beta));
        let k2 = add(p1, -self.da, e(beta + theta));
        let k3 = add(add(b, self.sa, e(gamma)), self.sb, e_perp(gamma));
        let g = add(a, self.zt, e(delta));
        let k4 = add(g, self.e - self.ea, e_perp(phi + delta));
        let k5 = add(add(a, self.ta, e(delta)), self.tb, e_perp(delta));
        let h = add(a, self.u, e_perp(epsilon));
        let k6 = add(h, self.zf - self.fa, e(omega + epsilon));
        let k7 = add(add(a, self.ua, e(epsilon)), self.ub, e_perp(epsilon));
        world_from_body[0] = pose(k1, beta);
        world_from_body[1] = pose(k2, beta + theta);
        world_from_body[2] = pose(k3, gamma);
        world_from_body[3] = pose(k4, phi + delta);
        world_from_body[4] = pose(k5, delta);
        world_from_body[5] = pose(k6, omega + epsilon);
        world_from_body[6] = pose(k7, epsilon);
    }

    /// The spring C–D, `V = c0 (L − l0)²/2` with `D` on K3 at `(sd − sa, sb − sc)` in K3's frame
    /// (so that its force acts on K3).
    fn potential<S: Scalar>(&self, _t: S, _q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        let k3 = &world_from_body[2];
        let (s, c) = k3.angle.sin_cos();
        let (u, v) = (self.sd - self.sa, self.sb - self.sc);
        let dx = k3.x + c * u - s * v - self.xc;
        let dy = k3.y + s * u + c * v - self.yc;
        let stretch = (dx * dx + dy * dy).sqrt() - self.l0;
        Some(stretch * stretch * (0.5 * self.c0))
    }

    /// The test problem's `g(1..6)`: `E − (B + ss e⊥(γ))`, `E − (G + e e⊥(Φ + δ))`,
    /// `E − (H + zf e(Ω + ε))`, each x then y.
    fn constraints<S: Scalar>(&self, _t: S, q: &[S], phi: &mut [S]) {
        let end = self.point_e(q);
        let a = [S::from(self.xa), S::from(self.ya)];
        let b = [S::from(self.xb), S::from(self.yb)];
        let via_k3 = add(b, self.ss, e_perp(q[2]));
        let via_k4 = add(add(a, self.zt, e(q[4])), self.e, e_perp(q[3] + q[4]));
        let via_k6 = add(add(a, self.u, e_perp(q[6])), self.zf, e(q[5] + q[6]));
        for (i, p) in [via_k3, via_k4, via_k6].into_iter().enumerate() {
            phi[2 * i] = end[0] - p[0];
            phi[2 * i + 1] = end[1] - p[1];
        }
    }

    /// The driving torque `mom` on K1 (none when `mom = 0`).
    fn applied_forces<S: Scalar>(
        &self,
        _t: S,
        _q: &[S],
        _qdot: &[S],
        _world_from_body: &[Pose<S>],
        loads: &mut Loads<'_, S>,
    ) -> bool {
        if self.mom == 0.0 {
            return false;
        }
        loads.torque(0, S::from(self.mom));
        true
    }
}

impl SceneType for AndrewsSqueezer {
    const ID: &'static str = "andrews_squeezer";
    const TITLE: &'static str = "Andrews' squeezing mechanism (7 bodies, 6 loop constraints)";
    const REFERENCE: &'static str = "docs/scenes.md#andrews_squeezer; beyond the lecture (Hairer & Wanner, Solving ODEs II, §VII.7; the CWI/Bari IVP test set problem \"andrews\")";
    /// The test problem's interval, `[0, 0.03]` s: the span of the published solution.
    const HORIZON: Option<f64> = Some(0.03);
    param_table!();

    /// [`AndrewsSqueezer::closed_form_with_multipliers`].
    fn closed_form(&self, _t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
        qddot.copy_from_slice(&self.closed_form_with_multipliers(q, qdot).0);
    }

    /// At rest at the test problem's consistent initial angles [`INITIAL_ANGLES`]; with other
    /// geometry, those angles brought onto the loops with `β` held.
    fn default_state(&self) -> State {
        State::new(0.0, self.initial, [0.0; 7])
    }

    /// `T + V − mom β` (`V` the spring's energy): with `mom ≠ 0` not the energy the engine
    /// derives (it sees an applied torque), so declared as another constant; `E = T + V`
    /// when `mom = 0`.
    fn conserves_energy(&self) -> Vec<Conserved> {
        let energy = |s: &Self, q: &[f64], qdot: &[f64]| s.energy(q, qdot);
        if self.mom == 0.0 {
            vec![Conserved::energy(self, energy)]
        } else {
            vec![Conserved::new(
                self,
                "E − mom β",
                "a constant torque's work is mom Δβ",
                Invariant::Other,
                move |s, _, q, qdot| energy(s, q, qdot),
            )]
        }
    }

    body_scene!(engine);

    /// Seven pins as the spanning tree (`β`, `γ`, `δ`, `ε` at the ground, `Θ` of K2 on K1, `Φ`
    /// of K4 on K5 and `Ω` of K6 on K7, relative angles), the three pins at `E` (K2 with K3, K4
    /// and K6) closing the loops; the spring `C`–`D` on K3 and the torque `mom` on K1.
    fn joint_graph(&self) -> Option<JointGraph> {
        let s = self;
        let (a, e) = ([s.xa, s.ya], [s.da - s.d, 0.0]);
        let mut graph = crate::scene::graph_of(Self::ID, self)
            .with_joint(GraphJoint::revolute("β", GROUND, [0.0, 0.0], "K1", [-s.ra, 0.0]))
            .with_joint(GraphJoint::revolute("Θ", "K1", [s.rr - s.ra, 0.0], "K2", [s.da, 0.0]))
            .with_joint(GraphJoint::revolute("γ", GROUND, [s.xb, s.yb], "K3", [-s.sa, s.sb]))
            .with_joint(GraphJoint::revolute("Φ", "K5", [s.zt - s.ta, s.tb], "K4", [0.0, s.e - s.ea]))
            .with_joint(GraphJoint::revolute("δ", GROUND, a, "K5", [-s.ta, s.tb]))
            .with_joint(GraphJoint::revolute("Ω", "K7", [-s.ua, s.ub - s.u], "K6", [-(s.zf - s.fa), 0.0]))
            .with_joint(GraphJoint::revolute("ε", GROUND, a, "K7", [-s.ua, s.ub]))
            .with_joint(GraphJoint::revolute("E (K2–K3)", "K2", e, "K3", [-s.sa, s.sb - s.ss]).closing())
            .with_joint(GraphJoint::revolute("E (K2–K4)", "K2", e, "K4", [0.0, -s.ea]).closing())
            .with_joint(GraphJoint::revolute("E (K2–K6)", "K2", e, "K6", [s.fa, 0.0]).closing())
            .with_force(ForceElement::Spring {
                a: graph::Point::world([s.xc, s.yc]),
                b: graph::Point::on("K3", [s.sd - s.sa, s.sb - s.sc]),
                stiffness: s.c0,
                rest_length: s.l0,
            });
        if s.mom != 0.0 {
            graph = graph.with_force(ForceElement::Torque { body: "K1".into(), torque: Profile::constant(s.mom) });
        }
        Some(graph)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{assert_close, max_abs};
    use lagrange::{Method, Model, Output, Tolerances, accelerations, constraint_multipliers};

    fn relative(what: &str, expected: &[f64], got: &[f64], tol: f64) {
        // Zero entries are compared with an absolute bound scaled by the largest entry.
        let scale = max_abs(expected);
        for (i, (e, g)) in expected.iter().zip(got).enumerate() {
            let bound = tol * if *e == 0.0 { scale } else { e.abs() };
            assert!(
                (e - g).abs() <= bound,
                "{what}[{i}]: expected {e}, got {g} (|Δ| = {:e} > {bound:e})",
                (e - g).abs()
            );
        }
    }

    #[test]
    fn defaults_are_the_test_problem() {
        let s = AndrewsSqueezer::standard();
        assert_eq!(s, AndrewsSqueezer::from_params(&scene_of::<AndrewsSqueezer>().default_params()).unwrap());
        assert_eq!(PARAMS.len(), 42);
    }

    /// The published initial values satisfy the constraints to round-off of the
    /// coordinates' size (|g| ≤ 1e-17 m, lengths ~0.03 m: a few ε relative).
    #[test]
    fn default_state_is_consistent() {
        let s = AndrewsSqueezer::standard();
        let state = s.default_state();
        let (phi, rate) = s.residuals(&state.q, &state.qdot);
        assert!(max_abs(&phi) <= 16.0 * f64::EPSILON * 0.1, "{phi:?}");
        assert_eq!(max_abs(&rate), 0.0);
        let model = Model::new(s).unwrap();
        let [position, velocity] =
            lagrange::Dynamics::constraint_violation(&model, &mut model.workspace(), 0.0, &state.q, &state.qdot)
                .unwrap()
                .unwrap();
        assert!(position <= 16.0 * f64::EPSILON * 0.1 && velocity == 0.0, "{position:e} {velocity:e}");
    }

    /// The engine's q̈ and λ at t = 0 (and the hand-coded KKT closed form) against the
    /// published consistent initial accelerations and multipliers, ≤ 1e-10 relative; the zero
    /// entries within 1e-10 of the largest entry.
    #[test]
    fn initial_accelerations_and_multipliers_are_the_published_ones() {
        let s = AndrewsSqueezer::standard();
        let state = s.default_state();
        let model = Model::new(s.clone()).unwrap();
        let mut ws = model.workspace();
        let qddot = accelerations(&model, &mut ws, 0.0, &state.q, &state.qdot).unwrap().to_vec();
        let lambda = constraint_multipliers(&model, &mut ws, 0.0, &state.q, &state.qdot).unwrap().to_vec();
        relative("engine q̈(0)", &PUBLISHED_INITIAL_ACCELERATIONS, &qddot, 1e-10);
        relative("engine λ(0)", &PUBLISHED_INITIAL_MULTIPLIERS, &lambda, 1e-10);
        let (closed, closed_lambda) = s.closed_form_with_multipliers(&state.q, &state.qdot);
        relative("closed-form q̈(0)", &PUBLISHED_INITIAL_ACCELERATIONS, &closed, 1e-10);
        relative("closed-form λ(0)", &PUBLISHED_INITIAL_MULTIPLIERS, &closed_lambda, 1e-10);
    }

    /// Engine and hand-coded closed form at moving states taken along the motion: q̈ to 1e-9
    /// of the largest |q̈| (the KKT matrix mixes masses ~1e-2 kg m-scaled to 1e-6 with unit
    /// constraint rows, condition number ~1e7 measured by the size of λ against q̈).
    #[test]
    fn engine_matches_the_closed_form_along_the_motion() {
        let s = AndrewsSqueezer::standard();
        let model = Model::new(s.clone()).unwrap();
        let run = lagrange::simulate(&model, &s.default_state(), 0.03, Method::Rk4 { dt: 1e-5 }, &Output::Every(0.003))
            .unwrap();
        let mut ws = model.workspace();
        for k in 0..run.len() {
            let engine = accelerations(&model, &mut ws, run.t[k], run.q(k), run.qdot(k)).unwrap().to_vec();
            let closed = s.closed_form_with_multipliers(run.q(k), run.qdot(k)).0;
            assert_close(&format!("t = {}", run.t[k]), &closed, &engine, 1e-9 * max_abs(&closed));
        }
    }

    /// The adaptive integrator at rtol = atol = 1e-13 from the published initial state to
    /// t = 0.03: every angle within 1e-8 relative of the published solution (accurate to
    /// about 3e-10 itself), and the rates within 1e-7 relative.
    #[test]
    fn adaptive_run_reaches_the_published_solution_at_0_03() {
        let s = AndrewsSqueezer::standard();
        let model = Model::new(s.clone()).unwrap();
        let method = Method::Dopri5 { tol: Tolerances::uniform(1e-13) };
        let run = lagrange::simulate(&model, &s.default_state(), 0.03, method, &Output::Ends).unwrap();
        let last = run.len() - 1;
        assert_eq!(run.t[last], 0.03);
        for i in 0..7 {
            let (expected, got) = (PUBLISHED_AT_0_03[0][i], run.q(last)[i]);
            assert!((got - expected).abs() <= 1e-8 * expected.abs(), "angle {i}: {got} vs {expected}");
            let (expected, got) = (PUBLISHED_AT_0_03[1][i], run.qdot(last)[i]);
            assert!((got - expected).abs() <= 1e-7 * expected.abs(), "rate {i}: {got} vs {expected}");
        }
    }

    /// `T + V − mom β` along RK4 runs to t = 0.03: drift falls as dt⁴ (ratio 16 within a
    /// factor 2).
    #[test]
    fn energy_is_conserved_to_the_order_of_rk4() {
        let s = AndrewsSqueezer::standard();
        let model = Model::new(s.clone()).unwrap();
        let start = s.default_state();
        let e0 = s.energy(&start.q, &start.qdot);
        let drift = |dt: f64| {
            let run = lagrange::simulate(&model, &start, 0.03, Method::Rk4 { dt }, &Output::Every(0.001)).unwrap();
            (0..run.len()).map(|k| (s.energy(run.q(k), run.qdot(k)) - e0).abs()).fold(0.0, f64::max)
        };
        let (coarse, fine) = (drift(4e-5), drift(2e-5));
        let ratio = coarse / fine;
        assert!((8.0..=32.0).contains(&ratio), "drift {coarse:e} → {fine:e}, ratio {ratio}");
    }
}
