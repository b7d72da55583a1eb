//! Scene files through the command line: `eom` against golden files, a joint-graph file the
//! project does not ship (a Watt six-bar with a spring) through `compare --engine all` and
//! `report --scene`, and a malformed file's error.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn lagrange(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lagrange")).args(args).current_dir(workspace()).output().expect("the binary runs")
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The lecture's scenes, and three joint graphs, printed by `lagrange eom` exactly as the golden
/// files under tests/golden/eom say (`UPDATE_GOLDEN=1` rewrites them; review the diff).
#[test]
fn eom_prints_the_golden_equations() {
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/eom");
    for scene in [
        "cart_pendulum",
        "atwood",
        "double_pendulum",
        "wedge",
        "driven_pendulum",
        "nonminimal_pendulum",
        "rolling_disc",
        "kepler",
        "spring_pendulum",
        "four_bar.graph",
        "slider_crank.graph",
        "wedge.graph",
    ] {
        let file = format!("examples/scenes/{scene}.toml");
        let out = lagrange(&["eom", &file]);
        assert!(out.status.success(), "{scene}: {}", text(&out.stderr));
        let printed = text(&out.stdout);
        let path = golden.join(format!("{scene}.txt"));
        if std::env::var_os("UPDATE_GOLDEN").is_some() {
            std::fs::write(&path, &printed).unwrap();
        }
        let expected = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(printed, expected, "{scene}: `lagrange eom {file}` differs from {}", path.display());
    }
}

#[test]
fn eom_prints_the_lectures_forms() {
    let out = text(&lagrange(&["eom", "examples/scenes/cart_pendulum.toml"]).stdout);
    // Dots are combining characters (X + U+0307), never a precomposed letter.
    assert!(out.contains("T = ½ (M + m) X\u{307}² + m r X\u{307} θ\u{307} cos θ + ½ m r² θ\u{307}²"), "{out}");
    // A spring's energy as a completed square, its force factored.
    let out = text(&lagrange(&["eom", "examples/scenes/spring_pendulum.toml"]).stdout);
    assert!(out.contains("V = −m g r cos θ + ½ k (r − L₀)²"), "{out}");
    assert!(out.contains("m r̈ = m r θ̇² + m g cos θ − k (r − L₀)"), "{out}");
    let out = text(&lagrange(&["eom", "examples/scenes/atwood.toml"]).stdout);
    assert!(out.contains("(m₁ + m₂ + I/a²) x\u{308} = (m₁ − m₂) g"), "{out}");
    let json: serde_json::Value =
        serde_json::from_slice(&lagrange(&["eom", "examples/scenes/atwood.toml", "--json"]).stdout).unwrap();
    assert_eq!(json["equations"][0]["right"]["plain"], "(m1 - m2)*g");
    let latex = text(&lagrange(&["eom", "examples/scenes/atwood.toml", "--latex"]).stdout);
    assert!(latex.starts_with("\\begin{align*}"), "{latex}");
    // A joint graph, as a file or a built-in id: its coordinates, the poses they give, and the
    // equations of the coordinates form.
    for arg in ["examples/scenes/four_bar.graph.toml", "four_bar"] {
        let out = lagrange(&["eom", arg]);
        assert!(out.status.success(), "{arg}: {}", text(&out.stderr));
        let printed = text(&out.stdout);
        assert!(
            printed.contains("coupler:  x = cos θ₂/5 + 3 cos θ₃/10,  y = sin θ₂/5 + 3 sin θ₃/10,  φ = θ₃"),
            "{printed}"
        );
        assert!(printed.contains("B (x) (λ₁):  −½ + cos θ₂/5 + 3 cos θ₃/5 − ½ cos θ₄ = 0"), "{printed}");
    }
    // A built-in scene written in Rust: exit 2, naming its file.
    let out = lagrange(&["eom", "kepler"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("examples/scenes/kepler.toml"), "{}", text(&out.stderr));
}

#[test]
fn a_joint_graph_file_the_project_does_not_ship_is_compared_and_reported() {
    let out = lagrange(&["compare", "tests/files/watt_six_bar.toml", "--engine", "all", "--t-end", "1", "--json"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = table["rows"].as_array().expect("rows");
    let engines: Vec<&str> = rows.iter().filter_map(|r| r["engine"].as_str()).collect();
    for engine in ["cartesian", "rapier-impulse", "rapier-multibody", "rapier-impulse-f32", "rapier-multibody-f32"] {
        assert!(engines.contains(&engine), "{engines:?}");
    }
    // The independent Cartesian model (tol 1e-12) agrees with the reduced one: 1e-9 leaves
    // a factor of 1e3 for the growth of its error over the second (measured 7e-14).
    let cartesian = rows.iter().find(|r| r["engine"] == "cartesian").unwrap();
    assert!(cartesian["max_error"].as_f64().unwrap() < 1e-9, "{cartesian}");

    let described = text(&lagrange(&["scenes", "--describe", "tests/files/watt_six_bar.toml"]).stdout);
    assert!(described.contains("constraints: 4 holonomic, 0 velocity"), "{described}");
    assert!(described.contains("joint graph: 5 bodies, 7 joints (2 marked closing)"), "{described}");
    assert!(described.contains("spanning tree: O2, A, O4, C, E; loop-closing: B, D"), "{described}");
    let described = text(&lagrange(&["scenes", "--describe", "examples/scenes/kepler.toml"]).stdout);
    assert!(described.contains("M(q) assembled") && described.contains("region: r above 0"), "{described}");
    let described = text(&lagrange(&["scenes", "--describe", "double_pendulum"]).stdout);
    assert!(described.contains("q̈ by the articulated-body algorithm"), "{described}");

    let out_dir = std::env::temp_dir().join(format!("lagrange-watt-report-{}", std::process::id()));
    let out = lagrange(&[
        "report",
        "--quick",
        "--scene",
        "tests/files/watt_six_bar.toml",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("report.json")).unwrap()).unwrap();
    assert!(report.to_string().contains("watt_six_bar"));
    let _ = std::fs::remove_dir_all(&out_dir);
}

#[test]
fn a_malformed_file_is_drawn_on_its_text_and_exits_2() {
    let out = lagrange(&["simulate", "tests/files/bad/unknown_name.toml", "--t-end", "1"]);
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(err.contains("error: unknown name `thta`"), "{err}");
    assert!(err.contains("tests/files/bad/unknown_name.toml:24:13"), "{err}");
    assert!(err.contains("help: did you mean `theta`?"), "{err}");
    assert!(text(&out.stdout).is_empty());
}

/// `scenes --export ID --form coordinates` writes a joint graph in the coordinates form: a file
/// every command reads, whose accelerations are the graph's.
#[test]
fn a_joint_graph_exports_in_the_coordinates_form() {
    let out = lagrange(&["scenes", "--export", "slider_crank", "--form", "coordinates"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let written = text(&out.stdout);
    assert!(written.contains("residual = \"0.1*cos(φ) + 0.4*cos(ψ) - x\""), "{written}");
    let path = std::env::temp_dir().join(format!("lagrange-slider-crank-{}.toml", std::process::id()));
    std::fs::write(&path, &written).unwrap();
    let accel = |scene: &str| -> serde_json::Value {
        let out = lagrange(&["accel", scene, "--json"]);
        assert!(out.status.success(), "{scene}: {}", text(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let (file, graph) = (accel(path.to_str().unwrap()), accel("slider_crank"));
    let values = |v: &serde_json::Value| -> Vec<f64> {
        v["qddot"].as_array().expect("q̈").iter().map(|x| x.as_f64().unwrap()).collect()
    };
    // The same equations evaluated two ways: round-off (1e-12 relative, as tests/checks/files.rs).
    for (a, b) in values(&file).iter().zip(values(&graph)) {
        assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{file} vs {graph}");
    }
    let _ = std::fs::remove_file(&path);
    // A graph whose motion starts later: its equations print (they do not depend on the start);
    // its coordinates form, which starts at t = 0, is refused with the reason.
    let late = std::fs::read_to_string(workspace().join("examples/scenes/four_bar.graph.toml"))
        .unwrap()
        .replace("\nt = 0.0\n", "\nt = 2.5\n")
        .replace("id = \"four_bar_graph\"", "id = \"late_four_bar\"");
    let path = std::env::temp_dir().join(format!("lagrange-late-four-bar-{}.toml", std::process::id()));
    std::fs::write(&path, late).unwrap();
    let out = lagrange(&["eom", path.to_str().unwrap()]);
    assert!(out.status.success() && text(&out.stdout).contains("B (x) (λ₁)"), "{}", text(&out.stderr));
    let out = lagrange(&["scenes", "--export", path.to_str().unwrap(), "--form", "coordinates"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("starts its motion at t = 0"), "{}", text(&out.stderr));
    let _ = std::fs::remove_file(&path);
    // A scene written in Rust has no graph to export.
    assert_eq!(lagrange(&["scenes", "--export", "kepler", "--form", "coordinates"]).status.code(), Some(2));
}
