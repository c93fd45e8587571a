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
//! material = "clay"
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
//! # Layout
//!
//! This file holds the scene as the renderer sees it (the types below) and [`Scene::load`];
//! `schema.rs` the file as written (serde), `validate.rs` the checks from one to the other,
//! `mesh.rs` the OBJ reader, `texture.rs` the textures, `obj_scene.rs` an OBJ file as a scene,
//! `adjacency.rs` the triangle neighbourhoods, `parameter_range.rs` the range of a material
//! parameter over a triangle and `settings.rs` each render setting's default and bounds.

pub mod adjacency;
mod mesh;
pub mod obj_scene;
mod parameter_range;
mod schema;
pub mod settings;
pub mod texture;
mod validate;

pub use parameter_range::ParameterRange;
pub use schema::UvProjection;
use texture::{MinMaxPyramid, Texture};

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Vec2, Vec3};
use serde::Deserialize;

/// A loaded, checked scene. Everything is in world space; meshes have their transforms applied.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The TOML (or OBJ) file the scene was loaded from, as given to [`Scene::load`].
    pub path: PathBuf,
    /// The scene file's `description` (empty where it has none); for an OBJ model, a line that
    /// names it.
    pub description: String,
    pub camera: Camera,
    pub settings: RenderSettings,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    /// At least one after [`Scene::load`].
    pub meshes: Vec<Mesh>,
    /// The world point (f64) that every position here is relative to: a scene whose meshes
    /// lie farther from zero than their own size is recentred on them at load time (a floating
    /// origin: meshes, camera and lights move together), so that its f32 coordinates keep
    /// their precision; zero for a scene around the origin, which stays as written.
    pub origin: DVec3,
    /// What loading could not use and how it stood in for it (an OBJ file given as the scene
    /// whose texture is missing, say), for the user to read; empty for a TOML scene.
    pub warnings: Vec<String>,
}

/// A perspective camera. `near` and `far` are always set after loading (derived from the
/// scene bounds when the file leaves them out).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    /// Unit length, not parallel to `target - eye` (not necessarily perpendicular to it).
    pub up: Vec3,
    /// Vertical field of view, in (0, 180).
    pub fov_y_degrees: f32,
    /// `0 < near < far`.
    pub near: f32,
    pub far: f32,
}

/// How the scene is to be rendered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Image size in pixels, each in 1..=16384.
    pub width: u32,
    pub height: u32,
    /// The shading-error bound ε, > 0.
    pub epsilon: f32,
    /// The maximum shading rate (samples per side of a patch), in 1..=64.
    pub n_max: u32,
    /// Linear scale applied to radiance before display, > 0.
    pub exposure: f32,
    /// Linear colour of pixels no mesh covers, each component ≥ 0.
    pub clear_color: Vec3,
    /// How polygonal lights are sampled (copied into every [`PolygonLight`]).
    pub light_sampling: LightSampling,
}

/// How the specular part of a polygonal light is estimated at a shading point (the `[render]`
/// keys `polygon_samples`, `polygon_sampling`, `mis_visibility`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSampling {
    /// Samples per shading point of each technique (light and BRDF), in 1..=256. The same
    /// low-discrepancy set at every point, so images do not flicker.
    pub samples: u32,
    /// How the light technique samples directions.
    pub technique: PolygonSampling,
    /// The visibility estimate `v` of clamped optimal MIS, in [0, 1].
    pub mis_visibility: f32,
}

/// The visibility estimate `v` of clamped optimal MIS that the paper uses throughout (B.3).
pub const DEFAULT_MIS_VISIBILITY: f32 = 0.5;

impl Default for LightSampling {
    fn default() -> Self {
        LightSampling {
            samples: 8,
            technique: PolygonSampling::ProjectedSolidAngle,
            mis_visibility: DEFAULT_MIS_VISIBILITY,
        }
    }
}

/// The light-sampling technique for polygonal lights (seed 004).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PolygonSampling {
    /// Proportional to projected solid angle (Algorithms 1–4): the cosine is importance
    /// sampled too.
    ProjectedSolidAngle,
    /// Uniform in solid angle over a triangle fan of the clipped polygon (Algorithm 5).
    SolidAngle,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: settings::DEFAULT_WIDTH,
            height: settings::DEFAULT_HEIGHT,
            epsilon: settings::DEFAULT_EPSILON,
            n_max: settings::DEFAULT_N_MAX,
            exposure: 1.0,
            clear_color: Vec3::ZERO,
            light_sampling: LightSampling::default(),
        }
    }
}

/// A named material; meshes refer to materials by index into [`Scene::materials`].
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    /// The BRDF. With a parameter map, its shininess or roughness is the map's `lo`.
    pub kind: MaterialKind,
    pub maps: MaterialMaps,
}

/// The textures of a material (seed 003 Sec. 3.5).
#[derive(Debug, Clone, Default)]
pub struct MaterialMaps {
    /// Multiplies the diffuse colour (Lambert and Blinn-Phong `kd`, GGX `albedo`) per pixel.
    pub albedo: Option<Arc<Texture>>,
    /// Blinn-Phong shininess or GGX roughness per texel.
    pub parameter: Option<ParameterMap>,
}

impl PartialEq for MaterialMaps {
    fn eq(&self, other: &Self) -> bool {
        let same = |a: &Option<Arc<Texture>>, b: &Option<Arc<Texture>>| match (a, b) {
            (Some(a), Some(b)) => a.path == b.path,
            (None, None) => true,
            _ => false,
        };
        same(&self.albedo, &other.albedo)
            && match (&self.parameter, &other.parameter) {
                (Some(a), Some(b)) => a.texture.path == b.texture.path && a.lo == b.lo && a.hi == b.hi,
                (None, None) => true,
                _ => false,
            }
    }
}

/// A shininess or roughness map: texel value `u` in [0, 1] (8-bit UNORM) stands for
/// [`ParameterMap::value`]`(u)`, between `lo` and `hi`.
#[derive(Debug, Clone)]
pub struct ParameterMap {
    pub texture: Arc<Texture>,
    /// Per-block minima and maxima of the texels, for the estimator's range over a triangle.
    pub pyramid: Arc<MinMaxPyramid>,
    pub lo: f32,
    pub hi: f32,
    pub mapping: ParameterMapping,
}

/// How a parameter map's texel value maps to the parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParameterMapping {
    /// `lo · (hi/lo)^u`: shininess, whose useful values span decades.
    Exponential,
    /// `lo + (hi − lo) · u`: roughness.
    Linear,
}

impl ParameterMap {
    /// The parameter a texel value `u` stands for (monotone in `u`). The exponential mapping
    /// uses the bit-exact `est_pow` ([`crate::exact_math`]), as the control stage does, so that the two agree bit
    /// for bit.
    pub fn value(&self, u: f32) -> f32 {
        let (lo, hi) = (self.lo, self.hi);
        match self.mapping {
            ParameterMapping::Exponential => lo * crate::exact_math::est_pow(hi / lo, u),
            ParameterMapping::Linear => lo + (hi - lo) * u,
        }
    }
}

impl ParameterMap {
    /// The coarsest level of detail at which the evaluation stage samples this map on a
    /// triangle with texture coordinates `uvs`: log2 of its texel extent, at least 0. The
    /// control stage's `lod_bound_of` in `glsl/multirate.tesc`, bit for bit.
    pub fn lod_bound(&self, uvs: [Vec2; 3]) -> f32 {
        let size = Vec2::new(self.texture.width() as f32, self.texture.height() as f32);
        let (lo, hi) = (uvs[0].min(uvs[1]).min(uvs[2]), uvs[0].max(uvs[1]).max(uvs[2]));
        let extent = (hi - lo) * size;
        crate::exact_math::est_log2(extent.x.max(extent.y).max(1.0))
    }

    /// The range of the parameter over the texels a triangle with texture coordinates `uvs`
    /// can sample (seed 003 Sec. 3.5), from the min/max pyramid: what the control stage's
    /// `parameter_range_of` computes, bit for bit.
    pub fn range_over(&self, uvs: [Vec2; 3]) -> ParameterRange {
        let (lo, hi) = (uvs[0].min(uvs[1]).min(uvs[2]), uvs[0].max(uvs[1]).max(uvs[2]));
        let (u_lo, u_hi) = self.pyramid.query(lo, hi, self.lod_bound(uvs));
        ParameterRange { lo: self.value(u_lo), hi: self.value(u_hi) }
    }
}

/// `material` with its shininess (Blinn-Phong) or roughness (GGX) replaced by `parameter`.
pub fn with_parameter(material: &MaterialKind, parameter: f32) -> MaterialKind {
    match *material {
        MaterialKind::Lambert { kd } => MaterialKind::Lambert { kd },
        MaterialKind::BlinnPhong { kd, ks, .. } => MaterialKind::BlinnPhong { kd, ks, shininess: parameter },
        MaterialKind::Ggx { albedo, f0, .. } => MaterialKind::Ggx { albedo, f0, roughness: parameter },
    }
}

/// The BRDF of a material and its parameters. Colours are linear, each component in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MaterialKind {
    /// Diffuse only: `kd · max(n·l, 0)`.
    Lambert { kd: Vec3 },
    /// Diffuse plus `ks · max(n·h, 0)^shininess` where `n·l > 0`; shininess in [1, 10⁴].
    BlinnPhong { kd: Vec3, ks: Vec3, shininess: f32 },
    /// Lambert `albedo` plus a GGX microfacet specular lobe with Schlick Fresnel from `f0`;
    /// roughness in [0, 1], α = roughness².
    Ggx { albedo: Vec3, f0: Vec3, roughness: f32 },
}

impl MaterialKind {
    /// Whether it has a specular lobe (Blinn-Phong or GGX), which reads the view direction.
    pub fn is_specular(&self) -> bool {
        !matches!(self, MaterialKind::Lambert { .. })
    }
}

/// A light. Irradiance from a point light falls off as 1/d²; a directional light's does not.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    Point {
        position: Vec3,
        color: Vec3,
        intensity: f32,
    },
    /// `direction` is unit length and is the direction the light travels (from the light into
    /// the scene), so the direction towards the light is `-direction`.
    Directional {
        direction: Vec3,
        color: Vec3,
        intensity: f32,
    },
    /// A polygonal area light (seed 004).
    Polygon(PolygonLight),
}

/// Most vertices a polygonal light may have (the shading's fixed-size polygons are sized for it).
pub const MAX_POLYGON_VERTICES: usize = 8;

/// A one-sided Lambertian emitter: a convex planar polygon of 3 to
/// [`MAX_POLYGON_VERTICES`] vertices with constant radiance `color · intensity` towards the
/// side from which its vertices wind anticlockwise (the side `normal` points to).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolygonLight {
    /// The first `count` entries are the vertices; the rest are zero.
    pub vertices: [Vec3; MAX_POLYGON_VERTICES],
    pub count: usize,
    /// Unit normal of the emitting side.
    pub normal: Vec3,
    pub area: f32,
    pub color: Vec3,
    pub intensity: f32,
    /// How its specular part is sampled: the scene's `[render]` settings.
    pub sampling: LightSampling,
}

impl PolygonLight {
    /// Checks `vertices` (3 to 8, finite, planar, strictly convex, simple) and builds the
    /// light; the error says what is wrong.
    pub fn new(vertices: &[Vec3], color: Vec3, intensity: f32) -> Result<PolygonLight, String> {
        let count = vertices.len();
        if !(3..=MAX_POLYGON_VERTICES).contains(&count) {
            return Err(format!("a polygon light needs 3 to {MAX_POLYGON_VERTICES} vertices, not {count}"));
        }
        if let Some(j) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(format!("vertex {} is not finite", j + 1));
        }
        // Newell's normal: twice the area vector, exact for planar polygons of any winding.
        let centroid = vertices.iter().sum::<Vec3>() / count as f32;
        let twice_area: Vec3 =
            (0..count).map(|j| (vertices[j] - centroid).cross(vertices[(j + 1) % count] - centroid)).sum();
        let size = vertices.iter().map(|v| (*v - centroid).length()).fold(0.0, f32::max);
        // (NaN fails these comparisons, and so is rejected.)
        let has_area = twice_area.length() > 1.0e-6 * size * size;
        if !has_area {
            return Err("the polygon has no area (its vertices are collinear or coincide)".into());
        }
        let normal = twice_area.normalize();
        for (j, v) in vertices.iter().enumerate() {
            let off = (*v - centroid).dot(normal);
            if off.abs() > 1.0e-4 * size {
                return Err(format!(
                    "the polygon is not planar: vertex {} lies {off:e} off the plane of the others",
                    j + 1
                ));
            }
        }
        // Strictly convex and simple: every corner turns the same way (positive about the
        // normal) and the turns add up to one full turn.
        let mut turning = 0.0;
        for j in 0..count {
            let a = vertices[(j + count - 1) % count];
            let b = vertices[j];
            let c = vertices[(j + 1) % count];
            let (e0, e1) = (b - a, c - b);
            let cross = e0.cross(e1).dot(normal);
            let turns_left = cross > 1.0e-6 * e0.length() * e1.length();
            if !turns_left {
                return Err(format!(
                    "the polygon is not convex at vertex {} (or two vertices coincide)",
                    j + 1
                ));
            }
            turning += cross.atan2(e0.dot(e1));
        }
        if (turning - std::f32::consts::TAU).abs() > 1.0e-3 {
            return Err("the polygon winds around more than once (it is not simple)".into());
        }
        let mut stored = [Vec3::ZERO; MAX_POLYGON_VERTICES];
        stored[..count].copy_from_slice(vertices);
        Ok(PolygonLight {
            vertices: stored,
            count,
            normal,
            area: 0.5 * twice_area.length(),
            color,
            intensity,
            sampling: LightSampling::default(),
        })
    }

    /// The vertices, in order.
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices[..self.count]
    }

    /// The emitted radiance, `color · intensity`.
    pub fn radiance(&self) -> Vec3 {
        self.color * self.intensity
    }
}

/// A triangle mesh in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub name: String,
    /// The OBJ file it was read from (the scene file's folder joined with the `obj` key).
    pub source: PathBuf,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// World space, transform applied; all finite.
    pub positions: Vec<Vec3>,
    /// World space, unit length, one per position.
    pub normals: Vec<Vec3>,
    /// Triangle list, at least one triangle, every index < `positions.len()`. Degenerate
    /// (zero-area) triangles from the file are kept.
    pub indices: Vec<u32>,
    /// Texture coordinates, one per position (from the OBJ file's `vt` or `uv_projection`),
    /// or empty when the mesh has none.
    pub uvs: Vec<Vec2>,
    /// Whether back faces are drawn. From the `two_sided` key; without it, closed meshes are
    /// one-sided (their back faces are hidden, so every mode culls them) and open ones
    /// two-sided.
    pub two_sided: bool,
}

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

/// The bytes of the file at `path`, which must be a regular file: a folder, a device such as
/// `/dev/zero` or a pipe is refused before it is read (they may never end).
pub(crate) fn read_file(path: &Path) -> std::io::Result<Vec<u8>> {
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        let what = if metadata.is_dir() { "a folder" } else { "a device, pipe or socket" };
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("it is {what}, not a regular file"),
        ));
    }
    std::fs::read(path)
}

/// The 1-based line of `bytes` on which its first byte that is not UTF-8 lies.
pub(crate) fn first_non_utf8_line(bytes: &[u8], error: &std::str::Utf8Error) -> usize {
    1 + bytes[..error.valid_up_to()].iter().filter(|&&b| b == b'\n').count()
}

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

    /// The number of triangles in all meshes (degenerate ones included).
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len() / 3).sum()
    }

    /// The world-space axis-aligned bounds `(min, max)` of every mesh vertex, or
    /// `(Vec3::ZERO, Vec3::ZERO)` for a scene without vertices (which `load` never returns).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        bounds_of(self.meshes.iter().flat_map(|m| m.positions.iter().copied()))
    }
}

fn bounds_of(points: impl Iterator<Item = Vec3>) -> (Vec3, Vec3) {
    let (min, max) = points.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)));
    if min.x > max.x {
        (Vec3::ZERO, Vec3::ZERO)
    } else {
        (min, max)
    }
}

#[cfg(test)]
mod tests;
