//! One rapier step of every scene, impulse and multibody joints, f64 and f32, beside one RK4
//! step of the reduced solver on the same scene (dt = 1e-3, 1 substep: the cost of a step, not
//! its accuracy; `lagrange report` weighs cost against error).
//!
//! `cargo bench -p lagrange-benches --bench rapier` measures, then prints the table.

use criterion::Criterion;
use lagrange::Model;
use lagrange::integrate::Rk4;
use lagrange_benches::{bench_advance, bench_step, criterion, format_ns, mean_ns};
use lagrange_maximal::{BuildError, Engine, Settings, build};
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, visit_mechanism};
use std::hint::black_box;

const DT: f64 = 1e-3;

/// Registers one RK4 step of the reduced model of a scene.
struct ReducedStep<'a> {
    criterion: &'a mut Criterion,
    id: &'static str,
    state: lagrange::State,
}

impl MechanismVisitor for ReducedStep<'_> {
    type Output = ();

    fn visit<M: lagrange::Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) {
        let model = Model::new(mechanism).expect("valid");
        let mut ws = model.workspace();
        let mut rk4 = Rk4::new(model.dof());
        let state = self.state;
        bench_step(&mut self.criterion.benchmark_group(self.id), "reduced_rk4", &state, |s| {
            rk4.step(&model, &mut ws, s, black_box(DT))
        });
    }
}

fn main() {
    let mut criterion = criterion(30);
    let settings = Settings { dt: DT, substeps: 1, ..Settings::default() };
    let mut rows: Vec<(&str, Vec<Option<String>>)> = Vec::new();
    for scene in all() {
        let params = scene.default_params();
        let state = scene.default_state(&params).expect("valid");
        let id = scene.id();
        let mut reasons = Vec::new();
        for engine in &Engine::ALL[1..] {
            match build(*engine, *scene, &params, &state, &settings) {
                Ok(built) => {
                    bench_advance(&mut criterion.benchmark_group(id), engine.name(), built.simulation, DT);
                    reasons.push(None);
                }
                Err(BuildError::Unbuildable { reason, .. }) => reasons.push(Some(reason)),
                Err(e) => panic!("{id} {engine}: {e}"),
            }
        }
        visit_mechanism(id, &params, ReducedStep { criterion: &mut criterion, id, state }).expect("valid");
        rows.push((id, reasons));
    }
    criterion.final_summary();
    lagrange_benches::tables::print_header(lagrange_benches::tables::RAPIER);
    for (id, reasons) in rows {
        let mut cells = vec![mean_ns(id, "reduced_rk4").map_or("—".into(), format_ns)];
        for (engine, reason) in Engine::ALL[1..].iter().zip(&reasons) {
            cells.push(match reason {
                Some(_) => "not buildable".into(),
                None => mean_ns(id, engine.name()).map_or("—".into(), format_ns),
            });
        }
        println!("| {id} | {} |", cells.join(" | "));
    }
}
