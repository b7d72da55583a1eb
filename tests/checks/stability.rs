//! Stability: which methods stay stable and accurate, at what cost, against theory where
//! theory exists — stiff springs and strong damping at fixed steps (stability limits against
//! the stability functions of the methods), extreme parameters against closed forms and
//! conservation laws, a nearly parabolic Kepler orbit over 100 periods, chaos (how long two
//! tolerances agree), near-singular configurations, and long runs.

/// The report's stability cases, each run with its quick settings: every checked measurement
/// must pass against the case's own theory, with the bound the report states. The report and
/// these tests run the same code, so a bound is written once.
mod report_cases {
    use lagrange_validation::stability::{Effort, run_case};

    fn assert_case_passes(id: &str) {
        let case = run_case(id, Effort::Quick).unwrap_or_else(|e| panic!("{e}"));
        let failing: Vec<String> = case
            .measurements
            .iter()
            .filter(|m| m.pass == Some(false))
            .map(|m| {
                format!(
                    "{} [{} {}] {}: value {:?}, theory {:?}, check {:?}, bound {:?}, status {}, error {:?} (expected {:?}), note {:?}",
                    m.label,
                    m.scene,
                    m.method,
                    m.quantity,
                    m.value,
                    m.theory,
                    m.check,
                    m.bound,
                    m.status,
                    m.error,
                    m.expected_error,
                    m.note
                )
            })
            .collect();
        assert!(failing.is_empty(), "{id}: {} checks fail:\n{}", failing.len(), failing.join("\n"));
        assert_eq!(case.pass, Some(true), "{id}: no checked measurement");
    }

    #[test]
    fn every_case_is_run_here() {
        let ids: Vec<&str> = lagrange_validation::stability::case_ids().collect();
        let tested = [
            "stiff_spring",
            "stiff_damped",
            "extreme_parameters",
            "kepler_e099",
            "chaos",
            "near_singular",
            "parallelogram_branch",
            "constraints",
            "long_run",
            "rapier_long_run",
            "bad_input",
        ];
        assert_eq!(ids, tested);
    }

    #[test]
    fn stiff_spring() {
        assert_case_passes("stiff_spring");
    }

    #[test]
    fn stiff_damped() {
        assert_case_passes("stiff_damped");
    }

    #[test]
    fn extreme_parameters() {
        assert_case_passes("extreme_parameters");
    }

    #[test]
    fn kepler_e099() {
        assert_case_passes("kepler_e099");
    }

    #[test]
    fn chaos() {
        assert_case_passes("chaos");
    }

    #[test]
    fn parallelogram_branch() {
        assert_case_passes("parallelogram_branch");
    }

    #[test]
    fn constraints() {
        assert_case_passes("constraints");
    }

    #[test]
    fn near_singular() {
        assert_case_passes("near_singular");
    }

    #[test]
    fn long_run() {
        assert_case_passes("long_run");
    }

    #[test]
    fn rapier_long_run() {
        assert_case_passes("rapier_long_run");
    }

    #[test]
    fn bad_input() {
        assert_case_passes("bad_input");
    }
}
