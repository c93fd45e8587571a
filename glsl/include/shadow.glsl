// Shadow-map visibility V_k(x) in [0, 1] of one light at a surface point: the share of the
// filter kernel's texels around the point's image whose stored depth is not nearer to the light
// than the point (percentage-closer filtering; one texel: a hard shadow). The maps lie in
// shadow_atlas (a directional light's orthographic map, a point light's six cube faces), laid
// out and rendered once by the host (src/geometry/shadow_view.rs, src/render/shadows.rs).
//
// The bound does not see V (docs/estimator.md section 17): multirate interpolates each
// shadow-casting light's unshadowed shading apart (its slot, GpuLight.shadow.z, in the
// interpolants below) and multiplies it per pixel by the visibility at the same point that
// `pixel` mode looks it up at: the point of the triangle's plane the pixel's centre sees
// (`shadow_point`), computed from the same inputs by the same precise code in every fragment
// stage, so that both read the same V bit for bit.
#ifndef SHADOW_GLSL
#define SHADOW_GLSL
#include "lights.glsl"

// Whether any light casts shadows: without, no shadow code is compiled in.
layout(constant_id = 17) const bool SHADOWS = false;
// Whether the fragment stage may look a visibility up: false in the draws of the flat and the
// interpolated patches that no light reaches only in part (DRAWN_SHADOW_CLASSES, bindings.glsl),
// whose fragment stage then holds no lookup code. llvmpipe runs both sides of every branch under a
// mask, so the lookups cost every fragment of a draw that contains them, needed or not.
layout(constant_id = 18) const bool SHADOW_LOOKUPS = true;
// How many point and directional lights cast shadows: in `lights`, the first point lights and
// the first directional ones (src/render/scene_geometry.rs, ShaderLights), their slots in that
// order. So whether a light casts shadows and its slot are constants wherever its index is (an
// unrolled loop's): no light's record is read to know them, and no array is indexed by a
// loaded value (which llvmpipe spills to memory per lane).
layout(constant_id = 20) const int SHADOWED_POINT_LIGHTS = 0;
layout(constant_id = 21) const int SHADOWED_DIRECTIONAL_LIGHTS = 0;

// Whether light `i` of `lights` casts shadows.
bool casts_shadows(int i) {
    return SHADOWS && (i < SHADOWED_POINT_LIGHTS
                       || (i >= POINT_LIGHT_COUNT && i < POINT_LIGHT_COUNT + SHADOWED_DIRECTIONAL_LIGHTS));
}

// The slot of light `i` of `lights`, where it casts shadows.
int shadow_slot(int i) {
    return i < POINT_LIGHT_COUNT ? i : SHADOWED_POINT_LIGHTS + i - POINT_LIGHT_COUNT;
}

// The index in `lights` of the light in slot `slot`.
int slot_light(int slot) {
    return slot < SHADOWED_POINT_LIGHTS ? slot : POINT_LIGHT_COUNT + slot - SHADOWED_POINT_LIGHTS;
}

// A triangle's visibility classes as its estimate reads them (docs/estimator.md section 18):
// those of scene triangle `triangle` (triangle_shadow_classes), none without shadows (nothing
// read then).
uint estimated_classes(uint triangle) {
    return SHADOWS ? triangle_shadow_classes(triangle) : 0u;
}

// Whether light `i` of `lights` reaches none of a triangle of visibility classes `classes`: its
// shading there is zero, drawn as the class says, so its interpolation error is zero too, and the
// estimate leaves it out.
bool shadowed_in(int i, uint classes) {
    return casts_shadows(i) && (classes & (SHADOWED_CLASS_BIT << uint(shadow_slot(i)))) != 0u;
}

// How many lights reach none of a triangle of visibility classes `classes`.
int shadowed_count(uint classes) {
    return bitCount(classes & (MIXED_CLASS_BIT - 1u));
}

// The kernel's texels reach this far (in texels) beyond the point's own texel, plus rounding;
// the lookup point is pushed off the surface by as much, times the sine of the angle between
// the normal and the light, so that a plane never shadows itself (acne), while the offset
// stays within a few texels (no visible gap between a caster and its shadow).
const float SHADOW_TEXEL_SLACK = 1.5;

// Where a fragment looks its shadows up: a point of its triangle's plane and the plane's unit
// normal; not `valid` where the pixel's ray runs along the plane (its lights are then unshadowed).
struct ShadowPoint {
    vec3 position;
    vec3 normal;
    bool valid;
};

// The point of scene triangle `triangle`'s plane that the ray through the pixel centre
// `frag_coord` (gl_FragCoord.xy) meets: x with view_proj·x at that pixel, and n·x = n·a. Solved
// by Cramer's rule from the triangle's corners (triangle_corners) and the draw's view-projection:
// the same inputs in every pass that draws the triangle.
ShadowPoint shadow_point(uint triangle, vec2 frag_coord) {
    precise vec3 a = triangle_corner(triangle, 0u);
    precise vec3 b = triangle_corner(triangle, 1u);
    precise vec3 c = triangle_corner(triangle, 2u);
    precise vec3 n = cross(b - a, c - a);
    precise float d = dot(n, a);
    precise vec2 ndc = frag_coord / draw.viewport_size * 2.0 - 1.0;
    mat4 m = draw.view_proj;
    precise vec4 row_x = vec4(m[0][0], m[1][0], m[2][0], m[3][0]) - ndc.x * vec4(m[0][3], m[1][3], m[2][3], m[3][3]);
    precise vec4 row_y = vec4(m[0][1], m[1][1], m[2][1], m[3][1]) - ndc.y * vec4(m[0][3], m[1][3], m[2][3], m[3][3]);
    precise vec3 yz = cross(row_y.xyz, n);
    precise vec3 zx = cross(n, row_x.xyz);
    precise vec3 xy = cross(row_x.xyz, row_y.xyz);
    precise float det = dot(row_x.xyz, yz);
    precise vec3 position = (-row_x.w * yz - row_y.w * zx + d * xy) / det;
    float length_n = length(n);
    bool valid = abs(det) > 0.0 && length_n > 0.0 && all(lessThan(abs(position), vec3(3.0e38)));
    return ShadowPoint(position, valid ? n / length_n : vec3(0.0), valid);
}

// The unit direction from `position` towards `light` (a point light where `point_light`).
vec3 towards_light(GpuLight light, bool point_light, vec3 position) {
    if (point_light) {
        vec3 to_light = light.position.xyz - position;
        float d2 = max(dot(to_light, to_light), 1.0e-8);
        return to_light * inversesqrt(d2);
    }
    return -light.position.xyz;
}

// One shadow map in the atlas (src/gpu_types.rs, GpuShadowMap; six texels of shadow_maps): a
// directional light's square, or a point light's six square faces in a block of 3 x 2 (face f
// at (f mod 3, f div 3) sides from its first texel). Read as texels: on lavapipe a storage
// buffer load at an index that itself was loaded is a loop over the lanes for every word, and
// the map's 24 words cost more than the rest of a fragment's shading.
struct ShadowMapRecord {
    vec4 rect;   // xy: first texel in the atlas; z: side in texels; w: a texel's world width
                 // (a cube face: per unit of distance along its axis)
    vec4 depth;  // a cube: x near, y far along the faces' axes, z 1; directional: z 0
};

ShadowMapRecord shadow_map(int index) {
    return ShadowMapRecord(texelFetch(shadow_maps, 6 * index + 4), texelFetch(shadow_maps, 6 * index + 5));
}

// A directional light's map: world to its clip space (depth 0 to 1).
mat4 shadow_map_view_proj(int index) {
    int t = 6 * index;
    return mat4(texelFetch(shadow_maps, t), texelFetch(shadow_maps, t + 1), texelFetch(shadow_maps, t + 2),
                texelFetch(shadow_maps, t + 3));
}

// Where `lookup` falls in the cube face of a point light at `light` that looks along `axis` (a
// unit axis vector, either sign), its depths `near`..`far` along the axis: its position in the
// face's clip space, divided through. The face's map's x and y directions are
// src/geometry/shadow_view.rs's `face_basis`; the depth maps as its `perspective` does, so the
// lookup compares with what the shadow pass rasterised. (No component is indexed by a
// variable: llvmpipe would spill the vector to memory per lane.)
vec3 cube_face_ndc(vec3 lookup, vec3 light, vec3 axis, float near, float far) {
    vec3 up = axis.y != 0.0 ? vec3(0.0, 0.0, 1.0) : vec3(0.0, 1.0, 0.0);
    vec3 side = cross(axis, up);
    vec3 image_up = cross(side, axis);
    vec3 d = lookup - light;
    float along = dot(axis, d);
    return vec3(dot(side, d), -dot(image_up, d), far * (along - near) / (far - near)) / along;
}

// The visibility of light `light`, light `i` of `lights`, at `position`, on a surface of unit
// normal `normal` (either side). 1 where the light casts no shadow.
float shadow_visibility(GpuLight light, int i, vec3 position, vec3 normal) {
    if (!casts_shadows(i)) {
        return 1.0;
    }
    int index = light.shadow.x;
    ShadowMapRecord map = shadow_map(index);
    // A point light's map is a cube, a directional light's a square (ShadowLayout).
    bool cube = i < POINT_LIGHT_COUNT;
    vec3 l = towards_light(light, cube, position);
    int radius = light.shadow.y;
    float texel = map.rect.w;
    // A cube's face: that of the largest component of the light-to-point vector, at
    // (face mod 3, face div 3) sides from the map's first texel.
    vec3 d = position - light.position.xyz;
    vec3 a = abs(d);
    bool x_major = a.x >= a.y && a.x >= a.z;
    bool y_major = !x_major && a.y >= a.z;
    vec3 major = x_major ? vec3(1.0, 0.0, 0.0) : (y_major ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0));
    float signed_along = dot(d, major);
    vec3 axis = signed_along < 0.0 ? -major : major;
    int face = (x_major ? 0 : (y_major ? 2 : 4)) + (signed_along < 0.0 ? 1 : 0);
    if (cube) {
        texel *= abs(signed_along);
    } else {
        face = 0;
    }
    // The normal of the side the light is on: the lift goes towards the light.
    float cos_theta = clamp(dot(normal, l), -1.0, 1.0);
    vec3 n = cos_theta < 0.0 ? -normal : normal;
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    float lift = (float(radius) + SHADOW_TEXEL_SLACK) * texel;
    vec3 lookup = position + n * (lift * sin_theta) + l * (0.5 * texel);
    vec3 ndc;
    if (cube) {
        ndc = cube_face_ndc(lookup, light.position.xyz, axis, map.depth.x, map.depth.y);
    } else {
        vec4 clip = shadow_map_view_proj(index) * vec4(lookup, 1.0);
        ndc = clip.xyz / clip.w;
    }
    int size = int(map.rect.z);
    ivec2 origin = ivec2(map.rect.xy) + ivec2(face % 3, face / 3) * size;
    ivec2 centre = ivec2(floor((ndc.xy * 0.5 + 0.5) * map.rect.z));
    int lit = 0;
    for (int y = -radius; y <= radius; ++y) {
        for (int x = -radius; x <= radius; ++x) {
            ivec2 texel_at = clamp(centre + ivec2(x, y), ivec2(0), ivec2(size - 1));
            float stored = texelFetch(shadow_atlas, origin + texel_at, 0).r;
            lit += ndc.z <= stored ? 1 : 0;
        }
    }
    int side = 2 * radius + 1;
    return float(lit) / float(side * side);
}

// The visibility of light `light`, light `i` of `lights`, at the fragment's shadow point (1
// where it is not valid).
float shadow_visibility_at(GpuLight light, int i, ShadowPoint point) {
    return point.valid ? shadow_visibility(light, i, point.position, point.normal) : 1.0;
}

// What the multirate interpolants carry per shadow-casting light, by its slot: its unshadowed
// diffuse and specular shading (the diffuse part is multiplied by the albedo map per pixel).
// Locations after TRIANGLE_ID_LOCATION (bindings.glsl), in the evaluation stage, the flat
// patches' vertex stage and the fragment stages that read them.
#define SHADOWED_DIFFUSE_LOCATION 7
#define SHADOWED_SPECULAR_LOCATION 11

// The shadow-casting lights' part of the colour of a fragment at `frag_coord` on scene triangle
// `triangle`, by the triangle's visibility classes (triangle_shadow_classes): each light's
// interpolated unshadowed shading (`diffuse`, `specular` by slot) as it is where the light
// reaches all of the triangle, times its visibility at the fragment's shadow point where it may
// reach part of it, nothing where it reaches none. Only a part-lit triangle looks anything up.
// (Where the stage before applied the class, a slot it left zero adds zero.) Without lookups
// (SHADOW_LOOKUPS false: the draws of the patches no light reaches only in part, whose stage
// before applied their class: a lit light is in the sum, a shadowed one nowhere) every slot is
// zero: nothing to add, nothing read.
vec3 shadowed_lights_color(vec3 albedo, vec3 diffuse[MAX_SHADOWED_LIGHTS], vec3 specular[MAX_SHADOWED_LIGHTS],
                           uint triangle, vec2 frag_coord) {
    vec3 color = vec3(0.0);
    if (!SHADOWS || !SHADOW_LOOKUPS) {
        return color;
    }
    uint classes = triangle_shadow_classes(triangle);
    ShadowPoint point = ShadowPoint(vec3(0.0), vec3(0.0), false);
    if (classes >= MIXED_CLASS_BIT) {
        point = shadow_point(triangle, frag_coord);
    }
    for (int slot = 0; slot < SHADOWED_POINT_LIGHTS + SHADOWED_DIRECTIONAL_LIGHTS; ++slot) {
        uint slot_bit = 1u << uint(slot);
        if ((classes & SHADOWED_CLASS_BIT * slot_bit) != 0u) {
            continue;
        }
        int i = slot_light(slot);
        bool mixed = (classes & MIXED_CLASS_BIT * slot_bit) != 0u;
        float visibility = mixed ? shadow_visibility_at(lights[i], i, point) : 1.0;
        color += visibility * (albedo * diffuse[slot] + specular[slot]);
    }
    return color;
}

#endif
