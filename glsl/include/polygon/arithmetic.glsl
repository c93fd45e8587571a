// Arithmetic with Rust's semantics (infinity, finiteness, sign bit, copysign, glam's dot
// products and lengths, an fma emulated in two products, an accurate atan2) and the
// cancellation-free helpers: kahan, cross_stable, det2, rotate_90, mix_exact, unit_difference.
// Part of polygon.glsl, which includes its parts in order (each uses only those before it).
// Rust twin: `src/shading/polygon/arithmetic.rs`; `tests/polygon_gpu.rs` checks that the two agree.

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
