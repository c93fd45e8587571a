//! [`SceneError`]: why a scene could not be loaded, each message starting with the path of the
//! file at fault.

use std::path::PathBuf;

/// Why a scene could not be loaded. `Display` starts with the path of the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: cannot read file: {error}", path.display())]
    Io { path: PathBuf, error: std::io::Error },
    /// The scene file is not valid TOML, has an unknown key, a missing key or a value of the
    /// wrong type. `message` is the `toml` crate's.
    /// `text` is the offending line of the file, trimmed and shortened, so that the key is
    /// named even where the message does not name it.
    #[error("{}: {message}{}", path.display(), fmt_location(*line, *column, text))]
    Parse { path: PathBuf, message: String, line: Option<usize>, column: Option<usize>, text: String },
    /// The scene file parsed but a value is out of range or inconsistent. `item` names the
    /// table and key, e.g. `[[materials]] #2 ("shiny")`, `[camera]`.
    #[error("{}: {item}: {problem}", path.display())]
    Invalid { path: PathBuf, item: String, problem: String },
    /// An OBJ file named by the scene could not be read or used.
    #[error(
        "{}: {}{problem} (used by [[meshes]] #{mesh} in {})",
        path.display(),
        fmt_line(*line),
        scene.display()
    )]
    Obj { path: PathBuf, line: Option<usize>, problem: String, scene: PathBuf, mesh: usize },
    /// An OBJ file given as the scene, or one of its MTL files, could not be used.
    #[error("{}: {}{problem}", path.display(), fmt_line(*line))]
    Model { path: PathBuf, line: Option<usize>, problem: String },
}

fn fmt_location(line: Option<usize>, column: Option<usize>, text: &str) -> String {
    let text = if text.is_empty() { String::new() } else { format!(": `{text}`") };
    match (line, column) {
        (Some(l), Some(c)) => format!(" (line {l}, column {c}{text})"),
        (Some(l), None) => format!(" (line {l}{text})"),
        _ => String::new(),
    }
}

fn fmt_line(line: Option<usize>) -> String {
    line.map(|l| format!("line {l}: ")).unwrap_or_default()
}
