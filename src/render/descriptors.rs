//! The forward layout every pass of the renderer shares: set 0 (the scene's storage buffers,
//! bound once), set 1 (a material's textures, bound per draw), set 2 (the deferred pass's id
//! image) and the push constants (`DrawConstants`).

use super::deferred::deferred_set_bindings;
use super::scene_buffers::{SceneBuffers, SCENE_BINDINGS};
use super::textures::{material_set_bindings, SceneTextures};
use super::Renderer;
use crate::error::Result;
use crate::gpu_interface::bindings::forward;
use crate::gpu_types::DrawConstants;
use crate::scene::Scene;
use crate::vk::pipeline::{bind_storage_buffers, shader_binding, DescriptorPool, PipelineLayout};
use crate::vk::Context;
use ash::vk;
use std::sync::Arc;

/// The stages the push constants (`DrawConstants`) are visible to: every graphics stage, and
/// the triangle-level pre-pass.
pub(crate) const PUSH_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::ALL_GRAPHICS.as_raw() | vk::ShaderStageFlags::COMPUTE.as_raw(),
);

/// The forward layout, set 0 written with the scene's buffers, and the materials' sets.
pub(super) struct ForwardDescriptors {
    pub layout: PipelineLayout,
    _pool: DescriptorPool,
    /// Set 0: the scene's storage buffers ([`SceneBuffers::binding_table`]).
    pub set: vk::DescriptorSet,
    /// The scene's textures and, per material, its set 1.
    pub textures: SceneTextures,
}

impl ForwardDescriptors {
    /// The layout, the scene's textures uploaded into their sets, and set 0 bound to `buffers`.
    pub(super) fn new(
        context: &Arc<Context>,
        scene: &Scene,
        buffers: &SceneBuffers,
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
        let textures = SceneTextures::upload(context, scene, layout.set_layouts[1])?;
        let pool = DescriptorPool::new(
            context,
            "forward descriptors",
            1,
            &[vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: SCENE_BINDINGS as u32,
            }],
        )?;
        let set = pool.allocate(layout.set_layouts[0])?;
        bind_storage_buffers(context, set, forward::SCENE_BUFFERS[0].binding, &buffers.binding_table());
        context.name(set, "forward descriptor set");
        Ok(ForwardDescriptors { layout, _pool: pool, set, textures })
    }
}

impl Renderer {
    /// Binds `set` as set `index` of the forward layout for graphics on `cmd` (recording).
    pub(super) fn bind_set(&self, cmd: vk::CommandBuffer, index: u32, set: vk::DescriptorSet) {
        self.bind_set_at(cmd, vk::PipelineBindPoint::GRAPHICS, index, set);
    }

    /// Binds `set` as set `index` of the forward layout at `bind_point` on `cmd` (recording).
    pub(super) fn bind_set_at(
        &self,
        cmd: vk::CommandBuffer,
        bind_point: vk::PipelineBindPoint,
        index: u32,
        set: vk::DescriptorSet,
    ) {
        // SAFETY: `cmd` is recording; the set belongs to this renderer's layout and outlives
        // the submission.
        unsafe {
            self.context.device.cmd_bind_descriptor_sets(
                cmd,
                bind_point,
                self.descriptors.layout.raw,
                index,
                &[set],
                &[],
            )
        };
    }

    /// Pushes `constants` to every stage of the forward layout on `cmd` (recording).
    pub(super) fn push_draw_constants(&self, cmd: vk::CommandBuffer, constants: &DrawConstants) {
        // SAFETY: `cmd` is recording; the layout's push range covers `DrawConstants`.
        unsafe {
            self.context.device.cmd_push_constants(
                cmd,
                self.descriptors.layout.raw,
                PUSH_STAGES,
                0,
                bytemuck::bytes_of(constants),
            )
        };
    }
}
