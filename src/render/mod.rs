//! Rendering a scene: GPU copies of the scene, the pipeline variants specialised to its
//! materials and lights, and the forward pass that draws into a render target.

pub mod camera;
pub mod capture;
pub mod cull;
pub mod deferred;
pub mod limits;
pub mod output;
pub mod present;
pub mod textures;

use deferred::{deferred_set_bindings, Deferred};
use limits::SceneSizes;
use textures::{gpu_material, material_set_bindings, SceneTextures};

use crate::analysis::tessellator::uniform_vertex_count;
use crate::error::Result;
use crate::gpu_types::{
    DrawConstants, GpuLight, GpuMaterial, GpuPolygonLight, Vertex, FLAG_DERIVATIVE_CHECK,
    FLAG_FALLBACK_PATCHES, FLAG_HEAT_MAP, FLAG_ONE_SIDED,
};
use crate::scene::adjacency::{adjacency_patches, neighbours, PATCH_SIZE};
use crate::scene::{Camera, Light, MaterialKind, PolygonSampling, Scene};
use crate::shaders::{self, Features};
use crate::shading::estimator::{Discontinuity, Split};
use crate::vk::context::DeviceLimits;
use crate::vk::frames::FrameRing;
use crate::vk::memory::Buffer;
use crate::vk::pipeline::{
    bind_storage_buffers, shader_binding, DepthUse, DescriptorPool, GraphicsPipelineDesc, Optimization,
    Pipeline, PipelineLayout, ShaderModule, Specialization, Stage,
};
use crate::vk::target::{
    AfterPass, Attachments, FloatImage, RenderTarget, COLOR_FORMAT, DEPTH_FORMAT, ID_FORMAT,
};
use crate::vk::timing::{GpuInterval, GpuTimer, PipelineStatistics};
use crate::vk::Context;
use ash::vk;
use glam::Vec4;
use std::cell::OnceCell;
use std::sync::Arc;

/// How shading is sampled. Every mode runs the same BRDF code (`glsl/include/brdf.glsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    /// Full shading in the fragment shader at every pixel: the reference.
    #[default]
    Pixel,
    /// The same reference, deferred: a visibility buffer of triangle ids, then per pixel the
    /// attributes and their derivatives rebuilt analytically (seed 002) and shaded.
    PixelDeferred,
    /// Gouraud: shade the triangle's three vertices, interpolate; no subdivision, no fallback.
    Vertex,
    /// Tessellate every triangle at inner = outer = N and shade the sub-vertices in the TES.
    Fixed(u32),
    /// Per triangle, the smallest level whose error bound is under ε (the TCS estimator);
    /// triangles that would need more than n_max are shaded per pixel.
    Multirate,
}

/// Highest tessellation level Vulkan guarantees (`maxTessellationGenerationLevel` ≥ 64).
pub const MAX_LEVEL: u32 = 64;

/// The stages the push constants (`DrawConstants`) are visible to: every graphics stage, and
/// the triangle-level pre-pass.
pub(crate) const PUSH_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::ALL_GRAPHICS.as_raw() | vk::ShaderStageFlags::COMPUTE.as_raw(),
);

/// Where `multirate` mode runs the estimator. Both give the same levels (tests/multirate.rs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Estimator {
    /// In the tessellation control stage, as the seeds describe it: each patch carries its
    /// neighbours' vertices, and its four invocations estimate the triangle and its three
    /// neighbours, one each.
    Tcs,
    /// In a compute pre-pass, once per visible triangle and frame; the control stage reads its
    /// own and its neighbours' levels and only combines them, and the interpolated and the
    /// fallback patches are drawn apart. The default: 2–4× faster frames than `Tcs` on
    /// lavapipe, the only device measured, and its pipelines build as fast (docs/speedups.md).
    #[default]
    Compute,
}

impl std::str::FromStr for Estimator {
    type Err = String;
    fn from_str(text: &str) -> Result<Estimator, String> {
        match text {
            "tcs" => Ok(Estimator::Tcs),
            "compute" => Ok(Estimator::Compute),
            _ => Err(format!("unknown estimator placement \"{text}\" (known: tcs, compute)")),
        }
    }
}

impl std::fmt::Display for Estimator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Estimator::Tcs => "tcs",
            Estimator::Compute => "compute",
        })
    }
}

impl std::str::FromStr for Mode {
    type Err = String;
    fn from_str(text: &str) -> Result<Mode, String> {
        match text {
            "pixel" => Ok(Mode::Pixel),
            "pixel-deferred" => Ok(Mode::PixelDeferred),
            "vertex" => Ok(Mode::Vertex),
            "multirate" => Ok(Mode::Multirate),
            _ => match text.strip_prefix("fixed:").map(str::parse::<u32>) {
                Some(Ok(level)) if (1..=MAX_LEVEL).contains(&level) => Ok(Mode::Fixed(level)),
                Some(_) => {
                    Err(format!("\"{text}\": the level of fixed:N must be an integer in 1..={MAX_LEVEL}"))
                }
                None => Err(format!(
                    "unknown mode \"{text}\" (known: pixel, pixel-deferred, vertex, fixed:N, multirate)"
                )),
            },
        }
    }
}

impl std::fmt::Display for Mode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Mode::Pixel => write!(f, "pixel"),
            Mode::PixelDeferred => write!(f, "pixel-deferred"),
            Mode::Vertex => write!(f, "vertex"),
            Mode::Fixed(level) => write!(f, "fixed:{level}"),
            Mode::Multirate => write!(f, "multirate"),
        }
    }
}

/// The values of the shaders' MATERIAL_KIND (`Features::material_kind`).
fn material_kind_id(kind: &MaterialKind) -> u32 {
    match kind {
        MaterialKind::Lambert { .. } => 0,
        MaterialKind::BlinnPhong { .. } => 1,
        MaterialKind::Ggx { .. } => 2,
    }
}

/// The scene's lights in the order the shaders expect: point lights, then directional ones.
pub fn gpu_lights(lights: &[Light]) -> (Vec<GpuLight>, i32, i32) {
    let mut points = Vec::new();
    let mut directionals = Vec::new();
    for light in lights {
        match *light {
            Light::Point { position, color, intensity } => points
                .push(GpuLight { position: position.extend(1.0), radiance: (color * intensity).extend(0.0) }),
            Light::Directional { direction, color, intensity } => directionals.push(GpuLight {
                position: direction.extend(0.0),
                radiance: (color * intensity).extend(0.0),
            }),
            Light::Polygon(_) => {}
        }
    }
    let counts = (points.len() as i32, directionals.len() as i32);
    points.extend(directionals);
    (points, counts.0, counts.1)
}

/// The scene's polygonal lights, in scene order (the shaders' `polygon_lights`).
pub fn gpu_polygon_lights(lights: &[Light]) -> Vec<GpuPolygonLight> {
    lights
        .iter()
        .filter_map(|light| match light {
            Light::Polygon(p) => {
                let mut vertices = [glam::Vec4::ZERO; 8];
                for (out, v) in vertices.iter_mut().zip(p.vertices()) {
                    *out = v.extend(1.0);
                }
                Some(GpuPolygonLight {
                    vertices,
                    normal: p.normal.extend(p.area),
                    radiance: p.radiance().extend(0.0),
                    info: glam::IVec4::new(p.count as i32, 0, 0, 0),
                })
            }
            _ => None,
        })
        .collect()
}

/// The specialization constants of the scene's polygonal lights (8 to 11, brdf.glsl; only the
/// variants with polygonal lights have them).
fn polygon_specialization(specialization: Specialization, scene: &Scene, count: usize) -> Specialization {
    let sampling = scene.settings.light_sampling;
    let technique = match sampling.technique {
        PolygonSampling::ProjectedSolidAngle => 0,
        PolygonSampling::SolidAngle => 1,
    };
    specialization
        .int(8, count as i32)
        .int(9, sampling.samples as i32)
        .int(10, technique)
        .float(11, sampling.mis_visibility)
}

/// GPU times and counts of measured frames.
#[derive(Clone, Debug, Default)]
pub struct Measurement {
    /// When the forward pass ran in every measured frame, in submission order.
    pub frames: Vec<GpuInterval>,
    /// `Estimator::Compute`: when the triangle-level pre-pass (culling, triangle levels, patch
    /// levels and lists; part of the frame) ran in every measured frame; empty otherwise.
    pub pre_pass: Vec<GpuInterval>,
    /// `Estimator::Compute`: when each of its steps ran (`PrePassStep::ALL`'s order), in every
    /// measured frame; empty otherwise.
    pub pre_pass_steps: Vec<[GpuInterval; PRE_PASS_STEPS]>,
    /// Pipeline statistics of the last frame, where the device has them.
    pub statistics: Option<PipelineStatistics>,
}

impl Measurement {
    /// Forward-pass milliseconds of every measured frame.
    pub fn gpu_ms(&self) -> Vec<f64> {
        self.frames.iter().map(GpuInterval::milliseconds).collect()
    }

    /// Pre-pass milliseconds of every measured frame (empty without a pre-pass).
    pub fn pre_pass_ms(&self) -> Vec<f64> {
        self.pre_pass.iter().map(GpuInterval::milliseconds).collect()
    }

    /// Milliseconds of pre-pass step `step` in every measured frame (empty without a pre-pass).
    pub fn pre_pass_step_ms(&self, step: PrePassStep) -> Vec<f64> {
        self.pre_pass_steps.iter().map(|steps| steps[step as usize].milliseconds()).collect()
    }
}

/// Runs of the full shading function in one frame, by where they ran (the counting variant).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct EvaluationCounts {
    /// `vertex` mode: triangle vertices shaded by the vertex shader.
    pub vertices: u64,
    /// Tessellated modes: sub-vertices shaded by the evaluation shader.
    pub sub_vertices: u64,
    /// `pixel` mode and `multirate`'s fallback: fragments shaded per pixel.
    pub fragments: u64,
    /// `multirate`: triangles culled before their estimate (outside the view frustum, or back
    /// faces of one-sided meshes). Not a shading evaluation.
    pub culled_patches: u64,
}

impl EvaluationCounts {
    pub fn total(&self) -> u64 {
        self.vertices + self.sub_vertices + self.fragments
    }
}

/// Frames a measurement keeps in flight, so reading one frame's queries never stalls the next.
const FRAMES_IN_FLIGHT: usize = 2;

/// What a frame is rendered with.
#[derive(Clone, Debug)]
pub struct View {
    pub camera: Camera,
    pub mode: Mode,
    /// L∞ error bound of `multirate` mode, linear radiance.
    pub epsilon: f32,
    /// Largest level of `multirate` mode before per-pixel fallback.
    pub n_max: u32,
    pub split: Split,
    pub discontinuity: Discontinuity,
    /// `multirate` only: where the estimator runs.
    pub estimator: Estimator,
    /// Colour by tessellation level (heat map) instead of shading.
    pub heat_map: bool,
    /// Draw triangle edges only (where the device has `fillModeNonSolid`).
    pub wireframe: bool,
    /// `pixel-deferred` only: instead of shading, write per pixel the analytic uv derivatives'
    /// difference from the hardware's (`‖∂uv/∂x − dFdx uv‖ + ‖∂uv/∂y − dFdy uv‖` in red, the
    /// analytic `‖∂uv/∂x‖ + ‖∂uv/∂y‖` in green, and in blue 1 where the pixel's 2×2 quad
    /// spans several triangles; seed 002's comparison).
    pub derivative_check: bool,
}

impl View {
    /// The scene's own camera and settings.
    pub fn of_scene(scene: &Scene) -> View {
        View {
            camera: scene.camera,
            mode: Mode::Pixel,
            epsilon: scene.settings.epsilon,
            n_max: scene.settings.n_max,
            split: Split::Heuristic,
            discontinuity: Discontinuity::Relaxed,
            estimator: Estimator::default(),
            heat_map: false,
            wireframe: false,
            derivative_check: false,
        }
    }
}

/// The modes drawn by one pipeline per material kind.
#[derive(Clone, Copy, Debug)]
enum SingleMode {
    Pixel,
    Vertex,
    Fixed,
}

impl SingleMode {
    fn of(mode: Mode) -> Option<SingleMode> {
        match mode {
            Mode::Pixel => Some(SingleMode::Pixel),
            Mode::Vertex => Some(SingleMode::Vertex),
            Mode::Fixed(_) => Some(SingleMode::Fixed),
            Mode::PixelDeferred | Mode::Multirate => None,
        }
    }
}

/// Sets `cell` from `build` unless it is already set.
fn build_once<T>(cell: &OnceCell<T>, build: impl FnOnce() -> Result<T>) -> Result<()> {
    if cell.get().is_none() {
        let _ = cell.set(build()?);
    }
    Ok(())
}

/// The pipelines of one material kind, one per mode, each built on first use by
/// `Renderer::prepare` (or the analysis and recording frames): a frame, a test or a tool seldom
/// needs more than one mode, and the analysis and recording variants never draw the others.
struct Variant {
    pixel: OnceCell<Pipeline>,
    vertex: OnceCell<Pipeline>,
    tessellated: OnceCell<Pipeline>,
    /// Indexed by estimator placement, `split` and `discontinuity` (their specialization
    /// constants); built on first use by `Renderer::prepare`, since the estimator makes them
    /// slow to compile.
    multirate: [[[OnceCell<Multirate>; 2]; 2]; 2],
    /// The shader variant's features, instrumentation included.
    features: Features,
    instrumentation: Instrumentation,
    polygon_mode: vk::PolygonMode,
}

/// What a pipeline variant records besides the image. Only `None` is ever timed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Instrumentation {
    None,
    /// The pre-pass (patch_levels.comp, `VARIANT_RECORD_LEVELS`) or multirate.tesc (its
    /// specialization constant RECORD_LEVELS) writes each triangle's levels.
    RecordLevels,
    /// Every shading run adds to the evaluation counters (COUNT_EVALUATIONS), and the fragment
    /// stages write which triangle each pixel shows (`Attachments::ColorAndIds`,
    /// glsl/include/triangle_id.glsl).
    CountEvaluations,
}

impl Instrumentation {
    /// The attachments the variant's forward passes draw into.
    fn attachments(self) -> Attachments {
        match self {
            Instrumentation::CountEvaluations => Attachments::ColorAndIds,
            Instrumentation::None | Instrumentation::RecordLevels => Attachments::Color,
        }
    }

    /// Only the timed pipelines are worth the driver's optimisation.
    fn optimization(self) -> Optimization {
        match self {
            Instrumentation::None => Optimization::Optimized,
            Instrumentation::RecordLevels | Instrumentation::CountEvaluations => Optimization::Unoptimized,
        }
    }

    /// The formats of [`Instrumentation::attachments`].
    fn color_formats(self) -> &'static [vk::Format] {
        match self.attachments() {
            Attachments::Color => &[COLOR_FORMAT],
            Attachments::ColorAndIds => &[COLOR_FORMAT, ID_FORMAT],
        }
    }

    /// The scene's `features` with this instrumentation compiled in.
    fn features(self, features: Features) -> Features {
        Features {
            count_evaluations: self == Instrumentation::CountEvaluations,
            record_levels: self == Instrumentation::RecordLevels,
            ..features
        }
    }
}

/// The pipelines of `multirate` mode for one estimator placement.
struct Multirate {
    draw: Pipeline,
    /// `Estimator::Compute`: the pipelines of the other patch lists; `draw` then draws only
    /// the tessellated patches shaded on their sub-vertices, and its fragment shader holds no
    /// shading code (multirate_interpolated.frag).
    lists: Option<ListPipelines<Pipeline>>,
    /// `Estimator::Compute`: the pre-pass: culling, the levels of the visible triangles, then
    /// the patch levels, lists and indirect draws.
    pre_pass: Option<PrePass>,
}

/// `Estimator::Compute`: the pipelines of the pre-pass's fallback and flat patch lists.
#[derive(Clone, Copy)]
struct ListPipelines<P> {
    /// The fallback patches, shaded per pixel (multirate.frag) where they are the nearest
    /// surface once every list has been drawn into the depth attachment (DepthUse::Primed).
    fallback: P,
    /// The fallback patches' depth (DepthUse::Prime), before the fallback patches are shaded: the
    /// lists are filled by atomics in no fixed order, and the early depth test alone would let
    /// the per-pixel shading of overlapping fallback patches depend on that order.
    fallback_prime: P,
    /// The flat patches (all levels 1), without tessellation stages: multirate_flat.vert shades
    /// their corners.
    flat: P,
    /// The flat patches shaded per pixel: multirate_flat.vert passes their corners on to
    /// multirate.frag (DepthUse::Primed).
    flat_fallback: P,
    /// Their depth (DepthUse::Prime).
    flat_fallback_prime: P,
}

/// The steps of the triangle-level pre-pass (`Estimator::Compute`).
struct PrePass {
    cull: Pipeline,
    levels: Pipeline,
    /// refine_levels.comp, the refining step.
    refine: Pipeline,
    patches: Pipeline,
}

impl Variant {
    /// A variant of `features` (its `instrumentation` compiled in), no pipeline built yet.
    fn new(features: Features, instrumentation: Instrumentation, polygon_mode: vk::PolygonMode) -> Variant {
        Variant {
            pixel: OnceCell::new(),
            vertex: OnceCell::new(),
            tessellated: OnceCell::new(),
            multirate: Default::default(),
            features: instrumentation.features(features),
            instrumentation,
            polygon_mode,
        }
    }

    /// The pipeline of `view` (None: not yet prepared).
    fn for_view(&self, view: &View) -> Option<MeshPipelines> {
        let one = |pipeline: &Pipeline| MeshPipelines { first: pipeline.raw, lists: None };
        match view.mode {
            Mode::Pixel | Mode::Vertex | Mode::Fixed(_) => {
                self.single_cell(SingleMode::of(view.mode)?).get().map(one)
            }
            // Drawn by `record_deferred`, with its own pipelines.
            Mode::PixelDeferred => None,
            Mode::Multirate => self.multirate_cell(view).get().map(|m| MeshPipelines {
                first: m.draw.raw,
                lists: m.lists.as_ref().map(|l| ListPipelines {
                    fallback: l.fallback.raw,
                    fallback_prime: l.fallback_prime.raw,
                    flat: l.flat.raw,
                    flat_fallback: l.flat_fallback.raw,
                    flat_fallback_prime: l.flat_fallback_prime.raw,
                }),
            }),
        }
    }

    fn single_cell(&self, mode: SingleMode) -> &OnceCell<Pipeline> {
        match mode {
            SingleMode::Pixel => &self.pixel,
            SingleMode::Vertex => &self.vertex,
            SingleMode::Fixed => &self.tessellated,
        }
    }

    fn multirate_cell(&self, view: &View) -> &OnceCell<Multirate> {
        let placement = usize::from(view.estimator == Estimator::Compute);
        &self.multirate[placement][split_id(view.split) as usize]
            [discontinuity_id(view.discontinuity) as usize]
    }
}

/// The SPLIT specialization constant.
fn split_id(split: Split) -> i32 {
    match split {
        Split::Uniform => 0,
        Split::Heuristic => 1,
    }
}

/// The DISCONTINUITY specialization constant.
fn discontinuity_id(discontinuity: Discontinuity) -> i32 {
    match discontinuity {
        Discontinuity::Conservative => 0,
        Discontinuity::Relaxed => 1,
    }
}

/// The pipelines that draw one mesh.
#[derive(Clone, Copy)]
struct MeshPipelines {
    first: vk::Pipeline,
    /// Multirate's other patch lists (`Multirate::lists`): with them, all three draw the
    /// pre-pass's patch lists, `first` the interpolated one.
    lists: Option<ListPipelines<vk::Pipeline>>,
}

struct DrawCall {
    /// Index of the mesh's first triangle in the scene.
    first_triangle: u32,
    first_index: u32,
    index_count: u32,
    /// Where this mesh's 12-index adjacency patches start in the patch index buffer.
    first_patch_index: u32,
    /// Back faces are culled (`Mesh::two_sided` false).
    one_sided: bool,
    material_index: u32,
    mesh_index: u32,
    pipeline: usize,
}

/// The emissive geometry of one polygonal light: a triangle fan in the scene's buffers.
struct EmitterDraw {
    first_index: u32,
    index_count: u32,
    light_index: u32,
}

/// One frame drawn by the analysis variant ([`Renderer::analyze`]).
#[derive(Clone, Debug)]
pub struct Analysis {
    pub image: FloatImage,
    /// Per pixel, rows from the top: the id of the triangle it shows (glsl/include/triangle_id.glsl; 0: nothing).
    pub triangles: Vec<u32>,
    pub evaluations: EvaluationCounts,
}

impl Analysis {
    /// The image and its triangle ids, for the error metrics.
    pub fn frame(&self) -> crate::analysis::metrics::Frame<'_> {
        crate::analysis::metrics::Frame { image: &self.image, triangles: &self.triangles }
    }
}

/// A scene uploaded to the GPU with its specialised pipelines.
pub struct Renderer {
    context: Arc<Context>,
    vertices: Buffer,
    indices: Buffer,
    patch_indices: Buffer,
    /// Per triangle: its level, written by the pre-pass of `Estimator::Compute`.
    _triangle_levels: Buffer,
    /// Per triangle: the triangles across its edges (`uvec4`, scene indices).
    _triangle_neighbours: Buffer,
    /// Per mesh: its triangles the pre-pass did not cull, those to estimate from its first
    /// triangle on, the back faces of a two-sided mesh from its last triangle down.
    _visible_triangles: Buffer,
    /// Per mesh: the triangles whose estimate the pre-pass's refining step refines, listed by its
    /// estimator step.
    _refine_triangles: Buffer,
    /// Per mesh: the indirect dispatches of the pre-pass's estimator, patch and refining steps
    /// over the triangles its culling and estimator steps listed (`VkDispatchIndirectCommand`
    /// and the list's length, 4 words each, `LEVEL_DISPATCHES` per mesh), reset from
    /// `level_dispatch_reset` before each pre-pass.
    level_dispatches: Buffer,
    /// `level_dispatches` before the culling step: (0, 1, 1, 0), no workgroups yet.
    level_dispatch_reset: Buffer,
    /// `PATTERN_LEVELS`, the effective levels of the hardware patterns.
    pattern_levels: Buffer,
    /// The device's own effective-level table in `pattern_levels`, where the built-in one
    /// does not hold on it (`capture::check_patterns`).
    measured_table: std::sync::Mutex<Option<Arc<Vec<u32>>>>,
    /// Per triangle: its patch's tessellation levels, written by the pre-pass's last step.
    _patch_levels: Buffer,
    /// Per mesh, from its first triangle on: its visible triangles shaded on sub-vertices,
    /// those shaded per pixel, and those whose patch is the triangle itself (flat), as the
    /// pre-pass's last step lists them.
    _patch_lists: [Buffer; 3],
    /// Per mesh: the lengths of its interpolated and fallback lists (zeroed before each pre-pass).
    patch_counts: Buffer,
    /// The indirect draws of the first two lists (`VkDrawIndirectCommand`, one per triangle).
    patch_draws: [Buffer; 2],
    /// The indirect draws of each mesh's flat list (`VkDrawIndirectCommand`, two per mesh: the
    /// triangles shaded on their corners, then those shaded per pixel).
    flat_draws: Buffer,
    _lights: Buffer,
    _materials: Buffer,
    textures: SceneTextures,
    layout: PipelineLayout,
    _pool: DescriptorPool,
    descriptor_set: vk::DescriptorSet,
    _polygon_lights: Buffer,
    /// The polygonal lights' emissive geometry and the pipeline that draws it (None without).
    emitters: Vec<EmitterDraw>,
    emitter: Option<Pipeline>,
    /// The same for the analysis pipelines (ids), built with the counting variants.
    analysis_emitter: OnceCell<Pipeline>,
    variants: Vec<Variant>,
    /// The same pipelines drawing edges only, built by `enable_wireframe`.
    wireframe_variants: Option<Vec<Variant>>,
    /// The modules every variant shares; the variants' pipelines are built on first use.
    modules: Modules,
    /// Per material kind of the scene: its shader features and specialization constants.
    specializations: Vec<(Features, Specialization)>,
    levels: Buffer,
    /// The counting variants' four counters (`EvaluationCounters` in bindings.glsl).
    counters: Buffer,
    /// The counting variants, built on first use by `count_evaluations`.
    counting_variants: OnceCell<Vec<Variant>>,
    /// The level-recording variants, built on first use by `record_levels`.
    recording_variants: OnceCell<Vec<Variant>>,
    draws: Vec<DrawCall>,
    clear_color: [f32; 4],
    /// Most tessellated vertices one draw may emit, where the driver needs a limit.
    tessellated_vertex_budget: Option<u32>,
    /// The `pixel-deferred` passes, built on first use.
    deferred: OnceCell<Deferred>,
}

impl Renderer {
    /// Uploads `scene` and prepares its pipelines, once the scene was found to fit the device
    /// and the shaders (`limits::check`).
    pub fn new(context: &Arc<Context>, scene: &Scene) -> Result<Renderer> {
        Renderer::with_limits(context, scene, &context.limits)
    }

    /// [`Renderer::new`], checking the scene against `limits` where they are lower than the
    /// device's own (the tests reach each check with a small scene that way); never against
    /// higher ones.
    pub fn with_limits(context: &Arc<Context>, scene: &Scene, limits: &DeviceLimits) -> Result<Renderer> {
        limits::check(&scene.path, &SceneSizes::of(scene), &limits.min(&context.limits))?;
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut patch_indices = Vec::new();
        let mut triangle_neighbours: Vec<[u32; 4]> = Vec::new();
        let mut draws = Vec::new();
        let mut kinds: Vec<u32> = Vec::new();
        for (mesh_index, mesh) in scene.meshes.iter().enumerate() {
            let base = vertices.len() as u32;
            vertices.extend(mesh.positions.iter().zip(&mesh.normals).enumerate().map(|(i, (p, n))| Vertex {
                position: p.to_array(),
                normal: n.to_array(),
                uv: mesh.uvs.get(i).map_or([0.0; 2], |uv| uv.to_array()),
            }));
            let first_index = indices.len() as u32;
            indices.extend(mesh.indices.iter().map(|i| i + base));
            let first_patch_index = patch_indices.len() as u32;
            patch_indices.extend(adjacency_patches(mesh).iter().map(|i| i + base));
            let first_triangle = first_index / 3;
            triangle_neighbours
                .extend(neighbours(mesh).iter().map(|n| [n[0], n[1], n[2], 0].map(|t| t + first_triangle)));
            let kind = material_kind_id(&scene.materials[mesh.material].kind);
            let pipeline = kinds.iter().position(|&k| k == kind).unwrap_or_else(|| {
                kinds.push(kind);
                kinds.len() - 1
            });
            draws.push(DrawCall {
                first_triangle: first_index / 3,
                first_index,
                index_count: mesh.indices.len() as u32,
                first_patch_index,
                one_sided: !mesh.two_sided,
                material_index: mesh.material as u32,
                mesh_index: mesh_index as u32,
                pipeline,
            });
        }
        let (lights, point_count, directional_count) = gpu_lights(&scene.lights);
        let materials: Vec<GpuMaterial> = scene.materials.iter().map(gpu_material).collect();
        let polygon_lights = gpu_polygon_lights(&scene.lights);
        // The emitters' triangles go after the meshes' (level records cover the meshes only).
        let triangle_count = indices.len() / 3;
        let mut emitters = Vec::new();
        for (light_index, light) in polygon_lights.iter().enumerate() {
            let base = vertices.len() as u32;
            let count = light.info.x as u32;
            vertices.extend(light.vertices[..count as usize].iter().map(|v| Vertex {
                position: v.truncate().to_array(),
                normal: light.normal.truncate().to_array(),
                uv: [0.0; 2],
            }));
            let first_index = indices.len() as u32;
            indices.extend((1..count - 1).flat_map(|j| [base, base + j, base + j + 1]));
            emitters.push(EmitterDraw {
                first_index,
                index_count: indices.len() as u32 - first_index,
                light_index: light_index as u32,
            });
        }

        // Every buffer below is in `SceneSizes::buffers`, which `limits::check` checked.
        // Storage too: the deferred pass fetches triangles by id.
        let vertex_buffer = Buffer::with_data(
            context,
            "scene vertices",
            vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            &vertices,
        )?;
        let index_buffer = Buffer::with_data(
            context,
            "scene indices",
            vk::BufferUsageFlags::INDEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            &indices,
        )?;
        let patch_index_buffer = Buffer::with_data(
            context,
            "scene adjacency patches",
            vk::BufferUsageFlags::INDEX_BUFFER,
            &patch_indices,
        )?;
        let triangle_level_buffer =
            device_words(context, "triangle levels", triangle_count, vk::BufferUsageFlags::empty())?;
        if triangle_neighbours.is_empty() {
            triangle_neighbours.push([0; 4]);
        }
        let neighbour_buffer = Buffer::with_data(
            context,
            "triangle neighbours",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &triangle_neighbours,
        )?;
        let visible_triangle_buffer =
            device_words(context, "visible triangles", triangle_count, vk::BufferUsageFlags::empty())?;
        let refine_triangle_buffer =
            device_words(context, "triangles to refine", triangle_count, vk::BufferUsageFlags::empty())?;
        let patch_count_buffer = device_words(
            context,
            "interpolated and fallback patch counts",
            2 * draws.len(),
            vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        let level_dispatch_buffer = device_words(
            context,
            "pre-pass dispatches",
            4 * LEVEL_DISPATCHES as usize * draws.len(),
            vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        let level_dispatch_reset = Buffer::with_data(
            context,
            "pre-pass dispatch reset",
            vk::BufferUsageFlags::TRANSFER_SRC,
            &vec![[0u32, 1, 1, 0]; LEVEL_DISPATCHES as usize * draws.len().max(1)],
        )?;
        let patch_list = |name| device_words(context, name, triangle_count, vk::BufferUsageFlags::empty());
        let interpolated_patch_buffer = patch_list("interpolated patches")?;
        let fallback_patch_buffer = patch_list("fallback patches")?;
        let flat_patch_buffer = patch_list("flat patches")?;
        let indirect = vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let interpolated_draw_buffer =
            device_words(context, "interpolated patch draws", 4 * triangle_count, indirect)?;
        let fallback_draw_buffer =
            device_words(context, "fallback patch draws", 4 * triangle_count, indirect)?;
        let flat_draw_buffer = device_words(context, "flat patch draws", 2 * 4 * draws.len(), indirect)?;
        let level_buffer = Buffer::new(
            context,
            "level records",
            (triangle_count * 16) as vk::DeviceSize,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let counter_buffer = Buffer::new(
            context,
            "evaluation counters",
            16,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let light_buffer =
            Buffer::with_data(context, "scene lights", vk::BufferUsageFlags::STORAGE_BUFFER, &lights)?;
        let material_buffer =
            Buffer::with_data(context, "scene materials", vk::BufferUsageFlags::STORAGE_BUFFER, &materials)?;
        // A scene without polygonal lights still binds one (unread) entry.
        let polygon_count = polygon_lights.len();
        let polygon_entries =
            if polygon_lights.is_empty() { vec![GpuPolygonLight::default()] } else { polygon_lights };
        let polygon_buffer = Buffer::with_data(
            context,
            "scene polygonal lights",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &polygon_entries,
        )?;

        let patch_level_buffer = device_words(
            context,
            "patch tessellation levels",
            4 * triangle_count,
            vk::BufferUsageFlags::empty(),
        )?;
        let pattern_level_buffer = Buffer::with_data(
            context,
            "pattern levels",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &crate::shading::estimator::PATTERN_LEVELS,
        )?;

        let bindings =
            std::array::from_fn::<_, 21, _>(|b| shader_binding(b as u32, vk::DescriptorType::STORAGE_BUFFER));
        let push = [vk::PushConstantRange::default()
            .stage_flags(PUSH_STAGES)
            .size(std::mem::size_of::<DrawConstants>() as u32)];
        let material_bindings = material_set_bindings();
        let deferred_bindings = deferred_set_bindings();
        let layout = PipelineLayout::new(
            context,
            "forward layout",
            &[&bindings, &material_bindings, &deferred_bindings],
            &push,
        )?;
        let textures = SceneTextures::upload(context, scene, layout.set_layouts[1])?;
        let pool = DescriptorPool::new(
            context,
            "forward descriptors",
            1,
            &[vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 21 }],
        )?;
        let descriptor_set = pool.allocate(layout.set_layouts[0])?;
        bind_storage_buffers(
            context,
            descriptor_set,
            0,
            &[
                light_buffer.raw,
                material_buffer.raw,
                level_buffer.raw,
                counter_buffer.raw,
                polygon_buffer.raw,
                triangle_level_buffer.raw,
                neighbour_buffer.raw,
                vertex_buffer.raw,
                index_buffer.raw,
                visible_triangle_buffer.raw,
                patch_count_buffer.raw,
                pattern_level_buffer.raw,
                patch_level_buffer.raw,
                interpolated_patch_buffer.raw,
                fallback_patch_buffer.raw,
                interpolated_draw_buffer.raw,
                fallback_draw_buffer.raw,
                flat_patch_buffer.raw,
                flat_draw_buffer.raw,
                level_dispatch_buffer.raw,
                refine_triangle_buffer.raw,
            ],
        );

        let modules = Modules {
            forward_vert: ShaderModule::new(context, "forward.vert", shaders::single("forward.vert"))?,
            patch_vert: ShaderModule::new(context, "patch.vert", shaders::single("patch.vert"))?,
            fixed_tesc: ShaderModule::new(context, "fixed.tesc", shaders::single("fixed.tesc"))?,
        };
        let emitter = if emitters.is_empty() {
            None
        } else {
            Some(modules.emitter(context, &layout, Instrumentation::None)?)
        };
        let mut variants = Vec::new();
        let mut specializations = Vec::new();
        for &kind in &kinds {
            let features = Features {
                material_kind: kind,
                polygon_lights: polygon_count > 0,
                textured: SceneTextures::any(scene),
                ..Features::default()
            };
            let specialization = Specialization::default().int(1, point_count).int(2, directional_count);
            let specialization = polygon_specialization(specialization, scene, polygon_count);
            variants.push(Variant::new(features, Instrumentation::None, vk::PolygonMode::FILL));
            specializations.push((features, specialization));
        }
        context.name(descriptor_set, "forward descriptor set");
        let clear = scene.settings.clear_color;
        Ok(Renderer {
            context: context.clone(),
            vertices: vertex_buffer,
            indices: index_buffer,
            patch_indices: patch_index_buffer,
            _triangle_levels: triangle_level_buffer,
            _triangle_neighbours: neighbour_buffer,
            _visible_triangles: visible_triangle_buffer,
            _refine_triangles: refine_triangle_buffer,
            patch_counts: patch_count_buffer,
            level_dispatches: level_dispatch_buffer,
            level_dispatch_reset,
            pattern_levels: pattern_level_buffer,
            measured_table: std::sync::Mutex::new(None),
            _patch_levels: patch_level_buffer,
            _patch_lists: [interpolated_patch_buffer, fallback_patch_buffer, flat_patch_buffer],
            patch_draws: [interpolated_draw_buffer, fallback_draw_buffer],
            flat_draws: flat_draw_buffer,
            _lights: light_buffer,
            _materials: material_buffer,
            _polygon_lights: polygon_buffer,
            emitters,
            emitter,
            analysis_emitter: OnceCell::new(),
            textures,
            layout,
            _pool: pool,
            descriptor_set,
            variants,
            wireframe_variants: None,
            modules,
            specializations,
            levels: level_buffer,
            counters: counter_buffer,
            counting_variants: OnceCell::new(),
            recording_variants: OnceCell::new(),
            draws,
            clear_color: [clear.x, clear.y, clear.z, 0.0],
            tessellated_vertex_budget: tessellated_vertex_budget(&context.info),
            deferred: OnceCell::new(),
        })
    }

    /// Records the forward pass into `target`, leaving the colour image ready for `after`.
    pub fn record(&self, cmd: vk::CommandBuffer, target: &RenderTarget, view: &View, after: AfterPass) {
        let variants = match (&self.wireframe_variants, view.wireframe) {
            (Some(lines), true) => lines,
            _ => &self.variants,
        };
        self.record_with(variants, cmd, target, view, after);
    }

    /// Builds what `view` needs that is built on first use (the multirate pipelines, the
    /// deferred passes) and sizes the deferred id target for `target`.
    pub fn prepare(&self, view: &View, target: &RenderTarget) -> Result<()> {
        self.prepare_frame(view, target)?;
        let wireframe = self.wireframe_variants.as_ref().filter(|_| view.wireframe);
        for variants in std::iter::once(&self.variants).chain(wireframe) {
            self.prepare_variants(variants, view)?;
        }
        Ok(())
    }

    /// What a frame of `view` needs whichever variants draw it: the deferred passes, sized for
    /// `target`, and in multirate mode the device's tessellation patterns checked against the
    /// effective-level table. The analysis and recording frames prepare only their own
    /// variants' multirate pipelines: the timed ones are as slow to build and would go unused.
    fn prepare_frame(&self, view: &View, target: &RenderTarget) -> Result<()> {
        if view.mode == Mode::PixelDeferred {
            self.prepare_deferred(target.extent())?;
        }
        if view.mode == Mode::Multirate {
            // The effective-level table holds only for the tessellator it was computed from.
            if let capture::PatternTable::Measured(words) =
                capture::check_patterns(&self.context, view.n_max)?
            {
                self.use_measured_table(&words)?;
            }
        }
        Ok(())
    }

    /// Replaces the effective-level table the shaders read by the device's measured one (once
    /// per table); waits for the device first, since submitted frames read the buffer.
    fn use_measured_table(&self, words: &Arc<Vec<u32>>) -> Result<()> {
        let mut current = self.measured_table.lock().expect("measured table lock");
        if current.as_ref().is_some_and(|table| Arc::ptr_eq(table, words)) {
            return Ok(());
        }
        self.context.wait_idle()?;
        self.pattern_levels.upload(words.as_slice())?;
        *current = Some(Arc::clone(words));
        Ok(())
    }

    /// Builds the pipelines of `view`'s mode in each of `variants` that it lacks.
    fn prepare_variants(&self, variants: &[Variant], view: &View) -> Result<()> {
        let (context, layout) = (&self.context, &self.layout);
        for (variant, (_, specialization)) in variants.iter().zip(&self.specializations) {
            if let Some(mode) = SingleMode::of(view.mode) {
                build_once(variant.single_cell(mode), || {
                    self.modules.single(context, layout, variant, specialization, mode)
                })?;
            } else if view.mode == Mode::Multirate {
                build_once(variant.multirate_cell(view), || {
                    self.modules.multirate(context, layout, variant, specialization, view)
                })?;
            }
        }
        Ok(())
    }

    /// Builds the wireframe pipelines (once); false when the device cannot draw lines
    /// (`fillModeNonSolid`), in which case `View::wireframe` is ignored.
    pub fn enable_wireframe(&mut self) -> Result<bool> {
        if !self.context.features.fill_mode_non_solid {
            return Ok(false);
        }
        if self.wireframe_variants.is_none() {
            self.wireframe_variants = Some(self.new_variants(Instrumentation::None, vk::PolygonMode::LINE));
        }
        Ok(true)
    }

    fn record_with(
        &self,
        variants: &[Variant],
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        after: AfterPass,
    ) {
        self.record_timed(variants, cmd, target, view, after, &|_, _| {});
    }

    /// `record_with`, calling `stamp(Timed::PrePass, false)` before and `stamp(Timed::PrePass,
    /// true)` after the pre-pass (both back to back where there is none), and the same around
    /// each of its steps.
    fn record_timed(
        &self,
        variants: &[Variant],
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        after: AfterPass,
        stamp: &dyn Fn(Timed, bool),
    ) {
        stamp(Timed::PrePass, false);
        if view.mode == Mode::Multirate && view.estimator == Estimator::Compute {
            self.record_triangle_levels(variants, cmd, view, target.extent(), stamp);
        }
        stamp(Timed::PrePass, true);
        if view.mode == Mode::PixelDeferred {
            let instrumentation = variants.first().map_or(Instrumentation::None, |v| v.instrumentation);
            self.record_deferred(instrumentation, cmd, target, view, after);
            return;
        }
        let pick = |draw: &DrawCall| variants[draw.pipeline].for_view(view);
        let attachments = variants.first().map_or(Attachments::Color, |v| v.instrumentation.attachments());
        self.record_draws(&pick, true, cmd, target, attachments, view, self.clear_color, after);
    }

    /// `Estimator::Compute`: the pre-pass that prepares the multirate draws: culling, which
    /// lists each mesh's visible triangles, the estimator over those lists, then the patch
    /// levels, which also sort the visible triangles into the flat, interpolated and fallback
    /// patch lists and fill their indirect draws; with the barriers that order it after the
    /// previous frame's reads and before this frame's.
    fn record_triangle_levels(
        &self,
        variants: &[Variant],
        cmd: vk::CommandBuffer,
        view: &View,
        extent: vk::Extent2D,
        stamp: &dyn Fn(Timed, bool),
    ) {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        let device = &self.context.device;
        let barrier = |src: S, src_access: A, dst: S, dst_access: A| {
            let barriers = [vk::MemoryBarrier2::default()
                .src_stage_mask(src)
                .src_access_mask(src_access)
                .dst_stage_mask(dst)
                .dst_access_mask(dst_access)];
            // SAFETY: `cmd` is recording outside a render pass.
            unsafe {
                device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barriers))
            };
        };
        let storage = A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE;
        // The previous frame's indirect draws, vertex pulling and control stages have read the lists and levels.
        let readers = S::DRAW_INDIRECT | S::VERTEX_SHADER | S::TESSELLATION_CONTROL_SHADER;
        barrier(readers, A::NONE, S::COMPUTE_SHADER | S::CLEAR | S::COPY, A::NONE);
        for buffer in [&self.patch_counts, &self.flat_draws].into_iter().chain(&self.patch_draws) {
            // SAFETY: recording outside a render pass; the buffers have TRANSFER_DST usage.
            unsafe { device.cmd_fill_buffer(cmd, buffer.raw, 0, vk::WHOLE_SIZE, 0) };
        }
        let reset = [vk::BufferCopy::default().size(self.level_dispatches.size)];
        // SAFETY: recording outside a render pass; both buffers have the same size and the
        // TRANSFER_SRC / TRANSFER_DST usages.
        unsafe {
            device.cmd_copy_buffer(cmd, self.level_dispatch_reset.raw, self.level_dispatches.raw, &reset)
        };
        barrier(S::CLEAR | S::COPY, A::TRANSFER_WRITE, S::COMPUTE_SHADER, storage);
        let mut constants = draw_constants(view, extent);
        constants.patches_per_draw = self.patches_per_draw(view.n_max);
        self.bind_set_at(cmd, vk::PipelineBindPoint::COMPUTE, 0, self.descriptor_set);
        for step in PrePassStep::ALL {
            stamp(Timed::Step(step), false);
            for draw in &self.draws {
                let cell = variants[draw.pipeline].multirate_cell(view);
                let Some(pre_pass) = cell.get().and_then(|m| m.pre_pass.as_ref()) else {
                    debug_assert!(false, "render, measure and the viewer prepare the view first");
                    continue;
                };
                let pipeline = match step {
                    PrePassStep::Cull => &pre_pass.cull,
                    PrePassStep::Levels => &pre_pass.levels,
                    PrePassStep::Refine => &pre_pass.refine,
                    PrePassStep::Patches => &pre_pass.patches,
                };
                self.set_draw_constants(&mut constants, draw);
                constants.patch_base = draw.first_triangle;
                constants.triangle_count = draw.index_count / 3;
                let material_set = self.textures.sets[draw.material_index as usize];
                self.bind_set_at(cmd, vk::PipelineBindPoint::COMPUTE, 1, material_set);
                // SAFETY: recording outside a render pass; every bound object is owned by
                // `self` and outlives the submission.
                unsafe {
                    device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
                    device.cmd_push_constants(
                        cmd,
                        self.layout.raw,
                        PUSH_STAGES,
                        0,
                        bytemuck::bytes_of(&constants),
                    );
                    match step {
                        PrePassStep::Cull => {
                            device.cmd_dispatch(cmd, constants.triangle_count.div_ceil(PRE_PASS_GROUP), 1, 1)
                        }
                        // The later steps cover the triangles the culling step (or, for the
                        // refining step, the estimator step) listed, in the workgroups it counted.
                        PrePassStep::Levels | PrePassStep::Refine | PrePassStep::Patches => {
                            let which: vk::DeviceSize = match step {
                                PrePassStep::Patches => 1,
                                PrePassStep::Refine => 2,
                                _ => 0,
                            };
                            device.cmd_dispatch_indirect(
                                cmd,
                                self.level_dispatches.raw,
                                LEVEL_DISPATCH_STRIDE
                                    * (LEVEL_DISPATCHES * vk::DeviceSize::from(draw.mesh_index) + which),
                            )
                        }
                    }
                }
            }
            match step {
                PrePassStep::Cull => barrier(
                    S::COMPUTE_SHADER,
                    A::SHADER_STORAGE_WRITE,
                    S::COMPUTE_SHADER | S::DRAW_INDIRECT,
                    storage | A::INDIRECT_COMMAND_READ,
                ),
                PrePassStep::Levels => barrier(
                    S::COMPUTE_SHADER,
                    A::SHADER_STORAGE_WRITE,
                    S::COMPUTE_SHADER | S::DRAW_INDIRECT,
                    storage | A::INDIRECT_COMMAND_READ,
                ),
                PrePassStep::Refine => {
                    barrier(S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE, S::COMPUTE_SHADER, storage)
                }
                PrePassStep::Patches => barrier(
                    S::COMPUTE_SHADER,
                    A::SHADER_STORAGE_WRITE,
                    readers,
                    A::INDIRECT_COMMAND_READ | A::SHADER_STORAGE_READ,
                ),
            }
            stamp(Timed::Step(step), true);
        }
    }

    /// `Estimator::Compute`: draws the mesh's three patch lists of this frame's pre-pass, the
    /// interpolated patches with `interpolated`, the others with `lists`, each by the indirect
    /// draws the pre-pass filled (those it did not reach draw nothing).
    fn record_patch_lists(
        &self,
        cmd: vk::CommandBuffer,
        constants: &mut DrawConstants,
        draw: &DrawCall,
        view: &View,
        interpolated: vk::Pipeline,
        lists: ListPipelines<vk::Pipeline>,
    ) {
        let device = &self.context.device;
        let per_draw = self.patches_per_draw(view.n_max);
        let commands = (draw.index_count / 3).div_ceil(per_draw);
        let stride = std::mem::size_of::<vk::DrawIndirectCommand>() as u32;
        constants.patch_base = draw.first_triangle;
        constants.patches_per_draw = per_draw;
        constants.triangle_count = draw.index_count / 3;
        // The flat patches first and the per-pixel ones last, so that the early depth test
        // spares the per-pixel shading wherever the other lists cover it.
        let flat_draw = |constants: &mut DrawConstants, pipeline, which: u32, flag| {
            constants.flags = (constants.flags & !FLAG_FALLBACK_PATCHES) | flag;
            // SAFETY: recording inside the rendering begun by `record_draws`; the pre-pass
            // wrote the commands before the barrier it ends with; the draw buffers have
            // INDIRECT_BUFFER usage. A flat draw covers a mesh: no tessellated-vertex limit
            // applies.
            unsafe {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                self.push_draw_constants(cmd, constants);
                let offset = vk::DeviceSize::from((2 * draw.mesh_index + which) * stride);
                device.cmd_draw_indirect(cmd, self.flat_draws.raw, offset, 1, stride);
            }
        };
        let tessellated_draw = |constants: &mut DrawConstants, pipeline, which: usize, flag| {
            constants.flags = (constants.flags & !FLAG_FALLBACK_PATCHES) | flag;
            // SAFETY: as above.
            unsafe {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                self.push_draw_constants(cmd, constants);
                for k in 0..commands {
                    let offset = vk::DeviceSize::from((draw.first_triangle + k) * stride);
                    device.cmd_draw_indirect(cmd, self.patch_draws[which].raw, offset, 1, stride);
                }
            }
        };
        flat_draw(constants, lists.flat, 0, 0);
        tessellated_draw(constants, interpolated, 0, 0);
        // The per-pixel patches' depth first, then their shading where they are the nearest
        // surface: each covered pixel is shaded once, whatever the lists' order.
        tessellated_draw(constants, lists.fallback_prime, 1, FLAG_FALLBACK_PATCHES);
        flat_draw(constants, lists.flat_fallback_prime, 1, FLAG_FALLBACK_PATCHES);
        tessellated_draw(constants, lists.fallback, 1, FLAG_FALLBACK_PATCHES);
        flat_draw(constants, lists.flat_fallback, 1, FLAG_FALLBACK_PATCHES);
        constants.flags &= !FLAG_FALLBACK_PATCHES;
    }

    fn push_draw_constants(&self, cmd: vk::CommandBuffer, constants: &DrawConstants) {
        // SAFETY: `cmd` is recording; the layout's push range covers `DrawConstants`.
        unsafe {
            self.context.device.cmd_push_constants(
                cmd,
                self.layout.raw,
                PUSH_STAGES,
                0,
                bytemuck::bytes_of(constants),
            )
        };
    }

    /// The per-mesh fields of the push constants.
    fn set_draw_constants(&self, constants: &mut DrawConstants, draw: &DrawCall) {
        constants.material_index = draw.material_index;
        constants.mesh_index = draw.mesh_index;
        constants.flags =
            (constants.flags & !FLAG_ONE_SIDED) | if draw.one_sided { FLAG_ONE_SIDED } else { 0 };
    }

    /// The forward draws of every mesh with the pipeline `pick` gives, into `target`'s
    /// `attachments`, and with `emitters` the polygonal lights' emissive geometry.
    #[allow(clippy::too_many_arguments)]
    fn record_draws(
        &self,
        pick: &dyn Fn(&DrawCall) -> Option<MeshPipelines>,
        emitters: bool,
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        attachments: Attachments,
        view: &View,
        clear: [f32; 4],
        after: AfterPass,
    ) {
        let device = &self.context.device;
        let extent = target.extent();
        target.begin(device, cmd, clear, attachments);
        let mut constants = draw_constants(view, extent);
        // SAFETY: `cmd` is recording inside the rendering begun above; every bound object is
        // owned by `self` and outlives the submission (callers wait before dropping).
        unsafe {
            device.cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw], &[0]);
            device.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
            self.bind_set(cmd, 0, self.descriptor_set);
            for draw in &self.draws {
                self.set_draw_constants(&mut constants, draw);
                let cull = if draw.one_sided { vk::CullModeFlags::BACK } else { vk::CullModeFlags::NONE };
                let Some(pipelines) = pick(draw) else {
                    debug_assert!(false, "render, measure and the viewer prepare the view first");
                    continue;
                };
                device.cmd_set_cull_mode(cmd, cull);
                self.bind_set(cmd, 1, self.textures.sets[draw.material_index as usize]);
                if let Some(lists) = pipelines.lists {
                    self.record_patch_lists(cmd, &mut constants, draw, view, pipelines.first, lists);
                    continue;
                }
                // Multirate drawn here is `Estimator::Tcs`: 12-point adjacency patches.
                let adjacency = view.mode == Mode::Multirate;
                let (first_index, index_count, patches, indices_per_primitive) = match view.mode {
                    Mode::Pixel | Mode::Vertex | Mode::PixelDeferred => {
                        (draw.first_index, draw.index_count, u32::MAX, 3)
                    }
                    Mode::Fixed(level) => (
                        draw.first_index,
                        draw.index_count,
                        self.fixed_patches_per_draw(level, attachments),
                        3,
                    ),
                    Mode::Multirate => (
                        draw.first_patch_index,
                        draw.index_count / 3 * PATCH_SIZE as u32,
                        self.multirate_patches_per_draw(view.n_max),
                        PATCH_SIZE as u32,
                    ),
                };
                if adjacency {
                    device.cmd_bind_index_buffer(cmd, self.patch_indices.raw, 0, vk::IndexType::UINT32);
                }
                let chunk = patches.saturating_mul(indices_per_primitive);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipelines.first);
                let mut first = 0;
                while first < index_count {
                    let count = chunk.min(index_count - first);
                    constants.patch_base = draw.first_triangle + first / indices_per_primitive;
                    device.cmd_push_constants(
                        cmd,
                        self.layout.raw,
                        PUSH_STAGES,
                        0,
                        bytemuck::bytes_of(&constants),
                    );
                    device.cmd_draw_indexed(cmd, count, 1, first_index + first, 0, 0);
                    first += count;
                }
                if adjacency {
                    device.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
                }
            }
            let emitter = match attachments {
                Attachments::Color => self.emitter.as_ref(),
                Attachments::ColorAndIds => self.analysis_emitter.get(),
            };
            if let (Some(emitter), true) = (emitter, emitters) {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, emitter.raw);
                device.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
                for draw in &self.emitters {
                    constants.light_index = draw.light_index;
                    device.cmd_push_constants(
                        cmd,
                        self.layout.raw,
                        PUSH_STAGES,
                        0,
                        bytemuck::bytes_of(&constants),
                    );
                    device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0);
                }
            }
        }
        target.end(device, cmd, after, attachments);
    }

    /// Renders `view` in `multirate` mode with the level-recording variant and returns, per
    /// triangle of the scene (meshes in order), `[level, outer0, outer1, outer2]` as the
    /// control stage chose them (level 0: per-pixel fallback).
    pub fn record_levels(&self, target: &RenderTarget, view: &View) -> Result<Vec<[f32; 4]>> {
        let recording = self.instrumented_variants(&self.recording_variants, Instrumentation::RecordLevels);
        let view = View { mode: Mode::Multirate, ..view.clone() };
        self.prepare_frame(&view, target)?;
        self.prepare_variants(recording, &view)?;
        target.render_and_read(&self.context, |cmd| {
            self.record_with(recording, cmd, target, &view, AfterPass::Readback);
            let barrier = [vk::MemoryBarrier2::default()
                .src_stage_mask(
                    vk::PipelineStageFlags2::COMPUTE_SHADER
                        | vk::PipelineStageFlags2::TESSELLATION_CONTROL_SHADER,
                )
                .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                .dst_access_mask(vk::AccessFlags2::HOST_READ)];
            // SAFETY: recording command buffer.
            unsafe {
                self.context
                    .device
                    .cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barrier))
            };
        })?;
        let bytes = self.levels.mapped().expect("GpuToCpu memory is mapped");
        Ok(bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&bytes[..self.levels.size as usize]))
    }

    /// Renders `warmup` frames, then `frames` measured ones, with up to two frames in flight:
    /// when the forward pass of each measured frame ran on the GPU (timestamps outside the
    /// pass), when its pre-pass did, and the pipeline statistics of the last one. A frame's
    /// queries are read only once its slot comes round again, so reading never stalls the
    /// frame being recorded.
    pub fn measure(
        &self,
        target: &RenderTarget,
        view: &View,
        warmup: u32,
        frames: u32,
    ) -> Result<Measurement> {
        self.prepare(view, target)?;
        // Pass 0: the whole frame; pass 1: the pre-pass, within it; then its steps, where it
        // has them (every query read must have been written).
        let pre_pass = view.mode == Mode::Multirate && view.estimator == Estimator::Compute;
        let passes = if pre_pass { 2 + PRE_PASS_STEPS as u32 } else { 2 };
        let timer = GpuTimer::new(&self.context, passes, FRAMES_IN_FLIGHT as u32)?;
        let mut ring = FrameRing::new(&self.context, FRAMES_IN_FLIGHT)?;
        let mut measurement = Measurement::default();
        let mut frame_in_slot = [0u32; FRAMES_IN_FLIGHT];
        let total = warmup + frames;
        let collect = |ring: &mut FrameRing, slot: usize, frame: u32, measurement: &mut Measurement| {
            if ring.wait(slot)? && frame >= warmup {
                let intervals = timer.pass_intervals(slot as u32)?;
                measurement.frames.push(intervals[0]);
                if pre_pass {
                    measurement.pre_pass.push(intervals[1]);
                    let steps = PrePassStep::ALL.map(|step| intervals[Timed::Step(step).pass() as usize]);
                    measurement.pre_pass_steps.push(steps);
                }
                measurement.statistics = timer.read_statistics(slot as u32)?;
            }
            Ok::<_, crate::Error>(())
        };
        for frame in 0..total {
            let slot = frame as usize % FRAMES_IN_FLIGHT;
            collect(&mut ring, slot, frame_in_slot[slot], &mut measurement)?;
            ring.submit(slot, |cmd| {
                let slot = slot as u32;
                timer.reset(cmd, slot);
                timer.timestamp(cmd, slot, 0, false);
                timer.statistics(cmd, slot, true);
                // A step starts once the one before it has finished (the barrier between them
                // holds the next dispatch, not a top-of-pipe timestamp): its timestamps settle.
                let stamp = |timed: Timed, end: bool| match timed {
                    Timed::PrePass => timer.timestamp(cmd, slot, timed.pass(), end),
                    Timed::Step(_) => timer.settled_timestamp(cmd, slot, timed.pass(), end),
                };
                self.record_timed(&self.variants, cmd, target, view, AfterPass::Sampled, &stamp);
                timer.statistics(cmd, slot, false);
                timer.timestamp(cmd, slot, 0, true);
            })?;
            frame_in_slot[slot] = frame;
        }
        for frame in total..total + FRAMES_IN_FLIGHT as u32 {
            let slot = frame as usize % FRAMES_IN_FLIGHT;
            collect(&mut ring, slot, frame_in_slot[slot], &mut measurement)?;
        }
        Ok(measurement)
    }

    /// Renders one frame of `view` with the counting variant (never the timed one) and
    /// returns how many times the full shading function ran, by stage. Needs storage writes
    /// in the vertex pipeline and fragment stages (`vertexPipelineStoresAndAtomics`,
    /// `fragmentStoresAndAtomics`) and primitive ids in the fragment stage (`geometryShader`).
    pub fn count_evaluations(&self, target: &RenderTarget, view: &View) -> Result<EvaluationCounts> {
        let analysis = self.analysis_variants(target, view)?;
        self.context.run_once(|cmd| self.record_analysis(analysis, cmd, target, view, AfterPass::Sampled))?;
        Ok(self.read_counters())
    }

    /// One frame of `view` drawn by the analysis variant, the counting one: its image, which
    /// triangle each pixel shows, and how many times the full shading function ran. Its
    /// rasterisation and shading are the timed variant's (tests/counts.rs compares the two).
    pub fn analyze(&self, target: &RenderTarget, view: &View) -> Result<Analysis> {
        let analysis = self.analysis_variants(target, view)?;
        let (image, triangles) =
            target.render_and_read_with(&self.context, Attachments::ColorAndIds, |cmd| {
                self.record_analysis(analysis, cmd, target, view, AfterPass::Readback)
            })?;
        let triangles = triangles.expect("ColorAndIds reads the ids back");
        Ok(Analysis { image, triangles, evaluations: self.read_counters() })
    }

    /// The analysis variants, built on first use and prepared for `view`.
    fn analysis_variants(&self, target: &RenderTarget, view: &View) -> Result<&[Variant]> {
        let features = &self.context.features;
        if !(features.vertex_pipeline_stores && features.fragment_stores && features.geometry_shader) {
            return Err(crate::Error::Unsupported {
                device: self.context.info.name.clone(),
                what: "count shading evaluations and read triangle ids",
                missing: "vertexPipelineStoresAndAtomics, fragmentStoresAndAtomics and geometryShader",
            });
        }
        let analysis = self.instrumented_variants(&self.counting_variants, Instrumentation::CountEvaluations);
        target.prepare_ids(&self.context)?;
        if !self.emitters.is_empty() {
            build_once(&self.analysis_emitter, || {
                self.modules.emitter(&self.context, &self.layout, Instrumentation::CountEvaluations)
            })?;
        }
        self.prepare_frame(view, target)?;
        self.prepare_variants(analysis, view)?;
        Ok(analysis)
    }

    /// Records one analysis frame: the counters zeroed, the frame, the counters made visible
    /// to the host.
    fn record_analysis(
        &self,
        analysis: &[Variant],
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        after: AfterPass,
    ) {
        let device = &self.context.device;
        let to_shaders = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::CLEAR)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_GRAPHICS)
            .dst_access_mask(vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE)];
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_GRAPHICS)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        // SAFETY: recording outside a render pass; the counter buffer has TRANSFER_DST usage
        // and is 16 bytes long.
        unsafe {
            device.cmd_fill_buffer(cmd, self.counters.raw, 0, 16, 0);
            device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_shaders));
        }
        self.record_with(analysis, cmd, target, view, after);
        // SAFETY: recording outside a render pass.
        unsafe {
            device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host))
        };
    }

    /// The counters of the last analysis frame (after its submission has finished).
    fn read_counters(&self) -> EvaluationCounts {
        let bytes = self.counters.mapped().expect("GpuToCpu memory is mapped");
        let values: [u32; 4] = bytemuck::pod_read_unaligned(&bytes[..16]);
        EvaluationCounts {
            vertices: u64::from(values[0]),
            sub_vertices: u64::from(values[1]),
            fragments: u64::from(values[2]),
            culled_patches: u64::from(values[3]),
        }
    }

    /// The variants with `instrumentation`, made in `cell` on first use (their pipelines are
    /// built when a view first needs them).
    fn instrumented_variants<'a>(
        &self,
        cell: &'a OnceCell<Vec<Variant>>,
        instrumentation: Instrumentation,
    ) -> &'a [Variant] {
        cell.get_or_init(|| self.new_variants(instrumentation, vk::PolygonMode::FILL))
    }

    /// One variant per feature set the scene uses, with `instrumentation` and `polygon_mode`.
    fn new_variants(&self, instrumentation: Instrumentation, polygon_mode: vk::PolygonMode) -> Vec<Variant> {
        self.specializations
            .iter()
            .map(|(features, _)| Variant::new(*features, instrumentation, polygon_mode))
            .collect()
    }

    /// Patches per `Estimator::Tcs` multirate draw: besides the vertex budget, lavapipe
    /// (Mesa 22.3) restarts `gl_PrimitiveID` in the control stage every 1020 control points (85
    /// patches of 12), which would scramble the triangle indices; other drivers get no limit.
    /// (`Estimator::Compute` draws need no `gl_PrimitiveID`.)
    fn multirate_patches_per_draw(&self, n_max: u32) -> u32 {
        let patches = self.patches_per_draw(n_max);
        if self.tessellated_vertex_budget.is_some() {
            patches.min(LAVAPIPE_PRIMITIVE_ID_CONTROL_POINTS / PATCH_SIZE as u32)
        } else {
            patches
        }
    }

    /// Patches per `fixed:N` draw: besides the vertex budget, where the evaluation stage
    /// passes triangle ids on (`gl_PrimitiveID`), lavapipe's restart (see
    /// `multirate_patches_per_draw`) limits a draw to 340 patches of 3.
    fn fixed_patches_per_draw(&self, level: u32, attachments: Attachments) -> u32 {
        let patches = self.patches_per_draw(level);
        if self.tessellated_vertex_budget.is_some() && attachments == Attachments::ColorAndIds {
            patches.min(LAVAPIPE_PRIMITIVE_ID_CONTROL_POINTS / 3)
        } else {
            patches
        }
    }

    /// How many patches one draw may hold when every patch is tessellated at `level`.
    fn patches_per_draw(&self, level: u32) -> u32 {
        match self.tessellated_vertex_budget {
            Some(budget) => (budget / uniform_vertex_count(level) as u32).max(1),
            None => u32::MAX,
        }
    }

    /// Renders one frame into `target` and reads the float image back.
    pub fn render(&self, target: &RenderTarget, view: &View) -> Result<FloatImage> {
        self.prepare(view, target)?;
        target.render_and_read(&self.context, |cmd| self.record(cmd, target, view, AfterPass::Readback))
    }
}

impl Renderer {
    /// Binds `set` as set `index` of the forward layout for graphics on `cmd` (recording).
    fn bind_set(&self, cmd: vk::CommandBuffer, index: u32, set: vk::DescriptorSet) {
        self.bind_set_at(cmd, vk::PipelineBindPoint::GRAPHICS, index, set);
    }

    /// Binds `set` as set `index` of the forward layout at `bind_point` on `cmd` (recording).
    fn bind_set_at(
        &self,
        cmd: vk::CommandBuffer,
        bind_point: vk::PipelineBindPoint,
        index: u32,
        set: vk::DescriptorSet,
    ) {
        // SAFETY: `cmd` is recording; the set belongs to this renderer's layout and outlives
        // the submission.
        unsafe {
            self.context.device.cmd_bind_descriptor_sets(cmd, bind_point, self.layout.raw, index, &[set], &[])
        };
    }
}

/// A device-local storage buffer of `count` 32-bit words (at least one), written and read only
/// by shaders (and by the usages in `extra`).
fn device_words(
    context: &Arc<Context>,
    name: &str,
    count: usize,
    extra: vk::BufferUsageFlags,
) -> Result<Buffer> {
    let size = (count.max(1) * std::mem::size_of::<u32>()) as vk::DeviceSize;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | extra;
    Buffer::new(context, name, size, usage, gpu_allocator::MemoryLocation::GpuOnly)
}

/// The steps of the triangle-level pre-pass, in order: list the visible triangles, estimate
/// their levels (listing those to refine), refine those, combine each level with its neighbours'
/// into its patch's tessellation levels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrePassStep {
    Cull,
    Levels,
    Refine,
    Patches,
}

impl PrePassStep {
    /// Every step, in the order they run.
    pub const ALL: [PrePassStep; PRE_PASS_STEPS] =
        [PrePassStep::Cull, PrePassStep::Levels, PrePassStep::Refine, PrePassStep::Patches];

    /// Its name in `bench`'s columns (`<name>_ms_median`).
    pub fn name(self) -> &'static str {
        match self {
            PrePassStep::Cull => "cull",
            PrePassStep::Levels => "estimate",
            PrePassStep::Refine => "refine",
            PrePassStep::Patches => "patches",
        }
    }
}

/// How many steps the pre-pass has.
pub const PRE_PASS_STEPS: usize = 4;

/// What a timestamp pair of `measure` times: the whole frame, the pre-pass, or one of its steps.
#[derive(Clone, Copy)]
enum Timed {
    PrePass,
    Step(PrePassStep),
}

impl Timed {
    /// Its pass in `measure`'s `GpuTimer` (pass 0 is the whole frame).
    fn pass(self) -> u32 {
        match self {
            Timed::PrePass => 1,
            Timed::Step(step) => 2 + step as u32,
        }
    }
}

/// Lavapipe (Mesa 22.3) restarts `gl_PrimitiveID` in the tessellation stages every this many
/// control points within a draw: draws that read it there hold no more.
const LAVAPIPE_PRIMITIVE_ID_CONTROL_POINTS: u32 = 1020;

/// Invocations per work group of the triangle-level pre-pass (`PRE_PASS_GROUP` in
/// glsl/include/bindings.glsl, the `local_size_x` of its three compute shaders).
pub const PRE_PASS_GROUP: u32 = 64;

/// Listed triangles per block of the pre-pass's refining step (`REFINE_BLOCK` in
/// glsl/refine_levels.comp and glsl/triangle_levels.comp): a workgroup takes their children's
/// turns side by side, then estimates each of them. `tests/layout.rs` checks that the three agree.
pub const REFINE_BLOCK: u32 = 8;

/// The refining step's workgroup size on `info`'s device. A GPU runs invocations as threads:
/// `PRE_PASS_GROUP` of them share a block's children's turns (a GPU gains the most here: one
/// thread taking a triangle's turns in a row made the step 4.6 × the estimator step on an H200,
/// `docs/gpu.md`). A CPU device runs each SIMD batch through the whole estimator, idle lanes
/// or not: there the workgroup is the block alone, one batch.
fn refine_lanes(info: &crate::vk::context::DeviceInfo) -> u32 {
    if info.cpu {
        REFINE_BLOCK
    } else {
        PRE_PASS_GROUP
    }
}

/// Bytes per dispatch in `Renderer::level_dispatches` (`uvec4 level_dispatches[]`).
const LEVEL_DISPATCH_STRIDE: vk::DeviceSize = 16;

/// Dispatches per mesh in `Renderer::level_dispatches` (`LEVEL_DISPATCHES` in
/// glsl/include/bindings.glsl): the estimator, patch and refining steps'.
const LEVEL_DISPATCHES: vk::DeviceSize = 3;

/// The push constants of `view` on a target of `extent` (per draw: material, mesh, first
/// triangle).
fn draw_constants(view: &View, extent: vk::Extent2D) -> DrawConstants {
    DrawConstants {
        view_proj: camera::view_projection(&view.camera, extent.width, extent.height),
        eye: view.camera.eye.extend(1.0),
        viewport: Vec4::new(extent.width as f32, extent.height as f32, view.epsilon, view.n_max as f32),
        fixed_level: match view.mode {
            Mode::Fixed(level) => level,
            _ => 1,
        },
        flags: if view.heat_map { FLAG_HEAT_MAP } else { 0 }
            | if view.derivative_check { FLAG_DERIVATIVE_CHECK } else { 0 },
        ..Default::default()
    }
}

/// What this device's draws are split for, where that splitting exists only for lavapipe's
/// limits (None elsewhere): for the tools to print beside their timings.
pub fn draw_splitting_note(info: &crate::vk::context::DeviceInfo) -> Option<String> {
    tessellated_vertex_budget(info).map(|budget| {
        format!(
            "note: on lavapipe only, tessellated draws are split to emit at most {budget} vertices each \
             (Mesa 22.3 loses patches past about 2^16), and `--estimator tcs` multirate draws to 85 \
             patches (it restarts gl_PrimitiveID every 1020 control points); other devices draw \
             each mesh whole"
        )
    })
}

/// Lavapipe's draw module (Mesa 22.3) loses tessellated patches when one draw emits more than
/// about 2^16 vertices in one of its internal batches (measured: the 8192-patch plane renders
/// whole at fixed:15 and loses rows of patches from fixed:16 on). Splitting draws so that each
/// emits at most 65535 vertices avoids it; other drivers get no limit.
fn tessellated_vertex_budget(info: &crate::vk::context::DeviceInfo) -> Option<u32> {
    info.is_lavapipe().then_some(65535)
}

/// Renders `scene` headless at `width`×`height` with `view`.
pub fn render_headless(
    context: &Arc<Context>,
    scene: &Scene,
    view: &View,
    width: u32,
    height: u32,
) -> Result<FloatImage> {
    let renderer = Renderer::new(context, scene)?;
    let target = RenderTarget::new(context, vk::Extent2D { width, height })?;
    renderer.render(&target, view)
}

/// The shader modules every variant of the forward passes shares; the shading stages are
/// created per variant from their feature set (`shaders::spirv`).
struct Modules {
    forward_vert: ShaderModule,
    patch_vert: ShaderModule,
    fixed_tesc: ShaderModule,
}

/// The module of `stage` compiled for `features`.
fn variant_module(context: &Arc<Context>, stage: &str, features: Features) -> Result<ShaderModule> {
    ShaderModule::new(context, stage, shaders::spirv(stage, features))
}

const VERTEX_BINDINGS: [vk::VertexInputBindingDescription; 1] = [vk::VertexInputBindingDescription {
    binding: 0,
    stride: std::mem::size_of::<Vertex>() as u32,
    input_rate: vk::VertexInputRate::VERTEX,
}];

const VERTEX_ATTRIBUTES: [vk::VertexInputAttributeDescription; 3] = [
    vk::VertexInputAttributeDescription {
        location: 0,
        binding: 0,
        format: vk::Format::R32G32B32_SFLOAT,
        offset: std::mem::offset_of!(Vertex, position) as u32,
    },
    vk::VertexInputAttributeDescription {
        location: 1,
        binding: 0,
        format: vk::Format::R32G32B32_SFLOAT,
        offset: std::mem::offset_of!(Vertex, normal) as u32,
    },
    vk::VertexInputAttributeDescription {
        location: 2,
        binding: 0,
        format: vk::Format::R32G32_SFLOAT,
        offset: std::mem::offset_of!(Vertex, uv) as u32,
    },
];

/// A pipeline of the forward passes: the scene's vertices as filled triangles, into the float
/// colour target with depth; the cull mode is set per mesh (back faces of one-sided meshes).
/// Callers change what differs (patches, lines, inputs).
fn scene_pipeline<'a>(
    name: &'a str,
    stages: Vec<Stage<'a>>,
    layout: &'a PipelineLayout,
    instrumentation: Instrumentation,
) -> GraphicsPipelineDesc<'a> {
    GraphicsPipelineDesc {
        name,
        stages,
        layout,
        vertex_bindings: &VERTEX_BINDINGS,
        vertex_attributes: &VERTEX_ATTRIBUTES,
        topology: vk::PrimitiveTopology::TRIANGLE_LIST,
        patch_control_points: None,
        polygon_mode: vk::PolygonMode::FILL,
        cull_mode: vk::CullModeFlags::NONE,
        front_face: vk::FrontFace::COUNTER_CLOCKWISE,
        dynamic_cull_mode: true,
        color_formats: instrumentation.color_formats(),
        depth_format: Some(DEPTH_FORMAT),
        depth_use: DepthUse::Nearest,
        rasterizer_discard: false,
        optimization: instrumentation.optimization(),
    }
}

impl Modules {
    /// The pipeline of `variant` that draws `mode`.
    fn single(
        &self,
        context: &Arc<Context>,
        layout: &PipelineLayout,
        variant: &Variant,
        specialization: &Specialization,
        mode: SingleMode,
    ) -> Result<Pipeline> {
        let (features, instrumentation) = (variant.features, variant.instrumentation);
        let kind = features.material_kind;
        let stage = |stage, module, specialised: bool| Stage {
            stage,
            module,
            specialization: specialised.then_some(specialization),
        };
        let build = |name: String, stages: Vec<Stage<'_>>, control_points: Option<u32>| {
            let topology = if control_points.is_some() {
                vk::PrimitiveTopology::PATCH_LIST
            } else {
                vk::PrimitiveTopology::TRIANGLE_LIST
            };
            Pipeline::graphics(
                context,
                &GraphicsPipelineDesc {
                    topology,
                    patch_control_points: control_points,
                    polygon_mode: variant.polygon_mode,
                    ..scene_pipeline(&name, stages, layout, instrumentation)
                },
            )
        };
        use vk::ShaderStageFlags as S;
        match mode {
            SingleMode::Pixel => {
                let pixel_frag = variant_module(context, "pixel.frag", features)?;
                build(
                    format!("pixel mode, material kind {kind}"),
                    vec![stage(S::VERTEX, &self.forward_vert, false), stage(S::FRAGMENT, &pixel_frag, true)],
                    None,
                )
            }
            SingleMode::Vertex => {
                let gouraud_vert = variant_module(context, "gouraud.vert", features)?;
                let color_frag = variant_module(context, "color.frag", features)?;
                build(
                    format!("vertex mode, material kind {kind}"),
                    vec![stage(S::VERTEX, &gouraud_vert, true), stage(S::FRAGMENT, &color_frag, false)],
                    None,
                )
            }
            SingleMode::Fixed => {
                let shade_tese = variant_module(context, "shade.tese", features)?;
                let color_frag = variant_module(context, "color.frag", features)?;
                build(
                    format!("fixed mode, material kind {kind}"),
                    vec![
                        stage(S::VERTEX, &self.patch_vert, false),
                        stage(S::TESSELLATION_CONTROL, &self.fixed_tesc, false),
                        stage(S::TESSELLATION_EVALUATION, &shade_tese, true),
                        stage(S::FRAGMENT, &color_frag, false),
                    ],
                    Some(3),
                )
            }
        }
    }
}

impl Modules {
    /// The pipeline that draws the polygonal lights' emissive geometry with `instrumentation`'s
    /// attachments.
    fn emitter(
        &self,
        context: &Arc<Context>,
        layout: &PipelineLayout,
        instrumentation: Instrumentation,
    ) -> Result<Pipeline> {
        let features = instrumentation.features(Features::default());
        let emitter_frag = variant_module(context, "emitter.frag", features)?;
        use vk::ShaderStageFlags as S;
        let stages = vec![
            Stage { stage: S::VERTEX, module: &self.forward_vert, specialization: None },
            Stage { stage: S::FRAGMENT, module: &emitter_frag, specialization: None },
        ];
        Pipeline::graphics(context, &scene_pipeline("emissive geometry", stages, layout, instrumentation))
    }

    /// The multirate pipelines of `variant` for `view`'s estimator placement, split and
    /// discontinuity handling.
    fn multirate(
        &self,
        context: &Arc<Context>,
        layout: &PipelineLayout,
        variant: &Variant,
        specialization: &Specialization,
        view: &View,
    ) -> Result<Multirate> {
        let (split, discontinuity) = (split_id(view.split), discontinuity_id(view.discontinuity));
        let specialization = specialization.clone().int(3, split).int(4, discontinuity);
        let features = variant.features;
        let (multirate_tesc, control_points, pre_pass, specialization) = match view.estimator {
            // The analysis pipelines share multirate.tesc's instrumented module (its
            // `count_evaluations` variant); what it records or counts is specialised.
            Estimator::Tcs => {
                let instrumented = Features {
                    count_evaluations: variant.instrumentation != Instrumentation::None,
                    record_levels: false,
                    ..features
                };
                let module = variant_module(context, "multirate.tesc", instrumented)?;
                let specialization = specialization
                    .boolean(14, variant.instrumentation == Instrumentation::RecordLevels)
                    .boolean(15, variant.instrumentation == Instrumentation::CountEvaluations);
                (module, PATCH_SIZE as u32, None, specialization)
            }
            Estimator::Compute => {
                let module = variant_module(context, "triangle_levels.comp", features)?;
                let name = format!("triangle levels, material kind {}", features.material_kind);
                let optimization = variant.instrumentation.optimization();
                let levels =
                    Pipeline::compute(context, &name, layout, &module, Some(&specialization), optimization)?;
                let module = variant_module(context, "refine_levels.comp", features)?;
                let refining = specialization.clone().int(13, refine_lanes(&context.info) as i32);
                let name = format!("triangle levels refined, material kind {}", features.material_kind);
                let refine =
                    Pipeline::compute(context, &name, layout, &module, Some(&refining), optimization)?;
                let module = variant_module(context, "cull_triangles.comp", features)?;
                let cull =
                    Pipeline::compute(context, "triangle culling", layout, &module, None, optimization)?;
                let module = variant_module(context, "patch_levels.comp", features)?;
                let patches =
                    Pipeline::compute(context, "patch levels", layout, &module, None, optimization)?;
                let module = variant_module(context, "multirate_levels.tesc", features)?;
                (module, 3, Some(PrePass { cull, levels, refine, patches }), specialization)
            }
        };
        let multirate_tese = variant_module(context, "multirate.tese", features)?;
        let multirate_frag = variant_module(context, "multirate.frag", features)?;
        let name = format!(
            "multirate mode, estimator {}, material kind {}, split {split}, discontinuity {discontinuity}",
            view.estimator, features.material_kind
        );
        // The compute placement pulls the vertices of the pre-pass's patch lists.
        let pull_vert = match pre_pass {
            Some(_) => Some(ShaderModule::new(
                context,
                "multirate_pull.vert",
                shaders::single("multirate_pull.vert"),
            )?),
            None => None,
        };
        // `fragment` None: a depth prime (DepthUse::Prime).
        let graphics = |name: &str, fragment: Option<&ShaderModule>, depth_use| {
            let stage = |stage, module| Stage { stage, module, specialization: Some(&specialization) };
            use vk::ShaderStageFlags as S;
            let mut stages = vec![
                stage(S::VERTEX, pull_vert.as_ref().unwrap_or(&self.patch_vert)),
                stage(S::TESSELLATION_CONTROL, &multirate_tesc),
                stage(S::TESSELLATION_EVALUATION, &multirate_tese),
            ];
            stages.extend(fragment.map(|module| stage(S::FRAGMENT, module)));
            let scene = scene_pipeline(name, stages, layout, variant.instrumentation);
            let pulled = pull_vert.is_some();
            Pipeline::graphics(
                context,
                &GraphicsPipelineDesc {
                    topology: vk::PrimitiveTopology::PATCH_LIST,
                    patch_control_points: Some(control_points),
                    polygon_mode: variant.polygon_mode,
                    vertex_bindings: if pulled { &[] } else { scene.vertex_bindings },
                    vertex_attributes: if pulled { &[] } else { scene.vertex_attributes },
                    depth_use,
                    ..scene
                },
            )
        };
        if pre_pass.is_none() {
            let draw = graphics(&name, Some(&multirate_frag), DepthUse::Nearest)?;
            return Ok(Multirate { draw, lists: None, pre_pass });
        }
        let interpolated_frag = variant_module(context, "multirate_interpolated.frag", features)?;
        let draw =
            graphics(&format!("{name}, interpolated patches"), Some(&interpolated_frag), DepthUse::Nearest)?;
        let fallback =
            graphics(&format!("{name}, fallback patches"), Some(&multirate_frag), DepthUse::Primed)?;
        let fallback_prime = graphics(&format!("{name}, fallback patches' depth"), None, DepthUse::Prime)?;
        let flat_vert = variant_module(context, "multirate_flat.vert", features)?;
        let flat = |name: &str, fragment: Option<&ShaderModule>, depth_use| {
            let stage = |stage, module| Stage { stage, module, specialization: Some(&specialization) };
            let mut stages = vec![stage(vk::ShaderStageFlags::VERTEX, &flat_vert)];
            stages.extend(fragment.map(|module| stage(vk::ShaderStageFlags::FRAGMENT, module)));
            let scene = scene_pipeline(name, stages, layout, variant.instrumentation);
            Pipeline::graphics(
                context,
                &GraphicsPipelineDesc {
                    polygon_mode: variant.polygon_mode,
                    vertex_bindings: &[],
                    vertex_attributes: &[],
                    depth_use,
                    ..scene
                },
            )
        };
        let flat_fallback =
            flat(&format!("{name}, flat patches shaded per pixel"), Some(&multirate_frag), DepthUse::Primed)?;
        let flat_fallback_prime =
            flat(&format!("{name}, flat patches shaded per pixel, their depth"), None, DepthUse::Prime)?;
        let flat = flat(&format!("{name}, flat patches"), Some(&interpolated_frag), DepthUse::Nearest)?;
        let lists = ListPipelines { fallback, fallback_prime, flat, flat_fallback, flat_fallback_prime };
        Ok(Multirate { draw, lists: Some(lists), pre_pass })
    }
}
