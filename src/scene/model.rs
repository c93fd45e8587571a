//! The scene as the renderer sees it: [`Scene`] and its camera, settings, materials, lights and
//! meshes, all in world space; and [`ParameterRange`], the range a textured material parameter
//! takes over a triangle.
//!
//! GLSL twin of [`ParameterRange`]: the `vec2` (lo, hi) that `parameter_range_of` in
//! `glsl/include/triangle_level.glsl` returns. Proof that the twins are equal: `tests/multirate.rs`
//! `control_stage_levels_equal_the_twin` (its textured scenes' levels hang on the range).

use super::path::CameraPath;
use super::settings;
use super::texture::{MinMaxPyramid, Texture};
use std::path::PathBuf;
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
    /// The scene file's camera path (`[[path]]`), none without one.
    pub camera_path: Option<CameraPath>,
    pub settings: RenderSettings,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    /// The lights that cast shadows, each with its map's settings; empty where none does.
    pub shadow_casters: Vec<ShadowCaster>,
    /// At least one after [`Scene::load`].
    pub meshes: Vec<Mesh>,
    /// The world point (f64) that every position here is relative to: a scene whose meshes
    /// lie farther from zero than their own size is recentred on them at load time (a floating
    /// origin: meshes, camera and lights move together), so that its f32 coordinates keep
    /// their precision; zero for a scene around the origin, which stays as written.
    pub origin: DVec3,
    /// What loading could not use and how it stood in for it (an OBJ file whose texture is
    /// missing, say, given as the scene or with `materials = "mtl"`), for the user to read;
    /// empty for a TOML scene whose meshes name their materials.
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

impl Camera {
    /// This camera moved to where `path` is `time` seconds in (an orbit turns from this one);
    /// its far plane pushed out where the scene's box `lo`..`hi` reaches farther from that eye
    /// (its near plane with it, in the same ratio), so that no frame of the path clips the scene.
    pub fn on_path(&self, path: &CameraPath, time: f32, (lo, hi): (Vec3, Vec3)) -> Camera {
        let (eye, target) = path.eye_and_target((self.eye, self.target, self.up), time);
        let reach = (0..8)
            .map(|i| Vec3::select(glam::BVec3::new(i & 1 == 0, i & 2 == 0, i & 4 == 0), lo, hi).distance(eye))
            .fold(eye.distance(target), f32::max)
            * 1.01;
        let scale = if reach > self.far { reach / self.far } else { 1.0 };
        Camera { eye, target, near: self.near * scale, far: self.far * scale, ..*self }
    }
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

/// A point or directional light's shadow map, from the `shadow = { .. }` table of its
/// `[[lights]]` entry. A point light's map is six square faces (a cube map), a directional
/// light's one orthographic square fitted to the scene's bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShadowCaster {
    /// The light's index in [`Scene::lights`].
    pub light: usize,
    /// Texels along a side of the map (of each face, for a point light).
    pub resolution: u32,
    /// Texels along a side of the percentage-closer filter's square kernel: odd, 1 for hard
    /// shadows.
    pub filter: u32,
}

impl ShadowCaster {
    /// A side of the map when the scene file leaves `resolution` out.
    pub const DEFAULT_RESOLUTION: u32 = 1024;
    /// The least and the greatest side of a map.
    pub const RESOLUTIONS: std::ops::RangeInclusive<u32> = 16..=4096;
    /// The widest filter kernel.
    pub const MAX_FILTER: u32 = 9;
    /// Most lights of a scene that cast shadows: multirate's interpolants carry each one's
    /// unshadowed shading apart (`gpu_interface::slots::MAX_SHADOWED_LIGHTS`).
    pub const MAX_LIGHTS: usize = 4;
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

/// The range `[lo, hi]` a textured parameter (Blinn-Phong shininess, GGX roughness) takes
/// over a triangle's texels (seed 003 Sec. 3.5, Eq. 34–38). `lo == hi` is an untextured
/// material; Lambert ignores it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParameterRange {
    pub lo: f32,
    pub hi: f32,
}

impl ParameterRange {
    /// The material's own (untextured) parameter: shininess, roughness, or 0 for Lambert.
    pub fn of(material: &MaterialKind) -> ParameterRange {
        let value = match *material {
            MaterialKind::Lambert { .. } => 0.0,
            MaterialKind::BlinnPhong { shininess, .. } => shininess,
            MaterialKind::Ggx { roughness, .. } => roughness,
        };
        ParameterRange { lo: value, hi: value }
    }
}

/// The axis-aligned bounds `(min, max)` of `points`, `(Vec3::ZERO, Vec3::ZERO)` where there are none.
pub fn bounds_of(points: impl Iterator<Item = Vec3>) -> (Vec3, Vec3) {
    let (min, max) = points.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)));
    if min.x > max.x {
        (Vec3::ZERO, Vec3::ZERO)
    } else {
        (min, max)
    }
}
