//! Cost of constrained mechanisms: the constrained `q̈` with its multipliers `λ` (one call) on
//! every scene with constraints among its coordinates, beside — for Andrews' squeezer — the
//! dense KKT solve of the test set's hand-derived formulas
//! (`lagrange_validation::andrews::kkt`); and one RK4 step and one adaptive (Dormand–Prince)
//! step, each followed by the projection onto the constraints, as a run takes them.
//!
//! `cargo bench -p lagrange-benches --bench constraints` measures, then prints the table of
//! this run's ratios.

use criterion::Criterion;
use lagrange::integrate::{Dopri5, Rk4};
use lagrange::{Mechanism, Model, State, Tolerances};
use lagrange_benches::{bench_step, criterion, format_ns, mean_ns};
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, visit_mechanism};
use lagrange_validation::andrews;
use std::hint::black_box;

/// Step of the RK4 bench, as a fraction of the scene's own span (the report's finest-but-two
/// step): small enough for every constrained scene's motion.
const STEP_FRACTION: f64 = 1e-4;

/// Registers the benches of one typed constrained scene.
struct Register<'a> {
    criterion: &'a mut Criterion,
    id: &'static str,
    state: State,
    span: f64,
}

impl MechanismVisitor for Register<'_> {
    type Output = bool;

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) -> bool {
        let model = Model::new(mechanism).expect("valid");
        if !model.is_constrained() {
            return false;
        }
        let n = model.dof();
        let s = self.state;
        let mut group = self.criterion.benchmark_group(self.id);
        let mut ws = model.workspace();
        group.bench_function("engine_qddot_lambda", |b| {
            b.iter(|| {
                black_box(
                    lagrange::constraint_multipliers(&model, &mut ws, s.t, black_box(&s.q), black_box(&s.qdot))
                        .map(|l| l.first().copied()),
                )
            })
        });
        if self.id == "andrews_squeezer" {
            let (q, qdot): ([f64; 7], [f64; 7]) = (s.q[..].try_into().unwrap(), s.qdot[..].try_into().unwrap());
            group.bench_function("hand_coded_kkt", |b| {
                b.iter(|| black_box(andrews::kkt(black_box(&q), black_box(&qdot)).map(|(a, _)| a[0])))
            });
        }
        let dt = self.span * STEP_FRACTION;
        let mut rk4 = Rk4::new(n);
        bench_step(&mut group, "rk4_step_projected", &s, |state| {
            rk4.step(&model, &mut ws, state, black_box(dt))?;
            lagrange::project(&model, &mut ws, state.t, &mut state.q, &mut state.qdot)
        });
        // The adaptive step as a constrained run takes it: from the projected state (its first
        // stage re-evaluated there), one accepted step, then the projection. Every iteration
        // restarts from the same state (the scenes are autonomous), so the step-size controller
        // settles on that state's step; a step is never longer than 1 % of the span (a motion
        // of constant acceleration, the rolling disc's, has no local error to bound it).
        let mut dopri = Dopri5::new(n, Tolerances::uniform(1e-10)).expect("valid");
        dopri.start(&model, &mut ws, s.t, &s.q, &s.qdot, self.span).expect("starts");
        let (mut q, mut qdot) = (s.q.clone(), s.qdot.clone());
        group.bench_function("adaptive_step_projected", |b| {
            b.iter(|| {
                dopri.restart(&model, &mut ws, black_box(&s.q), black_box(&s.qdot)).expect("evaluates");
                dopri.step(&model, &mut ws, dopri.t() + 0.01 * self.span).expect("steps");
                q.copy_from_slice(dopri.q());
                qdot.copy_from_slice(dopri.qdot());
                lagrange::project(&model, &mut ws, dopri.t(), &mut q, &mut qdot).expect("projects");
                black_box(q[0])
            })
        });
        group.finish();
        true
    }
}

fn main() {
    let mut criterion = criterion(40);
    let mut ids = Vec::new();
    for scene in all() {
        let params = scene.default_params();
        let state = scene.default_state(&params).expect("valid");
        let span = scene.horizon().unwrap_or(1.0);
        let register = Register { criterion: &mut criterion, id: scene.id(), state, span };
        if visit_mechanism(scene.id(), &params, register).expect("valid") == Some(true) {
            ids.push(scene.id());
        }
    }
    criterion.final_summary();
    lagrange_benches::tables::print_header(lagrange_benches::tables::CONSTRAINTS);
    for id in ids {
        let get = |bench| mean_ns(id, bench);
        let cell = |v: Option<f64>| v.map_or("—".to_string(), format_ns);
        let ratio = match (get("engine_qddot_lambda"), get("hand_coded_kkt")) {
            (Some(e), Some(h)) => format!("{:.2}×", e / h),
            _ => "—".into(),
        };
        println!(
            "| {id} | {} | {} | {ratio} | {} | {} |",
            cell(get("engine_qddot_lambda")),
            cell(get("hand_coded_kkt")),
            cell(get("rk4_step_projected")),
            cell(get("adaptive_step_projected")),
        );
    }
}
