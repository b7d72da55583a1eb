//! Long runs: ten million steps of the symplectic Gauss integrator and of rapier, and whether
//! their energy drifts.

use super::theory;
use super::{CaseBuilder, CaseSpec, Check, Cost, Effort, Measurement, RunSettings, find, scene_params, timed_simulate};
use crate::Error;
use lagrange::{Method, Output, State};
use lagrange_maximal::{Engine, Settings, build};
use std::time::Instant;

pub const LONG_RUN: CaseSpec = CaseSpec {
    id: "long_run",
    title: "Long runs of the Gauss–Legendre integrator",
    scenes: &["double_pendulum", "chain", "harmonic_oscillator"],
    theory: "Gauss–Legendre is symplectic and symmetric: on a nonlinear system its energy error is a bounded \
             O(h⁴) oscillation without drift (Hairer, Lubich & Wanner, Geometric Numerical Integration, \
             §IX.8), so the largest error over the last tenth of a run is no larger than over the first (50 % \
             allows the two tenths to sample the oscillation differently); on the linear oscillator it conserves \
             the quadratic energy exactly, up to round-off (≤ 4ε per step, accumulating at worst linearly).",
    run: gauss_long_run,
};

pub const RAPIER_LONG_RUN: CaseSpec = CaseSpec {
    id: "rapier_long_run",
    title: "Long runs of rapier on the harmonic oscillator",
    scenes: &["harmonic_oscillator"],
    theory: "rapier with one substep and a per-step spring force is symplectic Euler, which conserves \
             I = v² + ω²x² − hω² x v exactly: from a turning point the relative energy error stays within \
             (hω/2)/(1 − hω/2) for ever, with no drift.",
    run: rapier_long_run,
};

/// The largest relative energy error in each tenth of `energy`.
fn tenths(energy: &[f64]) -> Vec<f64> {
    let e0 = energy[0];
    let size = (energy.len() / 10).max(1);
    energy.chunks(size).map(|w| w.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max) / e0.abs()).collect()
}

/// Rows for one long run's energy: the largest error (against the round-off bound of a linear
/// system), and the drift (last tenth / first tenth), checked on a nonlinear system only — on a
/// linear one the error is round-off, which random-walks (≈ √N) without any drift of the method.
fn energy_rows(case: &mut CaseBuilder, base: &Measurement, energy: &[f64], bound: Option<f64>) {
    let windows = tenths(energy);
    let (first, last) = (windows[0], windows[windows.len() - 1]);
    let largest = windows.iter().copied().fold(0.0, f64::max);
    let mut m = base.clone().value(largest);
    m.quantity = "largest relative energy error".into();
    case.push(match bound {
        Some(b) => m.check(Check::AtMost, Some(0.0), Some(b)),
        None => m,
    });
    let mut m = base.clone().value(last / first).note(format!("first tenth {first:.2e}, last tenth {last:.2e}"));
    m.quantity = "energy drift: largest error of the last tenth / of the first tenth".into();
    case.push(if bound.is_none() { m.check(Check::AtMost, None, Some(1.5)) } else { m });
}

fn gauss_long_run(case: &mut CaseBuilder, effort: Effort) -> Result<(), Error> {
    let steps: usize = effort.pick(10_000_000, 100_000);
    let dt = 0.01;
    case.setup = format!(
        "Gauss at dt = {dt}, {steps} steps, energy saved every {} steps: the double pendulum from θ₁ = θ₂ = 0.5 at \
         rest, the physical pendulum (one link of the chain) from θ = 2.5 at rest, and the harmonic oscillator (k/m = 10) from x = 0.1 at rest.",
        steps / 1000
    );
    for (id, changes, initial, bound) in [
        ("double_pendulum", &[][..], State::new(0.0, [0.5, 0.5], [0.0, 0.0]), None),
        ("chain", &[("links", 1.0)][..], State::new(0.0, [2.5], [0.0]), None),
        ("harmonic_oscillator", &[][..], State::new(0.0, [0.1], [0.0]), Some(4.0 * f64::EPSILON * steps as f64)),
    ] {
        let scene = find(id)?;
        let params = scene_params(scene, changes)?;
        let system = scene.build(&params)?;
        let method = Method::Gauss4 { dt };
        let t_end = steps as f64 * dt;
        let every = (steps / 1000) as f64 * dt;
        let (run, wall) = timed_simulate(system.as_ref(), &initial, t_end, method, &Output::Every(every));
        let base = Measurement::new(format!("{steps} steps"), id, "gauss4", "").method_settings(method, t_end);
        let base = base.params(changes);
        match run {
            Ok(t) if id == "chain" => {
                let base = base.cost(Cost::of(&t.stats, wall));
                energy_rows(case, &base, &t.energy, bound);
                // The physical pendulum at a large amplitude: nonlinear, so the error is the
                // bounded O(h⁴) oscillation (measured 8e-9 at h = 0.01 in the first tenth).
                let mut m = base.value(tenths(&t.energy)[0]);
                m.quantity = "largest relative energy error of the first tenth".into();
                case.push(m.check(Check::AtMost, Some(0.0), Some(1e-6)));
            }
            Ok(t) => energy_rows(case, &base.cost(Cost::of(&t.stats, wall)), &t.energy, bound),
            Err(e) => case.push(base.failed(e).check(Check::Finite, None, None)),
        }
    }
    Ok(())
}

fn rapier_long_run(case: &mut CaseBuilder, effort: Effort) -> Result<(), Error> {
    let dt = 0.01;
    let runs: [(Engine, usize); 2] = [
        (Engine::RapierImpulse, effort.pick(10_000_000, 100_000)),
        (Engine::RapierMultibody, effort.pick(1_000_000, 100_000)),
    ];
    case.setup = format!(
        "k/m = 10 (ω dt = {:.4}) from x = 0.1 at rest, dt = {dt}, one substep: {} impulse-joint steps and {} \
         multibody steps, energy read every 1/1000 of the run.",
        10f64.sqrt() * dt,
        runs[0].1,
        runs[1].1
    );
    let scene = find("harmonic_oscillator")?;
    let params = scene.default_params();
    let initial = scene.default_state(&params)?;
    let band = theory::symplectic_euler_energy_band(10f64.sqrt() * dt);
    for (engine, steps) in runs {
        let settings = Settings { dt, substeps: 1, tolerance: 1e-12 };
        let base = Measurement::new(format!("{steps} steps"), "harmonic_oscillator", engine.name(), "").settings(
            RunSettings {
                dt: Some(dt),
                substeps: Some(1),
                horizon_s: Some(steps as f64 * dt),
                ..RunSettings::default()
            },
        );
        let start = Instant::now();
        let mut built = match build(engine, scene, &params, &initial, &settings) {
            Ok(built) => built,
            Err(e) => {
                case.push(base.failed(e));
                continue;
            }
        };
        let mut energy = Vec::with_capacity(1001);
        let mut failure = None;
        for k in 0..=1000 {
            let t = (k * steps / 1000) as f64 * dt;
            if let Err(e) = built.simulation.advance_to(t) {
                failure = Some(e.to_string());
                break;
            }
            energy.push(built.read_back.energy(t, &built.simulation.bodies()));
        }
        let cost = Cost {
            steps: Some(built.simulation.steps()),
            wall_time_s: start.elapsed().as_secs_f64(),
            ..Cost::default()
        };
        match failure {
            Some(e) => case.push(base.failed(e)),
            None => {
                let base = base.cost(cost);
                let windows = tenths(&energy);
                let largest = windows.iter().copied().fold(0.0, f64::max);
                let mut m = base.clone().value(largest);
                m.quantity = "largest relative energy error".into();
                // Sampled every 1/1000 of the run: at most the band, up to round-off.
                case.push(m.clone().check(Check::AtMost, Some(band), Some(band * (1.0 + 1e-9))));
                // And the band is reached (the bound is sharp): at least 90 % of it.
                m.quantity = "largest relative energy error, against the band it must reach".into();
                case.push(m.check(Check::AtLeast, Some(band), Some(0.9 * band)));
                let (first, last) = (windows[0], windows[windows.len() - 1]);
                let mut m = base.value(last / first).note(format!("first tenth {first:.3e}, last tenth {last:.3e}"));
                m.quantity = "energy drift: largest error of the last tenth / of the first tenth".into();
                case.push(m.check(Check::AtMost, None, Some(1.5)));
            }
        }
    }
    Ok(())
}
