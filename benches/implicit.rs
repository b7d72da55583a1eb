//! Cost of the implicit integrators: one Gauss–Legendre 4 step and one exact AD Jacobian
//! `∂q̈/∂(q, q̇)` beside one RK4 step on every body scene, and whole stiff runs of the L-stable
//! SDIRK4 against the explicit Dormand–Prince 5(4) at the same tolerance.
//!
//! `cargo bench -p lagrange-benches --bench implicit` measures, then prints both tables from
//! criterion's estimates of this run.

use criterion::Criterion;
use lagrange::integrate::{Gauss4, Rk4};
use lagrange::{Dynamics, Mechanism, Method, Model, Output, State, Tolerances};
use lagrange_benches::{bench_step, criterion, format_ns, mean_ns};
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, find, visit_mechanism};
use std::hint::black_box;

/// Step of the per-step benches (s): well inside every scene's accuracy range, so Gauss's
/// Newton converges in its usual two or three iterations on a kept Jacobian.
const STEP: f64 = 1e-3;

/// Registers the per-step benches of one typed scene.
struct Register<'a> {
    criterion: &'a mut Criterion,
    id: &'static str,
    state: State,
}

impl MechanismVisitor for Register<'_> {
    type Output = ();

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) {
        let model = Model::new(mechanism).expect("valid");
        let n = model.dof();
        let s = self.state;
        let mut group = self.criterion.benchmark_group(format!("implicit_{}", self.id));
        let mut ws = model.workspace();
        let mut rk4 = Rk4::new(n);
        bench_step(&mut group, "rk4_step", &s, |state| rk4.step(&model, &mut ws, state, black_box(STEP)));
        // Gauss keeps its Jacobian, factor and stage values between steps, as in a run: the
        // first (untimed) step sets them up, every timed step starts from the same state.
        let mut gauss = Gauss4::new(n);
        let mut warm = s.clone();
        gauss.step(&model, &mut ws, &mut warm, STEP).expect("converges");
        bench_step(&mut group, "gauss4_step", &s, |state| gauss.step(&model, &mut ws, state, black_box(STEP)));
        let mut jacobian = vec![0.0; 2 * n * n];
        group.bench_function("jacobian", |b| {
            b.iter(|| {
                model
                    .acceleration_jacobian(&mut ws, black_box(s.t), black_box(&s.q), black_box(&s.qdot), &mut jacobian)
                    .map(|_| black_box(jacobian[0]))
            })
        });
        group.finish();
    }
}

/// A whole stiff run, SDIRK4 against Dormand–Prince at one tolerance.
struct StiffCase {
    /// Criterion group (a plain name: criterion rewrites `/` and other characters in paths).
    group: &'static str,
    /// Label in the table.
    name: &'static str,
    /// Scene and parameter changes.
    scene: &'static str,
    changes: &'static [(&'static str, f64)],
    /// Initial state.
    initial: fn() -> State,
    /// Horizon (s) and tolerance.
    t_end: f64,
    tol: f64,
}

/// The stiff cases of the stability suite (`lagrange report`, `stiff_damped`, `stiff_spring`).
const STIFF: [StiffCase; 2] = [
    StiffCase {
        group: "stiff_damped_oscillator",
        name: "damped oscillator k/m = c/m = 1e6, 1 s",
        scene: "harmonic_oscillator",
        changes: &[("stiffness", 1e6), ("damping", 1e6)],
        initial: || State::new(0.0, [0.1], [0.0]),
        t_end: 1.0,
        tol: 1e-6,
    },
    StiffCase {
        group: "stiff_spring_pendulum",
        name: "spring pendulum k/m = 1e8, 2 s",
        scene: "spring_pendulum",
        changes: &[("stiffness", 1e8)],
        // Released at rest from its static stretch at θ = 1 (as in the report): the stiff radial
        // mode is not excited, so resolving it is not needed for accuracy — the situation an
        // L-stable method is for. (Started 1 mm off the stretch, the mode's amplitude is far
        // above the tolerance and both methods must follow it: SDIRK4 is then the slower.)
        initial: || State::new(0.0, [1.0 + 9.81 * 1f64.cos() / 1e8, 1.0], [0.0, 0.0]),
        t_end: 2.0,
        tol: 1e-6,
    },
];

fn stiff_runs(criterion: &mut Criterion) {
    for case in &STIFF {
        let scene = find(case.scene).expect("registered");
        let mut params = scene.default_params();
        for &(name, value) in case.changes {
            params.set(name, value).expect("valid");
        }
        let system = scene.build(&params).expect("valid");
        let initial = (case.initial)();
        let tol = Tolerances::uniform(case.tol);
        let mut group = criterion.benchmark_group(case.group);
        group.sample_size(10);
        for (bench, method) in [("sdirk4", Method::Sdirk4 { tol }), ("dopri5", Method::Dopri5 { tol })] {
            group.bench_function(bench, |b| {
                b.iter(|| {
                    system.simulate(black_box(&initial), case.t_end, method, &Output::Ends).map(|r| r.stats.steps)
                })
            });
        }
        group.finish();
    }
}

fn main() {
    let mut criterion = criterion(40);
    let mut ids = Vec::new();
    for scene in all() {
        let params = scene.default_params();
        let state = scene.default_state(&params).expect("valid");
        let register = Register { criterion: &mut criterion, id: scene.id(), state };
        if visit_mechanism(scene.id(), &params, register).expect("valid").is_some() {
            ids.push(scene.id());
        }
    }
    stiff_runs(&mut criterion);
    criterion.final_summary();

    lagrange_benches::tables::print_header(lagrange_benches::tables::IMPLICIT_STEP);
    for id in ids {
        let group = format!("implicit_{id}");
        let get = |bench| mean_ns(&group, bench);
        match (get("rk4_step"), get("gauss4_step"), get("jacobian")) {
            (Some(r), Some(g), Some(j)) => {
                println!("| {id} | {} | {} | {:.1}× | {} |", format_ns(r), format_ns(g), g / r, format_ns(j))
            }
            _ => println!("| {id} | (not measured in this run) | | | |"),
        }
    }
    lagrange_benches::tables::print_header(lagrange_benches::tables::IMPLICIT_STIFF);
    for case in &STIFF {
        match (mean_ns(case.group, "sdirk4"), mean_ns(case.group, "dopri5")) {
            (Some(s), Some(d)) => {
                println!("| {} (tol {:e}) | {} | {} | {:.0}× |", case.name, case.tol, format_ns(s), format_ns(d), d / s)
            }
            _ => println!("| {} | (not measured in this run) | | |", case.name),
        }
    }
}
