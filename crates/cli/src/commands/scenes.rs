//! `lagrange scenes`: every scene with its coordinates and parameters.

use crate::error::CliError;
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
    unit: &'static str,
    default: f64,
    description: &'static str,
}

#[derive(Serialize)]
struct CoordinateOut {
    name: String,
    unit: &'static str,
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
}

/// Print the scene list.
pub fn run(args: &Args) -> Result<(), CliError> {
    let mut scenes = Vec::new();
    for scene in lagrange_scenes::all() {
        let params = scene.default_params();
        let coordinates = scene.coordinates(&params)?;
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
                    unit: p.unit,
                    default: p.default,
                    description: p.description,
                })
                .collect(),
            conserved: scene.conserved_quantities(&params).unwrap_or_default().into_iter().map(|c| c.symbol).collect(),
        });
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&scenes)?);
        return Ok(());
    }
    for s in &scenes {
        let coordinates: Vec<String> = s.coordinates.iter().map(|c| format!("{} [{}]", c.name, c.unit)).collect();
        println!("{} — {} ({})", s.id, s.title, s.reference);
        println!("  coordinates: {}", coordinates.join(", "));
        println!("  conserved: {}", if s.conserved.is_empty() { "none".into() } else { s.conserved.join(", ") });
        for p in &s.parameters {
            let unit = if p.unit.is_empty() { String::new() } else { format!(" {}", p.unit) };
            println!("  {:<22} {:<4} = {}{unit}  — {}", p.name, p.symbol, p.default, p.description);
        }
    }
    Ok(())
}
