//! `lagrange scenes`: every scene with its coordinates, parameters and default initial state.

use crate::error::CliError;
use crate::output::outln;
use serde::Serialize;

/// Arguments of `lagrange scenes`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct ParamOut {
    name: &'static str,
    symbol: &'static str,
    /// The symbol in ASCII (`alpha` for `α`), also accepted by `--param`.
    ascii_symbol: String,
    unit: &'static str,
    default: f64,
    description: &'static str,
}

#[derive(Serialize)]
struct CoordinateOut {
    name: String,
    unit: &'static str,
}

/// The state a run starts from when `--q`, `--qdot` are not given.
#[derive(Serialize)]
struct StateOut {
    t: f64,
    /// In the order of the scene's coordinates.
    q: Vec<f64>,
    qdot: Vec<f64>,
}

#[derive(Serialize)]
struct SceneOut {
    id: &'static str,
    title: &'static str,
    reference: &'static str,
    coordinates: Vec<CoordinateOut>,
    parameters: Vec<ParamOut>,
    /// The constants of the motion at the default parameters (valid: `coordinates` took them).
    conserved: Vec<String>,
    /// The default initial state, at the default parameters.
    initial_state: StateOut,
}

/// Print the scene list.
pub fn run(args: &Args) -> Result<(), CliError> {
    let mut scenes = Vec::new();
    for scene in lagrange_scenes::all() {
        let params = scene.default_params();
        let coordinates = scene.coordinates(&params)?;
        let initial = scene.default_state(&params)?;
        scenes.push(SceneOut {
            id: scene.id(),
            title: scene.title(),
            reference: scene.reference(),
            coordinates: coordinates.iter().map(|c| CoordinateOut { name: c.name.clone(), unit: c.unit() }).collect(),
            parameters: scene
                .params()
                .iter()
                .map(|p| ParamOut {
                    name: p.name,
                    symbol: p.symbol,
                    ascii_symbol: p.ascii_symbol(),
                    unit: p.unit,
                    default: p.default,
                    description: p.description,
                })
                .collect(),
            conserved: scene.conserved_quantities(&params).unwrap_or_default().into_iter().map(|c| c.symbol).collect(),
            initial_state: StateOut { t: initial.t, q: initial.q, qdot: initial.qdot },
        });
    }
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&scenes)?)?;
        return Ok(());
    }
    for s in &scenes {
        let coordinates: Vec<String> = s.coordinates.iter().map(|c| format!("{} [{}]", c.name, c.unit)).collect();
        outln!("{} — {} ({})", s.id, s.title, s.reference)?;
        outln!("  coordinates: {}", coordinates.join(", "))?;
        // `{:?}`: full precision, as `accel` prints; `q̇[x']`, as `accel` names `q̈[x']`.
        let initial = &s.initial_state;
        let values = |values: &[f64], symbol: &str| -> Vec<String> {
            s.coordinates.iter().zip(values).map(|(c, v)| format!("{symbol}[{}] = {v:?}", c.name)).collect()
        };
        outln!(
            "  initial state: t = {:?}; {}; {}",
            initial.t,
            values(&initial.q, "q").join(", "),
            values(&initial.qdot, "q̇").join(", ")
        )?;
        outln!("  conserved: {}", if s.conserved.is_empty() { "none".into() } else { s.conserved.join(", ") })?;
        for p in &s.parameters {
            let unit = if p.unit.is_empty() { String::new() } else { format!(" {}", p.unit) };
            // The ASCII spelling of a Greek symbol is a key too (`--param alpha=0.3`).
            let symbol = if p.ascii_symbol == p.symbol {
                p.symbol.to_string()
            } else {
                format!("{} ({})", p.symbol, p.ascii_symbol)
            };
            outln!("  {:<22} {:<4} = {}{unit}  — {}", p.name, symbol, p.default, p.description)?;
        }
    }
    Ok(())
}
