//! Shape checks on the states that reach a scene's closed forms.

use lagrange::{Error, State};

/// Check that `q` and `q̇` both have `n` entries.
///
/// # Errors
/// [`Error::DimensionMismatch`] naming the first slice of the wrong length.
pub(crate) fn check_dimensions(n: usize, q: &[f64], qdot: &[f64]) -> Result<(), Error> {
    for (what, values) in [("q", q), ("q̇", qdot)] {
        if values.len() != n {
            return Err(Error::DimensionMismatch { what, expected: n, got: values.len() });
        }
    }
    Ok(())
}

/// Check that a state has `n` coordinates and `n` velocities.
///
/// # Errors
/// As [`check_dimensions`].
pub(crate) fn check_state(n: usize, state: &State) -> Result<(), Error> {
    check_dimensions(n, &state.q, &state.qdot)
}

/// The `N` entries of a slice as an array, for the typed scenes' closed forms.
///
/// # Panics
/// If the slice does not have exactly `N` entries: the typed closed forms document this; the
/// [`Scene`](crate::Scene) methods check the lengths first and return an error instead.
pub(crate) fn fixed<const N: usize>(values: &[f64], what: &str) -> [f64; N] {
    match values.try_into() {
        Ok(array) => array,
        Err(_) => panic!("{what} must have {N} entries, got {}", values.len()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrong_lengths_are_reported_with_the_slice_named() {
        assert_eq!(check_dimensions(2, &[0.0, 1.0], &[0.0, 1.0]), Ok(()));
        assert_eq!(
            check_dimensions(2, &[0.0], &[0.0, 1.0]),
            Err(Error::DimensionMismatch { what: "q", expected: 2, got: 1 })
        );
        assert_eq!(
            check_state(1, &State::new(0.0, [0.0], [0.0, 1.0])),
            Err(Error::DimensionMismatch { what: "q̇", expected: 1, got: 2 })
        );
    }

    #[test]
    #[should_panic(expected = "q must have 2 entries, got 3")]
    fn fixed_panics_on_the_wrong_length() {
        let _: [f64; 2] = fixed(&[1.0, 2.0, 3.0], "q");
    }
}
