//! What `lagrange` writes, as a user reads it: Markdown tables whose rows keep their columns,
//! JSON that matches its documentation (docs/cli-json.md), a CSV header with units, warnings
//! on energy drift, refusals of absurd requests, and output files that are never left half
//! written.

use super::{lagrange, stderr, stdout};
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh directory under the system's temporary directory.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lagrange-outputs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temporary directory");
    dir
}

/// The repository's root (two levels above this crate).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The cells of one Markdown table row: split on every `|` not escaped as `\|`, without the
/// row's leading and trailing pipes.
fn cells(row: &str) -> Vec<String> {
    let row = row.trim();
    let mut cells = Vec::new();
    let mut cell = String::new();
    let mut chars = row.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                cell.push('|');
                chars.next();
            }
            '|' => cells.push(std::mem::take(&mut cell)),
            c => cell.push(c),
        }
    }
    cells.push(cell);
    // A row starts and ends with a pipe: drop the empty pieces outside them.
    if row.starts_with('|') {
        cells.remove(0);
    }
    if row.ends_with('|') && !row.ends_with("\\|") {
        cells.pop();
    }
    cells
}

/// One Markdown table: the line number of its header, the header's cells, and its other rows
/// with their line numbers.
type Table = (usize, Vec<String>, Vec<(usize, String)>);

/// Every table of a Markdown document: a run of lines starting with `|`, the first its header.
fn tables(markdown: &str) -> Vec<Table> {
    let mut tables = Vec::new();
    let mut current: Option<Table> = None;
    let mut in_code = false;
    for (index, line) in markdown.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
        }
        if !in_code && line.trim_start().starts_with('|') {
            match &mut current {
                Some((_, _, rows)) => rows.push((index + 1, line.to_string())),
                None => current = Some((index + 1, cells(line), Vec::new())),
            }
        } else if let Some(table) = current.take() {
            tables.push(table);
        }
    }
    tables.extend(current);
    tables
}

/// Every row of every table has its header's number of cells.
fn assert_tables_keep_their_columns(markdown: &str, what: &str) -> usize {
    let tables = tables(markdown);
    let mut rows = 0;
    for (line, header, body) in &tables {
        for (number, row) in body {
            assert_eq!(
                cells(row).len(),
                header.len(),
                "{what}, line {number}: {} cells under the {}-cell header of line {line}: {row}",
                cells(row).len(),
                header.len()
            );
            rows += 1;
        }
    }
    rows
}

#[test]
fn markdown_cells_split_on_unescaped_pipes_only() {
    assert_eq!(cells("| a | b |"), [" a ", " b "]);
    assert_eq!(cells("| `\\|λ\\| dt` | b |"), [" `|λ| dt` ", " b "]);
    assert_eq!(cells("| a | `|λ| dt` |").len(), 4);
    assert_eq!(cells("| a | b ||||").len(), 5);
}

#[test]
fn every_table_row_of_the_report_has_its_headers_cells() {
    // The harmonic oscillator's stability cases name `|λ| dt` in their quantities and labels.
    let dir = temp_dir("report");
    let out = dir.to_str().unwrap();
    let output = lagrange(&["report", "--quick", "--scene", "harmonic_oscillator", "--out", out]);
    assert!(output.status.success(), "{}", stderr(&output));
    let markdown = std::fs::read_to_string(dir.join("report.md")).expect("report.md written");
    assert!(markdown.contains("\\|λ\\| dt"), "the report no longer names |λ| dt: the test checks nothing");
    let rows = assert_tables_keep_their_columns(&markdown, "report.md");
    assert!(rows > 50, "only {rows} table rows in report.md");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_table_row_of_the_documentation_has_its_headers_cells() {
    for doc in ["crates/cli/REPORT_SCHEMA.md", "docs/cli-json.md"] {
        let markdown = std::fs::read_to_string(root().join(doc)).unwrap_or_else(|e| panic!("{doc}: {e}"));
        assert!(assert_tables_keep_their_columns(&markdown, doc) > 0, "{doc} has no table");
    }
}

/// The field paths that docs/cli-json.md lists in the table of the section `## {command}`.
fn documented_fields(command: &str) -> BTreeSet<String> {
    let doc = std::fs::read_to_string(root().join("docs/cli-json.md")).expect("docs/cli-json.md");
    let section = doc
        .split("\n## ")
        .find(|s| s.lines().next() == Some(command))
        .unwrap_or_else(|| panic!("docs/cli-json.md has no section `## {command}`"));
    let (_, header, rows) = tables(section).into_iter().next().expect("a field table");
    assert_eq!(header[0].trim(), "field", "{command}: the first column names the fields");
    rows.iter()
        .map(|(_, row)| cells(row)[0].trim().to_string())
        .filter(|first| !first.starts_with("---"))
        .map(|first| first.trim_matches('`').to_string())
        .collect()
}

/// The field paths of `value` (`a`, `a[].b`), descending into an object or an array of objects
/// where the documentation lists fields below it.
fn fields(value: &Value, prefix: &str, documented: &BTreeSet<String>, found: &mut BTreeSet<String>) {
    let below = |path: &str| documented.iter().any(|d| d.starts_with(path));
    match value {
        Value::Object(object) => {
            for (key, value) in object {
                let path = format!("{prefix}{key}");
                found.insert(path.clone());
                if value.is_object() && below(&format!("{path}.")) {
                    fields(value, &format!("{path}."), documented, found);
                }
                if let Value::Array(items) = value
                    && below(&format!("{path}[]."))
                {
                    for item in items {
                        fields(item, &format!("{path}[]."), documented, found);
                    }
                }
            }
        }
        Value::Array(items) => {
            for item in items {
                fields(item, prefix, documented, found);
            }
        }
        _ => {}
    }
}

/// A command's JSON has exactly the documented fields.
fn assert_documented(command: &str, args: &[&str]) -> Value {
    let output = lagrange(args);
    assert!(output.status.success(), "{args:?}: {}", stderr(&output));
    let json: Value = serde_json::from_str(&stdout(&output)).expect("valid JSON");
    let documented = documented_fields(command);
    let mut found = BTreeSet::new();
    fields(&json, "", &documented, &mut found);
    let undocumented: Vec<&String> = found.difference(&documented).collect();
    let missing: Vec<&String> = documented.difference(&found).collect();
    assert!(undocumented.is_empty(), "{args:?} prints fields docs/cli-json.md does not list: {undocumented:?}");
    assert!(missing.is_empty(), "docs/cli-json.md lists fields {args:?} does not print: {missing:?}");
    json
}

#[test]
fn the_json_of_scenes_accel_compare_and_modes_is_documented_field_by_field() {
    assert_documented("scenes", &["scenes", "--json"]);
    assert_documented("accel", &["accel", "wedge", "--q", "0,0", "--qdot", "0,0", "--json"]);
    // One engine that builds the scene and one that does not: every row field appears.
    let json = assert_documented("compare", &["compare", "atwood", "--t-end", "0.5", "--json"]);
    let rows = json["rows"].as_array().expect("rows");
    assert!(rows.iter().any(|r| r["unbuildable"].is_string()) && rows.iter().any(|r| r["max_error"].is_f64()));
    assert_documented("modes", &["modes", "cart_pendulum", "--json"]);
}

#[test]
fn compare_json_says_what_was_compared() {
    let output = lagrange(&[
        "compare",
        "cart_pendulum",
        "--param",
        "m=2",
        "--engine",
        "cartesian",
        "--dt",
        "0.005",
        "--substeps",
        "2",
        "--t-end",
        "0.5",
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let json: Value = serde_json::from_str(&stdout(&output)).expect("valid JSON");
    assert!(json.is_object(), "not an object: {json}");
    assert_eq!(json["scene"], "cart_pendulum");
    assert_eq!(json["parameters"]["bob_mass"], 2.0, "{}", json["parameters"]);
    assert_eq!(
        (json["dt"].as_f64(), json["substeps"].as_u64(), json["t_end"].as_f64()),
        (Some(0.005), Some(2), Some(0.5))
    );
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(1));
    assert_eq!(json["rows"][0]["engine"], "cartesian");
    // No closed form: measured against the reduced solution, at its tolerance.
    assert_eq!(
        (json["rows"][0]["reference"].as_str(), json["reference_tol"].as_f64()),
        (Some("reduced_dop853"), Some(3e-15))
    );
}

/// `compare` measures against the scene's closed form where it has one, as the report does:
/// the parallelogram chain passes its flat position within 2 s, where the reduced solution
/// is least exact (at tol 3e-15 its energy drifts by 8.3e-7 over these 2 s, measured). The
/// Cartesian engine at its default tolerance 1e-12 is 5.1e-11 off the exact motion
/// (measured); 1e-8 bounds that with a factor 200 of room.
#[test]
fn compare_measures_against_the_closed_form_where_there_is_one() {
    let output = lagrange(&[
        "compare",
        "parallelogram_chain",
        "--param",
        "N=2",
        "--engine",
        "cartesian",
        "--t-end",
        "2",
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let json: Value = serde_json::from_str(&stdout(&output)).expect("valid JSON");
    let row = &json["rows"][0];
    assert_eq!((row["reference"].as_str(), json["reference_tol"].as_f64()), (Some("closed_form"), None), "{json}");
    assert!(row["max_error"].as_f64().is_some_and(|e| e < 1e-8), "{json}");
    let text = lagrange(&["compare", "parallelogram_chain", "--param", "N=2", "--engine", "cartesian", "--t-end", "2"]);
    assert!(stdout(&text).contains("errors against the scene's closed form"), "{}", stdout(&text));
}

/// The rows of a CSV, as numbers, after its header.
fn csv_rows(text: &str) -> Vec<Vec<f64>> {
    text.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().expect("number")).collect()).collect()
}

#[test]
fn simulate_csv_header_names_the_units_and_the_energy_function_h() {
    let output = lagrange(&["simulate", "cart_pendulum", "--t-end", "0.1"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(stdout(&output).lines().next(), Some("t [s],X [m],θ [rad],X_dot [m/s],θ_dot [rad/s],h [J]"));
    let output = lagrange(&["simulate", "wedge", "--t-end", "0.1"]);
    assert_eq!(stdout(&output).lines().next(), Some("t [s],x [m],x' [m],x_dot [m/s],x'_dot [m/s],h [J]"));
}

#[test]
fn simulate_starts_at_the_start_time() {
    // The driven pendulum's support moves as A sin ωt: the same state at another time is
    // another motion.
    let run = |args: &[&str]| {
        let output = lagrange(
            &[&["simulate", "driven_pendulum", "--integrator", "rk4", "--dt", "0.01", "--every", "0.5"][..], args]
                .concat(),
        );
        assert!(output.status.success(), "{args:?}: {}", stderr(&output));
        csv_rows(&stdout(&output))
    };
    let later = run(&["--start", "1", "--t-end", "2"]);
    assert_eq!(later.iter().map(|r| r[0]).collect::<Vec<_>>(), [1.0, 1.5, 2.0]);
    let from_zero = run(&["--t-end", "1"]);
    assert_eq!(from_zero.iter().map(|r| r[0]).collect::<Vec<_>>(), [0.0, 0.5, 1.0]);
    assert_eq!(later[0][1..3], from_zero[0][1..3], "both start from the default state");
    assert!((later[2][1] - from_zero[2][1]).abs() > 1e-3, "the drive's phase changed nothing: {later:?} {from_zero:?}");
    let output = lagrange(&["simulate", "driven_pendulum", "--start", "3", "--t-end", "2"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("--t-end (2) must be after --start (3)"), "{}", stderr(&output));
}

/// Every run checks itself against the constants of the motion its scene declares (`E − τ θ₂`
/// of the driven four-bar, `E − mom β` of Andrews' squeezer, not only the engine's energy) and
/// its constraints: beyond the error its method and setting allow it exits 1 — after writing
/// its output — naming the quantity, its drift and when it left its bound; `--allow-drift`
/// keeps it with a warning. The runs below exited 0 at 6d4bf6b (the driven four-bar 22 % off
/// in speed, Andrews' squeezer 1.3 rad off, the four-bar at dt 0.05 6 % off in energy).
#[test]
fn a_run_that_drifts_from_what_its_scene_declares_exits_1() {
    for (args, quantity, flag) in [
        (&["simulate", "four_bar", "--param", "tau=1", "--t-end", "8.98", "--tol", "1e-3"][..], "E − τ θ2", "--tol"),
        (&["simulate", "andrews_squeezer", "--t-end", "0.03", "--integrator", "rk4"], "E − mom β", "--dt"),
        (&["simulate", "andrews_squeezer", "--t-end", "0.03", "--integrator", "gauss4"], "E − mom β", "--dt"),
        (&["simulate", "andrews_squeezer", "--t-end", "0.03", "--integrator", "variational"], "E − mom β", "--dt"),
        (&["simulate", "four_bar", "--integrator", "rk4", "--dt", "0.05", "--t-end", "10"], "E drifted", "--dt"),
        (&["simulate", "harmonic_oscillator", "--t-end", "10", "--tol", "1e-1"], "E drifted", "--tol"),
        (
            &[
                "simulate",
                "harmonic_oscillator",
                "--param",
                "k=6.25",
                "--t-end",
                "10",
                "--integrator",
                "rk4",
                "--dt",
                "1",
            ],
            "E drifted",
            "--dt",
        ),
    ] {
        let output = lagrange(args);
        let err = stderr(&output);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(quantity) && err.contains("beyond its bound from t = "), "{args:?}: {err}");
        assert!(err.contains(&format!("use a smaller {flag}")), "{args:?}: {err}");
        assert!(!stdout(&output).is_empty(), "{args:?}: the output is written before the verdict");
        let mut allowed = args.to_vec();
        allowed.push("--allow-drift");
        let output = lagrange(&allowed);
        assert!(output.status.success(), "{allowed:?}: {}", stderr(&output));
        assert!(stderr(&output).starts_with("warning: "), "{allowed:?}: {}", stderr(&output));
    }
    // Runs that resolve the motion pass silently: the defaults, and every method at a setting
    // that resolves it — the same scenes at their defaults included.
    for args in [
        &["simulate", "harmonic_oscillator", "--t-end", "10"][..],
        &["simulate", "harmonic_oscillator", "--t-end", "10", "--tol", "1e-6"],
        &["simulate", "kepler", "--t-end", "10", "--integrator", "rk4"],
        &["simulate", "double_pendulum", "--t-end", "10", "--integrator", "variational", "--dt", "0.01"],
        &["simulate", "double_pendulum", "--t-end", "10", "--integrator", "gauss4", "--dt", "0.1"],
        &["simulate", "four_bar", "--param", "tau=1", "--t-end", "8.98"],
        &["simulate", "andrews_squeezer", "--t-end", "0.03"],
        &["simulate", "andrews_squeezer", "--t-end", "0.03", "--integrator", "rk4", "--dt", "1e-4"],
        &["simulate", "chaplygin_sleigh", "--t-end", "10", "--integrator", "sdirk4"],
    ] {
        let output = lagrange(args);
        assert!(output.status.success(), "{args:?}: {}", stderr(&output));
        assert!(stderr(&output).is_empty(), "{args:?}: {}", stderr(&output));
    }
}

/// A run that blows up and then stops is told as a divergence (with the quantity that left its
/// bound), not as stiffness: at 6d4bf6b the double pendulum at tol 0.9 said "looks stiff, use
/// the implicit integrator", and the driven four-bar at tol 0.1 "stiff or singular".
#[test]
fn a_blow_up_is_not_called_stiffness() {
    for args in [
        &["simulate", "double_pendulum", "--tol", "0.9", "--t-end", "10"][..],
        &["simulate", "four_bar", "--param", "tau=1", "--t-end", "10", "--tol", "0.1"],
    ] {
        let output = lagrange(args);
        let err = stderr(&output);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains("diverged (") && err.contains("drifted by"), "{args:?}: {err}");
        assert!(err.contains("use a smaller --tol"), "{args:?}: {err}");
    }
}

/// Run `lagrange` for at most `seconds`; `None` (the child killed) if it has not finished.
fn lagrange_within(args: &[&str], seconds: u64) -> Option<Output> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_lagrange"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = std::time::Instant::now();
    while start.elapsed().as_secs() < seconds {
        if child.try_wait().expect("wait").is_some() {
            return Some(child.wait_with_output().expect("output"));
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

#[test]
fn absurd_requests_are_refused_up_front_with_the_estimate_and_the_flag_to_change() {
    for (args, flag) in [
        (&["simulate", "harmonic_oscillator", "--t-end", "1e12"][..], "--t-end"),
        (&["simulate", "harmonic_oscillator", "--t-end", "1e12", "--integrator", "rk4"], "--dt"),
        (&["simulate", "harmonic_oscillator", "--t-end", "1", "--every", "1.1e-8"], "--every"),
        (&["compare", "cart_pendulum", "--t-end", "1e12"], "--t-end"),
        (&["compare", "cart_pendulum", "--substeps", "1000000000"], "--substeps"),
        // The chain of 64 links over 1000 s: its default 10 s took 23 s (test build, every
        // engine; the Cartesian build's sparse solve made it a runnable request), so ≈ 40 min,
        // 19× the limit — far enough that the machine's load cannot move it under.
        (&["compare", "chain", "--param", "N=64", "--t-end", "1000"], "--t-end"),
    ] {
        let output = lagrange_within(args, 60).unwrap_or_else(|| panic!("{args:?} still running after 60 s"));
        let err = stderr(&output);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: not one line: {err}");
        assert!(err.contains("estimated") && err.contains("beyond the limit of"), "{args:?}: {err}");
        assert!(err.contains(flag) && err.contains("--force"), "{args:?}: {err}");
        assert!(output.stdout.is_empty(), "{args:?} wrote output");
    }
    // Within the limits, the defaults run as before.
    let output = lagrange(&["simulate", "harmonic_oscillator", "--t-end", "10"]);
    assert!(output.status.success(), "{}", stderr(&output));
    // --force lifts the output limit (here on a request small enough to run: the limit is
    // checked on the estimate, so a forced request is simply run).
    let output = lagrange(&["simulate", "harmonic_oscillator", "--t-end", "0.001", "--every", "1e-4", "--force"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(csv_rows(&stdout(&output)).len(), 11);
}

#[test]
fn an_interrupted_simulate_leaves_no_partial_file() {
    // 10⁶ rows (≈ 70 MB): killed as soon as the file appears, it must hold every row — the
    // file only ever appears complete.
    let dir = temp_dir("partial");
    let file = dir.join("run.csv");
    let args = [
        "simulate",
        "harmonic_oscillator",
        "--t-end",
        "1000",
        "--integrator",
        "rk4",
        "--dt",
        "1e-3",
        "--every",
        "1e-3",
        "--out",
        file.to_str().unwrap(),
    ];
    let mut child = Command::new(env!("CARGO_BIN_EXE_lagrange"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("the binary runs");
    let start = std::time::Instant::now();
    while !file.exists() && child.try_wait().expect("wait").is_none() && start.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_micros(200));
    }
    let _ = child.kill();
    let _ = child.wait();
    let text = std::fs::read_to_string(&file).expect("the run got as far as its file");
    assert_eq!(text.lines().count(), 1 + 1_000_001, "a partial file: {} bytes", text.len());
    assert!(text.ends_with('\n'));
    // Nothing else is left beside it once a run ends normally.
    std::fs::remove_file(&file).unwrap();
    let output = lagrange(&["simulate", "kepler", "--t-end", "1", "--out", file.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
    let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, [std::ffi::OsString::from("run.csv")]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--out` through a symbolic link writes the file the link points to and leaves the link a
/// link; a named pipe is written through, not replaced; a device that refuses the write
/// (`/dev/full`) is an error naming it and stays a device; a directory is refused. (At 6d4bf6b
/// each of them was replaced by a regular file.)
#[test]
fn out_never_replaces_what_is_not_a_regular_file() {
    use std::os::unix::fs::FileTypeExt;
    let dir = temp_dir("links");
    let real = dir.join("real.csv");
    std::fs::write(&real, "old\n").unwrap();
    let link = dir.join("link.csv");
    std::os::unix::fs::symlink("real.csv", &link).unwrap();
    let output = lagrange(&["simulate", "kepler", "--t-end", "1", "--out", link.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link was replaced");
    let text = std::fs::read_to_string(&real).unwrap();
    assert!(text.starts_with("t [s],"), "the link's target holds {text:?}");
    let names: BTreeSet<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 2, "left beside them: {names:?}");

    // A named pipe: a reader on the other end gets the CSV, and the pipe is still a pipe.
    let pipe = dir.join("pipe");
    let made = Command::new("mkfifo").arg(&pipe).status().expect("mkfifo runs");
    assert!(made.success());
    let reader = {
        let pipe = pipe.clone();
        std::thread::spawn(move || std::fs::read_to_string(pipe).unwrap())
    };
    let output = lagrange(&["simulate", "kepler", "--t-end", "1", "--out", pipe.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(reader.join().unwrap().starts_with("t [s],"));
    assert!(std::fs::symlink_metadata(&pipe).unwrap().file_type().is_fifo(), "the pipe was replaced");

    // A device that takes no bytes: exit 1, naming it; still a device.
    let output = lagrange(&["simulate", "kepler", "--t-end", "1", "--out", "/dev/full"]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).contains("/dev/full"), "{}", stderr(&output));
    assert!(std::fs::symlink_metadata("/dev/full").unwrap().file_type().is_char_device());

    // A directory.
    let output = lagrange(&["simulate", "kepler", "--t-end", "1", "--out", dir.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).contains("directory"), "{}", stderr(&output));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--max-seconds` stops a long run with what it has (exit 1, saying how far it got), also when
/// the measured progress shows early that it cannot finish; the samples before the stop are
/// written. At 6d4bf6b a run the up-front estimate got wrong ran on for minutes.
#[test]
fn max_seconds_stops_a_long_run_with_what_it_has() {
    let started = std::time::Instant::now();
    let output = lagrange(&[
        "simulate",
        "harmonic_oscillator",
        "--t-end",
        "1e5",
        "--integrator",
        "rk4",
        "--dt",
        "1e-3",
        "--every",
        "1",
        "--max-seconds",
        "2",
    ]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(err.contains("--max-seconds 2") && err.contains("of 100000 s reached"), "{err}");
    // Stopped at 2 s, or earlier on its projection; the process's own start-up on top.
    assert!(started.elapsed().as_secs_f64() < 30.0, "ran {:?}", started.elapsed());
    let rows = csv_rows(&stdout(&output));
    assert!(rows.len() > 1, "the samples before the stop are written");
    // compare: the engines not done in time are named.
    let output = lagrange(&["compare", "chain", "--param", "N=64", "--t-end", "100", "--max-seconds", "1"]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(err.contains("left out: ") && err.contains("rapier-impulse"), "{err}");
}
