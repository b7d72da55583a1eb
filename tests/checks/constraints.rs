//! Constraints among the coordinates (docs/method.md#constraints): the same mechanism written
//! with constraints and written in independent coordinates gives the same accelerations and
//! trajectories; multipliers are the constraint forces; assembly, projection, redundant and
//! inconsistent constraints.

use lagrange::{
    Body, Coordinate, Description, Error, Mechanism, Method, Model, Output, Pose, Scalar, State, Tolerances,
    accelerations, assemble, constraint_multipliers,
};

const G: f64 = 9.81;

/// A pendulum bob in Cartesian coordinates `q = (x, y)` tied to the circle `x² + y² = l²`.
struct CartesianPendulum {
    description: Description,
    length: f64,
}

impl CartesianPendulum {
    fn new(mass: f64, length: f64) -> Self {
        Self {
            description: Description::new().length("x").length("y").point("bob", mass).gravity(G).constraint("Φ1"),
            length,
        }
    }
}

impl Mechanism for CartesianPendulum {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0], q[1]);
    }
    fn constraints<S: Scalar>(&self, _t: S, q: &[S], phi: &mut [S]) {
        phi[0] = q[0] * q[0] + q[1] * q[1] - self.length * self.length;
    }
}

/// The pendulum's state in `(x, y)` from its angle from the downward vertical.
fn cartesian(length: f64, theta: f64, theta_dot: f64) -> ([f64; 2], [f64; 2]) {
    let (s, c) = theta.sin_cos();
    ([length * s, -length * c], [length * c * theta_dot, length * s * theta_dot])
}

/// `q̈ = (ẍ, ÿ)` against `θ̈ = −(g/l) sin θ` carried to `(x, y)`, and `λ` against the rod
/// tension `T = m (g cos θ + l θ̇²)`: the force on the bob is `−Gᵀ λ = −2 λ (x, y)`, so
/// `λ = T / (2 l)`. Bound 64 ε relative: a handful of operations in either formula.
#[test]
fn cartesian_pendulum_matches_the_pendulum_in_its_angle() {
    let (mass, length) = (1.3, 0.7);
    let model = Model::new(CartesianPendulum::new(mass, length)).expect("valid");
    assert_eq!(model.constraint_counts(), (1, 0));
    let mut ws = model.workspace();
    for (theta, theta_dot) in [(0.5, 0.0), (-1.2, 2.5), (2.9, -0.7)] {
        let (q, qdot) = cartesian(length, theta, theta_dot);
        let theta_ddot = -G / length * theta.sin();
        let (s, c) = theta.sin_cos();
        let expected = [
            length * (c * theta_ddot - s * theta_dot * theta_dot),
            length * (s * theta_ddot + c * theta_dot * theta_dot),
        ];
        let got = accelerations(&model, &mut ws, 0.0, &q, &qdot).expect("evaluates").to_vec();
        let scale = expected.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        for i in 0..2 {
            assert!(
                (got[i] - expected[i]).abs() <= 64.0 * f64::EPSILON * scale,
                "θ = {theta}: {got:?} vs {expected:?}"
            );
        }
        let lambda = constraint_multipliers(&model, &mut ws, 0.0, &q, &qdot).expect("evaluates")[0];
        let tension = mass * (G * c + length * theta_dot * theta_dot);
        assert!((lambda - tension / (2.0 * length)).abs() <= 64.0 * f64::EPSILON * tension.abs().max(1.0));
    }
}

/// Every integrator runs the Cartesian pendulum on its circle: the position error against the
/// angle pendulum (adaptive, tol 1e-13) stays within the method's own error (bounds measured
/// ×10 below), and the constraint violation at every sample is round-off (≤ 16 ε (1 + |q|)):
/// the projection's, or the variational integrator's own constrained step's.
#[test]
fn every_integrator_keeps_the_cartesian_pendulum_on_its_circle() {
    let (mass, length) = (1.0, 1.0);
    let model = Model::new(CartesianPendulum::new(mass, length)).expect("valid");
    let (q0, v0) = cartesian(length, 0.5, 0.0);
    let initial = State::new(0.0, q0, v0);
    // The reference: the same pendulum in its angle.
    let angle = AnglePendulum { description: Description::new().angle("θ").point("bob", mass).gravity(G), length };
    let reference = Model::new(angle).expect("valid");
    let t_end = 2.0;
    let output = Output::Every(0.1);
    let exact = lagrange::simulate(
        &reference,
        &State::new(0.0, [0.5], [0.0]),
        t_end,
        Method::Dopri5 { tol: Tolerances::uniform(1e-13) },
        &output,
    )
    .expect("runs");
    let methods = [
        (Method::Rk4 { dt: 1e-3 }, 1e-10),
        (Method::Dopri5 { tol: Tolerances::uniform(1e-10) }, 1e-8),
        (Method::Sdirk4 { tol: Tolerances::uniform(1e-10) }, 1e-8),
        (Method::Gauss4 { dt: 1e-2 }, 1e-8),
        (Method::Variational { dt: 1e-3 }, 1e-5),
    ];
    let mut ws = model.workspace();
    for (method, bound) in methods {
        let run = lagrange::simulate(&model, &initial, t_end, method, &output).expect("runs");
        let mut worst: f64 = 0.0;
        for k in 0..run.len() {
            let (x, _) = cartesian(length, exact.q(k)[0], exact.qdot(k)[0]);
            worst = worst.max((run.q(k)[0] - x[0]).abs()).max((run.q(k)[1] - x[1]).abs());
            let [position, velocity] =
                lagrange::Dynamics::constraint_violation(&model, &mut ws, run.t[k], run.q(k), run.qdot(k))
                    .expect("evaluates")
                    .expect("constrained");
            assert!(
                position <= 32.0 * f64::EPSILON && velocity <= 1e-13,
                "{method:?} at {}: {position:e}, {velocity:e}",
                run.t[k]
            );
        }
        eprintln!("{method:?}: largest position error {worst:.2e}");
        assert!(worst <= bound, "{method:?}: {worst:e} > {bound:e}");
    }
}

struct AnglePendulum {
    description: Description,
    length: f64,
}

impl Mechanism for AnglePendulum {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0].sin() * self.length, -q[0].cos() * self.length);
    }
}

/// Crank-rocker four-bar (ground O2 = 0, O4 = (d, 0); crank a, coupler b, rocker c; uniform
/// rods) in its three absolute angles with two loop constraints.
#[derive(Clone)]
struct FourBar {
    description: Description,
    lengths: [f64; 4],
}

impl FourBar {
    fn new(lengths: [f64; 4], masses: [f64; 3], reduced: bool) -> Self {
        let [a, b, c, _] = lengths;
        let rod = |name: &str, m: f64, l: f64| Body::rigid(name, m, m * l * l / 12.0);
        let (coordinates, constraints) = if reduced {
            (vec![Coordinate::angle("θ2")], vec![])
        } else {
            (
                vec![Coordinate::angle("θ2"), Coordinate::angle("θ3"), Coordinate::angle("θ4")],
                vec!["Φ1".to_string(), "Φ2".to_string()],
            )
        };
        let description = Description {
            coordinates,
            bodies: vec![rod("crank", masses[0], a), rod("coupler", masses[1], b), rod("rocker", masses[2], c)],
            gravity: G,
            constraints,
            ..Description::default()
        };
        Self { description, lengths }
    }

    /// `(θ3, θ4)` from `θ2` by the closed-form position analysis: `B` is where the circle of
    /// radius `b` about `A` meets the circle of radius `c` about `O4`, above the ground line.
    fn closed<S: Scalar>(&self, theta2: S) -> (S, S) {
        let [a, b, c, d] = self.lengths;
        let (ax, ay) = (theta2.cos() * a, theta2.sin() * a);
        let (dx, dy) = (-ax + d, -ay);
        let dist2 = dx * dx + dy * dy;
        let dist = dist2.sqrt();
        let along = (dist2 + b * b - c * c) / (dist * 2.0);
        let h = (-(along * along) + b * b).sqrt();
        let (ux, uy) = (dx / dist, dy / dist);
        // The intersection with B above A → O4 turned counter-clockwise.
        let (bx, by) = (ax + ux * along - uy * h, ay + uy * along + ux * h);
        ((by - ay).atan2(bx - ax), by.atan2(bx - d))
    }
}

impl Mechanism for FourBar {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        let [a, b, c, d] = self.lengths;
        let theta2 = q[0];
        let (theta3, theta4) = if q.len() == 1 { self.closed(theta2) } else { (q[1], q[2]) };
        let (ax, ay) = (theta2.cos() * a, theta2.sin() * a);
        p[0] = Pose::new(theta2.cos() * (a / 2.0), theta2.sin() * (a / 2.0), theta2);
        p[1] = Pose::new(ax + theta3.cos() * (b / 2.0), ay + theta3.sin() * (b / 2.0), theta3);
        p[2] = Pose::new(theta4.cos() * (c / 2.0) + d, theta4.sin() * (c / 2.0), theta4);
    }
    fn constraints<S: Scalar>(&self, _t: S, q: &[S], phi: &mut [S]) {
        let [a, b, c, d] = self.lengths;
        phi[0] = q[0].cos() * a + q[1].cos() * b - q[2].cos() * c - d;
        phi[1] = q[0].sin() * a + q[1].sin() * b - q[2].sin() * c;
    }
}

const LENGTHS: [f64; 4] = [0.2, 0.6, 0.5, 0.5];
const MASSES: [f64; 3] = [1.0, 2.0, 1.5];

/// The three-angle four-bar assembled from the crank angle and rate.
fn four_bar_state(model: &Model<FourBar>, theta2: f64, rate: f64) -> State {
    let guess = State::new(0.0, [theta2, 0.3, 1.5], [rate, 0.0, 0.0]);
    assemble(model, &guess, &[true, false, false]).expect("the crank-rocker closes at every crank angle")
}

/// Assembly holds the crank and lands on the closed-form branch; the crank's `q̈` agrees with
/// the one-coordinate model (poses from the position analysis) to round-off scaled by the
/// conditioning of the constrained solve (bound `1e3 ε` relative: the Schur complement's
/// condition number here is below 1e2, measured, and each formula takes a few hundred
/// operations).
#[test]
fn four_bar_with_constraints_matches_the_closed_form_position_analysis() {
    let constrained = Model::new(FourBar::new(LENGTHS, MASSES, false)).expect("valid");
    let reduced = Model::new(FourBar::new(LENGTHS, MASSES, true)).expect("valid");
    let (mut wc, mut wr) = (constrained.workspace(), reduced.workspace());
    for (theta2, rate) in [(std::f64::consts::FRAC_PI_3, 6.0), (2.0, -3.0), (4.5, 1.0), (0.0, 10.0)] {
        let state = four_bar_state(&constrained, theta2, rate);
        assert_eq!(state.q[0], theta2, "the crank is held");
        assert_eq!(state.qdot[0], rate, "the crank rate is held");
        let (theta3, theta4) = constrained.mechanism().closed(theta2);
        let wrap = |x: f64| (x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        assert!(wrap(state.q[1] - theta3).abs() < 1e-12 && wrap(state.q[2] - theta4).abs() < 1e-12, "{state:?}");
        let full = accelerations(&constrained, &mut wc, 0.0, &state.q, &state.qdot).expect("evaluates")[0];
        let one = accelerations(&reduced, &mut wr, 0.0, &[theta2], &[rate]).expect("evaluates")[0];
        eprintln!(
            "θ2 = {theta2}: crank q̈ differs by {:.1} ε relative",
            (full - one).abs() / (f64::EPSILON * one.abs().max(1.0))
        );
        assert!((full - one).abs() <= 1e3 * f64::EPSILON * one.abs().max(1.0), "θ2 = {theta2}: {full} vs {one}");
    }
}

/// Over 2 s from the scene's default state (θ2 = π/3, 6 rad/s) the crank angle of the
/// constrained model (RK4 dt 1e-4, projection every step) follows the one-coordinate model
/// (RK4 at the same step) to 1e-10: both are 4th-order at dt = 1e-4 (error ≈ 1e-12 measured).
#[test]
fn four_bar_trajectory_matches_the_one_coordinate_model() {
    let constrained = Model::new(FourBar::new(LENGTHS, MASSES, false)).expect("valid");
    let reduced = Model::new(FourBar::new(LENGTHS, MASSES, true)).expect("valid");
    let start = four_bar_state(&constrained, std::f64::consts::FRAC_PI_3, 6.0);
    let output = Output::Every(0.1);
    let method = Method::Rk4 { dt: 1e-4 };
    let a = lagrange::simulate(&constrained, &start, 2.0, method, &output).expect("runs");
    let b = lagrange::simulate(&reduced, &State::new(0.0, [start.q[0]], [start.qdot[0]]), 2.0, method, &output)
        .expect("runs");
    let worst = (0..a.len()).map(|k| (a.q(k)[0] - b.q(k)[0]).abs()).fold(0.0, f64::max);
    eprintln!("four-bar crank angle, constrained vs one coordinate: {worst:.2e}");
    assert!(worst <= 1e-10, "{worst:e}");
}

/// `project` corrects in the metric of the mass matrix: a velocity pushed off the constraints
/// by an impulse along the constraint forces, `q̇ + M⁻¹ Gᵀ κ`, comes back to `q̇` itself (the
/// projection onto `G q̇ = 0` along `M⁻¹ Gᵀ` is exact for such a drift; a Euclidean projection,
/// along `Gᵀ`, leaves part of it as a change of speed along the motion).
/// Bound: the refined solve of `G M⁻¹ Gᵀ` is exact to round-off away from a singular
/// configuration (condition below 1e2 here), so 1e3 ε of the largest velocity.
#[test]
fn projection_removes_a_drift_along_the_constraint_forces_exactly() {
    use lagrange::Dynamics;
    let model = Model::new(FourBar::new(LENGTHS, MASSES, false)).expect("valid");
    let (n, c) = (3, 2);
    for (theta2, rate) in [(std::f64::consts::FRAC_PI_3, 6.0), (2.0, -3.0), (4.5, 1.0)] {
        let state = four_bar_state(&model, theta2, rate);
        let mut ws = model.workspace();
        let mass = lagrange::mass_matrix(&model, &mut model.workspace(), 0.0, &state.q, &state.qdot)
            .expect("evaluates")
            .to_vec();
        let (mut g, mut phi, mut rates) = (vec![0.0; c * n], vec![0.0; c], vec![0.0; c]);
        model.constraint_rows(&mut ws, (0.0, &state.q, &state.qdot), &mut g, &mut phi, &mut rates).expect("rows");
        let m = nalgebra::DMatrix::from_row_slice(n, n, &mass);
        let g = nalgebra::DMatrix::from_row_slice(c, n, &g);
        let kick = m.cholesky().expect("M > 0").solve(&(g.transpose() * nalgebra::DVector::from_vec(vec![0.7, -1.3])));
        let (mut q, mut qdot) = (state.q.clone(), state.qdot.clone());
        for (v, k) in qdot.iter_mut().zip(kick.iter()) {
            *v += k;
        }
        lagrange::project(&model, &mut model.workspace(), 0.0, &mut q, &mut qdot).expect("projects");
        let speed = state.qdot.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let off = qdot.iter().zip(&state.qdot).fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()));
        eprintln!("θ2 = {theta2}: velocity after the projection off by {:.1} ε", off / (f64::EPSILON * speed));
        assert!(off <= 1e3 * f64::EPSILON * speed, "θ2 = {theta2}: {qdot:?} vs {:?}", state.qdot);
        assert_eq!(q, state.q, "a consistent position is left as it is");
    }
}

/// A crank-rocker whose links cannot close (coupler longer than the other three together)
/// cannot be assembled: a typed error naming a constraint.
#[test]
fn a_four_bar_that_cannot_close_is_an_assembly_error() {
    let model = Model::new(FourBar::new([0.2, 2.0, 0.5, 0.5], MASSES, false)).expect("valid");
    let guess = State::new(0.0, [1.0, 0.3, 1.5], [0.0, 0.0, 0.0]);
    match assemble(&model, &guess, &[true, false, false]) {
        Err(Error::AssemblyFailed { constraint, .. }) => assert!(constraint.starts_with('Φ'), "{constraint}"),
        other => panic!("{other:?}"),
    }
}

/// A parallelogram linkage with a third parallel link: of its four loop equations two are
/// redundant on the parallelogram — `q̈` is still unique (the one-coordinate motion of the
/// three cranks moving as one) and the redundant rows carry no multiplier; a redundant row
/// that asks for a different acceleration is an inconsistency naming it.
#[test]
fn redundant_constraints_are_resolved_and_contradictory_ones_named() {
    let model = lagrange_tests::parallelogram;
    let m = model(false);
    let mut ws = m.workspace();
    let (theta, rate) = (-0.8, 1.5);
    let (q, qdot) = ([theta; 3], [rate; 3]);
    let got = accelerations(&m, &mut ws, 0.0, &q, &qdot).expect("unique accelerations").to_vec();
    // All three tips move together: one pendulum of total mass 3.5 with the masses at unit
    // radius driven by the torque, θ̈ = 2/3.5 − g cos θ (angle from +x).
    let expected = 2.0 / 3.5 - G * theta.cos();
    for a in &got {
        assert!((a - expected).abs() <= 1e3 * f64::EPSILON * expected.abs(), "{got:?} vs {expected}");
    }
    // Rows Φ2 (parallel to Φ1 on the parallelogram) and Φ4 (= Φ1-row − Φ3-row up to factors)
    // are dependent: the reactions are not unique, and the engine's λ is the minimum-norm one,
    // orthogonal to both row combinations that Gᵀ maps to zero, w1 = (c, s, 0, 0) and
    // w2 = (−c, 0, c, s) (c, s of θ). The refined solve keeps λ in the range of S up to
    // round-off amplified by its shift, ε / 1e-10 ≈ 2.2e-6 of |λ|.
    let lambda = constraint_multipliers(&m, &mut ws, 0.0, &q, &qdot).expect("evaluates").to_vec();
    let (s, c) = theta.sin_cos();
    let norm = lambda.iter().map(|v| v * v).sum::<f64>().sqrt();
    for w in [[c, s, 0.0, 0.0], [-c, 0.0, c, s]] {
        let along = w.iter().zip(&lambda).map(|(a, b)| a * b).sum::<f64>().abs();
        let size = w.iter().map(|v| v * v).sum::<f64>().sqrt() * norm;
        assert!(along <= 1e-5 * size, "λ = {lambda:?} has {along:e} along the redundancy {w:?}");
    }
    // The reactions themselves are unique: −Gᵀλ carries the torque's share to every crank,
    // M q̈ = Q − Gᵀ λ with q̈ the common θ̈ (masses 1, 2, 0.5 at unit radius).
    let masses = [1.0, 2.0, 0.5];
    let rows = [[s, -s, 0.0], [-c, c, 0.0], [s, 0.0, -s], [0.0, -c, c]];
    for j in 0..3 {
        let reaction: f64 = -(0..4).map(|i| rows[i][j] * lambda[i]).sum::<f64>();
        let torque = if j == 0 { 2.0 } else { 0.0 };
        let expected_reaction = masses[j] * expected - torque + masses[j] * G * theta.cos();
        assert!(
            (reaction - expected_reaction).abs() <= 1e-12 * (1.0 + expected_reaction.abs()),
            "crank {j}: reaction {reaction} vs {expected_reaction}"
        );
    }
    // Contradictory rows (Φ4 asks Φ̈₄ = −2 at t = 0 where the others ask 0) cannot hold: no q̈
    // meets them, so the solve returns the least-squares one, and a run stops at the first
    // projection, which cannot close the loops once t² ≠ 0.
    let contradictory = model(true);
    let least_squares = accelerations(&contradictory, &mut contradictory.workspace(), 0.0, &q, &qdot)
        .expect("least-squares accelerations")
        .to_vec();
    assert!(least_squares.iter().all(|a| a.is_finite()), "{least_squares:?}");
    let run = lagrange::simulate(
        &contradictory,
        &State::new(0.0, q, qdot),
        1.0,
        lagrange::Method::Rk4 { dt: 1e-2 },
        &lagrange::Output::Ends,
    );
    assert!(matches!(run, Err(Error::AssemblyFailed { .. } | Error::Diverged { .. })), "{run:?}");
}

/// The multipliers say when they are not unique: the parallelogram with a third link has two
/// redundant directions of its four rows everywhere (`w1`, `w2` above); the chain of 3
/// parallelogram windows has none swinging and 3 laid flat, where 3 of its 6 loop rows become
/// dependent; a four-bar, a Cartesian pendulum and a model without constraints have none.
#[test]
fn the_multiplier_rank_counts_redundant_and_dependent_rows() {
    use lagrange::multiplier_rank;
    let m = lagrange_tests::parallelogram(false);
    let rank = multiplier_rank(&m, &mut m.workspace(), 0.0, &[-0.8; 3], &[1.5; 3]).expect("evaluates");
    assert_eq!((rank.rows, rank.determined, rank.unique()), (4, 2, false), "{rank:?}");
    // An exact redundancy: the eigenvalues of S along w1, w2 are round-off.
    assert!(rank.conditioning < 1e-14, "{rank:?}");

    let scene = lagrange_scenes::ParallelogramChain::new(3, G, 8.0).expect("valid");
    let chain = Model::new(scene.clone()).expect("valid");
    let mut ws = chain.workspace();
    for (theta, dependent) in [(-1.0, 0), (0.0, 3), (std::f64::consts::PI, 3)] {
        let s = scene.state_at(0.0, theta, 6.0);
        let rank = multiplier_rank(&chain, &mut ws, 0.0, &s.q, &s.qdot).expect("evaluates");
        assert_eq!((rank.rows, rank.rows - rank.determined), (6, dependent), "θ = {theta}: {rank:?}");
        assert_eq!(rank.unique(), dependent == 0);
    }

    let four_bar = Model::new(FourBar::new(LENGTHS, MASSES, false)).expect("valid");
    let start = four_bar_state(&four_bar, 0.6, 1.0);
    let rank = multiplier_rank(&four_bar, &mut four_bar.workspace(), 0.0, &start.q, &start.qdot).expect("evaluates");
    assert!(rank.unique() && rank.rows == 2 && rank.conditioning > 1e-3, "{rank:?}");

    let pendulum = Model::new(CartesianPendulum::new(1.0, 1.0)).expect("valid");
    let mut ws = pendulum.workspace();
    let rank = multiplier_rank(&pendulum, &mut ws, 0.0, &[0.6, -0.8], &[0.8, 0.6]).expect("evaluates");
    assert!(rank.unique() && rank.rows == 1, "{rank:?}");
    assert!(matches!(
        multiplier_rank(&pendulum, &mut ws, 0.0, &[f64::NAN, -0.8], &[0.8, 0.6]),
        Err(Error::NonFinite { .. })
    ));

    let reduced = Model::new(FourBar::new(LENGTHS, MASSES, true)).expect("valid");
    let rank = multiplier_rank(&reduced, &mut reduced.workspace(), 0.0, &[0.6], &[1.0]).expect("evaluates");
    assert_eq!((rank.rows, rank.determined, rank.unique()), (0, 0, true), "{rank:?}");
}

/// A knife edge (Chaplygin sleigh, no gravity): the velocity constraint
/// `−sin φ ẋ + cos φ ẏ + a φ̇ = 0` keeps the point `C + a e` moving along `e`. The constraint
/// force does no work, so `E = T` is conserved; it acts along every coordinate (none is cyclic) and
/// the run stays on the constraint after every projection.
#[test]
fn a_velocity_constraint_holds_and_does_no_work() {
    struct Sleigh {
        description: Description,
        a: f64,
    }
    impl Mechanism for Sleigh {
        fn description(&self) -> &Description {
            &self.description
        }
        fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
            p[0] = Pose::new(q[0], q[1], q[2]);
        }
        fn velocity_constraint<S: Scalar>(&self, _t: S, q: &[S], qdot: &[S], r: &mut [S]) {
            r[0] = -q[2].sin() * qdot[0] + q[2].cos() * qdot[1] + qdot[2] * self.a;
        }
    }
    let sleigh = Sleigh {
        description: Description::new()
            .length("x")
            .length("y")
            .angle("φ")
            .rigid("sleigh", 1.0, 0.1)
            .velocity_constraint("A1"),
        a: 0.5,
    };
    let model = Model::new(sleigh).expect("valid");
    assert_eq!(model.constraint_counts(), (0, 1));
    // x and y are cyclic in L, but the knife edge's force −Aᵀλ acts along both (and along φ):
    // no momentum is conserved.
    assert_eq!(model.cyclic_coordinates(), &[false, false, false]);
    assert!(model.conserves_energy());
    let initial = State::new(0.0, [0.0, 0.0, 0.0], [1.0, -1.0, 2.0]);
    let mut ws = model.workspace();
    let energy = |ws: &mut lagrange::Workspace<f64>, q: &[f64], v: &[f64]| {
        lagrange::energy_function(&model, ws, 0.0, q, v).expect("evaluates")
    };
    let e0 = energy(&mut ws, &initial.q, &initial.qdot);
    let run = lagrange::simulate(
        &model,
        &initial,
        3.0,
        Method::Dopri5 { tol: Tolerances::uniform(1e-12) },
        &Output::Every(0.1),
    )
    .expect("runs");
    for k in 0..run.len() {
        let [_, velocity] = lagrange::Dynamics::constraint_violation(&model, &mut ws, run.t[k], run.q(k), run.qdot(k))
            .expect("evaluates")
            .expect("constrained");
        assert!(velocity <= 1e-14, "violation {velocity:e} at {}", run.t[k]);
        // Energy: the integrator's error at tol 1e-12 over ≈ 100 steps, plus the projection's
        // removal of the velocity drift (second order in it); 1e-10 relative is 100× the
        // per-step tolerance.
        let e = energy(&mut ws, run.q(k), run.qdot(k));
        assert!((e - e0).abs() <= 1e-10 * e0, "E = {e}, E₀ = {e0} at {}", run.t[k]);
    }
}

/// The loop-closing pin's force is `λ`, and the bodies' reaction forces include it: with
/// `Φ = B_coupler − B_rocker`, `−Gᵀ λ = Gᵀ F` makes `F = −λ` the force of the rocker on the
/// coupler at `B` (and `+λ` on the rocker). The rocker's other joint is the ground pivot `O4`,
/// the coupler's the crank pin `A` (both eliminated by the coordinates), so the moment of each
/// body's reaction wrench about that joint is the moment of the pin force alone:
/// `R_τ + (C − P) × R_F = (B − P) × F`. Both sides are sums of a few products of size
/// `|λ| l`; the bound `1e-12` relative to that size leaves ~4500 ε for the multiplier's and the
/// reaction's own round-off (measured below 1e-14).
#[test]
fn the_loop_pin_force_is_the_multiplier_and_the_reactions_include_it() {
    let model = Model::new(FourBar::new(LENGTHS, MASSES, false)).unwrap();
    let [a, b, c, d] = LENGTHS;
    let mut ws = model.workspace();
    for (theta2, rate) in [(1.0, 6.0), (2.5, -3.0), (4.4, 10.0)] {
        let state = four_bar_state(&model, theta2, rate);
        let (q, qdot) = (&state.q, &state.qdot);
        let lambda = constraint_multipliers(&model, &mut ws, 0.0, q, qdot).unwrap().to_vec();
        let reactions = lagrange::reaction_forces(&model, &mut ws, 0.0, q, qdot).unwrap().to_vec();
        let point = |angle: f64, length: f64| [angle.cos() * length, angle.sin() * length];
        let [ax, ay] = point(q[0], a);
        let (pin_a, pin_o4) = ([ax, ay], [d, 0.0]);
        let [ex, ey] = point(q[1], b);
        let pin_b = [ax + ex, ay + ey];
        let cross = |r: [f64; 2], f: [f64; 2]| r[0] * f[1] - r[1] * f[0];
        let sub = |u: [f64; 2], v: [f64; 2]| [u[0] - v[0], u[1] - v[1]];
        let [half_ex, half_ey] = point(q[1], b / 2.0);
        let [half_rx, half_ry] = point(q[2], c / 2.0);
        let centres = [[ax + half_ex, ay + half_ey], [d + half_rx, half_ry]];
        let on_rocker = [lambda[0], lambda[1]];
        let on_coupler = [-lambda[0], -lambda[1]];
        let scale = (lambda[0].abs() + lambda[1].abs()) * (a + b + c + d);
        for (body, joint, force) in [(1, pin_a, on_coupler), (2, pin_o4, on_rocker)] {
            let r = &reactions[3 * body..3 * body + 3];
            let moment = r[2] + cross(sub(centres[body - 1], joint), [r[0], r[1]]);
            let expected = cross(sub(pin_b, joint), force);
            eprintln!(
                "body {body} at θ2 = {theta2}: moment balance to {:.1e} relative",
                (moment - expected).abs() / scale
            );
            assert!(
                (moment - expected).abs() <= 1e-12 * scale,
                "body {body} at θ2 = {theta2}: reaction moment {moment:e}, pin force moment {expected:e}"
            );
        }
    }
}
