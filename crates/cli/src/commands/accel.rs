//! `lagrange accel`: generalized accelerations at one state.

use crate::args;
use crate::error::CliError;
use serde::Serialize;

/// Arguments of `lagrange accel`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id (see `lagrange scenes`).
    scene: String,
    /// Parameter override NAME=VALUE (name or symbol), repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Generalized coordinates, comma-separated.
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    q: String,
    /// Generalized velocities, comma-separated.
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    qdot: String,
    /// Time.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    t: f64,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Out<'a> {
    scene: &'a str,
    t: f64,
    coordinates: Vec<String>,
    q: &'a [f64],
    qdot: &'a [f64],
    qddot: &'a [f64],
    closed_form: Option<Vec<f64>>,
}

/// Print `q̈` (and the scene's closed form beside it).
pub fn run(args: &Args) -> Result<(), CliError> {
    let scene = args::scene(&args.scene)?;
    let params = args::params(scene, &args.params)?;
    let state = args::state(scene, &params, Some(&args.q), Some(&args.qdot), Some(args.t))?;
    let mut system = scene.build(&params)?;
    let qddot = system.accelerations(state.t, &state.q, &state.qdot)?.to_vec();
    let closed_form = scene.closed_form_accelerations(&params, state.t, &state.q, &state.qdot)?;
    let coordinates: Vec<String> = system.coordinates().iter().map(|c| c.name.clone()).collect();
    if args.json {
        let out = Out {
            scene: scene.id(),
            t: state.t,
            coordinates,
            q: &state.q,
            qdot: &state.qdot,
            qddot: &qddot,
            closed_form,
        };
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    // `{:?}` prints the shortest decimal that reads back to the same f64: full precision.
    for (i, name) in coordinates.iter().enumerate() {
        match &closed_form {
            Some(exact) => println!("{name}'' = {:?}    (closed form {:?})", qddot[i], exact[i]),
            None => println!("{name}'' = {:?}", qddot[i]),
        }
    }
    Ok(())
}
