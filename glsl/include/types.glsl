// Structs shared between the shaders and the CPU. Each has a `#[repr(C)]` twin in
// `src/gpu_types.rs`; a test reads the member offsets out of the compiled SPIR-V and compares.
// The flag bits of DrawConstants too, twins of `src/gpu_interface/flags.rs` (compared by the
// same test file).
#ifndef TYPES_GLSL
#define TYPES_GLSL

// One light. Point lights come first in the buffer, then directional ones
// (their counts are the specialization constants POINT_LIGHT_COUNT and DIRECTIONAL_LIGHT_COUNT).
struct GpuLight {
    vec4 position;   // point: world position; directional: unit direction the light travels
    vec4 radiance;   // rgb: colour * intensity (the irradiance at unit distance, facing the light)
    ivec4 shadow;    // x: its map in shadow_maps, -1: none;
                     // y: the filter kernel's radius in texels; z: its slot in the
                     // interpolants that carry its unshadowed shading apart (shadow.glsl)
};


// One polygonal area light (a one-sided Lambertian emitter, convex, planar).
struct GpuPolygonLight {
    vec4 vertices[8]; // xyz: world positions, the first `info.x` in order
    vec4 normal;      // xyz: unit normal of the emitting side; w: area
    vec4 radiance;    // rgb: emitted radiance
    ivec4 info;       // x: vertex count (3 to 8)
};

// One material. Which fields mean what depends on MATERIAL_KIND.
struct GpuMaterial {
    vec4 diffuse;    // Lambert kd, Blinn-Phong kd, GGX albedo
    vec4 specular;   // Blinn-Phong ks, GGX f0 (unused for Lambert)
    vec4 params;     // x: Blinn-Phong shininess or GGX roughness (the map's lo with a map)
    ivec4 maps;      // >= 0 where the material has it, -1 where not: x albedo map, y parameter
                     // map (and its pyramid); w: the parameter mapping (0 linear, 1 exponential)
    vec4 parameter_range; // x, y: the parameter map's lo and hi
};

// A triangle's hold state in the multirate pre-pass (level_hold.glsl): the level it is held at,
// the highest of the coarser estimates since, how many of those came in a row, and whether no
// hold is open (1) or one is (0).
struct LevelHold {
    float held;
    float lower;
    uint estimates;
    uint closed;
};

// Per-draw constants, pushed for every mesh.
struct DrawConstants {
    mat4 view_proj;      // world to Vulkan clip space
    vec3 eye;            // camera position in world space
    float min_estimated_area; // multirate: images smaller (pixels) are shaded per pixel unestimated
    vec2 viewport_size;  // the target's size in pixels
    float epsilon;       // multirate's error bound
    uint n_max;          // multirate's highest level, in 1..=64 (clamped by the host)
    uint material_index; // index into the material buffer
    uint mesh_index;
    uint draw_argument;  // what the draw's kind takes: read through fixed_level() and emitter_light()
    uint patch_base;     // index of this draw's first triangle in the scene (level records)
    uint flags;          // FLAG_ bits, below
    float eye_radius;    // multirate: the levels hold for every eye this close to `eye`
    uint triangle_count; // the triangle-level pre-pass: triangles of this dispatch
    uint patches_per_draw; // the compute placement: patches per indirect draw of a patch list
};

// DrawConstants.flags bits (`src/gpu_interface/flags.rs`; declared here only).
// Show the tessellation level heat map instead of shading (heat.glsl).
const uint FLAG_HEAT_MAP = 1u;
// `pixel-deferred` writes the analytic against hardware uv derivative difference instead of
// shading (deferred.frag).
const uint FLAG_DERIVATIVE_CHECK = 2u;
// The mesh is one-sided: its back faces are culled (triangle_level.glsl).
const uint FLAG_ONE_SIDED = 4u;
// The multirate draw of a mesh's fallback list (else of its interpolated one), or of its flat
// triangles shaded per pixel (bindings.glsl).
const uint FLAG_FALLBACK_PATCHES = 16u;
// The mesh's flat patches shaded on their corners are drawn indexed from flat_indices (its
// material has no parameter map).
const uint FLAG_SHARED_CORNERS = 32u;
// The multirate pre-pass reuses the levels of estimated_levels and keeps those it finds.
const uint FLAG_REUSE_LEVELS = 64u;
// The multirate pre-pass holds levels: a lower estimate is used only once it has come several
// times in a row (level_hold.glsl).
const uint FLAG_HOLD_LEVELS = 128u;

#endif
