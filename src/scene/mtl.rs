//! An OBJ file's own materials: its MTL libraries read and turned into the renderer's BRDFs, and
//! its faces split into one part per material used. An OBJ file given as the scene
//! (`obj_scene.rs`) and a scene file's `[[meshes]]` entry with `materials = "mtl"`
//! (`validate.rs`) both take their materials from here.
//!
//! An MTL material becomes:
//! - `Kd` alone (or with a black `Ks`): Lambert;
//! - `Kd`, `Ks` and `Ns`: Blinn-Phong (`Ns` clamped to [1, 10⁴], 32 where it is missing);
//! - a PBR `Pr` (roughness) or `Pm` (metallic), where either is present: GGX with albedo
//!   `Kd·(1 − Pm)`, `f0 = 0.04·(1 − Pm) + Kd·Pm` and roughness `Pr` (default 0.5, 0);
//! - `map_Kd` is the albedo map (PNG, JPEG or TGA), multiplying `Kd`; texture coordinates outside
//!   [0, 1] repeat it.
//!
//! What cannot be used stands aside with a warning, as a model viewer would: a missing or
//! unreadable MTL file, a `usemtl` naming no material (both: the default material), a missing or
//! undecodable texture, a textured material on faces without texture coordinates (both: drawn
//! without the map) and colours outside [0, 1] (clamped). The statements the renderer does not
//! model ([`UNMODELLED`]: transparency, emission, ambient, specular, bump and other maps) are named
//! once per statement and library, with the materials in use that have them. A malformed or
//! non-finite number in an MTL file is an error naming the file and line.

use super::error::SceneError;
use super::mesh::{self, ObjProblem, Transform, TransformedMesh};
use super::model::{Material, MaterialKind, MaterialMaps};
use super::texture::{Texture, TextureUsage};

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;

/// The material of faces whose `usemtl` names nothing loaded, or that have none.
pub const DEFAULT_MATERIAL: MaterialKind =
    MaterialKind::BlinnPhong { kd: Vec3::splat(0.7), ks: Vec3::splat(0.2), shininess: 32.0 };

/// Blinn-Phong shininess where an MTL material has a specular colour but no `Ns`.
const DEFAULT_SHININESS: f32 = 32.0;

/// The MTL statements the renderer does not model, and what each is. `d` and `Tr` count where
/// they make a material less than opaque, `Ke` where it is not black; the maps always. Keys match
/// without regard to case (`map_bump` is `map_Bump`).
pub const UNMODELLED: [(&str, &str); 15] = [
    ("d", "transparency"),
    ("Tr", "transparency"),
    ("map_d", "transparency map"),
    ("Ke", "emission"),
    ("map_Ke", "emission map"),
    ("map_Ka", "ambient map"),
    ("map_Ks", "specular colour map"),
    ("map_Ns", "shininess map"),
    ("map_Bump", "bump map"),
    ("bump", "bump map"),
    ("norm", "normal map"),
    ("disp", "displacement map"),
    ("decal", "decal map"),
    ("refl", "reflection map"),
    ("map_Pr", "roughness map"),
];

/// The faces of an OBJ file that use one material, with the renderer's material for them.
pub(crate) struct Part {
    pub material: Material,
    pub geometry: TransformedMesh,
}

/// How a caller names a problem of a file it reads (the OBJ file or one of its MTL files).
pub(crate) type FileError<'a> = &'a dyn Fn(&Path, ObjProblem) -> SceneError;

/// An MTL file that was read: how many materials it added (in the order `tobj` merges them),
/// and per statement of [`UNMODELLED`] (by index) the materials that have it.
struct Library {
    path: PathBuf,
    count: usize,
    unmodelled: BTreeMap<usize, Vec<String>>,
}

/// The OBJ file at `path` (its contents `bytes`) split into one part per material used, in the
/// order the materials are defined (the default material last), each with `transform` applied;
/// its MTL libraries are read from beside it. What stands aside is added to `warnings`.
pub(crate) fn load_parts(
    path: &Path,
    bytes: &[u8],
    transform: &Transform,
    error: FileError,
    warnings: &mut Vec<String>,
) -> Result<Vec<Part>, SceneError> {
    let folder = path.parent().unwrap_or(Path::new(""));
    let unread = RefCell::new(Vec::new());
    let libraries: RefCell<Vec<Library>> = RefCell::new(Vec::new());
    let failure: RefCell<Option<SceneError>> = RefCell::new(None);
    let loader = |name: &Path| -> tobj::MTLLoadResult {
        let file = folder.join(file_name(&name.to_string_lossy()));
        match read_library(&file) {
            Ok(Some((parsed, unmodelled))) => {
                let count = parsed.as_ref().map_or(0, |(materials, _)| materials.len());
                libraries.borrow_mut().push(Library { path: file, count, unmodelled });
                parsed
            }
            Ok(None) => {
                unread.borrow_mut().push(format!(
                    "{}: cannot read its material library {}: its materials are drawn with the default material",
                    path.display(),
                    file.display()
                ));
                Err(tobj::LoadError::OpenFileFailed)
            }
            Err(problem) => {
                failure.borrow_mut().get_or_insert(error(&file, problem));
                Err(tobj::LoadError::MaterialParseError)
            }
        }
    };
    let parsed = mesh::parse_obj(bytes, &loader);
    if let Some(failure) = failure.into_inner() {
        return Err(failure);
    }
    let (models, materials) = parsed.map_err(|p| error(path, p))?;
    let materials = materials.unwrap_or_default();
    let libraries = libraries.into_inner();
    let unread = unread.into_inner();
    if unread.is_empty() {
        if libraries.is_empty() {
            warnings.push(format!(
                "{}: names no material library: drawn with the default material",
                path.display()
            ));
        }
        // (Where a library is missing, its names are unknown: that warning says it already.)
        warn_unknown_materials(path, bytes, &materials, warnings);
    }
    warnings.extend(unread);

    // One part per material used, in the order the materials are defined (the default last).
    let mut groups: BTreeMap<Option<usize>, Vec<&tobj::Model>> = BTreeMap::new();
    for model in models.iter().filter(|m| !m.mesh.indices.is_empty()) {
        let material = model.mesh.material_id.filter(|&i| i < materials.len());
        groups.entry(material).or_default().push(model);
    }
    if groups.is_empty() {
        return Err(error(
            path,
            ObjProblem::new("contains no triangles (no `f` lines with 3 or more vertices)"),
        ));
    }
    let mut ordered: Vec<_> = groups.into_iter().collect();
    if ordered[0].0.is_none() {
        ordered.rotate_left(1);
    }
    let used: Vec<usize> = ordered.iter().filter_map(|(material, _)| *material).collect();
    warn_unmodelled(&libraries, &materials, &used, warnings);
    let mut parts = Vec::with_capacity(ordered.len());
    for (material, models) in ordered {
        let geometry = mesh::assemble(&models, transform).map_err(|p| error(path, p))?;
        let mut material = match material {
            Some(i) => {
                let library =
                    library_of(&libraries, i).map_or(Path::new(""), |l| libraries[l].path.as_path());
                material_of(&materials[i], library, warnings)
            }
            None => {
                Material { name: "default".into(), kind: DEFAULT_MATERIAL, maps: MaterialMaps::default() }
            }
        };
        let textured = material.maps.albedo.is_some() || material.maps.parameter.is_some();
        if textured && !geometry.has_uvs() {
            warnings.push(format!(
                "{}: faces of material \"{}\" have no texture coordinates (`vt`): drawn without its texture",
                path.display(),
                material.name
            ));
            material.maps = MaterialMaps::default();
        }
        parts.push(Part { material, geometry });
    }
    Ok(parts)
}

/// The index of the library that material `index` came from.
fn library_of(libraries: &[Library], index: usize) -> Option<usize> {
    let mut first = 0;
    for (number, library) in libraries.iter().enumerate() {
        if index < first + library.count {
            return Some(number);
        }
        first += library.count;
    }
    None
}

/// One warning per library and statement of [`UNMODELLED`] that a material in `used` (indices
/// into `materials`) has, naming the materials.
fn warn_unmodelled(
    libraries: &[Library],
    materials: &[tobj::Material],
    used: &[usize],
    warnings: &mut Vec<String>,
) {
    for (index, library) in libraries.iter().enumerate() {
        for (&statement, names) in &library.unmodelled {
            let in_use: Vec<&String> = names
                .iter()
                .filter(|name| {
                    used.iter()
                        .any(|&i| materials[i].name == **name && library_of(libraries, i) == Some(index))
                })
                .collect();
            if in_use.is_empty() {
                continue;
            }
            let (key, what) = UNMODELLED[statement];
            let mut listed: Vec<String> = in_use.iter().take(3).map(|n| format!("\"{n}\"")).collect();
            if in_use.len() > 3 {
                listed.push(format!("and {} more", in_use.len() - 3));
            }
            let whose = if in_use.len() == 1 { "material" } else { "materials" };
            warnings.push(format!(
                "{}: `{key}` ({what}) is not modelled: left out of {whose} {}",
                library.path.display(),
                listed.join(", ")
            ));
        }
    }
}

/// A file name written in an OBJ or MTL file: exporters on Windows write `\` between folders,
/// and texture statements may carry options (`-bm 0.5 bump.png`) before the name.
fn file_name(written: &str) -> PathBuf {
    let written = written.trim();
    let name =
        if written.starts_with('-') { written.split_whitespace().last().unwrap_or(written) } else { written };
    PathBuf::from(name.replace('\\', "/"))
}

/// The MTL file at `path` parsed, with its statements the renderer does not model; `None` when
/// it cannot be read, a problem naming the line when a number in it is malformed or not finite.
#[allow(clippy::type_complexity)]
fn read_library(
    path: &Path,
) -> Result<Option<(tobj::MTLLoadResult, BTreeMap<usize, Vec<String>>)>, ObjProblem> {
    let Ok(bytes) = super::file::read_file(path) else {
        return Ok(None);
    };
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        ObjProblem::at(super::file::first_non_utf8_line(&bytes, &e), "is not valid UTF-8 text")
    })?;
    check_numbers(text)?;
    let parsed = tobj::load_mtl_buf(&mut text.as_bytes())
        .map_err(|e| ObjProblem::new(format!("cannot be parsed as a material library: {e}")))?;
    Ok(Some((Ok(parsed), unmodelled_statements(text))))
}

/// Per statement of [`UNMODELLED`] (by index) that `text` (an MTL file whose numbers are checked)
/// has where it changes the look, the materials that have it, in the order of the file.
fn unmodelled_statements(text: &str) -> BTreeMap<usize, Vec<String>> {
    let mut found: BTreeMap<usize, Vec<String>> = BTreeMap::new();
    let mut material = String::new();
    for line in text.lines() {
        let line = line.trim();
        let Some(key) = line.split_whitespace().next() else { continue };
        if key == "newmtl" {
            material = line["newmtl".len()..].trim().to_owned();
            continue;
        }
        let Some(index) = UNMODELLED.iter().position(|(k, _)| k.eq_ignore_ascii_case(key)) else {
            continue;
        };
        let values: Vec<f32> = line.split_whitespace().skip(1).filter_map(|v| v.parse().ok()).collect();
        let changes_the_look = match UNMODELLED[index].0 {
            "d" => values.iter().any(|&d| d < 1.0),
            "Tr" => values.iter().any(|&t| t > 0.0),
            "Ke" => values.iter().any(|&e| e > 0.0),
            _ => true,
        };
        let names = found.entry(index).or_default();
        if changes_the_look && !names.contains(&material) {
            names.push(material.clone());
        }
    }
    found.retain(|_, names| !names.is_empty());
    found
}

/// Checks the numbers of an MTL file's colour and scalar statements, which `tobj` reports
/// without a line or not at all.
fn check_numbers(text: &str) -> Result<(), ObjProblem> {
    const COLOURS: [&str; 5] = ["Ka", "Kd", "Ks", "Ke", "Tf"];
    const SCALARS: [&str; 8] = ["Ns", "Ni", "d", "Tr", "Pr", "Pm", "Ps", "Pc"];
    for (number, line) in text.lines().enumerate().map(|(i, l)| (i + 1, l)) {
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        let expected = if COLOURS.contains(&key) {
            3
        } else if SCALARS.contains(&key) {
            1
        } else {
            continue;
        };
        let values: Vec<&str> = words.collect();
        if values.len() != expected {
            let what = if expected == 3 { "three numbers (r g b)" } else { "one number" };
            return Err(ObjProblem::at(number, format!("`{key}` needs {what}, not `{}`", values.join(" "))));
        }
        for value in values {
            match value.parse::<f32>() {
                Ok(v) if v.is_finite() => {}
                Ok(v) => {
                    return Err(ObjProblem::at(
                        number,
                        format!("`{key}` has a value that is not finite ({v})"),
                    ))
                }
                Err(_) => {
                    return Err(ObjProblem::at(
                        number,
                        format!("`{key}` has `{value}`, which is not a number"),
                    ))
                }
            }
        }
    }
    Ok(())
}

/// Warns of each `usemtl` name that no material library defines.
fn warn_unknown_materials(
    path: &Path,
    bytes: &[u8],
    materials: &[tobj::Material],
    warnings: &mut Vec<String>,
) {
    let text = String::from_utf8_lossy(bytes);
    let mut unknown: Vec<&str> = Vec::new();
    for line in text.lines() {
        if let Some(name) = line.trim().strip_prefix("usemtl") {
            let name = name.trim();
            if !name.is_empty() && !materials.iter().any(|m| m.name == name) && !unknown.contains(&name) {
                unknown.push(name);
            }
        }
    }
    for name in unknown {
        warnings.push(format!(
            "{}: `usemtl {name}` names no material of its libraries: drawn with the default material",
            path.display()
        ));
    }
}

/// The renderer's material for an MTL material read from `library`.
fn material_of(m: &tobj::Material, library: &Path, warnings: &mut Vec<String>) -> Material {
    let here = format!("{}: material \"{}\"", library.display(), m.name);
    let mut clamped = Vec::new();
    let mut colour = |key: &str, v: Option<[f64; 3]>, default: f32| {
        let v = v.map_or(Vec3::splat(default), |c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32));
        let inside = v.clamp(Vec3::ZERO, Vec3::ONE);
        if inside != v {
            clamped.push(format!("`{key}` to [0, 1]"));
        }
        inside
    };
    let kd = colour("Kd", m.diffuse, 0.8);
    let ks = colour("Ks", m.specular, 0.0);
    let scalar = |key: &str| m.unknown_param.get(key).and_then(|v| v.trim().parse::<f32>().ok());
    let (roughness, metallic) = (scalar("Pr"), scalar("Pm"));
    let kind = if roughness.is_some() || metallic.is_some() {
        let metallic = metallic.unwrap_or(0.0).clamp(0.0, 1.0);
        MaterialKind::Ggx {
            albedo: kd * (1.0 - metallic),
            f0: Vec3::splat(0.04).lerp(kd, metallic),
            roughness: roughness.unwrap_or(0.5).clamp(0.0, 1.0),
        }
    } else if ks.max_element() > 0.0 {
        let given = m.shininess.map_or(DEFAULT_SHININESS, |n| n as f32);
        let shininess = given.clamp(1.0, 1.0e4);
        if shininess != given {
            clamped.push(format!("`Ns` = {given} to [1, 10000]"));
        }
        MaterialKind::BlinnPhong { kd, ks, shininess }
    } else {
        MaterialKind::Lambert { kd }
    };
    if !clamped.is_empty() {
        warnings.push(format!("{here}: clamped {}", clamped.join(", ")));
    }

    let folder = library.parent().unwrap_or(Path::new(""));
    let albedo = match &m.diffuse_texture {
        Some(written) => match Texture::load(&folder.join(file_name(written)), TextureUsage::Albedo) {
            Ok(texture) => Some(Arc::new(texture)),
            Err(e) => {
                warnings.push(format!("{here}: `map_Kd`: {e}: drawn with `Kd` alone"));
                None
            }
        },
        None => None,
    };
    Material { name: m.name.clone(), kind, maps: MaterialMaps { albedo, parameter: None } }
}

#[cfg(test)]
mod tests;
