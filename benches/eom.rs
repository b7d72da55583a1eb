//! EOM cost of the generic engine against the hand-coded closed form of the same scene, the
//! raw-Lagrangian path (scenes without constraints among their coordinates), and one RK4 step,
//! for every body scene.
//!
//! `cargo bench -p lagrange-benches --bench eom` measures, then prints a table of the ratios
//! (engine / hand-coded) read back from criterion's estimates.

use criterion::Criterion;
use lagrange::integrate::Rk4;
use lagrange::{Mechanism, Model, RawModel, State};
use lagrange_benches::{bench_step, criterion, mean_ns};
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, visit_mechanism};
use std::hint::black_box;

/// Registers the benches of one typed scene.
struct Register<'a> {
    criterion: &'a mut Criterion,
    id: &'static str,
    state: State,
}

impl MechanismVisitor for Register<'_> {
    type Output = ();

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) {
        let model = Model::new(mechanism.clone()).expect("valid");
        // The raw path takes no constraints among the coordinates (`RawModel::new` refuses them).
        let raw = (!model.is_constrained())
            .then(|| RawModel::new(Model::new(mechanism.clone()).expect("valid")).expect("valid"));
        let n = model.dof();
        let s = self.state;
        let mut group = self.criterion.benchmark_group(self.id);
        // Setup (workspaces, buffers) outside the timed closures.
        let mut ws = model.workspace();
        group.bench_function("engine", |b| {
            b.iter(|| {
                black_box(
                    lagrange::accelerations(&model, &mut ws, black_box(s.t), black_box(&s.q), black_box(&s.qdot))
                        .map(|a| a[0]),
                )
            })
        });
        let mut out = vec![0.0; n];
        group.bench_function("closed_form", |b| {
            b.iter(|| {
                mechanism.closed_form_into(black_box(s.t), black_box(&s.q), black_box(&s.qdot), &mut out);
                black_box(out[0])
            })
        });
        if let Some(raw) = &raw {
            let mut rws = raw.workspace();
            group.bench_function("raw_path", |b| {
                b.iter(|| {
                    black_box(
                        lagrange::accelerations(raw, &mut rws, black_box(s.t), black_box(&s.q), black_box(&s.qdot))
                            .map(|a| a[0]),
                    )
                })
            });
        }
        let mut rk4 = Rk4::new(n);
        bench_step(&mut group, "rk4_step", &s, |state| rk4.step(&model, &mut ws, state, black_box(1e-3)));
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
    criterion.final_summary();
    // The table: engine / closed form, side by side from this run.
    lagrange_benches::tables::print_header(lagrange_benches::tables::EOM);
    for id in ids {
        let n = lagrange_scenes::find(id).and_then(|s| s.coordinates(&s.default_params()).ok()).map_or(0, |c| c.len());
        let get = |bench| mean_ns(id, bench);
        match (get("engine"), get("closed_form"), get("raw_path"), get("rk4_step")) {
            (Some(e), Some(c), raw, Some(k)) => {
                let raw = raw.map_or("— (constraints)".to_string(), |r| format!("{r:.1} ns"));
                println!("| {id} | {n} | {e:.1} ns | {c:.1} ns | {:.1}× | {raw} | {k:.1} ns |", e / c)
            }
            _ => println!("| {id} | {n} | (not measured in this run) | | | | |"),
        }
    }
}
