//! `lagrange animate`: the motion as one self-contained HTML page — the reduced solution and
//! each maximal engine drawn over one another, each engine's error against time beside it
//! ([`lagrange_validation::animation`], docs/animation.md) — or a normal mode played beside the
//! nonlinear motion it predicts (`--mode k`).

use super::compare::estimates;
use crate::args;
use crate::error::CliError;
use crate::output::{compact, warn};
use lagrange_maximal::Engine;
use lagrange_validation::animation::{Animation, animate, animate_mode};
use lagrange_validation::render::animation::page;
use std::path::PathBuf;

/// Arguments of `lagrange animate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    start: args::Start,
    /// Engine drawn over the reduced solution: cartesian, rapier-impulse, rapier-multibody,
    /// rapier-impulse-f32, rapier-multibody-f32, all, or none; repeatable [default: all].
    #[arg(long = "engine", value_name = "ENGINE")]
    engines: Vec<String>,
    #[command(flatten)]
    engine_settings: args::EngineSettings,
    /// Simulated time (s) [default: the scene's own span where it has one (Andrews' squeezer:
    /// 30 ms), otherwise 10 s; with --mode, four periods].
    #[arg(long, allow_negative_numbers = true)]
    t_end: Option<f64>,
    /// Play normal mode K (0: the lowest frequency; see `lagrange modes`) about the equilibrium
    /// nearest the initial configuration, beside the nonlinear motion it predicts.
    #[arg(long, value_name = "K")]
    mode: Option<usize>,
    /// With --mode: the displacement along the mode shape (largest entry 1), in the
    /// coordinates' units.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    amplitude: f64,
    /// The HTML file to write [default: SCENE.html].
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Run a request whose estimated wall time is beyond the limit (2 minutes).
    #[arg(long)]
    force: bool,
}

/// The engines asked for.
fn engines(names: &[String]) -> Result<Vec<Engine>, CliError> {
    if names.is_empty() {
        return Ok(Engine::ALL.to_vec());
    }
    let mut engines = Vec::new();
    for name in names {
        match name.as_str() {
            "all" => engines.extend(Engine::ALL),
            "none" => {}
            name => engines.push(Engine::from_name(name).ok_or_else(|| CliError::UnknownEngine(name.into()))?),
        }
    }
    let mut unique = Vec::new();
    for engine in engines {
        if !unique.contains(&engine) {
            unique.push(engine);
        }
    }
    Ok(unique)
}

/// Run, draw and write the page.
pub fn run(args: &Args) -> Result<(), CliError> {
    let (scene, params, given) = args.start.resolve()?;
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("{}.html", scene.id())));
    if let Some(t_end) = args.t_end
        && !(t_end.is_finite() && t_end > given.t)
    {
        return Err(CliError::NotPositive { flag: "--t-end", value: t_end });
    }
    let animation: Animation = if let Some(index) = args.mode {
        if !(args.amplitude.is_finite() && args.amplitude != 0.0) {
            return Err(CliError::NotPositive { flag: "--amplitude", value: args.amplitude });
        }
        animate_mode(scene, &params, (given.t, &given.q), index, args.amplitude, args.t_end)?
    } else {
        let initial = args::hold(args::build(scene, &params, &given)?.as_mut(), given, args.start.hold.as_deref())?;
        let t_end = args.t_end.unwrap_or(initial.t + scene.horizon().unwrap_or(10.0));
        let settings = args.engine_settings.settings();
        args::step("--dt", settings.dt, t_end)?;
        let engines = engines(&args.engines)?;
        estimates((args.force, t_end - initial.t), scene, (&params, &initial), &settings, &engines)?;
        animate(scene, &params, &initial, &engines, &settings, t_end)?
    };
    let html = page(&animation);
    std::fs::write(&out, &html).map_err(|source| CliError::Io { path: out.clone(), source })?;
    let frames = animation.tracks.first().map_or(0, |t| t.times.len());
    let drawn: Vec<&str> = animation.tracks.iter().filter(|t| !t.times.is_empty()).map(|t| t.label.as_str()).collect();
    warn(&format!(
        "wrote {} ({} kB): {frames} frames over {} s; {}",
        out.display(),
        html.len().div_ceil(1000),
        compact(animation.tracks.first().and_then(|t| t.times.last().zip(t.times.first())).map_or(0.0, |(b, a)| b - a)),
        drawn.join(", ")
    ));
    for track in animation.tracks.iter().filter(|t| t.times.is_empty()) {
        warn(&format!("{}: no frames: {}", track.label, track.note.as_deref().unwrap_or("")));
    }
    Ok(())
}
