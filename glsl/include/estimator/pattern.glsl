// The pattern constants of an attribute map (pattern_constants, jung_scales) and the pattern
// scales (Scale).
// Twin: `src/shading/estimator/pattern.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// sqrt(K1), sqrt(K), D1, D of one attribute map (see `pattern_constants`).
struct PatternConstants {
    float sqrt_k1;
    float sqrt_k;
    float diam1;
    float diam;
};

// max_x sum mu_k |v_k - x|^2 over the triangle {0, u, v}, and its squared diameter.
P vec2 enclosing_radius2(vec3 u, vec3 v) {
    P float e0 = len2(u);
    P float e1 = len2(v);
    P float e2 = len2(u - v);
    P float d2 = rmax(rmax(e0, e1), e2);
    if (!(d2 > 0.0)) {
        return vec2(0.0);
    }
    P float sum = e0 + e1 + e2;
    if (2.0 * d2 >= sum) {
        return vec2(0.25 * d2, d2);
    }
    P float x = len2(cross3(u, v)) / (d2 * d2);
    P float r = (e0 / d2) * (e1 / d2) * (e2 / d2) / rmax(4.0 * x, 1.0e-30);
    P vec2 out_value = vec2(d2 * clamp(r, 0.25, THIRD), d2);
    return out_value;
}

// The seven shapes {0, u, v} in the basis (e1, e2): see SHAPES in Rust.
const vec4 PATTERN_SHAPES[7] = vec4[7](
    vec4(1.0, 0.0, 0.0, 1.0),
    vec4(1.0, 0.0, TWO_THIRDS, TWO_THIRDS),
    vec4(1.0, 0.0, -THIRD, TWO_THIRDS),
    vec4(0.0, 1.0, TWO_THIRDS, TWO_THIRDS),
    vec4(0.0, 1.0, TWO_THIRDS, -THIRD),
    vec4(-1.0, 1.0, -FOUR_THIRDS, TWO_THIRDS),
    vec4(-1.0, 1.0, -THIRD, -THIRD));

// The largest squares first and one square root of each (see `pattern_constants`).
PatternConstants pattern_constants(vec3 e1, vec3 e2) {
    P vec2 first = vec2(0.0);
    P vec2 largest = vec2(0.0);
    for (int s = 0; s < 7; ++s) {
        P vec3 u = e1 * PATTERN_SHAPES[s].x + e2 * PATTERN_SHAPES[s].y;
        P vec3 v = e1 * PATTERN_SHAPES[s].z + e2 * PATTERN_SHAPES[s].w;
        P vec2 kd = enclosing_radius2(u, v);
        if (s == 0) {
            first = kd;
        }
        largest = vec2(rmax(largest.x, kd.x), rmax(largest.y, kd.y));
    }
    PatternConstants o = PatternConstants(sqrt(first.x), sqrt(largest.x), sqrt(first.y), sqrt(largest.y));
    return o;
}

// Upper bounds (sqrt K1, sqrt K) from the shapes' longest edge, r^2 <= d^2/3 (see `jung_scales`).
P vec2 jung_scales(vec3 e1, vec3 e2) {
    P float d1 = 0.0;
    P float d = 0.0;
    for (int s = 0; s < 7; ++s) {
        P vec3 u = e1 * PATTERN_SHAPES[s].x + e2 * PATTERN_SHAPES[s].y;
        P vec3 v = e1 * PATTERN_SHAPES[s].z + e2 * PATTERN_SHAPES[s].w;
        P float d2 = rmax(rmax(len2(u), len2(v)), len2(u - v));
        if (s == 0) {
            d1 = d2;
        }
        d = rmax(d, d2);
    }
    P vec2 r = vec2(sqrt(d1 / 3.0), sqrt(d / 3.0));
    return r;
}

// Pattern scales: what |X delta|, |N delta| and |G delta| are replaced by (see `Scale`).
struct Scale {
    float a;
    float b;
    float g;
};
