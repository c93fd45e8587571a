//! `pixel-deferred` mode: the per-pixel reference through a visibility buffer. A first pass
//! draws every triangle's id (mesh + 1, scene triangle index) into a float target with the
//! `pixel` mode's rasterisation; a second, full-screen pass per mesh reads the ids, fetches the
//! triangle from the vertex and index buffers, rebuilds perspective-correct barycentrics and
//! their screen derivatives analytically (seed 002, `glsl/include/derivatives.glsl`) and shades.
//! The same id buffer gives `analyze --measured` each pixel's triangle.

use super::descriptors::Recorder;
use super::draws::{ForwardDraws, IndirectCounts};
use super::frame_config::FrameConfig;
use super::pipelines::{
    scene_pipeline, variant_module, Instrumentation, MeshPipelines, VERTEX_ATTRIBUTES, VERTEX_BINDINGS,
};
use super::pre_pass::steps::FrameStamps;
use crate::error::{Error, Result};
use crate::gpu_interface::bindings::forward;
use crate::shaders::{self, Features};
use crate::vk::pipeline::{
    bind_sampled_images, DescriptorPool, GraphicsPipelineDesc, Pipeline, PipelineLayout, ShaderModule,
    Specialization, Stage,
};
use crate::vk::target::{AfterPass, Attachments, DepthAfter, RenderTarget};
use crate::vk::texture::Sampler;
use crate::vk::Context;
use ash::vk;
use std::cell::RefCell;
use std::sync::Arc;

/// The pipelines, the id target (sized on use) and set 2.
pub struct Deferred {
    context: Arc<Context>,
    visibility: Pipeline,
    /// Per material kind, in the renderer's variant order: `[0]` plain, `[1]` counting
    /// (empty where the device cannot count).
    shade: [Vec<Pipeline>; 2],
    _pool: DescriptorPool,
    pub set: vk::DescriptorSet,
    sampler: Sampler,
    ids: RefCell<Option<RenderTarget>>,
}

impl Deferred {
    /// Builds the passes for `specializations` (one per material kind: its shader features and
    /// specialization constants); needs primitive ids in the fragment stage, that is the
    /// `geometryShader` feature.
    pub fn new(
        context: &Arc<Context>,
        layout: &PipelineLayout,
        specializations: &[(Features, Specialization)],
    ) -> Result<Deferred> {
        if !context.features.geometry_shader {
            return Err(Error::Unsupported {
                device: context.info.name.clone(),
                what: "render pixel-deferred (primitive ids in the fragment stage)",
                missing: "the geometryShader feature",
            });
        }
        let visibility_vert =
            ShaderModule::new(context, "visibility.vert", shaders::single("visibility.vert"))?;
        let visibility_frag =
            ShaderModule::new(context, "visibility.frag", shaders::single("visibility.frag"))?;
        let fullscreen = ShaderModule::new(context, "fullscreen.vert", shaders::single("fullscreen.vert"))?;
        // The visibility pass reads positions only; the full-screen passes read no vertices.
        fn desc<'a>(
            name: &'a str,
            stages: Vec<Stage<'a>>,
            layout: &'a PipelineLayout,
            vertex_input: bool,
            instrumentation: Instrumentation,
        ) -> GraphicsPipelineDesc<'a> {
            GraphicsPipelineDesc {
                vertex_bindings: if vertex_input { &VERTEX_BINDINGS } else { &[] },
                vertex_attributes: if vertex_input { &VERTEX_ATTRIBUTES[..1] } else { &[] },
                // The id pass culls as the forward passes do; the full-screen passes need not.
                dynamic_cull_mode: vertex_input,
                ..scene_pipeline(name, stages, layout, instrumentation)
            }
        }
        use vk::ShaderStageFlags as S;
        let visibility = Pipeline::graphics(
            context,
            &desc(
                "visibility buffer",
                vec![
                    Stage { stage: S::VERTEX, module: &visibility_vert, specialization: None },
                    Stage { stage: S::FRAGMENT, module: &visibility_frag, specialization: None },
                ],
                layout,
                true,
                Instrumentation::None,
            ),
        )?;
        // One shading pipeline per material kind, and per kind a counting one where the device
        // can count (the `count_evaluations` variant, COUNT_EVALUATIONS).
        let counts = context.features.vertex_pipeline_stores && context.features.fragment_stores;
        let instrumentations: &[Instrumentation] = if counts {
            &[Instrumentation::None, Instrumentation::CountEvaluations]
        } else {
            &[Instrumentation::None]
        };
        let mut shade = [Vec::new(), Vec::new()];
        for (&instrumentation, pipelines) in instrumentations.iter().zip(&mut shade) {
            for (features, specialization) in specializations {
                let features = instrumentation.features(*features);
                let deferred_frag = variant_module(context, "deferred.frag", features)?;
                pipelines.push(Pipeline::graphics(
                    context,
                    &desc(
                        "deferred shading",
                        vec![
                            Stage { stage: S::VERTEX, module: &fullscreen, specialization: None },
                            Stage {
                                stage: S::FRAGMENT,
                                module: &deferred_frag,
                                specialization: Some(specialization),
                            },
                        ],
                        layout,
                        false,
                        instrumentation,
                    ),
                )?);
            }
        }
        let pool = DescriptorPool::new(
            context,
            "deferred descriptors",
            1,
            &[vk::DescriptorPoolSize { ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, descriptor_count: 1 }],
        )?;
        let set = pool.allocate(layout.set_layouts[2])?;
        context.name(set, "deferred descriptor set");
        let sampler = Sampler::trilinear_repeat(context, "id buffer sampler")?;
        Ok(Deferred {
            context: context.clone(),
            visibility,
            shade,
            _pool: pool,
            set,
            sampler,
            ids: RefCell::new(None),
        })
    }

    /// Makes the id target `extent`-sized, (re)creating it and binding it to set 2 when the
    /// size changes. A change waits for the device to be idle (the old target and the set may
    /// be in use).
    fn size_ids(&self, extent: vk::Extent2D) -> Result<()> {
        if self.ids.borrow().as_ref().is_some_and(|t| t.extent() == extent) {
            return Ok(());
        }
        // SAFETY: plain wait; nothing is recorded on this thread meanwhile.
        unsafe { self.context.device.device_wait_idle() }.map_err(|result| Error::Vulkan {
            what: "waiting for the device before resizing the visibility buffer",
            result,
        })?;
        let target = RenderTarget::new(&self.context, extent)?;
        // The device is idle, so the set is not in use.
        let ids = [target.color.view];
        bind_sampled_images(&self.context, self.set, forward::VISIBILITY.binding, self.sampler.raw, &ids);
        *self.ids.borrow_mut() = Some(target);
        Ok(())
    }

    /// Builds the id target for `extent` where it has another size or none.
    pub fn prepare(&self, extent: vk::Extent2D) -> Result<()> {
        self.size_ids(extent)
    }

    /// Records the id pass of `frame`'s meshes into `ids`, leaving it ready to be `after`.
    pub(super) fn record_ids(
        &self,
        rec: &Recorder<'_>,
        draws: &ForwardDraws,
        frame: &FrameConfig,
        ids: &RenderTarget,
        after: AfterPass,
    ) {
        let pick =
            |_: &_, _: &_| Some(MeshPipelines { first: self.visibility.raw, lists: None, back_faces: None });
        // The id pass draws no patch lists.
        let counts = IndirectCounts { supported: false, max_count: 0 };
        ids.begin(rec.device, rec.cmd, [0.0; 4], Attachments::Color, DepthAfter::Discarded);
        let _ =
            draws.record_meshes(rec, frame, &pick, None, counts, Attachments::Color, FrameStamps::NONE.stamp);
        ids.end(rec.device, rec.cmd, after, Attachments::Color);
    }

    /// `pixel-deferred`: the id pass, then one full-screen shading pass per mesh into `target`
    /// (cleared to `clear`), with the counting pipelines for `Instrumentation::CountEvaluations`.
    /// [`Deferred::prepare`] must have run for `target`'s size.
    pub(super) fn record(
        &self,
        rec: &Recorder<'_>,
        draws: &ForwardDraws,
        frame: &FrameConfig,
        instrumentation: Instrumentation,
        target: &RenderTarget,
        (clear, after): ([f32; 4], AfterPass),
    ) {
        let ids = self.ids.borrow();
        let Some(ids) = ids.as_ref().filter(|ids| ids.extent() == target.extent()) else {
            debug_assert!(false, "prepare sizes the id target for the target");
            return;
        };
        let shade = &self.shade[usize::from(instrumentation == Instrumentation::CountEvaluations)];
        self.record_ids(rec, draws, frame, ids, AfterPass::Sampled);
        let device = rec.device;
        let attachments = instrumentation.attachments();
        target.begin(device, rec.cmd, clear, attachments, DepthAfter::Discarded);
        let mut constants = frame.draw_constants();
        // Its shaders read no estimator.
        constants.min_estimated_area = 0.0;
        rec.bind_set(0, rec.descriptors.set);
        rec.bind_set(2, self.set);
        for draw in &draws.meshes {
            constants.material_index = draw.material_index;
            constants.mesh_index = draw.mesh_index;
            rec.bind_pipeline(vk::PipelineBindPoint::GRAPHICS, shade[draw.pipeline].raw);
            rec.bind_set(1, rec.descriptors.textures.sets[draw.material_index as usize]);
            rec.push(&constants);
            // SAFETY: recording inside the rendering begun above; the pass reads no vertices.
            unsafe { device.cmd_draw(rec.cmd, 3, 1, 0, 0) };
        }
        target.end(device, rec.cmd, after, attachments);
    }
}
