//! The README tells the truth: its quickstart is the example verbatim, and every path and
//! package it names exists.

use std::path::Path;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn readme() -> String {
    std::fs::read_to_string(root().join("README.md")).expect("README.md exists")
}

#[test]
fn quickstart_is_the_example_verbatim() {
    let readme = readme();
    let start = readme.find("```rust\n").expect("a rust block") + "```rust\n".len();
    let end = start + readme[start..].find("```").expect("closed block");
    let example = std::fs::read_to_string(root().join("examples/quickstart.rs")).expect("example exists");
    assert_eq!(&readme[start..end], example, "README quickstart differs from examples/quickstart.rs");
}

#[test]
fn the_first_two_commands_are_the_main_job_and_the_tests() {
    let readme = readme();
    let block = readme.split("```bash\n").nth(1).expect("a bash block");
    let commands: Vec<&str> = block.lines().take(2).collect();
    assert_eq!(commands, ["cargo run --release -p lagrange-cli -- report", "cargo test --workspace"]);
    // CI runs the README's test line exactly as written, not a variant of it.
    let ci = std::fs::read_to_string(root().join(".ci/run")).expect(".ci/run exists");
    assert!(ci.lines().any(|l| l == commands[1]), "CI runs the README's test command");
}

#[test]
fn every_path_and_package_named_exists() {
    let readme = readme();
    let manifest = |dir: &str| std::fs::read_to_string(root().join(dir).join("Cargo.toml")).unwrap_or_default();
    // The workspace members, from the root manifest's `members = [...]` list.
    let root_manifest = std::fs::read_to_string(root().join("Cargo.toml")).expect("root manifest");
    let members = root_manifest.split("members = [").nth(1).and_then(|m| m.split(']').next()).expect("a members list");
    let packages: Vec<String> = members
        .split(',')
        .map(|m| m.trim().trim_matches('"'))
        .filter(|m| !m.is_empty())
        .filter_map(|d| manifest(d).lines().find(|l| l.starts_with("name = ")).map(|l| l[8..l.len() - 1].to_string()))
        .collect();
    for word in readme.split(['`', ' ', '(', ')', ',', '|', '\n']) {
        let word = word.trim_end_matches([':', '.']);
        let is_path = (word.starts_with("crates/")
            || word.starts_with("tests/")
            || word.starts_with("examples/")
            || word.starts_with("benches/")
            || word.starts_with("scripts/")
            || word.starts_with("docs/")
            || word.starts_with(".ci/"))
            && !word.contains('*');
        if is_path {
            // A document's anchor is not part of its path.
            let path = word.split('#').next().unwrap_or(word);
            assert!(root().join(path).exists(), "README names `{word}`, which does not exist");
        }
        if let Some(rest) = word.strip_prefix("lagrange-") {
            let name = format!("lagrange-{rest}");
            assert!(packages.contains(&name), "README names package `{name}`; packages are {packages:?}");
        }
    }
    for line in readme.lines().filter(|l| l.contains("--example ")) {
        let name = line.split("--example ").nth(1).and_then(|s| s.split([' ', '`']).next()).expect("example name");
        assert!(manifest("examples").contains(&format!("name = \"{name}\"")), "no example `{name}`");
    }
}

/// The README's scene files and printed equations are the shipped files and the golden output,
/// verbatim.
#[test]
fn scene_files_and_equations_are_the_shipped_ones_verbatim() {
    let readme = readme();
    for file in [
        "examples/scenes/double_pendulum.toml",
        "examples/scenes/four_bar.graph.toml",
        "crates/cli/tests/golden/eom/double_pendulum.txt",
    ] {
        let text = std::fs::read_to_string(root().join(file)).unwrap();
        assert!(readme.contains(&text), "the README does not show {file} verbatim");
    }
}
