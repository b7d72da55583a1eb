//! Chaos: how long runs at neighbouring tolerances agree, against the Lyapunov exponent.

use super::{CaseBuilder, CaseSpec, Check, Cost, Effort, Measurement, find};
use crate::Error;
use lagrange::{Method, Output, State, System, Tolerances, Trajectory};
use std::time::Instant;

pub const CHAOS: CaseSpec = CaseSpec {
    id: "chaos",
    title: "Double pendulum from large angles: agreement time against tolerance",
    scenes: &["double_pendulum"],
    theory: "Errors grow like tol · e^{λt} in a chaotic motion, so two runs at tolerances tol and tol/10 agree to \
             1e-2 rad up to T(tol) ≈ (ln(1e-2/C) + ln(1/tol))/λ: T grows by ln 10/λ per decade of tolerance. The \
             slope of a least-squares line through T against log₁₀(1/tol) gives a Lyapunov-like exponent \
             λ = ln 10/slope, compared with Benettin's estimate of the largest Lyapunov exponent (the \
             separation of two neighbouring trajectories renormalized every 0.5 s). Finite-time exponents \
             along one trajectory and a tolerance error that does not start along the most unstable direction \
             allow agreement within a factor 2.",
    run: chaos,
};

/// Agreement threshold (rad).
const AGREEMENT: f64 = 1e-2;

fn agreement_time(a: &Trajectory, b: &Trajectory, horizon: f64) -> f64 {
    let differs = |k: usize| a.q(k).iter().zip(b.q(k)).any(|(x, y)| (x - y).abs() > AGREEMENT);
    (0..a.len().min(b.len())).find(|&k| differs(k)).map_or(horizon, |k| a.t[k])
}

/// Benettin's largest Lyapunov exponent: separation 1e-8 renormalized every `segment`.
fn lyapunov(system: &dyn System, initial: &State, segment: f64, segments: usize) -> Result<f64, Error> {
    let method = Method::Dopri5 { tol: Tolerances::uniform(1e-13) };
    let d0 = 1e-8;
    let (mut a, mut b) = (initial.clone(), initial.clone());
    b.q[0] += d0;
    let mut sum = 0.0;
    let last = |s: &State, t: f64| -> Result<State, Error> {
        let run = system.simulate(s, t, method, &Output::Ends)?;
        run.last_state().ok_or(Error::Missing("empty run"))
    };
    for _ in 0..segments {
        let t = a.t + segment;
        a = last(&a, t)?;
        let end = last(&b, t)?;
        let n = a.q.len();
        let diff: Vec<f64> = (0..n).map(|i| end.q[i] - a.q[i]).chain((0..n).map(|i| end.qdot[i] - a.qdot[i])).collect();
        let d = diff.iter().map(|x| x * x).sum::<f64>().sqrt();
        sum += (d / d0).ln();
        b = a.clone();
        for i in 0..n {
            b.q[i] += diff[i] * d0 / d;
            b.qdot[i] += diff[n + i] * d0 / d;
        }
    }
    Ok(sum / (segment * segments as f64))
}

/// The least-squares slope of `y` against `x` over `points` `(x, y)`, and their correlation
/// coefficient.
fn line_fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(x, y), p| (x + p.0 / n, y + p.1 / n));
    let (sxy, sxx, syy) = points.iter().fold((0.0, 0.0, 0.0), |(a, b, c), p| {
        (a + (p.0 - mx) * (p.1 - my), b + (p.0 - mx) * (p.0 - mx), c + (p.1 - my) * (p.1 - my))
    });
    (sxy / sxx, sxy / (sxx * syy).sqrt())
}

fn chaos(case: &mut CaseBuilder, effort: Effort) -> Result<(), Error> {
    let horizon = effort.pick(60.0, 40.0);
    let decades: Vec<i32> = effort.pick((4..=13).collect(), (4..=11).collect());
    let initial = State::new(0.0, [2.0, 2.0], [0.0, 0.0]);
    case.setup = format!(
        "θ₁ = θ₂ = 2 rad at rest, m = l = 1, g = 9.81; adaptive at tol = 1e-{} … 1e-{}, saved every 0.01 s for {horizon} s; \
         Benettin over {} s.",
        decades[0],
        decades[decades.len() - 1],
        effort.pick(100, 50)
    );
    let scene = find("double_pendulum")?;
    let system = scene.build(&scene.default_params())?;
    let mut runs = Vec::new();
    for &d in &decades {
        let tol = 10f64.powi(-d);
        let start = Instant::now();
        let method = Method::Dopri5 { tol: Tolerances::uniform(tol) };
        let run = system.simulate(&initial, horizon, method, &Output::Every(0.01))?;
        runs.push((tol, run, start.elapsed().as_secs_f64()));
    }
    let mut points = Vec::new();
    for pair in runs.windows(2) {
        let ((tol, a, wall), (_, b, _)) = (&pair[0], &pair[1]);
        let time = agreement_time(a, b, horizon);
        points.push(((1.0 / tol).log10(), time));
        case.push(
            Measurement::new(
                format!("tol = {tol:.0e} vs {:.0e}", tol / 10.0),
                "double_pendulum",
                "dopri5",
                "agreement time to 1e-2 rad (s)",
            )
            .method_settings(Method::Dopri5 { tol: Tolerances::uniform(*tol) }, horizon)
            .value(time)
            .cost(Cost::of(&a.stats, *wall)),
        );
    }
    // Least-squares slope of T against log₁₀(1/tol).
    let (slope, correlation) = line_fit(&points);
    let start = Instant::now();
    let lambda = lyapunov(system.as_ref(), &initial, 0.5, effort.pick(200, 100))?;
    let benettin_wall = start.elapsed().as_secs_f64();
    // Logarithmic growth: a straight line in log(1/tol) explains the agreement times (measured
    // r = 0.99; 0.95 allows the scatter of a chaotic system's error direction), and the
    // tightest tolerance pair agrees longest.
    case.push(
        Measurement::new("all tolerances", "double_pendulum", "dopri5", "correlation of T with log₁₀(1/tol)")
            .value(correlation)
            .check(Check::AtLeast, None, Some(0.95)),
    );
    let (first, last) = (points[0].1, points[points.len() - 1].1);
    case.push(
        Measurement::new(
            "all tolerances",
            "double_pendulum",
            "dopri5",
            "agreement time, tightest pair − loosest pair (s)",
        )
        .value(last - first)
        .note(format!("T = {first:.2} s at the loosest pair, {last:.2} s at the tightest"))
        .check(Check::AtLeast, None, Some(f64::MIN_POSITIVE)),
    );
    case.push(
        Measurement::new("all tolerances", "double_pendulum", "dopri5", "agreement time per decade of tolerance (s)")
            .value(slope)
            .check(Check::WithinFactor, Some(10f64.ln() / lambda), Some(2.0)),
    );
    case.push(
        Measurement::new("all tolerances", "double_pendulum", "dopri5", "Lyapunov-like exponent ln 10 / slope (1/s)")
            .value(10f64.ln() / slope)
            .check(Check::WithinFactor, Some(lambda), Some(2.0))
            .note(format!("theory: Benettin's λ = {lambda:.3}/s")),
    );
    case.push(
        Measurement::new("Benettin", "double_pendulum", "dopri5", "largest Lyapunov exponent (1/s)")
            .method_settings(Method::Dopri5 { tol: Tolerances::uniform(1e-13) }, 0.5 * effort.pick(200.0, 100.0))
            .value(lambda)
            .cost(Cost { wall_time_s: benettin_wall, ..Cost::default() }),
    );
    Ok(())
}
