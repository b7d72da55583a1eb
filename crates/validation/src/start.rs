//! Where a run starts: a given state brought onto the scene's constraints among its
//! coordinates, keeping the coordinates the user names ([`hold`]). The command line (`--hold`)
//! and the Python package (`hold=`) take it from here, with the same messages.

use lagrange::{State, System};

/// The residual, relative to the state's size, above which a given state is not on the
/// constraints: the engine's own test of a consistent start (1e-10).
pub const INCONSISTENT: f64 = 1e-10;

/// `1 + max(|q|, |q̇|)`: the size [`INCONSISTENT`] is relative to.
fn state_scale(state: &State) -> f64 {
    1.0 + state.q.iter().chain(&state.qdot).fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// A number for a message as the command line writes it: plain between 1e-4 and 1e6,
/// scientific outside.
fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) { format!("{v}") } else { format!("{v:e}") }
}

/// Why a start could not be held.
#[derive(Debug, thiserror::Error)]
pub enum HoldError {
    /// An unknown or repeated name, a scene without constraints, an inconsistent state with
    /// nothing held or with everything held: what is wrong, in one sentence.
    #[error("{0}")]
    Refused(String),
    /// The engine failed: the links cannot close from the state
    /// ([`lagrange::Error::AssemblyFailed`]), or the state is malformed.
    #[error(transparent)]
    Engine(#[from] lagrange::Error),
}

/// The state `initial` brought onto the constraints among the system's coordinates, keeping
/// the coordinates named in `held` and their rates ([`System::assemble`]); `initial` itself
/// when `held` is `None` and it is on them already. `spell` writes how the user names a
/// coordinate to hold (`--hold θ2`, `hold=['θ2']`), for the hint of an inconsistent start.
///
/// # Errors
/// [`HoldError::Refused`] for an unknown or repeated name, a scene without constraints, or an
/// inconsistent state without names (or with every coordinate named); [`HoldError::Engine`]
/// when the links cannot close from there.
pub fn hold(
    system: &mut dyn System,
    initial: State,
    held: Option<&[&str]>,
    spell: impl Fn(&str) -> String,
) -> Result<State, HoldError> {
    let Some(held) = held else {
        // The engine refuses an inconsistent start too; here the message can say what to do.
        if let Some([position, velocity]) = system.constraint_violation(initial.t, &initial.q, &initial.qdot)?
            && position.max(velocity) > INCONSISTENT * state_scale(&initial)
        {
            let first = system.coordinates().first().map_or(String::new(), |c| c.name.to_string());
            return Err(HoldError::Refused(format!(
                "the initial state does not satisfy the scene's constraints (max |Φ| = {}, velocity \
                 residual {}); name the coordinates to keep, e.g. {}, and the others are moved onto \
                 the constraints",
                short(position),
                short(velocity),
                spell(&first)
            )));
        }
        return Ok(initial);
    };
    if system.constraint_counts() == (0, 0) {
        return Err(HoldError::Refused("this scene has no constraints among its coordinates".into()));
    }
    let names: Vec<&str> = system.coordinates().iter().map(|c| c.name.as_ref()).collect();
    let mut keep = vec![false; names.len()];
    for &name in held {
        if name.is_empty() {
            return Err(HoldError::Refused(format!(
                "an empty name; name the coordinates to keep, from {}",
                names.join(", ")
            )));
        }
        let Some(i) = names.iter().position(|n| *n == name) else {
            return Err(HoldError::Refused(format!(
                "no coordinate `{name}`; the coordinates are {}",
                names.join(", ")
            )));
        };
        if keep[i] {
            return Err(HoldError::Refused(format!("`{name}` is named twice")));
        }
        keep[i] = true;
    }
    if keep.iter().all(|&k| k) {
        // Nothing is left to move: the state must already be on the constraints.
        return match system.constraint_violation(initial.t, &initial.q, &initial.qdot)? {
            Some([position, velocity]) if position.max(velocity) > INCONSISTENT * state_scale(&initial) => {
                Err(HoldError::Refused(format!(
                    "every coordinate is held, so none can move onto the constraints (max |Φ| = {}, \
                     velocity residual {}); hold fewer",
                    short(position),
                    short(velocity)
                )))
            }
            _ => Ok(initial),
        };
    }
    Ok(system.assemble(&initial, &keep)?)
}
