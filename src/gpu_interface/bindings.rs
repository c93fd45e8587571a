//! Every descriptor the shaders declare, by pipeline layout: its GLSL name, set, binding and
//! type (twins: `glsl/include/bindings.glsl` for the forward layout, declared in binding order;
//! the stages of the other layouts).
//!
//! A descriptor's name is its block's for a storage buffer (`Lights` of `buffer Lights { ... }`)
//! and its variable's for a sampler or a texel buffer (`albedo_map`, `triangle_corners`): the
//! names SPIR-V keeps, which the layout test reads back. Each layout's sets list their bindings
//! in order, from 0 without gaps.

use ash::vk;

/// What a descriptor is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DescriptorKind {
    /// A `buffer` block (std430).
    StorageBuffer,
    /// A `sampler2D`.
    CombinedImageSampler,
    /// A `samplerBuffer` or `usamplerBuffer` read with `texelFetch`, four 32-bit words a texel.
    UniformTexelBuffer(TexelFormat),
}

impl DescriptorKind {
    pub const fn descriptor_type(self) -> vk::DescriptorType {
        match self {
            DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
            DescriptorKind::CombinedImageSampler => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            DescriptorKind::UniformTexelBuffer(_) => vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
        }
    }
}

/// The texels of a uniform texel buffer: four 32-bit components, whose formats every Vulkan
/// device must support for uniform texel buffers (the specification's mandatory format
/// support for 32-bit four-component formats).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TexelFormat {
    /// `vec4` texels of a `samplerBuffer`.
    Float4,
    /// `uvec4` texels of a `usamplerBuffer`.
    Uint4,
}

impl TexelFormat {
    /// Bytes of one texel.
    pub const BYTES: u64 = 16;

    pub const fn format(self) -> vk::Format {
        match self {
            TexelFormat::Float4 => vk::Format::R32G32B32A32_SFLOAT,
            TexelFormat::Uint4 => vk::Format::R32G32B32A32_UINT,
        }
    }
}

/// One descriptor of a pipeline layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    /// The GLSL block's name (buffers) or variable's name (samplers).
    pub name: &'static str,
    pub set: u32,
    pub binding: u32,
    pub kind: DescriptorKind,
}

const fn storage(set: u32, binding: u32, name: &'static str) -> Binding {
    Binding { name, set, binding, kind: DescriptorKind::StorageBuffer }
}

const fn sampler(set: u32, binding: u32, name: &'static str) -> Binding {
    Binding { name, set, binding, kind: DescriptorKind::CombinedImageSampler }
}

const fn texels(set: u32, binding: u32, name: &'static str, format: TexelFormat) -> Binding {
    Binding { name, set, binding, kind: DescriptorKind::UniformTexelBuffer(format) }
}

/// A pipeline layout: its descriptor sets, each its bindings in order.
#[derive(Clone, Copy, Debug)]
pub struct Layout {
    pub name: &'static str,
    pub sets: &'static [&'static [Binding]],
}

impl Layout {
    /// The binding named `name`, if the layout has one.
    pub fn find(&self, name: &str) -> Option<Binding> {
        self.sets.iter().flat_map(|set| set.iter()).copied().find(|b| b.name == name)
    }
}

/// The forward passes, the deferred pass and the multirate pre-pass: every stage not listed
/// under another layout.
pub mod forward {
    use super::{sampler, storage, texels, Binding, Layout, TexelFormat};

    pub const LIGHTS: Binding = storage(0, 0, "Lights");
    pub const MATERIALS: Binding = storage(0, 1, "Materials");
    /// Written only by the level-recording pipelines.
    pub const LEVEL_RECORDS: Binding = storage(0, 2, "LevelRecords");
    /// The counting variants' four counters.
    pub const EVALUATION_COUNTERS: Binding = storage(0, 3, "EvaluationCounters");
    pub const POLYGON_LIGHTS: Binding = storage(0, 4, "PolygonLights");
    pub const TRIANGLE_LEVELS: Binding = storage(0, 5, "TriangleLevels");
    /// Per triangle of the meshes, the triangles across its three edges (and 0).
    pub const TRIANGLE_NEIGHBOURS: Binding = texels(0, 6, "triangle_neighbours", TexelFormat::Uint4);
    /// The scene's vertices, two texels each: (position, normal.x), (normal.yz, uv).
    pub const SCENE_VERTICES: Binding = texels(0, 7, "scene_vertices", TexelFormat::Float4);
    const _: () = {
        use crate::gpu_types::Vertex;
        assert!(
            std::mem::offset_of!(Vertex, normal) == 12
                && std::mem::offset_of!(Vertex, uv) == 24
                && std::mem::size_of::<Vertex>() == 2 * TexelFormat::BYTES as usize
        );
    };
    pub const SCENE_INDICES: Binding = storage(0, 8, "SceneIndices");
    pub const VISIBLE_TRIANGLES: Binding = storage(0, 9, "VisibleTriangles");
    pub const PATCH_COUNTS: Binding = storage(0, 10, "PatchCounts");
    pub const PATTERN_LEVELS: Binding = storage(0, 11, "PatternLevels");
    pub const PATCH_TESS_LEVELS: Binding = storage(0, 12, "PatchTessLevels");
    pub const INTERPOLATED_PATCHES: Binding = storage(0, 13, "InterpolatedPatches");
    pub const FALLBACK_PATCHES: Binding = storage(0, 14, "FallbackPatches");
    pub const INTERPOLATED_DRAWS: Binding = storage(0, 15, "InterpolatedDraws");
    pub const FALLBACK_DRAWS: Binding = storage(0, 16, "FallbackDraws");
    pub const FLAT_PATCHES: Binding = storage(0, 17, "FlatPatches");
    pub const FLAT_DRAWS: Binding = storage(0, 18, "FlatDraws");
    pub const LEVEL_DISPATCHES: Binding = storage(0, 19, "LevelDispatches");
    pub const REFINE_TRIANGLES: Binding = storage(0, 20, "RefineTriangles");
    pub const ESTIMATE_TRIANGLES: Binding = storage(0, 21, "EstimateTriangles");
    pub const FLAT_INDICES: Binding = storage(0, 22, "FlatIndices");
    /// Per triangle, the level the pre-pass found for it in the current ball of eyes (0 where it
    /// has found none yet): what later frames reuse.
    pub const ESTIMATED_LEVELS: Binding = storage(0, 23, "EstimatedLevels");
    /// The flat patches shaded per pixel, as an index buffer over the scene's vertices.
    pub const FALLBACK_INDICES: Binding = storage(0, 24, "FallbackIndices");
    /// Per triangle of the meshes, its corners' positions (a texel each): what the culling step
    /// reads without the indices.
    pub const TRIANGLE_CORNERS: Binding = texels(0, 25, "triangle_corners", TexelFormat::Float4);
    /// The shadow maps (`GpuShadowMap`), six texels each: the directional light's matrix's
    /// columns, `rect`, `depth`; one unread entry where no light casts shadows. A texel buffer:
    /// on lavapipe a storage-buffer load at an index read from another buffer is a loop over the
    /// lanes for every word, and took most of a frame's time with shadows.
    pub const SHADOW_MAPS: Binding = texels(0, 26, "shadow_maps", TexelFormat::Float4);
    const _: () = {
        use crate::gpu_types::GpuShadowMap;
        assert!(
            std::mem::offset_of!(GpuShadowMap, rect) == 4 * TexelFormat::BYTES as usize
                && std::mem::offset_of!(GpuShadowMap, depth) == 5 * TexelFormat::BYTES as usize
                && std::mem::size_of::<GpuShadowMap>() == SHADOW_MAP_TEXELS * TexelFormat::BYTES as usize
        );
    };
    /// Texels of one shadow map in `shadow_maps`.
    pub const SHADOW_MAP_TEXELS: usize = 6;
    /// Per triangle, the pre-pass's hold state (`gpu_types::LevelHold`, `render::level_hold`).
    pub const LEVEL_HOLDS: Binding = storage(0, 27, "LevelHolds");

    pub const ALBEDO_MAP: Binding = sampler(1, 0, "albedo_map");
    pub const PARAMETER_MAP: Binding = sampler(1, 1, "parameter_map");
    /// The parameter map's min/max pyramid.
    pub const PARAMETER_PYRAMID: Binding = sampler(1, 2, "parameter_pyramid");
    /// Every shadow map in one depth image, the same in every material's set.
    pub const SHADOW_ATLAS: Binding = sampler(1, 3, "shadow_atlas");

    /// The deferred pass's visibility buffer.
    pub const VISIBILITY: Binding = sampler(2, 0, "visibility");

    /// Set 0: the scene's storage and texel buffers, bound once.
    pub const SCENE_BUFFERS: [Binding; 28] = [
        LIGHTS,
        MATERIALS,
        LEVEL_RECORDS,
        EVALUATION_COUNTERS,
        POLYGON_LIGHTS,
        TRIANGLE_LEVELS,
        TRIANGLE_NEIGHBOURS,
        SCENE_VERTICES,
        SCENE_INDICES,
        VISIBLE_TRIANGLES,
        PATCH_COUNTS,
        PATTERN_LEVELS,
        PATCH_TESS_LEVELS,
        INTERPOLATED_PATCHES,
        FALLBACK_PATCHES,
        INTERPOLATED_DRAWS,
        FALLBACK_DRAWS,
        FLAT_PATCHES,
        FLAT_DRAWS,
        LEVEL_DISPATCHES,
        REFINE_TRIANGLES,
        ESTIMATE_TRIANGLES,
        FLAT_INDICES,
        ESTIMATED_LEVELS,
        FALLBACK_INDICES,
        TRIANGLE_CORNERS,
        SHADOW_MAPS,
        LEVEL_HOLDS,
    ];
    /// Set 1: the draw's material textures, bound per draw.
    pub const MATERIAL_TEXTURES: [Binding; 4] = [ALBEDO_MAP, PARAMETER_MAP, PARAMETER_PYRAMID, SHADOW_ATLAS];
    /// Set 2: the deferred pass's input.
    pub const DEFERRED_INPUTS: [Binding; 1] = [VISIBILITY];

    pub const LAYOUT: Layout =
        Layout { name: "forward", sets: &[&SCENE_BUFFERS, &MATERIAL_TEXTURES, &DEFERRED_INPUTS] };
}

/// The present pass (`fullscreen.vert`, `present.frag`).
pub mod present {
    use super::{sampler, Binding, Layout};

    /// The float render target it tone-maps.
    pub const HDR_IMAGE: Binding = sampler(0, 0, "hdr_image");

    pub const LAYOUT: Layout = Layout { name: "present", sets: &[&[HDR_IMAGE]] };
}

/// The post chain (`post_*.comp`, `post_*.frag` with `fullscreen.vert`): one set, bound by every
/// stage (`glsl/include/post.glsl`).
pub mod post {
    use super::{sampler, storage, Binding, Layout};

    /// The linear float frame, read only.
    pub const LINEAR_FRAME: Binding = sampler(0, 0, "linear_frame");
    /// One of the chain's quarter-resolution images.
    pub const BLOOM_IMAGE: Binding = sampler(0, 1, "bloom_image");
    /// The adapted log luminance and exposure.
    pub const ADAPTATION: Binding = storage(0, 2, "Adaptation");

    /// Set 0.
    pub const INPUTS: [Binding; 3] = [LINEAR_FRAME, BLOOM_IMAGE, ADAPTATION];

    pub const LAYOUT: Layout = Layout { name: "post", sets: &[&INPUTS] };
}

/// The tessellation capture (`capture.*`).
pub mod capture {
    use super::{storage, Binding, Layout};

    /// The evaluation stage's tessellation coordinates.
    pub const COORDS: Binding = storage(0, 0, "Coords");
    /// The geometry stage's triangles.
    pub const TRIANGLES: Binding = storage(0, 1, "Triangles");

    /// Set 0.
    pub const BUFFERS: [Binding; 2] = [COORDS, TRIANGLES];

    pub const LAYOUT: Layout = Layout { name: "capture", sets: &[&BUFFERS] };
}

/// The GPU check of the polygon code (`polygon_check.comp`).
pub mod polygon_check {
    use super::{storage, Binding, Layout};

    pub const CASES: Binding = storage(0, 0, "Cases");
    pub const RESULTS: Binding = storage(0, 1, "Results");

    /// Set 0.
    pub const BUFFERS: [Binding; 2] = [CASES, RESULTS];

    pub const LAYOUT: Layout = Layout { name: "polygon check", sets: &[&BUFFERS] };
}

/// Every layout.
pub const LAYOUTS: [Layout; 5] =
    [forward::LAYOUT, present::LAYOUT, post::LAYOUT, capture::LAYOUT, polygon_check::LAYOUT];

/// The layout `stage` (a file name under `glsl/`) is compiled against.
pub fn layout_of(stage: &str) -> Layout {
    match stage {
        "fullscreen.vert" | "present.frag" => present::LAYOUT,
        "capture.vert" | "capture.tesc" | "capture.tese" | "capture.geom" => capture::LAYOUT,
        "polygon_check.comp" => polygon_check::LAYOUT,
        stage if stage.starts_with("post_") => post::LAYOUT,
        _ => forward::LAYOUT,
    }
}

/// `resources`, each given with the binding it goes to, in the order of `bindings`.
///
/// # Panics
/// If a binding of `bindings` is given no resource or more than one (then another is missing).
pub fn in_binding_order<T: Copy, const N: usize>(
    bindings: &[Binding; N],
    resources: [(Binding, T); N],
) -> [T; N] {
    bindings.map(|binding| {
        let mut given = resources.iter().filter(|(b, _)| *b == binding).map(|&(_, resource)| resource);
        let resource = given.next().unwrap_or_else(|| panic!("no resource for binding {}", binding.name));
        assert!(given.next().is_none(), "two resources for binding {}", binding.name);
        resource
    })
}
