//! `lagrange animate`: the motion as one self-contained HTML page — the reduced solution and
//! each maximal engine drawn over one another, each engine's error against time beside it
//! ([`lagrange_validation::animation`], docs/animation.md) — or a normal mode played beside the
//! nonlinear motion it predicts (`--mode k`).

use super::compare::estimates;
use crate::args;
use crate::error::CliError;
use crate::output::{compact, warn};
use lagrange_maximal::{Engine, Settings};
use lagrange_validation::animation::{Animation, animate, animate_mode};
use lagrange_validation::render::animation::page;
use std::path::PathBuf;

/// Arguments of `lagrange animate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id (see `lagrange scenes`) or scene file (`*.toml`, docs/files.md).
    scene: String,
    /// Parameter override NAME=VALUE (name or symbol), repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Initial coordinates (default: the scene's initial state); with --mode, where to start
    /// looking for the equilibrium.
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    q: Option<String>,
    /// Initial velocities (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    qdot: Option<String>,
    /// For a mechanism with constraints among its coordinates: bring the initial state onto
    /// them, keeping these coordinates and their rates (as `compare --hold`).
    #[arg(long, value_name = "NAME,..")]
    hold: Option<String>,
    /// Engine drawn over the reduced solution: cartesian, rapier-impulse, rapier-multibody,
    /// rapier-impulse-f32, rapier-multibody-f32, all, or none; repeatable [default: all].
    #[arg(long = "engine", value_name = "ENGINE")]
    engines: Vec<String>,
    /// rapier step (s) [default: 1/240].
    #[arg(long, default_value_t = 1.0 / 240.0, hide_default_value = true, allow_negative_numbers = true)]
    dt: f64,
    /// rapier substeps per step.
    #[arg(long, default_value_t = 4)]
    substeps: usize,
    /// Tolerance of the Cartesian engine's integrator.
    #[arg(long, default_value = "1e-12", allow_negative_numbers = true)]
    tol: f64,
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
    let scene = args::scene(&args.scene)?;
    let params = args::params(scene, &args.params)?;
    let given = args::state(scene, &params, args.q.as_deref(), args.qdot.as_deref(), None)?;
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
        // Four periods of the mode unless told otherwise.
        let t_end = match args.t_end {
            Some(t_end) => t_end,
            None => {
                let mut system = args::build(scene, &params, &given)?;
                let modes = lagrange::modes::normal_modes(system.as_mut(), given.t, &given.q)?;
                let omega = modes.modes.get(index).map_or(0.0, lagrange::modes::Mode::omega);
                given.t + if omega > 0.0 { 4.0 * std::f64::consts::TAU / omega } else { 10.0 }
            }
        };
        animate_mode(scene, &params, (given.t, &given.q), index, args.amplitude, t_end)?
    } else {
        let initial = args::hold(args::build(scene, &params, &given)?.as_mut(), given, args.hold.as_deref())?;
        let t_end = args.t_end.unwrap_or(initial.t + scene.horizon().unwrap_or(10.0));
        args::step("--dt", args.dt, t_end)?;
        let settings = Settings { dt: args.dt, substeps: args.substeps, tolerance: args.tol };
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
