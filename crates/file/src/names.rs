//! "Did you mean …?": the closest known name to one that is not known.

/// The known name closest to `name`, if one is close enough to be what was meant: at most a
/// third of its characters edited (at least one), or the same name in other case.
pub fn suggest<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.chars().count() / 3).max(1);
    known
        .into_iter()
        .map(|candidate| {
            let distance = if candidate.to_lowercase() == name.to_lowercase() {
                0
            } else {
                strsim::damerau_levenshtein(name, candidate)
            };
            (distance, candidate)
        })
        .filter(|&(distance, _)| distance <= limit)
        .min_by_key(|&(distance, _)| distance)
        .map(|(_, candidate)| candidate)
}

#[cfg(test)]
mod tests {
    use super::suggest;

    #[test]
    fn close_names_are_suggested_and_far_ones_not() {
        let known = ["theta", "phi", "l1", "mass"];
        assert_eq!(suggest("thta", known), Some("theta"));
        assert_eq!(suggest("Theta", known), Some("theta"));
        assert_eq!(suggest("l2", known), Some("l1"));
        assert_eq!(suggest("velocity", known), None);
    }
}
