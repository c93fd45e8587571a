//! Scenes: the TOML scene schema, its validation, and OBJ mesh loading.
//!
//! This module owns everything between a scene file on disk and a checked, world-space
//! [`Scene`] in memory: the camera, the render settings (shading-error bound `epsilon`,
//! maximum shading rate `n_max`, exposure, image size), the materials (Lambert, Blinn-Phong,
//! GGX), the lights (point, directional, polygonal area lights) and the triangle meshes, read from Wavefront OBJ files
//! with their transforms applied and with finite, unit-length vertex normals. It knows nothing
//! of Vulkan or of how a scene is drawn.
//!
//! # File format
//!
//! A scene is one TOML file; paths in it are relative to the folder the file is in. Unknown
//! keys are errors. See `scenes/README.md` for the complete schema with every default; in short:
//!
//! ```toml
//! description = "Stanford bunny, Blinn-Phong, two point lights"   # optional
//! source = "free text: where the mesh came from"   # optional
//! [camera]
//! eye = [0.0, 0.1, 0.3]
//! target = [0.0, 0.1, 0.0]
//! up = [0.0, 1.0, 0.0]        # optional, default +Y
//! fov_y_degrees = 40.0
//! near = 0.01                  # optional, default 0.001 × far
//! far = 10.0                   # optional, default: just past the farthest corner of the bounds
//! [render]                     # optional, as is each key in it
//! width = 1280
//! height = 720
//! epsilon = 0.075
//! n_max = 16
//! exposure = 1.0
//! clear_color = [0.0, 0.0, 0.0]
//! [[materials]]
//! name = "clay"
//! type = "lambert"             # lambert (kd) | blinn_phong (kd, ks, shininess) | ggx (albedo, f0, roughness)
//! kd = [0.8, 0.8, 0.8]
//! [[meshes]]
//! obj = "bunny.obj"
//! material = "clay"            # or materials = "mtl": the OBJ file's own MTL materials
//! name = "bunny"               # optional, default the OBJ file's stem
//! translate = [0, 0, 0]        # optional
//! rotate_degrees = [0, 0, 0]   # optional: about X, then Y, then Z
//! scale = 1.0                  # optional: a number or [x, y, z]
//! [[lights]]
//! type = "point"               # point (position) | directional (direction) | polygon (vertices)
//! position = [1, 1, 1]
//! color = [1, 1, 1]
//! intensity = 2.0
//! [[lights]]
//! type = "polygon"             # a one-sided Lambertian emitter: 3 to 8 vertices, convex, planar;
//! vertices = [[0, 1, 0], [1, 1, 0], [1, 1, 1]]  # it emits towards the side they wind anticlockwise
//! color = [1, 1, 1]            # radiance = color × intensity
//! intensity = 5.0
//! ```
//!
//! Positions are read and placed in f64: a scene far from the world origin is recentred on its
//! meshes ([`Scene::origin`]), so that its f32 coordinates keep their precision.
//!
//! # Errors
//!
//! [`Scene::load`] never panics. Every [`SceneError`] displays as the path of the file at fault
//! (the TOML file or an OBJ file), then the item or line, then the problem, for example
//! `scenes/x.toml: [[meshes]] #2: material "steel" is not defined`.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`settings`]: each render setting's default and bounds.
//! 2. [`file`]: reading a scene's files.
//! 3. [`texture`]: the textures and the bounds of a parameter texture over a region.
//! 4. [`error`]: why a scene could not be loaded.
//! 5. [`path`]: a camera path, and the eye and target at any time of it.
//! 6. [`model`]: the scene as the renderer sees it, and a parameter's range over a triangle.
//! 7. [`schema`]: the scene file as written (serde).
//! 8. [`mesh`]: the OBJ reader.
//! 9. [`mtl`]: an OBJ file's own MTL materials, and its faces split by material.
//! 10. [`adjacency`]: the triangle neighbourhoods.
//! 11. [`obj_scene`]: an OBJ file as a scene.
//! 12. [`validate`]: the checks from the file as written to the scene.

pub mod adjacency;
mod error;
mod file;
mod mesh;
mod model;
mod mtl;
pub mod obj_scene;
pub mod path;
mod schema;
pub mod settings;
pub mod texture;
mod validate;

pub use error::SceneError;
pub use model::*;
pub use schema::UvProjection;

use file::{first_non_utf8_line, read_file};
use glam::Vec3;
use std::path::Path;

impl Scene {
    /// Reads, parses and checks the scene file at `path` and every OBJ file it names. A path
    /// ending in `.obj` is a model rather than a scene file: its materials come from its MTL
    /// files, and it gets a camera framed on it and default lights (see [`obj_scene`]).
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj")) {
            return obj_scene::load(path);
        }
        let bytes = read_file(path).map_err(|error| SceneError::Io { path: path.to_path_buf(), error })?;
        let text = std::str::from_utf8(&bytes).map_err(|e| SceneError::Parse {
            path: path.to_path_buf(),
            message: "is not valid UTF-8 text".into(),
            line: Some(first_non_utf8_line(&bytes, &e)),
            column: None,
            text: String::new(),
        })?;
        let file = schema::parse(path, text)?;
        validate::build(path, file)
    }

    /// This scene with no light casting shadows (the viewer's S, bench's `--without-shadows`).
    pub fn without_shadows(&self) -> Scene {
        Scene { shadow_casters: Vec::new(), ..self.clone() }
    }

    /// The number of triangles in all meshes (degenerate ones included).
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len() / 3).sum()
    }

    /// Every triangle of the meshes by its corners, mesh by mesh, in the order the renderer
    /// numbers them (a triangle id is its index here + 1).
    pub fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.meshes.iter().flat_map(|mesh| {
            mesh.indices.chunks_exact(3).map(|t| [0, 1, 2].map(|k| mesh.positions[t[k] as usize]))
        })
    }

    /// The world-space axis-aligned bounds `(min, max)` of every mesh vertex, or
    /// `(Vec3::ZERO, Vec3::ZERO)` for a scene without vertices (which `load` never returns).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        bounds_of(self.meshes.iter().flat_map(|m| m.positions.iter().copied()))
    }
}

#[cfg(test)]
mod tests;
