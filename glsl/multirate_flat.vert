#version 460
// variants: material_kind polygon_lights textured count_evaluations shadows
// `multirate` mode, `--estimator compute`: the flat patches (bindings.glsl), whose inner and
// outer levels are all 1, drawn without the tessellation stages. Drawn indexed from
// flat_indices or fallback_indices, vertex v is the scene's; drawn from the flat list, vertex
// 3k + c is corner c of the list's k-th triangle. A corner is shaded as multirate.tese shades it at level 1 (same
// position, normal, parameter level of detail and precise clip position), so the image, the
// evaluation count and the edges shared with tessellated neighbours are those of the
// tessellated draw. In the draw of the flat triangles shaded per pixel (FLAG_FALLBACK_PATCHES)
// it shades nothing and passes the corner on to multirate.frag at level 0, as multirate.tese
// does for a fallback patch.
#include "triangle_level.glsl"
#include "texturing.glsl"

layout(location = 0) out vec3 out_diffuse;
layout(location = 1) out vec3 out_specular;
layout(location = 2) out vec3 out_position;
layout(location = 3) out vec3 out_normal;
layout(location = 4) out vec2 out_uv;
layout(location = 5) flat out float out_level;
#if TRIANGLE_IDS || VARIANT_SHADOWS
layout(location = TRIANGLE_ID_LOCATION) flat out uint out_triangle;
#endif
#if VARIANT_SHADOWS
// Each shadow-casting light's unshadowed shading, by slot (shadow.glsl).
layout(location = SHADOWED_DIFFUSE_LOCATION) out vec3 out_shadowed_diffuse[MAX_SHADOWED_LIGHTS];
layout(location = SHADOWED_SPECULAR_LOCATION) out vec3 out_shadowed_specular[MAX_SHADOWED_LIGHTS];
#endif

// Writes `apart` to the shadowed lights' outputs (where the variant has them).
void write_shadowed(Shading apart[MAX_SHADOWED_LIGHTS]) {
#if VARIANT_SHADOWS
    for (uint k = 0u; k < MAX_SHADOWED_LIGHTS; ++k) {
        out_shadowed_diffuse[k] = apart[k].diffuse;
        out_shadowed_specular[k] = apart[k].specular;
    }
#endif
}

// Writes the triangle the fragment stage reads (where the variant passes it on).
void write_triangle(uint triangle) {
#if TRIANGLE_IDS || VARIANT_SHADOWS
    out_triangle = triangle;
#endif
}

precise gl_Position;

void main() {
    bool per_pixel = (draw.flags & FLAG_FALLBACK_PATCHES) != 0u;
    GpuMaterial m = materials[draw.material_index];
    // Drawn from the flat list (shaded on the corners of a mesh with a parameter map), or
    // indexed from flat_indices or fallback_indices, where a vertex is the scene's and the
    // triangle the draw's primitive.
    bool listed = !per_pixel && (draw.flags & FLAG_SHARED_CORNERS) == 0u;
    uint triangle = ID_FROM_PRIMITIVE;
    uint vertex = uint(gl_VertexIndex);
    if (listed) {
        triangle = flat_patches[draw.patch_base + uint(gl_VertexIndex) / 3u];
        vertex = scene_indices[3u * triangle + uint(gl_VertexIndex) % 3u];
    }
    // The listed patches are drawn by class (DRAWN_SHADOW_CLASSES, bindings.glsl).
    bool other_draws = listed && !drawn_by_class(triangle);
    if (vertex == SKIPPED_VERTEX || other_draws) {
        // A triangle that is not such a patch, or that the other draw shows: a point, dropped
        // before rasterisation.
        gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
        out_diffuse = vec3(0.0);
        out_specular = vec3(0.0);
        out_position = vec3(0.0);
        out_normal = vec3(0.0);
        out_uv = vec2(0.0);
        out_level = 1.0;
        write_triangle(triangle);
        write_shadowed(no_shading_apart());
        return;
    }
    vec3 position = scene_position(vertex);
    vec3 normal = scene_normal(vertex);
    vec2 uv = scene_uv(vertex);
    out_position = position;
    out_normal = normal;
    out_uv = uv;
    write_triangle(triangle);
    gl_Position = draw.view_proj * vec4(position, 1.0);
    if (per_pixel) {
        out_diffuse = vec3(0.0);
        out_specular = vec3(0.0);
        out_level = 0.0;
        write_shadowed(no_shading_apart());
        return;
    }
    float parameter = m.params.x;
    if (has_parameter_map(m)) {
        uvec3 corners = uvec3(scene_indices[3u * triangle], scene_indices[3u * triangle + 1u],
                              scene_indices[3u * triangle + 2u]);
        vec3 p[3] = vec3[3](scene_position(corners.x), scene_position(corners.y), scene_position(corners.z));
        vec2 t[3] = vec2[3](scene_uv(corners.x), scene_uv(corners.y), scene_uv(corners.z));
        // multirate_patch.glsl's `parameter_lod_bound` of the patch.
        float lod_bound = material_lod_bound(t[0], t[1], t[2]) - 0.02;
        parameter = parameter_at_lod(m, uv, subvertex_lod(m, p, t, position, 1.0, lod_bound));
    }
    Shading apart[MAX_SHADOWED_LIGHTS] = no_shading_apart();
#if VARIANT_SHADOWS
    // A shared corner serves triangles of every class: each shadow-casting light apart.
    uint classes = listed ? triangle_shadow_classes(triangle) : MIXED_CLASS_BIT * ((1u << MAX_SHADOWED_LIGHTS) - 1u);
    Shading s = shade_split(position, normal, draw.eye.xyz, draw.material_index, parameter, classes, apart);
#else
    Shading s = shade(position, normal, draw.eye.xyz, draw.material_index, parameter);
#endif
    write_shadowed(apart);
    out_diffuse = s.diffuse;
    out_specular = s.specular;
    if (COUNT_EVALUATIONS) {
        atomicAdd(counters.subvertex_evaluations, 1u);
    }
    out_level = 1.0;
}
