//! `pixel-deferred` mode: the per-pixel reference through a visibility buffer. A first pass
//! draws every triangle's id (mesh + 1, scene triangle index) into a float target with the
//! `pixel` mode's rasterisation; a second, full-screen pass per mesh reads the ids, fetches the
//! triangle from the vertex and index buffers, rebuilds perspective-correct barycentrics and
//! their screen derivatives analytically (seed 002, `glsl/include/derivatives.glsl`) and shades.
//! The same id buffer gives `analyze --measured` each pixel's triangle.

use super::descriptors::PUSH_STAGES;
use super::draws::{draw_constants, DrawCall, Draws};
use super::pipelines::{
    scene_pipeline, variant_module, Instrumentation, MeshPipelines, VERTEX_ATTRIBUTES, VERTEX_BINDINGS,
};
use super::{Renderer, View};
use crate::error::{Error, Result};
use crate::gpu_interface::bindings::forward;
use crate::shaders::{self, Features};
use crate::vk::pipeline::{
    bind_sampled_images, shader_binding, DescriptorPool, GraphicsPipelineDesc, Pipeline, PipelineLayout,
    ShaderModule, Specialization, Stage,
};
use crate::vk::target::{AfterPass, Attachments, FloatImage, RenderTarget};
use crate::vk::texture::Sampler;
use crate::vk::Context;
use ash::vk;
use std::cell::RefCell;
use std::sync::Arc;

/// Set 2 of the forward layout: the id image (the vertices and indices are set 0's).
pub fn deferred_set_bindings() -> [vk::DescriptorSetLayoutBinding<'static>; 1] {
    forward::DEFERRED_INPUTS.map(|b| shader_binding(b.binding, b.kind.descriptor_type()))
}

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
}

impl Renderer {
    fn deferred(&self) -> Result<&Deferred> {
        if let Some(deferred) = self.deferred.get() {
            return Ok(deferred);
        }
        let deferred =
            Deferred::new(&self.context, &self.descriptors.layout, &self.pipelines.specializations)?;
        Ok(self.deferred.get_or_init(|| deferred))
    }

    /// Builds the deferred passes (once) and sizes the id target for `extent`.
    pub(super) fn prepare_deferred(&self, extent: vk::Extent2D) -> Result<()> {
        self.deferred()?.size_ids(extent)
    }

    /// Records the id pass into the visibility buffer, leaving it ready to be `after`.
    fn record_ids(&self, cmd: vk::CommandBuffer, ids: &RenderTarget, view: &View, after: AfterPass) {
        let deferred = self.deferred.get().expect("prepared");
        let pick = |_: &DrawCall, _: &View| {
            Some(MeshPipelines { first: deferred.visibility.raw, lists: None, back_faces: None })
        };
        let draws = Draws { pick: &pick, per_pixel: &[], emitters: false, clear: [0.0; 4] };
        self.record_draws(&draws, cmd, ids, Attachments::Color, view, after);
    }

    /// `pixel-deferred`: the id pass, then one full-screen shading pass per mesh into `target`,
    /// with the counting pipelines for `Instrumentation::CountEvaluations`. `prepare` must
    /// have run for `target`'s size.
    pub(super) fn record_deferred(
        &self,
        instrumentation: Instrumentation,
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        after: AfterPass,
    ) {
        let Some(deferred) = self.deferred.get() else {
            debug_assert!(false, "render, measure and the viewer prepare the view first");
            return;
        };
        let ids = deferred.ids.borrow();
        let Some(ids) = ids.as_ref().filter(|ids| ids.extent() == target.extent()) else {
            debug_assert!(false, "prepare sizes the id target for the target");
            return;
        };
        let shade = &deferred.shade[usize::from(instrumentation == Instrumentation::CountEvaluations)];
        self.record_ids(cmd, ids, view, AfterPass::Sampled);
        let device = &self.context.device;
        let extent = target.extent();
        let attachments = instrumentation.attachments();
        target.begin(device, cmd, self.clear_color, attachments);
        let mut constants = draw_constants(view, extent, 0.0);
        // SAFETY: recording inside the rendering begun above; every object is owned by `self`
        // and outlives the submission.
        unsafe {
            self.bind_set(cmd, 0, self.descriptors.set);
            self.bind_set(cmd, 2, deferred.set);
            for draw in &self.draws {
                constants.material_index = draw.material_index;
                constants.mesh_index = draw.mesh_index;
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, shade[draw.pipeline].raw);
                self.bind_set(cmd, 1, self.descriptors.textures.sets[draw.material_index as usize]);
                device.cmd_push_constants(
                    cmd,
                    self.descriptors.layout.raw,
                    PUSH_STAGES,
                    0,
                    bytemuck::bytes_of(&constants),
                );
                device.cmd_draw(cmd, 3, 1, 0, 0);
            }
        }
        target.end(device, cmd, after, attachments);
    }

    /// The visibility buffer of `view` at `target`'s size: per pixel (rows from the top),
    /// `Some((mesh, triangle))` with the triangle's index in its mesh, or `None`.
    pub fn triangle_ids(&self, target: &RenderTarget, view: &View) -> Result<Vec<Option<(usize, usize)>>> {
        self.deferred()?;
        let image: FloatImage = target
            .render_and_read(&self.context, |cmd| self.record_ids(cmd, target, view, AfterPass::Readback))?;
        Ok(image
            .pixels
            .iter()
            .map(|p| {
                (p[3] > 0.0 && p[0] >= 1.0).then(|| {
                    let mesh = p[0] as usize - 1;
                    let first = self.draws[mesh].first_triangle as usize;
                    (mesh, p[1] as usize - first)
                })
            })
            .collect())
    }
}
