//! Constraints among the coordinates under stress: a four-bar through its toggle positions, a
//! parallelogram with a redundant link, the drift an unprojected run accumulates, a change point
//! where the constraints lose rank, and Andrews' squeezer with its accelerations of 1e4–1e6
//! rad/s².

use super::{CaseBuilder, CaseSpec, Check, Cost, Effort, Measurement, find, scene_params, timed_simulate};
use crate::andrews;
use lagrange::{Description, Error, Mechanism, Method, Model, Output, Pose, Scalar, State, System, Tolerances};

pub const CONSTRAINED: CaseSpec = CaseSpec {
    id: "constraints",
    title: "Constraints among the coordinates: toggle positions, a redundant link, drift without projection, a \
            change point, Andrews' squeezer",
    scenes: &["four_bar", "andrews_squeezer"],
    theory: "Every integrator projects the state onto Φ = 0 and Φ̇ = 0 after each step (docs/method.md#constraints), \
             which leaves max |Φ| ≤ 16 ε L ≈ 1e-14 (L the scale of the positions, here about 1 m) and a velocity residual at round-off: a bound of \
             1e-10 on every saved sample (positions in m or rad, velocities in their units per second) leaves \
             ample margin. A crank-rocker passes its toggle positions (crank and coupler collinear: the rocker \
             at its extreme angles) twice per turn; G keeps full rank there, so nothing is singular and the \
             run passes them with its energy conserved. The same run without projection drifts off the \
             constraints, with an RK4 error ∝ t h⁴ per unit time. A parallelogram with a third parallel link \
             has two dependent constraint rows: q̈ is unique, λ is not. At a change point (a four-bar \
             with a = c, b = d fully flattened) the row of the x closure vanishes; moving along the \
             anti-parallelogram branch asks Φ̈ₓ = −θ̇₂² ≠ 0 of a vanished row, which no q̈ gives: the \
             regularized solve returns the least-squares q̈, finite. At the redundancy λ is the minimum-norm \
             choice, orthogonal to the rows' dependencies. \
             Andrews' squeezer (CWI/Bari test set) at t = 0.03 against the published angles, accurate to \
             about 3e-10 relative.",
    run: constrained,
};

/// A constraint violation on a saved sample beyond this fails: 5000 times the projection's
/// own stopping point, `16 ε L` for positions `L ≲ 10` m (up to 1000 times that where
/// Gauss–Newton stalls at the round-off of `Φ`).
const VIOLATION_BOUND: f64 = 1e-10;

fn constrained(case: &mut CaseBuilder, effort: Effort) -> Result<(), crate::Error> {
    let horizon = effort.pick(10.0, 2.0);
    case.setup = format!(
        "four_bar at its defaults (crank-rocker a = 0.2, b = 0.6, c = 0.5, d = 0.5 m, θ̇₂(0) = 6 rad/s, τ = 0) \
         over {horizon} s with adaptive (tol 1e-10) and RK4 (dt 1e-3), saved every 1 ms: violation, energy, \
         toggle crossings; the same RK4 without projection at dt = 1e-2 and 1e-3; a parallelogram of three \
         unit cranks (4 constraints, 2 dependent) over 2 s; the four-bar a = c = 0.5, b = d = 1 flattened \
         with θ̇ = (1, −1, −1); andrews_squeezer to t = 0.03 with adaptive at tol 1e-8, 1e-10, 1e-12."
    );
    toggles(case, horizon)?;
    drift(case, horizon)?;
    redundant(case)?;
    change_point(case)?;
    squeezer(case)?;
    Ok(())
}

/// The largest violation (positions and velocities) over a trajectory's samples.
fn largest_violation(trajectory: &lagrange::Trajectory) -> f64 {
    trajectory.violation.iter().flatten().fold(0.0, |m: f64, v| m.max(*v))
}

/// A finished run's measurement, or its failure.
fn run_measurement(
    m: Measurement,
    run: &Result<lagrange::Trajectory, Error>,
    wall: f64,
    value: impl FnOnce(&lagrange::Trajectory) -> f64,
) -> Measurement {
    match run {
        Ok(t) => m.value(value(t)).cost(Cost::of(&t.stats, wall)),
        Err(e) => m.failed(e),
    }
}

fn toggles(case: &mut CaseBuilder, horizon: f64) -> Result<(), crate::Error> {
    let scene = find("four_bar")?;
    let params = scene.default_params();
    let system = scene.build(&params)?;
    let initial = scene.default_state(&params)?;
    let output = Output::Every(1e-3);
    for method in [Method::Dopri5 { tol: Tolerances::uniform(1e-10) }, Method::Rk4 { dt: 1e-3 }] {
        let (run, wall) = timed_simulate(system.as_ref(), &initial, horizon, method, &output);
        let m = Measurement::new("defaults", "four_bar", method.name(), "max constraint violation over the samples")
            .method_settings(method, horizon);
        case.push(run_measurement(m, &run, wall, largest_violation).check(
            Check::AtMost,
            Some(0.0),
            Some(VIOLATION_BOUND),
        ));
        // Toggle positions: sin(θ₃ − θ₂) changes sign.
        let crossings = |t: &lagrange::Trajectory| {
            let side = |k: usize| (t.q(k)[1] - t.q(k)[0]).sin().signum();
            (1..t.len()).filter(|&k| side(k) != side(k - 1)).count() as f64
        };
        let turns = run.as_ref().map_or(0.0, |t| {
            let k = t.len() - 1;
            ((t.q(k)[0] - t.q(0)[0]) / std::f64::consts::TAU).abs().floor()
        });
        let m = Measurement::new("defaults", "four_bar", method.name(), "toggle positions passed")
            .method_settings(method, horizon)
            .note(format!("{turns} full crank turns; two toggle positions per turn"));
        case.push(run_measurement(m, &run, wall, crossings).check(
            Check::AtLeast,
            Some(2.0 * turns),
            Some(2.0 * turns),
        ));
        let m = Measurement::new("defaults", "four_bar", method.name(), "relative energy error (τ = 0)")
            .method_settings(method, horizon);
        case.push(run_measurement(m, &run, wall, |t| super::relative_energy_error(&t.energy)).check(
            Check::None,
            None,
            None,
        ));
    }
    Ok(())
}

/// Classical RK4 on `q̈(t, q, q̇)` without any projection: the drift the projection removes.
fn unprojected_rk4(system: &mut dyn System, initial: &State, dt: f64, steps: usize) -> Result<[f64; 2], Error> {
    let n = initial.q.len();
    let (mut q, mut v, mut t) = (initial.q.clone(), initial.qdot.clone(), initial.t);
    let (mut kq, mut kv) = (vec![vec![0.0; n]; 4], vec![vec![0.0; n]; 4]);
    let (mut qs, mut vs) = (vec![0.0; n], vec![0.0; n]);
    for _ in 0..steps {
        for stage in 0..4 {
            let c = [0.0, 0.5, 0.5, 1.0][stage];
            for i in 0..n {
                let (dq, dv) = if stage == 0 { (0.0, 0.0) } else { (kq[stage - 1][i], kv[stage - 1][i]) };
                qs[i] = q[i] + c * dt * dq;
                vs[i] = v[i] + c * dt * dv;
            }
            let a = system.accelerations(t + c * dt, &qs, &vs)?;
            kq[stage].copy_from_slice(&vs);
            kv[stage].copy_from_slice(a);
        }
        for i in 0..n {
            q[i] += dt / 6.0 * (kq[0][i] + 2.0 * kq[1][i] + 2.0 * kq[2][i] + kq[3][i]);
            v[i] += dt / 6.0 * (kv[0][i] + 2.0 * kv[1][i] + 2.0 * kv[2][i] + kv[3][i]);
        }
        t += dt;
    }
    Ok(system.constraint_violation(t, &q, &v)?.unwrap_or([0.0; 2]))
}

fn drift(case: &mut CaseBuilder, horizon: f64) -> Result<(), crate::Error> {
    let scene = find("four_bar")?;
    let params = scene.default_params();
    let mut system = scene.build(&params)?;
    let initial = scene.default_state(&params)?;
    for dt in [1e-2, 1e-3] {
        let steps = (horizon / dt).round() as usize;
        let start = std::time::Instant::now();
        let unprojected = unprojected_rk4(system.as_mut(), &initial, dt, steps);
        let wall = start.elapsed().as_secs_f64();
        let m = Measurement::new(format!("dt = {dt:e}, no projection"), "four_bar", "rk4", "final max |Φ| (m)")
            .method_settings(Method::Rk4 { dt }, horizon)
            .note("what the projection removes at every step; reported, not checked");
        let m = match unprojected {
            Ok([position, _]) => {
                m.value(position).cost(Cost { steps: Some(steps), wall_time_s: wall, ..Cost::default() })
            }
            Err(e) => m.failed(e),
        };
        case.push(m.check(Check::None, None, None));
        let method = Method::Rk4 { dt };
        let (run, wall) = timed_simulate(system.as_ref(), &initial, horizon, method, &Output::Ends);
        let m = Measurement::new(format!("dt = {dt:e}, projected"), "four_bar", "rk4", "final max |Φ| (m)")
            .method_settings(method, horizon);
        case.push(run_measurement(m, &run, wall, |t| t.violation.last().map_or(f64::NAN, |v| v[0])).check(
            Check::AtMost,
            Some(0.0),
            Some(VIOLATION_BOUND),
        ));
    }
    Ok(())
}

/// Three unit cranks from (0, 0), (1, 0), (2, 0) joined by a coupler: four closure equations
/// of which two are implied by the others.
struct Parallelogram {
    description: Description,
}

impl Mechanism for Parallelogram {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        for (i, pose) in p.iter_mut().enumerate() {
            *pose = Pose::point(q[i].cos() + i as f64, q[i].sin());
        }
    }
    fn constraints<S: Scalar>(&self, _t: S, q: &[S], phi: &mut [S]) {
        phi[0] = q[1].cos() - q[0].cos();
        phi[1] = q[1].sin() - q[0].sin();
        phi[2] = q[2].cos() - q[0].cos();
        phi[3] = q[2].sin() - q[1].sin();
    }
}

fn redundant(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let model = Model::new(Parallelogram {
        description: Description::new()
            .angle("q0")
            .angle("q1")
            .angle("q2")
            .point("a", 1.0)
            .point("b", 2.0)
            .point("c", 0.5)
            .gravity(9.81)
            .constraint("Φ1")
            .constraint("Φ2")
            .constraint("Φ3")
            .constraint("Φ4"),
    })?;
    let initial = State::new(0.0, [-0.8; 3], [1.5; 3]);
    let method = Method::Dopri5 { tol: Tolerances::uniform(1e-10) };
    let start = std::time::Instant::now();
    let run = lagrange::simulate(&model, &initial, 2.0, method, &Output::Every(0.01));
    let wall = start.elapsed().as_secs_f64();
    let label = "three parallel cranks";
    let m = Measurement::new(label, "local:parallelogram", "dopri5", "max constraint violation over the samples")
        .method_settings(method, 2.0);
    case.push(run_measurement(m, &run, wall, largest_violation).check(Check::AtMost, Some(0.0), Some(VIOLATION_BOUND)));
    // The three cranks swing as one pendulum: every angle equal, to the tolerance.
    let m = Measurement::new(label, "local:parallelogram", "dopri5", "max |q2 − q0| over the samples (rad)")
        .method_settings(method, 2.0);
    let spread = |t: &lagrange::Trajectory| (0..t.len()).map(|k| (t.q(k)[2] - t.q(k)[0]).abs()).fold(0.0, f64::max);
    case.push(run_measurement(m, &run, wall, spread).check(Check::AtMost, Some(0.0), Some(VIOLATION_BOUND)));
    // At a redundancy the reactions are not unique; the engine reports the minimum-norm λ, which
    // is orthogonal to every combination w of the rows with Gᵀ w = 0. For q0 = q1 = q2 = θ those
    // are w1 = (cos θ, sin θ, 0, 0) and w2 = (−cos θ, 0, cos θ, sin θ).
    let mut ws = model.workspace();
    let lambda = lagrange::constraint_multipliers(&model, &mut ws, 0.0, &initial.q, &initial.qdot)?.to_vec();
    let (s, c) = initial.q[0].sin_cos();
    let along = |w: [f64; 4]| {
        let norm = w.iter().map(|v| v * v).sum::<f64>().sqrt() * lambda.iter().map(|v| v * v).sum::<f64>().sqrt();
        // λ = 0 (no reaction needed) is the minimum-norm solution itself.
        if norm == 0.0 { 0.0 } else { w.iter().zip(&lambda).map(|(a, b)| a * b).sum::<f64>().abs() / norm }
    };
    let m = Measurement::new(label, "local:parallelogram", "engine", "|λ · w| / (|λ| |w|) over the redundancies w")
        .note(format!("λ = {lambda:?}"));
    // The refined solve keeps λ in the range of S up to round-off amplified by the shift:
    // ε / 1e-10 ≈ 2.2e-6 of |λ| along a redundancy.
    case.push(m.value(along([c, s, 0.0, 0.0]).max(along([-c, 0.0, c, s]))).check(Check::AtMost, Some(0.0), Some(1e-5)));
    Ok(())
}

fn change_point(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let scene = find("four_bar")?;
    let changes = [("crank", 0.5), ("coupler", 1.0), ("rocker", 0.5), ("ground", 1.0)];
    let params = scene_params(scene, &changes)?;
    let mut system = scene.build(&params)?;
    let m = Measurement::new("a = c, b = d, flattened, θ̇ = (1, −1, −1)", "four_bar", "engine", "q̈").params(&changes);
    let m = match system.accelerations(0.0, &[0.0; 3], &[1.0, -1.0, -1.0]) {
        Ok(a) => m.value(a.iter().fold(0.0, |x: f64, v| x.max(v.abs()))),
        Err(e) => m.failed_with(&e),
    };
    // No acceleration keeps the vanished row at Φ̈ = 0: the regularized solve returns the
    // least-squares q̈, finite, rather than an error (docs/method.md#constraints).
    case.push(m.check(Check::Finite, None, None));
    // Along the parallelogram branch (θ̇ = (1, 0, 1)) the vanished row asks nothing: q̈ exists.
    let m = Measurement::new("a = c, b = d, flattened, θ̇ = (1, 0, 1)", "four_bar", "engine", "max |q̈| (rad/s²)")
        .params(&changes);
    let m = match system.accelerations(0.0, &[0.0; 3], &[1.0, 0.0, 1.0]) {
        Ok(a) => m.value(a.iter().fold(0.0, |x: f64, v| x.max(v.abs()))),
        Err(e) => m.failed(e),
    };
    case.push(m.check(Check::Finite, None, None));
    Ok(())
}

fn squeezer(case: &mut CaseBuilder) -> Result<(), crate::Error> {
    let scene = find("andrews_squeezer")?;
    let params = scene.default_params();
    let mut system = scene.build(&params)?;
    let initial = scene.default_state(&params)?;
    // The published consistent initial accelerations, from the body model.
    let got = system.accelerations(0.0, &initial.q, &initial.qdot)?.to_vec();
    let scale = andrews::PUBLISHED_INITIAL_ACCELERATIONS[0].abs();
    let worst =
        got.iter().zip(andrews::PUBLISHED_INITIAL_ACCELERATIONS).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
            / scale;
    let m = Measurement::new("t = 0", "andrews_squeezer", "engine", "relative error of q̈(0) vs the published values")
        .note("relative to the largest published |q̈| = 1.42e4 rad/s²");
    case.push(m.value(worst).check(Check::AtMost, Some(0.0), Some(1e-10)));
    for tol in [1e-8, 1e-10, 1e-12] {
        let method = Method::Dopri5 { tol: Tolerances::uniform(tol) };
        let (run, wall) = timed_simulate(system.as_ref(), &initial, andrews::T_END, method, &Output::Ends);
        let m = Measurement::new(
            format!("tol {tol:e}"),
            "andrews_squeezer",
            "dopri5",
            "max relative angle error at t = 0.03 vs the published solution",
        )
        .method_settings(method, andrews::T_END);
        let error = |t: &lagrange::Trajectory| {
            let q = t.q(t.len() - 1);
            q.iter().zip(andrews::PUBLISHED_AT_0_03[0]).map(|(a, b)| ((a - b) / b).abs()).fold(0.0, f64::max)
        };
        // 1e-8 relative is asked at the tightest tolerance; the others are reported.
        let bound = if tol <= 1e-12 { Check::AtMost } else { Check::None };
        case.push(run_measurement(m, &run, wall, error).check(bound, Some(0.0), (tol <= 1e-12).then_some(1e-8)));
        let m =
            Measurement::new(format!("tol {tol:e}"), "andrews_squeezer", "dopri5", "constraint violation at t = 0.03")
                .method_settings(method, andrews::T_END);
        case.push(run_measurement(m, &run, wall, largest_violation).check(
            Check::AtMost,
            Some(0.0),
            Some(VIOLATION_BOUND),
        ));
    }
    Ok(())
}
