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

pub mod adjacency;
mod mesh;
pub mod obj_scene;
pub mod texture;

use crate::shading::polygon::MAX_POLYGON_VERTICES;
use texture::{MinMaxPyramid, Texture, TextureUsage};

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Vec2, Vec3};
use serde::de::{self, Deserializer, SeqAccess, Visitor};
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

impl Default for LightSampling {
    fn default() -> Self {
        LightSampling {
            samples: 8,
            technique: PolygonSampling::ProjectedSolidAngle,
            mis_visibility: crate::shading::polygon::DEFAULT_MIS_VISIBILITY,
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
            width: 1280,
            height: 720,
            epsilon: 0.075,
            n_max: 16,
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
    /// uses the estimator's `est_pow`, as the control stage does, so that the two agree bit
    /// for bit.
    pub fn value(&self, u: f32) -> f32 {
        let (lo, hi) = (self.lo, self.hi);
        match self.mapping {
            ParameterMapping::Exponential => lo * crate::shading::estimator::est_pow(hi / lo, u),
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
        crate::shading::estimator::est_log2(extent.x.max(extent.y).max(1.0))
    }

    /// The range of the parameter over the texels a triangle with texture coordinates `uvs`
    /// can sample (seed 003 Sec. 3.5), from the min/max pyramid: what the control stage's
    /// `parameter_range_of` computes, bit for bit.
    pub fn range_over(&self, uvs: [Vec2; 3]) -> crate::shading::estimator::ParameterRange {
        let (lo, hi) = (uvs[0].min(uvs[1]).min(uvs[2]), uvs[0].max(uvs[1]).max(uvs[2]));
        let (u_lo, u_hi) = self.pyramid.query(lo, hi, self.lod_bound(uvs));
        crate::shading::estimator::ParameterRange { lo: self.value(u_lo), hi: self.value(u_hi) }
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
        let file: SceneFile = toml::from_str(text).map_err(|e| {
            let (line, column, snippet) = match e.span() {
                Some(span) => {
                    let (l, c) = line_column(text, span.start);
                    (Some(l), Some(c), line_text(text, l))
                }
                None => (None, None, String::new()),
            };
            SceneError::Parse {
                path: path.to_path_buf(),
                message: e.message().trim().lines().map(str::trim).collect::<Vec<_>>().join("; "),
                line,
                column,
                text: snippet,
            }
        })?;
        build(path, file)
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

/// 1-based line and column (in characters) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[line_start..].chars().count() + 1)
}

/// Line `line` (1-based) of `text`, trimmed, cut to at most 60 characters.
fn line_text(text: &str, line: usize) -> String {
    let full = text.lines().nth(line.saturating_sub(1)).unwrap_or("").trim();
    let mut short: String = full.chars().take(60).collect();
    if short.len() < full.len() {
        short.push_str("...");
    }
    short
}

// ---------------------------------------------------------------------------------------------
// The file as written (serde), before checking.

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    /// Optional: what the scene shows (free text); empty in [`Scene::description`] without it.
    description: Option<String>,
    /// Optional: where the meshes come from (free text, for the people who read the file).
    source: Option<String>,
    camera: CameraFile,
    #[serde(default)]
    render: RenderFile,
    #[serde(default)]
    materials: Vec<MaterialFile>,
    #[serde(default)]
    meshes: Vec<MeshFile>,
    #[serde(default)]
    lights: Vec<LightFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    eye: [f64; 3],
    target: [f64; 3],
    up: Option<[f32; 3]>,
    fov_y_degrees: f32,
    near: Option<f32>,
    far: Option<f32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
struct RenderFile {
    width: u32,
    height: u32,
    epsilon: f32,
    n_max: u32,
    exposure: f32,
    clear_color: [f32; 3],
    polygon_samples: u32,
    polygon_sampling: PolygonSampling,
    mis_visibility: f32,
}

impl Default for RenderFile {
    fn default() -> Self {
        let d = RenderSettings::default();
        RenderFile {
            width: d.width,
            height: d.height,
            epsilon: d.epsilon,
            n_max: d.n_max,
            exposure: d.exposure,
            clear_color: d.clear_color.to_array(),
            polygon_samples: d.light_sampling.samples,
            polygon_sampling: d.light_sampling.technique,
            mis_visibility: d.light_sampling.mis_visibility,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case")]
enum MaterialType {
    Lambert,
    BlinnPhong,
    Ggx,
}

impl MaterialType {
    fn as_str(self) -> &'static str {
        match self {
            MaterialType::Lambert => "lambert",
            MaterialType::BlinnPhong => "blinn_phong",
            MaterialType::Ggx => "ggx",
        }
    }
}

/// One flat table for every material type, so that serde keeps exact error positions; which
/// keys a type needs and allows is checked in [`check_material`].
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFile {
    name: String,
    #[serde(rename = "type")]
    kind: MaterialType,
    kd: Option<[f32; 3]>,
    ks: Option<[f32; 3]>,
    shininess: Option<f32>,
    albedo: Option<[f32; 3]>,
    f0: Option<[f32; 3]>,
    roughness: Option<f32>,
    kd_map: Option<PathBuf>,
    albedo_map: Option<PathBuf>,
    shininess_map: Option<PathBuf>,
    shininess_range: Option<[f32; 2]>,
    roughness_map: Option<PathBuf>,
    roughness_range: Option<[f32; 2]>,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case")]
enum LightType {
    Point,
    Directional,
    Polygon,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightFile {
    #[serde(rename = "type")]
    kind: LightType,
    position: Option<[f64; 3]>,
    direction: Option<[f32; 3]>,
    vertices: Option<Vec<[f64; 3]>>,
    color: [f32; 3],
    intensity: f32,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshFile {
    obj: PathBuf,
    material: String,
    name: Option<String>,
    translate: Option<[f64; 3]>,
    rotate_degrees: Option<[f32; 3]>,
    scale: Option<Scale>,
    uv_projection: Option<UvProjection>,
    uv_scale: Option<[f32; 2]>,
    two_sided: Option<bool>,
}

/// Texture coordinates computed from world-space positions, about the centre of the mesh's
/// bounding box: `cylindrical` (u around +Y, v up), `spherical` (u around +Y, v from the top)
/// or `planar` (the XZ plane). Triangles that cross the u seam get their own vertices, with
/// u continued past 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UvProjection {
    Cylindrical,
    Spherical,
    Planar,
}

/// `scale = 2.0` or `scale = [1, 2, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Scale([f32; 3]);

impl<'de> Deserialize<'de> for Scale {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ScaleVisitor;

        impl<'de> Visitor<'de> for ScaleVisitor {
            type Value = Scale;

            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an array of three numbers")
            }

            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }

            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }

            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Scale, A::Error> {
                let mut xyz = [0.0f32; 3];
                for (i, c) in xyz.iter_mut().enumerate() {
                    *c = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                let mut extra = 3;
                while seq.next_element::<de::IgnoredAny>()?.is_some() {
                    extra += 1;
                }
                if extra > 3 {
                    return Err(de::Error::invalid_length(extra, &self));
                }
                Ok(Scale(xyz))
            }
        }

        deserializer.deserialize_any(ScaleVisitor)
    }
}

// ---------------------------------------------------------------------------------------------
// Checking.

/// Builds errors for one item of one file.
struct Item<'a> {
    path: &'a Path,
    item: String,
}

impl Item<'_> {
    fn error(&self, problem: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            path: self.path.to_path_buf(),
            item: self.item.clone(),
            problem: problem.into(),
        }
    }

    fn finite(&self, key: &str, v: f32) -> Result<f32, SceneError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(format!("`{key}` = {v} is not a finite number")))
        }
    }

    /// A world position (f64 in the file) relative to the scene's `origin`, in f32.
    fn point(&self, key: &str, v: [f64; 3], origin: DVec3) -> Result<Vec3, SceneError> {
        let world = self.dvec3(key, v)?;
        let placed = (world - origin).as_vec3();
        if placed.is_finite() {
            Ok(placed)
        } else {
            Err(self.error(format!(
                "`{key}` = {} is too far from the scene's meshes: not a finite number in f32",
                fmt_array(v)
            )))
        }
    }

    fn dvec3(&self, key: &str, v: [f64; 3]) -> Result<DVec3, SceneError> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(DVec3::from_array(v))
        } else {
            Err(self.error(format!("`{key}` = {} has a component that is not a finite number", fmt_array(v))))
        }
    }

    fn vec3(&self, key: &str, v: [f32; 3]) -> Result<Vec3, SceneError> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(Vec3::from_array(v))
        } else {
            Err(self.error(format!("`{key}` = {} has a component that is not a finite number", fmt_array(v))))
        }
    }

    /// A finite number in `lo..=hi` (or `lo < v` / `v < hi` where the bound is open).
    fn range(&self, key: &str, v: f32, lo: Bound, hi: Bound) -> Result<f32, SceneError> {
        let v = self.finite(key, v)?;
        if lo.below(v) && hi.above(v) {
            Ok(v)
        } else {
            Err(self.error(format!("`{key}` = {v} is outside {}", fmt_interval(lo, hi))))
        }
    }

    fn vec3_range(&self, key: &str, v: [f32; 3], lo: Bound, hi: Bound) -> Result<Vec3, SceneError> {
        let v3 = self.vec3(key, v)?;
        if v.iter().all(|&c| lo.below(c) && hi.above(c)) {
            Ok(v3)
        } else {
            Err(self.error(format!(
                "`{key}` = {} has a component outside {}",
                fmt_array(v),
                fmt_interval(lo, hi)
            )))
        }
    }

    fn required<T>(&self, key: &str, v: Option<T>, why: &str) -> Result<T, SceneError> {
        v.ok_or_else(|| self.error(format!("missing `{key}` (required {why})")))
    }

    fn forbidden<T>(&self, key: &str, v: &Option<T>, why: &str) -> Result<(), SceneError> {
        match v {
            Some(_) => Err(self.error(format!("`{key}` does not apply {why}"))),
            None => Ok(()),
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum Bound {
    Closed(f32),
    Open(f32),
    None,
}

impl Bound {
    /// Whether `v` is on the allowed side of this bound taken as a lower bound.
    fn below(self, v: f32) -> bool {
        match self {
            Bound::Closed(b) => v >= b,
            Bound::Open(b) => v > b,
            Bound::None => true,
        }
    }

    /// Whether `v` is on the allowed side of this bound taken as an upper bound.
    fn above(self, v: f32) -> bool {
        match self {
            Bound::Closed(b) => v <= b,
            Bound::Open(b) => v < b,
            Bound::None => true,
        }
    }
}

fn fmt_interval(lo: Bound, hi: Bound) -> String {
    let lo = match lo {
        Bound::Closed(b) => format!("[{b}"),
        Bound::Open(b) => format!("({b}"),
        Bound::None => "(-inf".to_string(),
    };
    let hi = match hi {
        Bound::Closed(b) => format!("{b}]"),
        Bound::Open(b) => format!("{b})"),
        Bound::None => "inf)".to_string(),
    };
    format!("{lo}, {hi}")
}

fn fmt_array<T: std::fmt::Display>(v: [T; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

use Bound::{Closed, Open};

fn build(path: &Path, file: SceneFile) -> Result<Scene, SceneError> {
    let top = |key: &str| Item { path, item: format!("`{key}`") };
    if file.source.as_deref().is_some_and(|s| s.trim().is_empty()) {
        return Err(top("source").error("is empty: say where the meshes come from, or leave the key out"));
    }

    let settings = check_render(path, &file.render)?;

    let folder = path.parent().unwrap_or(Path::new(""));
    let mut materials: Vec<Material> = Vec::with_capacity(file.materials.len());
    for (i, m) in file.materials.iter().enumerate() {
        let material = check_material(path, folder, i, m)?;
        if materials.iter().any(|other| other.name == material.name) {
            return Err(Item { path, item: format!("[[materials]] #{} (\"{}\")", i + 1, m.name) }
                .error(format!("duplicate material name \"{}\"", m.name)));
        }
        materials.push(material);
    }

    if file.lights.is_empty() {
        return Err(top("lights").error("the scene has no lights; add at least one [[lights]] table"));
    }
    let check_lights = |origin| {
        file.lights
            .iter()
            .enumerate()
            .map(|(i, l)| check_light(path, i, l, settings.light_sampling, origin))
            .collect::<Result<Vec<_>, _>>()
    };
    let mut lights = check_lights(DVec3::ZERO)?;

    // The camera checks that do not need the meshes come first, so that a mistake there is
    // reported without reading any OBJ file.
    let camera_item = Item { path, item: "[camera]".to_string() };
    let mut camera = check_camera(&camera_item, &file.camera, DVec3::ZERO)?;

    if file.meshes.is_empty() {
        return Err(top("meshes").error("the scene has no meshes; add at least one [[meshes]] table"));
    }
    let mut geometry = Vec::with_capacity(file.meshes.len());
    for (i, m) in file.meshes.iter().enumerate() {
        geometry.push(read_mesh(path, folder, i, m, &materials)?);
    }
    // The floating origin: lights and camera were checked at the world origin above, so that
    // their mistakes are reported before any OBJ file is read; far from it they are placed again.
    let (lo, hi) = geometry
        .iter()
        .map(|g| g.2.bounds())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), (l, h)| (lo.min(l), hi.max(h)));
    let origin = mesh::recentring_origin(lo, hi);
    if origin != DVec3::ZERO {
        lights = check_lights(origin)?;
        camera = check_camera(&camera_item, &file.camera, origin)?;
    }
    let mut meshes = Vec::with_capacity(geometry.len());
    for (i, (name, source, transformed)) in geometry.into_iter().enumerate() {
        meshes.push(finish_mesh(path, i, &file.meshes[i], &materials, name, source, transformed, origin)?);
    }

    // Emitters are drawn too, so the default far plane must reach them.
    let emitters = lights.iter().flat_map(|l| match l {
        Light::Polygon(p) => p.vertices().to_vec(),
        _ => Vec::new(),
    });
    let (lo, hi) = bounds_of(meshes.iter().flat_map(|m: &Mesh| m.positions.iter().copied()).chain(emitters));
    let camera = finish_camera(&camera_item, camera, &file.camera, lo, hi)?;

    Ok(Scene {
        path: path.to_path_buf(),
        description: file.description.unwrap_or_default(),
        camera,
        settings,
        materials,
        lights,
        meshes,
        origin,
        warnings: Vec::new(),
    })
}

fn check_render(path: &Path, r: &RenderFile) -> Result<RenderSettings, SceneError> {
    let item = Item { path, item: "[render]".to_string() };
    let size = |key: &str, v: u32| {
        if (1..=16384).contains(&v) {
            Ok(v)
        } else {
            Err(item.error(format!("`{key}` = {v} is outside 1..=16384")))
        }
    };
    let width = size("width", r.width)?;
    let height = size("height", r.height)?;
    if !(1..=64).contains(&r.n_max) {
        return Err(item.error(format!("`n_max` = {} is outside 1..=64", r.n_max)));
    }
    if !(1..=256).contains(&r.polygon_samples) {
        return Err(item.error(format!("`polygon_samples` = {} is outside 1..=256", r.polygon_samples)));
    }
    Ok(RenderSettings {
        width,
        height,
        epsilon: item.range("epsilon", r.epsilon, Open(0.0), Bound::None)?,
        n_max: r.n_max,
        exposure: item.range("exposure", r.exposure, Open(0.0), Bound::None)?,
        clear_color: item.vec3_range("clear_color", r.clear_color, Closed(0.0), Bound::None)?,
        light_sampling: LightSampling {
            samples: r.polygon_samples,
            technique: r.polygon_sampling,
            mis_visibility: item.range("mis_visibility", r.mis_visibility, Closed(0.0), Closed(1.0))?,
        },
    })
}

fn check_material(
    path: &Path,
    folder: &Path,
    index: usize,
    m: &MaterialFile,
) -> Result<Material, SceneError> {
    let item = Item { path, item: format!("[[materials]] #{} (\"{}\")", index + 1, m.name) };
    if m.name.trim().is_empty() {
        return Err(item.error("`name` is empty"));
    }
    let why = format!("for type \"{}\"", m.kind.as_str());
    let why_not = format!("to type \"{}\"", m.kind.as_str());
    let unit = |key: &str, v: [f32; 3]| item.vec3_range(key, v, Closed(0.0), Closed(1.0));
    let kind = match m.kind {
        MaterialType::Lambert => {
            for (key, v) in [("ks", &m.ks), ("albedo", &m.albedo), ("f0", &m.f0)] {
                item.forbidden(key, v, &why_not)?;
            }
            item.forbidden("shininess", &m.shininess, &why_not)?;
            item.forbidden("roughness", &m.roughness, &why_not)?;
            MaterialKind::Lambert { kd: unit("kd", item.required("kd", m.kd, &why)?)? }
        }
        MaterialType::BlinnPhong => {
            for (key, v) in [("albedo", &m.albedo), ("f0", &m.f0)] {
                item.forbidden(key, v, &why_not)?;
            }
            item.forbidden("roughness", &m.roughness, &why_not)?;
            let shininess = match m.shininess_range {
                Some(range) => {
                    item.forbidden("shininess", &m.shininess, "together with `shininess_range`")?;
                    check_parameter_range(&item, "shininess_range", range, 1.0, 1e4)?[0]
                }
                None => item.range(
                    "shininess",
                    item.required("shininess", m.shininess, &why)?,
                    Closed(1.0),
                    Closed(1e4),
                )?,
            };
            MaterialKind::BlinnPhong {
                kd: unit("kd", item.required("kd", m.kd, &why)?)?,
                ks: unit("ks", item.required("ks", m.ks, &why)?)?,
                shininess,
            }
        }
        MaterialType::Ggx => {
            for (key, v) in [("kd", &m.kd), ("ks", &m.ks)] {
                item.forbidden(key, v, &why_not)?;
            }
            item.forbidden("shininess", &m.shininess, &why_not)?;
            let roughness = match m.roughness_range {
                Some(range) => {
                    item.forbidden("roughness", &m.roughness, "together with `roughness_range`")?;
                    check_parameter_range(&item, "roughness_range", range, 0.0, 1.0)?[0]
                }
                None => item.range(
                    "roughness",
                    item.required("roughness", m.roughness, &why)?,
                    Closed(0.0),
                    Closed(1.0),
                )?,
            };
            MaterialKind::Ggx {
                albedo: unit("albedo", item.required("albedo", m.albedo, &why)?)?,
                f0: unit("f0", item.required("f0", m.f0, &why)?)?,
                roughness,
            }
        }
    };
    let maps = check_maps(&item, folder, m, &why_not)?;
    Ok(Material { name: m.name.clone(), kind, maps })
}

/// `[lo, hi]` with `min ≤ lo ≤ hi ≤ max`.
fn check_parameter_range(
    item: &Item,
    key: &str,
    range: [f32; 2],
    min: f32,
    max: f32,
) -> Result<[f32; 2], SceneError> {
    let [lo, hi] = range;
    if !(lo.is_finite() && hi.is_finite() && min <= lo && lo <= hi && hi <= max) {
        return Err(item.error(format!("`{key}` = [{lo}, {hi}] must satisfy {min} <= lo <= hi <= {max}")));
    }
    Ok(range)
}

/// The material's texture keys: which apply to its type, that a map and its range come
/// together, and the files themselves (read here, so that a bad file names the material).
fn check_maps(
    item: &Item,
    folder: &Path,
    m: &MaterialFile,
    why_not: &str,
) -> Result<MaterialMaps, SceneError> {
    let (albedo_key, albedo_path, other_albedo) = match m.kind {
        MaterialType::Ggx => ("albedo_map", &m.albedo_map, ("kd_map", &m.kd_map)),
        _ => ("kd_map", &m.kd_map, ("albedo_map", &m.albedo_map)),
    };
    item.forbidden(other_albedo.0, other_albedo.1, why_not)?;
    let (map_key, range_key, map, range, other_map, other_range, mapping) = match m.kind {
        MaterialType::Lambert => {
            item.forbidden("shininess_map", &m.shininess_map, why_not)?;
            item.forbidden("roughness_map", &m.roughness_map, why_not)?;
            item.forbidden("shininess_range", &m.shininess_range, why_not)?;
            item.forbidden("roughness_range", &m.roughness_range, why_not)?;
            ("", "", &None, &None, ("", &None), ("", &None), ParameterMapping::Linear)
        }
        MaterialType::BlinnPhong => (
            "shininess_map",
            "shininess_range",
            &m.shininess_map,
            &m.shininess_range,
            ("roughness_map", &m.roughness_map),
            ("roughness_range", &m.roughness_range),
            ParameterMapping::Exponential,
        ),
        MaterialType::Ggx => (
            "roughness_map",
            "roughness_range",
            &m.roughness_map,
            &m.roughness_range,
            ("shininess_map", &m.shininess_map),
            ("shininess_range", &m.shininess_range),
            ParameterMapping::Linear,
        ),
    };
    item.forbidden(other_map.0, other_map.1, why_not)?;
    item.forbidden(other_range.0, other_range.1, why_not)?;
    let load = |key: &str, file: &Path, usage: TextureUsage| {
        Texture::load(&folder.join(file), usage)
            .map(Arc::new)
            .map_err(|e| item.error(format!("`{key}`: {e}")))
    };
    let albedo = match albedo_path {
        Some(file) => Some(load(albedo_key, file, TextureUsage::Albedo)?),
        None => None,
    };
    let parameter = match (map, range) {
        (Some(file), Some([lo, hi])) => {
            let texture = load(map_key, file, TextureUsage::Parameter)?;
            let pyramid = Arc::new(MinMaxPyramid::new(&texture));
            Some(ParameterMap { texture, pyramid, lo: *lo, hi: *hi, mapping })
        }
        (Some(_), None) => return Err(item.error(format!("`{map_key}` needs `{range_key}` = [lo, hi]"))),
        (None, Some(_)) => return Err(item.error(format!("`{range_key}` is given without `{map_key}`"))),
        (None, None) => None,
    };
    Ok(MaterialMaps { albedo, parameter })
}

fn check_light(
    path: &Path,
    index: usize,
    l: &LightFile,
    sampling: LightSampling,
    origin: DVec3,
) -> Result<Light, SceneError> {
    let kind = match l.kind {
        LightType::Point => "point",
        LightType::Directional => "directional",
        LightType::Polygon => "polygon",
    };
    let item = Item { path, item: format!("[[lights]] #{} ({kind})", index + 1) };
    let color = item.vec3_range("color", l.color, Closed(0.0), Bound::None)?;
    let intensity = item.range("intensity", l.intensity, Closed(0.0), Bound::None)?;
    let why = format!("for type \"{kind}\"");
    let why_not = format!("to type \"{kind}\"");
    Ok(match l.kind {
        LightType::Point => {
            let position = item.point("position", item.required("position", l.position, &why)?, origin)?;
            item.forbidden("direction", &l.direction, &why_not)?;
            item.forbidden("vertices", &l.vertices, &why_not)?;
            Light::Point { position, color, intensity }
        }
        LightType::Polygon => {
            let raw = item.required("vertices", l.vertices.as_ref(), &why)?;
            item.forbidden("position", &l.position, &why_not)?;
            item.forbidden("direction", &l.direction, &why_not)?;
            let vertices =
                raw.iter().map(|v| item.point("vertices", *v, origin)).collect::<Result<Vec<_>, _>>()?;
            let light = PolygonLight::new(&vertices, color, intensity)
                .map_err(|problem| item.error(format!("`vertices`: {problem}")))?;
            Light::Polygon(PolygonLight { sampling, ..light })
        }
        LightType::Directional => {
            let raw = item.required("direction", l.direction, &why)?;
            item.forbidden("position", &l.position, &why_not)?;
            item.forbidden("vertices", &l.vertices, &why_not)?;
            let direction = item.vec3("direction", raw)?.normalize_or_zero();
            if direction == Vec3::ZERO || !direction.is_finite() {
                return Err(item.error(format!("`direction` = {} is zero", fmt_array(raw))));
            }
            Light::Directional { direction, color, intensity }
        }
    })
}

/// Checks everything about the camera except `near`/`far`, which may need the scene bounds.
fn check_camera(item: &Item, c: &CameraFile, origin: DVec3) -> Result<Camera, SceneError> {
    let eye = item.point("eye", c.eye, origin)?;
    let target = item.point("target", c.target, origin)?;
    let raw_up = c.up.unwrap_or([0.0, 1.0, 0.0]);
    let up = item.vec3("up", raw_up)?;
    let fov_y_degrees = item.range("fov_y_degrees", c.fov_y_degrees, Open(0.0), Open(180.0))?;
    // In f64: two points far from zero can differ by less than f32's spacing there.
    let view = (item.dvec3("target", c.target)? - item.dvec3("eye", c.eye)?).normalize_or_zero().as_vec3();
    if view == Vec3::ZERO || !view.is_finite() {
        return Err(item.error(format!("`eye` and `target` are the same point {}", fmt_array(c.eye))));
    }
    let up = up.normalize_or_zero();
    if up == Vec3::ZERO || !up.is_finite() {
        return Err(item.error(format!("`up` = {} is zero", fmt_array(raw_up))));
    }
    if view.cross(up).length() < 1e-4 {
        return Err(item.error(format!(
            "`up` = {} is parallel to the view direction (from `eye` to `target`)",
            fmt_array(raw_up)
        )));
    }
    if let Some(near) = c.near {
        item.range("near", near, Open(0.0), Bound::None)?;
    }
    if let Some(far) = c.far {
        item.range("far", far, Open(0.0), Bound::None)?;
    }
    Ok(Camera { eye, target, up, fov_y_degrees, near: 0.0, far: 0.0 })
}

/// Fills in `near` and `far`: a missing `far` lies just past the bounds corner farthest from
/// the eye (and past the target), a missing `near` is `far / 1000`.
fn finish_camera(
    item: &Item,
    mut camera: Camera,
    c: &CameraFile,
    lo: Vec3,
    hi: Vec3,
) -> Result<Camera, SceneError> {
    let far = match c.far {
        Some(far) => far,
        None => {
            let eye = camera.eye.as_dvec3();
            let mut farthest = (camera.target.as_dvec3() - eye).length();
            for i in 0..8 {
                let corner = Vec3::select(glam::BVec3::new(i & 1 == 0, i & 2 == 0, i & 4 == 0), lo, hi);
                farthest = farthest.max((corner.as_dvec3() - eye).length());
            }
            let far = (farthest * 1.01) as f32;
            if !far.is_finite() {
                return Err(item.error("cannot derive `far` from the scene bounds (too large); give `far`"));
            }
            far
        }
    };
    let near = c.near.unwrap_or(far * 1e-3);
    if !(near > 0.0 && near.is_finite()) {
        return Err(item.error(format!("derived `near` = {near} is not a positive number; give `near`")));
    }
    if near >= far {
        return Err(item.error(format!("`near` = {near} is not less than `far` = {far}")));
    }
    camera.near = near;
    camera.far = far;
    Ok(camera)
}

/// Reads the OBJ file of `[[meshes]]` entry `index` and applies its transform: its name, its
/// path and its geometry, not yet placed relative to the scene's origin.
fn read_mesh(
    path: &Path,
    folder: &Path,
    index: usize,
    m: &MeshFile,
    materials: &[Material],
) -> Result<(String, PathBuf, mesh::TransformedMesh), SceneError> {
    let item = mesh_item(path, index, m);
    if !materials.iter().any(|mat| mat.name == m.material) {
        return Err(item.error(format!("material \"{}\" is not defined", m.material)));
    }
    let scale = item.vec3("scale", m.scale.unwrap_or(Scale([1.0; 3])).0)?;
    if scale.to_array().contains(&0.0) {
        return Err(item.error(format!("`scale` = {} has a zero component", fmt_array(scale.to_array()))));
    }
    let transform = mesh::Transform {
        scale,
        rotate_degrees: item.vec3("rotate_degrees", m.rotate_degrees.unwrap_or([0.0; 3]))?,
        translate: item.dvec3("translate", m.translate.unwrap_or([0.0; 3]))?,
    };
    let source = folder.join(&m.obj);
    let name = match &m.name {
        Some(name) => name.clone(),
        None => m.obj.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
    };
    let transformed = mesh::load_obj(&source, &transform).map_err(|p| obj_error(path, &source, index, p))?;
    Ok((name, source, transformed))
}

/// `problem` with the OBJ file `source` of `[[meshes]]` entry `index` of the scene at `path`.
fn obj_error(path: &Path, source: &Path, index: usize, problem: mesh::ObjProblem) -> SceneError {
    SceneError::Obj {
        path: source.to_path_buf(),
        line: problem.line,
        problem: problem.message,
        scene: path.to_path_buf(),
        mesh: index + 1,
    }
}

fn mesh_item<'a>(path: &'a Path, index: usize, m: &MeshFile) -> Item<'a> {
    Item { path, item: format!("[[meshes]] #{} (\"{}\")", index + 1, m.obj.display()) }
}

/// The [`Mesh`] of `[[meshes]]` entry `index`, its geometry placed relative to `origin`.
#[allow(clippy::too_many_arguments)]
fn finish_mesh(
    path: &Path,
    index: usize,
    m: &MeshFile,
    materials: &[Material],
    name: String,
    source: PathBuf,
    transformed: mesh::TransformedMesh,
    origin: DVec3,
) -> Result<Mesh, SceneError> {
    let item = mesh_item(path, index, m);
    let material = materials.iter().position(|mat| mat.name == m.material).unwrap_or_default();
    let loaded = transformed.place(origin).map_err(|p| obj_error(path, &source, index, p))?;
    let mut mesh = Mesh {
        name,
        source,
        material,
        positions: loaded.positions,
        normals: loaded.normals,
        indices: loaded.indices,
        uvs: loaded.uvs,
        two_sided: true,
    };
    mesh.two_sided = m.two_sided.unwrap_or_else(|| !adjacency::is_closed(&mesh));
    if let Some(projection) = m.uv_projection {
        let uv_scale = m.uv_scale.unwrap_or([1.0, 1.0]);
        if !uv_scale.iter().all(|s| s.is_finite() && *s != 0.0) {
            return Err(item.error(format!(
                "`uv_scale` = [{}, {}] must be finite and non-zero",
                uv_scale[0], uv_scale[1]
            )));
        }
        mesh::project_uvs(&mut mesh, projection, Vec2::from_array(uv_scale));
    } else if m.uv_scale.is_some() {
        return Err(item.error("`uv_scale` applies only with `uv_projection`"));
    }
    let maps = &materials[material].maps;
    if (maps.albedo.is_some() || maps.parameter.is_some()) && mesh.uvs.is_empty() {
        return Err(item.error(format!(
            "material \"{}\" is textured but {} has no texture coordinates (add `vt` lines or `uv_projection`)",
            m.material,
            mesh.source.display()
        )));
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests;
