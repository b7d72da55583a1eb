//! `lagrange report` as a user runs it: the files it writes, the documented fields of
//! report.json (crates/cli/REPORT_SCHEMA.md), errors that fall along the sweeps, and one-line
//! errors for bad arguments.

use super::{assert_one_line_error, lagrange, stderr};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A fresh directory under the system's temporary directory.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lagrange-report-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

const METHODS: [&str; 9] = [
    "rk4",
    "dopri5",
    "dop853",
    "variational",
    "cartesian",
    "rapier-impulse",
    "rapier-multibody",
    "rapier-impulse-f32",
    "rapier-multibody-f32",
];

fn has_keys(value: &Value, keys: &[&str], what: &str) {
    let object = value.as_object().unwrap_or_else(|| panic!("{what} is not an object: {value}"));
    for key in keys {
        assert!(object.contains_key(*key), "{what} lacks `{key}`: {value}");
    }
}

fn number_or_null(value: &Value, what: &str) -> Option<f64> {
    assert!(value.is_null() || value.is_f64() || value.is_u64(), "{what} is neither a number nor null: {value}");
    value.as_f64()
}

/// Max errors of a method's runs, in sweep order.
fn max_errors(scene: &Value, method: &str) -> Vec<f64> {
    let method = scene["methods"].as_array().unwrap().iter().find(|m| m["method"] == method).expect("method entry");
    method["runs"].as_array().unwrap().iter().map(|r| r["max_error"].as_f64().expect("a successful run")).collect()
}

/// Every documented field of one run, and what it may hold.
fn check_run(run: &Value, solver: &str, conserves_energy: bool, what: &str) {
    has_keys(
        run,
        &[
            "settings",
            "status",
            "reason",
            "max_error",
            "final_error",
            "energy_error",
            "constraint_violation",
            "wall_time_s",
            "timed_repetitions",
            "steps",
            "on_front",
        ],
        what,
    );
    has_keys(&run["settings"], &["dt", "tolerance", "substeps", "h"], what);
    assert_eq!(run["status"], "ok", "{what}: {run}");
    let max = run["max_error"].as_f64().expect("max_error");
    let last = run["final_error"].as_f64().expect("final_error");
    assert!(max.is_finite() && max >= last && last >= 0.0, "{what}: {run}");
    assert!(run["wall_time_s"].as_f64().is_some_and(|t| t > 0.0), "{what}: {run}");
    assert!(run["timed_repetitions"].as_u64().is_some_and(|n| n >= 1), "{what}: {run}");
    // Energy only where the scene conserves it; a constraint violation only from maximal engines.
    let energy = number_or_null(&run["energy_error"], what);
    assert_eq!(energy.is_some(), conserves_energy, "{what}: {run}");
    let violation = number_or_null(&run["constraint_violation"], what);
    if solver == "reduced" {
        assert!(violation.is_none(), "{what}: {run}");
    }
}

fn check_ratio(ratio: &Value, what: &str) {
    has_keys(ratio, &["value", "lower_bound", "reason", "target", "met"], what);
    let value = number_or_null(&ratio["value"], what);
    let bound = number_or_null(&ratio["lower_bound"], what);
    assert!(value.is_some() || ratio["reason"].is_string(), "{what}: a null ratio says why: {ratio}");
    assert!(ratio["met"].is_null() || ratio["met"].is_boolean(), "{what}: {ratio}");
    if let Some(v) = value {
        assert_eq!(ratio["met"].as_bool(), Some(v >= ratio["target"].as_f64().unwrap()), "{what}: {ratio}");
    } else if ratio["met"] == true {
        assert!(bound.is_some_and(|b| b >= ratio["target"].as_f64().unwrap()), "{what}: {ratio}");
    }
}

fn check_scene(scene: &Value, dir: &Path) {
    let id = scene["scene"].as_str().expect("scene id");
    has_keys(
        scene,
        &[
            "scene",
            "title",
            "coordinates",
            "conserves_energy",
            "reference",
            "methods",
            "summary",
            "plots",
            "scene_wall_time_s",
        ],
        id,
    );
    has_keys(&scene["reference"], &["kind", "tolerance", "cartesian_tolerance", "cartesian_agreement"], id);
    let conserves_energy = scene["conserves_energy"].as_bool().expect("conserves_energy");
    let methods = scene["methods"].as_array().expect("methods");
    let names: Vec<&str> = methods.iter().map(|m| m["method"].as_str().unwrap()).collect();
    assert_eq!(names, METHODS, "{id}");
    for method in methods {
        let what = format!("{id} {}", method["method"]);
        has_keys(method, &["method", "solver", "status", "reason", "deviations", "reference", "note", "runs"], &what);
        let runs = method["runs"].as_array().expect("runs");
        match method["status"].as_str().unwrap() {
            "ok" => {
                assert!(runs.len() >= 3, "{what}: a sweep has several runs");
                for run in runs {
                    check_run(run, method["solver"].as_str().unwrap(), conserves_energy, &what);
                }
            }
            "unbuildable" => {
                assert!(method["reason"].as_str().is_some_and(|r| !r.is_empty()), "{what}: no reason");
                assert!(runs.is_empty(), "{what}");
            }
            other => panic!("{what}: status {other}"),
        }
    }
    let versus = scene["summary"]["versus"].as_array().expect("versus");
    let engines: Vec<&str> = versus.iter().map(|v| v["rapier"].as_str().unwrap()).collect();
    assert_eq!(engines, ["rapier-impulse", "rapier-multibody"], "{id}");
    for v in versus {
        check_ratio(&v["error_ratio_at_equal_time"], &format!("{id} {} equal time", v["rapier"]));
        check_ratio(&v["time_ratio_at_equal_error"], &format!("{id} {} equal error", v["rapier"]));
    }
    for plot in ["work_precision", "error"] {
        let file = dir.join(scene["plots"][plot].as_str().expect("plot file"));
        let svg = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        assert!(svg.contains("<svg") && svg.contains(id), "{}", file.display());
    }
    // The animation page, and the index page linking it.
    let page = dir.join(scene["plots"]["animation"].as_str().expect("an animation page"));
    let html = std::fs::read_to_string(&page).unwrap_or_else(|e| panic!("{}: {e}", page.display()));
    assert!(html.contains(r#"<canvas id="view""#) && html.contains(id), "{}", page.display());
    let index = std::fs::read_to_string(dir.join("index.html")).expect("index.html written");
    let link = format!(r#"<a href="{id}.html">play</a>"#);
    assert!(index.contains(&link), "index.html does not link {id}'s animation");
}

#[test]
fn quick_report_covers_the_requested_scenes_and_methods() {
    let dir = temp_dir("quick");
    let out = dir.to_str().unwrap();
    // Listed out of registry order: the report keeps registry order.
    let output =
        lagrange(&["report", "--quick", "--scene", "atwood", "--scene", "cart_pendulum", "--out", out, "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let printed: Value = serde_json::from_slice(&output.stdout).expect("--json prints report.json");
    let text = std::fs::read_to_string(dir.join("report.json")).expect("report.json written");
    let report: Value = serde_json::from_str(&text).expect("report.json parses");
    assert_eq!(printed, report);

    has_keys(
        &report,
        &[
            "schema_version",
            "generator",
            "mode",
            "horizon_s",
            "sample_interval_s",
            "samples",
            "timing",
            "targets",
            "scenes",
            "stability",
            "total_wall_time_s",
        ],
        "report",
    );
    assert_eq!(report["schema_version"], 1);
    assert_eq!(report["mode"], "quick");
    let scenes = report["scenes"].as_array().expect("scenes");
    let ids: Vec<&str> = scenes.iter().map(|s| s["scene"].as_str().unwrap()).collect();
    assert_eq!(ids, ["cart_pendulum", "atwood"]);
    for scene in scenes {
        check_scene(scene, &dir);
    }

    // The cart pendulum has no closed form: its reference is the tight reduced solution, and the
    // Cartesian solver at tol 1e-12 agrees with it to its tolerance (measured 2e-12; the
    // compare test's bound 1e-8 leaves the same margin here).
    let cart = &scenes[0];
    assert_eq!(cart["reference"]["kind"], "reduced_dop853");
    assert!(cart["reference"]["cartesian_agreement"].as_f64().is_some_and(|a| a <= 1e-8), "{}", cart["reference"]);
    // The Atwood machine's motion is closed-form; impulse joints have no pulley and say so.
    let atwood = &scenes[1];
    assert_eq!(atwood["reference"]["kind"], "closed_form");
    let impulse = atwood["methods"].as_array().unwrap().iter().find(|m| m["method"] == "rapier-impulse").unwrap();
    assert_eq!(impulse["status"], "unbuildable");
    assert!(impulse["reason"].as_str().unwrap().contains("pulley"), "{impulse}");
    let versus = &atwood["summary"]["versus"][0];
    assert_eq!(versus["status"], "unbuildable");
    assert!(versus["error_ratio_at_equal_time"]["value"].is_null(), "{versus}");

    // Errors fall along the sweeps on the cart pendulum. RK4 is fourth order: each halving of
    // dt divides the error by ≈ 16, so by more than 8 while it is well above the reference's own
    // accuracy (≈ 1e-12, so 1e-9 leaves three decades). The adaptive error tracks the
    // tolerance: it falls with every decade while above 1e-10.
    let rk4 = max_errors(cart, "rk4");
    for pair in rk4.windows(2).filter(|p| p[1] > 1e-9) {
        assert!(pair[1] < pair[0] / 8.0, "RK4 errors do not fall at order 4: {rk4:?}");
    }
    assert!(rk4.last().unwrap() < &(rk4[0] * 1e-4), "{rk4:?}");
    let adaptive = max_errors(cart, "dopri5");
    for pair in adaptive.windows(2).filter(|p| p[0] > 1e-10) {
        assert!(pair[1] < pair[0], "adaptive errors do not fall with the tolerance: {adaptive:?}");
    }
    assert!(adaptive.last().unwrap() < &(adaptive[0] * 1e-6), "{adaptive:?}");

    // With --scene, the stability section runs the cases involving those scenes only.
    let stability = check_stability(&report["stability"], "quick");
    assert_eq!(stability, ["extreme_parameters", "bad_input"]);

    let markdown = std::fs::read_to_string(dir.join("report.md")).expect("report.md written");
    for needle in [
        "## Summary",
        "## cart_pendulum",
        "## atwood",
        "not buildable",
        "cart_pendulum_work_precision.svg",
        "## Stability",
        "### extreme_parameters",
    ] {
        assert!(markdown.contains(needle), "report.md lacks `{needle}`");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every documented field of the stability section; the case ids, in order.
fn check_stability(stability: &Value, mode: &str) -> Vec<String> {
    has_keys(stability, &["mode", "cases", "passed", "failed", "unchecked", "wall_time_s"], "stability");
    assert_eq!(stability["mode"], mode);
    let cases = stability["cases"].as_array().expect("cases");
    let (mut passed, mut failed, mut unchecked) = (0, 0, 0);
    for case in cases {
        let id = case["id"].as_str().expect("case id");
        has_keys(case, &["id", "title", "scenes", "setup", "theory", "measurements", "pass", "wall_time_s"], id);
        assert!(case["setup"].as_str().is_some_and(|s| !s.is_empty()), "{id}: setup");
        assert!(case["theory"].as_str().is_some_and(|s| !s.is_empty()), "{id}: theory");
        let measurements = case["measurements"].as_array().expect("measurements");
        assert!(!measurements.is_empty(), "{id}: no measurements");
        for m in measurements {
            let what = format!("{id} {} {} {}", m["label"], m["method"], m["quantity"]);
            has_keys(
                m,
                &[
                    "label",
                    "scene",
                    "parameters",
                    "method",
                    "settings",
                    "quantity",
                    "value",
                    "theory",
                    "check",
                    "bound",
                    "pass",
                    "status",
                    "note",
                    "cost",
                ],
                &what,
            );
            has_keys(&m["settings"], &["dt", "tolerance", "substeps", "horizon_s"], &what);
            has_keys(&m["cost"], &["steps", "evaluations", "jacobians", "factorizations", "wall_time_s"], &what);
            let value = number_or_null(&m["value"], &what);
            let theory = number_or_null(&m["theory"], &what);
            let bound = number_or_null(&m["bound"], &what);
            let status = m["status"].as_str().expect("status");
            assert!(status == "ok" || status == "failed", "{what}: status {status}");
            if status == "failed" {
                assert!(m["note"].as_str().is_some_and(|n| !n.is_empty()), "{what}: a failed run says why");
            }
            // `pass` follows from the documented check.
            let expected = match m["check"].as_str().expect("check") {
                "none" => None,
                "typed_error" => Some(status == "failed"),
                "finite" => Some(status == "ok" && value.is_some()),
                "finite_or_typed_error" => Some(status == "failed" || value.is_some()),
                check => Some(match (check, value, theory, bound) {
                    (_, None, ..) => false,
                    ("relative_to_theory", Some(v), Some(t), Some(b)) => (v / t - 1.0).abs() <= b,
                    ("absolute_to_theory", Some(v), Some(t), Some(b)) => (v - t).abs() <= b,
                    ("within_factor", Some(v), Some(t), Some(b)) => v > 0.0 && t > 0.0 && (v / t).max(t / v) <= b,
                    ("at_most", Some(v), _, Some(b)) => v <= b,
                    ("at_least", Some(v), _, Some(b)) => v >= b,
                    ("exact", Some(v), Some(t), _) => v == t,
                    (other, ..) => panic!("{what}: undocumented check `{other}` or missing operands"),
                }),
            };
            assert_eq!(m["pass"].as_bool(), expected, "{what}: {m}");
            match expected {
                Some(true) => passed += 1,
                Some(false) => failed += 1,
                None => unchecked += 1,
            }
        }
        let checked: Vec<bool> = measurements.iter().filter_map(|m| m["pass"].as_bool()).collect();
        let case_pass = (!checked.is_empty()).then(|| checked.iter().all(|&p| p));
        assert_eq!(case["pass"].as_bool(), case_pass, "{id}: case verdict");
    }
    assert_eq!(
        (stability["passed"].as_u64(), stability["failed"].as_u64(), stability["unchecked"].as_u64()),
        (Some(passed), Some(failed), Some(unchecked)),
        "stability totals"
    );
    cases.iter().map(|c| c["id"].as_str().unwrap().to_string()).collect()
}

/// The measurements of `case` with this method and quantity.
fn rows<'a>(stability: &'a Value, case: &str, method: &str, quantity: &str) -> Vec<&'a Value> {
    let case = stability["cases"].as_array().unwrap().iter().find(|c| c["id"] == case).expect("case present");
    case["measurements"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["method"] == method && m["quantity"].as_str().is_some_and(|q| q.starts_with(quantity)))
        .collect()
}

#[test]
fn quick_report_measures_stability_limits_against_theory() {
    let dir = temp_dir("stability");
    let out = dir.to_str().unwrap();
    let output = lagrange(&["report", "--quick", "--scene", "harmonic_oscillator", "--out", out, "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let report: Value = serde_json::from_slice(&output.stdout).expect("--json prints report.json");
    let stability = &report["stability"];
    let ids = check_stability(stability, "quick");
    assert_eq!(ids, ["stiff_spring", "stiff_damped", "long_run", "rapier_long_run", "bad_input"]);
    // RK4's limit on the undamped oscillator is the imaginary-axis boundary 2√2 (to 1 %, which
    // also tells it from the real-axis 2.785), on the damped one the real-axis boundary;
    // rapier's is symplectic Euler's 2.
    let limit = "stability limit";
    for (case, method, theory) in [
        ("stiff_spring", "rk4", 2.0 * std::f64::consts::SQRT_2),
        ("stiff_damped", "rk4", 2.785_293_563_405_282),
        ("stiff_spring", "rapier-impulse", 2.0),
        ("stiff_spring", "rapier-multibody", 2.0),
    ] {
        let found = rows(stability, case, method, limit);
        assert!(!found.is_empty(), "{case} {method}: no limit measured");
        for m in found {
            assert_eq!(m["check"], "relative_to_theory", "{m}");
            assert!((m["theory"].as_f64().unwrap() / theory - 1.0).abs() < 1e-12, "{m}");
            let value = m["value"].as_f64().expect("measured");
            assert!((value / theory - 1.0).abs() <= 0.01, "{case} {method}: {value} vs {theory}");
            assert_eq!(m["pass"], true, "{m}");
        }
    }
    // The stiff damped oscillator: the explicit adaptive method is pinned to its stability
    // boundary and detects stiffness; the L-stable method takes orders of magnitude fewer steps.
    let explicit = rows(stability, "stiff_damped", "dopri5", "mean step");
    let implicit = rows(stability, "stiff_damped", "sdirk4", "mean step");
    assert_eq!((explicit.len(), implicit.len()), (3, 3));
    for (e, i) in explicit.iter().zip(&implicit) {
        assert!(e["note"].as_str().unwrap().contains("stiffness detected"), "{e}");
        let (e_steps, i_steps) = (e["cost"]["steps"].as_u64().unwrap(), i["cost"]["steps"].as_u64().unwrap());
        assert!(i_steps * 100 < e_steps, "implicit {i_steps} vs explicit {e_steps} steps");
    }
    let markdown = std::fs::read_to_string(dir.join("report.md")).expect("report.md written");
    for needle in ["## Stability", "### stiff_spring", "### stiff_damped", "2√2"] {
        assert!(markdown.contains(needle), "report.md lacks `{needle}`");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_report_arguments_are_one_line_errors() {
    let dir = temp_dir("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("a-file");
    std::fs::write(&file, "not a directory").unwrap();
    let out = dir.join("unused");
    let out = out.to_str().unwrap();
    assert_one_line_error(&["report", "--quick", "--scene", "pendulum", "--out", out], "unknown scene `pendulum`");
    assert_one_line_error(&["report", "--quick", "--scene", "atwood", "--out", file.to_str().unwrap()], "--out");
    let below_a_file = file.join("report");
    assert_one_line_error(
        &["report", "--quick", "--scene", "atwood", "--out", below_a_file.to_str().unwrap()],
        "--out",
    );
    assert_one_line_error(&["report", "--quick", "--t-end", "0.07", "--out", out], "--t-end");
    assert_one_line_error(&["report", "--quick", "--t-end", "-1", "--out", out], "--t-end");
    assert_one_line_error(&["report", "--frobnicate"], "--frobnicate");
    assert_one_line_error(&["report", "--quick", "--jobs", "0", "--out", out], "--jobs must be positive");
    // Nothing ran, so nothing was written.
    assert!(!Path::new(out).join("report.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every run's errors, steps and status, in order (the fields that do not depend on timing).
fn measurements(report: &Value) -> Vec<String> {
    let mut out = Vec::new();
    for scene in report["scenes"].as_array().expect("scenes") {
        for method in scene["methods"].as_array().expect("methods") {
            for run in method["runs"].as_array().expect("runs") {
                let fields = ["status", "max_error", "final_error", "energy_error", "constraint_violation", "steps"];
                out.push(format!("{} {} {:?}", scene["scene"], method["method"], fields.map(|f| run[f].to_string())));
            }
        }
    }
    out
}

#[test]
fn the_number_of_jobs_changes_no_result() {
    // Two scenes on one thread and on two: every error, step count and status to the bit.
    let run = |jobs: &str| {
        let dir = temp_dir(&format!("jobs-{jobs}"));
        let out = dir.to_str().unwrap().to_string();
        let args =
            ["report", "--quick", "--scene", "double_pendulum", "--scene", "four_bar", "--jobs", jobs, "--out", &out];
        let output = lagrange(&args);
        assert!(output.status.success(), "{}", stderr(&output));
        let report: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        measurements(&report)
    };
    let (serial, parallel) = (run("1"), run("2"));
    assert!(serial.len() > 40, "{} runs", serial.len());
    assert_eq!(serial, parallel);
}
