//! A Wavefront OBJ file as a whole scene: `multirate render --scene model.obj`.
//!
//! The model's MTL materials become the renderer's BRDFs, one [`Mesh`] per material used (see
//! `mtl.rs` for how, and for what stands aside with a warning in [`Scene::warnings`]).
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
use super::model::{Camera, Light, Material, Mesh, RenderSettings, Scene, ShadowCaster};
use super::mtl::{self, Part};

use std::path::Path;

use glam::{DVec3, Vec3};

pub use super::mtl::DEFAULT_MATERIAL;

/// Vertical field of view of the framed camera, degrees.
const FOV_Y_DEGREES: f32 = 40.0;

/// Reads the OBJ file at `path` and what it refers to, and makes a scene of it.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let bytes =
        super::file::read_file(path).map_err(|error| SceneError::Io { path: path.to_path_buf(), error })?;
    let mut warnings = Vec::new();
    let parts = mtl::load_parts(path, &bytes, &Transform::default(), &model_error, &mut warnings)?;
    let (lo, hi) = parts
        .iter()
        .map(|part| part.geometry.bounds())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), (l, h)| (lo.min(l), hi.max(h)));
    let origin = mesh::recentring_origin(lo, hi);
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let mut scene_materials = Vec::with_capacity(parts.len());
    let mut meshes = Vec::with_capacity(parts.len());
    for (index, Part { mut material, geometry }) in parts.into_iter().enumerate() {
        let placed = geometry.place(origin).map_err(|p| model_error(path, p))?;
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
    let closed = adjacency::is_closed_together(&meshes);
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

fn model_error(path: &Path, problem: ObjProblem) -> SceneError {
    SceneError::Model { path: path.to_path_buf(), line: problem.line, problem: problem.message }
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
