//! The shape of the code, checked on its text:
//! - **layers**: `src/lib.rs` lists the crate's modules bottom to top (`//! N. [`module`]`), and
//!   every `crate::` path in a module's non-test code names a module listed before its own, so
//!   that no import cycle between modules can form;
//! - **rooms**: no source file over [`MAX_FILE_LINES`] lines (test files and generated tables,
//!   `*_table.rs`, aside) and no function over [`MAX_FUNCTION_LINES`] lines, tests included.

use std::path::{Path, PathBuf};

const MAX_FILE_LINES: usize = 800;
const MAX_FUNCTION_LINES: usize = 150;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every file under `dir` (recursively) whose name ends with one of `extensions`, sorted.
fn files_under(dir: &Path, extensions: &[&str]) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap_or_else(|e| panic!("{}: {e}", folder.display())) {
            let path = entry.expect("readable folder entry").path();
            if path.is_dir() {
                pending.push(path);
            } else if extensions.iter().any(|ext| path.extension().is_some_and(|e| e == *ext)) {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A unit-test file: `tests.rs` or anything under a `tests/` folder.
fn is_test_file(relative: &Path) -> bool {
    relative.file_name().is_some_and(|n| n == "tests.rs")
        || relative.components().any(|c| c.as_os_str() == "tests")
}

/// The layer order `src/lib.rs` states: the names of its `//! N. [`module`]` lines, in order.
fn stated_layers(lib: &str) -> Vec<String> {
    lib.lines()
        .filter_map(|line| {
            let item = line.strip_prefix("//! ")?;
            let (number, rest) = item.split_once(". [`")?;
            number.parse::<u32>().ok()?;
            Some(rest.split_once('`')?.0.to_string())
        })
        .collect()
}

/// The modules `lib.rs` declares (`pub mod name;` / `mod name;`), test-only ones aside.
fn declared_modules(lib: &str) -> Vec<String> {
    declarations(lib).into_iter().filter(|(_, test_only)| !test_only).map(|(name, _)| name).collect()
}

/// Every module `lib.rs` declares, and whether it is `#[cfg(test)]`.
fn declarations(lib: &str) -> Vec<(String, bool)> {
    let mut test_only = false;
    let mut modules = Vec::new();
    for line in lib.lines().map(str::trim) {
        if line == "#[cfg(test)]" {
            test_only = true;
            continue;
        }
        let declared = line.strip_prefix("pub mod ").or_else(|| line.strip_prefix("mod "));
        if let Some(name) = declared.and_then(|rest| rest.strip_suffix(';')) {
            modules.push((name.to_string(), test_only));
        }
        test_only = false;
    }
    modules
}

/// The top-level modules a line of code names through `crate::` (`crate::a::b`, `crate::{a, b::c}`);
/// `crate::Error` and `crate::Result` are the `error` module's re-exports.
fn crate_paths(code: &str) -> Vec<String> {
    let mut named = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        rest = &rest[at + "crate::".len()..];
        let roots: Vec<&str> = match rest.strip_prefix('{') {
            Some(group) => {
                let inside = &group[..group.find('}').unwrap_or(group.len())];
                inside.split(',').map(|item| item.trim()).collect()
            }
            None => vec![rest],
        };
        for root in roots {
            let name: String = root.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            let name = if name == "Error" || name == "Result" { "error".to_string() } else { name };
            if !name.is_empty() {
                named.push(name);
            }
        }
    }
    named
}

/// The code of a Rust line, without its `//` comment (string literals holding `//` aside, which
/// no `crate::` path follows in this crate).
fn code_of(line: &str) -> &str {
    line.split("//").next().unwrap_or("")
}

#[test]
fn lib_rs_states_every_module_once() {
    let lib = read(&root().join("src/lib.rs"));
    let stated = stated_layers(&lib);
    let mut declared = declared_modules(&lib);
    assert!(!stated.is_empty(), "src/lib.rs states no layers (`//! 1. [`module`]: ...` lines)");
    let mut sorted = stated.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), stated.len(), "a module is stated twice in src/lib.rs: {stated:?}");
    declared.sort();
    assert_eq!(sorted, declared, "src/lib.rs: the layer list and the `mod` declarations differ");
}

#[test]
fn every_module_imports_only_from_layers_below_its_own() {
    let src = root().join("src");
    let lib = read(&src.join("lib.rs"));
    let layers = stated_layers(&lib);
    let test_modules: Vec<String> =
        declarations(&lib).into_iter().filter(|(_, test_only)| *test_only).map(|(name, _)| name).collect();
    let rank = |name: &str| layers.iter().position(|l| l == name);
    let mut violations = Vec::new();
    for path in files_under(&src, &["rs"]) {
        let relative = path.strip_prefix(&src).expect("under src");
        let first = relative.components().next().expect("a path").as_os_str().to_string_lossy();
        let module = first.trim_end_matches(".rs");
        // The binary (main.rs and the cli/ files it includes) sits above every layer.
        if is_test_file(relative)
            || ["lib", "main", "cli"].contains(&module)
            || test_modules.iter().any(|m| m == module)
        {
            continue;
        }
        let own = rank(module).unwrap_or_else(|| {
            panic!("src/{}: module `{module}` is not in lib.rs's layer list", relative.display())
        });
        let text = read(&path);
        let lines: Vec<&str> = text.lines().collect();
        for (index, line) in lines.iter().enumerate() {
            if line.trim() == "#[cfg(test)]" {
                // Inline test code would hide its imports from this check: tests live in sibling files.
                let next = lines.get(index + 1).map_or("", |l| l.trim());
                if next != "mod tests;" {
                    violations.push(format!(
                        "src/{}:{}: inline test code (tests live in sibling files)",
                        relative.display(),
                        index + 2
                    ));
                }
            }
            for named in crate_paths(code_of(line)) {
                if named == module {
                    continue;
                }
                match rank(&named) {
                    Some(theirs) if theirs < own => {}
                    Some(_) => violations.push(format!(
                        "src/{}:{}: `{module}` imports `{named}`, a layer above it",
                        relative.display(),
                        index + 1
                    )),
                    None => violations.push(format!(
                        "src/{}:{}: `crate::{named}` is not a listed module",
                        relative.display(),
                        index + 1
                    )),
                }
            }
        }
    }
    assert!(violations.is_empty(), "layer order broken:\n{}", violations.join("\n"));
}

#[test]
fn the_layer_check_sees_an_import_from_above() {
    assert_eq!(crate_paths("use crate::render::View;"), ["render"]);
    assert_eq!(crate_paths("use crate::{scene::Scene, vk::Context, Error};"), ["scene", "vk", "error"]);
    assert_eq!(
        crate_paths("let x = crate::exact_math::est_pow(a, b) + crate::Result::Ok(1);"),
        ["exact_math", "error"]
    );
    assert!(crate_paths(code_of("let x = 1; // see crate::render")).is_empty());
    let lib = "//! 1. [`scene`]: a\n//! 2. [`render`]: b\npub mod render;\npub mod scene;\n#[cfg(test)]\nmod test_rng;\n";
    assert_eq!(stated_layers(lib), ["scene", "render"]);
    assert_eq!(declared_modules(lib), ["render", "scene"]);
}

/// The functions of a source file longer than `MAX_FUNCTION_LINES`: `(first line, name, lines)`.
/// A function starts at a line that declares it (Rust `fn name`; GLSL a top-level `type name(`)
/// and ends at the first later line that is its indentation followed by `}`.
fn long_functions(text: &str, rust: bool) -> Vec<(usize, String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut long = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let indent = &line[..line.len() - line.trim_start().len()];
        if line.trim_end().ends_with(';') {
            continue;
        }
        let Some(name) = (if rust { rust_function_name(line) } else { glsl_function_name(line) }) else {
            continue;
        };
        let close = format!("{indent}}}");
        let Some(length) = lines[start + 1..].iter().position(|l| *l == close).map(|end| end + 2) else {
            continue;
        };
        if length > MAX_FUNCTION_LINES {
            long.push((start + 1, name, length));
        }
    }
    long
}

fn rust_function_name(line: &str) -> Option<String> {
    let mut words = line
        .split_whitespace()
        .skip_while(|w| w.starts_with("pub") || ["const", "async", "unsafe", "extern", "\"C\""].contains(w));
    (words.next()? == "fn")
        .then(|| words.next())
        .flatten()
        .map(|w| w.split(['(', '<']).next().unwrap_or(w).to_string())
}

fn glsl_function_name(line: &str) -> Option<String> {
    if line.starts_with([' ', '\t', '#', '/', '}']) || line.contains(';') || line.contains('=') {
        return None;
    }
    let head = line.split_once('(')?.0;
    let mut words = head.split_whitespace().rev();
    let name = words.next()?;
    let return_type = words.next()?;
    let keyword = ["return", "else", "if", "for", "while", "switch", "layout", "struct"];
    (!keyword.contains(&return_type) && name.chars().all(|c| c.is_alphanumeric() || c == '_'))
        .then(|| name.to_string())
}

#[test]
fn no_room_is_too_big() {
    let mut too_big = Vec::new();
    let sources = [
        ("src", &["rs"][..]),
        ("tests", &["rs"]),
        ("benches", &["rs"]),
        ("glsl", &["glsl", "vert", "tesc", "tese", "geom", "frag", "comp"]),
    ];
    for (folder, extensions) in sources {
        for path in files_under(&root().join(folder), extensions) {
            let relative = path.strip_prefix(root()).expect("under the root").to_path_buf();
            let text = read(&path);
            let generated = path.file_stem().is_some_and(|s| s.to_string_lossy().ends_with("_table"));
            let test = folder == "tests"
                || folder == "benches"
                || is_test_file(path.strip_prefix(root().join(folder)).expect("under"));
            let count = text.lines().count();
            if count > MAX_FILE_LINES && !generated && !test {
                too_big.push(format!("{}: {count} lines (at most {MAX_FILE_LINES})", relative.display()));
            }
            for (line, name, length) in long_functions(&text, extensions == ["rs"]) {
                too_big.push(format!(
                    "{}:{line}: fn {name} is {length} lines (at most {MAX_FUNCTION_LINES})",
                    relative.display()
                ));
            }
        }
    }
    assert!(too_big.is_empty(), "rooms too big:\n{}", too_big.join("\n"));
}

#[test]
fn the_room_check_sees_a_long_function() {
    let body = "    let x = 1;\n".repeat(MAX_FUNCTION_LINES);
    let rust = format!("pub(crate) fn long_one(a: u32) -> u32 {{\n{body}}}\nfn short() {{\n}}\n");
    assert_eq!(long_functions(&rust, true), [(1, "long_one".to_string(), MAX_FUNCTION_LINES + 2)]);
    let glsl = format!("precise float long_one(vec3 a,\n    vec3 b) {{\n{body}}}\nvoid short() {{\n}}\n");
    assert_eq!(long_functions(&glsl, false), [(1, "long_one".to_string(), MAX_FUNCTION_LINES + 3)]);
    let fine = format!("fn fits() {{\n{}}}\n", "    let x = 1;\n".repeat(MAX_FUNCTION_LINES - 2));
    assert!(long_functions(&fine, true).is_empty());
}
