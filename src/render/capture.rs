//! Captures what the driver's fixed-function tessellator emits for one patch: the
//! `gl_TessCoord` of every TES invocation and every emitted triangle (as its three
//! `gl_TessCoord` values, in arrival order), written to storage buffers by the TES and a
//! geometry shader with rasterisation discarded. The tessellator model in
//! `analysis::tessellator` is tested against these captures, and [`check_patterns`] checks,
//! before multirate first draws on a device, that the device tessellates as the model does:
//! the effective-level table (`estimator::PATTERN_LEVELS`) is computed from the model. Where
//! it does not, the table is measured on the device's own patterns instead.

use crate::analysis::pattern_level::{effective_level, pack, table_entry};
use crate::analysis::tessellator::{triangle_pattern, Pattern};
use crate::error::{Error, Result};
use crate::gpu_interface::bindings::capture::{BUFFERS, COORDS, TRIANGLES};
use crate::gpu_interface::bindings::in_binding_order;
use crate::shaders;
use crate::vk::memory::Buffer;
use crate::vk::pipeline::{
    bind_storage_buffers, DepthUse, DescriptorPool, GraphicsPipelineDesc, Optimization, Pipeline,
    PipelineLayout, ShaderModule, Stage,
};
use crate::vk::target::begin_rendering;
use crate::vk::Context;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// Room for this many TES invocations and triangles per capture (level 64 emits 3169 and 6144).
const CAPACITY: usize = 16384;
/// Counter and padding before each buffer's array (std430: uint + uint[3]).
const HEADER_BYTES: usize = 16;

/// What the tessellator emitted for one patch.
#[derive(Clone, Debug, Default)]
pub struct CapturedPattern {
    /// `gl_TessCoord` of every TES invocation, in invocation order (may repeat a vertex).
    pub tess_coords: Vec<[f32; 3]>,
    /// Every triangle as the three `gl_TessCoord` values of its corners, in winding order.
    pub triangles: Vec<[[f32; 3]; 3]>,
}

/// A domain coordinate to 2⁻¹⁶ (the reference tessellator's fixed point), for comparisons.
type Corner = [i64; 3];

fn corner(c: [f64; 3]) -> Corner {
    c.map(|x| (x * 65536.0).round() as i64)
}

/// A triangle with its corners rotated so that the smallest comes first (winding kept).
fn canonical(mut t: [Corner; 3]) -> [Corner; 3] {
    let first = (0..3).min_by_key(|&k| t[k]).expect("three corners");
    t.rotate_left(first);
    t
}

impl CapturedPattern {
    /// Its distinct domain coordinates, sorted.
    pub fn distinct_vertices(&self) -> Vec<Corner> {
        let mut keys: Vec<Corner> = self.tess_coords.iter().map(|c| corner(c.map(f64::from))).collect();
        keys.sort();
        keys.dedup();
        keys
    }

    /// Its triangles (corners rotated to start at the smallest, winding kept), sorted.
    pub fn canonical_triangles(&self) -> Vec<[Corner; 3]> {
        let mut triangles: Vec<_> =
            self.triangles.iter().map(|t| canonical(t.map(|c| corner(c.map(f64::from))))).collect();
        triangles.sort();
        triangles
    }

    /// Whether it is `model`'s pattern: the same vertices and the same triangles with the same
    /// winding. The model lists corners in D3D's clockwise order; the capture's evaluation
    /// shader declares `ccw` with Vulkan's upper-left domain origin, which emits the same
    /// triangles with the last two corners swapped.
    pub fn is(&self, model: &Pattern) -> bool {
        let mut vertices: Vec<Corner> = model.vertices.iter().map(|&v| corner(v)).collect();
        vertices.sort();
        let at = |i: u32| corner(model.vertices[i as usize]);
        let mut triangles: Vec<_> =
            model.triangles.iter().map(|t| canonical([at(t[0]), at(t[2]), at(t[1])])).collect();
        triangles.sort();
        self.distinct_vertices() == vertices && self.canonical_triangles() == triangles
    }

    /// The effective level of this pattern (`analysis::pattern_level`).
    pub fn effective_level(&self) -> f64 {
        effective_level(self.triangles.iter().map(|t| t.map(|c| c.map(f64::from))))
    }
}

/// The effective-level table multirate uses on a device (what [`check_patterns`] found).
#[derive(Clone, Debug, PartialEq)]
pub enum PatternTable {
    /// The device tessellates as the model: `estimator::PATTERN_LEVELS` holds.
    Model,
    /// The device's own table, in the layout of `PATTERN_LEVELS`, measured on its patterns up
    /// to the checked `n_max` (entries above it are 0: no level is ever reached there).
    Measured(Arc<Vec<u32>>),
}

/// A device's own effective-level table from its captured patterns `captured`, one per entry
/// of `levels` ([`pattern_check_levels`]`(n_max)`): each `(inner, outer)` entry from the
/// pattern with `outer` on all three edges; then every captured pattern, the mixed ones
/// included, must have an effective level of at least the smallest of its edges' entries
/// (the rule `estimator::patch_levels` relies on), or the table is refused: the error names
/// the first pattern that breaks it.
pub fn measured_table(
    device: &str,
    levels: &[(f32, [f32; 3])],
    captured: &[CapturedPattern],
    n_max: u32,
) -> Result<Vec<u32>> {
    let n_max = n_max.clamp(1, 64);
    let mut entries = vec![0u32; 64 * 64];
    let index = |inner: u32, outer: u32| ((inner - 1) * 64 + (outer - 1)) as usize;
    for ((inner, outer), pattern) in levels.iter().zip(captured) {
        if outer[0] == outer[1] && outer[1] == outer[2] {
            entries[index(*inner as u32, outer[0] as u32)] = table_entry(pattern.effective_level());
        }
    }
    for ((inner, outer), pattern) in levels.iter().zip(captured) {
        let table = outer.iter().map(|&o| entries[index(*inner as u32, o as u32)]).min().unwrap_or(0);
        let reached = pattern.effective_level();
        if table == 0 || f64::from(table) / 256.0 > reached + 1e-9 {
            return Err(Error::Patterns { device: device.to_owned(), inner: *inner, outer: *outer });
        }
    }
    Ok(pack(|inner, outer| if inner <= n_max && outer <= n_max { entries[index(inner, outer)] } else { 0 }))
}

/// The levels [`check_patterns`] captures for `n_max`: every inner level with every outer
/// level on all three edges (each edge's transition strip), and per inner level three patches
/// of mixed outer levels (the strips side by side, and the corners where they meet).
pub fn pattern_check_levels(n_max: u32) -> Vec<(f32, [f32; 3])> {
    let n_max = n_max.clamp(1, 64);
    let mut levels = Vec::new();
    for inner in 1..=n_max {
        for outer in 1..=n_max {
            levels.push((inner as f32, [outer as f32; 3]));
        }
        let mixed = [[1, inner, n_max], [inner, 1, (inner + 1).min(n_max)], [n_max, (inner / 2).max(1), 1]];
        levels.extend(mixed.map(|outer| (inner as f32, outer.map(|o| o as f32))));
    }
    levels
}

/// Checks, once per device and `n_max` (the context remembers the largest checked and what
/// it found), whether the device tessellates every level multirate may set up to `n_max` as
/// the model does ([`pattern_check_levels`]): multirate's built-in effective-level table is
/// computed from the model, and a table that was not checked on the device is never used.
/// Where a pattern differs, the table is measured on the device's patterns
/// ([`measured_table`]). Fails with [`Error::Patterns`] where even that table does not hold,
/// and with [`Error::NoDevice`] where the device cannot capture (no geometryShader or
/// vertexPipelineStoresAndAtomics).
pub fn check_patterns(context: &Arc<Context>, n_max: u32) -> Result<PatternTable> {
    let n_max = n_max.clamp(1, 64);
    let mut check = context.pattern_check.lock().expect("pattern check lock");
    if check.checked_up_to >= n_max {
        return Ok(check.measured.clone().map_or(PatternTable::Model, PatternTable::Measured));
    }
    let capture = TessellationCapture::new(context)?;
    let levels = pattern_check_levels(n_max);
    let mut captured = Vec::with_capacity(levels.len());
    let mut as_model = true;
    for &(inner, outer) in &levels {
        let pattern = capture.capture(inner, outer)?;
        as_model &= pattern.is(&triangle_pattern(inner, outer));
        captured.push(pattern);
    }
    check.measured = if as_model {
        None
    } else {
        Some(Arc::new(measured_table(&context.info.name, &levels, &captured, n_max)?))
    };
    check.checked_up_to = n_max;
    Ok(check.measured.clone().map_or(PatternTable::Model, PatternTable::Measured))
}

/// A pipeline that tessellates one patch and records the result.
pub struct TessellationCapture {
    context: Arc<Context>,
    coords: Buffer,
    triangles: Buffer,
    layout: PipelineLayout,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    pipeline: Pipeline,
}

impl TessellationCapture {
    pub fn new(context: &Arc<Context>) -> Result<TessellationCapture> {
        if !(context.features.geometry_shader && context.features.vertex_pipeline_stores) {
            return Err(Error::NoDevice(format!(
                "{}: capturing the tessellator needs geometryShader and vertexPipelineStoresAndAtomics",
                context.info.name
            )));
        }
        let coords = Buffer::new(
            context,
            "captured tess coords",
            (HEADER_BYTES + CAPACITY * 16) as vk::DeviceSize,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
        )?;
        let triangles = Buffer::new(
            context,
            "captured triangles",
            (HEADER_BYTES + CAPACITY * 48) as vk::DeviceSize,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
        )?;
        let bindings = [
            vk::DescriptorSetLayoutBinding::default()
                .binding(COORDS.binding)
                .descriptor_type(COORDS.kind.descriptor_type())
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::TESSELLATION_EVALUATION),
            vk::DescriptorSetLayoutBinding::default()
                .binding(TRIANGLES.binding)
                .descriptor_type(TRIANGLES.kind.descriptor_type())
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::GEOMETRY),
        ];
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::TESSELLATION_CONTROL)
            .size(20)];
        let layout = PipelineLayout::new(context, "tessellation capture layout", &[&bindings], &push)?;
        let pool = DescriptorPool::new(
            context,
            "tessellation capture descriptors",
            1,
            &[vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 2 }],
        )?;
        let set = pool.allocate(layout.set_layouts[0])?;
        let buffers = in_binding_order(&BUFFERS, [(COORDS, coords.raw), (TRIANGLES, triangles.raw)]);
        bind_storage_buffers(context, set, BUFFERS[0].binding, &buffers);

        let vert = ShaderModule::new(context, "capture.vert", shaders::single("capture.vert"))?;
        let tesc = ShaderModule::new(context, "capture.tesc", shaders::single("capture.tesc"))?;
        let tese = ShaderModule::new(context, "capture.tese", shaders::single("capture.tese"))?;
        let geom = ShaderModule::new(context, "capture.geom", shaders::single("capture.geom"))?;
        use vk::ShaderStageFlags as S;
        let pipeline = Pipeline::graphics(
            context,
            &GraphicsPipelineDesc {
                name: "tessellation capture",
                stages: vec![
                    Stage { stage: S::VERTEX, module: &vert, specialization: None },
                    Stage { stage: S::TESSELLATION_CONTROL, module: &tesc, specialization: None },
                    Stage { stage: S::TESSELLATION_EVALUATION, module: &tese, specialization: None },
                    Stage { stage: S::GEOMETRY, module: &geom, specialization: None },
                ],
                layout: &layout,
                vertex_bindings: &[],
                vertex_attributes: &[],
                topology: vk::PrimitiveTopology::PATCH_LIST,
                patch_control_points: Some(3),
                polygon_mode: vk::PolygonMode::FILL,
                cull_mode: vk::CullModeFlags::NONE,
                front_face: vk::FrontFace::COUNTER_CLOCKWISE,
                color_formats: &[],
                depth_format: None,
                depth_use: DepthUse::Nearest,
                rasterizer_discard: true,
                dynamic_cull_mode: false,
                optimization: Optimization::Optimized,
            },
        )?;
        Ok(TessellationCapture {
            context: context.clone(),
            coords,
            triangles,
            layout,
            _pool: pool,
            set,
            pipeline,
        })
    }

    /// Tessellates one patch with these levels (as a TCS would write them) and reads back
    /// what was emitted.
    pub fn capture(&self, inner: f32, outer: [f32; 3]) -> Result<CapturedPattern> {
        self.coords.write(&[0u8; HEADER_BYTES]);
        self.triangles.write(&[0u8; HEADER_BYTES]);
        let mut levels = [0u8; 20];
        for (k, value) in outer.iter().chain([0.0, inner].iter()).enumerate() {
            levels[4 * k..4 * k + 4].copy_from_slice(&value.to_ne_bytes());
        }
        let device = &self.context.device;
        self.context.run_once(|cmd| {
            let barrier = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::PRE_RASTERIZATION_SHADERS)
                .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                .dst_access_mask(vk::AccessFlags2::HOST_READ)];
            begin_rendering(device, cmd, vk::Extent2D { width: 1, height: 1 }, vk::RenderingInfo::default());
            // SAFETY: `cmd` is recording; all objects are owned by `self`; the host writes
            // above are made visible by the queue submission.
            unsafe {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.layout.raw,
                    0,
                    &[self.set],
                    &[],
                );
                device.cmd_push_constants(
                    cmd,
                    self.layout.raw,
                    vk::ShaderStageFlags::TESSELLATION_CONTROL,
                    0,
                    &levels,
                );
                device.cmd_draw(cmd, 3, 1, 0, 0);
                device.cmd_end_rendering(cmd);
                device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barrier));
            }
        })?;
        let read = |buffer: &Buffer, stride: usize| -> (usize, Vec<f32>) {
            let bytes = buffer.mapped().expect("GpuToCpu memory is mapped");
            let count = u32::from_ne_bytes(bytes[0..4].try_into().expect("4 bytes")) as usize;
            let count = count.min(CAPACITY);
            let floats =
                bytemuck::pod_collect_to_vec::<u8, f32>(&bytes[HEADER_BYTES..HEADER_BYTES + count * stride]);
            (count, floats)
        };
        let (coord_count, coords) = read(&self.coords, 16);
        let (triangle_count, corners) = read(&self.triangles, 48);
        let vec3 = |f: &[f32]| [f[0], f[1], f[2]];
        Ok(CapturedPattern {
            tess_coords: (0..coord_count).map(|i| vec3(&coords[4 * i..])).collect(),
            triangles: (0..triangle_count)
                .map(|t| {
                    [vec3(&corners[12 * t..]), vec3(&corners[12 * t + 4..]), vec3(&corners[12 * t + 8..])]
                })
                .collect(),
        })
    }
}

#[cfg(test)]
mod tests;
