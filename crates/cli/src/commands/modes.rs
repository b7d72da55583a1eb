//! `lagrange modes`: the equilibrium nearest a configuration and the normal modes about it
//! ([`lagrange::modes::normal_modes`]): natural frequencies, mode shapes, zero modes named, unstable
//! directions reported with their imaginary frequencies.

use crate::args;
use crate::error::CliError;
use crate::output::{compact, outln, print};
use lagrange::modes::{ModeKind, Modes};
use serde::Serialize;

/// Arguments of `lagrange modes`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id (see `lagrange scenes`) or scene file (`*.toml`, docs/files.md).
    scene: String,
    /// Parameter override NAME=VALUE (name, symbol, or the symbol in ASCII), once per parameter.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Where to start looking for the equilibrium, comma-separated (default: the scene's
    /// initial configuration).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    q: Option<String>,
    /// Time (default: the scene's initial time, 0).
    #[arg(long, allow_hyphen_values = true)]
    t: Option<f64>,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct ModeOut<'a> {
    /// `oscillating`, `zero` or `unstable`.
    kind: &'static str,
    /// `ω²` (rad²/s²).
    omega_squared: f64,
    /// `ω` (rad/s): the growth rate of an unstable mode (its frequency is `i ω`).
    omega: f64,
    /// `ω / 2π` (Hz) of an oscillating mode.
    frequency: Option<f64>,
    /// `2π / ω` (s) of an oscillating mode.
    period: Option<f64>,
    /// The mode shape, largest entry 1.
    shape: &'a [f64],
}

#[derive(Serialize)]
struct Out<'a> {
    scene: &'a str,
    t: f64,
    coordinates: &'a [String],
    equilibrium: &'a [f64],
    mass_matrix: &'a [f64],
    stiffness_matrix: &'a [f64],
    damped: bool,
    asymmetry: f64,
    modes: Vec<ModeOut<'a>>,
}

fn kind(k: ModeKind) -> &'static str {
    match k {
        ModeKind::Oscillating => "oscillating",
        ModeKind::Zero => "zero",
        ModeKind::Unstable => "unstable",
    }
}

/// Find the equilibrium and print the modes.
pub fn run(args: &Args) -> Result<(), CliError> {
    let scene = args::scene(&args.scene)?;
    let params = args::params(scene, &args.params)?;
    let state = args::state(scene, &params, args.q.as_deref(), None, args.t)?;
    let mut system = args::build(scene, &params, &state)?;
    let names: Vec<String> = system.coordinates().iter().map(|c| c.name.clone()).collect();
    let modes = lagrange::modes::normal_modes(system.as_mut(), state.t, &state.q)
        .map_err(|error| args::explain(error, &params, &names, &state))?;
    let out = Out {
        scene: scene.id(),
        t: state.t,
        coordinates: &names,
        equilibrium: &modes.equilibrium,
        mass_matrix: &modes.mass,
        stiffness_matrix: &modes.stiffness,
        damped: modes.damped,
        asymmetry: modes.asymmetry,
        modes: modes
            .modes
            .iter()
            .map(|m| {
                let oscillating = m.kind == ModeKind::Oscillating;
                ModeOut {
                    kind: kind(m.kind),
                    omega_squared: m.omega_squared,
                    omega: m.omega(),
                    frequency: oscillating.then(|| m.omega() / std::f64::consts::TAU),
                    period: oscillating.then(|| std::f64::consts::TAU / m.omega()),
                    shape: &m.shape,
                }
            })
            .collect(),
    };
    if args.json {
        return outln!("{}", serde_json::to_string_pretty(&out)?);
    }
    print(&text(&out, &modes, system.cyclic_coordinates()))
}

fn text(out: &Out<'_>, modes: &Modes, cyclic: &[bool]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let equilibrium: Vec<String> =
        out.coordinates.iter().zip(out.equilibrium).map(|(n, q)| format!("{n} = {}", compact(*q))).collect();
    let _ = writeln!(s, "{}: equilibrium at t = {}: {}", out.scene, compact(out.t), equilibrium.join(", "));
    let _ = writeln!(s, "{} normal modes (M δq̈ + K δq = 0 on the constraints' tangent space):", modes.modes.len());
    for (k, m) in out.modes.iter().enumerate() {
        let shape: Vec<String> =
            out.coordinates.iter().zip(m.shape).map(|(n, v)| format!("{n} {}", compact(*v))).collect();
        let what = match m.kind {
            "oscillating" => format!(
                "ω = {} rad/s, f = {} Hz, T = {} s",
                compact(m.omega),
                compact(m.frequency.unwrap_or(f64::NAN)),
                compact(m.period.unwrap_or(f64::NAN))
            ),
            "zero" => {
                // Name the coordinate it moves, and whether that coordinate is cyclic.
                let along =
                    m.shape.iter().enumerate().max_by(|a, b| a.1.abs().total_cmp(&b.1.abs())).map_or(0, |(i, _)| i);
                let note = if cyclic.get(along).copied().unwrap_or(false) { ", a cyclic coordinate" } else { "" };
                format!("zero mode: a free motion along {}{note}, no restoring force", out.coordinates[along])
            }
            _ => format!("unstable: ω = {} i rad/s (grows as e^({} t))", compact(m.omega), compact(m.omega)),
        };
        let _ = writeln!(s, "  mode {}: {what}\n    shape: {}", k + 1, shape.join(", "));
    }
    if out.damped {
        let _ = writeln!(s, "(q̈ depends on q̇ at rest: damping; these are the undamped frequencies)");
    }
    if out.asymmetry > 1e-8 {
        let _ = writeln!(
            s,
            "(K is not symmetric, {:.1e} of its size: circulatory forces; its symmetric part is shown)",
            out.asymmetry
        );
    }
    s
}
