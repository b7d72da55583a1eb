//! A run's check of itself (`lagrange_validation::health`, what `lagrange simulate` exits 1 on)
//! over the report's grid: every scene, every reduced method, every setting of the quick
//! report's sweeps. A run the check passes must be right — within a stated distance of the
//! scene's reference — so that exit 0 means right; a run it fails is allowed to be anything.

use lagrange::integrate::MethodKind;
use lagrange::{Method, Output, Tolerances};
use lagrange_scenes::SINGULAR_DEFAULT_MOTION;
use lagrange_validation::health;
use lagrange_validation::plan::{Family, Plan, Setting};
use lagrange_validation::reference::Reference;

/// How far from the reference a run that passes its check may end, relative to the size of the
/// motion `1 + max |q_ref|`: a run this far off is wrong to the eye (a swing a tenth of its
/// size off), which a check of the constants of the motion must see — their drift is at least
/// the state's relative error times the constants' sensitivity. Phase errors that keep every
/// constant are the exception, and the quick report's horizon (2 s, or the scene's own) keeps
/// them below it at every setting of its sweeps: the largest error of a passing run measured
/// 1.6e-2 (the chain, variational at dt 0.05; 660 runs, 14 failing their check, 2 stopping
/// with an error), a margin of 6.
const WRONG: f64 = 0.1;

/// The methods of the grid: the report's four families over their sweeps, and the implicit and
/// Gauss methods at the settings `simulate` offers by default.
fn methods(plan: &Plan) -> Vec<Method> {
    let mut methods: Vec<Method> = Family::OURS
        .iter()
        .flat_map(|&family| {
            let Family::Reduced(kind) = family else { unreachable!("ours are reduced") };
            plan.settings(family, true).into_iter().map(move |setting| match setting {
                Setting::Step { dt } | Setting::Rapier { dt, .. } => kind.with(dt),
                Setting::Tolerance { tol } => kind.with(tol),
            })
        })
        .collect();
    methods.push(MethodKind::Sdirk4.default_method());
    methods.push(MethodKind::Gauss4.default_method());
    methods.push(Method::Sdirk4 { tol: Tolerances::uniform(1e-4) });
    methods
}

#[test]
fn no_run_of_the_report_grid_passes_its_check_and_ends_wrong() {
    let quick = Plan::new(true, None).expect("the quick plan");
    let (mut runs, mut flagged, mut failed, mut worst) = (0, 0, 0, (0.0_f64, String::new()));
    // The scenes whose default motion passes a singular configuration are issue 21's (their
    // accuracy there is not yet what a check can promise).
    for scene in lagrange_scenes::all().iter().filter(|s| !SINGULAR_DEFAULT_MOTION.contains(&s.id())) {
        let plan = scene.horizon().map_or_else(|| quick.clone(), |h| quick.scaled_to(h));
        let params = scene.default_params();
        let initial = scene.default_state(&params).expect("default state");
        let times: Vec<f64> = plan.times.iter().map(|t| initial.t + t).collect();
        let reference = Reference::new(*scene, &params, &initial, &times).expect("reference");
        let size = 1.0 + reference.q.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        for method in methods(&plan) {
            let mut system = scene.build(&params).expect("builds");
            let t_end = *times.last().expect("times");
            runs += 1;
            let run = match system.simulate(&initial, t_end, method, &Output::Times(times.clone())) {
                Ok(run) => run,
                Err(_) => {
                    failed += 1;
                    continue;
                }
            };
            let health = health::check(*scene, &params, system.as_mut(), method, &run).expect("check");
            if !health.is_healthy() {
                flagged += 1;
                continue;
            }
            // The run's last samples are the saved times (the initial state may come first).
            let offset = run.len() - times.len();
            let error = (0..times.len()).map(|k| reference.error(k, run.q(k + offset))).fold(0.0_f64, f64::max) / size;
            let what = format!("{} {method:?}", scene.id());
            if error > worst.0 {
                worst = (error, what.clone());
            }
            assert!(
                error <= WRONG,
                "{what}: passes its check ({:?}) but ends {error:.3e} of its size off",
                health.checked
            );
        }
    }
    eprintln!(
        "{runs} runs: {flagged} failed their check, {failed} stopped with an error; the largest error of a passing run {:.2e} ({})",
        worst.0, worst.1
    );
    assert!(runs > 100, "the grid ran");
}
