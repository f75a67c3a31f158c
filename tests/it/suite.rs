//! The suite's own bookkeeping: `docs/testing.md` names every test there is, integration and
//! unit, so a reviewer can check that no property went unproven when tests were merged, moved
//! or shrunk, and it names no test that does not exist.

use std::path::Path;

/// `(module path, test name)` of every `#[test]` in the Rust files under `dir`; `module` is the
/// file's stem for `tests/it`, its path under `src` otherwise.
fn tests_in(dir: &Path, out: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).expect("a test or source directory").flatten().collect();
    entries.sort_by_key(|e| e.path());
    for entry in entries {
        let path = entry.path();
        if path.is_dir() {
            tests_in(&path, out);
            continue;
        }
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("a source file");
        // A folder's `mod.rs` is known by the folder's name.
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
        let module = if stem == "mod" {
            path.parent().and_then(|p| p.file_name()).and_then(|s| s.to_str()).unwrap_or_default().to_string()
        } else {
            stem.to_string()
        };
        let mut lines = text.lines();
        while let Some(line) = lines.next() {
            if line.trim() != "#[test]" {
                continue;
            }
            for next in lines.by_ref() {
                let t = next.trim_start();
                if let Some(rest) = t.strip_prefix("fn ").or_else(|| t.strip_prefix("pub fn ")) {
                    let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                    out.push((module.clone(), name));
                    break;
                }
            }
        }
    }
}

/// The module name (as [`tests_in`] gives it) of every Rust file under `dir`.
fn source_modules(dir: &Path, out: &mut Vec<String>) {
    for entry in std::fs::read_dir(dir).expect("a source directory").flatten() {
        let path = entry.path();
        if path.is_dir() {
            if let Some(name) = path.file_name().and_then(|s| s.to_str()) {
                out.push(name.to_string());
            }
            source_modules(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            if let Some(stem) = path.file_stem().and_then(|s| s.to_str()) {
                out.push(stem.to_string());
            }
        }
    }
}

#[test]
fn docs_testing_names_every_test_and_no_other() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/testing.md")).expect("docs/testing.md");
    let mut integration = Vec::new();
    tests_in(&root.join("tests/it"), &mut integration);
    let mut unit = Vec::new();
    tests_in(&root.join("src"), &mut unit);
    assert!(integration.len() > 150 && unit.len() > 50, "{} and {} tests found", integration.len(), unit.len());
    let mut missing = Vec::new();
    for (module, name) in &integration {
        if !doc.contains(&format!("`{module}::{name}`")) {
            missing.push(format!("{module}::{name}"));
        }
    }
    for (file, name) in &unit {
        if !doc.contains(&format!("`{file}: {name}`")) {
            missing.push(format!("{file}: {name}"));
        }
    }
    assert!(missing.is_empty(), "docs/testing.md does not name these tests:\n{}", missing.join("\n"));
    // Every test the tables name exists: an entry left behind by a removed test fails too.
    let names: Vec<String> = integration.iter().map(|(m, n)| format!("{m}::{n}")).collect();
    let unit_names: Vec<String> = unit.iter().map(|(m, n)| format!("{m}: {n}")).collect();
    let mut modules = Vec::new();
    source_modules(&root.join("src"), &mut modules);
    let snake =
        |name: &str| !name.is_empty() && name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    let mut stale = Vec::new();
    for cell in doc.split('`').skip(1).step_by(2) {
        if let Some((module, name)) = cell.split_once("::") {
            let is_test = snake(name) && integration.iter().any(|(m, _)| m == module);
            if is_test && !names.iter().any(|n| n == cell) {
                stale.push(cell.to_string());
            }
        } else if let Some((module, name)) = cell.split_once(": ") {
            // A unit test's entry: `module: name`, module a source file or folder.
            let is_test = snake(name) && modules.iter().any(|m| m == module);
            if is_test && !unit_names.iter().any(|n| n == cell) {
                stale.push(cell.to_string());
            }
        }
    }
    assert!(stale.is_empty(), "docs/testing.md names tests that do not exist:\n{}", stale.join("\n"));
}
