//! `lagrange simulate`: integrate a scene and write `t, q, q̇, energy` as CSV.

use crate::args;
use crate::error::CliError;
use lagrange::integrate::MethodKind;
use lagrange::{Method, Output, Trajectory};
use std::io::Write;

/// Which integrator: a [`MethodKind`], spelled and described as the solver names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Integrator(MethodKind);

/// Every integrator, in [`MethodKind::ALL`] order.
const INTEGRATORS: [Integrator; MethodKind::ALL.len()] = {
    let mut all = [Integrator(MethodKind::Rk4); MethodKind::ALL.len()];
    let mut i = 0;
    while i < all.len() {
        all[i] = Integrator(MethodKind::ALL[i]);
        i += 1;
    }
    all
};

impl clap::ValueEnum for Integrator {
    fn value_variants<'a>() -> &'a [Self] {
        &INTEGRATORS
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.0.name()).help(self.0.summary()))
    }
}

/// Arguments of `lagrange simulate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id (see `lagrange scenes`).
    scene: String,
    /// Parameter override NAME=VALUE (name or symbol), repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Initial coordinates, comma-separated (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    q: Option<String>,
    /// Initial velocities, comma-separated (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    qdot: Option<String>,
    /// End time (s).
    #[arg(long, allow_negative_numbers = true)]
    t_end: f64,
    /// Integrator.
    #[arg(long, value_enum, default_value_t = Integrator(MethodKind::Adaptive))]
    integrator: Integrator,
    /// Step of the fixed-step integrators: rk4, variational, gauss (default 1e-3).
    #[arg(long, allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Tolerance (relative and absolute) of the error-controlled integrators: adaptive, implicit
    /// (default 1e-10 for adaptive, 1e-8 for implicit).
    #[arg(long, allow_negative_numbers = true)]
    tol: Option<f64>,
    /// Output interval (default: 200 samples; a multiple of --dt for fixed steps).
    #[arg(long, allow_negative_numbers = true)]
    every: Option<f64>,
    /// CSV file to write (default: standard output).
    #[arg(long)]
    out: Option<std::path::PathBuf>,
}

/// The method and output grid the arguments ask for.
fn method_and_output(args: &Args) -> Result<(Method, Output), CliError> {
    if !(args.t_end.is_finite() && args.t_end > 0.0) {
        return Err(CliError::NotPositive { flag: "--t-end", value: args.t_end });
    }
    let Integrator(kind) = args.integrator;
    let method = match kind.default_method() {
        default @ (Method::Adaptive { .. } | Method::Implicit { .. }) => {
            if args.dt.is_some() {
                return Err(CliError::NotForIntegrator {
                    flag: "--dt",
                    integrator: kind.name(),
                    applies_to: "the fixed-step integrators (rk4, variational, gauss)",
                    instead: "--tol",
                });
            }
            args.tol.map_or(default, |tol| kind.with(tol))
        }
        Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss { dt } => {
            if args.tol.is_some() {
                return Err(CliError::NotForIntegrator {
                    flag: "--tol",
                    integrator: kind.name(),
                    applies_to: "the error-controlled integrators (adaptive, implicit)",
                    instead: "--dt",
                });
            }
            kind.with(args::step("--dt", args.dt.unwrap_or(dt), args.t_end)?)
        }
    };
    let every = match (args.every, method) {
        (Some(every), _) => every,
        (None, Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss { dt }) => {
            dt * (args.t_end / 200.0 / dt).round().max(1.0)
        }
        (None, Method::Adaptive { .. } | Method::Implicit { .. }) => args.t_end / 200.0,
    };
    if !(every > 0.0 && every.is_finite()) {
        return Err(CliError::NotPositive { flag: "--every", value: every });
    }
    Ok((method, Output::Every(every)))
}

/// Write the trajectory as CSV.
fn write_csv(out: &mut dyn Write, names: &[String], trajectory: &Trajectory) -> std::io::Result<()> {
    let mut header = vec!["t".to_string()];
    header.extend(names.iter().cloned());
    header.extend(names.iter().map(|n| format!("{n}_dot")));
    header.push("energy".into());
    writeln!(out, "{}", header.join(","))?;
    for k in 0..trajectory.len() {
        let mut row = vec![trajectory.t[k].to_string()];
        row.extend(trajectory.q(k).iter().map(f64::to_string));
        row.extend(trajectory.qdot(k).iter().map(f64::to_string));
        row.push(trajectory.energy[k].to_string());
        writeln!(out, "{}", row.join(","))?;
    }
    Ok(())
}

/// Integrate and write.
pub fn run(args: &Args) -> Result<(), CliError> {
    let scene = args::scene(&args.scene)?;
    let params = args::params(scene, &args.params)?;
    let initial = args::state(scene, &params, args.q.as_deref(), args.qdot.as_deref(), None)?;
    let (method, output) = method_and_output(args)?;
    let system = scene.build(&params)?;
    let trajectory = system.simulate(&initial, initial.t + args.t_end, method, &output)?;
    if let Some(t) = trajectory.stats.stiffness {
        eprintln!("warning: the problem looks stiff from t = {t}; try --integrator implicit");
    }
    let names: Vec<String> = system.coordinates().iter().map(|c| c.name.clone()).collect();
    match &args.out {
        Some(path) => {
            let file = std::fs::File::create(path).map_err(|source| CliError::Io { path: path.clone(), source })?;
            let mut writer = std::io::BufWriter::new(file);
            write_csv(&mut writer, &names, &trajectory)
                .and_then(|()| writer.flush())
                .map_err(|source| CliError::Io { path: path.clone(), source })?;
            eprintln!(
                "{}: {} samples to {} ({} steps, {} rejected)",
                scene.id(),
                trajectory.len(),
                path.display(),
                trajectory.stats.steps,
                trajectory.stats.rejected
            );
        }
        None => {
            let stdout = std::io::stdout();
            write_csv(&mut stdout.lock(), &names, &trajectory).map_err(CliError::Stdout)?;
        }
    }
    Ok(())
}
