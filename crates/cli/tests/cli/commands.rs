//! The `lagrange` command as a user runs it: outputs, exit codes, one-line errors.

use super::{assert_one_line_error, lagrange, stderr, stdout};

#[test]
fn scenes_lists_every_scene_with_coordinates_and_symbols() {
    let output = lagrange(&["scenes", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let scenes: serde_json::Value = serde_json::from_str(&stdout(&output)).expect("valid JSON");
    let ids: Vec<&str> = scenes.as_array().expect("a list").iter().map(|s| s["id"].as_str().expect("id")).collect();
    for id in [
        "cart_pendulum",
        "harmonic_oscillator",
        "kepler",
        "isotropic_oscillator",
        "atwood",
        "double_atwood",
        "double_double_atwood",
        "wedge",
        "double_pendulum",
        "chain",
    ] {
        assert!(ids.contains(&id), "{id} missing from {ids:?}");
    }
    let wedge = scenes.as_array().unwrap().iter().find(|s| s["id"] == "wedge").unwrap();
    let symbols: Vec<&str> =
        wedge["parameters"].as_array().unwrap().iter().map(|p| p["symbol"].as_str().unwrap()).collect();
    assert!(symbols.contains(&"α") && symbols.contains(&"M") && symbols.contains(&"g"), "{symbols:?}");
    let double = scenes.as_array().unwrap().iter().find(|s| s["id"] == "double_atwood").unwrap();
    let symbols: Vec<&str> =
        double["parameters"].as_array().unwrap().iter().map(|p| p["symbol"].as_str().unwrap()).collect();
    assert!(symbols.contains(&"l'") && symbols.contains(&"m1"), "{symbols:?}");
    assert!(lagrange(&["scenes"]).status.success());
}

#[test]
fn accel_prints_the_closed_form_value_to_full_precision() {
    // Wedge, docs/scenes.md#wedge: ẍ' = (M + m) g sin α / (M + m sin²α) with M = 3, m = 1, α = 0.5.
    let output = lagrange(&["accel", "wedge", "--param", "α=0.5", "--q", "0,0", "--qdot", "0,0", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let out: serde_json::Value = serde_json::from_str(&stdout(&output)).expect("valid JSON");
    let got = out["qddot"][1].as_f64().expect("a number");
    let (big, m, g, a) = (3.0_f64, 1.0_f64, 9.81_f64, 0.5_f64);
    let expected = (big + m) * g * a.sin() / (big + m * a.sin().powi(2));
    assert!((got - expected).abs() <= 1e-14 * expected, "{got} vs {expected}");
    // By name as well as by symbol, and in text form.
    let text = lagrange(&["accel", "wedge", "--param", "angle=0.5", "--q", "0,0", "--qdot", "0,0"]);
    assert!(stdout(&text).contains(&format!("{:?}", got)), "{}", stdout(&text));
}

#[test]
fn simulate_writes_csv_with_time_coordinates_velocities_and_energy() {
    let output = lagrange(&[
        "simulate",
        "cart_pendulum",
        "--t-end",
        "1",
        "--integrator",
        "rk4",
        "--dt",
        "0.001",
        "--every",
        "0.25",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t [s],X [m],θ [rad],X_dot [m/s],θ_dot [rad/s],h [J]"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().expect("number")).collect()).collect();
    assert_eq!(rows.len(), 5);
    assert_eq!(rows.iter().map(|r| r[0]).collect::<Vec<_>>(), vec![0.0, 0.25, 0.5, 0.75, 1.0]);
    // RK4 at dt = 1e-3 conserves the energy to ~1e-12 relative over 1 s.
    let e0 = rows[0][5];
    assert!(rows.iter().all(|r| (r[5] - e0).abs() <= 1e-9 * e0.abs()), "{rows:?}");
    let dir = std::env::temp_dir().join(format!("lagrange-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("run.csv");
    let output = lagrange(&[
        "simulate",
        "kepler",
        "--t-end",
        "2",
        "--integrator",
        "variational",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(std::fs::read_to_string(&file).unwrap().starts_with("t [s],r [m],θ [rad],r_dot [m/s],θ_dot [rad/s],h [J]"));
}

#[test]
fn simulate_with_the_implicit_and_gauss_integrators_and_a_stiffness_warning() {
    // A strongly damped oscillator (c = 1e4, k = 1: eigenvalues ≈ −1e4 and −1e-4) is stiff:
    // the explicit adaptive integrator warns once, the implicit one takes few steps silently.
    let stiff = ["simulate", "harmonic_oscillator", "--param", "c=1e4", "--param", "k=1", "--q", "1", "--t-end", "1"];
    let explicit = lagrange(&[&stiff[..], &["--integrator", "dopri5", "--tol", "1e-6"]].concat());
    assert!(explicit.status.success(), "{}", stderr(&explicit));
    let warning = stderr(&explicit);
    assert_eq!(warning.trim_end().lines().count(), 1, "{warning}");
    assert!(warning.starts_with("warning: the problem looks stiff from t = "), "{warning}");
    assert!(warning.contains("--integrator sdirk4"), "{warning}");
    // SDIRK4 and Gauss4 by their former names (`implicit`, `gauss`), which the CLI still reads.
    let implicit = lagrange(&[&stiff[..], &["--integrator", "implicit", "--tol", "1e-6", "--every", "0.5"]].concat());
    assert!(implicit.status.success(), "{}", stderr(&implicit));
    assert!(stderr(&implicit).is_empty(), "{}", stderr(&implicit));
    let text = stdout(&implicit);
    let rows: Vec<Vec<f64>> =
        text.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().expect("number")).collect()).collect();
    assert_eq!(rows.iter().map(|r| r[0]).collect::<Vec<_>>(), vec![0.0, 0.5, 1.0]);
    // Exactly x = (r₂ e^{r₁t} − r₁ e^{r₂t})/(r₂ − r₁), r = (−c ± √(c² − 4k))/2, within the tolerance.
    let root = (1e8_f64 - 4.0).sqrt();
    let (slow, fast) = ((-1e4 + root) / 2.0, (-1e4 - root) / 2.0);
    for row in &rows {
        let expected = (fast * (slow * row[0]).exp() - slow * (fast * row[0]).exp()) / (fast - slow);
        assert!((row[1] - expected).abs() <= 1e-6, "{row:?} vs {expected}");
    }
    // Gauss–Legendre with a fixed step on the cart pendulum: the energy stays put.
    let gauss = lagrange(&[
        "simulate",
        "cart_pendulum",
        "--t-end",
        "1",
        "--integrator",
        "gauss",
        "--dt",
        "0.01",
        "--every",
        "0.25",
    ]);
    assert!(gauss.status.success(), "{}", stderr(&gauss));
    let rows: Vec<Vec<f64>> =
        stdout(&gauss).lines().skip(1).map(|l| l.split(',').map(|v| v.parse().expect("number")).collect()).collect();
    assert_eq!(rows.len(), 5);
    // Order 4 at h = 0.01: energy error ~(h ω)⁴ ~ 1e-8 at most, bounded (symplectic).
    let e0 = rows[0][5];
    assert!(rows.iter().all(|r| (r[5] - e0).abs() <= 1e-6 * e0.abs()), "{rows:?}");
    // Each integrator takes only its own setting.
    assert_one_line_error(&["simulate", "wedge", "--t-end", "1", "--integrator", "sdirk4", "--dt", "0.1"], "--dt");
    assert_one_line_error(&["simulate", "wedge", "--t-end", "1", "--integrator", "gauss4", "--tol", "1e-6"], "--tol");
}

#[test]
fn wrong_scene_parameter_arity_or_value_is_a_one_line_error() {
    assert_one_line_error(&["accel", "pendulum", "--q", "0", "--qdot", "0"], "unknown scene `pendulum`");
    assert_one_line_error(&["accel", "wedge", "--param", "mass=2", "--q", "0,0", "--qdot", "0,0"], "mass");
    assert_one_line_error(&["accel", "wedge", "--param", "m=-2", "--q", "0,0", "--qdot", "0,0"], "block_mass");
    assert_one_line_error(&["accel", "wedge", "--param", "m=abc", "--q", "0,0", "--qdot", "0,0"], "abc");
    assert_one_line_error(&["accel", "wedge", "--q", "0,0,0", "--qdot", "0,0"], "--q needs 2 values");
    assert_one_line_error(&["accel", "wedge", "--q", "0,x", "--qdot", "0,0"], "`x` is not a number");
    assert_one_line_error(&["simulate", "wedge", "--t-end", "1", "--integrator", "rk4", "--dt", "0"], "--dt");
    assert_one_line_error(&["simulate", "wedge", "--t-end", "1", "--integrator", "rk4", "--tol", "1e-6"], "--tol");
    assert_one_line_error(&["simulate", "wedge", "--t-end", "-1"], "--t-end");
    // `accel wedge` alone runs from the default state; a flag without its value is an error.
    assert_one_line_error(&["accel", "wedge", "--q"], "--q");
    assert_one_line_error(&["frobnicate"], "frobnicate");
}

#[test]
fn compare_reports_every_engine_or_why_it_cannot_build_the_scene() {
    let output = lagrange(&["compare", "atwood", "--t-end", "1", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let json: serde_json::Value = serde_json::from_str(&stdout(&output)).expect("valid JSON");
    let rows = json["rows"].as_array().expect("a list of rows");
    assert_eq!(rows.len(), 5, "{rows:?}");
    for row in rows {
        let unbuildable = row["unbuildable"].as_str();
        let error = row["max_error"].as_f64();
        assert!(unbuildable.is_some() != error.is_some(), "{row}");
    }
    // The Cartesian formulation agrees with the reduced solver to its tolerance; the impulse
    // joints cannot express a pulley and say so.
    let cartesian = rows.iter().find(|r| r["engine"] == "cartesian").expect("cartesian row");
    assert!(cartesian["max_error"].as_f64().expect("built") <= 1e-8, "{cartesian}");
    let impulse = rows.iter().find(|r| r["engine"] == "rapier-impulse").expect("impulse row");
    assert!(impulse["unbuildable"].as_str().is_some_and(|r| r.contains("pulley")), "{impulse}");
    assert_one_line_error(&["compare", "atwood", "--engine", "bullet"], "unknown engine `bullet`");
}

#[test]
fn a_bad_argument_exits_2_and_a_failure_at_run_time_exits_1() {
    let code = |args: &[&str]| {
        let output = lagrange(args);
        let err = stderr(&output);
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: not one line: {err}");
        (output.status.code(), err)
    };
    // Usage errors: clap's own, the CLI's bad argument values, and a value the engine rejects.
    let (status, err) = code(&["accel", "wedge", "--q", "0,x", "--qdot", "0,0"]);
    assert_eq!(status, Some(2), "{err}");
    assert!(err.starts_with("error: --q: `x` is not a number"), "{err}");
    assert_eq!(code(&["frobnicate"]).0, Some(2));
    let (status, err) = code(&["simulate", "kepler", "--t-end", "1", "--tol", "0"]);
    assert_eq!(status, Some(2), "{err}");
    assert!(err.contains("invalid tolerance = 0"), "{err}");
    // A valid request the engine cannot carry out: a double pendulum whose upper bob weighs
    // 1e-12 kg has a mass matrix singular to round-off, a typed engine error naming the coordinate.
    let (status, err) = code(&["accel", "double_pendulum", "--param", "m1=1e-12"]);
    assert_eq!(status, Some(1), "{err}");
    assert!(err.starts_with("error: singular mass matrix") && err.contains("`θ1`"), "{err}");
    // A state outside the scene's admissible region: Kepler at r = 0.
    let (status, err) = code(&["accel", "kepler", "--q", "0,0", "--qdot", "0,0"]);
    assert_eq!(status, Some(1), "{err}");
    assert_eq!(err.trim_end(), "error: r = 0 is outside the admissible region r > 0 at t = 0 s");
    // A file that cannot be written is a failure at run time too, naming the path.
    let missing = std::env::temp_dir().join(format!("lagrange-cli-missing-{}", std::process::id())).join("run.csv");
    let (status, err) = code(&["simulate", "kepler", "--t-end", "1", "--out", missing.to_str().unwrap()]);
    assert_eq!(status, Some(1), "{err}");
    assert!(err.contains(&format!("cannot write {}", missing.display())), "{err}");
}

/// `lagrange modes`: the cart pendulum's frequency and zero mode, a file's modes, JSON, and a
/// mechanism that cannot rest refused with exit 1.
#[test]
fn modes_prints_frequencies_and_refuses_what_cannot_rest() {
    let out = lagrange(&["modes", "cart_pendulum"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let printed = stdout(&out);
    assert!(printed.contains("zero mode: a free motion along X, a cyclic coordinate"), "{printed}");
    // ω² = g (M + m)/(M r) = 9.81 · 3/2 at the defaults.
    let json: serde_json::Value =
        serde_json::from_slice(&lagrange(&["modes", "cart_pendulum", "--json"]).stdout).unwrap();
    let omega = json["modes"][1]["omega"].as_f64().unwrap();
    assert!((omega - (9.81_f64 * 3.0 / 2.0).sqrt()).abs() < 1e-12, "{json}");
    let out = lagrange(&["modes", concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/scenes/spring_pendulum.toml")]);
    assert!(stdout(&out).contains("ω = 10 rad/s"), "{}", stdout(&out));
    let out = lagrange(&["modes", "kepler"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("no equilibrium near q = [1, 0]"), "{}", stderr(&out));
}

#[test]
fn animate_writes_one_self_contained_page() {
    let dir = std::env::temp_dir().join(format!("lagrange-cli-animate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let page = dir.join("atwood.html");
    let output = lagrange(&["animate", "atwood", "--t-end", "1", "--out", page.to_str().expect("a UTF-8 path")]);
    assert!(output.status.success(), "{}", stderr(&output));
    let err = stderr(&output);
    // What was drawn, and why the impulse builds have no frames.
    assert!(err.contains("301 frames over 1 s; reduced, cartesian, rapier-multibody, rapier-multibody-f32"), "{err}");
    assert!(err.contains("rapier-impulse: no frames: joint `rope to m2` is coupled"), "{err}");
    let html = std::fs::read_to_string(&page).expect("the page is written");
    assert!(html.starts_with("<!DOCTYPE html>") && html.contains(r#"<canvas id="view""#));
    assert!(!html.contains("http://") && !html.contains("https://") && !html.contains(" src="), "fetches nothing");
    std::fs::remove_dir_all(&dir).expect("cleaned up");
}

#[test]
fn animate_refuses_what_it_cannot_draw() {
    assert_one_line_error(&["animate", "four_bar", "--engine", "bullet"], "unknown engine `bullet`");
    assert_one_line_error(&["animate", "four_bar", "--t-end", "-1"], "--t-end must be positive");
    // The cart's free translation is mode 0 (ω = 0); the upright four-bar's one mode is unstable;
    // Kepler has no equilibrium.
    assert_one_line_error(&["animate", "cart_pendulum", "--mode", "0"], "mode 0: is a zero mode");
    assert_one_line_error(&["animate", "four_bar", "--mode", "0"], "is unstable");
    assert_one_line_error(&["animate", "kepler", "--mode", "0"], "no equilibrium near");
    assert_one_line_error(&["animate", "cart_pendulum", "--mode", "7"], "has 2 modes");
}

#[test]
fn compare_gives_the_same_rows_on_one_thread_and_on_several() {
    let run = |jobs: &str| {
        let output = lagrange(&["compare", "double_pendulum", "--t-end", "1", "--jobs", jobs, "--json"]);
        assert!(output.status.success(), "{}", stderr(&output));
        let mut table: serde_json::Value = serde_json::from_str(&stdout(&output)).expect("valid JSON");
        // Everything but the wall time per step.
        for row in table["rows"].as_array_mut().expect("rows") {
            row.as_object_mut().expect("a row").remove("microseconds_per_step");
        }
        table
    };
    let serial = run("1");
    assert_eq!(serial["rows"].as_array().map(Vec::len), Some(5));
    assert_eq!(serial, run("3"));
    assert_one_line_error(&["compare", "double_pendulum", "--jobs", "0"], "--jobs must be positive");
}
