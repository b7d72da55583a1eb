//! A scene written as a file against the same scene written in Rust: `q̈` of each
//! coordinates-form example (its expressions compiled into tapes) beside the built-in scene's
//! engine model (with its tree or constant `M`, as the scene declares them) and the built-in
//! mechanism on the generic path a file takes, one run, side by side.
//!
//! `cargo bench -p lagrange-benches --bench files` measures, then prints the table.

use criterion::{BenchmarkGroup, measurement::WallTime};
use lagrange::{Mechanism, Model, State};
use lagrange_benches::{criterion, format_ns, mean_ns};
use lagrange_scenes::{ClosedForm, MechanismVisitor, visit_mechanism};
use std::hint::black_box;

/// The built-in scene's mechanism on the engine's generic path (`M` assembled, no tree, no
/// declared constant `M`): the same algorithm a file scene runs, so the ratio to it is the
/// cost of interpreting the file's tapes.
struct Generic<'a, 'b> {
    group: &'a mut BenchmarkGroup<'b, WallTime>,
    state: &'a State,
}

impl MechanismVisitor for Generic<'_, '_> {
    type Output = ();

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) {
        let model = Model::new_generic(mechanism).expect("valid");
        let mut ws = model.workspace();
        let s = self.state;
        self.group.bench_function("built_in_generic", |b| {
            b.iter(|| {
                black_box(
                    lagrange::accelerations(&model, &mut ws, black_box(s.t), black_box(&s.q), black_box(&s.qdot))
                        .map(|a| a[0]),
                )
            })
        });
    }
}

fn main() {
    let mut criterion = criterion(40);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .expect("examples/scenes")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.to_string_lossy().ends_with(".toml") && !p.to_string_lossy().ends_with(".graph.toml"))
        .collect();
    paths.sort();
    let mut ids = Vec::new();
    for path in paths {
        let file = lagrange_file::load(&path).expect("a valid scene file");
        let id = path.file_stem().and_then(|s| s.to_str()).expect("a name").to_string();
        let Some(built_in) = lagrange_scenes::find(&id) else { continue };
        let state = built_in.default_state(&built_in.default_params()).expect("valid");
        let mut group = criterion.benchmark_group(format!("file_{id}"));
        for (name, scene) in [("built_in", built_in), ("file", file.as_ref())] {
            let mut system = scene.build(&scene.default_params()).expect("valid");
            group.bench_function(name, |b| {
                b.iter(|| {
                    black_box(
                        system
                            .accelerations(black_box(state.t), black_box(&state.q), black_box(&state.qdot))
                            .map(|a| a[0]),
                    )
                })
            });
        }
        visit_mechanism(&id, &built_in.default_params(), Generic { group: &mut group, state: &state }).expect("valid");
        group.finish();
        ids.push(id);
    }
    criterion.final_summary();
    lagrange_benches::tables::print_header(lagrange_benches::tables::FILES);
    for id in ids {
        let group = format!("file_{id}");
        let generic = mean_ns(&group, "built_in_generic");
        match (mean_ns(&group, "built_in"), mean_ns(&group, "file")) {
            (Some(b), Some(f)) => {
                let (g, ratio) =
                    generic.map_or(("—".into(), "—".into()), |g| (format_ns(g), format!("{:.2}×", f / g)));
                println!("| {id} | {} | {g} | {} | {:.2}× | {ratio} |", format_ns(b), format_ns(f), f / b)
            }
            _ => println!("| {id} | (not measured in this run) | | | | |"),
        }
    }
}
