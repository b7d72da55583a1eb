//! What `lagrange` writes, as a user reads it: Markdown tables whose rows keep their columns,
//! JSON that matches its documentation (docs/cli-json.md), a CSV header with units, warnings
//! on energy drift, refusals of absurd requests, and output files that are never left half
//! written.

use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn lagrange(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lagrange")).args(args).output().expect("the binary runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

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

/// Every table of a Markdown document: a run of lines starting with `|`, the first its header.
/// Returns `(line number, header, rows)` per table.
fn tables(markdown: &str) -> Vec<(usize, Vec<String>, Vec<(usize, String)>)> {
    let mut tables = Vec::new();
    let mut current: Option<(usize, Vec<String>, Vec<(usize, String)>)> = None;
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
    for doc in ["crates/cli/REPORT_SCHEMA.md"] {
        let markdown = std::fs::read_to_string(root().join(doc)).unwrap_or_else(|e| panic!("{doc}: {e}"));
        assert!(assert_tables_keep_their_columns(&markdown, doc) > 0, "{doc} has no table");
    }
}
