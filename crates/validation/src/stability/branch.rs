//! Singular configurations passed in motion: the parallelogram chain turning over keeps its
//! branch through every flat position, at every setting of the report's sweeps.

use super::{CaseBuilder, CaseSpec, Check, Cost, Effort, Measurement, find, scene_params, timed_simulate};
use crate::plan::Plan;
use lagrange::{Method, Output, Tolerances};

pub const BRANCH: CaseSpec = CaseSpec {
    id: "parallelogram_branch",
    title: "The parallelogram chain through its flat positions: the branch kept at every setting",
    scenes: &["parallelogram_chain"],
    theory: "At the flat position (every link horizontal) N of the chain's 2N loop rows become dependent and \
             the anti-parallelogram branches cross the parallelogram one; the exact motion stays on the \
             parallelogram branch, every crank at one angle, a pendulum of one degree of freedom (Jacobi \
             elliptic functions: the number of turns is exact). A solve continuous through the rank loss and \
             projections that keep the branch leave the cranks parallel to round-off and the turns within the \
             integrator's error of the exact ones; a branch jump would put cranks ~π apart. A setting too \
             coarse for the motion may end turns off by its phase error, but then fails its own check \
             (lagrange_validation::health: the energy drifts beyond what its tolerance allows).",
    run: branch,
};

/// The largest angle between two cranks (the coordinates `θk`) over a run, and its final
/// first-crank angle.
fn spread(names: &[String], run: &lagrange::Trajectory) -> f64 {
    let cranks: Vec<usize> = names.iter().enumerate().filter(|(_, n)| n.starts_with('θ')).map(|(i, _)| i).collect();
    (0..run.len())
        .map(|k| cranks.iter().map(|&c| (run.q(k)[c] - run.q(k)[cranks[0]]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max)
}

fn branch(case: &mut CaseBuilder, effort: Effort) -> Result<(), crate::Error> {
    let plan = Plan::new(effort.pick(false, true), None)?;
    let horizon: f64 = effort.pick(20.0, 10.0);
    case.setup = format!(
        "The parallelogram chain (default: g = 9.81, every crank from hanging at ω0 = 8 rad/s, about 2.5 turns a \
         second) with N = 2 and 10 windows for {horizon} s (about {} flat positions): RK4 at the report's steps, \
         Dormand–Prince and DOP853 at its tolerances, SDIRK4 at 1e-4, 1e-6, 1e-8, the variational integrator at \
         the report's steps, Gauss at 1e-2 and 1e-3 s (its steps at a flat position by RK4 substeps). Measured: the largest angle \
         between two cranks (bound 1e-8 rad) and the turns of crank 0 against the exact solution's (bound a \
         quarter turn for a run that passes its own check; reported for one that fails it).{}",
        (horizon * 5.0).round(),
        effort.pick(
            " With N = 40 (81 coordinates) and 80 windows (161): RK4 at 1e-2 and 2.5e-3 s, Dormand–Prince and \
             DOP853 at 1e-6, 1e-8, 1e-10, 1e-12, and with N = 40 SDIRK4 at 1e-4, 1e-6, 1e-8 too; there the \
             turns are checked for every run, and the cranks at N = 80 within 1e3 tol where the tolerance is \
             above 1e-10 (the run's own global error, not the solve's round-off).",
            "",
        )
    );
    let scene = find("parallelogram_chain")?;
    let mut methods: Vec<Method> = plan.rk4_steps.iter().map(|&dt| Method::Rk4 { dt }).collect();
    for &tol in &plan.tolerances {
        methods.push(Method::Dopri5 { tol: Tolerances::uniform(tol) });
    }
    for &tol in &plan.high_order_tolerances {
        methods.push(Method::Dop853 { tol: Tolerances::uniform(tol) });
    }
    for tol in [1e-4, 1e-6, 1e-8] {
        methods.push(Method::Sdirk4 { tol: Tolerances::uniform(tol) });
    }
    // Gauss at two steps: its Newton iteration does not converge at a flat position, and the
    // steps there are taken by RK4 substeps (counted in the run's statistics).
    methods.extend([1e-2, 1e-3].map(|dt| Method::Gauss4 { dt }));
    let variational: Vec<Method> = plan.variational_steps.iter().map(|&dt| Method::Variational { dt }).collect();
    let every: Vec<Method> = methods.iter().chain(&variational).copied().collect();
    let mut chains = vec![(2.0, every.clone()), (10.0, every)];
    if effort == Effort::Full {
        // The long chains at the explicit settings of the test suite's walk
        // (tests/checks/singular.rs), and SDIRK at 40 windows (its Jacobian has 2n columns).
        let mut explicit = vec![Method::Rk4 { dt: 1e-2 }, Method::Rk4 { dt: 2.5e-3 }];
        for tol in [1e-6, 1e-8, 1e-10, 1e-12].map(Tolerances::uniform) {
            explicit.extend([Method::Dopri5 { tol }, Method::Dop853 { tol }]);
        }
        let sdirk = [1e-4, 1e-6, 1e-8].map(|tol| Method::Sdirk4 { tol: Tolerances::uniform(tol) });
        chains.push((40.0, explicit.iter().chain(&sdirk).copied().collect()));
        chains.push((80.0, explicit));
    }
    for (windows, methods) in chains {
        let params = scene_params(scene, &[("N", windows)])?;
        // The long chains: every run's turns checked, and at 80 windows the cranks of a run at a
        // tolerance above 1e-10 within 1e3 tol: there the spread is the run's own global error
        // (measured 1.5e-11 … 5.4e-8 at 1e-6 and 1e-8), still 1e-3 of the 3.1 rad of a jump to an
        // anti-parallelogram branch.
        let long = windows > 10.0;
        let crank_bound = |method: Method| match method {
            Method::Dopri5 { tol } | Method::Dop853 { tol } if windows >= 80.0 && tol.rtol > 1e-10 => 1e3 * tol.rtol,
            _ => 1e-8,
        };
        let system = scene.build(&params)?;
        let names: Vec<String> = system.coordinates().iter().map(|c| c.name.clone()).collect();
        let initial = scene.default_state(&params)?;
        let exact = scene.exact_solution(&params, &initial, horizon)?.ok_or(crate::Error::Missing("exact solution"))?;
        let exact_turns = (exact.q[0] - initial.q[0]) / std::f64::consts::TAU;
        for &method in &methods {
            let setting = match method {
                Method::Rk4 { dt } | Method::Gauss4 { dt } | Method::Variational { dt } => format!("dt = {dt:.2e}"),
                Method::Dopri5 { tol } | Method::Dop853 { tol } | Method::Sdirk4 { tol } => {
                    format!("tol = {:.0e}", tol.rtol)
                }
            };
            let label = format!("N = {windows}, {setting}");
            let (run, wall) = timed_simulate(system.as_ref(), &initial, horizon, method, &Output::Every(0.05));
            let cranks = Measurement::new(label.clone(), scene.id(), method.name(), "largest angle between two cranks")
                .params(&[("N", windows)])
                .method_settings(method, horizon);
            let turns = Measurement::new(label, scene.id(), method.name(), "turns of crank 0 off the exact solution's")
                .params(&[("N", windows)])
                .method_settings(method, horizon);
            match run {
                Ok(run) => {
                    let cost = Cost::of(&run.stats, wall);
                    let off = ((run.q(run.len() - 1)[0] - initial.q[0]) / std::f64::consts::TAU - exact_turns).abs();
                    let bound = crank_bound(method);
                    case.push(cranks.value(spread(&names, &run)).cost(cost).check(Check::AtMost, None, Some(bound)));
                    // A setting too coarse for 20 s of this motion (Dormand–Prince at 1e-3) ends
                    // turns off by its phase error: such a run must fail its own check, as the
                    // command line reports it; one that passes must be within a quarter turn.
                    let mut system = scene.build(&params)?;
                    let health = crate::health::check(scene, &params, system.as_mut(), method, &run)?;
                    let turns = turns.value(off).cost(cost);
                    case.push(if long || health.is_healthy() {
                        turns.check(Check::AtMost, None, Some(0.25))
                    } else {
                        turns.note(format!("fails its own check: {}", health.findings[0])).check(
                            Check::None,
                            None,
                            None,
                        )
                    });
                }
                Err(error) => {
                    let message = error.to_string();
                    case.push(cranks.failed(&error).check(Check::AtMost, None, Some(crank_bound(method))));
                    case.push(turns.failed(message).check(Check::AtMost, None, Some(0.25)));
                }
            }
        }
    }
    Ok(())
}
