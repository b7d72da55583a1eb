//! Chains of N = 2 … 64 uniform rods: one RK4 step of the reduced solver (the path `Model`
//! chooses for a tree) against one rapier step with multibody and with impulse joints
//! (rapier2d-f64, dt = 1e-3, 1 substep), and one evaluation of q̈ — the hand-written scene's
//! model and the model of its joint graph (`lagrange::graph`) side by side.
//!
//! `cargo bench -p lagrange-benches --bench scaling` measures, then prints the table.

use lagrange::graph::GraphMechanism;
use lagrange::integrate::Rk4;
use lagrange::{Dynamics, Model};
use lagrange_benches::{bench_advance, bench_step, criterion, format_ns, mean_ns};
use lagrange_maximal::{Engine, Settings, build};
use lagrange_scenes::SceneType;
use lagrange_scenes::chain::Chain;
use std::hint::black_box;

const DT: f64 = 1e-3;
const LINKS: [usize; 6] = [2, 4, 8, 16, 32, 64];

fn main() {
    let mut criterion = criterion(20);
    let scene = lagrange_scenes::find("chain").expect("registered");
    let settings = Settings { dt: DT, substeps: 1, ..Settings::default() };
    for n in LINKS {
        let group = format!("chain_{n}");
        let mut params = scene.default_params();
        params.set("links", n as f64).expect("in range");
        let state = scene.default_state(&params).expect("valid");
        // The reduced solver.
        let model = Model::new(Chain::from_params(&params).expect("valid")).expect("valid");
        let mut ws = model.workspace();
        let mut qddot = vec![0.0; n];
        let mut g = criterion.benchmark_group(&group);
        g.bench_function("reduced_accelerations", |b| {
            b.iter(|| model.accelerations(&mut ws, 0.0, black_box(&state.q), black_box(&state.qdot), &mut qddot))
        });
        let mut rk4 = Rk4::new(n);
        bench_step(&mut g, "reduced_rk4", &state, |s| rk4.step(&model, &mut ws, s, black_box(DT)));
        // The same chain from its joint graph.
        let graph = scene.joint_graph(&params).expect("valid").expect("the chain is a joint graph");
        let graph_model = Model::new(GraphMechanism::new(graph).expect("a mechanism")).expect("valid");
        let mut graph_ws = graph_model.workspace();
        g.bench_function("graph_accelerations", |b| {
            b.iter(|| {
                graph_model.accelerations(&mut graph_ws, 0.0, black_box(&state.q), black_box(&state.qdot), &mut qddot)
            })
        });
        let mut graph_rk4 = Rk4::new(n);
        bench_step(&mut g, "graph_rk4", &state, |s| graph_rk4.step(&graph_model, &mut graph_ws, s, black_box(DT)));
        // rapier, multibody and impulse joints.
        for engine in [Engine::RapierMultibody, Engine::RapierImpulse] {
            let built = build(engine, scene, &params, &state, &settings).expect("chains are buildable");
            bench_advance(&mut g, engine.name(), built.simulation, DT);
        }
        g.finish();
    }
    criterion.final_summary();
    lagrange_benches::tables::print_header(lagrange_benches::tables::SCALING);
    for n in LINKS {
        let group = format!("chain_{n}");
        let get = |bench| mean_ns(&group, bench);
        let cell = |v: Option<f64>| v.map_or("—".into(), format_ns);
        let ratio = match (get("reduced_rk4"), get("rapier-impulse")) {
            (Some(a), Some(b)) => format!("{:.2}", a / b),
            _ => "—".into(),
        };
        let graph_ratio = match (get("graph_rk4"), get("reduced_rk4")) {
            (Some(a), Some(b)) => format!("{:.2}", a / b),
            _ => "—".into(),
        };
        println!(
            "| {n} | {} | {} | {} | {} | {} | {} | {ratio} | {graph_ratio} |",
            cell(get("reduced_accelerations")),
            cell(get("graph_accelerations")),
            cell(get("reduced_rk4")),
            cell(get("graph_rk4")),
            cell(get("rapier-multibody")),
            cell(get("rapier-impulse"))
        );
    }
}
