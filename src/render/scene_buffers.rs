//! The scene on the GPU: its meshes, emitters, lights and materials gathered for upload
//! ([`SceneGeometry`]), the per-scene buffers they and the multirate pre-pass live in
//! ([`SceneBuffers`]), and which of those buffers each binding of set 0 holds
//! ([`SceneBuffers::binding_table`], the one place that says so).

use super::draws::{DrawCall, EmitterDraw};
use super::textures::gpu_material;
use crate::error::Result;
use crate::gpu_interface::bindings::in_binding_order;
use crate::gpu_interface::slots::{
    FALLBACK_LIST, INTERPOLATED_LIST, LEVEL_DISPATCHES, PATCH_COUNT_WORDS, PATCH_LISTS,
};
use crate::gpu_types::{GpuLight, GpuMaterial, GpuPolygonLight, Vertex};
use crate::scene::adjacency::{adjacency_patches, neighbours};
use crate::scene::{Light, MaterialKind, Mesh, Scene};
use crate::vk::memory::Buffer;
use crate::vk::Context;
use ash::vk;
use std::sync::Arc;

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

/// The scene as its buffers hold it, gathered on the CPU: every mesh's vertices and
/// triangles, then every polygonal light's emissive fan, in one vertex and one index array.
#[derive(Default)]
pub(super) struct SceneGeometry {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    /// Per triangle of the meshes: its 12-index adjacency patch.
    pub patch_indices: Vec<u32>,
    /// Per triangle of the meshes: the triangles across its edges (scene indices), then 0.
    pub triangle_neighbours: Vec<[u32; 4]>,
    /// One per mesh, in scene order.
    pub draws: Vec<DrawCall>,
    /// The material kinds the meshes use, in order of first use (`DrawCall::pipeline`).
    pub kinds: Vec<u32>,
    /// One per polygonal light, in scene order.
    pub emitters: Vec<EmitterDraw>,
    /// Triangles of the meshes; the emitters' come after them (level records cover the meshes
    /// only).
    pub triangle_count: usize,
    /// Point lights, then directional ones ([`gpu_lights`]).
    pub lights: Vec<GpuLight>,
    pub point_count: i32,
    pub directional_count: i32,
    pub materials: Vec<GpuMaterial>,
    pub polygon_lights: Vec<GpuPolygonLight>,
}

impl SceneGeometry {
    /// The geometry, lights and materials of `scene`.
    pub(super) fn of(scene: &Scene) -> SceneGeometry {
        let mut geometry = SceneGeometry::default();
        for (mesh_index, mesh) in scene.meshes.iter().enumerate() {
            geometry.add_mesh(scene, mesh_index, mesh);
        }
        let (lights, point_count, directional_count) = gpu_lights(&scene.lights);
        let materials: Vec<GpuMaterial> = scene.materials.iter().map(gpu_material).collect();
        let polygon_lights = gpu_polygon_lights(&scene.lights);
        // The emitters' triangles go after the meshes' (level records cover the meshes only).
        let triangle_count = geometry.indices.len() / 3;
        for (light_index, light) in polygon_lights.iter().enumerate() {
            geometry.add_emitter(light_index, light);
        }
        SceneGeometry {
            triangle_count,
            lights,
            point_count,
            directional_count,
            materials,
            polygon_lights,
            ..geometry
        }
    }

    /// Appends mesh `mesh_index` of `scene`: its vertices, triangles, adjacency patches,
    /// neighbours and draw.
    fn add_mesh(&mut self, scene: &Scene, mesh_index: usize, mesh: &Mesh) {
        let base = self.vertices.len() as u32;
        self.vertices.extend(mesh.positions.iter().zip(&mesh.normals).enumerate().map(|(i, (p, n))| {
            Vertex {
                position: p.to_array(),
                normal: n.to_array(),
                uv: mesh.uvs.get(i).map_or([0.0; 2], |uv| uv.to_array()),
            }
        }));
        let first_index = self.indices.len() as u32;
        self.indices.extend(mesh.indices.iter().map(|i| i + base));
        let first_patch_index = self.patch_indices.len() as u32;
        self.patch_indices.extend(adjacency_patches(mesh).iter().map(|i| i + base));
        let first_triangle = first_index / 3;
        self.triangle_neighbours
            .extend(neighbours(mesh).iter().map(|n| [n[0], n[1], n[2], 0].map(|t| t + first_triangle)));
        let kind = material_kind_id(&scene.materials[mesh.material].kind);
        let kinds = &mut self.kinds;
        let pipeline = kinds.iter().position(|&k| k == kind).unwrap_or_else(|| {
            kinds.push(kind);
            kinds.len() - 1
        });
        self.draws.push(DrawCall {
            first_triangle: first_index / 3,
            first_index,
            index_count: mesh.indices.len() as u32,
            first_patch_index,
            one_sided: !mesh.two_sided,
            shared_corners: scene.materials[mesh.material].maps.parameter.is_none(),
            material_index: mesh.material as u32,
            mesh_index: mesh_index as u32,
            pipeline,
        });
    }

    /// Appends the emissive fan of polygonal light `light_index`.
    fn add_emitter(&mut self, light_index: usize, light: &GpuPolygonLight) {
        let base = self.vertices.len() as u32;
        let count = light.info.x as u32;
        self.vertices.extend(light.vertices[..count as usize].iter().map(|v| Vertex {
            position: v.truncate().to_array(),
            normal: light.normal.truncate().to_array(),
            uv: [0.0; 2],
        }));
        let first_index = self.indices.len() as u32;
        self.indices.extend((1..count - 1).flat_map(|j| [base, base + j, base + j + 1]));
        self.emitters.push(EmitterDraw {
            first_index,
            index_count: self.indices.len() as u32 - first_index,
            light_index: light_index as u32,
        });
    }
}

/// Storage buffers in set 0 of the forward layout ([`SceneBuffers::binding_table`]).
pub(super) const SCENE_BINDINGS: usize = crate::gpu_interface::bindings::forward::SCENE_BUFFERS.len();

/// The per-scene buffers. Every one is in `SceneSizes::buffers` (limits.rs), which
/// `limits::check` checks before they are created.
pub(super) struct SceneBuffers {
    /// The meshes' and the emitters' vertices; storage too: the deferred pass fetches
    /// triangles by id, and the compute placement pulls its patches' vertices.
    pub vertices: Buffer,
    pub indices: Buffer,
    /// Per triangle of the meshes: its 12-index adjacency patch (`Placement::Tcs` draws).
    pub patch_indices: Buffer,
    pub lights: Buffer,
    pub materials: Buffer,
    /// The polygonal lights; a scene without any still binds one (unread) entry.
    pub polygon_lights: Buffer,
    /// What the triangle-level pre-pass (`Placement::Compute`) writes and reads.
    pub pre_pass: PrePassBuffers,
    /// `PATTERN_LEVELS`, the effective levels of the hardware patterns (replaced by the
    /// device's measured table where the built-in one does not hold on it).
    pub pattern_levels: Buffer,
    /// Per triangle: the level records of the level-recording variants (host-visible).
    pub level_records: Buffer,
    /// The counting variants' four counters (`EvaluationCounters` in bindings.glsl).
    pub counters: Buffer,
}

/// The buffers of the triangle-level pre-pass (`Placement::Compute`).
pub(super) struct PrePassBuffers {
    /// Per triangle: its level.
    pub triangle_levels: Buffer,
    /// Per triangle: the level found for it in the current ball of eyes, 0 where none yet
    /// (`ESTIMATED_LEVELS`; zeroed when a ball begins, `Renderer::record_triangle_levels`).
    pub estimated_levels: Buffer,
    /// Per triangle: the triangles across its edges (`uvec4`, scene indices).
    pub triangle_neighbours: Buffer,
    /// Per mesh: its triangles the pre-pass did not cull, those to estimate from its first
    /// triangle on, the back faces of a two-sided mesh from its last triangle down.
    pub visible_triangles: Buffer,
    /// Per mesh: the triangles whose estimate the refining step refines, listed by the
    /// estimator step.
    pub refine_triangles: Buffer,
    /// Per mesh: the triangles to estimate that the range class does not settle, listed by the
    /// range step for the estimator step.
    pub estimate_triangles: Buffer,
    /// Per mesh: the lengths of its interpolated and fallback lists, and the indirect draws each
    /// opened (`PATCH_COUNT_WORDS` a list; zeroed before each pre-pass; the draw counts of
    /// `Renderer::record_patch_lists`).
    pub patch_counts: Buffer,
    /// Per mesh: the indirect dispatches of the range, patch, refining and estimator steps over
    /// the triangles the culling, estimator and range steps listed (`VkDispatchIndirectCommand` and the
    /// list's length, 4 words each, `LEVEL_DISPATCHES` per mesh), reset from
    /// `level_dispatch_reset` before each pre-pass.
    pub level_dispatches: Buffer,
    /// `level_dispatches` before the culling step: (0, 1, 1, 0), no workgroups yet.
    pub level_dispatch_reset: Buffer,
    /// Per mesh, from its first triangle on: its visible triangles shaded on sub-vertices,
    /// those shaded per pixel, and those whose patch is the triangle itself (flat), as the
    /// last step lists them.
    pub patch_lists: [Buffer; 3],
    /// The indirect draws of the first two lists (`VkDrawIndirectCommand`, one per triangle),
    /// indexed by `INTERPOLATED_LIST` and `FALLBACK_LIST`.
    pub patch_draws: [Buffer; 2],
    /// The indirect draws of each mesh's flat list (`VkDrawIndirectCommand`, `PATCH_LISTS` per
    /// mesh: the triangles shaded on their corners, then those shaded per pixel).
    pub flat_draws: Buffer,
    /// The flat patches shaded on their corners as an index buffer over the scene's vertices
    /// (`flat_indices` in glsl/include/bindings.glsl), for meshes whose draws have
    /// `DrawCall::shared_corners`.
    pub flat_indices: Buffer,
    /// Per triangle: its patch's tessellation levels, written by the last step.
    pub patch_levels: Buffer,
}

impl SceneBuffers {
    /// Uploads `geometry` and creates the buffers the shaders write.
    pub(super) fn upload(context: &Arc<Context>, geometry: &SceneGeometry) -> Result<SceneBuffers> {
        let vertices = Buffer::with_data(
            context,
            "scene vertices",
            vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            &geometry.vertices,
        )?;
        let indices = Buffer::with_data(
            context,
            "scene indices",
            vk::BufferUsageFlags::INDEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            &geometry.indices,
        )?;
        let patch_indices = Buffer::with_data(
            context,
            "scene adjacency patches",
            vk::BufferUsageFlags::INDEX_BUFFER,
            &geometry.patch_indices,
        )?;
        let pre_pass = PrePassBuffers::new(context, geometry)?;
        let level_records = Buffer::new(
            context,
            "level records",
            (geometry.triangle_count * 16) as vk::DeviceSize,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let counters = Buffer::new(
            context,
            "evaluation counters",
            16,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let lights = Buffer::with_data(context, "scene lights", storage, &geometry.lights)?;
        let materials = Buffer::with_data(context, "scene materials", storage, &geometry.materials)?;
        let unread = [GpuPolygonLight::default()];
        let polygon_entries: &[GpuPolygonLight] =
            if geometry.polygon_lights.is_empty() { &unread } else { &geometry.polygon_lights };
        let polygon_lights = Buffer::with_data(context, "scene polygonal lights", storage, polygon_entries)?;
        let pattern_levels = Buffer::with_data(
            context,
            "pattern levels",
            storage,
            &crate::shading::estimator::PATTERN_LEVELS,
        )?;
        Ok(SceneBuffers {
            vertices,
            indices,
            patch_indices,
            lights,
            materials,
            polygon_lights,
            pre_pass,
            pattern_levels,
            level_records,
            counters,
        })
    }

    /// Set 0 of the forward layout: the buffer each binding holds, in binding order
    /// (`gpu_interface::bindings::forward`, twin of `glsl/include/bindings.glsl`).
    pub(super) fn binding_table(&self) -> [vk::Buffer; SCENE_BINDINGS] {
        use crate::gpu_interface::bindings::forward as set_0;
        let pre_pass = &self.pre_pass;
        in_binding_order(
            &set_0::SCENE_BUFFERS,
            [
                (set_0::LIGHTS, self.lights.raw),
                (set_0::MATERIALS, self.materials.raw),
                (set_0::LEVEL_RECORDS, self.level_records.raw),
                (set_0::EVALUATION_COUNTERS, self.counters.raw),
                (set_0::POLYGON_LIGHTS, self.polygon_lights.raw),
                (set_0::TRIANGLE_LEVELS, pre_pass.triangle_levels.raw),
                (set_0::TRIANGLE_NEIGHBOURS, pre_pass.triangle_neighbours.raw),
                (set_0::SCENE_VERTICES, self.vertices.raw),
                (set_0::SCENE_INDICES, self.indices.raw),
                (set_0::VISIBLE_TRIANGLES, pre_pass.visible_triangles.raw),
                (set_0::PATCH_COUNTS, pre_pass.patch_counts.raw),
                (set_0::PATTERN_LEVELS, self.pattern_levels.raw),
                (set_0::PATCH_TESS_LEVELS, pre_pass.patch_levels.raw),
                (set_0::INTERPOLATED_PATCHES, pre_pass.patch_lists[0].raw),
                (set_0::FALLBACK_PATCHES, pre_pass.patch_lists[1].raw),
                (set_0::INTERPOLATED_DRAWS, pre_pass.patch_draws[INTERPOLATED_LIST as usize].raw),
                (set_0::FALLBACK_DRAWS, pre_pass.patch_draws[FALLBACK_LIST as usize].raw),
                (set_0::FLAT_PATCHES, pre_pass.patch_lists[2].raw),
                (set_0::FLAT_DRAWS, pre_pass.flat_draws.raw),
                (set_0::LEVEL_DISPATCHES, pre_pass.level_dispatches.raw),
                (set_0::REFINE_TRIANGLES, pre_pass.refine_triangles.raw),
                (set_0::ESTIMATE_TRIANGLES, pre_pass.estimate_triangles.raw),
                (set_0::FLAT_INDICES, pre_pass.flat_indices.raw),
                (set_0::ESTIMATED_LEVELS, pre_pass.estimated_levels.raw),
            ],
        )
    }
}

impl PrePassBuffers {
    /// The pre-pass's buffers for `geometry`'s triangles and meshes.
    fn new(context: &Arc<Context>, geometry: &SceneGeometry) -> Result<PrePassBuffers> {
        let (triangle_count, meshes) = (geometry.triangle_count, geometry.draws.len());
        let per_triangle = |name| device_words(context, name, triangle_count, vk::BufferUsageFlags::empty());
        let triangle_levels = per_triangle("triangle levels")?;
        let estimated_levels = device_words(
            context,
            "levels of the ball of eyes",
            triangle_count,
            vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        let no_neighbours = [[0; 4]];
        let neighbours: &[[u32; 4]] = if geometry.triangle_neighbours.is_empty() {
            &no_neighbours
        } else {
            &geometry.triangle_neighbours
        };
        let triangle_neighbours = Buffer::with_data(
            context,
            "triangle neighbours",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            neighbours,
        )?;
        let visible_triangles = per_triangle("visible triangles")?;
        let refine_triangles = per_triangle("triangles to refine")?;
        let estimate_triangles = per_triangle("triangles to estimate in full")?;
        let patch_counts = device_words(
            context,
            "interpolated and fallback patch counts",
            PATCH_COUNT_WORDS as usize * PATCH_LISTS as usize * meshes,
            vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        let level_dispatches = device_words(
            context,
            "pre-pass dispatches",
            4 * LEVEL_DISPATCHES as usize * meshes,
            // TRANSFER_SRC: `Renderer::pre_pass_dispatches` reads it back.
            vk::BufferUsageFlags::INDIRECT_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
        )?;
        let level_dispatch_reset = Buffer::with_data(
            context,
            "pre-pass dispatch reset",
            vk::BufferUsageFlags::TRANSFER_SRC,
            &vec![[0u32, 1, 1, 0]; LEVEL_DISPATCHES as usize * meshes.max(1)],
        )?;
        let patch_lists = [
            per_triangle("interpolated patches")?,
            per_triangle("fallback patches")?,
            per_triangle("flat patches")?,
        ];
        let indirect = vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let patch_draws = [
            device_words(context, "interpolated patch draws", 4 * triangle_count, indirect)?,
            device_words(context, "fallback patch draws", 4 * triangle_count, indirect)?,
        ];
        let flat_draws =
            device_words(context, "flat patch draws", PATCH_LISTS as usize * 4 * meshes, indirect)?;
        let flat_indices = device_words(
            context,
            "flat patch indices",
            3 * triangle_count,
            vk::BufferUsageFlags::INDEX_BUFFER,
        )?;
        let patch_levels = device_words(
            context,
            "patch tessellation levels",
            4 * triangle_count,
            vk::BufferUsageFlags::empty(),
        )?;
        Ok(PrePassBuffers {
            triangle_levels,
            estimated_levels,
            triangle_neighbours,
            visible_triangles,
            refine_triangles,
            estimate_triangles,
            patch_counts,
            level_dispatches,
            level_dispatch_reset,
            patch_lists,
            patch_draws,
            flat_draws,
            flat_indices,
            patch_levels,
        })
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
