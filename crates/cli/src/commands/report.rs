//! `lagrange report`: simulate the built-in scenes with every integrator and summarise how
//! well each conserves what the scene conserves, and how far it is from the closed-form
//! solution where one exists.

use crate::args;
use lagrange::{Method, Output, State, System, Tolerances};
use serde::Serialize;
use std::time::Instant;

/// Arguments of `lagrange report`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene ids to report (default: all).
    #[arg(long = "scene")]
    scenes: Vec<String>,
    /// Simulated time per run (s).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    t_end: f64,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

/// One run of one method on one scene.
#[derive(Serialize, Debug)]
struct Run {
    method: String,
    steps: usize,
    /// `max |h − h₀| / |h₀|`, when the scene conserves `h`.
    energy_drift: Option<f64>,
    /// `max |p_j − p_j(0)|` over the cyclic coordinates, when there are any.
    momentum_drift: Option<f64>,
    /// `max ‖q − q_exact‖∞` over the samples, when the scene has a closed-form solution.
    error_vs_exact: Option<f64>,
    wall_ms: f64,
}

/// All runs of one scene.
#[derive(Serialize, Debug)]
struct SceneReport {
    scene: &'static str,
    conserves_energy: bool,
    cyclic: Vec<String>,
    runs: Vec<Run>,
}

const SAMPLES: usize = 100;

/// The integrators compared, at settings that resolve every default scene.
fn methods() -> [Method; 3] {
    [Method::Adaptive { tol: Tolerances::uniform(1e-10) }, Method::Rk4 { dt: 1e-3 }, Method::Variational { dt: 1e-3 }]
}

fn run_one(
    scene: &dyn lagrange_scenes::Scene,
    params: &lagrange_scenes::Params,
    system: &mut Box<dyn System>,
    initial: &State,
    t_end: f64,
    method: Method,
) -> Result<Run, String> {
    let every = match method {
        Method::Rk4 { dt } | Method::Variational { dt } => dt * (t_end / SAMPLES as f64 / dt).round().max(1.0),
        Method::Adaptive { .. } => t_end / SAMPLES as f64,
    };
    let start = Instant::now();
    let trajectory = system
        .simulate(initial, initial.t + t_end, method, &Output::Every(every))
        .map_err(|e| format!("{}: {}: {e}", scene.id(), method.name()))?;
    let wall_ms = start.elapsed().as_secs_f64() * 1e3;
    let energy_drift = system.conserves_energy().then(|| {
        let h0 = trajectory.energy[0];
        let drift = trajectory.energy.iter().map(|h| (h - h0).abs()).fold(0.0, f64::max);
        if h0 != 0.0 { drift / h0.abs() } else { drift }
    });
    let cyclic: Vec<usize> =
        system.cyclic_coordinates().iter().enumerate().filter(|(_, c)| **c).map(|(j, _)| j).collect();
    let momentum_drift = if cyclic.is_empty() {
        None
    } else {
        let p0 = system.momenta(initial.t, &initial.q, &initial.qdot).map_err(|e| e.to_string())?.to_vec();
        let mut drift: f64 = 0.0;
        for k in 0..trajectory.len() {
            let p = system.momenta(trajectory.t[k], trajectory.q(k), trajectory.qdot(k)).map_err(|e| e.to_string())?;
            for &j in &cyclic {
                drift = drift.max((p[j] - p0[j]).abs());
            }
        }
        Some(drift)
    };
    let mut error_vs_exact = None;
    for k in 0..trajectory.len() {
        if let Some(exact) = scene.exact_solution(params, initial, trajectory.t[k]).map_err(|e| e.to_string())? {
            let e = trajectory.q(k).iter().zip(&exact.q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            error_vs_exact = Some(error_vs_exact.unwrap_or(0.0_f64).max(e));
        }
    }
    Ok(Run {
        method: describe(method),
        steps: trajectory.stats.steps,
        energy_drift,
        momentum_drift,
        error_vs_exact,
        wall_ms,
    })
}

fn describe(method: Method) -> String {
    match method {
        Method::Rk4 { dt } => format!("rk4 dt={dt:e}"),
        Method::Variational { dt } => format!("variational dt={dt:e}"),
        Method::Adaptive { tol } => format!("adaptive tol={:e}", tol.rtol),
    }
}

fn cell(value: Option<f64>) -> String {
    value.map_or_else(|| "—".to_string(), |v| format!("{v:.2e}"))
}

/// Run the report.
pub fn run(args: &Args) -> Result<(), String> {
    if !(args.t_end.is_finite() && args.t_end > 0.0) {
        return Err(format!("--t-end must be positive and finite, got {}", args.t_end));
    }
    let scenes: Vec<&dyn lagrange_scenes::Scene> = if args.scenes.is_empty() {
        lagrange_scenes::all().to_vec()
    } else {
        args.scenes.iter().map(|id| args::scene(id)).collect::<Result<_, _>>()?
    };
    let mut reports = Vec::new();
    for scene in scenes {
        let params = scene.default_params();
        let initial = scene.default_state(&params).map_err(|e| e.to_string())?;
        let mut system = scene.build(&params).map_err(|e| e.to_string())?;
        let cyclic = system
            .coordinates()
            .iter()
            .zip(system.cyclic_coordinates())
            .filter(|(_, c)| **c)
            .map(|(c, _)| c.name.clone())
            .collect();
        let mut runs = Vec::new();
        for method in methods() {
            runs.push(run_one(scene, &params, &mut system, &initial, args.t_end, method)?);
        }
        reports.push(SceneReport { scene: scene.id(), conserves_energy: system.conserves_energy(), cyclic, runs });
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&reports).map_err(|e| e.to_string())?);
        return Ok(());
    }
    println!("Default state of every scene, {} s simulated; drifts are maxima over {SAMPLES} samples.", args.t_end);
    println!("energy: max|h − h₀|/|h₀| (— where h is not conserved); momentum: max|p − p₀| of the cyclic coordinates;");
    println!("exact: max‖q − q_exact‖∞ against the closed-form solution (— where the scene has none).\n");
    println!(
        "{:<22} {:<26} {:>9} {:>10} {:>10} {:>10} {:>9}",
        "scene", "method", "steps", "energy", "momentum", "exact", "ms"
    );
    for report in &reports {
        for run in &report.runs {
            println!(
                "{:<22} {:<26} {:>9} {:>10} {:>10} {:>10} {:>9.2}",
                report.scene,
                run.method,
                run.steps,
                cell(run.energy_drift),
                cell(run.momentum_drift),
                cell(run.error_vs_exact),
                run.wall_ms
            );
        }
    }
    Ok(())
}
