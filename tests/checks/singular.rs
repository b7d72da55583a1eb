//! Mechanisms far from the origin and long chains of loops: the projection's convergence test
//! is relative to the scale of the positions the constraints compare, so neither where the
//! world's origin is nor how many loops a mechanism has decides whether a run goes on.

use lagrange::graph::{ForceElement, GROUND, GraphMechanism, JointGraph, Point};
use lagrange::integrate::Stats;
use lagrange::{Method, Model, Output, State, Tolerances, simulate};
use lagrange_scenes::{ParallelogramChain, SceneType};
use lagrange_testing::max_abs_diff;

/// How far every scene is moved.
const SHIFT: f64 = 1e3;

/// Two runs of one scene, 1 km apart, at the same fixed RK4 step: the only difference is the
/// round-off of positions of size 1e3 m. The projection after each step stops at
/// `16 ε L ≈ 3.6e-12` there (against `16 ε` at the origin), so over 2000 steps the runs part by
/// at most `2000 × 3.6e-12 ≈ 7e-9` without growth. Measured: 5.5e-10 (four_bar), 1.8e-10
/// (slider_crank), 1.2e-9 (andrews_squeezer, whose accelerations reach 1e6 rad/s²), round-off
/// or exactly 0 for the scenes without loops.
const TRANSLATION: f64 = 1e-8;

/// Scenes whose default motion passes a singular configuration, where a perturbation `ε` of the
/// state changes `q̈` by about `ε/δ` at distance `δ` from it: their two runs part further.
/// Measured 4.0e-6 for the change-point four-bar; the bound is a factor 25 above it. This is a
/// measured weakness of the index-1 formulation at singular configurations, not round-off.
const SINGULAR: (&[&str], f64) = (&["change_point_four_bar"], 1e-4);

/// `graph` with every point fixed in the world moved by `(dx, 0)`: the ground ends of joints
/// and the world ends of force elements.
fn translated(mut graph: JointGraph, dx: f64) -> JointGraph {
    for joint in &mut graph.joints {
        if joint.parent == GROUND {
            joint.parent_anchor[0] += dx;
        }
        if joint.child == GROUND {
            joint.child_anchor[0] += dx;
        }
    }
    let moved = |p: &mut Point| {
        if p.body == GROUND {
            p.at[0] += dx;
        }
    };
    for force in &mut graph.forces {
        match force {
            ForceElement::Spring { a, b, .. } | ForceElement::Damper { a, b, .. } => {
                moved(a);
                moved(b);
            }
            ForceElement::Force { at, .. } => moved(at),
            _ => {}
        }
    }
    graph
}

fn run(graph: JointGraph, start: &State, t_end: f64) -> Vec<Vec<f64>> {
    let model = Model::new(GraphMechanism::new(graph).unwrap()).unwrap();
    let run = simulate(&model, start, t_end, Method::Rk4 { dt: 1e-3 }, &Output::Every(0.1)).unwrap();
    (0..run.len()).map(|k| run.q(k).to_vec()).collect()
}

#[test]
fn where_the_origin_is_changes_no_joint_graph_scene() {
    let mut checked = 0;
    for scene in lagrange_scenes::all() {
        let params = scene.default_params();
        let Some(graph) = scene.joint_graph(&params).unwrap() else { continue };
        let start = scene.default_state(&params).unwrap();
        let t_end = scene.horizon().unwrap_or(2.0).min(2.0);
        let here = run(graph.clone(), &start, t_end);
        let there = run(translated(graph, SHIFT), &start, t_end);
        let gap = here.iter().zip(&there).map(|(a, b)| max_abs_diff(a, b)).fold(0.0, f64::max);
        println!("{}: largest gap {gap:.1e} over {t_end} s", scene.id());
        let bound = if SINGULAR.0.contains(&scene.id()) { SINGULAR.1 } else { TRANSLATION };
        assert!(gap <= bound, "{}: moved by {SHIFT} m the motion differs by {gap:e}", scene.id());
        checked += 1;
    }
    assert!(checked >= 11, "only {checked} joint-graph scenes");
}

/// The scene's chain of `n` parallelogram windows (uniform 1 kg, 1 m rods, written as it is
/// read) with its ground pivots moved to start at `x0`.
fn parallelogram_chain(n: usize, x0: f64) -> JointGraph {
    let scene = ParallelogramChain::new(n, 9.81, 8.0).expect("valid");
    translated(scene.joint_graph().expect("the scene is a joint graph"), x0)
}

/// Every crank hanging down, crank 0 turning at `speed`, assembled with crank 0 held.
fn hanging(model: &Model<GraphMechanism>, speed: f64) -> State {
    let coordinates = &lagrange::Mechanism::description(model.mechanism()).coordinates;
    let crank = |name: &str| name.starts_with('θ');
    let q = coordinates
        .iter()
        .map(|c| if crank(&c.name) { -std::f64::consts::FRAC_PI_2 } else { std::f64::consts::FRAC_PI_2 });
    let qdot = coordinates.iter().map(|c| if c.name == "θ0" { speed } else { 0.0 });
    let held: Vec<bool> = coordinates.iter().map(|c| c.name == "θ0").collect();
    model.assemble(&State::new(0.0, q.collect::<Vec<_>>(), qdot.collect::<Vec<_>>()), &held).unwrap()
}

/// The largest angle between two cranks (the coordinates `θk`) over a run.
fn crank_spread<M: lagrange::Mechanism>(model: &Model<M>, run: &lagrange::Trajectory) -> f64 {
    let cranks: Vec<usize> = lagrange::Mechanism::description(model.mechanism())
        .coordinates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.name.starts_with('θ'))
        .map(|(i, _)| i)
        .collect();
    (0..run.len())
        .map(|k| cranks.iter().map(|&c| (run.q(k)[c] - run.q(k)[cranks[0]]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max)
}

/// Thirty windows: before the projection's test was scaled by the positions, a residual of a
/// few ulps at x ≈ 30 m never passed a test scaled by the angles and every run stopped within
/// its first second. Here the chain swings (it does not reach its flat position: 3 rad/s from
/// hanging is below the turning speed) for 2 s at tol 1e-8, at the origin and 1 km away; the
/// cranks stay parallel to the integrator's tolerance, and the two runs agree to it.
#[test]
fn thirty_parallelogram_windows_project_at_the_round_off_of_their_positions() {
    let mut finals = Vec::new();
    for x0 in [0.0, SHIFT] {
        let model = Model::new(GraphMechanism::new(parallelogram_chain(30, x0)).unwrap()).unwrap();
        let start = hanging(&model, 3.0);
        let method = Method::Dopri5 { tol: lagrange::Tolerances::uniform(1e-8) };
        let run = simulate(&model, &start, 2.0, method, &Output::Every(0.1)).unwrap();
        let spread = crank_spread(&model, &run);
        println!("x0 = {x0}: crank spread {spread:.1e}");
        // The cranks of a parallelogram are parallel on the whole branch: what separates them is
        // the integrator's error at tol 1e-8 (relative and absolute), with a factor 10 for its
        // growth over 2 s.
        assert!(spread <= 1e-7, "x0 = {x0}: cranks {spread:e} apart");
        finals.push(run.q(run.len() - 1).to_vec());
    }
    let gap = max_abs_diff(&finals[0], &finals[1]);
    assert!(gap <= 1e-7, "1 km apart, the chains end {gap:e} apart");
}

/// The parallelogram chain of the scene (`N` windows listed as written, on the tree path) run
/// for 20 s — 25 turns, about 50 flat positions, where `N` of the `2N` loop rows become
/// dependent and the anti-parallelogram branches cross the parallelogram one — by every
/// explicit and SDIRK method over its range of settings, from coarse to tight, with 2 and 10
/// windows, and at a sample of them with 40 (81 coordinates): each run ends without an error and
/// keeps every crank at one angle. Bound 1e-8 rad (the issue's; measured ≤ 1.3e-11 at N = 2 and
/// 10, ≤ 1.9e-10 at N = 40). The sample at 40 windows is one setting of each method, the coarse
/// ones (SDIRK at 1e-8 alone took 16 s there: its Jacobian has 2n = 162 columns); every setting
/// at 40 windows is walked by the stability suite's `parallelogram_branch` case in the full
/// report (the same runs, the same bounds). 80 windows are walked by the explicit methods in the
/// next test; the variational integrator walks the report's steps in its own test below, and
/// Gauss passes the flat positions by counted RK4 steps (the test after it).
#[test]
fn the_parallelogram_chain_keeps_its_branch_through_fifty_flat_positions_at_every_setting() {
    let sdirk = [1e-4, 1e-6, 1e-8].map(|tol| Method::Sdirk4 { tol: Tolerances::uniform(tol) });
    for windows in [2, 10] {
        let methods: Vec<Method> = explicit_settings().into_iter().chain(sdirk).collect();
        walk(windows, &methods, |_| 1e-8);
    }
    let tol = Tolerances::uniform(1e-6);
    walk(40, &[Method::Rk4 { dt: 1e-2 }, Method::Dopri5 { tol }, Method::Dop853 { tol }, sdirk[0]], |_| 1e-8);
}

/// Eighty windows (161 coordinates, 160 loop rows) through the same fifty flat positions by the
/// explicit methods at a coarse setting of each and DOP853 at a tight one: each run ends without an error,
/// going round with the pendulum, on the parallelogram branch. The cranks stay within the
/// issue's 1e-8 rad at RK4's step and at tolerance 1e-12 (measured ≤ 5.0e-9). At 1e-6 the
/// spread is the run's own error, not the solve's round-off (measured 1.5e-11 … 3.8e-10, and
/// 5.4e-8 by DOP853 at 1e-8): bounded there by 1e3 tol, a global error of 10³ steps' local errors
/// adding up — still 10³ below the 3.1 rad of a jump to an anti-parallelogram branch. Every
/// explicit setting at 80 windows (RK4 at 1e-2 and 2.5e-3 s, both methods at 1e-6 … 1e-12: about
/// 35 s) is walked by the stability suite's `parallelogram_branch` case in the full report, with
/// these bounds.
#[test]
fn eighty_parallelogram_windows_keep_their_branch_at_coarse_and_tight_settings() {
    let [coarse, tight] = [1e-6, 1e-12].map(Tolerances::uniform);
    let methods = [
        Method::Rk4 { dt: 1e-2 },
        Method::Dopri5 { tol: coarse },
        Method::Dop853 { tol: coarse },
        Method::Dop853 { tol: tight },
    ];
    walk(80, &methods, |method| match method {
        Method::Dopri5 { tol } | Method::Dop853 { tol } if tol.rtol > 1e-10 => 1e3 * tol.rtol,
        _ => 1e-8,
    });
}

/// The variational integrator (constrained discrete Euler–Lagrange: `Φ = 0` at the end of every
/// step, no projection) at every step of the full report's sweep, `0.05 / 2^k` s for
/// `k = 0 … 8`, with 2 windows, at `k = 0 … 4` with 10, and at the coarsest with 40: each run
/// ends without an error on the parallelogram branch, cranks within 1e-8 rad (measured ≤
/// 1.3e-13 at N = 2, 2.3e-13 at N = 10, 3.3e-13 at N = 40; 8.0e-13 at N = 80 over 5 s in a
/// scratch run) and the exact motion's turns within a quarter turn (measured 0.043 turns behind
/// at 0.05 s, converging at second order). Cost, release build, in a scratch run: 0.26 s for N =
/// 10 at 0.05 s, 3.2 s at 1.6e-3 s, 4.0 s for N = 40 at 0.05 s — the Newton matrix (a dense
/// Hessian of `L`, `O(n³)`) is built once and kept while Newton contracts fast, so the finer
/// steps at N = 10 and 40 and the chain of 80 are left to the report's timing, not the suite.
#[test]
fn the_variational_integrator_keeps_the_branch_at_every_step_of_the_report() {
    let steps: Vec<Method> = (0..9).map(|k| Method::Variational { dt: 0.05 / f64::powi(2.0, k) }).collect();
    walk(2, &steps, |_| 1e-8);
    walk(10, &steps[..5], |_| 1e-8);
    walk(40, &steps[..1], |_| 1e-8);
}

/// Gauss on the parallelogram chain: swinging away from the flat position (from 0.3 rad past
/// hanging at 2 rad/s: it never turns over) it follows the exact motion at fourth order with 2
/// and 5 windows, every step its own (once it failed there at 1e-2 and 1e-4 s and passed at
/// 1e-3); turning over, its Newton iteration does not converge at the flat positions at any
/// step (its stage values are not held on the constraints, and the accelerations between them
/// change faster there than the iteration follows: splitting the failing step in halves down to
/// 2⁻¹² of it was tried, and failed with 10 windows), so those steps are taken by RK4 substeps
/// and counted: the run goes through the fifty flat positions of 20 s on the parallelogram
/// branch, and the counted steps are a few near each flat position, not the run.
#[test]
fn gauss_follows_the_chain_swinging_and_passes_the_flat_positions_by_counted_explicit_steps() {
    for windows in [2, 5] {
        let scene = ParallelogramChain::new(windows, 9.81, 8.0).expect("valid");
        let start = scene.state_at(0.0, -std::f64::consts::FRAC_PI_2 + 0.3, 2.0);
        let model = Model::new(scene.clone()).expect("valid");
        for dt in [1e-2, 1e-3, 1e-4] {
            let run = simulate(&model, &start, 5.0, Method::Gauss4 { dt }, &Output::Every(0.05))
                .unwrap_or_else(|e| panic!("N = {windows}, dt = {dt}: {e}"));
            let error = (0..run.len())
                .map(|i| (run.q(i)[0] - scene.exact_solution(&start, run.t[i]).expect("on the branch").q[0]).abs())
                .fold(0.0, f64::max);
            eprintln!("N = {windows}, Gauss at {dt}: crank 0 within {error:.1e} rad of the exact motion");
            // Fourth order: measured 1.5e-8 at 1e-2 (C = 1.5 in C dt⁴), 1.4e-12 at 1e-3 and
            // 1.1e-14 (round-off) at 1e-4; bound 10 dt⁴ plus 1e-12 of round-off over 5e4 steps.
            assert!(error <= 10.0 * dt.powi(4) + 1e-12, "N = {windows}, dt = {dt}: {error:e} rad off");
            assert_eq!(run.stats.fallbacks, 0, "N = {windows}, dt = {dt}: far from flat, every step is Gauss's");
        }
    }
    for windows in [2, 10] {
        let steps = [1e-2, 1e-3].map(|dt| Method::Gauss4 { dt });
        for (method, stats) in steps.iter().zip(walk(windows, &steps, |_| 1e-8)) {
            let (fallbacks, steps) = (stats.fallbacks, stats.steps);
            eprintln!("N = {windows}, {method:?}: {fallbacks} of {steps} steps by RK4 substeps");
            // About fifty flat positions in 20 s: at least one step taken by RK4 in the run, and
            // at most two per flat position (the failing step and its neighbour); measured 3, 5
            // (N = 2) and 5, 8 (N = 10).
            assert!((1..=100).contains(&fallbacks), "N = {windows}, {method:?}: {fallbacks} of {steps} steps");
        }
    }
}

/// RK4 at two steps, Dormand–Prince and DOP853 at tolerances 1e-6 … 1e-12.
fn explicit_settings() -> Vec<Method> {
    let mut methods = vec![Method::Rk4 { dt: 1e-2 }, Method::Rk4 { dt: 2.5e-3 }];
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        methods.push(Method::Dopri5 { tol: Tolerances::uniform(tol) });
        methods.push(Method::Dop853 { tol: Tolerances::uniform(tol) });
    }
    methods
}

/// Run the chain of `windows` for 20 s from the scene's default state by each of `methods`:
/// no error, the number of turns within a quarter turn of the exact motion's, and the cranks
/// within `bound(method)` rad of each other at every sample.
fn walk(windows: usize, methods: &[Method], bound: impl Fn(&Method) -> f64) -> Vec<Stats> {
    let scene = ParallelogramChain::new(windows, 9.81, 8.0).expect("valid");
    let start = scene.default_state();
    let end = scene.exact_solution(&start, 20.0).expect("the default state is on the branch");
    let exact = (end.q[0] - start.q[0]) / std::f64::consts::TAU;
    let model = Model::new(scene).expect("valid");
    assert!(model.uses_tree_path(), "the chain as written is a tree with loops");
    let mut stats = Vec::new();
    for &method in methods {
        let run = simulate(&model, &start, 20.0, method, &Output::Every(0.05))
            .unwrap_or_else(|e| panic!("N = {windows}, {method:?}: {e}"));
        let spread = crank_spread(&model, &run);
        let turns = (run.q(run.len() - 1)[0] - start.q[0]) / std::f64::consts::TAU;
        eprintln!("N = {windows}, {method:?}: {turns:.4} turns ({exact:.4} exact), cranks within {spread:.1e} rad");
        // Still going round with the pendulum's energy: off by at most 0.045 turns (SDIRK at
        // 1e-4, N = 10, measured), bound a quarter turn.
        assert!((turns - exact).abs() < 0.25, "N = {windows}, {method:?}: {turns:.3} turns, {exact:.3} exact");
        let bound = bound(&method);
        assert!(spread <= bound, "N = {windows}, {method:?}: cranks {spread:e} rad apart (bound {bound:e})");
        stats.push(run.stats);
    }
    stats
}

/// The error floor of the 10-window chain's 20 s (m): what the constrained solve's filter
/// leaves out of the vanishing rows' force at the flat positions, 1.3e-8 … 4.0e-8 m measured at
/// DOP853 tol 1e-10 and 1e-11 with the solves of commits 3a2bbdf … this one, with a margin of
/// 2.5× over the largest (the issue asks 1e-6 m of the 40-window run).
const FLOOR: f64 = 1e-7;

/// The parallelogram chain of 10 windows for 20 s (about fifty flat positions) gets closer to
/// its exact motion as the tolerance tightens, down to the floor the constrained solve's filter
/// leaves: the crank tip's largest distance from the exact solution's at 400 output times, by
/// DOP853 at tolerances 1e-8 … 1e-11 and Dormand–Prince at 1e-9 and 1e-10, never grows when the
/// tolerance tightens unless both runs are below [`FLOOR`], and the tightest runs are below it.
/// Measured: DOP853 1.9e-6, 2.7e-7, 1.9e-8, 4.0e-8 m, Dormand–Prince 5.4e-7, 7.2e-8 m (DOP853's
/// last two both at the floor, where round-off decides their order: at 40 windows the same
/// runs read 1.4e-7 then 2.6e-7 with the solve of commit 3a2bbdf). With the previous shift of
/// the constrained solve (1e-10, two refinement steps) the same DOP853 runs read 1.2e-6,
/// 8.5e-5, 1.1e-3, 9.8e-4 m: tightening made them worse, as the noise that a solve enforcing
/// nearly dependent rows exactly amplifies (as `ε/δ³` at `δ` from flat) drove the step-size
/// controller into the flat position.
#[test]
fn the_parallelogram_chain_gets_closer_to_its_exact_motion_as_the_tolerance_tightens() {
    let scene = ParallelogramChain::new(10, 9.81, 8.0).expect("valid");
    let start = scene.default_state();
    let model = Model::new(scene.clone()).expect("valid");
    let times: Vec<f64> = (1..=400).map(|k| 20.0 * k as f64 / 400.0).collect();
    let tip_error = |method: Method| {
        let run = simulate(&model, &start, 20.0, method, &Output::Times(times.clone()))
            .unwrap_or_else(|e| panic!("{method:?}: {e}"));
        (0..run.len())
            .map(|i| {
                let exact = scene.exact_solution(&start, run.t[i]).expect("on the branch").q[0];
                let theta = run.q(i)[0];
                (theta.cos() - exact.cos()).hypot(theta.sin() - exact.sin())
            })
            .fold(0.0, f64::max)
    };
    let families: [(&str, Vec<Method>); 2] = [
        ("DOP853", [1e-8, 1e-9, 1e-10, 1e-11].map(|tol| Method::Dop853 { tol: Tolerances::uniform(tol) }).to_vec()),
        ("Dormand–Prince", [1e-9, 1e-10].map(|tol| Method::Dopri5 { tol: Tolerances::uniform(tol) }).to_vec()),
    ];
    for (name, methods) in families {
        let errors: Vec<f64> = methods.iter().map(|&m| tip_error(m)).collect();
        let shown = errors.iter().map(|e| format!("{e:.1e}")).collect::<Vec<_>>().join(", ");
        eprintln!("{name}: crank-tip errors {shown} m");
        for pair in errors.windows(2) {
            assert!(pair[1] <= pair[0].max(FLOOR), "{name}: a tighter tolerance ended further off: {shown} m");
        }
        let tightest = errors[errors.len() - 1];
        assert!(tightest <= FLOOR, "{name}: {tightest:e} m off the exact crank tip at the tightest tolerance");
    }
}
