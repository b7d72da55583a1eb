//! `lagrange accel`: generalized accelerations at one state, beside the scene's closed form.
//!
//! A state off the scene's constraints (a loop that does not close, a velocity that breaks a
//! rolling condition) is refused with exit 2, as `simulate` refuses to start from it; `--hold`
//! brings it onto them first, keeping the named coordinates.
//!
//! A state outside the scene's admissible region (docs/method.md#admissible-regions) is refused
//! with exit 1, as `simulate` refuses to step there; `--ignore-region` evaluates it anyway with a
//! warning, to look at where the models part.
//!
//! The two are exact formulas for the same `q̈` and differ by round-off only: at most
//! `max(1e-12, 64 ε κ(M))` relative to the largest `|q̈_i|` (`lagrange_validation::tolerance::Agreement`,
//! the bound the integration tests hold every scene to at random states and parameters). A
//! larger difference means the state or the parameters lie where the two models part (outside
//! the scene's admissible region, say): `accel` says so on standard error, and with `--check`
//! fails with exit 1.

use crate::args;
use crate::error::CliError;
use crate::output::{compact_all, outln, warn};
use lagrange_testing::condition_number;
use lagrange_validation::tolerance::Agreement;
use serde::Serialize;

/// Arguments of `lagrange accel`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id (see `lagrange scenes`) or scene file (`*.toml`, docs/files.md).
    scene: String,
    /// Parameter override NAME=VALUE (name, symbol, or the symbol in ASCII: alpha for α),
    /// once per parameter.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Generalized coordinates, comma-separated (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    q: Option<String>,
    /// Generalized velocities, comma-separated (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    qdot: Option<String>,
    /// For a mechanism with constraints among its coordinates (a four-bar): bring the state onto
    /// them first, keeping these coordinates and their rates (comma-separated names, e.g. `θ2`).
    /// Without it, a given state must already satisfy the constraints (exit 2 otherwise).
    #[arg(long, value_name = "NAME,..")]
    hold: Option<String>,
    /// Time (default: the scene's initial time, 0).
    #[arg(long, allow_hyphen_values = true)]
    t: Option<f64>,
    /// Fail (exit 1) when the engine and the closed form differ beyond round-off.
    #[arg(long)]
    check: bool,
    /// Evaluate a state outside the scene's admissible region (a warning instead of exit 1).
    #[arg(long)]
    ignore_region: bool,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

/// One coordinate's acceleration, named.
#[derive(Serialize)]
struct AccelerationOut<'a> {
    /// The coordinate whose second time derivative this is.
    coordinate: &'a str,
    /// The engine's `q̈` of the coordinate.
    engine: f64,
    /// The closed form's `q̈` of the coordinate.
    closed_form: Option<f64>,
}

#[derive(Serialize)]
struct Out<'a> {
    scene: &'a str,
    t: f64,
    coordinates: &'a [String],
    q: &'a [f64],
    qdot: &'a [f64],
    /// The engine's `q̈`, in the order of `coordinates`.
    qddot: &'a [f64],
    /// The closed form's `q̈`, in the order of `coordinates`.
    closed_form: Option<&'a [f64]>,
    /// The same, one object per coordinate.
    accelerations: Vec<AccelerationOut<'a>>,
    /// Absent when the scene has no closed form.
    agreement: Option<Agreement>,
}

/// Print `q̈` (and the scene's closed form beside it, checked against it).
pub fn run(args: &Args) -> Result<(), CliError> {
    let scene = args::scene(&args.scene)?;
    let params = args::params(scene, &args.params)?;
    let state = args::state(scene, &params, args.q.as_deref(), args.qdot.as_deref(), args.t)?;
    let mut system = args::build(scene, &params, &state)?;
    // A state off the constraints has no accelerations of the mechanism: refused, as
    // `simulate` refuses to start from it (or brought onto them with --hold).
    let state = args::hold(system.as_mut(), state, args.hold.as_deref())?;
    let coordinates: Vec<String> = system.coordinates().iter().map(|c| c.name.clone()).collect();
    let explain = |error| args::explain(error, &params, &coordinates, &state);
    match system.check_admissible(state.t, &state.q, &state.qdot) {
        Err(error) if args.ignore_region => warn(&format!("warning: {error}; evaluated anyway (--ignore-region)")),
        region => drop(region.map_err(explain)?),
    }
    let qddot = system.accelerations(state.t, &state.q, &state.qdot).map_err(explain)?.to_vec();
    let closed_form = scene.closed_form_accelerations(&params, state.t, &state.q, &state.qdot).map_err(explain)?;
    // A hand-derived formula that divides by zero at this state (a singular configuration) has
    // no value here: said, not printed as NaN.
    let closed_form = closed_form.filter(|exact| {
        let defined = exact.iter().all(|v| v.is_finite());
        if !defined {
            warn("warning: the scene's closed form is undefined at this state (it divides by zero there); the engine's q̈ is shown alone");
        }
        defined
    });
    let agreement = match &closed_form {
        Some(exact) => {
            let mass_matrix = system.mass_matrix(state.t, &state.q, &state.qdot).map_err(explain)?;
            Some(Agreement::of(&qddot, exact, condition_number(coordinates.len(), mass_matrix)))
        }
        None => None,
    };
    if args.json {
        let accelerations = coordinates
            .iter()
            .enumerate()
            .map(|(i, name)| AccelerationOut {
                coordinate: name,
                engine: qddot[i],
                closed_form: closed_form.as_ref().map(|c| c[i]),
            })
            .collect();
        let out = Out {
            scene: scene.id(),
            t: state.t,
            coordinates: &coordinates,
            q: &state.q,
            qdot: &state.qdot,
            qddot: &qddot,
            closed_form: closed_form.as_deref(),
            accelerations,
            agreement,
        };
        outln!("{}", serde_json::to_string_pretty(&out)?)?;
    } else {
        // `{:?}` prints the shortest decimal that reads back to the same f64: full precision.
        // `q̈[x']`, not `x'''`: the coordinate's name may end in a prime itself.
        for (i, name) in coordinates.iter().enumerate() {
            match &closed_form {
                Some(exact) => outln!("q̈[{name}] = {:?}    (closed form {:?})", qddot[i], exact[i])?,
                None => outln!("q̈[{name}] = {:?}", qddot[i])?,
            }
        }
    }
    match agreement {
        Some(a) if !a.agrees => {
            let error = CliError::Disagreement {
                difference: a.difference,
                bound: a.bound,
                condition_number: a.condition_number,
            };
            if args.check {
                return Err(error);
            }
            let (q, qdot) = (compact_all(&state.q), compact_all(&state.qdot));
            warn(&format!(
                "warning: {error}; the two models part at q = {q}, q̇ = {qdot} (--check makes this an error)"
            ));
        }
        _ => {}
    }
    Ok(())
}
