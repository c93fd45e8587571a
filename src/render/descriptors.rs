//! The forward layout every pass of the renderer shares: set 0 (the scene's storage and texel
//! buffers, bound once), set 1 (a material's textures, bound per draw), set 2 (the deferred pass's id
//! image) and the push constants (`DrawConstants`); and the [`Recorder`] the passes record
//! with, which binds them.

use super::scene_buffers::SceneBuffers;
use super::textures::{material_set_bindings, SceneTextures};
use crate::error::Result;
use crate::gpu_interface::bindings::{forward, DescriptorKind};
use crate::gpu_types::DrawConstants;
use crate::scene::Scene;
use crate::vk::memory::{Buffer, BufferView};
use crate::vk::pipeline::{
    bind_storage_buffers, bind_texel_buffers, shader_binding, DescriptorPool, PipelineLayout,
};
use crate::vk::Context;
use ash::vk;
use std::sync::Arc;

/// The stages the push constants (`DrawConstants`) are visible to: every graphics stage, and
/// the triangle-level pre-pass.
pub(crate) const PUSH_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::ALL_GRAPHICS.as_raw() | vk::ShaderStageFlags::COMPUTE.as_raw(),
);

/// Storage and texel buffers in set 0 of the forward layout (`Renderer`'s `binding_table`).
pub(super) const SCENE_BINDINGS: usize = forward::SCENE_BUFFERS.len();

/// Set 2 of the forward layout: the id image of `pixel-deferred` mode (the vertices and
/// indices are set 0's).
fn deferred_set_bindings() -> [vk::DescriptorSetLayoutBinding<'static>; 1] {
    forward::DEFERRED_INPUTS.map(|b| shader_binding(b.binding, b.kind.descriptor_type()))
}

/// The forward layout, set 0 written with the scene's buffers, and the materials' sets.
pub(super) struct ForwardDescriptors {
    pub layout: PipelineLayout,
    _pool: DescriptorPool,
    /// Set 0: the scene's and the pre-pass's storage and texel buffers.
    pub set: vk::DescriptorSet,
    /// The views set 0's texel buffers are read through.
    _texel_views: Vec<BufferView>,
    /// The scene's textures and, per material, its set 1.
    pub textures: SceneTextures,
}

impl ForwardDescriptors {
    /// The layout, the scene's textures uploaded into their sets, and set 0 bound to the buffers
    /// of `binding_table` (in binding order).
    pub(super) fn new(
        context: &Arc<Context>,
        scene: &Scene,
        binding_table: &[&Buffer; SCENE_BINDINGS],
        shadow_atlas: (vk::ImageView, vk::Sampler),
    ) -> Result<ForwardDescriptors> {
        let bindings = forward::SCENE_BUFFERS.map(|b| shader_binding(b.binding, b.kind.descriptor_type()));
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
        let textures = SceneTextures::upload(context, scene, layout.set_layouts[1], shadow_atlas)?;
        let count = |wanted: fn(DescriptorKind) -> bool| {
            forward::SCENE_BUFFERS.iter().filter(|b| wanted(b.kind)).count() as u32
        };
        let texel_count = count(|kind| matches!(kind, DescriptorKind::UniformTexelBuffer(_)));
        let sizes = [
            (vk::DescriptorType::STORAGE_BUFFER, count(|kind| kind == DescriptorKind::StorageBuffer)),
            (vk::DescriptorType::UNIFORM_TEXEL_BUFFER, texel_count),
        ]
        .map(|(ty, descriptor_count)| vk::DescriptorPoolSize { ty, descriptor_count });
        let pool = DescriptorPool::new(context, "forward descriptors", 1, &sizes)?;
        let set = pool.allocate(layout.set_layouts[0])?;
        let mut texel_views = Vec::with_capacity(texel_count as usize);
        for (binding, buffer) in forward::SCENE_BUFFERS.iter().zip(binding_table) {
            match binding.kind {
                DescriptorKind::UniformTexelBuffer(format) => {
                    let view = BufferView::new(context, binding.name, buffer, format.format())?;
                    bind_texel_buffers(context, set, binding.binding, &[view.raw]);
                    texel_views.push(view);
                }
                _ => bind_storage_buffers(context, set, binding.binding, &[buffer.raw]),
            }
        }
        context.name(set, "forward descriptor set");
        Ok(ForwardDescriptors { layout, _pool: pool, set, _texel_views: texel_views, textures })
    }
}

/// What the passes record with: the command buffer, the scene's buffers and the forward
/// layout's sets.
pub(super) struct Recorder<'a> {
    pub device: &'a ash::Device,
    pub cmd: vk::CommandBuffer,
    pub buffers: &'a SceneBuffers,
    pub descriptors: &'a ForwardDescriptors,
}

impl Recorder<'_> {
    /// Binds `set` as set `index` of the forward layout for graphics.
    pub(super) fn bind_set(&self, index: u32, set: vk::DescriptorSet) {
        self.bind_set_at(vk::PipelineBindPoint::GRAPHICS, index, set);
    }

    /// Binds `set` as set `index` of the forward layout at `bind_point`.
    pub(super) fn bind_set_at(&self, bind_point: vk::PipelineBindPoint, index: u32, set: vk::DescriptorSet) {
        // SAFETY: `cmd` is recording; the set belongs to this layout and outlives the submission.
        unsafe {
            self.device.cmd_bind_descriptor_sets(
                self.cmd,
                bind_point,
                self.descriptors.layout.raw,
                index,
                &[set],
                &[],
            )
        };
    }

    /// Binds material `material`'s set 1 at `bind_point`.
    pub(super) fn bind_material(&self, bind_point: vk::PipelineBindPoint, material: u32) {
        self.bind_set_at(bind_point, 1, self.descriptors.textures.sets[material as usize]);
    }

    /// Pushes `constants` to every stage of the forward layout.
    pub(super) fn push(&self, constants: &DrawConstants) {
        // SAFETY: `cmd` is recording; the layout's push range covers `DrawConstants`.
        unsafe {
            self.device.cmd_push_constants(
                self.cmd,
                self.descriptors.layout.raw,
                PUSH_STAGES,
                0,
                bytemuck::bytes_of(constants),
            )
        };
    }

    /// Binds `pipeline` at `bind_point`.
    pub(super) fn bind_pipeline(&self, bind_point: vk::PipelineBindPoint, pipeline: vk::Pipeline) {
        // SAFETY: `cmd` is recording; the pipeline was built with the forward layout and outlives
        // the submission.
        unsafe { self.device.cmd_bind_pipeline(self.cmd, bind_point, pipeline) };
    }

    /// A global memory barrier from `(source stages, source accesses)` to `(destination
    /// stages, destination accesses)`; outside a rendering.
    pub(super) fn barrier(
        &self,
        (src, src_access, dst, dst_access): (
            vk::PipelineStageFlags2,
            vk::AccessFlags2,
            vk::PipelineStageFlags2,
            vk::AccessFlags2,
        ),
    ) {
        let barriers = [vk::MemoryBarrier2::default()
            .src_stage_mask(src)
            .src_access_mask(src_access)
            .dst_stage_mask(dst)
            .dst_access_mask(dst_access)];
        // SAFETY: `cmd` is recording outside a rendering.
        unsafe {
            self.device
                .cmd_pipeline_barrier2(self.cmd, &vk::DependencyInfo::default().memory_barriers(&barriers))
        };
    }
}
