//! The pipeline variants specialised to the scene's materials and lights: per material kind
//! one [`Variant`] per instrumentation (timed, counting, level-recording) and polygon mode, each
//! holding its modes' pipelines built on first use; the shader modules they share; and the
//! specialization constants they are built with.

use super::frame_config::may_draw_per_pixel;
use super::mode::{Mode, Placement};
use super::multirate_config::MultirateConfig;
use super::scene_geometry::SceneGeometry;
use super::textures::SceneTextures;
use super::view::View;
use crate::error::Result;
use crate::gpu_interface::slots::{WITHOUT_MIXED_LIGHTS, WITH_MIXED_LIGHTS};
use crate::gpu_interface::specialization as spec;
use crate::gpu_types::Vertex;
use crate::scene::adjacency::PATCH_SIZE;
use crate::scene::{PolygonSampling, Scene};
use crate::shaders::{self, Features};
use crate::vk::pipeline::{
    DepthUse, GraphicsPipelineDesc, Optimization, Pipeline, PipelineLayout, ShaderModule, Specialization,
    Stage,
};
use crate::vk::target::{Attachments, COLOR_FORMAT, DEPTH_FORMAT, ID_FORMAT};
use crate::vk::Context;
use ash::vk;
use std::cell::OnceCell;
use std::sync::Arc;

/// The scene's pipeline variants and what they are built from.
pub(super) struct Pipelines {
    /// The modules every variant shares; the variants' pipelines are built on first use.
    modules: Modules,
    /// Per material kind of the scene: its shader features and specialization constants.
    pub specializations: Vec<(Features, Specialization)>,
    /// The timed variants, one per material kind (`DrawCall::pipeline`).
    pub variants: Vec<Variant>,
    /// The same pipelines drawing edges only, built by `Renderer::enable_wireframe`.
    pub wireframe_variants: Option<Vec<Variant>>,
    /// The counting variants, built on first use by `count_evaluations` and `analyze`.
    counting_variants: OnceCell<Vec<Variant>>,
    /// The level-recording variants, built on first use by `record_levels`.
    recording_variants: OnceCell<Vec<Variant>>,
    /// The pipeline that draws the polygonal lights' emissive geometry (None without).
    pub emitter: Option<Pipeline>,
    /// The same for the analysis pipelines (ids), built with the counting variants.
    pub analysis_emitter: OnceCell<Pipeline>,
}

impl Pipelines {
    /// The shared modules, the emitter pipeline, and one timed variant per material kind of
    /// `geometry` (no pipeline of theirs built yet).
    pub(super) fn new(
        context: &Arc<Context>,
        scene: &Scene,
        layout: &PipelineLayout,
        geometry: &SceneGeometry,
    ) -> Result<Pipelines> {
        let modules = Modules {
            forward_vert: ShaderModule::new(context, "forward.vert", shaders::single("forward.vert"))?,
            patch_vert: ShaderModule::new(context, "patch.vert", shaders::single("patch.vert"))?,
            fixed_tesc: ShaderModule::new(context, "fixed.tesc", shaders::single("fixed.tesc"))?,
        };
        let emitter = if geometry.emitters.is_empty() {
            None
        } else {
            Some(modules.emitter(context, layout, Instrumentation::None)?)
        };
        let polygon_count = geometry.polygon_lights.len();
        let mut variants = Vec::new();
        let mut specializations = Vec::new();
        for &kind in &geometry.kinds {
            let features = Features {
                material_kind: kind,
                polygon_lights: polygon_count > 0,
                textured: SceneTextures::any(scene),
                shadows: !scene.shadow_casters.is_empty(),
                ..Features::default()
            };
            let specialization = Specialization::default()
                .int(spec::POINT_LIGHT_COUNT.id, geometry.lights.point_count)
                .int(spec::DIRECTIONAL_LIGHT_COUNT.id, geometry.lights.directional_count)
                .boolean(spec::SHADOWS.id, !scene.shadow_casters.is_empty())
                .int(spec::SHADOWED_POINT_LIGHTS.id, geometry.lights.shadowed_point_count)
                .int(spec::SHADOWED_DIRECTIONAL_LIGHTS.id, geometry.lights.shadowed_directional_count);
            let specialization = polygon_specialization(specialization, scene, polygon_count);
            variants.push(Variant::new(features, Instrumentation::None, vk::PolygonMode::FILL));
            specializations.push((features, specialization));
        }
        Ok(Pipelines {
            modules,
            specializations,
            variants,
            wireframe_variants: None,
            counting_variants: OnceCell::new(),
            recording_variants: OnceCell::new(),
            emitter,
            analysis_emitter: OnceCell::new(),
        })
    }

    /// `forward.vert`, which the shadow pass draws with too (depth only).
    pub(super) fn forward_vert(&self) -> &ShaderModule {
        &self.modules.forward_vert
    }

    /// One variant per feature set the scene uses, with `instrumentation` and `polygon_mode`.
    pub(super) fn new_variants(
        &self,
        instrumentation: Instrumentation,
        polygon_mode: vk::PolygonMode,
    ) -> Vec<Variant> {
        self.specializations
            .iter()
            .map(|(features, _)| Variant::new(*features, instrumentation, polygon_mode))
            .collect()
    }

    /// The filled variants with `instrumentation`; the instrumented ones are made on first use
    /// (their pipelines are built when a view first needs them).
    pub(super) fn instrumented(&self, instrumentation: Instrumentation) -> &[Variant] {
        let cell = match instrumentation {
            Instrumentation::None => return &self.variants,
            Instrumentation::RecordLevels => &self.recording_variants,
            Instrumentation::CountEvaluations => &self.counting_variants,
        };
        cell.get_or_init(|| self.new_variants(instrumentation, vk::PolygonMode::FILL))
    }

    /// Builds the pipelines of `view`'s mode (in multirate mode, of `config`) in each of
    /// `variants` that it lacks; `one_sided` per mesh (the back faces' per-pixel choice).
    pub(super) fn prepare(
        &self,
        context: &Arc<Context>,
        layout: &PipelineLayout,
        variants: &[Variant],
        view: &View,
        config: &MultirateConfig,
        one_sided: impl Iterator<Item = bool> + Clone,
    ) -> Result<()> {
        for (variant, (_, specialization)) in variants.iter().zip(&self.specializations) {
            if let Some(mode) = SingleMode::of(view.mode) {
                build_once(variant.single_cell(mode), || {
                    self.modules.single(context, layout, variant, specialization, mode)
                })?;
            } else if view.mode == Mode::Multirate {
                build_once(variant.multirate_cell(config), || {
                    self.modules.multirate(context, layout, variant, specialization, config)
                })?;
                if may_draw_per_pixel(view, one_sided.clone()) {
                    build_once(variant.single_cell(SingleMode::Pixel), || {
                        self.modules.single(context, layout, variant, specialization, SingleMode::Pixel)
                    })?;
                }
            }
        }
        Ok(())
    }

    /// The pipeline that draws the emissive geometry into `attachments` (None without
    /// polygonal lights, or before `prepare_analysis_emitter` for the analysis frames).
    pub(super) fn emitter_for(&self, attachments: Attachments) -> Option<&Pipeline> {
        match attachments {
            Attachments::Color => self.emitter.as_ref(),
            Attachments::ColorAndIds => self.analysis_emitter.get(),
        }
    }

    /// The emissive-geometry pipeline of the analysis variants, built on first use.
    pub(super) fn prepare_analysis_emitter(
        &self,
        context: &Arc<Context>,
        layout: &PipelineLayout,
    ) -> Result<()> {
        build_once(&self.analysis_emitter, || {
            self.modules.emitter(context, layout, Instrumentation::CountEvaluations)
        })
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
pub(super) struct Variant {
    pixel: OnceCell<Pipeline>,
    vertex: OnceCell<Pipeline>,
    tessellated: OnceCell<Pipeline>,
    /// Indexed by estimator placement, `split` and `discontinuity` (their specialization
    /// constants); built on first use by `Renderer::prepare`, since the estimator makes them
    /// slow to compile.
    multirate: [[[OnceCell<Multirate>; 2]; 2]; 2],
    /// The shader variant's features, instrumentation included.
    features: Features,
    pub instrumentation: Instrumentation,
    polygon_mode: vk::PolygonMode,
}

/// What a pipeline variant records besides the image. Only `None` is ever timed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Instrumentation {
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
    /// How many instrumentations there are.
    pub(super) const COUNT: usize = 3;

    /// Its index among the [`Instrumentation::COUNT`].
    pub(super) fn index(self) -> usize {
        match self {
            Instrumentation::None => 0,
            Instrumentation::RecordLevels => 1,
            Instrumentation::CountEvaluations => 2,
        }
    }

    /// The attachments the variant's forward passes draw into.
    pub(super) fn attachments(self) -> Attachments {
        match self {
            Instrumentation::CountEvaluations => Attachments::ColorAndIds,
            Instrumentation::None | Instrumentation::RecordLevels => Attachments::Color,
        }
    }

    /// Only the timed pipelines are worth the driver's optimisation.
    pub(super) fn optimization(self) -> Optimization {
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
    pub(super) fn features(self, features: Features) -> Features {
        Features {
            count_evaluations: self == Instrumentation::CountEvaluations,
            record_levels: self == Instrumentation::RecordLevels,
            ..features
        }
    }
}

/// The pipelines of `multirate` mode for one estimator placement.
pub(super) struct Multirate {
    draw: Pipeline,
    /// `Placement::Compute`: the pipelines of the other patch lists; `draw` then draws only
    /// the tessellated patches shaded on their sub-vertices, and its fragment shader holds no
    /// shading code (multirate_interpolated.frag).
    lists: Option<ListPipelines<Pipeline>>,
}

/// `Placement::Compute`: the pipelines of the pre-pass's fallback and flat patch lists.
#[derive(Clone, Copy)]
pub(super) struct ListPipelines<P> {
    /// The fallback patches, shaded per pixel (multirate.frag) where they are the nearest
    /// surface once every list has been drawn into the depth attachment (DepthUse::Primed).
    pub fallback: P,
    /// The fallback patches' depth (DepthUse::Prime), before the fallback patches are shaded: the
    /// lists are filled by atomics in no fixed order, and the early depth test alone would let
    /// the per-pixel shading of overlapping fallback patches depend on that order.
    pub fallback_prime: P,
    /// The flat patches (all levels 1), without tessellation stages: multirate_flat.vert shades
    /// their corners. With shadows, listed, only those some light reaches in part.
    pub flat: P,
    /// With shadows: the flat patches no light reaches only in part, drawn by a fragment stage
    /// without lookup code.
    pub flat_without_mixed: Option<P>,
    /// With shadows: the interpolated patches no light reaches only in part, likewise (the
    /// mesh's first pipeline then draws the others).
    pub interpolated_without_mixed: Option<P>,
    /// The flat patches shaded per pixel: multirate_flat.vert passes their corners on to
    /// multirate.frag (DepthUse::Primed).
    pub flat_fallback: P,
    /// Their depth (DepthUse::Prime).
    pub flat_fallback_prime: P,
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

    /// The pipelines of `view` (in multirate mode, of `config`; None: not yet prepared).
    pub(super) fn for_view(&self, view: &View, config: &MultirateConfig) -> Option<MeshPipelines> {
        let one = |pipeline: &Pipeline| MeshPipelines { first: pipeline.raw, lists: None, back_faces: None };
        match view.mode {
            Mode::Pixel | Mode::Vertex | Mode::Fixed(_) => {
                self.single_cell(SingleMode::of(view.mode)?).get().map(one)
            }
            // Drawn by `record_deferred`, with its own pipelines.
            Mode::PixelDeferred => None,
            Mode::Multirate => self.multirate_cell(config).get().map(|m| MeshPipelines {
                first: m.draw.raw,
                lists: m.lists.as_ref().map(|l| ListPipelines {
                    fallback: l.fallback.raw,
                    fallback_prime: l.fallback_prime.raw,
                    flat: l.flat.raw,
                    flat_without_mixed: l.flat_without_mixed.as_ref().map(|p| p.raw),
                    interpolated_without_mixed: l.interpolated_without_mixed.as_ref().map(|p| p.raw),
                    flat_fallback: l.flat_fallback.raw,
                    flat_fallback_prime: l.flat_fallback_prime.raw,
                }),
                back_faces: m.lists.as_ref().and(self.pixel.get()).map(|p| p.raw),
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

    /// The multirate pipelines of `config`'s placement, split and discontinuity handling.
    pub(super) fn multirate_cell(&self, config: &MultirateConfig) -> &OnceCell<Multirate> {
        let placement = usize::from(config.placement == Placement::Compute);
        let (split, discontinuity) = config.estimator_ids();
        &self.multirate[placement][split as usize][discontinuity as usize]
    }
}

/// `specialization` with the estimator's `SPLIT` and `DISCONTINUITY` of `config`.
pub(super) fn estimator_specialization(
    specialization: &Specialization,
    config: &MultirateConfig,
) -> Specialization {
    let (split, discontinuity) = config.estimator_ids();
    specialization.clone().int(spec::SPLIT.id, split).int(spec::DISCONTINUITY.id, discontinuity)
}

/// The pipelines that draw one mesh.
#[derive(Clone, Copy)]
pub(super) struct MeshPipelines {
    pub first: vk::Pipeline,
    /// Multirate's other patch lists (`Multirate::lists`): with them, all three draw the
    /// pre-pass's patch lists, `first` the interpolated one.
    pub lists: Option<ListPipelines<vk::Pipeline>>,
    /// With the lists, the back faces of a two-sided mesh: `pixel` mode's pipeline, drawn over
    /// the mesh with front faces culled after the lists (`Renderer::record_mesh`).
    pub back_faces: Option<vk::Pipeline>,
}

/// A list's pipeline, or with shadows its two by visibility class (`DRAWN_SHADOW_CLASSES`):
/// those some light reaches in part, and those none does, without lookup code. `specs`: every
/// class, with mixed lights, without.
fn drawn_by_class(
    shadows: bool,
    name: &str,
    [every, with_mixed, without_mixed]: [&Specialization; 3],
    build: impl Fn(&str, &Specialization) -> Result<Pipeline>,
) -> Result<(Pipeline, Option<Pipeline>)> {
    if !shadows {
        return Ok((build(name, every)?, None));
    }
    let with = build(&format!("{name} some light reaches in part"), with_mixed)?;
    Ok((with, Some(build(&format!("{name} no light reaches in part"), without_mixed)?)))
}

/// The specialization constants of the scene's polygonal lights (`spec::POLYGON_LIGHTS`; only
/// the variants with polygonal lights have them).
fn polygon_specialization(specialization: Specialization, scene: &Scene, count: usize) -> Specialization {
    let sampling = scene.settings.light_sampling;
    let technique = match sampling.technique {
        PolygonSampling::ProjectedSolidAngle => 0,
        PolygonSampling::SolidAngle => 1,
    };
    specialization
        .int(spec::POLYGON_LIGHT_COUNT.id, count as i32)
        .int(spec::POLYGON_SAMPLES.id, sampling.samples as i32)
        .int(spec::POLYGON_TECHNIQUE.id, technique)
        .float(spec::MIS_VISIBILITY.id, sampling.mis_visibility)
}

/// The shader modules every variant of the forward passes shares; the shading stages are
/// created per variant from their feature set (`shaders::spirv`).
struct Modules {
    forward_vert: ShaderModule,
    patch_vert: ShaderModule,
    fixed_tesc: ShaderModule,
}

/// The module of `stage` compiled for `features`.
pub(super) fn variant_module(
    context: &Arc<Context>,
    stage: &str,
    features: Features,
) -> Result<ShaderModule> {
    ShaderModule::new(context, stage, shaders::spirv(stage, features))
}

/// The scene's vertex buffer: one binding of [`Vertex`] per vertex.
pub(super) const VERTEX_BINDINGS: [vk::VertexInputBindingDescription; 1] =
    [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<Vertex>() as u32,
        input_rate: vk::VertexInputRate::VERTEX,
    }];

/// [`Vertex`]'s position, normal and uv at locations 0, 1 and 2.
pub(super) const VERTEX_ATTRIBUTES: [vk::VertexInputAttributeDescription; 3] = [
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
pub(super) fn scene_pipeline<'a>(
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

    /// The multirate pipelines of `variant` for `config`'s estimator placement, split and
    /// discontinuity handling (the pre-pass's own are `pre_pass::pipelines`).
    fn multirate(
        &self,
        context: &Arc<Context>,
        layout: &PipelineLayout,
        variant: &Variant,
        specialization: &Specialization,
        config: &MultirateConfig,
    ) -> Result<Multirate> {
        let (split, discontinuity) = config.estimator_ids();
        let specialization = estimator_specialization(specialization, config);
        let features = variant.features;
        let compute = config.placement == Placement::Compute;
        let (multirate_tesc, control_points, specialization) = match config.placement {
            // The analysis pipelines share multirate.tesc's instrumented module (its
            // `count_evaluations` variant); what it records or counts is specialised.
            Placement::Tcs => {
                let instrumented = Features {
                    count_evaluations: variant.instrumentation != Instrumentation::None,
                    record_levels: false,
                    ..features
                };
                let module = variant_module(context, "multirate.tesc", instrumented)?;
                let specialization = specialization
                    .boolean(spec::RECORD_LEVELS.id, variant.instrumentation == Instrumentation::RecordLevels)
                    .boolean(
                        spec::COUNT_CULLED_PATCHES.id,
                        variant.instrumentation == Instrumentation::CountEvaluations,
                    );
                (module, PATCH_SIZE as u32, specialization)
            }
            Placement::Compute => {
                let module = variant_module(context, "multirate_levels.tesc", features)?;
                (module, 3, specialization)
            }
        };
        let multirate_tese = variant_module(context, "multirate.tese", features)?;
        let multirate_frag = variant_module(context, "multirate.frag", features)?;
        let name = format!(
            "multirate mode, estimator {}, material kind {}, split {split}, discontinuity {discontinuity}",
            config.placement, features.material_kind
        );
        // The compute placement pulls the vertices of the pre-pass's patch lists.
        let pull_vert = match compute {
            true => Some(ShaderModule::new(
                context,
                "multirate_pull.vert",
                shaders::single("multirate_pull.vert"),
            )?),
            false => None,
        };
        // `fragment` None: a depth prime (DepthUse::Prime).
        let graphics_with =
            |name: &str, fragment: Option<&ShaderModule>, depth_use, specialization: &Specialization| {
                let stage = |stage, module| Stage { stage, module, specialization: Some(specialization) };
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
        let graphics =
            |name: &str, fragment, depth_use| graphics_with(name, fragment, depth_use, &specialization);
        if !compute {
            let draw = graphics(&name, Some(&multirate_frag), DepthUse::Nearest)?;
            return Ok(Multirate { draw, lists: None });
        }
        let interpolated_frag = variant_module(context, "multirate_interpolated.frag", features)?;
        // With shadows, the interpolated and the flat lists are each drawn twice by the patches'
        // visibility classes (DRAWN_SHADOW_CLASSES): those no light reaches only in part with no
        // lookup code (llvmpipe runs every branch).
        let by_class = |drawn| {
            let classes = specialization.clone().uint(spec::DRAWN_SHADOW_CLASSES.id, drawn);
            match drawn {
                WITHOUT_MIXED_LIGHTS => classes.boolean(spec::SHADOW_LOOKUPS.id, false),
                _ => classes,
            }
        };
        let (with_mixed, without_mixed) = (by_class(WITH_MIXED_LIGHTS), by_class(WITHOUT_MIXED_LIGHTS));
        let specs = [&specialization, &with_mixed, &without_mixed];
        let (draw, interpolated_without_mixed) = drawn_by_class(
            features.shadows,
            &format!("{name}, interpolated patches"),
            specs,
            |name, spec| graphics_with(name, Some(&interpolated_frag), DepthUse::Nearest, spec),
        )?;
        let fallback =
            graphics(&format!("{name}, fallback patches"), Some(&multirate_frag), DepthUse::Primed)?;
        let fallback_prime = graphics(&format!("{name}, fallback patches' depth"), None, DepthUse::Prime)?;
        let flat_vert = variant_module(context, "multirate_flat.vert", features)?;
        let flat_with =
            |name: &str, fragment: Option<&ShaderModule>, depth_use, specialization: &Specialization| {
                let stage = |stage, module| Stage { stage, module, specialization: Some(specialization) };
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
        let flat = |name: &str, fragment, depth_use| flat_with(name, fragment, depth_use, &specialization);
        let flat_fallback =
            flat(&format!("{name}, flat patches shaded per pixel"), Some(&multirate_frag), DepthUse::Primed)?;
        let flat_fallback_prime =
            flat(&format!("{name}, flat patches shaded per pixel, their depth"), None, DepthUse::Prime)?;
        let (flat, flat_without_mixed) =
            drawn_by_class(features.shadows, &format!("{name}, flat patches"), specs, |name, spec| {
                flat_with(name, Some(&interpolated_frag), DepthUse::Nearest, spec)
            })?;
        let lists = ListPipelines {
            fallback,
            fallback_prime,
            flat,
            flat_without_mixed,
            interpolated_without_mixed,
            flat_fallback,
            flat_fallback_prime,
        };
        Ok(Multirate { draw, lists: Some(lists) })
    }
}
