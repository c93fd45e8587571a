//! The scene file as written: the serde form of the TOML schema (`scenes/README.md` has every
//! key and default), before any value is checked, and the parsing that turns a TOML error into a
//! [`SceneError`] naming the line. Unknown keys are errors; which keys a material or light type
//! needs or allows, and every range, is checked in `validate.rs`.

use super::error::SceneError;
use super::model::{PolygonSampling, RenderSettings};

use std::fmt;
use std::path::{Path, PathBuf};

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    /// Optional: what the scene shows (free text); empty in
    /// [`Scene::description`](super::Scene::description) without it.
    pub(super) description: Option<String>,
    /// Optional: where the meshes come from (free text, for the people who read the file).
    pub(super) source: Option<String>,
    pub(super) camera: CameraFile,
    #[serde(default)]
    pub(super) render: RenderFile,
    #[serde(default)]
    pub(super) materials: Vec<MaterialFile>,
    #[serde(default)]
    pub(super) meshes: Vec<MeshFile>,
    #[serde(default)]
    pub(super) lights: Vec<LightFile>,
    /// Optional: a camera path, its keyframes in increasing time.
    #[serde(default)]
    pub(super) path: Vec<PathKeyFile>,
}

/// One `[[path]]` keyframe: the camera's eye and target `time` seconds in (its `up` and field of
/// view are `[camera]`'s).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PathKeyFile {
    pub(super) time: f32,
    pub(super) eye: [f64; 3],
    pub(super) target: [f64; 3],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraFile {
    pub(super) eye: [f64; 3],
    pub(super) target: [f64; 3],
    pub(super) up: Option<[f32; 3]>,
    pub(super) fov_y_degrees: f32,
    pub(super) near: Option<f32>,
    pub(super) far: Option<f32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub(super) struct RenderFile {
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) epsilon: f32,
    pub(super) n_max: u32,
    pub(super) exposure: f32,
    pub(super) clear_color: [f32; 3],
    pub(super) polygon_samples: u32,
    pub(super) polygon_sampling: PolygonSampling,
    pub(super) mis_visibility: f32,
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
pub(super) enum MaterialType {
    Lambert,
    BlinnPhong,
    Ggx,
}

impl MaterialType {
    pub(super) fn as_str(self) -> &'static str {
        match self {
            MaterialType::Lambert => "lambert",
            MaterialType::BlinnPhong => "blinn_phong",
            MaterialType::Ggx => "ggx",
        }
    }
}

/// One flat table for every material type, so that serde keeps exact error positions; which
/// keys a type needs and allows is checked in `check_material` (`validate.rs`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialFile {
    pub(super) name: String,
    #[serde(rename = "type")]
    pub(super) kind: MaterialType,
    pub(super) kd: Option<[f32; 3]>,
    pub(super) ks: Option<[f32; 3]>,
    pub(super) shininess: Option<f32>,
    pub(super) albedo: Option<[f32; 3]>,
    pub(super) f0: Option<[f32; 3]>,
    pub(super) roughness: Option<f32>,
    pub(super) kd_map: Option<PathBuf>,
    pub(super) albedo_map: Option<PathBuf>,
    pub(super) shininess_map: Option<PathBuf>,
    pub(super) shininess_range: Option<[f32; 2]>,
    pub(super) roughness_map: Option<PathBuf>,
    pub(super) roughness_range: Option<[f32; 2]>,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum LightType {
    Point,
    Directional,
    Polygon,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LightFile {
    #[serde(rename = "type")]
    pub(super) kind: LightType,
    pub(super) position: Option<[f64; 3]>,
    pub(super) direction: Option<[f32; 3]>,
    pub(super) vertices: Option<Vec<[f64; 3]>>,
    pub(super) color: [f32; 3],
    pub(super) intensity: f32,
    pub(super) shadow: Option<ShadowFile>,
}

/// A light's `shadow = { resolution = 1024, filter = 3 }`: it casts shadows, with these settings
/// (both optional).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ShadowFile {
    pub(super) resolution: Option<u32>,
    pub(super) filter: Option<u32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshFile {
    pub(super) obj: PathBuf,
    /// The name of a `[[materials]]` entry; exactly one of this and `materials` is given.
    pub(super) material: Option<String>,
    /// `materials = "mtl"`: the OBJ file's own MTL materials, one mesh per material used.
    pub(super) materials: Option<MeshMaterials>,
    pub(super) name: Option<String>,
    pub(super) translate: Option<[f64; 3]>,
    pub(super) rotate_degrees: Option<[f32; 3]>,
    pub(super) scale: Option<Scale>,
    pub(super) uv_projection: Option<UvProjection>,
    pub(super) uv_scale: Option<[f32; 2]>,
    pub(super) two_sided: Option<bool>,
}

/// Where a `[[meshes]]` entry's materials come from other than a `[[materials]]` entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum MeshMaterials {
    /// The OBJ file's own MTL libraries (`mtllib`, `usemtl`).
    Mtl,
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
pub(super) struct Scale(pub(super) [f32; 3]);

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

/// Parses the text of the scene file at `path` into the file as written; a TOML error names
/// the line, the column and the text of the line.
pub(super) fn parse(path: &Path, text: &str) -> Result<SceneFile, SceneError> {
    toml::from_str(text).map_err(|e| {
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
    })
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
