// The three BRDFs of the paper (seed 003 Eq. 16, 24, 30) and their sum over the scene's lights.
// Textures are read in texturing.glsl.
// Rust twin: `src/shading/brdf.rs` and `src/shading/mod.rs` (polygonal lights:
// polygon_light.glsl). Keep the two in step, operation
// for operation: a GPU test compares rendered pixels with the twin.
//
// The material kind and whether polygonal lights exist are build.rs's variant defines, so only
// what the scene uses is compiled in: a Lambert variant contains no GGX code, a variant without
// polygonal lights none of polygon_light.glsl. The light counts are specialization constants.
#ifndef BRDF_GLSL
#define BRDF_GLSL
#include "bindings.glsl"
#include "shadow.glsl"

#define MATERIAL_LAMBERT 0
#define MATERIAL_BLINN_PHONG 1
#define MATERIAL_GGX 2

const int MATERIAL_KIND = VARIANT_MATERIAL_KIND;
#if VARIANT_POLYGON_LIGHTS
// Polygonal lights: how many, samples per technique, the light technique (0 projected solid
// angle, 1 solid angle) and MIS's visibility estimate v (polygon_light.glsl).
layout(constant_id = 8) const int POLYGON_LIGHT_COUNT = 0;
layout(constant_id = 9) const int POLYGON_SAMPLES = 8;
layout(constant_id = 10) const int POLYGON_TECHNIQUE = 0;
layout(constant_id = 11) const float MIS_VISIBILITY = 0.5;
#else
// No polygonal lights: the loops over them vanish (the estimator's polygon bounds, which read
// the other three, are then never called).
const int POLYGON_LIGHT_COUNT = 0;
const int POLYGON_SAMPLES = 8;
const int POLYGON_TECHNIQUE = 0;
const float MIS_VISIBILITY = 0.5;
#endif

const float PI = 3.14159265358979323846;
// GGX alpha is clamped from below so that D stays finite at roughness 0.
const float GGX_MIN_ALPHA = 1.0e-3;
// Squared distance below which a point light counts as this close (keeps 1/d^2 finite).
const float MIN_LIGHT_DISTANCE_SQUARED = 1.0e-8;

// v / |v|, and the zero vector for the zero vector (never NaN).
vec3 safe_normalize(vec3 v) {
    return v * inversesqrt(max(dot(v, v), 1.0e-30));
}

// GGX / Trowbridge-Reitz normal distribution (Eq. 46 of the supplement).
float ggx_d(float n_dot_h, float alpha) {
    float a2 = alpha * alpha;
    float d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// The same of sin^2 theta_h = 1 - (n.h)^2, which the shading takes as |n x h|^2: near the
// highlight (n.h)^2 (a^2 - 1) + 1 cancels in f32 (see `ggx_d_sin2` in brdf.rs).
float ggx_d_sin2(float sin2, float alpha) {
    float a2 = alpha * alpha;
    float d = sin2 * (1.0 - a2) + a2;
    return a2 / (PI * d * d);
}

// Schlick's Fresnel approximation.
vec3 schlick_f(float v_dot_h, vec3 f0) {
    float m = 1.0 - v_dot_h;
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// Smith / Schlick-GGX visibility with the cosines of the microfacet denominator folded in:
// V = G1(l) G1(v) / (n.l n.v) = 1 / ((n.l (1-k) + k) (n.v (1-k) + k)).
float smith_v(float n_dot_l, float n_dot_v, float k) {
    return 1.0 / ((n_dot_l * (1.0 - k) + k) * (n_dot_v * (1.0 - k) + k));
}

// Reflected radiance per unit irradiance for one light, split into the diffuse part (which an
// albedo map multiplies per pixel) and the specular part: BRDF term times the cosine where the
// paper's model includes it. n, l, v are unit vectors; `parameter` is the shininess
// (Blinn-Phong) or roughness (GGX) to shade with (the material's own or its map's).
struct Shading {
    vec3 diffuse;
    vec3 specular;
};

Shading reflect_one_light(vec3 n, vec3 l, vec3 v, GpuMaterial m, float parameter) {
    Shading s = Shading(vec3(0.0), vec3(0.0));
    float n_dot_l = dot(n, l);
    if (n_dot_l <= 0.0) {
        return s;
    }
    s.diffuse = m.diffuse.rgb * n_dot_l;
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return s;
    }
    vec3 h = safe_normalize(l + v);
    float n_dot_h = max(dot(n, h), 0.0);
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        s.specular = m.specular.rgb * pow(n_dot_h, parameter);
        return s;
    }
    float alpha = max(parameter * parameter, GGX_MIN_ALPHA);
    float k = 0.5 * alpha;
    float n_dot_v = max(dot(n, v), 0.0);
    float v_dot_h = clamp(dot(v, h), 0.0, 1.0);
    vec3 n_cross_h = cross(n, h);
    float sin2_h = n_dot_h > 0.0 ? min(dot(n_cross_h, n_cross_h), 1.0) : 1.0;
    vec3 specular = ggx_d_sin2(sin2_h, alpha) * schlick_f(v_dot_h, m.specular.rgb)
        * smith_v(n_dot_l, n_dot_v, k) * 0.25;
    s.specular = specular * n_dot_l;
    return s;
}

#if VARIANT_POLYGON_LIGHTS
#include "polygon_light.glsl"
#endif

// How `shade_lights` treats a shadow-casting light (a constant at every call, so a caller holds
// only its rule's code, and none where no light casts shadows).
const int LIGHTS_UNSHADOWED = 0; // every light in the sum, unshadowed
const int LIGHTS_VISIBLE = 1;    // every light in the sum, each times its visibility at `lookup`
const int LIGHTS_SPLIT = 2;      // by the triangle's class (`classes`): those that reach all of it
                                 // in the sum, those that reach part apart by slot, unshadowed,
                                 // those that reach none left out

// Adds the shading of light `light`, light `i` of `lights` (towards it `l`, its irradiance
// `irradiance`), to `total`, or puts it in `apart`, or leaves it out, by `rule`.
void add_light_shading(GpuLight light, int i, vec3 l, vec3 irradiance, vec3 n, vec3 v, GpuMaterial m,
                       float parameter, int rule, ShadowPoint lookup, uint classes, inout Shading total,
                       inout Shading apart[MAX_SHADOWED_LIGHTS]) {
    bool casts = casts_shadows(i);
    int slot = casts ? shadow_slot(i) : 0;
    uint slot_bit = casts ? 1u << uint(slot) : 0u;
    if (rule == LIGHTS_SPLIT && (classes & SHADOWED_CLASS_BIT * slot_bit) != 0u) {
        return;
    }
    if (rule == LIGHTS_VISIBLE && casts) {
        irradiance *= shadow_visibility_at(light, i, lookup);
    }
    Shading one = reflect_one_light(n, l, v, m, parameter);
    if (rule == LIGHTS_SPLIT && (classes & MIXED_CLASS_BIT * slot_bit) != 0u) {
        apart[slot] = Shading(one.diffuse * irradiance, one.specular * irradiance);
    } else {
        total.diffuse += one.diffuse * irradiance;
        total.specular += one.specular * irradiance;
    }
}

// Outgoing radiance at a surface point, summed over the scene's lights by `rule`, diffuse and
// specular apart. `normal` need not be unit length (it is interpolated); `eye` is the camera.
Shading shade_lights(vec3 position, vec3 normal, vec3 eye, uint material_index, float parameter, int rule,
                     ShadowPoint lookup, uint classes, inout Shading apart[MAX_SHADOWED_LIGHTS]) {
    GpuMaterial m = materials[material_index];
    vec3 n = safe_normalize(normal);
    vec3 v = safe_normalize(eye - position);
    Shading total = Shading(vec3(0.0), vec3(0.0));
    for (int i = 0; i < POINT_LIGHT_COUNT; ++i) {
        vec3 to_light = lights[i].position.xyz - position;
        float d2 = max(dot(to_light, to_light), MIN_LIGHT_DISTANCE_SQUARED);
        vec3 l = to_light * inversesqrt(d2);
        vec3 irradiance = lights[i].radiance.rgb / d2;
        add_light_shading(lights[i], i, l, irradiance, n, v, m, parameter, rule, lookup, classes, total, apart);
    }
    for (int i = 0; i < DIRECTIONAL_LIGHT_COUNT; ++i) {
        GpuLight light = lights[POINT_LIGHT_COUNT + i];
        add_light_shading(light, POINT_LIGHT_COUNT + i, -light.position.xyz, light.radiance.rgb, n, v, m, parameter,
                          rule, lookup, classes, total, apart);
    }
#if VARIANT_POLYGON_LIGHTS
    for (int i = 0; i < POLYGON_LIGHT_COUNT; ++i) {
        Shading one = shade_polygon(position, n, v, m, parameter, i);
        total.diffuse += one.diffuse;
        total.specular += one.specular;
    }
#endif
    return total;
}

// No shading per shadow-casting light (the `apart` of the rules that fill none).
Shading[MAX_SHADOWED_LIGHTS] no_shading_apart() {
    Shading apart[MAX_SHADOWED_LIGHTS];
    for (uint k = 0u; k < MAX_SHADOWED_LIGHTS; ++k) {
        apart[k] = Shading(vec3(0.0), vec3(0.0));
    }
    return apart;
}

// Every light, unshadowed.
Shading shade(vec3 position, vec3 normal, vec3 eye, uint material_index, float parameter) {
    Shading apart[MAX_SHADOWED_LIGHTS] = no_shading_apart();
    ShadowPoint none = ShadowPoint(vec3(0.0), vec3(0.0), false);
    return shade_lights(position, normal, eye, material_index, parameter, LIGHTS_UNSHADOWED, none, 0u, apart);
}

// Every light, each shadow-casting one times its visibility at `lookup`.
Shading shade_visible(vec3 position, vec3 normal, vec3 eye, uint material_index, float parameter,
                      ShadowPoint lookup) {
    Shading apart[MAX_SHADOWED_LIGHTS] = no_shading_apart();
    return shade_lights(position, normal, eye, material_index, parameter, LIGHTS_VISIBLE, lookup, 0u, apart);
}

// What multirate interpolates on a triangle of visibility classes `classes`
// (triangle_shadow_classes): summed, the lights without a shadow map and those that reach all
// of the triangle; apart, by slot, the unshadowed shading of each light that may reach part of
// it (zero in the other slots); the lights that reach none of it nowhere.
Shading shade_split(vec3 position, vec3 normal, vec3 eye, uint material_index, float parameter, uint classes,
                    out Shading apart[MAX_SHADOWED_LIGHTS]) {
    apart = no_shading_apart();
    ShadowPoint none = ShadowPoint(vec3(0.0), vec3(0.0), false);
    return shade_lights(position, normal, eye, material_index, parameter, LIGHTS_SPLIT, none, classes, apart);
}

#endif
