// The level of one triangle of the multirate pass, wherever it is computed: in the control stage
// (`--estimator tcs`, multirate.tesc) or in the compute pre-pass (`--estimator compute`,
// triangle_levels.comp). Both run this same code, so both give the same levels.
//
// A triangle that cannot be seen is culled before the estimator runs: it lies wholly outside
// one plane of the view frustum, its image is a segment (degenerate_image), or it faces away
// from the eye on a one-sided mesh. Its level is
// CULLED_LEVEL, and the control stage gives its patch outer level 0. A back face of a two-sided
// mesh, and a triangle the range class does not settle whose image is too small to pay for its
// estimate, are not estimated either: they are shaded per pixel (back_face_per_pixel,
// small_per_pixel, visible_level). Rust twin of both: `src/geometry/cull.rs` (bit-identical:
// `precise`, no fused multiply-adds).
#ifndef TRIANGLE_LEVEL_GLSL
#define TRIANGLE_LEVEL_GLSL
#include "estimator.glsl"
#include "level_hold.glsl"
#if VARIANT_TEXTURED
#include "texture_bounds.glsl"
#endif

// The level of a culled triangle: below every real level, so a culled neighbour asks its
// neighbours for nothing (uniform_level gives 1).
const float CULLED_LEVEL = -1.0;
const vec4 CULLED_RECORD = vec4(CULLED_LEVEL, 0.0, 0.0, 0.0);
// Back faces are culled here only when the eye is more than this sine away from their plane;
// the rasteriser culls the nearly edge-on rest, so culling never differs from `pixel` mode.
const float BACKFACE_MARGIN_SQUARED = 1.0e-6;
// The sine below which a triangle's image counts as a segment (degenerate_image): 2⁻¹⁸, some 64
// times the relative rounding of a float area, so that the image of a triangle that is not
// culled has an area that rounds to a number of the right sign.
const float DEGENERATE_IMAGE_SINE = 3.814697265625e-6;

// Clip-space position of world point p, summed in a fixed order (`cull::clip_of` in Rust).
P vec4 clip_of(vec3 p) {
    P vec4 c = ((draw.view_proj[0] * p.x + draw.view_proj[1] * p.y) + draw.view_proj[2] * p.z)
        + draw.view_proj[3];
    return c;
}

// Whether the eye lies clearly behind the triangle's plane (`cull::faces_away` in Rust).
bool faces_away(vec3 p0, vec3 p1, vec3 p2) {
    // Front faces wind anticlockwise: their normal (p1 − p0) × (p2 − p0) points to the eye.
    P vec3 normal = cross3(p1 - p0, p2 - p0);
    P vec3 to_eye = draw.eye.xyz - p0;
    P float facing = dot3(normal, to_eye);
    P float margin = BACKFACE_MARGIN_SQUARED * len2(normal) * len2(to_eye);
    return facing < 0.0 && facing * facing > margin;
}

// The image edge from the corner at clip position a to the one at b, times a.w·b.w
// (`cull::scaled_edge` in Rust): b.xy/b.w − a.xy/a.w without a division.
P vec2 scaled_edge(vec4 a, vec4 b) {
    P vec2 edge = b.xy * a.w - a.xy * b.w;
    return edge;
}

// Twice the signed area of the image of the triangle at clip positions a, b, c, times
// a.w·b.w·c.w: the determinant of the rows (x, y, w) (`cull::image_determinant` in Rust).
P float image_determinant(vec4 a, vec4 b, vec4 c) {
    P float det = (a.x * (b.y * c.w - c.y * b.w) - b.x * (a.y * c.w - c.y * a.w))
        + c.x * (a.y * b.w - b.y * a.w);
    return det;
}

// |v.x| + |v.y|, a norm between |v| and √2·|v| that needs no square root.
P float norm1(vec2 v) {
    P float n = abs(v.x) + abs(v.y);
    return n;
}

// Whether the triangle's image, in front of the eye, is a segment or a point to floating-point
// precision (`cull::degenerate_image` in Rust): twice its area is at most
// DEGENERATE_IMAGE_SINE times the product of two of its edges at one corner (measured in |·|₁).
// The rasteriser can still cover a sample of such an image (from its snapped corners) while
// its interpolation, from the float corners, divides by an area that rounded to zero: not a
// number at every attribute. Such a triangle shows no surface; `pixel` mode shows at most
// single pixels of it.
bool degenerate_image(vec4 a, vec4 b, vec4 c) {
    if (!(a.w > 0.0 && b.w > 0.0 && c.w > 0.0)) {
        return false;
    }
    P float size = abs(image_determinant(a, b, c));
    P vec2 ab = scaled_edge(a, b);
    P vec2 bc = scaled_edge(b, c);
    P vec2 ca = scaled_edge(c, a);
    // At corner a the edges are ab/(a.w·b.w) and ca/(c.w·a.w): the area over their product,
    // times a.w·b.w·c.w, is size·a.w over |ab|·|ca|; likewise at b and c.
    P float at_a = DEGENERATE_IMAGE_SINE * (norm1(ab) * norm1(ca));
    P float at_b = DEGENERATE_IMAGE_SINE * (norm1(bc) * norm1(ab));
    P float at_c = DEGENERATE_IMAGE_SINE * (norm1(ca) * norm1(bc));
    P float size_a = size * a.w;
    P float size_b = size * b.w;
    P float size_c = size * c.w;
    return size_a <= at_a || size_b <= at_b || size_c <= at_c;
}

// Whether no point of the triangle can be visible (`cull::culled` in Rust).
bool patch_culled(vec3 p0, vec3 p1, vec3 p2) {
    P vec4 a = clip_of(p0);
    P vec4 b = clip_of(p1);
    P vec4 c = clip_of(p2);
    // Clip coordinates are linear in the position, so a triangle whose three corners are
    // outside one half-space lies wholly outside it.
    if ((a.x > a.w && b.x > b.w && c.x > c.w) || (a.x < -a.w && b.x < -b.w && c.x < -c.w)
        || (a.y > a.w && b.y > b.w && c.y > c.w) || (a.y < -a.w && b.y < -b.w && c.y < -c.w)
        || (a.z > a.w && b.z > b.w && c.z > c.w) || (a.z < 0.0 && b.z < 0.0 && c.z < 0.0)) {
        return true;
    }
    if (degenerate_image(a, b, c)) {
        return true;
    }
    return (draw.flags & FLAG_ONE_SIDED) != 0u && faces_away(p0, p1, p2);
}

// The coarsest level of detail at which the evaluation stage samples the parameter map on the
// triangle with texture coordinates a, b, c: log2 of its texel extent (at least 0). Rust twin:
// `ParameterMap::lod_bound` in src/scene/mod.rs.
float lod_bound_of(vec2 a, vec2 b, vec2 c, vec2 size) {
    P vec2 extent = (max(max(a, b), c) - min(min(a, b), c)) * size;
    return est_log2(rmax(rmax(extent.x, extent.y), 1.0));
}

// The parameter map's level-of-detail bound of the draw's material on the triangle (0 without
// a parameter map).
float material_lod_bound(vec2 a, vec2 b, vec2 c) {
#if VARIANT_TEXTURED
    GpuMaterial m = materials[draw.material_index];
    if (m.maps.y >= 0) {
        return lod_bound_of(a, b, c, vec2(textureSize(parameter_map, 0)));
    }
#endif
    return 0.0;
}

// The range of the material's shininess or roughness over the triangle's texels (seed 003
// Sec. 3.5), from the min/max pyramid; the material's own value without a map.
// `bound`: the triangle's lod_bound_of.
vec2 parameter_range_of(GpuMaterial m, vec2 p, vec2 q, vec2 r, float bound) {
#if VARIANT_TEXTURED
    if (m.maps.y >= 0) {
        vec2 u = parameter_bounds(min(min(p, q), r), max(max(p, q), r), bound);
        P float lo = m.parameter_range.x;
        P float hi = m.parameter_range.y;
        P float a;
        P float b;
        if (m.maps.w == 1) {
            a = lo * est_pow(hi / lo, u.x);
            b = lo * est_pow(hi / lo, u.y);
        } else {
            a = lo + (hi - lo) * u.x;
            b = lo + (hi - lo) * u.y;
        }
        return vec2(a, b);
    }
#endif
    return vec2(m.params.x);
}

// The parameter range of the draw's material over the triangle with texture coordinates t.
vec2 draw_parameter_range(vec2 t0, vec2 t1, vec2 t2) {
    GpuMaterial material = materials[draw.material_index];
    return parameter_range_of(material, t0, t1, t2, material_lod_bound(t0, t1, t2));
}

// The eye the draw's estimates are for, and the radius of the ball of eyes they hold for.
vec4 estimator_eye() {
    return vec4(draw.eye.xyz, draw.eye_radius);
}

// Whether the range class settles the draw's triangle (estimator/range.glsl): level 1 without
// an estimate; `every_capped`: whether its estimate bounds every light's specular part by its cap.
// `classes`, here and below: the triangle's visibility classes (shadow.glsl, estimated_classes),
// by which the lights that reach none of it are left out.
bool settled_triangle(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec2 t0, vec2 t1, vec2 t2,
                      uint classes, out bool every_capped) {
    return settled_by_range(p0, p1, p2, n0, n1, n2, estimator_eye(), draw.material_index,
                            draw_parameter_range(t0, t1, t2), draw.epsilon, classes, every_capped);
}

// The estimator's level of the draw's triangle (positions p, normals n, texture coordinates t),
// not culled and not settled by the range class: >= 1, or FALLBACK_LEVEL for per-pixel shading.
// `every_capped`: settled_triangle's.
float estimated_level(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec2 t0, vec2 t1, vec2 t2,
                      uint classes, bool every_capped) {
    return required_level(p0, p1, p2, n0, n1, n2, estimator_eye(), draw.material_index,
                          draw_parameter_range(t0, t1, t2), draw.epsilon, float(draw.n_max), every_capped, classes);
}

// One of the two passes of estimated_level (estimate_pass): the compute pre-pass runs the
// second, with `refine`, as a step of its own over the triangles the first lists.
float estimated_level_pass(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec2 t0, vec2 t1, vec2 t2,
                           uint classes, bool every_capped, bool refine, out bool refine_next) {
    return estimate_pass(p0, p1, p2, n0, n1, n2, estimator_eye(), draw.material_index,
                         draw_parameter_range(t0, t1, t2), draw.epsilon, float(draw.n_max), every_capped, refine,
                         classes, refine_next);
}

// Whether the image of the triangle at clip positions a, b, c, all in front of the eye, covers
// fewer than draw.min_estimated_area pixels (`cull::small_image` in Rust). Its area in pixels
// is |det| / (a.w·b.w·c.w) · width·height/8 (the image spans 2 units of normalised device
// coordinates per viewport side); the area of the whole triangle bounds that of its visible
// part from above. A triangle with a corner at or behind the eye's plane is never small.
bool small_image(vec4 a, vec4 b, vec4 c) {
    if (!(a.w > 0.0 && b.w > 0.0 && c.w > 0.0)) {
        return false;
    }
    P float pixels = abs(image_determinant(a, b, c)) * (0.125 * (draw.viewport_size.x * draw.viewport_size.y));
    P float least = draw.min_estimated_area * ((a.w * b.w) * c.w);
    return pixels < least;
}

// Whether the draw's triangle, not culled, is a back face shaded per pixel
// (`cull::back_face_per_pixel` in Rust): a back face of a two-sided mesh. Such a triangle is shaded
// per pixel by the mesh's back-face draw (`pixel` mode's pipeline, front faces culled), which
// comes after the front faces, so that where they hide it (the far side of an open mesh) the
// early depth test rejects its fragments before they shade; interpolated, its sub-vertices would
// all be shaded. It asks its neighbours for no level on their shared edges (patch_levels).
bool back_face_per_pixel(vec3 p0, vec3 p1, vec3 p2) {
    return (draw.flags & FLAG_ONE_SIDED) == 0u && faces_away(p0, p1, p2);
}

// Whether the draw's triangle, not culled and not settled by the range class, is shaded per
// pixel without an estimate because its image is too small to pay for one
// (`cull::small_per_pixel` in Rust): a small_image, whose estimate would cost more than shading
// its few pixels (the cost model, `src/render/cost_model.rs`, sets draw.min_estimated_area; 0
// estimates every triangle). The range class costs a fraction of an estimate, so it runs first.
bool small_per_pixel(vec3 p0, vec3 p1, vec3 p2) {
    return draw.min_estimated_area > 0.0 && small_image(clip_of(p0), clip_of(p1), clip_of(p2));
}

// The level of the draw's triangle that is not culled, in this order: FALLBACK_LEVEL for a
// back_face_per_pixel, 1 where the range class settles it, FALLBACK_LEVEL for a small_per_pixel,
// else its estimated_level (`analysis::report`'s `level_of` in Rust). The compute pre-pass takes
// the same steps apart: cull_triangles.comp, range_levels.comp, triangle_levels.comp.
float visible_level(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec2 t0, vec2 t1, vec2 t2,
                    uint classes) {
    if (back_face_per_pixel(p0, p1, p2)) {
        return FALLBACK_LEVEL;
    }
    bool every_capped;
    if (settled_triangle(p0, p1, p2, n0, n1, n2, t0, t1, t2, classes, every_capped)) {
        return 1.0;
    }
    if (small_per_pixel(p0, p1, p2)) {
        return FALLBACK_LEVEL;
    }
    return estimated_level(p0, p1, p2, n0, n1, n2, t0, t1, t2, classes, every_capped);
}

// The level of the draw's triangle: CULLED_LEVEL, or its visible_level.
float triangle_level(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec2 t0, vec2 t1, vec2 t2,
                     uint classes) {
    if (patch_culled(p0, p1, p2)) {
        return CULLED_LEVEL;
    }
    return visible_level(p0, p1, p2, n0, n1, n2, t0, t1, t2, classes);
}

#endif
