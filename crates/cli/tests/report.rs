//! `lagrange report` as a user runs it: the files it writes, the documented fields of
//! report.json (crates/cli/REPORT_SCHEMA.md), errors that fall along the sweeps, and one-line
//! errors for bad arguments.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn lagrange(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lagrange")).args(args).output().expect("the binary runs")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A fresh directory under the system's temporary directory.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lagrange-report-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// A failing command: non-zero exit, one line on stderr that mentions `needle`.
fn assert_one_line_error(args: &[&str], needle: &str) {
    let output = lagrange(args);
    let err = stderr(&output);
    assert!(!output.status.success(), "{args:?} succeeded");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: not one line: {err}");
    assert!(err.contains(needle), "{args:?}: `{err}` does not mention `{needle}`");
}

const METHODS: [&str; 8] = [
    "rk4",
    "adaptive",
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
    assert_eq!(cart["reference"]["kind"], "reduced_adaptive");
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
    let adaptive = max_errors(cart, "adaptive");
    for pair in adaptive.windows(2).filter(|p| p[0] > 1e-10) {
        assert!(pair[1] < pair[0], "adaptive errors do not fall with the tolerance: {adaptive:?}");
    }
    assert!(adaptive.last().unwrap() < &(adaptive[0] * 1e-6), "{adaptive:?}");

    let markdown = std::fs::read_to_string(dir.join("report.md")).expect("report.md written");
    for needle in ["## Summary", "## cart_pendulum", "## atwood", "not buildable", "cart_pendulum_work_precision.svg"] {
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
    // Nothing ran, so nothing was written.
    assert!(!Path::new(out).join("report.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
