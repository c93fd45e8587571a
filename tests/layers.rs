//! The shape of the code, checked on its text:
//! - **layers**: `src/lib.rs` lists the crate's modules bottom to top (`//! N. [`module`]`), and
//!   every `crate::` path in a module's non-test code names a module listed before its own, so
//!   that no import cycle between modules can form;
//! - **folders**: the same inside every folder of `src/`: the folder's root file (`mod.rs`, or
//!   `name.rs` beside the folder `name/`) lists its child modules bottom to top in that format,
//!   and every `super::`, `self::` and `crate::` path in a child's non-test code (its own
//!   subfolder's files included) that leads into the folder names a sibling listed before the
//!   child; naming an item of the root file itself is a cycle through the root;
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

/// The layer order `src/lib.rs` (or a folder's root file) states: the names of its
/// `//! N. [`module`]` lines, in order.
fn stated_layers(lib: &str) -> Vec<String> {
    list_entries(lib).into_iter().map(|entry| entry.name).collect()
}

/// One `//! N. [`name`]: text` line of a list.
struct ListEntry {
    /// Its line in the file, from 1.
    line: usize,
    number: u32,
    name: String,
    /// Whether `]: ` and a text follow the name.
    described: bool,
}

/// The lines of a file that read `//! N. [`name`]...`, in order.
fn list_entries(text: &str) -> Vec<ListEntry> {
    text.lines()
        .enumerate()
        .filter_map(|(index, line)| {
            let item = line.strip_prefix("//! ")?;
            let (number, rest) = item.split_once(". [`")?;
            let number = number.parse::<u32>().ok()?;
            let (name, after) = rest.split_once('`')?;
            let described = after.strip_prefix("]: ").is_some_and(|text| !text.trim().is_empty());
            Some(ListEntry { line: index + 1, number, name: name.to_string(), described })
        })
        .collect()
}

/// The modules `lib.rs` (or a folder's root file) declares (`mod name;`, `pub mod name;`,
/// `pub(crate) mod name;`), test-only ones aside.
fn declared_modules(lib: &str) -> Vec<String> {
    declarations(lib).into_iter().filter(|(_, test_only)| !test_only).map(|(name, _)| name).collect()
}

/// Every module `lib.rs` (or a folder's root file) declares, and whether it is `#[cfg(test)]`.
fn declarations(lib: &str) -> Vec<(String, bool)> {
    let mut test_only = false;
    let mut modules = Vec::new();
    for line in lib.lines().map(str::trim) {
        if line == "#[cfg(test)]" {
            test_only = true;
            continue;
        }
        let declared = line.strip_prefix("mod ").or_else(|| {
            line.split_once(" mod ")
                .filter(|(visibility, _)| visibility.starts_with("pub"))
                .map(|(_, rest)| rest)
        });
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

// ---------------------------------------------------------------------------------------------
// Folders: the layer rule inside every folder of `src/`.

/// A file of a source tree: its path under `src/` and its text.
type SourceFile = (PathBuf, String);

/// A folder of `src/` and the list its root file states.
struct Folder {
    /// The folder, under `src/`.
    dir: PathBuf,
    /// The folder's module, as a path from its crate's root (`["scene", "texture"]`).
    module: Vec<String>,
    /// Its root file under `src/` (`dir/mod.rs`, or `dir.rs` beside it), if it has one.
    root: Option<PathBuf>,
    /// The root file's `//! N. [`child`]: text` lines.
    entries: Vec<ListEntry>,
    /// The non-test child modules the root file declares.
    declared: Vec<String>,
}

impl Folder {
    /// Where a child module stands in the list (0 for the first listed).
    fn rank(&self, child: &str) -> Option<usize> {
        self.entries.iter().position(|entry| entry.name == child)
    }

    fn root_name(&self) -> String {
        self.root
            .as_ref()
            .map_or_else(|| format!("src/{}/", self.dir.display()), |r| format!("src/{}", r.display()))
    }
}

/// The module a file under `src/` holds, as a path from its crate's root: `scene/mod.rs` and
/// `scene.rs` are `["scene"]`; `lib.rs` and `main.rs` (the binary's root) are `[]`.
fn module_of(relative: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        relative.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
    let file = names.pop().unwrap_or_default();
    match file.trim_end_matches(".rs") {
        "mod" => {}
        "lib" | "main" if names.is_empty() => {}
        stem => names.push(stem.to_string()),
    }
    names
}

/// Every folder that holds non-test source files, with what its root file states.
fn folders(files: &[SourceFile]) -> Vec<Folder> {
    let text_of = |path: &Path| files.iter().find(|(p, _)| p == path).map(|(_, text)| text.as_str());
    let dirs: std::collections::BTreeSet<PathBuf> = files
        .iter()
        .filter(|(path, _)| !is_test_file(path))
        .filter_map(|(path, _)| path.parent())
        .filter(|dir| !dir.as_os_str().is_empty())
        .map(Path::to_path_buf)
        .collect();
    dirs.into_iter()
        .map(|dir| {
            let root =
                [dir.join("mod.rs"), dir.with_extension("rs")].into_iter().find(|p| text_of(p).is_some());
            let text = root.as_deref().and_then(text_of).unwrap_or("");
            Folder {
                module: module_of(&dir.join("mod.rs")),
                entries: list_entries(text),
                declared: declared_modules(text),
                root,
                dir,
            }
        })
        .collect()
}

/// What is wrong with a folder's list: no root file, entries out of format, out of count or
/// twice, a listed name that is not a child, a child not listed.
fn list_problems(folder: &Folder) -> Vec<String> {
    let at = folder.root_name();
    if folder.root.is_none() {
        return vec![format!("{at}: no root file (`mod.rs` in the folder, or a file of its name beside it)")];
    }
    let mut problems = Vec::new();
    for (index, entry) in folder.entries.iter().enumerate() {
        let (line, name) = (entry.line, &entry.name);
        if entry.number as usize != index + 1 {
            problems.push(format!("{at}:{line}: `{name}` is numbered {}, not {}", entry.number, index + 1));
        }
        if !entry.described {
            problems
                .push(format!("{at}:{line}: `{name}`: not in the form `//! N. [`child`]: what it holds`"));
        }
        if folder.rank(name) != Some(index) {
            problems.push(format!("{at}:{line}: `{name}` is listed twice"));
        }
        if !folder.declared.contains(name) {
            problems.push(format!("{at}:{line}: `{name}` is listed but is no child module declared here"));
        }
    }
    for name in folder.declared.iter().filter(|name| folder.rank(name).is_none()) {
        problems.push(format!("{at}: child module `{name}` is not listed (`//! N. [`{name}`]: ...`)"));
    }
    problems
}

/// `text` with its comments and the insides of its string and character literals blanked
/// (line breaks kept), so that only code is left where paths are looked for.
fn code_only(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    let mut code = String::with_capacity(text.len());
    let mut i = 0;
    while i < chars.len() {
        let end = match (chars[i], chars.get(i + 1).copied()) {
            ('/', Some('/')) => chars[i..].iter().position(|&c| c == '\n').map_or(chars.len(), |n| i + n),
            ('/', Some('*')) => find_after(&chars, i + 2, &['*', '/']),
            ('"', _) => string_end(&chars, i + 1, 0),
            ('r', Some('"' | '#')) if !chars[..i].last().is_some_and(|&c| is_word(c)) => {
                let hashes = chars[i + 1..].iter().take_while(|&&c| c == '#').count();
                match chars.get(i + 1 + hashes) {
                    Some('"') => string_end(&chars, i + 2 + hashes, hashes),
                    _ => i,
                }
            }
            ('\'', Some('\\')) => find_after(&chars, i + 3, &['\'']),
            ('\'', Some(_)) if chars.get(i + 2) == Some(&'\'') => i + 3,
            _ => i,
        };
        if end == i {
            code.push(chars[i]);
            i += 1;
        } else {
            code.extend(chars[i..end.min(chars.len())].iter().map(|&c| blank(c)));
            i = end;
        }
    }
    code
}

/// The index just past the first `pattern` at or after `from` (the end where there is none).
fn find_after(chars: &[char], from: usize, pattern: &[char]) -> usize {
    (from..chars.len()).find(|&i| chars[i..].starts_with(pattern)).map_or(chars.len(), |i| i + pattern.len())
}

/// The index just past the string literal whose text starts at `from`, closed by `"` and
/// `hashes` `#` (a raw string), or by an unescaped `"`.
fn string_end(chars: &[char], from: usize, hashes: usize) -> usize {
    let mut i = from;
    while i < chars.len() {
        match chars[i] {
            '\\' if hashes == 0 => i += 2,
            '"' if chars[i + 1..].iter().take(hashes).filter(|&&c| c == '#').count() == hashes => {
                return i + 1 + hashes;
            }
            _ => i += 1,
        }
    }
    chars.len()
}

fn is_word(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Every path in `code` (comments and strings blanked) that starts with `super::`, `self::` or
/// `crate::`: its line and its words, one path per leaf of its `{...}` groups (`super::{a,
/// b::{c, self}}` gives `super::a`, `super::b::c` and `super::b::self`).
fn written_paths(code: &str) -> Vec<(usize, Vec<String>)> {
    let mut found = Vec::new();
    let mut line = 1;
    for (at, c) in code.char_indices() {
        if c == '\n' {
            line += 1;
        }
        let starts = ["super::", "self::", "crate::"].iter().any(|keyword| code[at..].starts_with(keyword));
        let joined = code[..at].chars().next_back().is_some_and(|c| is_word(c) || c == '$' || c == ':');
        if starts && !joined {
            let mut rest = &code[at..];
            found.extend(use_tree(&mut rest).into_iter().map(|path| (line, path)));
        }
    }
    found
}

/// The paths of the use tree (or path expression) at the start of `rest`, which it consumes.
fn use_tree(rest: &mut &str) -> Vec<Vec<String>> {
    let mut prefix: Vec<String> = Vec::new();
    loop {
        *rest = rest.trim_start();
        if let Some(group) = rest.strip_prefix('{') {
            *rest = group;
            return use_group(rest).into_iter().map(|path| [prefix.clone(), path].concat()).collect();
        }
        if let Some(after) = rest.strip_prefix('*') {
            *rest = after;
            prefix.push("*".to_string());
            return vec![prefix];
        }
        let length = rest.find(|c: char| !is_word(c)).unwrap_or(rest.len());
        if length == 0 {
            return vec![prefix];
        }
        prefix.push(rest[..length].to_string());
        *rest = &rest[length..];
        match rest.trim_start().strip_prefix("::") {
            Some(after) => *rest = after,
            None => return vec![prefix],
        }
    }
}

/// The paths of the items of a `{...}` group whose `{` `rest` has just passed; consumes the `}`.
fn use_group(rest: &mut &str) -> Vec<Vec<String>> {
    let mut paths = Vec::new();
    loop {
        *rest = rest.trim_start();
        if let Some(after) = rest.strip_prefix('}') {
            *rest = after;
            return paths;
        }
        paths.extend(use_tree(rest).into_iter().filter(|path| !path.is_empty()));
        *rest = rest.trim_start();
        if let Some(after) = rest.strip_prefix("as ") {
            *rest = after.trim_start().trim_start_matches(is_word).trim_start();
        }
        match rest.strip_prefix(',') {
            Some(after) => *rest = after,
            None if rest.starts_with('}') => {}
            None => return paths,
        }
    }
}

/// The module a written path leads into, from a file whose code is in `module`: `crate::`
/// from the crate's root, `self::` from `module`, each `super::` one up; a last `self` (in a
/// group) names the module before it. `None` where the path climbs above the crate's root.
fn resolve(module: &[String], written: &[String]) -> Option<Vec<String>> {
    let (first, rest) = written.split_first()?;
    let mut target = match first.as_str() {
        "crate" => Vec::new(),
        "self" => module.to_vec(),
        "super" => module.split_last()?.1.to_vec(),
        _ => return None,
    };
    let mut rest = rest.iter().peekable();
    while rest.next_if(|word| *word == "super").is_some() {
        target.pop()?;
    }
    target.extend(rest.filter(|word| *word != "self").cloned());
    Some(target)
}

/// The inline modules of a file (`mod name {` ... `}` at the same indentation): the lines they
/// span (from 1, both ends) and their names.
fn inline_modules(lines: &[&str]) -> Vec<(usize, usize, String)> {
    let mut modules = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let indent = &line[..line.len() - line.trim_start().len()];
        let Some(head) = line.trim().strip_suffix('{') else {
            continue;
        };
        let Some(name) = declared_modules(&format!("{};", head.trim_end())).pop() else {
            continue;
        };
        let close = format!("{indent}}}");
        if let Some(length) = lines[start + 1..].iter().position(|l| l.trim_end() == close) {
            modules.push((start + 1, start + 2 + length, name));
        }
    }
    modules
}

/// What is wrong with a path from code in module `own` to `target`, seen from `folder`, a
/// folder `own` lies in: nothing where the path leaves the folder, stays in `own`'s child of
/// it or names a sibling listed before that child.
fn folder_problem(folder: &Folder, own: &[String], target: &[String]) -> Option<String> {
    let depth = folder.module.len();
    if !target.starts_with(&folder.module) || target.get(depth) == own.get(depth) {
        return None;
    }
    let child = &own[depth];
    let root = folder.root_name();
    let Some(named) = target.get(depth).filter(|name| folder.declared.contains(name)) else {
        let what = target.get(depth).map_or("the root module itself".to_string(), |name| format!("`{name}`"));
        return Some(format!("`{child}` names {what} of {root}: a cycle through the root file"));
    };
    match (folder.rank(child), folder.rank(named)) {
        (Some(mine), Some(theirs)) if theirs < mine => None,
        (Some(_), Some(_)) => {
            Some(format!("`{child}` imports `{named}`, listed after it in {root}: a cycle"))
        }
        _ => Some(format!("`{child}` imports `{named}`, and {root} does not list both")),
    }
}

/// The paths of one non-test file that break the order of a folder it lies in.
fn import_problems(relative: &Path, text: &str, folders: &[Folder]) -> Vec<String> {
    let code = code_only(text);
    let inline = inline_modules(&code.lines().collect::<Vec<_>>());
    let file_module = module_of(relative);
    let mut problems = Vec::new();
    for (line, written) in written_paths(&code) {
        let mut own = file_module.clone();
        own.extend(
            inline.iter().filter(|(start, end, _)| (*start..=*end).contains(&line)).map(|m| m.2.clone()),
        );
        let Some(target) = resolve(&own, &written) else {
            continue;
        };
        let around = folders.iter().filter(|f| f.module.len() < own.len() && own.starts_with(&f.module));
        for problem in around.filter_map(|folder| folder_problem(folder, &own, &target)) {
            let problem = format!("src/{}:{line}: {problem}", relative.display());
            if !problems.contains(&problem) {
                problems.push(problem);
            }
        }
    }
    problems
}

/// Everything the folder check reports for a source tree (paths under `src/`).
fn folder_violations(files: &[SourceFile]) -> Vec<String> {
    let folders = folders(files);
    let mut problems: Vec<String> = folders.iter().flat_map(list_problems).collect();
    for (path, text) in files.iter().filter(|(path, _)| !is_test_file(path)) {
        problems.extend(import_problems(path, text, &folders));
    }
    problems
}

#[test]
fn every_folder_lists_its_files_and_imports_only_from_those_before() {
    let src = root().join("src");
    let files: Vec<SourceFile> = files_under(&src, &["rs"])
        .into_iter()
        .map(|path| (path.strip_prefix(&src).expect("under src").to_path_buf(), read(&path)))
        .collect();
    let problems = folder_violations(&files);
    assert!(problems.is_empty(), "folder order broken:\n{}", problems.join("\n"));
}

/// A folder `room/` whose root lists `a` then `b`; `b` may import `a`, not the other way round.
fn planted_room(a: &str, b: &str) -> Vec<SourceFile> {
    let root = "//! A room.\n//!\n//! Files, bottom to top: each imports through `super::` only from those listed before it.\n\
                //! 1. [`a`]: the first.\n//! 2. [`b`]: the second.\n\n\
                mod a;\npub(crate) mod b;\n\npub use b::Thing;\npub struct Root;\n\n#[cfg(test)]\nmod tests;\n";
    [
        ("room/mod.rs", root),
        ("room/a.rs", a),
        ("room/b.rs", b),
        ("room/tests.rs", "use super::*;\nuse super::b::Thing;\n"),
    ]
    .into_iter()
    .map(|(path, text)| (PathBuf::from(path), text.to_string()))
    .collect()
}

#[test]
fn the_folder_check_passes_a_clean_room() {
    let b = "//! Uses `super::Root` in a comment only.\nuse super::a::A;\nuse crate::room::{a, a::A as B};\n\
             pub struct Thing(A, &'static str);\nconst S: &str = \"super::Root\";\nconst C: char = '\"';\n\
             fn f() -> self::super::a::A { super::a::A }\n";
    assert_eq!(folder_violations(&planted_room("pub struct A;\n", b)), Vec::<String>::new());
}

#[test]
fn the_folder_check_sees_a_planted_cycle() {
    let a = "use super::{\n    b::Thing,\n    Root,\n};\npub struct A;\n";
    let b = "use super::a::A;\nfn f() -> super::super::room::b::Thing { crate::room::Root }\n";
    assert_eq!(
        folder_violations(&planted_room(a, b)),
        [
            "src/room/a.rs:1: `a` imports `b`, listed after it in src/room/mod.rs: a cycle",
            "src/room/a.rs:1: `a` names `Root` of src/room/mod.rs: a cycle through the root file",
            "src/room/b.rs:2: `b` names `Root` of src/room/mod.rs: a cycle through the root file",
        ]
    );
    let b = "//! 1. [`c`]: the third.\nmod c;\npub struct Thing;\n";
    let c = "use super::super::a::A;\nuse super::super::Root;\nuse super::Thing;\n";
    let mut nested = planted_room("use super::*;\n", b);
    nested.push((PathBuf::from("room/b/c.rs"), c.to_string()));
    nested.push((PathBuf::from("room/lost/x.rs"), "pub struct Lost;\n".to_string()));
    assert_eq!(
        folder_violations(&nested),
        [
            "src/room/lost/: no root file (`mod.rs` in the folder, or a file of its name beside it)",
            "src/room/a.rs:1: `a` names `*` of src/room/mod.rs: a cycle through the root file",
            "src/room/b/c.rs:2: `b` names `Root` of src/room/mod.rs: a cycle through the root file",
            "src/room/b/c.rs:3: `c` names `Thing` of src/room/b.rs: a cycle through the root file",
        ]
    );
}

#[test]
fn the_folder_check_reads_lists_and_paths() {
    let root =
        "//! 1. [`a`]: fine.\n//! 3. [`b`]\n//! 3. [`a`]: twice.\nmod a;\npub(crate) mod b;\npub mod c;\n";
    let files =
        [(PathBuf::from("room/mod.rs"), root.to_string()), (PathBuf::from("room/a.rs"), String::new())];
    assert_eq!(
        list_problems(&folders(&files)[0]),
        [
            "src/room/mod.rs:2: `b` is numbered 3, not 2",
            "src/room/mod.rs:2: `b`: not in the form `//! N. [`child`]: what it holds`",
            "src/room/mod.rs:3: `a` is listed twice",
            "src/room/mod.rs: child module `c` is not listed (`//! N. [`c`]: ...`)",
        ]
    );
    let code = code_only("use super::{a::{self, B as C}, d::*}; // super::x\nlet s = r#\"crate::y\"#;");
    let paths: Vec<_> =
        written_paths(&code).into_iter().map(|(line, path)| (line, path.join("::"))).collect();
    assert_eq!(paths, [(1, "super::a::self".into()), (1, "super::a::B".into()), (1, "super::d::*".into())]);
    let module = ["room".to_string(), "b".to_string()];
    let words = |path: &str| path.split("::").map(str::to_string).collect::<Vec<_>>();
    assert_eq!(resolve(&module, &words("super::a::self")), Some(words("room::a")));
    assert_eq!(resolve(&module, &words("self::super::super::x")), Some(words("x")));
    assert_eq!(resolve(&module, &words("super::super::super::x")), None);
    assert_eq!(module_of(Path::new("room/b/mod.rs")), module);
    assert_eq!(inline_modules(&["pub mod inner {", "    use super::x;", "}"]), [(1, 3, "inner".to_string())]);
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
