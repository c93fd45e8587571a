//! The cases: what one case writes and loads.

use super::*;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Target {
    /// `Scene::load` on `scene.toml`.
    SceneToml,
    /// `Scene::load` on `model.obj`, with `model.mtl`.
    ObjScene,
    /// `Texture::load`.
    Texture(TextureUsage),
}

/// One case: the files to write (name in the case's folder, bytes), the file the loader is
/// given, the names of the files that were mutated, and what was done to them.
pub(crate) struct Case {
    pub(crate) target: Target,
    pub(crate) files: Vec<(String, Vec<u8>)>,
    pub(crate) input: String,
    pub(crate) mutated: Vec<String>,
    pub(crate) log: String,
}

/// `count` random mutations of `data`, mixing byte- and (for text) line-level ones.
pub(crate) fn mutate(
    rng: &mut Rng,
    data: &mut Vec<u8>,
    name: &str,
    corpus: &Corpus,
    text: bool,
    log: &mut String,
) {
    let _ = write!(log, "{name}: ");
    let most = if rng.one_in(4) { 8 } else { 3 };
    let count = 1 + rng.below(most);
    for _ in 0..count {
        if text && rng.one_in(2) {
            mutate_lines(rng, data, corpus, log);
        } else if !text && rng.one_in(3) {
            mutate_header(rng, data, name, log);
        } else {
            mutate_bytes(rng, data, corpus, text, log);
        }
        if data.len() > MAX_INPUT {
            data.truncate(MAX_INPUT);
            let _ = write!(log, "cut to {MAX_INPUT} bytes; ");
        }
    }
    log.push('\n');
}

/// The quoted names after `key = ` in a scene file (its OBJ files or texture maps).
pub(crate) fn named_files(text: &str, keys: &[&str]) -> Vec<(String, String)> {
    text.lines()
        .filter_map(|line| {
            let (key, value) = line.split_once('=')?;
            let key = key.trim();
            let value = value.trim().strip_prefix('"')?.split('"').next()?;
            keys.contains(&key).then(|| (key.to_string(), value.to_string()))
        })
        .collect()
}

pub(crate) fn build_case(corpus: &Corpus, rng: &mut Rng) -> Case {
    let mut log = String::new();
    let mut mutated = Vec::new();
    match rng.below(10) {
        0..=3 => {
            let seed = rng.pick(&corpus.scenes);
            let text = String::from_utf8_lossy(&seed.bytes).into_owned();
            let _ = writeln!(log, "seed {}", seed.name);
            let mut files: Vec<(String, Vec<u8>)> = Vec::new();
            for (_, name) in named_files(&text, &["obj"]) {
                let mesh = if name.contains("plane") || name.contains("grid") {
                    &corpus.grid
                } else {
                    &corpus.sphere
                };
                if !files.iter().any(|(n, _)| *n == name) {
                    files.push((name, mesh.clone()));
                }
            }
            for (key, name) in named_files(&text, &["kd_map", "albedo_map", "shininess_map", "roughness_map"])
            {
                let map = if key.ends_with("albedo_map") || key == "kd_map" {
                    &corpus.albedo_map
                } else {
                    &corpus.parameter_map
                };
                if !files.iter().any(|(n, _)| *n == name) {
                    files.push((name, map.clone()));
                }
            }
            let mut scene = seed.bytes.clone();
            if !rng.one_in(5) || files.is_empty() {
                mutate(rng, &mut scene, "scene.toml", corpus, true, &mut log);
                mutated.push("scene.toml".to_string());
            }
            if mutated.is_empty() || rng.one_in(6) {
                let k = rng.below(files.len());
                let (name, bytes) = &mut files[k];
                let text = name.ends_with(".obj");
                mutate(rng, bytes, name, corpus, text, &mut log);
                mutated.push(name.clone());
            }
            files.push(("scene.toml".into(), scene));
            Case { target: Target::SceneToml, files, input: "scene.toml".into(), mutated, log }
        }
        4..=6 => {
            let seed = rng.pick(&corpus.models);
            let _ = writeln!(log, "seed {}", seed.name);
            let mut model = seed.bytes.clone();
            let mut mtl = corpus.mtl.clone();
            let choice = rng.below(4);
            if choice != 0 {
                mutate(rng, &mut model, "model.obj", corpus, true, &mut log);
                mutated.push("model.obj".to_string());
            }
            if choice != 1 {
                mutate(rng, &mut mtl, "model.mtl", corpus, true, &mut log);
                mutated.push("model.mtl".to_string());
            }
            let files = vec![
                ("model.obj".into(), model),
                ("model.mtl".into(), mtl),
                ("textures/albedo.png".into(), corpus.albedo_map.clone()),
                ("textures/bump.png".into(), corpus.parameter_map.clone()),
            ];
            Case { target: Target::ObjScene, files, input: "model.obj".into(), mutated, log }
        }
        _ => {
            let seed = rng.pick(&corpus.textures);
            let _ = writeln!(log, "seed {}", seed.name);
            let usage = if rng.one_in(2) { TextureUsage::Albedo } else { TextureUsage::Parameter };
            let extension = if rng.one_in(8) {
                *rng.pick(&["png", "jpg", "jpeg", "tga", "exr", "bin"])
            } else {
                seed.name.rsplit('.').next().unwrap_or("png")
            };
            let name = format!("texture.{extension}");
            let mut bytes = seed.bytes.clone();
            mutate(rng, &mut bytes, &name, corpus, false, &mut log);
            mutated.push(name.clone());
            Case {
                target: Target::Texture(usage),
                files: vec![(name.clone(), bytes)],
                input: name,
                mutated,
                log,
            }
        }
    }
}
