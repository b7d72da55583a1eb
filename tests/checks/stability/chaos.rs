//! Chaos: the double pendulum released from large angles. Two runs at tolerances `tol` and
//! `tol/10` agree (to 1e-2 rad) only up to a time `T(tol)`; errors grow like `tol · e^{λt}`, so
//! `T` grows like `ln(1/tol)/λ` — by `ln 10/λ` per decade. The slope is checked against an
//! independent estimate of the largest Lyapunov exponent `λ` (Benettin's renormalized
//! separation of two neighbouring trajectories).

use super::{build, params};
use lagrange::{Method, Output, State, System, Tolerances};
use lagrange_tests::max_abs_diff;

const AGREEMENT: f64 = 1e-2;
const HORIZON: f64 = 60.0;

fn initial() -> State {
    State::new(0.0, [2.0, 2.0], [0.0, 0.0])
}

/// The first saved time at which the two runs differ by more than [`AGREEMENT`].
fn agreement_time(a: &lagrange::Trajectory, b: &lagrange::Trajectory) -> f64 {
    (0..a.len()).find(|&k| max_abs_diff(a.q(k), b.q(k)) > AGREEMENT).map_or(HORIZON, |k| a.t[k])
}

/// Largest Lyapunov exponent: separation `d0` renormalized every `segment` over `segments`.
fn lyapunov(system: &dyn System, initial: &State, segment: f64, segments: usize) -> f64 {
    let method = Method::Adaptive { tol: Tolerances::uniform(1e-13) };
    let d0 = 1e-8;
    let (mut a, mut b) = (initial.clone(), initial.clone());
    b.q[0] += d0;
    let mut sum = 0.0;
    for _ in 0..segments {
        let t = a.t + segment;
        a = system.simulate(&a, t, method, &Output::Ends).expect("integrates").last_state().expect("recorded");
        let end = system.simulate(&b, t, method, &Output::Ends).expect("integrates").last_state().expect("recorded");
        let diff: Vec<f64> = (0..2).map(|i| end.q[i] - a.q[i]).chain((0..2).map(|i| end.qdot[i] - a.qdot[i])).collect();
        let d = diff.iter().map(|x| x * x).sum::<f64>().sqrt();
        sum += (d / d0).ln();
        b = a.clone();
        for i in 0..2 {
            b.q[i] += diff[i] * d0 / d;
            b.qdot[i] += diff[i + 2] * d0 / d;
        }
    }
    sum / (segment * segments as f64)
}

#[test]
fn agreement_time_grows_logarithmically_at_the_lyapunov_rate() {
    let system = build("double_pendulum", &params("double_pendulum", &[]));
    let decades: Vec<i32> = (4..=13).collect();
    let runs: Vec<_> = decades
        .iter()
        .map(|&d| {
            let tol = Tolerances::uniform(10f64.powi(-d));
            system.simulate(&initial(), HORIZON, Method::Adaptive { tol }, &Output::Every(0.01)).expect("integrates")
        })
        .collect();
    let times: Vec<f64> = runs.windows(2).map(|w| agreement_time(&w[0], &w[1])).collect();
    // Least-squares line T = a + b · decades.
    let x: Vec<f64> = decades[..times.len()].iter().map(|&d| d as f64).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, times.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&times).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let syy: f64 = times.iter().map(|b| (b - my) * (b - my)).sum();
    let slope = sxy / sxx;
    let correlation = sxy / (sxx * syy).sqrt();
    // Logarithmic growth: a straight line in log(1/tol) explains the agreement times
    // (measured r = 0.99; 0.95 allows the scatter of a chaotic system's error direction).
    assert!(correlation >= 0.95, "agreement times {times:?}: correlation with log(1/tol) {correlation}");
    assert!(times.last() > times.first(), "{times:?}");
    // The slope against Benettin's exponent (λ = 1.50/s measured: ln 10/λ = 1.53 s per decade;
    // slope measured 1.8 s per decade). Finite-time exponents along one trajectory differ from
    // the long-time average, and the tolerance error does not start along the most unstable
    // direction: agreement within a factor 2 is what theory supports.
    let lambda = lyapunov(system.as_ref(), &initial(), 0.5, 200);
    let predicted = 10f64.ln() / lambda;
    assert!(
        slope / predicted < 2.0 && predicted / slope < 2.0,
        "agreement time grows {slope:.2} s per decade; Lyapunov exponent {lambda:.3}/s predicts {predicted:.2}; times {times:?}"
    );
}
