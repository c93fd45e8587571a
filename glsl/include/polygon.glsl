// Polygonal area lights seen from one shading point (C. Peters, "BRDF Importance Sampling for
// Polygonal Lights", ACM TOG 40(4), 2021): clipping to the horizon, the closed-form projected
// solid angle, projected-solid-angle sampling, solid-angle sampling of triangle fans, clamped
// optimal MIS weights and a fixed low-discrepancy point set.
// Rust twin: `src/shading/polygon.rs`, whose header documents the methods and the deviations from
// the paper. Keep the two in step, function for function and operation for operation:
// `tests/polygon_gpu.rs` runs `polygon_check.comp` and compares with the twin.
//
// Directions live in the local shading frame (shading normal +z); a polygon is given by its
// vertices relative to the shading point (convex, planar, either winding).
//
// Rounding: Rust rounds every operation separately and fuses only where it calls `mul_add`, here
// `fused_multiply_add` (GLSL's fma() need not fuse). Every function that does arithmetic is
// `precise`, so that the compiler neither contracts a * b + c into an fma nor reassociates;
// vector lengths and dot products are spelled out in glam's order. Vulkan allows polygon_atan2() an error
// of 4096 ulps, far too much for small polygons (whose solid angles are atan2 of small ratios),
// so `polygon_atan2` is a polynomial accurate to a few ulps.
#ifndef POLYGON_GLSL
#define POLYGON_GLSL

// Most vertices a light polygon may have.
const int MAX_POLYGON_VERTICES = 8;
// Most vertices a polygon clipped to the horizon may have.
const int MAX_CLIPPED_VERTICES = MAX_POLYGON_VERTICES + 1;
// Most triangles in the fan of a clipped polygon.
const int MAX_FAN_TRIANGLES = MAX_CLIPPED_VERTICES - 2;
// The visibility estimate v of clamped optimal MIS that the paper uses throughout (B.3).
const float DEFAULT_MIS_VISIBILITY = 0.5;
// f32::EPSILON and f32::MIN_POSITIVE.
const float POLYGON_EPSILON = 1.1920929e-7;
const float POLYGON_MIN_POSITIVE = 1.17549435e-38;
// A (projected) solid angle below this fraction of its terms' magnitude counts as zero.
const float EMPTY_RELATIVE_THRESHOLD = 32.0 * POLYGON_EPSILON;
// Directions this close (radians) outside an edge's great circle still count as inside.
const float INSIDE_TOLERANCE = 4.0 * POLYGON_EPSILON;
// Algorithm 3 skips the iteration this close to the ends of the sector.
const float ITERATION_MARGIN = 1.0e-5;
// |u|^2 above which an ellipse counts as nearly degenerate in the decentral case.
const float STEEP_ELLIPSE_SQUARED = 1.0e6;
// Iterations of Algorithm 3.
const int ITERATION_COUNT = 2;

// A convex planar polygon: only the first `count` vertices are meaningful; 0 means empty.
struct Polygon {
    vec3 vertices[MAX_CLIPPED_VERTICES];
    int count;
};

// Everything projected-solid-angle sampling needs (the first half of Algorithm 4).
struct ProjectedSolidAngleSampler {
    int count;                                   // 0 when there is nothing to sample
    vec3 vertices[MAX_CLIPPED_VERTICES];         // counterclockwise about +z
    vec2 sector_dirs[MAX_CLIPPED_VERTICES];      // sector boundary directions
    vec2 ellipses[MAX_CLIPPED_VERTICES];         // per boundary the next edge's ellipse
    vec2 inner_ellipse_0;                        // inner ellipse of the first sector, or (1, 0)
    float sector_areas[MAX_CLIPPED_VERTICES];    // projected solid angle per sector
    float sector_total;                          // sum of sector_areas
    bool proxy_sector_areas;                     // sector_areas hold angles instead
    float projected_solid_angle;                 // the closed form (normalises the density)
};

// Everything solid-angle sampling needs: the polygon as a triangle fan around vertex 0.
struct SolidAngleSampler {
    int count;                                   // 0 when there is nothing to sample
    vec3 directions[MAX_CLIPPED_VERTICES];       // unit directions to the vertices
    vec3 triangles[MAX_FAN_TRIANGLES];           // (G0, G1, G2) of Algorithm 5 per triangle
    float fan_solid_angles[MAX_FAN_TRIANGLES];   // solid angle of the fan up to triangle j
    float solid_angle;                           // total
    float orientation;                           // +-1 such that edges' normals point inwards
};

Polygon polygon_empty() {
    Polygon polygon;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        polygon.vertices[j] = vec3(0.0);
    }
    polygon.count = 0;
    return polygon;
}

ProjectedSolidAngleSampler projected_solid_angle_sampler_empty() {
    ProjectedSolidAngleSampler state;
    state.count = 0;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        state.vertices[j] = vec3(0.0);
        state.sector_dirs[j] = vec2(0.0);
        state.ellipses[j] = vec2(0.0);
        state.sector_areas[j] = 0.0;
    }
    state.inner_ellipse_0 = vec2(1.0, 0.0);
    state.sector_total = 0.0;
    state.proxy_sector_areas = false;
    state.projected_solid_angle = 0.0;
    return state;
}

SolidAngleSampler solid_angle_sampler_empty() {
    SolidAngleSampler state;
    state.count = 0;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        state.directions[j] = vec3(0.0);
    }
    for (int j = 0; j < MAX_FAN_TRIANGLES; ++j) {
        state.triangles[j] = vec3(0.0);
        state.fan_solid_angles[j] = 0.0;
    }
    state.solid_angle = 0.0;
    state.orientation = 1.0;
    return state;
}

// Index of the vertex after j in a polygon with `count` vertices.
int next_index(int j, int count) {
    return j + 1 == count ? 0 : j + 1;
}

// +infinity.
float polygon_infinity() {
    return uintBitsToFloat(0x7f800000u);
}

// Whether x is neither infinite nor NaN.
bool polygon_is_finite(float x) {
    return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u;
}

// Whether the sign bit of x is set (also for -0).
bool polygon_sign_negative(float x) {
    return (floatBitsToUint(x) & 0x80000000u) != 0u;
}

// |magnitude| with the sign of `sign` (Rust's copysign).
float polygon_copysign(float magnitude, float sign) {
    return uintBitsToFloat((floatBitsToUint(magnitude) & 0x7fffffffu) | (floatBitsToUint(sign) & 0x80000000u));
}

// glam's dot products, lengths and normalisation, in its order of operations.
precise float dot2(vec2 a, vec2 b) {
    return a.x * b.x + a.y * b.y;
}

precise float polygon_dot3(vec3 a, vec3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

precise float length2(vec2 v) {
    return sqrt(dot2(v, v));
}

precise float length3(vec3 v) {
    return sqrt(polygon_dot3(v, v));
}

precise vec2 normalize2(vec2 v) {
    return v * (1.0 / length2(v));
}

precise vec3 normalize3(vec3 v) {
    return v * (1.0 / length3(v));
}

precise vec3 polygon_cross3(vec3 a, vec3 b) {
    return vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// a*b exactly, as the rounded product and its rounding error (Dekker's product with Veltkamp's
// splitting; no overflow for the magnitudes here).
precise vec2 two_product(float a, float b) {
    precise float product = a * b;
    precise float scaled_a = 4097.0 * a;
    precise float a_high = scaled_a - (scaled_a - a);
    precise float a_low = a - a_high;
    precise float scaled_b = 4097.0 * b;
    precise float b_high = scaled_b - (scaled_b - b);
    precise float b_low = b - b_high;
    precise float error = ((a_high * b_high - product) + a_high * b_low + a_low * b_high) + a_low * b_low;
    return vec2(product, error);
}

// a*b + c with (nearly always) a single rounding: Rust's `mul_add`. GLSL's fma() may round the
// product (Vulkan allows it, and lavapipe does), so the exact product of two_product is added
// with Knuth's two-sum.
precise float fused_multiply_add(float a, float b, float c) {
    precise vec2 product = two_product(a, b);
    precise float sum = product.x + c;
    precise float b_virtual = sum - product.x;
    precise float sum_error = (product.x - (sum - b_virtual)) + (c - b_virtual);
    return sum + (sum_error + product.y);
}

// polygon_atan2(t) for 0 <= t <= 1 to a few ulps (Cephes' atanf: reduction by tan(pi/8), odd polynomial).
precise float polygon_atan_unit(float t) {
    precise float offset = 0.0;
    precise float reduced = t;
    if (t > 0.41421356237309503) {
        offset = 0.78539816339744831;
        reduced = (t - 1.0) / (t + 1.0);
    }
    precise float z = reduced * reduced;
    precise float poly = (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z
                          - 3.33329491539e-1) * z * reduced + reduced;
    return offset + poly;
}

// atan2(y, x) (Rust's `f32::atan2`) to a few ulps, relative also for small results; at (+-0, +0)
// it is +-0 and at (+-0, -0) +-pi, like Rust's.
precise float polygon_atan2(float y, float x) {
    precise float abs_y = abs(y);
    precise float abs_x = abs(x);
    precise float angle;
    if (abs_y == 0.0 && abs_x == 0.0) {
        angle = 0.0;
    } else if (abs_y <= abs_x) {
        angle = polygon_atan_unit(abs_y / abs_x);
    } else {
        angle = 1.5707963267948966 - polygon_atan_unit(abs_x / abs_y);
    }
    if (polygon_sign_negative(x)) {
        angle = 3.1415926535897932 - angle;
    }
    return polygon_copysign(angle, y);
}

// a*b - c*d with at most 1.5 ulps of error (Kahan's algorithm with one fma).
precise float kahan(float a, float b, float c, float d) {
    precise float cd = c * d;
    precise float error = fused_multiply_add(c, d, -cd);
    return fused_multiply_add(a, b, -cd) - error;
}

// The cross product with every component evaluated by kahan.
vec3 cross_stable(vec3 a, vec3 b) {
    return vec3(kahan(a.y, b.z, a.z, b.y), kahan(a.z, b.x, a.x, b.z), kahan(a.x, b.y, a.y, b.x));
}

// det(a, b) = a.x b.y - a.y b.x; agrees bit for bit with cross_stable(...).z.
float det2(vec2 a, vec2 b) {
    return kahan(a.x, b.y, a.y, b.x);
}

// v rotated by 90 degrees counterclockwise.
vec2 rotate_90(vec2 v) {
    return vec2(-v.y, v.x);
}

// (1 - t) a + t b with two fmas, exact at both ends (Rust's `mix`).
precise float mix_exact(float a, float b, float t) {
    return fused_multiply_add(t, b, fused_multiply_add(-t, a, a));
}

// a/|a| - b/|b| with a small relative error also when the directions nearly agree.
precise vec3 unit_difference(vec3 a, vec3 b) {
    precise float length_b = length3(b);
    precise float inverse_lengths = 1.0 / (length3(a) * length_b);
    precise vec3 normal = cross_stable(a, b);
    precise float sine = length3(normal) * inverse_lengths;
    precise float cosine = polygon_dot3(a, b) * inverse_lengths;
    precise float one_minus_cosine = cosine > 0.0 ? sine * sine / (1.0 + cosine) : 1.0 - cosine;
    return polygon_cross3(b, normal) * (inverse_lengths / length_b) - b * (one_minus_cosine / length_b);
}

// Clips a convex polygon (3 to MAX_POLYGON_VERTICES vertices) to z >= 0 (supplement A.1).
precise Polygon clip_to_horizon(Polygon polygon) {
    Polygon clipped = polygon_empty();
    int count = polygon.count;
    if (count < 3 || count > MAX_CLIPPED_VERTICES) {
        return clipped;
    }
    int out_count = 0;
    bool overflow = false;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        vec3 a = polygon.vertices[j];
        vec3 b = polygon.vertices[next_index(j, count)];
        if (a.z >= 0.0) {
            if (out_count < MAX_CLIPPED_VERTICES) {
                clipped.vertices[out_count] = a;
                out_count += 1;
            } else {
                overflow = true;
            }
        }
        if ((a.z > 0.0 && b.z < 0.0) || (a.z < 0.0 && b.z > 0.0)) {
            // (p.xy q.z - q.xy p.z) / (q.z - p.z) with p above and q below
            vec3 p = a.z > 0.0 ? a : b;
            vec3 q = a.z > 0.0 ? b : a;
            precise float inverse_height = 1.0 / (q.z - p.z);
            precise vec3 crossing = vec3(kahan(p.x, q.z, q.x, p.z) * inverse_height,
                                         kahan(p.y, q.z, q.y, p.z) * inverse_height, 0.0);
            if (out_count < MAX_CLIPPED_VERTICES) {
                clipped.vertices[out_count] = crossing;
                out_count += 1;
            } else {
                overflow = true;
            }
        }
    }
    clipped.count = out_count >= 3 && !overflow ? out_count : 0;
    return clipped;
}

// (gamma / sin gamma - 1) c.z for an edge with c = v_j x v_j+1 (|c| = sin gamma) and cos gamma.
precise float edge_segment_term(vec3 c, float cos_angle) {
    precise float sine = length3(c);
    precise float angle = polygon_atan2(sine, cos_angle);
    if (angle < 0.5) {
        // x/sin x - 1 = x^2/6 + 7x^4/360 + 31x^6/15120 + 127x^8/604800 + 73x^10/3421440 + O(x^12)
        precise float x2 = angle * angle;
        precise float series = x2
            * (1.0 / 6.0
               + x2 * (7.0 / 360.0
                       + x2 * (31.0 / 15120.0 + x2 * (127.0 / 604800.0 + x2 * (73.0 / 3421440.0)))));
        return series * c.z;
    } else if (sine > 0.0) {
        return angle * (c.z / sine) - c.z;
    }
    return 0.0;
}

// The signed projected solid angle (positive iff counterclockwise about +z) of a polygon on or
// above the horizon; 0 for an empty or degenerate one.
precise float signed_projected_solid_angle(Polygon polygon) {
    int count = polygon.count;
    if (count < 3) {
        return 0.0;
    }
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        if (all(equal(polygon.vertices[j], vec3(0.0)))) {
            return 0.0;
        }
    }
    vec3 origin = polygon.vertices[0];
    precise float fan = 0.0;
    precise float segments = 0.0;
    precise float magnitude = 0.0;
    precise vec3 previous_offset = vec3(0.0);
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        vec3 a = polygon.vertices[j];
        vec3 b = polygon.vertices[next_index(j, count)];
        // Shoelace term of the projected unit directions, relative to direction 0
        precise vec3 offset = unit_difference(b, origin);
        precise float shoelace = kahan(previous_offset.x, offset.y, previous_offset.y, offset.x);
        previous_offset = offset;
        // Curved part of the edge
        precise vec3 edge = unit_difference(b, a);
        precise vec3 c = cross_stable(normalize3(a), edge);
        precise float segment = edge_segment_term(c, 1.0 - 0.5 * polygon_dot3(edge, edge));
        fan += shoelace;
        segments += segment;
        magnitude += abs(shoelace) + abs(segment);
    }
    precise float total = 0.5 * (fan + segments);
    return abs(total) > 0.5 * EMPTY_RELATIVE_THRESHOLD * magnitude ? total : 0.0;
}

// The projected solid angle of a polygon clipped to the horizon, in closed form.
float projected_solid_angle(Polygon clipped) {
    return abs(signed_projected_solid_angle(clipped));
}

// A density with respect to projected solid angle as one with respect to solid angle.
precise float projected_to_solid_angle_density(float projected_density, vec3 direction) {
    return projected_density * max(direction.z, 0.0);
}

// Algorithm 1: the ellipse u (C = I + u u^T) of the great circle through a and b; the sign bit
// of u.x is set iff the edge runs clockwise about the zenith; (inf, 0) when degenerate.
precise vec2 ellipse_from_edge(vec3 a, vec3 b) {
    precise vec3 normal = cross_stable(a, b);
    precise float scaling = polygon_copysign(1.0, normal.x) / normal.z;
    if (normal.z == 0.0 || !polygon_is_finite(scaling)) {
        return vec2(polygon_infinity(), 0.0);
    }
    return vec2(normal.x * scaling, normal.y * scaling);
}

// Whether an ellipse is an inner one (reads the sign bit).
bool is_inner(vec2 ellipse) {
    return polygon_sign_negative(ellipse.x);
}

// Whether an ellipse is degenerate (A.2).
bool is_degenerate(vec2 ellipse) {
    return ellipse.x == polygon_infinity();
}

// C p = p + u (u.p).
precise vec2 ellipse_transform(vec2 ellipse, vec2 point) {
    return point + ellipse * dot2(ellipse, point);
}

// p^T C p = |p|^2 + (u.p)^2.
precise float ellipse_quadratic_form(vec2 ellipse, vec2 point) {
    precise float along = dot2(ellipse, point);
    return fused_multiply_add(along, along, dot2(point, point));
}

// 1/sqrt(det C); 0 for degenerate ellipses.
precise float ellipse_rsqrt_det(vec2 ellipse) {
    if (is_degenerate(ellipse)) {
        return 0.0;
    }
    return 1.0 / sqrt(1.0 + dot2(ellipse, ellipse));
}

// Area of the ellipse within the sector from dir_0 counterclockwise to dir_1 (supplement Eq. (1)).
precise float ellipse_area_in_sector(vec2 ellipse, float rsqrt_det, vec2 dir_0, vec2 dir_1) {
    if (is_degenerate(ellipse)) {
        return 0.0;
    }
    precise float det_dirs = max(det2(dir_0, dir_1), 0.0);
    precise float dot_dirs = rsqrt_det * dot2(dir_0, ellipse_transform(ellipse, dir_1));
    return 0.5 * rsqrt_det * polygon_atan2(det_dirs, dot_dirs);
}

// Area between an outer and an inner ellipse within a sector; never negative.
precise float area_between_ellipses_in_sector(vec2 inner, vec2 outer, vec2 dir_0, vec2 dir_1) {
    precise float area = ellipse_area_in_sector(outer, ellipse_rsqrt_det(outer), dir_0, dir_1)
        - ellipse_area_in_sector(inner, ellipse_rsqrt_det(inner), dir_0, dir_1);
    return area > 0.0 ? area : 0.0;
}

// Algorithm 2 (Blinn): a non-zero root of w^T Q w = 0 from Q_xx, Q_xy + Q_yx and Q_yy.
precise vec2 solve_homogeneous_quadratic(float q_xx, float q_xy_plus_yx, float q_yy) {
    precise float b = 0.5 * q_xy_plus_yx;
    precise float sqrt_discriminant = sqrt(max(b * b - q_xx * q_yy, 0.0));
    precise float scaled_root = abs(b) + sqrt_discriminant;
    if (b >= 0.0) {
        return vec2(scaled_root, -q_xx);
    }
    return vec2(q_yy, scaled_root);
}

// The coefficients (Q_xx, Q_xy + Q_yx, Q_yy) of Q = a g^T - k c e^T.
precise vec3 quadratic_from_outer_products(vec2 a, vec2 g, float k, vec2 c, vec2 e) {
    return vec3(a.x * g.x - k * c.x * e.x,
                a.x * g.y + a.y * g.x - k * (c.x * e.y + c.y * e.x),
                a.y * g.y - k * c.y * e.y);
}

// `root` unless it is zero or not finite, then `fallback`.
precise vec2 usable_root(vec2 root, vec2 fallback) {
    precise float size = abs(root.x) + abs(root.y);
    return size > 0.0 && polygon_is_finite(size) ? root : fallback;
}

// Algorithm 3: a point uniform in area between the inner and outer ellipse within the sector
// from dir_0 to dir_1 (see the Rust twin for the rotated bases).
precise vec2 sample_sector_between_ellipses(vec2 u, float target_area, vec2 inner, vec2 outer, vec2 dir_0,
                                            vec2 dir_1, bool iterate) {
    precise vec2 s_0 = normalize2(dir_0);
    precise vec2 s_1_full = normalize2(dir_1);
    precise vec2 s_h = s_0 + s_1_full;
    precise float inner_0 = 1.0 / sqrt(ellipse_quadratic_form(inner, s_0));
    precise float inner_h = 1.0 / sqrt(ellipse_quadratic_form(inner, s_h));
    precise float inner_1_full = 1.0 / sqrt(ellipse_quadratic_form(inner, s_1_full));
    precise float outer_0 = 1.0 / sqrt(ellipse_quadratic_form(outer, s_0));
    precise float outer_h = 1.0 / sqrt(ellipse_quadratic_form(outer, s_h));
    precise float outer_1_full = 1.0 / sqrt(ellipse_quadratic_form(outer, s_1_full));
    // Areas of the two quads, up to a common factor
    precise float quad_0 = outer_0 * outer_h - inner_0 * inner_h;
    precise float quad_1 = outer_h * outer_1_full - inner_h * inner_1_full;
    // Pick a quad; its outer boundary direction goes to index 1
    precise float quad_target = mix_exact(-quad_0, quad_1, u.x);
    bool first_quad = quad_target <= 0.0;
    precise vec2 s_1 = first_quad ? s_0 : s_1_full;
    precise float inner_1 = first_quad ? inner_0 : inner_1_full;
    precise float outer_1 = first_quad ? outer_0 : outer_1_full;
    quad_target += first_quad ? quad_0 : -quad_1;
    // Twice the signed target area
    quad_target *= abs(det2(s_h, s_1));
    // Lines through the quad's inner and outer edge
    precise vec2 inner_normal = ellipse_transform(inner, inner_h * s_h + inner_1 * s_1);
    precise vec2 outer_normal = ellipse_transform(outer, outer_h * s_h + outer_1 * s_1);
    precise float inner_offset = inner_h * dot2(inner_normal, s_h);
    precise float outer_offset = outer_h * dot2(outer_normal, s_h);
    // Q in the basis (s_1, R s_1)
    precise vec2 e_1 = rotate_90(s_1);
    precise vec2 g = (outer_1 * outer_offset) * inner_normal - (inner_1 * inner_offset) * outer_normal;
    precise vec3 q = quadratic_from_outer_products(vec2(0.0, 1.0), vec2(dot2(g, s_1), dot2(g, e_1)), quad_target,
                                                   vec2(dot2(inner_normal, s_1), dot2(inner_normal, e_1)),
                                                   vec2(dot2(outer_normal, s_1), dot2(outer_normal, e_1)));
    precise vec2 root = usable_root(solve_homogeneous_quadratic(q.x, q.y, q.z), vec2(1.0, 0.0));
    precise vec2 w = root.x * s_1 + root.y * e_1;
    // Refine, unless at the ends of the sector where the initialisation is exact
    int iterations = iterate && u.x >= ITERATION_MARGIN && u.x <= 1.0 - ITERATION_MARGIN ? ITERATION_COUNT : 0;
    precise float inner_rsqrt_det = ellipse_rsqrt_det(inner);
    precise float outer_rsqrt_det = ellipse_rsqrt_det(outer);
    for (int iteration = 0; iteration < ITERATION_COUNT; ++iteration) {
        if (iteration >= iterations) {
            break;
        }
        // Keep w away from under- and overflow, on the side of the sector
        w *= 1.0 / (abs(w.x) + abs(w.y));
        if (dot2(w, s_h) < 0.0) {
            w = -w;
        }
        precise vec2 inner_w = ellipse_transform(inner, w);
        precise vec2 outer_w = ellipse_transform(outer, w);
        precise float det_dirs = max(det2(s_0, w), 0.0);
        precise float area = 0.5
            * (outer_rsqrt_det * polygon_atan2(det_dirs, outer_rsqrt_det * dot2(s_0, outer_w))
               - inner_rsqrt_det * polygon_atan2(det_dirs, inner_rsqrt_det * dot2(s_0, inner_w)));
        precise float residual = target_area - area;
        // T in the basis (w, R w)
        precise vec2 w_perp = rotate_90(w);
        precise float inner_along = dot2(inner, w);
        precise float outer_along = dot2(outer, w);
        precise float difference_along = (inner_along - outer_along) * (inner_along + outer_along);
        precise vec3 t = quadratic_from_outer_products(vec2(0.0, dot2(w, w)),
                                                       vec2(difference_along, dot2(inner_w - outer_w, w_perp)),
                                                       2.0 * residual, vec2(dot2(inner_w, w), dot2(inner_w, w_perp)),
                                                       vec2(dot2(outer_w, w), dot2(outer_w, w_perp)));
        precise vec2 refined = usable_root(solve_homogeneous_quadratic(t.x, t.y, t.z), vec2(1.0, 0.0));
        w = refined.x * w + refined.y * w_perp;
    }
    // The half sectors span at most 90 degrees: the root on the side of s_h is the right one
    if (dot2(w, s_h) < 0.0) {
        w = -w;
    }
    // Stay in the sector even when rounding dominates the areas
    if (det2(s_0, w) < 0.0) {
        w = s_0;
    } else if (det2(w, s_1_full) < 0.0) {
        w = s_1_full;
    }
    // Uniform in squared radius between the two ellipses
    precise float inner_squared_radius = 1.0 / ellipse_quadratic_form(inner, w);
    precise float outer_squared_radius = 1.0 / ellipse_quadratic_form(outer, w);
    return w * sqrt(max(mix_exact(inner_squared_radius, outer_squared_radius, u.y), 0.0));
}

// Whether the state is central (the polygon contains the zenith).
bool is_central(ProjectedSolidAngleSampler state) {
    return !is_inner(state.inner_ellipse_0);
}

// Swaps sector boundaries lhs and rhs (with their ellipses) when rhs is clockwise of lhs; on a
// tie a degenerate ellipse goes first (A.2, rule 3).
void compare_and_swap(inout ProjectedSolidAngleSampler state, int lhs, int rhs) {
    float det = det2(state.sector_dirs[lhs], state.sector_dirs[rhs]);
    bool swap = det < 0.0
        || (det == 0.0 && is_degenerate(state.ellipses[rhs]) && !is_degenerate(state.ellipses[lhs]));
    if (swap) {
        vec2 dir = state.sector_dirs[lhs];
        state.sector_dirs[lhs] = state.sector_dirs[rhs];
        state.sector_dirs[rhs] = dir;
        vec2 ellipse = state.ellipses[lhs];
        state.ellipses[lhs] = state.ellipses[rhs];
        state.ellipses[rhs] = ellipse;
    }
}

// Prepares projected-solid-angle sampling of a polygon clipped to the horizon (the first half of
// Algorithm 4); either winding.
precise ProjectedSolidAngleSampler prepare_projected_solid_angle(Polygon clipped) {
    ProjectedSolidAngleSampler state = projected_solid_angle_sampler_empty();
    int count = clipped.count;
    precise float signed_angle = signed_projected_solid_angle(clipped);
    if (count < 3 || signed_angle == 0.0 || !polygon_is_finite(signed_angle)) {
        return state;
    }
    // Counterclockwise about +z
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        state.vertices[j] = clipped.vertices[signed_angle > 0.0 ? j : count - 1 - j];
        state.sector_dirs[j] = state.vertices[j].xy;
    }
    // Associate vertices with ellipses (Algorithm 4)
    vec2 ellipse_0 = ellipse_from_edge(state.vertices[0], state.vertices[1]);
    vec2 previous = ellipse_0;
    for (int j = 1; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        vec2 current = ellipse_from_edge(state.vertices[j], state.vertices[next_index(j, count)]);
        state.ellipses[j] = is_inner(current) ? previous : current;
        if (is_inner(previous) && !is_inner(current)) {
            state.inner_ellipse_0 = previous;
        }
        previous = current;
    }
    state.ellipses[0] = is_inner(ellipse_0) ? previous : ellipse_0;
    if (is_inner(previous) && !is_inner(ellipse_0)) {
        state.inner_ellipse_0 = previous;
    }
    // Projected solid angle per sector
    precise float total = 0.0;
    if (is_central(state)) {
        for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
            if (j >= count) {
                break;
            }
            vec2 ellipse = state.ellipses[j];
            precise float area = ellipse_area_in_sector(ellipse, ellipse_rsqrt_det(ellipse), state.sector_dirs[j],
                                                        state.sector_dirs[next_index(j, count)]);
            state.sector_areas[j] = area;
            total += area;
        }
    } else {
        // Odd-even transposition sort: `count` passes sort `count` elements
        for (int pass = 0; pass < MAX_CLIPPED_VERTICES; ++pass) {
            if (pass >= count) {
                break;
            }
            for (int k = 0; k < MAX_CLIPPED_VERTICES / 2; ++k) {
                int lhs = 2 * k + (pass & 1);
                if (lhs + 1 < count) {
                    compare_and_swap(state, lhs, lhs + 1);
                }
            }
        }
        vec2 inner = state.inner_ellipse_0;
        vec2 outer = state.ellipses[0];
        for (int j = 0; j < MAX_CLIPPED_VERTICES - 1; ++j) {
            if (j + 1 >= count) {
                break;
            }
            if (j > 0) {
                vec2 ellipse = state.ellipses[j];
                if (is_inner(ellipse)) {
                    inner = ellipse;
                } else {
                    outer = ellipse;
                }
            }
            // Near-degenerate ellipses bound sectors too thin to sample in f32
            bool steep = max(dot2(inner, inner), dot2(outer, outer)) > STEEP_ELLIPSE_SQUARED;
            precise float area = steep ? 0.0
                : area_between_ellipses_in_sector(inner, outer, state.sector_dirs[j], state.sector_dirs[j + 1]);
            state.sector_areas[j] = area;
            total += area;
        }
    }
    if (!is_central(state) && total <= 0.0) {
        // Rounding swamped every sector area: select sectors by their angle instead
        state.proxy_sector_areas = true;
        total = 0.0;
        for (int j = 0; j < MAX_CLIPPED_VERTICES - 1; ++j) {
            if (j + 1 >= count) {
                break;
            }
            precise float angle = det2(normalize2(state.sector_dirs[j]), normalize2(state.sector_dirs[j + 1]));
            state.sector_areas[j] = max(angle, 0.0);
            total += state.sector_areas[j];
        }
    }
    if (!(total > 0.0 && polygon_is_finite(total))) {
        return projected_solid_angle_sampler_empty();
    }
    state.count = count;
    state.sector_total = total;
    state.projected_solid_angle = abs(signed_angle);
    return state;
}

// Samples a direction uniformly with respect to projected solid angle within the polygon from
// u in [0, 1)^2 (the second half of Algorithm 4). Returns the unit direction in xyz and its
// density with respect to projected solid angle in w; an empty state returns (+z, 0).
precise vec4 sample_projected_solid_angle(ProjectedSolidAngleSampler state, vec2 u) {
    if (state.count == 0) {
        return vec4(0.0, 0.0, 1.0, 0.0);
    }
    int count = state.count;
    precise float target = u.x * state.sector_total;
    // Select the sector; a target beyond the last non-empty sector clamps to its end
    precise float selected_area = 0.0;
    precise float selected_target = 0.0;
    vec2 dir_0 = vec2(1.0, 0.0);
    vec2 dir_1 = vec2(0.0, 1.0);
    vec2 inner = state.inner_ellipse_0;
    vec2 outer = state.ellipses[0];
    vec2 selected_inner = inner;
    vec2 selected_outer = outer;
    bool central = is_central(state);
    int sector_count = central ? count : count - 1;
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= sector_count) {
            break;
        }
        vec2 ellipse = state.ellipses[j];
        if (central || j == 0) {
            outer = ellipse;
        } else if (is_inner(ellipse)) {
            inner = ellipse;
        } else {
            outer = ellipse;
        }
        float area = state.sector_areas[j];
        if (area > 0.0) {
            selected_area = area;
            selected_target = min(target, area);
            selected_inner = inner;
            selected_outer = outer;
            dir_0 = state.sector_dirs[j];
            dir_1 = state.sector_dirs[next_index(j, count)];
        }
        if (target < area) {
            break;
        }
        target -= area;
    }
    precise vec2 w;
    if (central) {
        // Rotate s_0 within the ellipse by the angle 2 sqrt(det C) area
        precise float sqrt_det = sqrt(1.0 + dot2(selected_outer, selected_outer));
        precise float angle = 2.0 * selected_target * sqrt_det;
        precise vec2 direction =
            (cos(angle) * sqrt_det) * dir_0 + sin(angle) * rotate_90(ellipse_transform(selected_outer, dir_0));
        // Uniform in squared radius inside the ellipse
        w = direction * sqrt(max(u.y / ellipse_quadratic_form(selected_outer, direction), 0.0));
    } else {
        vec2 sector_u = vec2(min(selected_target / selected_area, 1.0), u.y);
        w = sample_sector_between_ellipses(sector_u, selected_target, selected_inner, selected_outer, dir_0, dir_1,
                                           !state.proxy_sector_areas);
    }
    precise float z = sqrt(max(1.0 - dot2(w, w), 0.0));
    return vec4(w, z, 1.0 / state.projected_solid_angle);
}

// Whether the unit direction lies in the convex spherical polygon (winding `orientation` = +-1),
// up to INSIDE_TOLERANCE radians.
precise bool is_inside(vec3 vertices[MAX_CLIPPED_VERTICES], int count, float orientation, vec3 direction) {
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        precise vec3 normal = cross_stable(vertices[j], vertices[next_index(j, count)]) * orientation;
        if (polygon_dot3(normal, direction) < -INSIDE_TOLERANCE * length3(normal)) {
            return false;
        }
    }
    return true;
}

// The density with respect to projected solid angle of sample_projected_solid_angle at the unit
// direction: 1 / projected solid angle inside the clipped polygon, 0 elsewhere.
precise float projected_solid_angle_density(ProjectedSolidAngleSampler state, vec3 direction) {
    if (state.count == 0 || direction.z <= 0.0 || !is_inside(state.vertices, state.count, 1.0, direction)) {
        return 0.0;
    }
    return 1.0 / state.projected_solid_angle;
}

// Prepares solid-angle sampling of a convex polygon (3 to MAX_CLIPPED_VERTICES vertices, clipped
// or not, either winding): the fan of triangles (v_j+1, v_0, v_j+2) with the Householder
// determinant of Sec. C.
precise SolidAngleSampler prepare_solid_angle(Polygon polygon) {
    SolidAngleSampler state = solid_angle_sampler_empty();
    int count = polygon.count;
    if (count < 3 || count > MAX_CLIPPED_VERTICES) {
        return state;
    }
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        if (all(equal(polygon.vertices[j], vec3(0.0)))) {
            return state;
        }
        state.directions[j] = normalize3(polygon.vertices[j]);
    }
    vec3 origin = polygon.vertices[0];
    vec3 apex = state.directions[0];
    // H = I - 2hh^T maps v_0 to sigma e_0
    float sigma = apex.x > 0.0 ? -1.0 : 1.0;
    precise vec2 householder_yz = vec2(apex.y, apex.z) / (abs(apex.x) + 1.0);
    precise vec3 previous_offset = unit_difference(polygon.vertices[1], origin);
    precise float total = 0.0;
    precise float signed_total = 0.0;
    precise float magnitude = 0.0;
    for (int j = 0; j < MAX_FAN_TRIANGLES; ++j) {
        if (j + 2 >= count) {
            break;
        }
        vec3 a = state.directions[j + 1];
        vec3 b = state.directions[j + 2];
        precise vec3 offset_a = previous_offset;
        precise vec3 offset_b = unit_difference(polygon.vertices[j + 2], origin);
        previous_offset = offset_b;
        // v_0.d = -|d|^2/2 exactly for d = v - v_0
        precise vec2 reflected_a =
            vec2(offset_a.y, offset_a.z) - householder_yz * (-0.5 * polygon_dot3(offset_a, offset_a) - sigma * offset_a.x);
        precise vec2 reflected_b =
            vec2(offset_b.y, offset_b.z) - householder_yz * (-0.5 * polygon_dot3(offset_b, offset_b) - sigma * offset_b.x);
        precise float signed_det = sigma * det2(reflected_a, reflected_b);
        precise float g_0 = abs(signed_det);
        precise float g_1 = polygon_dot3(a, b) + polygon_dot3(apex, b);
        precise float g_2 = 1.0 + polygon_dot3(a, apex);
        precise float triangle_solid_angle = 2.0 * polygon_atan2(g_0, g_1 + g_2);
        state.triangles[j] = vec3(g_0, g_1, g_2);
        total += triangle_solid_angle;
        state.fan_solid_angles[j] = total;
        signed_total += polygon_copysign(triangle_solid_angle, signed_det);
        magnitude += triangle_solid_angle;
    }
    if (!(total > 0.0 && polygon_is_finite(total)) || abs(signed_total) <= EMPTY_RELATIVE_THRESHOLD * magnitude) {
        return solid_angle_sampler_empty();
    }
    state.orientation = signed_total > 0.0 ? -1.0 : 1.0;
    state.count = count;
    state.solid_angle = total;
    return state;
}

// Samples a direction uniformly with respect to solid angle within the polygon from u in [0, 1)^2
// (Algorithm 5). Returns the unit direction in xyz and its density with respect to solid angle in
// w; an empty state returns (+z, 0).
precise vec4 sample_solid_angle(SolidAngleSampler state, vec2 u) {
    if (state.count == 0) {
        return vec4(0.0, 0.0, 1.0, 0.0);
    }
    int count = state.count;
    precise float target = u.x * state.solid_angle;
    // Select the triangle; a target beyond the last non-empty triangle clamps to its end
    int selected = 0;
    precise float sub_solid_angle = 0.0;
    precise float previous_fan = 0.0;
    for (int j = 0; j < MAX_FAN_TRIANGLES; ++j) {
        if (j + 2 >= count) {
            break;
        }
        float fan = state.fan_solid_angles[j];
        if (fan > previous_fan) {
            selected = j;
            sub_solid_angle = min(target - previous_fan, fan - previous_fan);
        }
        if (target < fan) {
            break;
        }
        previous_fan = fan;
    }
    vec3 g = state.triangles[selected];
    vec3 a = state.directions[selected + 1];
    vec3 apex = state.directions[0];
    vec3 b = state.directions[selected + 2];
    // The point on the arc from a to b that cuts off a triangle (a, apex, b') of the wanted solid
    // angle: b' = -a + 2 (a.r)/|r|^2 r with r = (G0 cos(A/2) - G1 sin(A/2)) a + G2 sin(A/2) b
    precise float half_angle = 0.5 * sub_solid_angle;
    precise float sin_half = sin(half_angle);
    precise float cos_half = cos(half_angle);
    precise vec3 r = (g.x * cos_half - g.y * sin_half) * a + (g.z * sin_half) * b;
    precise vec3 new_b = (2.0 * polygon_dot3(a, r) / polygon_dot3(r, r)) * r - a;
    // Uniform in cos of the distance from the apex along the arc from apex to b'
    precise float s_2 = polygon_dot3(apex, new_b);
    precise float s = mix_exact(1.0, s_2, u.y);
    precise float t = sqrt(max(u.y * (1.0 + s) / max(1.0 + s_2, POLYGON_MIN_POSITIVE), 0.0));
    precise vec3 direction = (s - t * s_2) * apex + t * new_b;
    return vec4(direction, 1.0 / state.solid_angle);
}

// The density with respect to solid angle of sample_solid_angle at the unit direction.
precise float solid_angle_density(SolidAngleSampler state, vec3 direction) {
    if (state.count == 0 || !is_inside(state.directions, state.count, state.orientation, direction)) {
        return 0.0;
    }
    return 1.0 / state.solid_angle;
}

// Clamped optimal MIS weights (supplement B.3) of two techniques at one direction: densities,
// coefficients c_j (the estimated unoccluded integral each technique models) and visibility v.
precise vec2 clamped_optimal_mis_weights(vec2 densities, vec2 coefficients, float visibility) {
    precise float density_sum = densities.x + densities.y;
    if (isnan(density_sum) || density_sum <= 0.0) {
        return vec2(0.0);
    }
    precise float weighted_sum = coefficients.x * densities.x + coefficients.y * densities.y;
    precise vec2 weights = vec2(0.0);
    for (int j = 0; j < 2; ++j) {
        precise float balance = densities[j] / density_sum;
        precise float weighted = weighted_sum > 0.0 ? coefficients[j] * densities[j] / weighted_sum : balance;
        weights[j] = clamp(mix_exact(balance, weighted, visibility), 0.0, 1.0);
    }
    return weights;
}

// Point `index` of the shifted Hammersley set of `count` points in [0, 1)^2.
precise vec2 sample_point(uint index, uint count) {
    precise float inverse_count = 1.0 / float(max(count, 1u));
    precise float u_0 = min((float(index) + 0.5) * inverse_count, 1.0 - POLYGON_EPSILON / 2.0);
    precise float radical_inverse = float(bitfieldReverse(index) >> 8) * (1.0 / 16777216.0);
    precise float shifted = radical_inverse + 0.5 * inverse_count;
    precise float u_1 = shifted >= 1.0 ? shifted - 1.0 : shifted;
    return vec2(u_0, u_1);
}

#endif
