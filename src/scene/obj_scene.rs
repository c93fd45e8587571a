//! A Wavefront OBJ file as a whole scene: `multirate render --scene model.obj`.
//!
//! The model's MTL materials become the renderer's BRDFs, one [`Mesh`] per material used:
//! - `Kd` alone (or with a black `Ks`) is Lambert;
//! - `Kd`, `Ks` and `Ns` are Blinn-Phong (`Ns` clamped to [1, 10⁴], 32 where it is missing);
//! - a PBR `Pr` (roughness) or `Pm` (metallic), where either is present, makes it GGX with
//!   albedo `Kd·(1 − Pm)`, `f0 = 0.04·(1 − Pm) + Kd·Pm` and roughness `Pr` (default 0.5, 0);
//! - `map_Kd` is the albedo map (PNG, JPEG or TGA), multiplying `Kd`.
//!
//! What cannot be used stands aside with a warning in [`Scene::warnings`], as a model viewer
//! would: a missing or unreadable MTL file, a `usemtl` naming no material (both: the default
//! material), a missing or undecodable texture, a textured material on faces without
//! texture coordinates (both: drawn without the map), colours outside [0, 1] (clamped), and the
//! MTL features the renderer does not model (transparency, emission, bump and specular maps).
//! A malformed or non-finite number in an MTL file is an error naming the file and line.
//!
//! The camera looks at the model's bounding sphere from the front (+Z), a little from the right
//! and above, framing it whole (from another side where that shows clearly more front-facing
//! area: the open side of a room); three lights follow the camera: a warm key light above left, a
//! cool fill light at the right (both points, giving about the same irradiance at the model for
//! any model size) and a directional light from above and behind; all three cast shadows.
//!
//! Faces without normals get smooth normals, per material. Neighbouring triangles of different
//! materials are different meshes: their shared edges may be subdivided differently (a
//! T-junction, which leaves at most single-pixel cracks along material seams).

use super::adjacency;
use super::error::SceneError;
use super::mesh::{self, ObjProblem, Transform};
use super::model::{
    Camera, Light, Material, MaterialKind, MaterialMaps, Mesh, RenderSettings, Scene, ShadowCaster,
};
use super::texture::{Texture, TextureUsage};

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Vec3};

/// The material of faces whose `usemtl` names nothing loaded, or that have none.
pub const DEFAULT_MATERIAL: MaterialKind =
    MaterialKind::BlinnPhong { kd: Vec3::splat(0.7), ks: Vec3::splat(0.2), shininess: 32.0 };

/// Blinn-Phong shininess where an MTL material has a specular colour but no `Ns`.
const DEFAULT_SHININESS: f32 = 32.0;

/// Vertical field of view of the framed camera, degrees.
const FOV_Y_DEGREES: f32 = 40.0;

/// Reads the OBJ file at `path` and what it refers to, and makes a scene of it.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let bytes =
        super::file::read_file(path).map_err(|error| SceneError::Io { path: path.to_path_buf(), error })?;
    let folder = path.parent().unwrap_or(Path::new(""));
    let warnings = RefCell::new(Vec::new());
    let libraries: RefCell<Vec<Library>> = RefCell::new(Vec::new());
    let failure: RefCell<Option<SceneError>> = RefCell::new(None);
    let loader = |name: &Path| -> tobj::MTLLoadResult {
        let file = folder.join(file_name(&name.to_string_lossy()));
        match read_library(&file) {
            Ok(Some(parsed)) => {
                let count = parsed.as_ref().map_or(0, |(materials, _)| materials.len());
                libraries.borrow_mut().push(Library { path: file, count });
                parsed
            }
            Ok(None) => {
                warnings.borrow_mut().push(format!(
                    "{}: cannot read its material library {}: its materials are drawn with the default material",
                    path.display(),
                    file.display()
                ));
                Err(tobj::LoadError::OpenFileFailed)
            }
            Err(error) => {
                failure.borrow_mut().get_or_insert(error);
                Err(tobj::LoadError::MaterialParseError)
            }
        }
    };
    let parsed = mesh::parse_obj(&bytes, &loader);
    if let Some(error) = failure.into_inner() {
        return Err(error);
    }
    let (models, materials) = parsed.map_err(|p| model_error(path, p))?;
    let materials = materials.unwrap_or_default();
    let libraries = libraries.into_inner();
    let mut warnings = warnings.into_inner();
    if warnings.is_empty() {
        if libraries.is_empty() {
            warnings.push(format!(
                "{}: names no material library: drawn with the default material",
                path.display()
            ));
        }
        // (Where a library is missing, its names are unknown: that warning says it already.)
        warn_unknown_materials(path, &bytes, &materials, &mut warnings);
    }

    // One mesh per material used, in the order the materials are defined (the default last).
    let mut groups: BTreeMap<Option<usize>, Vec<&tobj::Model>> = BTreeMap::new();
    for model in models.iter().filter(|m| !m.mesh.indices.is_empty()) {
        let material = model.mesh.material_id.filter(|&i| i < materials.len());
        groups.entry(material).or_default().push(model);
    }
    if groups.is_empty() {
        return Err(model_error(
            path,
            ObjProblem::new("contains no triangles (no `f` lines with 3 or more vertices)"),
        ));
    }
    let mut ordered: Vec<_> = groups.into_iter().collect();
    if ordered[0].0.is_none() {
        ordered.rotate_left(1);
    }
    let mut parts = Vec::with_capacity(ordered.len());
    for (material, models) in ordered {
        let transformed = mesh::assemble(&models, &Transform::default()).map_err(|p| model_error(path, p))?;
        let material = match material {
            Some(i) => material_of(&materials[i], &library_of(&libraries, i), &mut warnings)?,
            None => {
                Material { name: "default".into(), kind: DEFAULT_MATERIAL, maps: MaterialMaps::default() }
            }
        };
        parts.push((material, transformed));
    }

    let (lo, hi) = parts
        .iter()
        .map(|(_, t)| t.bounds())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), (l, h)| (lo.min(l), hi.max(h)));
    let origin = mesh::recentring_origin(lo, hi);
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let mut scene_materials = Vec::with_capacity(parts.len());
    let mut meshes = Vec::with_capacity(parts.len());
    for (index, (mut material, transformed)) in parts.into_iter().enumerate() {
        let placed = transformed.place(origin).map_err(|p| model_error(path, p))?;
        let textured = material.maps.albedo.is_some() || material.maps.parameter.is_some();
        if textured && placed.uvs.is_empty() {
            warnings.push(format!(
                "{}: faces of material \"{}\" have no texture coordinates (`vt`): drawn without its texture",
                path.display(),
                material.name
            ));
            material.maps = MaterialMaps::default();
        }
        if scene_materials.iter().any(|m: &Material| m.name == material.name) {
            material.name = format!("{} ({})", material.name, index + 1);
        }
        meshes.push(Mesh {
            name: format!("{stem}/{}", material.name),
            source: path.to_path_buf(),
            material: index,
            positions: placed.positions,
            normals: placed.normals,
            indices: placed.indices,
            uvs: placed.uvs,
            two_sided: true,
        });
        scene_materials.push(material);
    }
    // Closed as a whole (each material's part alone is open): back faces never show.
    let closed = adjacency::is_closed(&joined(&meshes));
    for mesh in &mut meshes {
        mesh.two_sided = !closed;
    }

    let (camera, lights) = frame(path, &meshes)?;
    let shadow_casters = casters_of(&lights);
    let triangles: usize = meshes.iter().map(|m| m.indices.len() / 3).sum();
    Ok(Scene {
        path: path.to_path_buf(),
        description: format!(
            "{} ({triangles} triangles, {} material{}): camera framed on its bounds, key, fill and directional lights casting shadows",
            path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
            scene_materials.len(),
            if scene_materials.len() == 1 { "" } else { "s" }
        ),
        camera,
        camera_path: None,
        settings: RenderSettings::default(),
        materials: scene_materials,
        lights,
        shadow_casters,
        meshes,
        origin,
        warnings,
    })
}

/// Every added light casts shadows, on maps of the default resolution: the key's hard (a sharp
/// key shadow shows the model's shape), the fill's and the directional light's through a 3 × 3
/// filter (softer, as light from wider sources).
fn casters_of(lights: &[Light]) -> Vec<ShadowCaster> {
    (0..lights.len())
        .map(|light| ShadowCaster {
            light,
            resolution: ShadowCaster::DEFAULT_RESOLUTION,
            filter: if light == 0 { 1 } else { 3 },
        })
        .collect()
}

/// An MTL file that was read, and how many materials it added (in the order `tobj` merges them).
struct Library {
    path: PathBuf,
    count: usize,
}

/// The MTL file that material `index` came from.
fn library_of(libraries: &[Library], index: usize) -> PathBuf {
    let mut first = 0;
    for library in libraries {
        if index < first + library.count {
            return library.path.clone();
        }
        first += library.count;
    }
    PathBuf::new()
}

/// A file name written in an OBJ or MTL file: exporters on Windows write `\` between folders,
/// and texture statements may carry options (`-bm 0.5 bump.png`) before the name.
fn file_name(written: &str) -> PathBuf {
    let written = written.trim();
    let name =
        if written.starts_with('-') { written.split_whitespace().last().unwrap_or(written) } else { written };
    PathBuf::from(name.replace('\\', "/"))
}

fn model_error(path: &Path, problem: ObjProblem) -> SceneError {
    SceneError::Model { path: path.to_path_buf(), line: problem.line, problem: problem.message }
}

/// The MTL file at `path` parsed, `None` when it cannot be read, an error naming the line when
/// a number in it is malformed or not finite.
fn read_library(path: &Path) -> Result<Option<tobj::MTLLoadResult>, SceneError> {
    let Ok(bytes) = super::file::read_file(path) else {
        return Ok(None);
    };
    let error =
        |line: Option<usize>, problem: String| SceneError::Model { path: path.to_path_buf(), line, problem };
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        error(Some(super::file::first_non_utf8_line(&bytes, &e)), "is not valid UTF-8 text".into())
    })?;
    check_numbers(text).map_err(|p| error(p.line, p.message))?;
    let parsed = tobj::load_mtl_buf(&mut text.as_bytes())
        .map_err(|e| error(None, format!("cannot be parsed as a material library: {e}")))?;
    Ok(Some(Ok(parsed)))
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
fn material_of(
    m: &tobj::Material,
    library: &Path,
    warnings: &mut Vec<String>,
) -> Result<Material, SceneError> {
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

    let mut left_out = Vec::new();
    let opacity = m.dissolve.map(|d| d as f32).or_else(|| scalar("Tr").map(|t| 1.0 - t));
    if let Some(opacity) = opacity.filter(|&o| o < 1.0) {
        left_out.push(format!("transparency (opacity {opacity})"));
    }
    if m.emissive.is_some_and(|e| e.iter().any(|&c| c > 0.0)) {
        left_out.push("emission (`Ke`)".into());
    }
    for (key, map) in [
        ("map_Ks", &m.specular_texture),
        ("map_Ns", &m.shininess_texture),
        ("map_Bump", &m.normal_texture),
        ("map_d", &m.dissolve_texture),
    ] {
        if map.is_some() {
            left_out.push(format!("`{key}`"));
        }
    }
    if !left_out.is_empty() {
        warnings.push(format!("{here}: not modelled, left out: {}", left_out.join(", ")));
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
    Ok(Material { name: m.name.clone(), kind, maps: MaterialMaps { albedo, parameter: None } })
}

/// All of `meshes` as one, for questions about the model as a whole.
fn joined(meshes: &[Mesh]) -> Mesh {
    let mut all = Mesh {
        name: String::new(),
        source: PathBuf::new(),
        material: 0,
        positions: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
        uvs: Vec::new(),
        two_sided: true,
    };
    for mesh in meshes {
        let base = all.positions.len() as u32;
        all.positions.extend_from_slice(&mesh.positions);
        all.indices.extend(mesh.indices.iter().map(|i| base + i));
    }
    all
}

/// The direction from the model to the camera: from the front (+Z), a little from the right
/// and above, or the same turned to the right, back or left side where that shows clearly more
/// front-facing area (the open side of a room or a box, say). A closed model shows about as
/// much from every side and keeps the front.
fn viewing_side(meshes: &[Mesh]) -> Vec3 {
    let front = Vec3::new(0.35, 0.3, 1.0).normalize();
    let sides = [0.0f32, 90.0, 180.0, 270.0].map(|yaw| glam::Quat::from_rotation_y(yaw.to_radians()) * front);
    let shown = |side: Vec3| -> f32 {
        meshes
            .iter()
            .flat_map(|m| {
                m.indices.chunks_exact(3).map(|t| {
                    let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
                    (b - a).cross(c - a).dot(side).max(0.0)
                })
            })
            .sum()
    };
    let areas = sides.map(shown);
    let best = (1..4).fold(0, |best, k| if areas[k] > areas[best] { k } else { best });
    if areas[best] > 1.25 * areas[0] {
        sides[best]
    } else {
        sides[0]
    }
}

/// A camera that frames `meshes` whole (the sphere about their bounds' centre that holds
/// them), and the lights that follow it.
fn frame(path: &Path, meshes: &[Mesh]) -> Result<(Camera, Vec<Light>), SceneError> {
    let (lo, hi) = super::model::bounds_of(meshes.iter().flat_map(|m| m.positions.iter().copied()));
    let centre = (lo + hi) * 0.5;
    let radius = meshes.iter().flat_map(|m| &m.positions).map(|p| p.distance(centre)).fold(0.0, f32::max);
    if radius <= 0.0 {
        return Err(model_error(
            path,
            ObjProblem::new("all its vertices are at one point: there is nothing to see"),
        ));
    }
    let too_large = || {
        model_error(
            path,
            ObjProblem::new(format!(
                "is too large to frame: its bounding sphere's radius {radius:e} puts the camera and \
                 lights beyond f32's range"
            )),
        )
    };
    if !radius.is_finite() {
        return Err(too_large());
    }
    let half_fov = (0.5 * FOV_Y_DEGREES).to_radians();
    // The bounding sphere just fits the vertical field of view, with a little margin.
    let distance = 1.1 * radius / half_fov.sin();
    let back = viewing_side(meshes);
    let eye = centre + distance * back;
    let right = Vec3::Y.cross(back).normalize();
    let up = back.cross(right);
    let far = (distance + radius) * 1.01;
    let camera = Camera {
        eye,
        target: centre,
        up: Vec3::Y,
        fov_y_degrees: FOV_Y_DEGREES,
        near: (0.5 * (distance - radius)).max(far * 1.0e-3),
        far,
    };
    // Point lights at twice the camera's distance, with intensities that give the model's
    // centre an irradiance of 0.8 (key) and 0.25 (fill) whatever its size.
    let reach = 2.0 * distance;
    let point = |direction: Vec3, irradiance: f32, color: Vec3| Light::Point {
        position: centre + reach * direction.normalize(),
        color,
        intensity: irradiance * reach * reach,
    };
    let lights = vec![
        point(-0.6 * right + 0.7 * up + 0.6 * back, 0.8, Vec3::new(1.0, 0.96, 0.9)),
        point(0.9 * right + 0.1 * up + 0.5 * back, 0.25, Vec3::new(0.85, 0.92, 1.0)),
        Light::Directional {
            direction: -(0.2 * right + 0.9 * up - 0.4 * back).normalize(),
            color: Vec3::ONE,
            intensity: 0.4,
        },
    ];
    let finite = |light: &Light| match light {
        Light::Point { position, intensity, .. } => position.is_finite() && intensity.is_finite(),
        _ => true,
    };
    if !(camera.eye.is_finite() && camera.far.is_finite() && camera.near > 0.0 && lights.iter().all(finite)) {
        return Err(too_large());
    }
    Ok((camera, lights))
}

#[cfg(test)]
mod tests;
