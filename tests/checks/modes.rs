//! Normal modes (`lagrange::modes`) against closed forms: the cart pendulum's frequency and zero
//! mode, the double and spring pendulums' two frequencies, the chain's lowest modes against its
//! mass and stiffness matrices derived by hand; a loop's one mode (the four-bar); the linear
//! motion a mode predicts against a small-amplitude nonlinear run; and the mechanisms without an
//! equilibrium, refused.

use lagrange::modes::{ModeKind, Modes, normal_modes};
use lagrange::{Error, Method, Output, State, Tolerances};
use lagrange_scenes::Params;
use lagrange_tests::scene;

/// The modes' frequencies come from exact derivatives through a Cholesky factor and a symmetric
/// eigensolver: round-off of a few ε times the condition of `M` (≤ 1e3 here); 1e-10 as the issue
/// asks leaves a wide margin.
const EXACT: f64 = 1e-10;

fn modes_of(id: &str, set: &[(&str, f64)], q: Option<&[f64]>) -> Result<Modes, Error> {
    let s = scene(id);
    let mut params = s.default_params();
    for (name, value) in set {
        params.set(name, *value).unwrap();
    }
    let q = q.map_or_else(|| s.default_state(&params).unwrap().q, <[f64]>::to_vec);
    let mut system = s.build(&params).unwrap();
    normal_modes(system.as_mut(), 0.0, &q)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= EXACT * b.abs().max(1e-300)
}

#[test]
fn the_cart_pendulum_rings_at_its_closed_form_and_rolls_freely() {
    let (cart, bob, r, g) = (2.7, 0.8, 1.3, 9.81);
    let modes =
        modes_of("cart_pendulum", &[("cart_mass", cart), ("bob_mass", bob), ("rod_length", r), ("gravity", g)], None)
            .unwrap();
    assert!(modes.equilibrium[1].abs() < 1e-12, "{:?}", modes.equilibrium);
    assert_eq!(modes.modes.len(), 2);
    // The zero mode: the cart and pendulum translating together, along X alone.
    let zero = &modes.modes[0];
    assert_eq!(zero.kind, ModeKind::Zero);
    assert_eq!(zero.shape, vec![1.0, 0.0]);
    let swing = &modes.modes[1];
    assert_eq!(swing.kind, ModeKind::Oscillating);
    let expected = g * (cart + bob) / (cart * r);
    assert!(close(swing.omega_squared, expected), "{} vs {expected}", swing.omega_squared);
    // The swing moves the cart against the bob: X/θ = −m r/(M + m).
    let ratio = swing.shape[0] / swing.shape[1];
    assert!(close(ratio, -bob * r / (cart + bob)), "{ratio}");
}

#[test]
fn the_double_pendulum_has_its_two_closed_form_frequencies() {
    let (m1, m2, l1, l2, g) = (1.3, 0.6, 0.9, 1.4, 9.81);
    let modes = modes_of(
        "double_pendulum",
        &[("mass_1", m1), ("mass_2", m2), ("length_1", l1), ("length_2", l2), ("gravity", g)],
        None,
    )
    .unwrap();
    // det(K − ω² M) = 0 with M = [[(m1+m2) l1², m2 l1 l2], [m2 l1 l2, m2 l2²]],
    // K = diag((m1+m2) g l1, m2 g l2): m1 l1 l2 ω⁴ − (m1+m2) g (l1+l2) ω² + (m1+m2) g² = 0.
    let (a, b, c) = (m1 * l1 * l2, -(m1 + m2) * g * (l1 + l2), (m1 + m2) * g * g);
    let root = (b * b - 4.0 * a * c).sqrt();
    let expected = [(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)];
    for (mode, w2) in modes.modes.iter().zip(expected) {
        assert!(close(mode.omega_squared, w2), "{} vs {w2}", mode.omega_squared);
    }
}

#[test]
fn the_spring_pendulum_stretches_and_swings_at_its_closed_forms() {
    let (m, k, l0, g) = (0.7, 35.0, 0.8, 9.81);
    let modes =
        modes_of("spring_pendulum", &[("mass", m), ("stiffness", k), ("rest_length", l0), ("gravity", g)], None)
            .unwrap();
    let stretched = l0 + m * g / k;
    assert!(close(modes.equilibrium[0], stretched) && modes.equilibrium[1].abs() < 1e-12, "{:?}", modes.equilibrium);
    let mut w2: Vec<f64> = modes.modes.iter().map(|m| m.omega_squared).collect();
    w2.sort_by(f64::total_cmp);
    let mut expected = [g / stretched, k / m];
    expected.sort_by(f64::total_cmp);
    for (got, want) in w2.iter().zip(expected) {
        assert!(close(*got, want), "{got} vs {want}");
    }
}

#[test]
fn the_chains_modes_are_those_of_its_hand_derived_matrices() {
    // N uniform rods (mass m, length l, inertia m l²/12), absolute angles, hanging: at rest
    // M_jk = m l² (N − max(j, k) − ½) for j ≠ k, M_jj = m l² (N − j − ⅔), K_jj = m g l (N − j − ½)
    // (0-based j), from the rods' centres x_i = Σ_{j<i} l sin θ_j + (l/2) sin θ_i.
    let (n, m, l, g) = (8_usize, 0.9, 0.6, 9.81);
    let modes =
        modes_of("chain", &[("links", n as f64), ("link_mass", m), ("link_length", l), ("gravity", g)], None).unwrap();
    let mass = nalgebra::DMatrix::from_fn(n, n, |j, k| {
        let top = j.max(k) as f64;
        m * l * l * if j == k { n as f64 - top - 2.0 / 3.0 } else { n as f64 - top - 0.5 }
    });
    let stiffness =
        nalgebra::DMatrix::from_fn(n, n, |j, k| if j == k { m * g * l * (n as f64 - j as f64 - 0.5) } else { 0.0 });
    let lower = mass.clone().cholesky().expect("positive definite").l();
    let inverse = lower.try_inverse().expect("invertible");
    let mut reference: Vec<f64> =
        (&inverse * stiffness * inverse.transpose()).symmetric_eigenvalues().iter().copied().collect();
    reference.sort_by(f64::total_cmp);
    assert!(modes.equilibrium.iter().all(|q| q.abs() < 1e-12));
    for (mode, want) in modes.modes.iter().zip(&reference).take(3) {
        assert!(close(mode.omega_squared, *want), "{} vs {want}", mode.omega_squared);
    }
    assert_eq!(modes.modes.len(), n);
}

/// The motion a mode predicts, `q* + ε v cos ωt`, against the nonlinear run from
/// `q* + ε v` at rest over one period: the largest gap in the coordinates.
fn linear_gap(id: &str, guess: Option<&[f64]>, mode: usize, epsilon: f64) -> f64 {
    let s = scene(id);
    let params: Params = s.default_params();
    let mut system = s.build(&params).unwrap();
    let q0 = guess.map_or_else(|| s.default_state(&params).unwrap().q, <[f64]>::to_vec);
    let modes = normal_modes(system.as_mut(), 0.0, &q0).unwrap();
    let (shape, omega) = (&modes.modes[mode].shape, modes.modes[mode].omega());
    let start: Vec<f64> = modes.equilibrium.iter().zip(shape).map(|(q, v)| q + epsilon * v).collect();
    let n = start.len();
    let mut initial = State::new(0.0, start, vec![0.0; n]);
    if system.constraint_counts() != (0, 0) {
        // On a loop the displaced state is put back on the constraints (an O(ε²) correction).
        let held: Vec<bool> = (0..n).map(|i| i == 0).collect();
        initial = system.assemble(&initial, &held).unwrap();
    }
    let period = std::f64::consts::TAU / omega;
    let times: Vec<f64> = (1..=40).map(|k| period * k as f64 / 40.0).collect();
    let run = system
        .simulate(&initial, period, Method::Dop853 { tol: Tolerances::uniform(1e-13) }, &Output::Times(times.clone()))
        .unwrap();
    let mut gap = 0.0_f64;
    for (row, t) in run.q.chunks(n).zip(&run.t) {
        for ((q, eq), v) in row.iter().zip(&modes.equilibrium).zip(shape) {
            gap = gap.max((q - (eq + epsilon * v * (omega * t).cos())).abs());
        }
    }
    gap
}

#[test]
fn a_mode_predicts_the_small_nonlinear_motion_to_second_order() {
    // Halving the amplitude divides the gap by 4 or more (the four-bar's nonlinear terms are
    // O(ε²): measured 4.5e-7 → 1.1e-7; the pendulums', even in θ, O(ε³): 3.5e-8 → 4.4e-9); the
    // integration's own error at tol 1e-13 is far below these gaps. The bound on the gap at
    // 1e-3, 1e-5, leaves a factor of about 90 over the largest measured.
    for (id, guess, mode) in
        [("double_pendulum", None, 0), ("double_pendulum", None, 1), ("four_bar", Some(&HANGING[..]), 0)]
    {
        let (big, small) = (linear_gap(id, guess, mode, 2e-3), linear_gap(id, guess, mode, 1e-3));
        eprintln!("{id} mode {mode}: linear gap {big:.2e} at amplitude 2e-3, {small:.2e} at 1e-3");
        assert!(big / small > 3.5, "{id} mode {mode}: gaps {big:e} at 2e-3 and {small:e} at 1e-3");
        assert!(small < 1e-3 * 1e-2, "{id} mode {mode}: gap {small:e} at amplitude 1e-3");
    }
}

/// A guess near the four-bar's hanging configuration (crank, coupler and rocker pointing down).
const HANGING: [f64; 3] = [-1.5, -0.5, -1.8];

#[test]
fn a_loop_rings_in_its_tangent_space() {
    // Three coordinates, two loop equations: one mode. Hanging, it oscillates; from the default
    // state (crank up) the nearest equilibrium is the upright one, the same mode unstable.
    let hanging = modes_of("four_bar", &[], Some(&HANGING)).unwrap();
    let upright = modes_of("four_bar", &[], None).unwrap();
    assert_eq!((hanging.modes.len(), upright.modes.len()), (1, 1));
    assert_eq!((hanging.modes[0].kind, upright.modes[0].kind), (ModeKind::Oscillating, ModeKind::Unstable));
    assert!(hanging.equilibrium[0] < 0.0 && upright.equilibrium[0] > 0.0);
    // The restriction of K to the tangent space is symmetric (a potential), to round-off.
    assert!(hanging.asymmetry < 1e-12, "{}", hanging.asymmetry);
}

#[test]
fn a_mechanism_that_cannot_rest_is_refused() {
    for (id, q) in [("kepler", None), ("driven_pendulum", None), ("wedge", None)] {
        match modes_of(id, &[], q) {
            Err(Error::NoEquilibrium { why, .. }) => assert!(!why.is_empty()),
            other => panic!("{id}: {other:?}"),
        }
    }
}
