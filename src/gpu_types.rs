//! `#[repr(C)]` twins of the structs in `glsl/include/types.glsl`. A test reads the member
//! offsets out of the compiled SPIR-V and checks they match these.

use bytemuck::{Pod, Zeroable};
use glam::{IVec4, Mat4, Vec2, Vec3, Vec4};

/// A light as the shaders read it (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// Point: world position; directional: the unit direction the light travels.
    pub position: Vec4,
    /// rgb: colour × intensity.
    pub radiance: Vec4,
    /// x: the light's map in [`GpuShadowMap`]s, or -1 where it casts no shadow; y: the radius of its filter kernel in texels; z: its slot
    /// in multirate's interpolants (`LightShadow::slot`).
    pub shadow: IVec4,
}

/// A triangle's hold state in the multirate pre-pass (std430; `render::level_hold`): the level
/// it is held at, the highest of the coarser estimates since, how many of those came in a row,
/// and whether no hold is open (1) or one is (0, as in a zeroed state).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LevelHold {
    pub held: f32,
    pub lower: f32,
    pub estimates: u32,
    pub closed: u32,
}

/// One shadow map in the atlas: a directional light's square, or a point light's six square
/// faces in a block of 3 × 2 (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuShadowMap {
    /// A directional light's map: world to its clip space (depth 0 to 1); unread for a cube.
    pub view_proj: Mat4,
    /// x, y: the map's first texel in the atlas; z: texels along its (each face's) side; w: a
    /// texel's width in world units (a cube face: per unit of distance along its axis).
    pub rect: Vec4,
    /// A cube: x, y the faces' near and far distances along their axes, z 1; a directional
    /// light's map: z 0.
    pub depth: Vec4,
}

/// A polygonal area light as the shaders read it (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPolygonLight {
    /// xyz: world positions; the first `info.x` are the vertices in order.
    pub vertices: [Vec4; 8],
    /// xyz: unit normal of the emitting side; w: area.
    pub normal: Vec4,
    /// rgb: emitted radiance.
    pub radiance: Vec4,
    /// x: vertex count.
    pub info: IVec4,
}

/// A material as the shaders read it (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Lambert kd, Blinn-Phong kd, GGX albedo.
    pub diffuse: Vec4,
    /// Blinn-Phong ks, GGX f0.
    pub specular: Vec4,
    /// x: Blinn-Phong shininess or GGX roughness (the map's `lo` with a parameter map).
    pub params: Vec4,
    /// ≥ 0 where the material has the texture, −1 where not: x albedo map, y parameter map
    /// (and its min/max pyramid); w: the parameter map's mapping (0 linear, 1 exponential).
    pub maps: IVec4,
    /// x, y: the parameter map's `lo` and `hi`.
    pub parameter_range: Vec4,
}

/// Per-draw push constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DrawConstants {
    pub view_proj: Mat4,
    /// The camera's position in world space.
    pub eye: Vec3,
    /// multirate: triangles whose image covers fewer pixels are shaded per pixel without an
    /// estimate (`geometry::cull::small_image`; 0: every visible triangle is estimated).
    pub min_estimated_area: f32,
    /// The target's size in pixels.
    pub viewport_size: Vec2,
    /// Multirate's error bound ε.
    pub epsilon: f32,
    /// Multirate's highest level, clamped by the host to `1..=MAX_LEVEL` (the range the shaders
    /// read it in).
    pub n_max: u32,
    pub material_index: u32,
    pub mesh_index: u32,
    /// What the draw's kind takes (the 128 bytes of push constants every device offers leave no
    /// room for a field each): a `fixed:N` draw's tessellation level, an emitter draw's polygonal
    /// light. The shaders read it through `fixed_level()` and `emitter_light()` (bindings.glsl).
    pub draw_argument: u32,
    /// Index of the draw's first triangle in the scene (level records).
    pub patch_base: u32,
    /// Bits of [`crate::gpu_interface::flags`].
    pub flags: u32,
    /// multirate: the levels hold for every eye within this distance of `eye`
    /// ([`EstimatorSettings::eye_radius`]).
    ///
    /// [`EstimatorSettings::eye_radius`]: crate::shading::estimator::EstimatorSettings::eye_radius
    pub eye_radius: f32,
    /// The triangle-level pre-pass: how many triangles the dispatch covers.
    pub triangle_count: u32,
    /// `--estimator compute`: patches per indirect draw of a patch list (see `Renderer::patches_per_draw`).
    pub patches_per_draw: u32,
}

/// Vertex buffer layout: world-space position, normal and texture coordinates. The shaders
/// also read it as two 16-byte texels, (position, normal.x) and (normal.yz, uv)
/// (`scene_position`, `scene_normal`, `scene_uv` in glsl/include/bindings.glsl;
/// `gpu_interface::bindings::forward::SCENE_VERTICES` asserts the layout).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// Texture coordinates (zero for meshes without them).
    pub uv: [f32; 2],
}
