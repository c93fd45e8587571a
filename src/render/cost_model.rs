//! The cost model of `multirate` mode: where estimating a triangle's level can pay.
//!
//! Estimating costs about the same whatever the triangle's size, shading per pixel costs its
//! pixels: a triangle whose image covers `A` pixels costs `triangle(L) + A · fallback(L)` shaded
//! per pixel by multirate's per-pixel path (a depth prime, then the shading where it is nearest:
//! two passes over the triangle, then each pixel shaded once), and at least
//! `estimate(L) + 3 · pixel(L)` estimated (the estimate, then at best level 1: its three corners
//! shaded, each about as dear as a pixel of `pixel` mode), `L` being the scene's light count.
//! Below the break-even area `A* = max(0, estimate(L) + 3 · pixel(L) − triangle(L)) / fallback(L)`
//! the pre-pass shades a triangle
//! per pixel without estimating it (`geometry::cull::small_per_pixel`, `draw.min_estimated_area`),
//! unless the range class (`shading::estimator::range`), which costs a fraction of an estimate
//! and runs first, settles it at level 1; `estimate(L)` is the full estimator's cost.
//! Per-pixel shading is exact, so the choice never costs accuracy; the area bounds the image
//! from above, so it never sends a triangle that would pay per pixel.
//!
//! A mesh most of whose visible triangles the pre-pass would shade per pixel without an estimate
//! (small, and not settled by the range class) is drawn whole as `pixel` mode draws it
//! ([`MeshSample::mostly_small`]): its per-pixel path (a depth prime, then the shading, pulling
//! each triangle's corners) costs more than `pixel`'s one indexed pass. The renderer decides per
//! mesh and frame from a sample of the mesh's triangles.
//!
//! Both costs grow linearly with the lights (a fixed part, a part per light) and depend on the
//! device: `multirate calibrate` measures them ([`Calibration`]) and stores them per device
//! ([`calibration_key`]: its name, and on lavapipe the shader compiler's setting,
//! [`LavapipeCompiler`]; [`CostModel::store`], read back by [`CostModel::for_device`]); a device
//! without a stored calibration uses the figures measured on lavapipe
//! ([`CostModel::built_in`]).

use crate::error::{Error, Result};
use crate::geometry::cull::{clip_of, culled, small_image};
use crate::scene::{Light, Material, MaterialKind, Mesh, ParameterRange, Scene};
use crate::shading::estimator::{settled_by_range, TriangleInput};
use crate::vk::context::names_lavapipe;
use glam::{Mat4, Vec2, Vec3};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A device time that grows linearly with the scene's lights, in nanoseconds.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LinearCost {
    pub fixed_ns: f64,
    pub per_light_ns: f64,
}

impl LinearCost {
    /// The cost with `lights` lights (never below a nanosecond's hundredth, so that ratios
    /// stay finite).
    pub fn at(&self, lights: usize) -> f64 {
        (self.fixed_ns + self.per_light_ns * lights as f64).max(0.01)
    }

    /// The line through the costs measured at two light counts (`low < high`).
    pub fn through(low: (usize, f64), high: (usize, f64)) -> LinearCost {
        let per_light_ns = (high.1 - low.1) / (high.0 - low.0) as f64;
        LinearCost { fixed_ns: low.1 - per_light_ns * low.0 as f64, per_light_ns }
    }
}

/// The device costs the model weighs.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Calibration {
    /// The pre-pass's estimate step per triangle it estimates (those the range class leaves).
    pub estimate: LinearCost,
    /// Per-pixel shading per fragment shaded (`pixel` mode's time above `vertex` mode's, over
    /// its shaded fragments).
    pub pixel: LinearCost,
    /// The same through multirate's per-pixel path, per fragment it shades (every triangle
    /// shaded per pixel without an estimate, above `vertex`'s time: the part that grows with the
    /// fragments, from two resolutions).
    pub fallback: LinearCost,
    /// The per-pixel path's cost per visible triangle it draws, whatever its size (the same
    /// measurement's part that the resolution does not change). `None` in a calibration stored
    /// before it was measured, whose `fallback` then holds both parts.
    #[serde(default)]
    pub fallback_triangle: Option<LinearCost>,
    /// A triangle drawn through the tessellation stages at level 1 (`fixed:1`), above `vertex`
    /// mode's draw of it, per triangle: the fixed part of a tessellated patch. `None` in a
    /// calibration stored before it was measured.
    #[serde(default)]
    pub tessellated_patch: Option<LinearCost>,
    /// A sub-vertex shaded in the evaluation stage, with its share of the primitives around it
    /// (`fixed:4` above `fixed:1`, over the sub-vertices it adds). `None` as above.
    #[serde(default)]
    pub sub_vertex: Option<LinearCost>,
    /// How the figures were measured (the command and the scene).
    pub measured_with: String,
}

/// The cost model of one device.
#[derive(Clone, Debug, PartialEq)]
pub struct CostModel {
    pub calibration: Calibration,
    /// Where the figures come from: a stored calibration of this device, or the built-in one.
    pub source: String,
}

/// Calibrations per device name, as `multirate calibrate` stores them.
#[derive(Default, serde::Serialize, serde::Deserialize)]
struct Store {
    #[serde(default)]
    devices: BTreeMap<String, Calibration>,
}

/// lavapipe's shader compiler setting (`GALLIVM_PERF`): with `nopt` llvmpipe leaves out LLVM's
/// optimisation passes (CI's setting: shaders build sooner and run slower). It changes what a
/// shader costs there several times over, a pixel of `pixel` mode most (docs/cost_model.md), so a
/// calibration holds for one setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LavapipeCompiler {
    /// LLVM's optimisation passes on: llvmpipe's default.
    Optimising,
    /// `GALLIVM_PERF=nopt`.
    Unoptimised,
}

impl LavapipeCompiler {
    /// The setting `GALLIVM_PERF`'s value (if set) selects: `Unoptimised` where `nopt` is among
    /// its flags.
    pub fn of(gallivm_perf: Option<&str>) -> LavapipeCompiler {
        let flags = gallivm_perf.unwrap_or_default();
        if flags.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).any(|flag| flag == "nopt") {
            LavapipeCompiler::Unoptimised
        } else {
            LavapipeCompiler::Optimising
        }
    }

    /// This process's setting.
    pub fn current() -> LavapipeCompiler {
        LavapipeCompiler::of(std::env::var("GALLIVM_PERF").ok().as_deref())
    }

    /// `compiler` where the device named `device` is lavapipe; `None` elsewhere, where the
    /// setting means nothing.
    fn on(device: &str, compiler: LavapipeCompiler) -> Option<LavapipeCompiler> {
        names_lavapipe(device).then_some(compiler)
    }
}

/// The name under which `multirate calibrate` stores the calibration of the device named
/// `device`, and under which the renderer looks it up: the name itself, with
/// `", GALLIVM_PERF=nopt"` on lavapipe run with `compiler` `Unoptimised`.
pub fn calibration_key(device: &str, compiler: LavapipeCompiler) -> String {
    match LavapipeCompiler::on(device, compiler) {
        Some(LavapipeCompiler::Unoptimised) => format!("{device}, GALLIVM_PERF=nopt"),
        _ => device.to_string(),
    }
}

impl CostModel {
    /// The figures measured on lavapipe (llvmpipe, Mesa 22.3.6, LLVM 15, 2 cores of an AMD EPYC) with
    /// `GALLIVM_PERF=nopt`: `multirate calibrate` (docs/cost_model.md).
    pub fn lavapipe() -> CostModel {
        CostModel::lavapipe_with(LavapipeCompiler::Unoptimised)
    }

    /// The figures measured on the same lavapipe with LLVM's optimisation passes on (its
    /// default): `multirate calibrate` (docs/cost_model.md).
    pub fn lavapipe_optimising() -> CostModel {
        CostModel::lavapipe_with(LavapipeCompiler::Optimising)
    }

    /// lavapipe's built-in figures with `compiler`, each the median of three runs of
    /// `multirate calibrate --dry-run` (docs/cost_model.md, "Calibration" and "Tessellating
    /// against the per-pixel path").
    fn lavapipe_with(compiler: LavapipeCompiler) -> CostModel {
        let line = |fixed_ns, per_light_ns| LinearCost { fixed_ns, per_light_ns };
        let (estimate, pixel, fallback, fallback_triangle, patch, sub_vertex, setting) = match compiler {
            LavapipeCompiler::Unoptimised => (
                line(1404.0, 699.0),
                line(92.3, 61.4),
                line(90.7, 59.0),
                line(2576.0, 380.0),
                line(845.0, 115.0),
                line(249.0, 22.3),
                "GALLIVM_PERF=nopt",
            ),
            LavapipeCompiler::Optimising => (
                line(1139.0, 317.0),
                line(45.2, 28.7),
                line(48.6, 28.2),
                line(1575.0, 69.9),
                line(668.0, 61.7),
                line(198.0, 26.0),
                "GALLIVM_PERF unset",
            ),
        };
        CostModel {
            calibration: Calibration {
                estimate,
                pixel,
                fallback,
                fallback_triangle: Some(fallback_triangle),
                tessellated_patch: Some(patch),
                sub_vertex: Some(sub_vertex),
                measured_with: format!(
                    "built in: per figure the median of three runs of multirate calibrate --scene \
                     scenes/bunny.toml on llvmpipe (LLVM 15.0.6, 256 bits), Mesa 22.3.6, {setting}, 2 cores \
                     of an AMD EPYC"
                ),
            },
            source: format!("built-in (lavapipe, {setting})"),
        }
    }

    /// The built-in figures for the device named `device` run with `compiler`: lavapipe's for
    /// that setting on lavapipe; elsewhere those of lavapipe with `nopt`, which the frame guard
    /// (`render::guard`) backs where they do not fit.
    pub fn built_in(device: &str, compiler: LavapipeCompiler) -> CostModel {
        match LavapipeCompiler::on(device, compiler) {
            Some(LavapipeCompiler::Optimising) => CostModel::lavapipe_optimising(),
            _ => CostModel::lavapipe(),
        }
    }

    /// The model of the device named `device`, run with this process's [`LavapipeCompiler`]:
    /// its calibration in the default store ([`CostModel::default_store`]) if there is one,
    /// else the built-in figures ([`CostModel::built_in`]).
    pub fn for_device(device: &str) -> CostModel {
        CostModel::from_store(CostModel::default_store().as_deref(), device, LavapipeCompiler::current())
    }

    /// The model of the device named `device` run with `compiler`: the calibration stored for it
    /// ([`calibration_key`]) in the store at `store`, else the built-in figures.
    pub fn from_store(store: Option<&Path>, device: &str, compiler: LavapipeCompiler) -> CostModel {
        store
            .and_then(|path| {
                let calibration =
                    load_store(path).ok()?.devices.remove(&calibration_key(device, compiler))?;
                Some(CostModel { calibration, source: format!("calibrated ({})", path.display()) })
            })
            .unwrap_or_else(|| CostModel::built_in(device, compiler))
    }

    /// Where `multirate calibrate` stores calibrations: `$MULTIRATE_COST_MODEL`, else
    /// `$XDG_CONFIG_HOME/multirate/cost_model.toml`, else `$HOME/.config/multirate/cost_model.toml`.
    pub fn default_store() -> Option<PathBuf> {
        if let Some(path) = std::env::var_os("MULTIRATE_COST_MODEL") {
            return Some(PathBuf::from(path));
        }
        let config = std::env::var_os("XDG_CONFIG_HOME")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|home| Path::new(&home).join(".config")))?;
        Some(config.join("multirate").join("cost_model.toml"))
    }

    /// Adds (or replaces) `device`'s calibration in the store at `path`, keeping the others.
    pub fn store(path: &Path, device: &str, calibration: &Calibration) -> Result<()> {
        let mut store = if path.exists() { load_store(path)? } else { Store::default() };
        store.devices.insert(device.to_string(), calibration.clone());
        let output = |message: String| Error::Output { path: path.to_path_buf(), message };
        let text = toml::to_string(&store).map_err(|e| output(e.to_string()))?;
        if let Some(folder) = path.parent() {
            std::fs::create_dir_all(folder).map_err(|e| output(format!("cannot create its folder: {e}")))?;
        }
        std::fs::write(path, text).map_err(|e| output(e.to_string()))
    }

    /// The break-even image area `A*` (pixels) with `lights` lights: images smaller than this
    /// are shaded per pixel without an estimate; 0 where the per-pixel path's cost per triangle
    /// alone exceeds an estimate's.
    pub fn min_estimated_area(&self, lights: usize) -> f32 {
        let c = &self.calibration;
        let per_triangle = c.fallback_triangle.map_or(0.0, |t| t.at(lights));
        let saved = c.estimate.at(lights) + 3.0 * c.pixel.at(lights) - per_triangle;
        (saved.max(0.0) / c.fallback.at(lights)) as f32
    }

    /// [`CostModel::min_estimated_area`] with `scene`'s lights.
    pub fn min_estimated_area_of(&self, scene: &Scene) -> f32 {
        self.min_estimated_area(weighed_lights(&scene.lights))
    }

    /// The image area (pixels) above which a patch tessellated at `level` (uniformly, with
    /// `(level + 1)·(level + 2)/2` sub-vertices) costs less than shading it through the per-pixel
    /// path (its cost per triangle, then per pixel), with `lights` lights; `None` without the
    /// tessellation costs. The renderer does not
    /// weigh it: on lavapipe the patches the estimator sends to such levels are mostly larger
    /// (docs/cost_model.md, "Tessellating against the per-pixel path").
    pub fn tessellation_break_even(&self, level: u32, lights: usize) -> Option<f32> {
        let c = &self.calibration;
        let (patch, sub_vertex) = (c.tessellated_patch?, c.sub_vertex?);
        let n = f64::from(level);
        let added = ((n + 1.0) * (n + 2.0) / 2.0).max(3.0) - 3.0;
        let per_triangle = c.fallback_triangle.map_or(0.0, |t| t.at(lights));
        let tessellated = patch.at(lights) + sub_vertex.at(lights) * added;
        Some(((tessellated - per_triangle).max(0.0) / c.fallback.at(lights)) as f32)
    }
}

/// The light count the model weighs for a scene's `lights`: every light, at least one.
pub fn weighed_lights(lights: &[Light]) -> usize {
    lights.len().max(1)
}

/// Most triangles of a mesh [`MeshSample`] keeps.
pub const MESH_SAMPLE_TRIANGLES: usize = 256;

/// Triangles of one mesh, evenly spread over its index list, that stand for it in the
/// per-mesh choice, with what the range class needs to try them.
#[derive(Clone, Debug)]
pub struct MeshSample {
    triangles: Vec<[Vec3; 3]>,
    normals: Vec<[Vec3; 3]>,
    one_sided: bool,
    /// The mesh's BRDF where the range class can try its triangles; `None` where a parameter
    /// map varies the shininess or roughness over them (the GPU bounds it per triangle from the
    /// map's pyramid, which the sample does not hold): every small triangle then counts.
    material: Option<MaterialKind>,
}

impl MeshSample {
    /// Up to [`MESH_SAMPLE_TRIANGLES`] of `mesh`'s triangles, evenly strided; `material` is the
    /// mesh's.
    pub fn of(mesh: &Mesh, material: &Material) -> MeshSample {
        let count = mesh.indices.len() / 3;
        let stride = count.div_ceil(MESH_SAMPLE_TRIANGLES).max(1);
        let corners = |t: usize, of: &[Vec3]| [0, 1, 2].map(|k| of[mesh.indices[3 * t + k] as usize]);
        let (triangles, normals) = (0..count)
            .step_by(stride)
            .map(|t| (corners(t, &mesh.positions), corners(t, &mesh.normals)))
            .unzip();
        MeshSample {
            triangles,
            normals,
            one_sided: !mesh.two_sided,
            material: material.maps.parameter.is_none().then_some(material.kind),
        }
    }

    /// Whether more than half of the sampled triangles that are not culled would be shaded
    /// per pixel without an estimate: an image smaller than `min_area` pixels of a `viewport`
    /// (width, height) seen through `view_proj` from `eye`, that the range class does not
    /// settle for `epsilon` under `lights` (as the pre-pass decides, `triangle_level.glsl`'s
    /// `visible_level`).
    ///
    /// It runs every frame on the CPU, per mesh, so the range class (about half a microsecond
    /// a triangle with three lights) runs only where the areas alone leave the answer open (more
    /// than half small), and on at most [`RANGE_TRIED`] of the small triangles, evenly strided;
    /// the share of those it settles stands for all of them.
    pub fn mostly_small(
        &self,
        view_proj: &Mat4,
        eye: Vec3,
        viewport: Vec2,
        min_area: f32,
        lights: &[Light],
        epsilon: f32,
    ) -> bool {
        let mut visible = 0usize;
        let mut small = Vec::new();
        for (k, &p) in self.triangles.iter().enumerate() {
            if culled(view_proj, eye, p, self.one_sided) {
                continue;
            }
            visible += 1;
            let [a, b, c] = p.map(|p| clip_of(view_proj, p));
            if small_image(a, b, c, viewport, min_area) {
                small.push(k);
            }
        }
        if 2 * small.len() <= visible {
            return false;
        }
        let Some(material) = self.material else {
            return true;
        };
        let parameter = ParameterRange::of(&material);
        let (mut tried, mut settled) = (0usize, 0usize);
        for &k in small.iter().step_by(small.len().div_ceil(RANGE_TRIED)) {
            let input = TriangleInput { positions: self.triangles[k], normals: self.normals[k], eye };
            tried += 1;
            settled += usize::from(settled_by_range(&input, &material, parameter, lights, (epsilon, 0.0)));
        }
        // small · (1 − settled / tried) > visible / 2, without a division.
        2 * small.len() * (tried - settled) > visible * tried
    }
}

/// Most small triangles of a mesh's sample that [`MeshSample::mostly_small`] tries the range
/// class on.
pub const RANGE_TRIED: usize = 64;

fn load_store(path: &Path) -> Result<Store> {
    let output = |message: String| Error::Output { path: path.to_path_buf(), message };
    let text = std::fs::read_to_string(path).map_err(|e| output(format!("cannot read: {e}")))?;
    toml::from_str(&text).map_err(|e| output(format!("not a cost-model store: {e}")))
}

#[cfg(test)]
mod tests;
