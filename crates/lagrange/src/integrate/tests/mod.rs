//! Integrator checks on small mechanisms: observed order, tolerance tracking, structure.

mod implicit;
mod newton;

use super::*;
use crate::test_support::{Charge, Spring, assert_relative, cart};
use crate::{Dynamics, Model, RawModel, State};
use lagrange_testing::max_abs_diff;

pub(super) fn final_state<D: Dynamics>(system: &D, initial: &State, t_end: f64, method: Method) -> Vec<f64> {
    let traj = simulate(system, initial, t_end, method, &Output::Ends).unwrap();
    let k = traj.len() - 1;
    [traj.q(k), traj.qdot(k)].concat()
}

/// The final-state errors of `method(dt)` on the cart pendulum over 2 s, against a 1e-13
/// reference, at three halving steps `dts`: each halving divides the error by a ratio in `ratios`.
pub(super) fn assert_order(initial: &State, dts: [f64; 3], method: fn(f64) -> Method, ratios: std::ops::Range<f64>) {
    let model = Model::new(cart(2.0, 1.0, 1.0)).unwrap();
    let reference = final_state(&model, initial, 2.0, Method::Dopri5 { tol: Tolerances::uniform(1e-13) });
    let errors: Vec<f64> =
        dts.iter().map(|&dt| max_abs_diff(&final_state(&model, initial, 2.0, method(dt)), &reference)).collect();
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!(ratios.contains(&ratio), "errors {errors:?}, ratio {ratio}");
    }
}

#[test]
fn rk4_is_fourth_order_on_the_cart_pendulum() {
    // Order 4: ratio 2⁴ = 16 per halving, ±25 % for the asymptotic regime at these steps.
    assert_order(&State::new(0.0, [0.0, 0.5], [0.0, 0.0]), [0.02, 0.01, 0.005], |dt| Method::Rk4 { dt }, 12.0..20.0);
}

#[test]
fn variational_is_second_order_and_conserves_cart_momentum() {
    let model = Model::new(cart(2.0, 1.0, 1.0)).unwrap();
    let initial = State::new(0.0, [0.0, 0.5], [0.3, 0.0]);
    // Order 2: ratio 4 per halving, ±25 %.
    assert_order(&initial, [0.02, 0.01, 0.005], |dt| Method::Variational { dt }, 3.0..5.0);
    // Horizontal momentum p_X: exactly conserved by the discrete Noether theorem.
    let traj = simulate(&model, &initial, 20.0, Method::Variational { dt: 0.01 }, &Output::Every(1.0)).unwrap();
    let mut ws = model.workspace();
    let mut p = [0.0; 2];
    model.momenta(&mut ws, 0.0, &initial.q, &initial.qdot, &mut p).unwrap();
    let p0 = p[0];
    for k in 0..traj.len() {
        model.momenta(&mut ws, traj.t[k], traj.q(k), traj.qdot(k), &mut p).unwrap();
        // 2000 steps, each conserving p_X to the Newton residual (~1e-16 relative): 1e-12 bound.
        assert_relative(p[0], p0, 1e-12);
    }
}

#[test]
fn adaptive_error_tracks_tolerance_and_dense_output_is_accurate() {
    let model = Model::new(Spring::new(1.0, 10.0, 0.0)).unwrap();
    let omega = 10.0_f64.sqrt();
    let initial = State::new(0.0, [0.1], [0.0]);
    let times: Vec<f64> = (0..=50).map(|k| k as f64 * 0.2).collect();
    let mut previous = f64::INFINITY;
    for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let traj = simulate(
            &model,
            &initial,
            10.0,
            Method::Dopri5 { tol: Tolerances::uniform(tol) },
            &Output::Times(times.clone()),
        )
        .unwrap();
        let err = (0..traj.len()).map(|k| (traj.q(k)[0] - 0.1 * (omega * traj.t[k]).cos()).abs()).fold(0.0, f64::max);
        // Global error within a factor 100 of the tolerance (local control, ~16 periods of accumulation),
        // and decreasing with it.
        assert!(err < 100.0 * tol, "tol {tol}: error {err}");
        assert!(err < previous, "tol {tol}: error {err} not below {previous}");
        previous = err;
    }
}

/// DOP853's step is of order 8: on the linear oscillator (`ω = √10`, 2 s) with steps forced to
/// `h` (a tolerance loose enough that no step is rejected, `t_limit` one step ahead), halving
/// `h` from `ω h` = 0.4 to 0.2 divides the final error against the exact solution by between
/// 2^7.5 and 2^9 (order 8 with the next order's term still visible: measured 366, and 1965
/// from `ω h` = 0.8; a wrong coefficient drops a Runge–Kutta method to order 5 or less, a ratio
/// of 32). Its dense output is of order 7 (the error of a point interpolated within a step is
/// `O(h⁸)` locally): the largest error at the steps' midpoints falls by at least 2⁷ × 0.75
/// (measured 292).
#[test]
fn dop853_is_eighth_order_with_a_seventh_order_dense_output() {
    let (amplitude, omega) = (0.1, 10.0_f64.sqrt());
    let model = Model::new(Spring::new(1.0, omega * omega, 0.0)).unwrap();
    let exact = |t: f64| [amplitude * (omega * t).cos(), -amplitude * omega * (omega * t).sin()];
    let initial = State::new(0.0, [amplitude], [0.0]);
    let (mut final_errors, mut middle_errors) = (Vec::new(), Vec::new());
    for steps in [16, 32] {
        let h = 2.0 / steps as f64;
        let mut dop = Dop853::new(1, Tolerances::uniform(0.9)).unwrap();
        let mut ws = model.workspace();
        dop.start(&model, &mut ws, 0.0, &initial.q, &initial.qdot, h).unwrap();
        let (mut q, mut qdot) = ([0.0; 1], [0.0; 1]);
        let mut middle: f64 = 0.0;
        for k in 0..steps {
            dop.step(&model, &mut ws, (k + 1) as f64 * h).unwrap();
            let t = (k as f64 + 0.5) * h;
            dop.interpolate(&model, &mut ws, t, &mut q, &mut qdot).unwrap();
            middle = middle.max(max_abs_diff(&[q[0], qdot[0]], &exact(t)));
        }
        assert_eq!((dop.stats().steps, dop.stats().rejected), (steps, 0), "h = {h}");
        final_errors.push(max_abs_diff(&[dop.q()[0], dop.qdot()[0]], &exact(2.0)));
        middle_errors.push(middle);
    }
    for w in final_errors.windows(2) {
        assert!((181.0..512.0).contains(&(w[0] / w[1])), "final errors {final_errors:?}");
    }
    for w in middle_errors.windows(2) {
        assert!(w[0] / w[1] >= 0.75 * 128.0, "midpoint errors {middle_errors:?}");
    }
}

/// DOP853's global error tracks its tolerance, as Dopri5's does, down to 1e-13 on the linear
/// oscillator over 10 s (dense-output samples every 0.2 s), with fewer evaluations than Dopri5
/// from 1e-8 down.
#[test]
fn dop853_error_tracks_tolerance_with_fewer_evaluations_than_dopri5() {
    let model = Model::new(Spring::new(1.0, 10.0, 0.0)).unwrap();
    let omega = 10.0_f64.sqrt();
    let initial = State::new(0.0, [0.1], [0.0]);
    let times: Vec<f64> = (0..=50).map(|k| k as f64 * 0.2).collect();
    let mut previous = f64::INFINITY;
    for tol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-13] {
        let run = |method| simulate(&model, &initial, 10.0, method, &Output::Times(times.clone())).unwrap();
        let traj = run(Method::Dop853 { tol: Tolerances::uniform(tol) });
        let err = (0..traj.len()).map(|k| (traj.q(k)[0] - 0.1 * (omega * traj.t[k]).cos()).abs()).fold(0.0, f64::max);
        // Global error within a factor 100 of the tolerance (local control, ~16 periods of
        // accumulation; round-off of ~1e-16 per step below 1e-13), and decreasing with it.
        assert!(err < 100.0 * tol, "tol {tol}: error {err}");
        assert!(err < previous, "tol {tol}: error {err} not below {previous}");
        previous = err;
        if tol <= 1e-8 {
            let dopri = run(Method::Dopri5 { tol: Tolerances::uniform(tol) });
            assert!(
                traj.stats.evaluations < dopri.stats.evaluations,
                "tol {tol}: {:?} vs {:?}",
                traj.stats,
                dopri.stats
            );
        }
    }
}

#[test]
fn raw_lagrangian_of_a_body_model_matches_the_body_path() {
    let model = Model::new(cart(2.0, 1.0, 1.3)).unwrap();
    let raw = RawModel::new(Model::new(cart(2.0, 1.0, 1.3)).unwrap()).unwrap();
    let (mut ws, mut rws) = (model.workspace(), raw.workspace());
    for (q, v) in [([0.1, 0.4], [0.2, -1.0]), ([-2.0, 2.9], [1.5, 3.0])] {
        let a = crate::accelerations(&model, &mut ws, 0.0, &q, &v).unwrap().to_vec();
        let b = crate::accelerations(&raw, &mut rws, 0.0, &q, &v).unwrap();
        let expected = model.mechanism().closed_form(&q, &v);
        for i in 0..2 {
            assert_relative(a[i], expected[i], 1e-13);
            assert_relative(b[i], expected[i], 1e-13);
        }
    }
    assert_eq!(model.cyclic_coordinates(), &[true, false]);
    assert_eq!(raw.cyclic_coordinates(), &[true, false]);
}

#[test]
fn velocity_dependent_potential_gives_cyclotron_motion() {
    let raw = RawModel::new(Charge::new(2.0, 3.0)).unwrap();
    let mut ws = raw.workspace();
    let a = crate::accelerations(&raw, &mut ws, 0.0, &[0.3, -0.2], &[0.7, 1.1]).unwrap();
    let omega = 1.5;
    assert!((a[0] - omega * 1.1).abs() < 1e-14 && (a[1] + omega * 0.7).abs() < 1e-14, "{a:?}");
}

#[test]
fn damped_oscillator_is_not_energy_conserving_and_decays() {
    let model = Model::new(Spring::new(1.0, 4.0, 0.5)).unwrap();
    assert!(model.has_generalized_force() && !model.conserves_energy() && model.has_constant_mass_matrix());
    let traj =
        simulate(&model, &State::new(0.0, [1.0], [0.0]), 10.0, Method::Rk4 { dt: 0.01 }, &Output::Every(1.0)).unwrap();
    // E(t) decays like exp(−c t / m) on average: after 10 s below 1 % of E0 = 2.
    assert!(traj.energy[traj.len() - 1] < 0.02 * traj.energy[0], "{:?}", traj.energy);
}

/// The variational integrator counts its work as the other methods do: one evaluation (the
/// gradient of `L`) for the momenta at the start, one per Newton iteration and one per step for
/// the new momenta; the Newton matrix (a Jacobian, from the Hessian of `L`, and one
/// factorization) is built at the first step and kept while Newton contracts fast, as it does on
/// this smooth motion. Reading the velocities back by [`Variational::velocities`] inverts the
/// Legendre map by Newton with the Hessian's velocity block (a Jacobian and a factorization per
/// iteration); a run through [`simulate`] reads them with the system's mass matrix instead (one
/// factorization, no Jacobian) and reports exactly these counts.
#[test]
fn variational_counts_its_evaluations() {
    let model = Model::new(cart(2.0, 1.0, 1.0)).unwrap();
    let initial = State::new(0.0, [0.0, 0.5], [0.3, 0.0]);
    let mut integrator = Variational::new(&model);
    integrator.start(&model, 0.0, &initial.q, &initial.qdot).unwrap();
    assert_eq!(integrator.stats(), Stats { evaluations: 1, ..Stats::default() });
    for _ in 0..10 {
        integrator.step(&model, 0.01).unwrap();
    }
    let stepped = integrator.stats();
    assert_eq!(stepped.steps, 10);
    assert!(stepped.newton_iterations >= 2 * stepped.steps, "{stepped:?}");
    assert_eq!(stepped.evaluations, 1 + stepped.newton_iterations + stepped.steps, "{stepped:?}");
    assert_eq!((stepped.jacobians, stepped.factorizations), (1, 1), "{stepped:?}");
    let mut qdot = [0.0; 2];
    integrator.velocities(&model, &mut qdot).unwrap();
    let read = integrator.stats();
    let legendre = read.newton_iterations - stepped.newton_iterations;
    assert!(legendre >= 1, "{read:?}");
    assert_eq!(read.evaluations - stepped.evaluations, legendre);
    assert_eq!((read.jacobians, read.factorizations), (1 + legendre, 1 + legendre));
    let run = simulate(&model, &initial, 0.1, Method::Variational { dt: 0.01 }, &Output::Ends).unwrap();
    let inversion = run.stats.newton_iterations - stepped.newton_iterations;
    assert!(inversion >= 1, "{:?}", run.stats);
    let expected = Stats {
        evaluations: stepped.evaluations + inversion,
        newton_iterations: stepped.newton_iterations + inversion,
        factorizations: stepped.factorizations + 1,
        ..stepped
    };
    assert_eq!(run.stats, expected);
}

/// [`run`] writes the samples [`simulate`] records into any sink, and evaluates the energy
/// only for a sink that asks for it.
#[test]
fn run_writes_the_samples_of_simulate_into_any_sink() {
    #[derive(Default)]
    struct Samples {
        t: Vec<f64>,
        q: Vec<f64>,
        qdot: Vec<f64>,
        energies: usize,
        stats: Option<Stats>,
    }
    impl Sink for Samples {
        fn record(&mut self, sample: Sample<'_>) {
            self.t.push(sample.t);
            self.q.extend_from_slice(sample.q);
            self.qdot.extend_from_slice(sample.qdot);
            self.energies += usize::from(sample.energy.is_some());
        }
        fn finish(&mut self, stats: Stats) {
            self.stats = Some(stats);
        }
    }
    let model = Model::new(cart(2.0, 1.0, 1.0)).unwrap();
    let initial = State::new(0.0, [0.0, 0.5], [0.3, 0.0]);
    let output = Output::Every(0.25);
    for method in [Method::Rk4 { dt: 0.01 }, Method::Dopri5 { tol: Tolerances::uniform(1e-9) }] {
        let expected = simulate(&model, &initial, 1.0, method, &output).unwrap();
        let mut sink = Samples::default();
        let stats = match method {
            Method::Rk4 { dt } => {
                run(&model, &mut Rk4::new(2).with_step(dt).unwrap(), &initial, 1.0, &output, &mut sink)
            }
            _ => {
                run(&model, &mut Dopri5::new(2, Tolerances::uniform(1e-9)).unwrap(), &initial, 1.0, &output, &mut sink)
            }
        }
        .unwrap();
        assert_eq!((&sink.t, &sink.q, &sink.qdot), (&expected.t, &expected.q, &expected.qdot), "{method:?}");
        assert_eq!((sink.energies, sink.stats), (0, Some(expected.stats)), "{method:?}");
        assert_eq!(stats, expected.stats);
        assert!(expected.stats.steps > 0 && expected.energy.iter().all(|e| e.is_finite()));
    }
}

/// Bad output times name the first offending time, never NaN (it used to report `= NaN`).
#[test]
fn bad_output_times_name_the_first_offending_time() {
    let model = Model::new(Spring::new(1.0, 10.0, 0.0)).unwrap();
    let initial = State::new(0.0, [0.1], [0.0]);
    for (times, bad) in [(vec![0.1, 0.3, 0.2], 0.2), (vec![0.1, 2.5], 2.5), (vec![-0.5, 0.5], -0.5)] {
        let error = simulate(&model, &initial, 1.0, Method::Rk4 { dt: 0.01 }, &Output::Times(times)).unwrap_err();
        assert!(!error.to_string().contains("NaN"), "{error}");
        match error {
            Error::InvalidSetting { what: "output time", value, .. } => assert_eq!(value, bad),
            other => panic!("expected InvalidSetting naming the output time, got {other}"),
        }
    }
}
