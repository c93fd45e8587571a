//! Shader modules, specialization constants, pipeline layouts, graphics pipelines for dynamic
//! rendering and compute pipelines. Every object here destroys itself in `Drop`.

use super::context::Context;
use crate::error::{Result, VkContext};
use ash::vk;
use std::ffi::CStr;
use std::sync::Arc;

const ENTRY_POINT: &CStr = c"main";

/// Values for a stage's `layout(constant_id = N)` constants, in the order they are pushed.
#[derive(Clone, Debug, Default)]
pub struct Specialization {
    entries: Vec<vk::SpecializationMapEntry>,
    data: Vec<u8>,
}

impl Specialization {
    /// Sets constant `id` (a GLSL `int`).
    pub fn int(mut self, id: u32, value: i32) -> Self {
        self.push(id, &value.to_ne_bytes());
        self
    }

    /// Sets constant `id` (a GLSL `uint`).
    pub fn uint(mut self, id: u32, value: u32) -> Self {
        self.push(id, &value.to_ne_bytes());
        self
    }

    /// Sets constant `id` (a GLSL `bool`, 32 bits in SPIR-V).
    pub fn boolean(mut self, id: u32, value: bool) -> Self {
        self.push(id, &u32::from(value).to_ne_bytes());
        self
    }

    /// Sets constant `id` (a GLSL `float`).
    pub fn float(mut self, id: u32, value: f32) -> Self {
        self.push(id, &value.to_ne_bytes());
        self
    }

    fn push(&mut self, id: u32, bytes: &[u8]) {
        self.entries.push(vk::SpecializationMapEntry {
            constant_id: id,
            offset: self.data.len() as u32,
            size: bytes.len(),
        });
        self.data.extend_from_slice(bytes);
    }

    fn info(&self) -> vk::SpecializationInfo<'_> {
        vk::SpecializationInfo::default().map_entries(&self.entries).data(&self.data)
    }
}

/// A compiled SPIR-V module.
pub struct ShaderModule {
    context: Arc<Context>,
    pub raw: vk::ShaderModule,
}

impl ShaderModule {
    pub fn new(context: &Arc<Context>, name: &str, spirv: &[u8]) -> Result<ShaderModule> {
        let words = crate::shaders::words(spirv);
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: `words` is SPIR-V produced by build.rs; destroyed in `Drop`.
        let raw =
            unsafe { context.device.create_shader_module(&info, None) }.while_("creating a shader module")?;
        context.name(raw, name);
        Ok(ShaderModule { context: context.clone(), raw })
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        // SAFETY: modules are only needed while pipelines are created.
        unsafe { self.context.device.destroy_shader_module(self.raw, None) };
    }
}

/// Descriptor set layouts and push constant ranges of a family of pipelines.
pub struct PipelineLayout {
    context: Arc<Context>,
    pub raw: vk::PipelineLayout,
    pub set_layouts: Vec<vk::DescriptorSetLayout>,
}

impl PipelineLayout {
    /// One layout per entry of `sets` (each a list of bindings), plus `push_constants`.
    pub fn new(
        context: &Arc<Context>,
        name: &str,
        sets: &[&[vk::DescriptorSetLayoutBinding<'_>]],
        push_constants: &[vk::PushConstantRange],
    ) -> Result<PipelineLayout> {
        let mut layout = PipelineLayout {
            context: context.clone(),
            raw: vk::PipelineLayout::null(),
            set_layouts: Vec::new(),
        };
        for bindings in sets {
            let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(bindings);
            // SAFETY: valid create info; destroyed in `Drop`.
            let set_layout = unsafe { context.device.create_descriptor_set_layout(&info, None) }
                .while_("creating a descriptor set layout")?;
            layout.set_layouts.push(set_layout);
        }
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&layout.set_layouts)
            .push_constant_ranges(push_constants);
        // SAFETY: the set layouts are live; destroyed in `Drop`.
        layout.raw = unsafe { context.device.create_pipeline_layout(&info, None) }
            .while_("creating a pipeline layout")?;
        context.name(layout.raw, name);
        Ok(layout)
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        // SAFETY: pipelines using the layout are dropped by their owners first.
        unsafe {
            self.context.device.destroy_pipeline_layout(self.raw, None);
            for &set_layout in &self.set_layouts {
                self.context.device.destroy_descriptor_set_layout(set_layout, None);
            }
        }
    }
}

/// One shader stage of a pipeline.
pub struct Stage<'a> {
    pub stage: vk::ShaderStageFlags,
    pub module: &'a ShaderModule,
    pub specialization: Option<&'a Specialization>,
}

/// Everything that varies between the project's graphics pipelines.
pub struct GraphicsPipelineDesc<'a> {
    pub name: &'a str,
    pub stages: Vec<Stage<'a>>,
    pub layout: &'a PipelineLayout,
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    pub topology: vk::PrimitiveTopology,
    /// Control points per patch when the pipeline tessellates.
    pub patch_control_points: Option<u32>,
    pub polygon_mode: vk::PolygonMode,
    pub cull_mode: vk::CullModeFlags,
    pub front_face: vk::FrontFace,
    /// The cull mode is set per draw (`vkCmdSetCullMode`) instead of `cull_mode`.
    pub dynamic_cull_mode: bool,
    /// The colour attachments' formats, in location order; none at all for a capture
    /// pipeline that discards rasterisation.
    pub color_formats: &'a [vk::Format],
    pub depth_format: Option<vk::Format>,
    /// What the pipeline does with the depth attachment, where there is one.
    pub depth_use: DepthUse,
    /// Stop after the last pre-rasterisation stage (captures that only write buffers).
    pub rasterizer_discard: bool,
    /// Whether the driver optimises this pipeline's code (only timed pipelines need it).
    pub optimization: Optimization,
}

/// Whether the driver optimises a pipeline's code. Pipelines that are never timed (the
/// analysis and level-recording variants) are built `Unoptimized`
/// (`VK_PIPELINE_CREATE_DISABLE_OPTIMIZATION_BIT`): lavapipe then builds the estimator's
/// pipelines in about 30 % less time, with the same results (docs/notebook/speedups.md, "Build and test
/// time").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Optimization {
    Optimized,
    Unoptimized,
}

impl Optimization {
    fn flags(self) -> vk::PipelineCreateFlags {
        match self {
            Optimization::Optimized => vk::PipelineCreateFlags::empty(),
            Optimization::Unoptimized => vk::PipelineCreateFlags::DISABLE_OPTIMIZATION,
        }
    }
}

/// How a graphics pipeline uses its depth attachment: a depth prime and the shading pass after
/// it shade every pixel once, whatever the order of their primitives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthUse {
    /// The nearer fragment wins: test `LESS`, write.
    Nearest,
    /// Depth only: test `LESS`, write, no colour (the stages hold no fragment shader).
    Prime,
    /// After a prime of the same primitives: only the fragments at the depth it left
    /// (`EQUAL`), no write.
    Primed,
}

/// A graphics or compute pipeline.
pub struct Pipeline {
    context: Arc<Context>,
    pub raw: vk::Pipeline,
}

impl Pipeline {
    pub fn graphics(context: &Arc<Context>, desc: &GraphicsPipelineDesc<'_>) -> Result<Pipeline> {
        let specializations: Vec<vk::SpecializationInfo<'_>> = desc
            .stages
            .iter()
            .map(|s| s.specialization.map(Specialization::info).unwrap_or_default())
            .collect();
        let stages: Vec<vk::PipelineShaderStageCreateInfo<'_>> = desc
            .stages
            .iter()
            .zip(&specializations)
            .map(|(stage, specialization)| {
                let info = vk::PipelineShaderStageCreateInfo::default()
                    .stage(stage.stage)
                    .module(stage.module.raw)
                    .name(ENTRY_POINT);
                if stage.specialization.is_some() {
                    info.specialization_info(specialization)
                } else {
                    info
                }
            })
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(desc.vertex_bindings)
            .vertex_attribute_descriptions(desc.vertex_attributes);
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
        let tessellation = vk::PipelineTessellationStateCreateInfo::default()
            .patch_control_points(desc.patch_control_points.unwrap_or(0));
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        let rasterization = vk::PipelineRasterizationStateCreateInfo::default()
            .rasterizer_discard_enable(desc.rasterizer_discard)
            .polygon_mode(desc.polygon_mode)
            .cull_mode(desc.cull_mode)
            .front_face(desc.front_face)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let has_depth = desc.depth_format.is_some();
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(has_depth)
            .depth_write_enable(has_depth && desc.depth_use != DepthUse::Primed)
            .depth_compare_op(match desc.depth_use {
                DepthUse::Nearest | DepthUse::Prime => vk::CompareOp::LESS,
                DepthUse::Primed => vk::CompareOp::EQUAL,
            });
        // Without a fragment shader the colour outputs are undefined: a prime writes none.
        let color_writes = match desc.depth_use {
            DepthUse::Prime => vk::ColorComponentFlags::empty(),
            DepthUse::Nearest | DepthUse::Primed => vk::ColorComponentFlags::RGBA,
        };
        let blend_attachments: Vec<vk::PipelineColorBlendAttachmentState> = desc
            .color_formats
            .iter()
            .map(|_| vk::PipelineColorBlendAttachmentState::default().color_write_mask(color_writes))
            .collect();
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states =
            [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR, vk::DynamicState::CULL_MODE];
        let dynamic_count = if desc.dynamic_cull_mode { 3 } else { 2 };
        let dynamic =
            vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states[..dynamic_count]);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(desc.color_formats)
            .depth_attachment_format(desc.depth_format.unwrap_or(vk::Format::UNDEFINED));
        let mut info = vk::GraphicsPipelineCreateInfo::default()
            .flags(desc.optimization.flags())
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&rasterization)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(desc.layout.raw)
            .push_next(&mut rendering);
        if desc.patch_control_points.is_some() {
            info = info.tessellation_state(&tessellation);
        }
        // SAFETY: every pointer in `info` refers to locals alive for the call.
        let raw =
            unsafe { context.device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) }
                .map_err(|(_, result)| result)
                .while_("creating a graphics pipeline")?[0];
        context.name(raw, desc.name);
        Ok(Pipeline { context: context.clone(), raw })
    }

    /// A compute pipeline running `module`'s `main` with `layout`, its constants set by
    /// `specialization` when given.
    pub fn compute(
        context: &Arc<Context>,
        name: &str,
        layout: &PipelineLayout,
        module: &ShaderModule,
        specialization: Option<&Specialization>,
        optimization: Optimization,
    ) -> Result<Pipeline> {
        let specialization_info = specialization.map(Specialization::info).unwrap_or_default();
        let mut stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.raw)
            .name(ENTRY_POINT);
        if specialization.is_some() {
            stage = stage.specialization_info(&specialization_info);
        }
        let info = vk::ComputePipelineCreateInfo::default()
            .flags(optimization.flags())
            .stage(stage)
            .layout(layout.raw);
        // SAFETY: every pointer in `info` refers to locals alive for the call.
        let raw =
            unsafe { context.device.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) }
                .map_err(|(_, result)| result)
                .while_("creating a compute pipeline")?[0];
        context.name(raw, name);
        Ok(Pipeline { context: context.clone(), raw })
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees no command buffer in flight uses the pipeline.
        unsafe { self.context.device.destroy_pipeline(self.raw, None) };
    }
}

/// A descriptor pool that frees its sets when dropped.
pub struct DescriptorPool {
    context: Arc<Context>,
    pub raw: vk::DescriptorPool,
}

impl DescriptorPool {
    pub fn new(
        context: &Arc<Context>,
        name: &str,
        max_sets: u32,
        sizes: &[vk::DescriptorPoolSize],
    ) -> Result<DescriptorPool> {
        let info = vk::DescriptorPoolCreateInfo::default().max_sets(max_sets).pool_sizes(sizes);
        // SAFETY: valid create info; destroyed in `Drop`.
        let raw = unsafe { context.device.create_descriptor_pool(&info, None) }
            .while_("creating a descriptor pool")?;
        context.name(raw, name);
        Ok(DescriptorPool { context: context.clone(), raw })
    }

    /// Allocates one set of `layout`.
    pub fn allocate(&self, layout: vk::DescriptorSetLayout) -> Result<vk::DescriptorSet> {
        let layouts = [layout];
        let info = vk::DescriptorSetAllocateInfo::default().descriptor_pool(self.raw).set_layouts(&layouts);
        // SAFETY: pool and layout are live.
        Ok(unsafe { self.context.device.allocate_descriptor_sets(&info) }
            .while_("allocating a descriptor set")?[0])
    }
}

/// One descriptor of `ty` at `binding`, visible to every graphics stage and to compute.
pub fn shader_binding(binding: u32, ty: vk::DescriptorType) -> vk::DescriptorSetLayoutBinding<'static> {
    vk::DescriptorSetLayoutBinding::default()
        .binding(binding)
        .descriptor_type(ty)
        .descriptor_count(1)
        .stage_flags(vk::ShaderStageFlags::ALL_GRAPHICS | vk::ShaderStageFlags::COMPUTE)
}

/// Points bindings `first`, `first + 1`, … of `set` at whole storage buffers, in order. The
/// set must not be in use by pending work.
pub fn bind_storage_buffers(context: &Context, set: vk::DescriptorSet, first: u32, buffers: &[vk::Buffer]) {
    let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
        .iter()
        .map(|&buffer| [vk::DescriptorBufferInfo { buffer, offset: 0, range: vk::WHOLE_SIZE }])
        .collect();
    write_each(context, set, first, vk::DescriptorType::STORAGE_BUFFER, &infos, |w, info| {
        w.buffer_info(info)
    });
}

/// Points bindings `first`, `first + 1`, … of `set` at uniform texel buffers, in order. The
/// set must not be in use by pending work.
pub fn bind_texel_buffers(context: &Context, set: vk::DescriptorSet, first: u32, views: &[vk::BufferView]) {
    let infos: Vec<[vk::BufferView; 1]> = views.iter().map(|&view| [view]).collect();
    write_each(context, set, first, vk::DescriptorType::UNIFORM_TEXEL_BUFFER, &infos, |w, info| {
        w.texel_buffer_view(info)
    });
}

/// Points bindings `first`, `first + 1`, … of `set` at combined image samplers (views in
/// `SHADER_READ_ONLY_OPTIMAL`), in order. The set must not be in use by pending work.
pub fn bind_sampled_images(
    context: &Context,
    set: vk::DescriptorSet,
    first: u32,
    sampler: vk::Sampler,
    views: &[vk::ImageView],
) {
    let infos: Vec<[vk::DescriptorImageInfo; 1]> = views
        .iter()
        .map(|&image_view| {
            [vk::DescriptorImageInfo {
                sampler,
                image_view,
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            }]
        })
        .collect();
    write_each(context, set, first, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, &infos, |w, info| {
        w.image_info(info)
    });
}

/// One descriptor write of `ty` per entry of `infos`, at bindings `first`, `first + 1`, …
fn write_each<'a, I>(
    context: &Context,
    set: vk::DescriptorSet,
    first: u32,
    ty: vk::DescriptorType,
    infos: &'a [I],
    attach: impl Fn(vk::WriteDescriptorSet<'a>, &'a I) -> vk::WriteDescriptorSet<'a>,
) {
    let writes: Vec<vk::WriteDescriptorSet<'a>> = infos
        .iter()
        .zip(first..)
        .map(|(info, binding)| {
            attach(
                vk::WriteDescriptorSet::default().dst_set(set).dst_binding(binding).descriptor_type(ty),
                info,
            )
        })
        .collect();
    // SAFETY: the callers guarantee the set and what the infos name are live and the set is idle.
    unsafe { context.device.update_descriptor_sets(&writes, &[]) };
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees no command buffer in flight uses the sets.
        unsafe { self.context.device.destroy_descriptor_pool(self.raw, None) };
    }
}
