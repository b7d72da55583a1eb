//! The engine's modules are layered: a module of `crates/lagrange/src` may use modules of its
//! own layer or below, never above. This reads the sources and fails, naming file and line, on
//! any `crate::` path (in a `use` or inline) that reaches a module of a higher layer.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

/// The top-level modules of `lagrange`, bottom layer first. Modules in one layer may use each
/// other (a mechanism declares its tree, a tree is a mechanism; the evaluation stages fill the
/// workspace, which holds their scratch; a model holds the sparse structure of its solve).
const LAYERS: &[&[&str]] = &[
    &["error", "linalg", "pose", "scalar", "seed", "state"],
    &["mechanism", "tree"],
    &["passes", "probe", "graph"],
    // The model builds the sparse structure of its constrained solve at construction.
    &["model", "eom", "workspace"],
    &["ode"],
    &["integrate"],
    &["system"],
    // Normal modes: linearizes any system through its facade.
    &["modes"],
    // What most programs import: re-exports from every layer below.
    &["prelude"],
];

/// Test-only code, outside the layers: the crate's test fixtures, and unit tests (files named
/// `tests.rs` or under a `tests/` folder, and a trailing `#[cfg(test)] mod tests`), which may
/// drive the engine from its public surface whatever module they sit in.
const TEST_ONLY: &str = "test_support";

fn is_test_file(root: &Path, file: &Path) -> bool {
    let relative = file.strip_prefix(root).expect("file under the source directory");
    relative.components().any(|c| c.as_os_str() == "tests" || c.as_os_str() == "tests.rs")
}

/// The text before a trailing `#[cfg(test)] mod tests` block.
fn without_unit_tests(text: &str) -> &str {
    match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => text,
    }
}

fn source_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../crates/lagrange/src")).to_path_buf()
}

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

/// The text without `//` comments (doc links name modules without using them), same length
/// per line so that offsets keep their line numbers.
fn strip_comments(text: &str) -> String {
    text.lines()
        .map(|line| match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn identifier(text: &str) -> &str {
    let end = text.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(text.len());
    &text[..end]
}

/// The first path segment of each item of a `crate::` path starting at `rest`: `X` for
/// `crate::X…`, and `A`, `B` for `crate::{A, B::c}` (nested groups inside an item are skipped).
fn first_segments(rest: &str) -> Vec<&str> {
    let rest = rest.trim_start();
    let Some(group) = rest.strip_prefix('{') else {
        return vec![identifier(rest)];
    };
    let mut items = Vec::new();
    let (mut depth, mut start) = (0usize, 0usize);
    for (i, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                items.push(&group[start..i]);
                break;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&group[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.into_iter().map(|item| identifier(item.trim())).filter(|s| !s.is_empty()).collect()
}

/// Every `crate::` path of `text` (not `$crate::`, not part of a longer name), with its line
/// (1-based) and the first segment of each item it names.
fn crate_paths(text: &str) -> Vec<(usize, &str)> {
    let mut found = Vec::new();
    for (at, _) in text.match_indices("crate::") {
        let before = text[..at].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            continue;
        }
        let line = text[..at].matches('\n').count() + 1;
        for segment in first_segments(&text[at + "crate::".len()..]) {
            found.push((line, segment));
        }
    }
    found
}

/// The crate root's re-exports: public name → the top-level module it comes from.
fn root_exports(lib: &str) -> BTreeMap<String, String> {
    let mut exports = BTreeMap::new();
    for statement in lib.split(';') {
        let statement = statement.trim();
        let Some(path) = statement.rsplit("pub use ").next().filter(|_| statement.contains("pub use ")) else {
            continue;
        };
        let module = identifier(path).to_string();
        // The exported names: the last segment of each item, or its `as` alias.
        let names: Vec<&str> = match (path.find('{'), path.rfind('}')) {
            (Some(open), Some(close)) => path[open + 1..close].split(',').collect(),
            _ => vec![path],
        };
        for name in names {
            let name = name.trim();
            let exported = match name.rsplit_once(" as ") {
                Some((_, alias)) => alias.trim(),
                None => name.rsplit("::").next().unwrap_or(name),
            };
            if !exported.is_empty() {
                exports.insert(exported.to_string(), module.clone());
            }
        }
    }
    exports
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).expect("read source directory") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level module a source file belongs to (`None` for the crate root).
fn module_of(root: &Path, file: &Path) -> Option<String> {
    let relative = file.strip_prefix(root).expect("file under the source directory");
    let first = relative.components().next()?.as_os_str().to_str()?.to_string();
    let module = first.strip_suffix(".rs").map_or(first.clone(), str::to_string);
    (module != "lib").then_some(module)
}

#[test]
fn no_module_uses_a_module_of_a_higher_layer() {
    let root = source_dir();
    let lib = strip_comments(&fs::read_to_string(root.join("lib.rs")).expect("read lib.rs"));
    let exports = root_exports(&lib);
    // Every declared top-level module has a layer.
    for line in lib.lines() {
        let line = line.trim();
        if let Some(rest) = line.strip_prefix("mod ").or_else(|| line.strip_prefix("pub mod ")) {
            let module = identifier(rest);
            assert!(
                module == TEST_ONLY || layer_of(module).is_some(),
                "module `{module}` of lib.rs has no layer in LAYERS"
            );
        }
    }
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    files.sort();
    let mut violations = Vec::new();
    let mut checked = 0;
    for file in &files {
        let Some(module) = module_of(&root, file) else { continue };
        if module == TEST_ONLY || is_test_file(&root, file) {
            continue;
        }
        let own = layer_of(&module).unwrap_or_else(|| panic!("{} is in no layer", file.display()));
        let text = strip_comments(&fs::read_to_string(file).expect("read source"));
        for (line, segment) in crate_paths(without_unit_tests(&text)) {
            checked += 1;
            // A top-level module, or a name the root re-exports from one.
            let target = if layer_of(segment).is_some() {
                segment.to_string()
            } else if let Some(origin) = exports.get(segment) {
                origin.clone()
            } else {
                violations
                    .push(format!("{}:{line}: `crate::{segment}` is neither a module nor a re-export", file.display()));
                continue;
            };
            // `num_dual` is re-exported from outside the crate.
            let Some(layer) = layer_of(&target) else { continue };
            if layer > own {
                violations.push(format!(
                    "{}:{line}: `{module}` (layer {own}) uses `crate::{segment}` of `{target}` (layer {layer})",
                    file.display()
                ));
            }
        }
    }
    assert!(checked > 50, "found only {checked} crate paths: is the parser broken?");
    assert!(violations.is_empty(), "upward or unresolved imports:\n{}", violations.join("\n"));
}

#[test]
fn the_parser_sees_grouped_and_inline_paths() {
    let text = "use crate::{a::b, C, d::{e, f}};\nfn g() { crate::h::i(); $crate::j::k; mycrate::l; }";
    let paths: Vec<_> = crate_paths(text).into_iter().collect();
    assert_eq!(paths, vec![(1, "a"), (1, "C"), (1, "d"), (2, "h")]);
    let exports = root_exports("pub use x::{Y, z::W};\npub use v::U as T;\npub use num_dual;");
    assert_eq!(exports.get("Y").map(String::as_str), Some("x"));
    assert_eq!(exports.get("W").map(String::as_str), Some("x"));
    assert_eq!(exports.get("T").map(String::as_str), Some("v"));
    assert_eq!(exports.get("num_dual").map(String::as_str), Some("num_dual"));
}
