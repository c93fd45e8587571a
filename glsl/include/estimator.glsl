// The per-triangle error estimator: the GLSL port of `src/shading/estimator.rs` (the source of
// truth; its docs and `docs/estimator.md` have the derivation). Keep the two in step, operation
// for operation: the control stage must choose exactly the levels the Rust twin
// (`analysis::report`) predicts, and a GPU test compares them triangle by triangle.
//
// Porting rules followed throughout:
// - every floating-point result is `precise` (P below): no fused multiply-adds or reassociation,
//   so the level of a triangle is bit-identical in every patch that evaluates it (its own and
//   its three neighbours'), and as close as possible to the Rust f32 arithmetic;
// - the same operation order as Rust, with glam's formulas for dot, cross, length and
//   max_element written out (dot3, cross3, ...);
// - Rust's NaN behaviour where NaN can arise: `f32::max`/`min` ignore a NaN operand (rmax,
//   rmin), comparisons are false;
// - its own sin, cos, atan2, acos, asin and pow (bit-identical to the Rust ones, see below);
// - `acos` only ever sees arguments in [0, 1] (clamped as in Rust).
// Only the scene's material kind and light counts are compiled in (specialization constants of
// brdf.glsl), plus SPLIT and DISCONTINUITY below.
#ifndef ESTIMATOR_GLSL
#define ESTIMATOR_GLSL
#include "brdf.glsl"

// Split of epsilon between the terms: 0 Uniform, 1 Heuristic.
layout(constant_id = 3) const int SPLIT = 1;
// Terminator handling: 0 Conservative (fallback), 1 Relaxed.
layout(constant_id = 4) const int DISCONTINUITY = 0;

#define P precise

// Estimate::level of a triangle that falls back to per-pixel shading.
const float FALLBACK_LEVEL = 1.0e6;

const int TERM_COUNT = 13;
const int T_NORMAL = 0;
const int T_LIGHT = 1;
const int T_VIEW = 2;
const int T_HALF = 3;
const int T_DOT = 4;
const int T_ATTENUATION = 5;
const int T_POWER = 6;
const int T_D = 7;
const int T_F = 8;
const int T_V = 9;
const int T_CROSS = 10;
const int T_TERMINATOR = 11;
const int T_RANGE = 12;
// Not a term: the jets carry the sum of all terms (`Jet::t` in Rust).
const int T_ALL = 13;

// The f32 values of the Rust constants (shortest decimals that round to them).
const float K23 = 1.1547005;
const float BIG = 1.0e18;
const float UNIFORM_TINY = 9.536743e-7;   // 1.0 / 1048576.0
const float SAFETY = 1.01;
const float ANGLE_PAD = 2.0e-6;
// Relaxed: Lg - g <= E_f + TERMINATOR_KINK osc(f) where g = max(f, 0) has its kink (see Rust).
const float TERMINATOR_KINK = 0.25;
const float HALF_PI = 1.5707964;          // std::f32::consts::FRAC_PI_2
const float MAX_HALF = 1.5706964;         // FRAC_PI_2 - 1.0e-4 in f32
const float INV_SQRT3 = 0.57735026;       // 1.0 / 3.0f32.sqrt()
const float THIRD = 0.33333334;           // 1.0 / 3.0
const float TWO_THIRDS = 0.6666667;       // 2.0 / 3.0
const float FOUR_THIRDS = 1.3333334;      // 4.0 / 3.0
const float HULL_SHRINK = 0.999;          // 1.0 - 1.0e-3 in f32
const float PI_MINUS_MILLI = 3.1405928;   // PI - 1.0e-3 in f32
const float MIN_D2_SAFE = 1.0010001e-8;   // MIN_LIGHT_DISTANCE_SQUARED * 1.001 in f32
const float INF = 1.0 / 0.0;

const int SIGN_POSITIVE = 0;
const int SIGN_NON_POSITIVE = 1;
const int SIGN_BOTH = 2;

const int REASON_NONE = 0;
const int REASON_LEVEL = 1;
const int REASON_DISCONTINUITY = 2;
const int REASON_SINGULAR = 3;

// ---------------------------------------------------------------------------------------------
// Rust semantics
// ---------------------------------------------------------------------------------------------

bool is_nan(float x) {
    return !(x <= 0.0) && !(x > 0.0);
}

// f32::max / f32::min: a NaN operand is ignored.
float rmax(float a, float b) {
    return (b > a || is_nan(a)) ? b : a;
}
float rmin(float a, float b) {
    return (b < a || is_nan(a)) ? b : a;
}

float infinity() {
    return uintBitsToFloat(0x7f800000u);
}

// glam's Vec3::dot, cross, length_squared, length, max_element.
P float dot3(vec3 a, vec3 b) {
    P float d = a.x * b.x + a.y * b.y + a.z * b.z;
    return d;
}
P vec3 cross3(vec3 a, vec3 b) {
    P vec3 c = vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
    return c;
}
P float len2(vec3 v) {
    return dot3(v, v);
}
P float len(vec3 v) {
    P float l = sqrt(dot3(v, v));
    return l;
}
float max_el(vec3 v) {
    float yz = v.y > v.z ? v.y : v.z;
    return v.x > yz ? v.x : yz;
}
bool is_zero(vec3 v) {
    return v.x == 0.0 && v.y == 0.0 && v.z == 0.0;
}

// ---------------------------------------------------------------------------------------------
// Elementary functions: the estimator's own (see "Elementary functions" in Rust), from IEEE
// f32 +, -, *, /, sqrt, floor and bit manipulation only, so that they are bit-identical to
// the Rust twin's (the drivers' sin, atan, pow, ... are not).
// ---------------------------------------------------------------------------------------------

const float PIO2_P1 = 1.5703125;
const float PIO2_P2 = 0.0004837513;
const float PIO2_P3 = 7.54979e-8;
const float TWO_OVER_PI = 0.63661975;
const float TAN_PI_8 = 0.41421357;
const float FRAC_PI_4_F = 0.7853982;
const float SQRT_2 = 1.4142135;
const float LOG2_E = 1.442695;
const float LN_2 = 0.6931472;

// x reduced to r in [-pi/4, pi/4]; returns r, the quadrant (mod 4) goes to n.
P float reduce_quadrant(float x, out int n) {
    P float k = floor(x * TWO_OVER_PI + 0.5);
    P float r = x - k * PIO2_P1 - k * PIO2_P2 - k * PIO2_P3;
    n = int(k) & 3;
    return r;
}

P float sin_poly(float r) {
    P float z = r * r;
    P float s = r + r * z * (-0.16666667 + z * (0.008333334 + z * (-0.0001984127 + z * 2.7557319e-6)));
    return s;
}

P float cos_poly(float r) {
    P float z = r * r;
    P float c = 1.0 - 0.5 * z + z * z * (0.041666668 + z * (-0.0013888889 + z * (2.4801588e-5 + z * -2.755732e-7)));
    return c;
}

P float est_sin(float x) {
    int n;
    P float r = reduce_quadrant(x, n);
    if (n == 0) {
        return sin_poly(r);
    }
    if (n == 1) {
        return cos_poly(r);
    }
    if (n == 2) {
        return -sin_poly(r);
    }
    return -cos_poly(r);
}

P float est_cos(float x) {
    int n;
    P float r = reduce_quadrant(x, n);
    if (n == 0) {
        return cos_poly(r);
    }
    if (n == 1) {
        return -sin_poly(r);
    }
    if (n == 2) {
        return -cos_poly(r);
    }
    return sin_poly(r);
}

P float atan_poly(float t) {
    P float z = t * t;
    P float p = 0.06666667 + z * (-0.05882353 + z * 0.05263158);
    p = -0.07692308 + z * p;
    p = 0.09090909 + z * p;
    p = -0.11111111 + z * p;
    p = 0.14285715 + z * p;
    p = -0.2 + z * p;
    p = 0.33333334 + z * p;
    P float a = t - t * z * p;
    return a;
}

P float atan_unit(float t) {
    if (t > TAN_PI_8) {
        P float a = FRAC_PI_4_F + atan_poly((t - 1.0) / (t + 1.0));
        return a;
    }
    return atan_poly(t);
}

// atan2 (0 for (0, 0)).
P float est_atan2(float y, float x) {
    P float ax = abs(x);
    P float ay = abs(y);
    if (ax == 0.0 && ay == 0.0) {
        return 0.0;
    }
    P float a = ay <= ax ? atan_unit(ay / ax) : HALF_PI - atan_unit(ax / ay);
    a = x < 0.0 ? PI - a : a;
    return y < 0.0 ? -a : a;
}

P float est_acos(float x) {
    return est_atan2(sqrt(rmax((1.0 - x) * (1.0 + x), 0.0)), x);
}

P float est_asin(float x) {
    return est_atan2(x, sqrt(rmax((1.0 - x) * (1.0 + x), 0.0)));
}

// log2 of a positive normal x.
P float est_log2(float x) {
    uint bits = floatBitsToUint(x);
    int e = int((bits >> 23) & 0xffu) - 127;
    P float m = uintBitsToFloat((bits & 0x007fffffu) | 0x3f800000u);
    if (m > SQRT_2) {
        m = m * 0.5;
        e += 1;
    }
    P float t = (m - 1.0) / (m + 1.0);
    P float z = t * t;
    P float ln_m = 2.0 * t * (1.0 + z * (0.33333334 + z * (0.2 + z * (0.14285715 + z * 0.11111111))));
    P float l = float(e) + ln_m * LOG2_E;
    return l;
}

// 2^z; 0 below 2^-126, infinity from 2^128 on.
P float est_exp2(float z) {
    if (is_nan(z)) {
        return z;
    }
    if (z >= 128.0) {
        return infinity();
    }
    if (!(z >= -126.0)) {
        return 0.0;
    }
    P float n = floor(z);
    P float u = (z - n) * LN_2;
    P float p = 1.0 + u * (1.0 + u * (0.5 + u * (0.16666667 + u * (0.041666668 + u * (0.008333334
        + u * (0.0013888889 + u * (0.0001984127 + u * (2.4801588e-5 + u * 2.7557319e-6))))))));
    P float r = p * uintBitsToFloat(uint(int(n) + 127) << 23);
    return r;
}

// x^y for x >= 0: x^0 = 1, x^1 = x, 0^y = 0 or infinity; NaN for negative x.
P float est_pow(float x, float y) {
    if (y == 0.0) {
        return 1.0;
    }
    if (y == 1.0) {
        return x;
    }
    if (x == 0.0) {
        return y > 0.0 ? 0.0 : infinity();
    }
    if (!(x > 0.0)) {
        return uintBitsToFloat(0x7fc00000u);
    }
    if (x == infinity()) {
        return y > 0.0 ? infinity() : 0.0;
    }
    if (x < 1.17549435e-38) {
        return y > 0.0 ? 0.0 : infinity();
    }
    return est_exp2(y * est_log2(x));
}

// ---------------------------------------------------------------------------------------------
// Guard and jets
// ---------------------------------------------------------------------------------------------

// Set when a bound overflowed (or was NaN): the estimate then falls back (Singular).
bool est_bad;

P float gc(float x) {
    if (x <= BIG) {
        return x;
    }
    est_bad = true;
    return BIG;
}
P float gmul(float a, float b) {
    P float p = a * b;
    return gc(p);
}

// The bounds of one factor (see `Jet` in Rust): m >= sup|f|, g >= sup|Df|, and h, the part of
// sup|D^2 f| booked under the term `est_term`, or all of it (`Jet::t`) when est_term is
// T_ALL. Rust carries all 13 terms and their sum at once; every operation on them acts on
// each separately (scaling, sums, the guard), so a pass here gets the same value as Rust
// for its term. The levels are decided on the sum: one pass per level (`add_light`); the
// Uniform split adds one pass per term.
struct Jet {
    float m;
    float g;
    float h;
};

// The term whose share of the second derivative the jets carry in this pass, or T_ALL.
int est_term;

// Whether this pass carries the parts booked under `term`.
bool booked(int term) {
    return est_term == term || est_term == T_ALL;
}

Jet jet_constant(float m) {
    return Jet(m, 0.0, 0.0);
}

Jet guard_jet(Jet j) {
    return Jet(gc(j.m), gc(j.g), gc(j.h));
}

// Product rule for k (2 or 5) factors, as `product` in Rust (the cross terms go to T_CROSS,
// in the same order).
Jet product(Jet f[5], int k) {
    P float m = 1.0;
    for (int j = 0; j < k; ++j) {
        m = gmul(m, f[j].m);
    }
    Jet o = jet_constant(m);
    for (int i = 0; i < k; ++i) {
        P float others = 1.0;
        for (int j = 0; j < k; ++j) {
            if (j != i) {
                others = gmul(others, f[j].m);
            }
        }
        P float gi = gmul(f[i].g, others);
        o.g = gc(o.g + gi);
        P float hi = gmul(f[i].h, others);
        o.h = gc(o.h + hi);
        for (int j = i + 1; j < k; ++j) {
            P float rest = 2.0;
            for (int l = 0; l < k; ++l) {
                if (l != i && l != j) {
                    rest = gmul(rest, f[l].m);
                }
            }
            P float gg = gmul(f[i].g, f[j].g);
            P float cr = gmul(gg, rest);
            if (booked(T_CROSS)) {
                o.h = gc(o.h + cr);
            }
        }
    }
    return o;
}

Jet product2(Jet a, Jet b) {
    Jet f[5] = Jet[5](a, b, a, a, a);
    return product(f, 2);
}

// A unit vector field: w >= |Du|, x >= |P m''|/|m|, and the term its curvature is booked under.
struct Field {
    float w;
    float x;
    int term;
};

// max sin(psi) over [p0, p1] in [0, pi].
P float max_sin(float p0, float p1) {
    if (p0 <= HALF_PI && p1 >= HALF_PI) {
        return 1.0;
    }
    P float s = rmax(rmax(est_sin(p0), est_sin(p1)), 0.0);
    return s;
}

// max phi(psi) over [p0, p1], phi = c/2 + sqrt(1 - 3c^2/4), c = |cos psi|.
P float max_phi(float p0, float p1) {
    P float c0 = abs(est_cos(p0));
    P float c1 = abs(est_cos(p1));
    P float lo;
    P float hi;
    if (p0 <= HALF_PI && p1 >= HALF_PI) {
        lo = 0.0;
        hi = rmax(c0, c1);
    } else {
        lo = rmin(c0, c1);
        hi = rmax(c0, c1);
    }
    P float c = clamp(INV_SQRT3, lo, hi);
    P float r = rmin(0.5 * c + sqrt(rmax(1.0 - 0.75 * c * c, 0.0)), K23);
    return r;
}

// max cos^p(psi) sin^q(psi) over [a, b] in [0, pi/2].
P float max_cos_sin(float p, float q, float a, float b) {
    P float peak = p > 0.0 ? est_atan2(sqrt(q / p), 1.0) : HALF_PI;
    P float x = clamp(peak, a, b);
    P float c = rmax(est_cos(x), 0.0);
    P float s = rmax(est_sin(x), 0.0);
    P float cp = p == 0.0 ? 1.0 : est_pow(c, p);
    P float sq = q == 0.0 ? 1.0 : est_pow(s, q);
    P float r = cp * sq;
    return r;
}

// Jet of c = a.b where the angle between them stays in psi (neither a nor b books under
// T_DOT; they may share a term, as a polygon's emitter cosine does).
Jet cosine(Field a, Field b, vec2 psi) {
    P float s_max = max_sin(psi.x, psi.y);
    P float phi = max_phi(psi.x, psi.y);
    Jet j = jet_constant(rmax(abs(est_cos(psi.x)), abs(est_cos(psi.y))));
    P float ha = gc(phi * a.w * a.w + s_max * a.x);
    P float hb = gc(phi * b.w * b.w + s_max * b.x);
    P float hd = gc(2.0 * a.w * b.w);
    if (booked(a.term)) {
        j.h = ha;
    }
    if (booked(b.term)) {
        j.h = j.h + hb;
    }
    if (booked(T_DOT)) {
        j.h = j.h + hd;
    }
    j.g = gc(s_max * (a.w + b.w));
    return j;
}

// ---------------------------------------------------------------------------------------------
// Cones
// ---------------------------------------------------------------------------------------------

// Every value of a field is within `half` of `axis`; half = PI means no bound.
struct Cone {
    vec3 axis;
    float spread;
};

Cone no_cone() {
    return Cone(vec3(0.0, 0.0, 1.0), PI);
}

// Angle between two vectors; 0 if one is zero.
P float angle(vec3 a, vec3 b) {
    return est_atan2(len(cross3(a, b)), dot3(a, b));
}

P vec3 unit(vec3 v) {
    P float l2 = len2(v);
    if (l2 > 0.0 && l2 <= 3.4028235e38) {
        P vec3 u = v / sqrt(l2);
        return u;
    }
    return vec3(0.0);
}

// The smallest cone containing three directions (see `cone_of`).
Cone cone_of(vec3 w0, vec3 w1, vec3 w2) {
    P vec3 u[3] = vec3[3](unit(w0), unit(w1), unit(w2));
    if (is_zero(u[0]) || is_zero(u[1]) || is_zero(u[2])) {
        return no_cone();
    }
    P float d[3] = float[3](len2(u[0] - u[1]), len2(u[1] - u[2]), len2(u[2] - u[0]));
    int k = (d[0] >= d[1] && d[0] >= d[2]) ? 0 : (d[1] >= d[2] ? 1 : 2);
    int i = k;
    int j = (k + 1) % 3;
    P float others = d[(k + 1) % 3] + d[(k + 2) % 3];
    P vec3 axis;
    if (d[k] >= others) {
        axis = unit(u[i] + u[j]);
    } else {
        P vec3 nrm = unit(cross3(u[1] - u[0], u[2] - u[0]));
        axis = dot3(nrm, u[0] + u[1] + u[2]) < 0.0 ? -nrm : nrm;
    }
    if (is_zero(axis)) {
        return no_cone();
    }
    P float half_angle = rmax(rmax(angle(axis, u[0]), angle(axis, u[1])), angle(axis, u[2])) + ANGLE_PAD;
    if (is_nan(half_angle) || half_angle >= MAX_HALF) {
        return no_cone();
    }
    return Cone(axis, half_angle);
}

// min |sum l_k w_k| over the simplex >= min_k w_k . axis.
P float min_length(vec3 w0, vec3 w1, vec3 w2, Cone cone) {
    if (cone.spread >= PI) {
        return 0.0;
    }
    P float r = rmin(rmin(dot3(w0, cone.axis), dot3(w1, cone.axis)), dot3(w2, cone.axis));
    return r > 0.0 ? r : 0.0;
}

// Range of the angle between a vector of cone a and one of cone b.
P vec2 psi_range(Cone a, Cone b) {
    P float t0 = angle(a.axis, b.axis);
    P vec2 r = vec2(rmax(t0 - a.spread - b.spread, 0.0), rmin(t0 + a.spread + b.spread, PI));
    return r;
}

// Exact range of q(l) = (sum l_k a_k).(sum l_k b_k) over the simplex.
P vec2 bilinear_range(vec3 a[3], vec3 b[3]) {
    P float s00 = 0.5 * (dot3(a[0], b[0]) + dot3(a[0], b[0]));
    P float s11 = 0.5 * (dot3(a[1], b[1]) + dot3(a[1], b[1]));
    P float s22 = 0.5 * (dot3(a[2], b[2]) + dot3(a[2], b[2]));
    P float s01 = 0.5 * (dot3(a[0], b[1]) + dot3(a[1], b[0]));
    P float s12 = 0.5 * (dot3(a[1], b[2]) + dot3(a[2], b[1]));
    P float s02 = 0.5 * (dot3(a[0], b[2]) + dot3(a[2], b[0]));
    P float lo = rmin(rmin(s00, s11), s22);
    P float hi = rmax(rmax(s00, s11), s22);
    P vec3 edges[3] = vec3[3](vec3(s00, s11, s01), vec3(s11, s22, s12), vec3(s22, s00, s02));
    for (int e = 0; e < 3; ++e) {
        P float sii = edges[e].x;
        P float sjj = edges[e].y;
        P float sij = edges[e].z;
        P float curv = sii - 2.0 * sij + sjj;
        P float t = (sii - sij) / curv;
        if (t > 0.0 && t < 1.0) {
            P float v = (1.0 - t) * (1.0 - t) * sii + 2.0 * t * (1.0 - t) * sij + t * t * sjj;
            lo = rmin(lo, v);
            hi = rmax(hi, v);
        }
    }
    P float d1 = s01 - s00;
    P float d2 = s02 - s00;
    P float ma = s00 - 2.0 * s01 + s11;
    P float mb = s00 - s01 - s02 + s12;
    P float mc = s00 - 2.0 * s02 + s22;
    P float det = ma * mc - mb * mb;
    P float x = (-d1 * mc + d2 * mb) / det;
    P float y = (-ma * d2 + mb * d1) / det;
    if (x > 0.0 && y > 0.0 && x + y < 1.0) {
        P float v = s00 + d1 * x + d2 * y;
        lo = rmin(lo, v);
        hi = rmax(hi, v);
    }
    return vec2(lo, hi);
}

// Angular distance from unit a to the spherical triangle of the unit vectors u.
P float hull_distance(vec3 a, vec3 u[3]) {
    P float orient = dot3(u[0], cross3(u[1], u[2]));
    P float side0 = dot3(a, cross3(u[0], u[1]));
    P float side1 = dot3(a, cross3(u[1], u[2]));
    P float side2 = dot3(a, cross3(u[2], u[0]));
    const float tol = 1.0e-6;
    bool same_half = dot3(a, u[0] + u[1] + u[2]) > 0.0;
    bool inside = same_half
        && ((orient >= 0.0 && side0 >= -tol && side1 >= -tol && side2 >= -tol)
            || (orient <= 0.0 && side0 <= tol && side1 <= tol && side2 <= tol));
    if (inside) {
        return 0.0;
    }
    P float best = PI;
    for (int e = 0; e < 3; ++e) {
        P vec3 p = u[e];
        P vec3 q = u[(e + 1) % 3];
        P float ends = rmin(angle(a, p), angle(a, q));
        P vec3 m = unit(cross3(p, q));
        P float d = ends;
        if (!is_zero(m)) {
            P vec3 foot = a - m * dot3(a, m);
            if (dot3(cross3(p, foot), m) >= 0.0 && dot3(cross3(foot, q), m) >= 0.0 && !is_zero(foot)) {
                d = rmin(d, est_atan2(abs(dot3(a, m)), len(foot)));
            }
        }
        best = rmin(best, d);
    }
    P float r = rmax(best * HULL_SHRINK - ANGLE_PAD, 0.0);
    return r;
}

// Largest angle between a and the spherical triangle u when below pi/2, else PI.
P float hull_max_angle(vec3 a, vec3 u[3]) {
    P float m = rmax(rmax(angle(a, u[0]), angle(a, u[1])), angle(a, u[2])) + ANGLE_PAD;
    return m < HALF_PI ? m : PI;
}

// ---------------------------------------------------------------------------------------------
// The pattern constants
// ---------------------------------------------------------------------------------------------

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

PatternConstants pattern_constants(vec3 e1, vec3 e2) {
    // The seven shapes {0, u, v} in the basis (e1, e2): see SHAPES in Rust.
    const vec4 shapes[7] = vec4[7](
        vec4(1.0, 0.0, 0.0, 1.0),
        vec4(1.0, 0.0, TWO_THIRDS, TWO_THIRDS),
        vec4(1.0, 0.0, -THIRD, TWO_THIRDS),
        vec4(0.0, 1.0, TWO_THIRDS, TWO_THIRDS),
        vec4(0.0, 1.0, TWO_THIRDS, -THIRD),
        vec4(-1.0, 1.0, -FOUR_THIRDS, TWO_THIRDS),
        vec4(-1.0, 1.0, -THIRD, -THIRD));
    PatternConstants o = PatternConstants(0.0, 0.0, 0.0, 0.0);
    for (int s = 0; s < 7; ++s) {
        P vec3 u = e1 * shapes[s].x + e2 * shapes[s].y;
        P vec3 v = e1 * shapes[s].z + e2 * shapes[s].w;
        P vec2 kd = enclosing_radius2(u, v);
        P float k = sqrt(kd.x);
        P float d = sqrt(kd.y);
        if (s == 0) {
            o.sqrt_k1 = k;
            o.diam1 = d;
        }
        o.sqrt_k = rmax(o.sqrt_k, k);
        o.diam = rmax(o.diam, d);
    }
    return o;
}

// ---------------------------------------------------------------------------------------------
// Per-triangle and per-light geometry
// ---------------------------------------------------------------------------------------------

// Pattern scales: what |X delta| and |N delta| are replaced by.
struct Scale {
    float a;
    float b;
};

// See `Frame` in Rust.
struct Frame {
    vec3 vertices[3];
    vec3 eye;
    vec3 center;
    float rho_x;
    Scale s1;
    Scale sn;
    Scale d1;
    Scale dn;
    Cone n_cone;
    float r_n;
    float n_max_len;
    vec3 normals[3];
    vec3 unit_normals[3];
    vec3 plane;
    Cone v_cone;
    float e_min;
    vec3 v_center;
};

Frame make_frame(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec3 eye) {
    Frame f;
    f.vertices = vec3[3](p0, p1, p2);
    f.eye = eye;
    P vec3 center = (p0 + p1 + p2) / 3.0;
    f.center = center;
    f.rho_x = rmax(rmax(len(p0 - center), len(p1 - center)), len(p2 - center));
    PatternConstants px = pattern_constants(p1 - p0, p2 - p0);
    PatternConstants pn = pattern_constants(n1 - n0, n2 - n0);
    f.n_cone = cone_of(n0, n1, n2);
    P float longest = rmax(rmax(len(n0), len(n1)), len(n2));
    P float r_n = min_length(n0, n1, n2, f.n_cone);
    if (!(r_n > 1.0e-6 * longest)) {
        r_n = 0.0;
    }
    f.r_n = r_n;
    P vec3 to_eye0 = eye - p0;
    P vec3 to_eye1 = eye - p1;
    P vec3 to_eye2 = eye - p2;
    f.v_cone = cone_of(to_eye0, to_eye1, to_eye2);
    f.e_min = min_length(to_eye0, to_eye1, to_eye2, f.v_cone);
    f.s1 = Scale(px.sqrt_k1, pn.sqrt_k1);
    f.sn = Scale(px.sqrt_k, pn.sqrt_k);
    f.d1 = Scale(px.diam1, pn.diam1);
    f.dn = Scale(px.diam, pn.diam);
    f.n_max_len = longest;
    f.normals = vec3[3](n0, n1, n2);
    f.unit_normals = vec3[3](unit(n0), unit(n1), unit(n2));
    P vec3 c = cross3(p1 - p0, p2 - p0);
    P float plane_scale = len(p1 - p0) * len(p2 - p0);
    f.plane = len(c) > 1.0e-6 * plane_scale ? unit(c) : vec3(0.0);
    f.v_center = unit(eye - center);
    return f;
}

// See `LightSetup` in Rust.
struct LightSetup {
    float plane_sin;
    float inv_d;
    vec2 psi_nl;
    bool straddle;
    Cone h_cone;
    float m_min;
    vec2 psi_nh;
    vec2 psi_nv;
    int nv_sign;
    vec2 psi_lv;
    // A polygonal light, and the range of the emitter's angle (see `LightSetup` in Rust).
    bool area;
    vec2 emitter;
};

// Accumulated bounds (see `Sums`): per term and channel, levels 1 and >= 2 (Uniform split
// only), and all terms at levels >= 2.
vec3 sum_h1[TERM_COUNT];
vec3 sum_hn[TERM_COUNT];
vec3 sum_tn;
vec3 sum_lin1;
vec3 sum_linn;
vec3 sum_jumps;
vec3 sum_jumps1;
vec3 sum_range;
vec3 sum_one;

// The range of the angle between n and w from the range q of n.w over the triangle and bounds
// on |w| (see `cosine_range_of`); the sign of n.w goes to `sign_out`.
P vec2 cosine_range_of(Frame frame, Cone w_cone, vec2 q, float w_max, float w_min, out int sign_out) {
    P vec2 psi = psi_range(frame.n_cone, w_cone);
    P float p0 = psi.x;
    P float p1 = psi.y;
    P float q_lo = q.x;
    P float q_hi = q.y;
    P float scale = frame.n_max_len * w_max;
    P float tol = 1.0e-5 * scale;
    int sign_of = q_lo > tol ? SIGN_POSITIVE : (q_hi < -tol ? SIGN_NON_POSITIVE : SIGN_BOTH);
    sign_out = sign_of;
    if (q_lo > tol && scale > 0.0) {
        p1 = rmin(p1, est_acos(rmin(q_lo / scale, 1.0)) + ANGLE_PAD);
    }
    P float denom = frame.r_n * w_min;
    if (q_hi > 0.0 && denom > 0.0) {
        p0 = rmax(p0, est_acos(rmin(q_hi / denom, 1.0)) - ANGLE_PAD);
    }
    if (sign_of == SIGN_NON_POSITIVE) {
        p0 = rmax(p0, HALF_PI);
    }
    if (p0 > p1) {
        p0 = p1;
    }
    return vec2(p0, p1);
}

// Range of the angle between n and the field normalize(sum l_k w_k), and the sign of n.w.
// Returns the range; the sign goes to `sign_out`.
P vec2 cosine_range(Frame frame, Cone w_cone, vec3 w[3], out int sign_out) {
    P vec2 q = bilinear_range(frame.normals, w);
    P float w_max = rmax(rmax(len(w[0]), len(w[1])), len(w[2]));
    P float w_min = min_length(w[0], w[1], w[2], w_cone);
    return cosine_range_of(frame, w_cone, q, w_max, w_min, sign_out);
}

// Where a polygonal light is as seen from the triangle (see `AreaGeometry` in Rust).
struct AreaGeometry {
    Cone cone;
    float d_min;
    vec2 q;
    float w_max;
    vec2 emitter;
};

// `area_geometry` in Rust: 0 with the geometry, 1 when the triangle is behind the emitter (it
// receives nothing), 2 when the emitter's plane cuts the triangle (a discontinuity).
int area_geometry(Frame frame, GpuPolygonLight light, out AreaGeometry g) {
    int count = light.info.x;
    P vec3 y0 = light.vertices[0].xyz;
    P vec3 normal = light.normal.xyz;
    P float side[3] = float[3](dot3(normal, frame.vertices[0] - y0), dot3(normal, frame.vertices[1] - y0),
                               dot3(normal, frame.vertices[2] - y0));
    if (side[0] <= 0.0 && side[1] <= 0.0 && side[2] <= 0.0) {
        return 1;
    }
    P float reach = 0.0;
    for (int k = 0; k < 3; ++k) {
        reach = rmax(reach, len(frame.vertices[k] - y0));
    }
    P float tol = 1.0e-5 * reach;
    if (!(side[0] > tol && side[1] > tol && side[2] > tol)) {
        return 2;
    }
    P vec3 light_centre = vec3(0.0);
    for (int j = 0; j < 8; ++j) {
        if (j < count) {
            light_centre = light_centre + light.vertices[j].xyz;
        }
    }
    light_centre = light_centre / float(count);
    P vec3 axis = unit(light_centre - frame.center);
    P float half_angle = 0.0;
    P float d_min = 3.4028235e38;
    P float w_max = 0.0;
    P float q_lo = 3.4028235e38;
    P float q_hi = -3.4028235e38;
    for (int j = 0; j < 8; ++j) {
        if (j < count) {
            P vec3 yj = light.vertices[j].xyz;
            P vec3 w[3] = vec3[3](yj - frame.vertices[0], yj - frame.vertices[1], yj - frame.vertices[2]);
            for (int k = 0; k < 3; ++k) {
                half_angle = rmax(half_angle, angle(axis, w[k]));
                d_min = rmin(d_min, dot3(w[k], axis));
                w_max = rmax(w_max, len(w[k]));
            }
            P vec2 q = bilinear_range(frame.normals, w);
            q_lo = rmin(q_lo, q.x);
            q_hi = rmax(q_hi, q.y);
        }
    }
    half_angle = half_angle + ANGLE_PAD;
    g.cone = (is_zero(axis) || !(half_angle < MAX_HALF)) ? no_cone() : Cone(axis, half_angle);
    if (g.cone.spread >= PI || !(d_min > 0.0)) {
        d_min = 0.0;
    }
    g.d_min = d_min;
    g.q = vec2(q_lo, q_hi);
    g.w_max = w_max;
    g.emitter = psi_range(Cone(-normal, 0.0), g.cone);
    return 0;
}

// Diffuse and specular colour weights of a light (see `weights`).
void light_weights(GpuMaterial m, vec3 radiance, out vec3 diff_w, out vec3 spec_w) {
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        diff_w = radiance * m.diffuse.rgb;
        spec_w = vec3(0.0);
    } else if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        diff_w = radiance * m.diffuse.rgb;
        spec_w = radiance * m.specular.rgb;
    } else {
        diff_w = radiance * m.diffuse.rgb;
        spec_w = radiance;
    }
}

// ---------------------------------------------------------------------------------------------
// Jets of one light
// ---------------------------------------------------------------------------------------------

// GGX D(n.h) jet (see `ggx_d_jet`).
Jet ggx_d_jet(Jet c, float p0, float p1, float w, float alpha) {
    P float a2 = alpha * alpha;
    P float beta = 1.0 - a2;
    P float coef = 4.0 * a2 * beta / PI;
    P float sp0 = est_sin(p0);
    P float sp1 = est_sin(p1);
    P float s0 = sp0 * sp0;
    P float s1 = sp1 * sp1;
    P float b1 = 5.0 * beta + 2.0 * a2;
    P float r1 = 2.0 * a2 / rmax(b1 + sqrt(rmax(b1 * b1 - 16.0 * a2 * beta, 0.0)), 1.0e-30);
    P float x1 = clamp(r1, s0, s1);
    P float u1 = a2 + beta * x1;
    P float d1 = sqrt(rmax(x1 * (1.0 - x1), 0.0)) / (u1 * u1 * u1);
    P float big_a = a2 + 6.0 * beta;
    P float b2 = 3.0 * big_a + 10.0 * a2;
    P float r2 = 2.0 * big_a * a2
        / rmax(beta * (b2 + sqrt(rmax(b2 * b2 - 40.0 * big_a * a2, 0.0))), 1.0e-30);
    P float x2 = clamp(r2, s0, s1);
    P float u2 = a2 + beta * x2;
    P float d2 = x2 * (big_a - 5.0 * beta * x2) / (u2 * u2 * u2 * u2);
    P float u0 = a2 + beta * s0;
    Jet o = jet_constant(a2 / (PI * u0 * u0));
    o.g = gmul(gc(coef * d1), w);
    P float slope = gc(coef * est_cos(p0) / (u0 * u0 * u0));
    o.h = gmul(c.h, slope);
    P float w2 = gmul(w, w);
    P float dd = gc(coef * d2);
    P float dh = gmul(dd, w2);
    if (booked(T_D)) {
        o.h = gc(o.h + dh);
    }
    return guard_jet(o);
}

// The roughness-dependent GGX factors G, V and D at one alpha (see `ggx_factor_jets`).
void ggx_factor_jets(Field n, Field l, Field v, Field h, LightSetup st, vec2 nh, float w_nh,
                     float alpha, out Jet gjet, out Jet vjet, out Jet djet) {
    P float h0 = nh.x;
    P float h1 = nh.y;
    P float k = 0.5 * alpha;

    // G = c/(c(1-k)+k) with c = n.l >= 0.
    P vec2 nl = vec2(st.psi_nl.x, rmin(st.psi_nl.y, HALF_PI));
    Jet c_g = cosine(n, l, nl);
    P float c0 = rmax(est_cos(nl.y), 0.0);
    P float c1 = est_cos(nl.x);
    P float q0 = c0 * (1.0 - k) + k;
    P float q1 = c1 * (1.0 - k) + k;
    P float g1 = k / (q0 * q0);
    P float g2 = 2.0 * k * (1.0 - k) / (q0 * q0 * q0);
    gjet = jet_constant(0.0);
    gjet.h = gmul(c_g.h, g1);
    P float cg2 = gmul(c_g.g, c_g.g);
    P float hg = gmul(g2, cg2);
    if (booked(T_V)) {
        gjet.h = gc(gjet.h + hg);
    }
    gjet.m = c1 / q1;
    gjet.g = gmul(g1, c_g.g);
    gjet = guard_jet(gjet);

    // V_v = 1/(max(n.v, 0)(1-k)+k): constant 1/k where n.v <= 0 throughout.
    if (st.nv_sign == SIGN_NON_POSITIVE) {
        vjet = jet_constant(1.0 / k);
    } else {
        P vec2 nv = vec2(st.psi_nv.x, rmin(st.psi_nv.y, HALF_PI));
        Jet c_v = cosine(n, v, nv);
        P float q = rmax(est_cos(nv.y), 0.0) * (1.0 - k) + k;
        P float v1 = (1.0 - k) / (q * q);
        P float v2 = 2.0 * (1.0 - k) * (1.0 - k) / (q * q * q);
        vjet = jet_constant(0.0);
        vjet.h = gmul(c_v.h, v1);
        P float cv2 = gmul(c_v.g, c_v.g);
        P float hv = gmul(v2, cv2);
        if (booked(T_V)) {
            vjet.h = gc(vjet.h + hv);
        }
        vjet.m = 1.0 / q;
        vjet.g = gmul(v1, c_v.g);
        vjet = guard_jet(vjet);
    }

    // D(t), t = n.h.
    if (st.psi_nh.x >= HALF_PI) {
        djet = jet_constant(alpha * alpha / PI);
    } else {
        Jet c_nh = cosine(n, h, vec2(h0, h1));
        djet = ggx_d_jet(c_nh, h0, h1, w_nh, alpha);
    }
}

// Elementwise larger bounds of two jets (see `jet_max`).
Jet jet_max(Jet a, Jet b) {
    return Jet(rmax(a.m, b.m), rmax(a.g, b.g), rmax(a.h, b.h));
}

// The jets of one light's diffuse part and (per channel) specular part at pattern scale s.
void light_jets(Frame frame, GpuMaterial material, vec2 param, LightSetup st, Scale s,
                out Jet diffuse, out Jet spec[3]) {
    Field n = Field(gc(s.b / frame.r_n), 0.0, T_NORMAL);
    Field l = Field(gmul(s.a, st.inv_d), 0.0, T_LIGHT);
    Jet att;
    if (st.inv_d > 0.0) {
        P float id = st.inv_d;
        P float id2 = gmul(id, id);
        P float a_id = gmul(s.a, id);
        P float sg = st.plane_sin;
        att = jet_constant(id2);
        P float a_id2 = gmul(a_id, a_id);
        P float k = rmax(6.0 * sg * sg - 2.0, 2.0);
        P float ha = gmul(k * a_id2, id2);
        if (booked(T_ATTENUATION)) {
            att.h = ha;
        }
        att.g = gmul(2.0 * sg * a_id, id2);
    } else {
        att = jet_constant(1.0);
    }
    if (st.area) {
        // Each point of the polygon: a point light with the emitter's cosine.
        Field fixed_direction = Field(0.0, 0.0, T_LIGHT);
        att = product2(att, cosine(fixed_direction, l, st.emitter));
    }
    Jet c_nl = cosine(n, l, st.psi_nl);
    diffuse = product2(att, c_nl);
    Jet zero = jet_constant(0.0);
    spec[0] = zero;
    spec[1] = zero;
    spec[2] = zero;
    if (MATERIAL_KIND == MATERIAL_LAMBERT || st.area) {
        return;
    }

    Field v = Field(gc(s.a / frame.e_min), 0.0, T_VIEW);
    Field h = Field(gc((l.w + v.w) / st.m_min), gc(K23 * (l.w * l.w + v.w * v.w) / st.m_min), T_HALF);
    P float h0 = st.psi_nh.x;
    P float h1 = rmin(st.psi_nh.y, HALF_PI);
    P float w_nh = gc(n.w + h.w);

    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        if (st.psi_nh.x >= HALF_PI) {
            return;
        }
        // A shininess anywhere in [s0, s1] (see Rust).
        P float s0 = param.x;
        P float s1 = param.y;
        Jet c_nh = cosine(n, h, vec2(h0, h1));
        P float chi = est_cos(h0);
        Jet t = jet_constant(est_pow(chi, s0));
        t.g = gc(s1 * max_cos_sin(s0 - 1.0, 1.0, h0, h1) * w_nh);
        t.h = gmul(c_nh.h, s1 * est_pow(chi, s0 - 1.0));
        if (s1 > 1.0) {
            P float k = s1 * (s1 - 1.0) * max_cos_sin(s0 - 2.0, 2.0, h0, h1);
            P float w2 = gmul(w_nh, w_nh);
            P float hp = gmul(k, w2);
            if (booked(T_POWER)) {
                t.h = gc(t.h + hp);
            }
        }
        t = guard_jet(t);
        Jet sp = product2(att, t);
        spec[0] = sp;
        spec[1] = sp;
        spec[2] = sp;
        return;
    }

    // GGX: D, G and V at the ends of the roughness range and where D peaks (see Rust).
    P float alpha_lo = max(param.x * param.x, GGX_MIN_ALPHA);
    P float alpha_hi = max(param.y * param.y, GGX_MIN_ALPHA);
    P float alphas[3] = float[3](alpha_lo, alpha_lo, alpha_lo);
    int alpha_count = 1;
    if (TEXTURED && alpha_hi > alpha_lo) {
        alphas[1] = alpha_hi;
        alpha_count = 2;
        if (st.psi_nh.x < HALF_PI) {
            P float sh0 = est_sin(h0);
            P float s2 = sh0 * sh0;
            alphas[2] = rmin(rmax(sqrt(s2 / (1.0 - s2)), alpha_lo), alpha_hi);
            alpha_count = 3;
        }
    }
    Jet gjet;
    Jet vjet;
    Jet djet;
    ggx_factor_jets(n, l, v, h, st, vec2(h0, h1), w_nh, alphas[0], gjet, vjet, djet);
    for (int i = 1; i < alpha_count; ++i) {
        Jet g2;
        Jet v2;
        Jet d2;
        ggx_factor_jets(n, l, v, h, st, vec2(h0, h1), w_nh, alphas[i], g2, v2, d2);
        gjet = jet_max(gjet, g2);
        vjet = jet_max(vjet, v2);
        djet = jet_max(djet, d2);
    }

    // v.h = |l + v|/2.
    P float t0 = clamp(est_cos(0.5 * st.psi_lv.y), 0.0, 1.0);
    P float gt = gc(0.5 * (l.w + v.w));
    P float ht_light = gc(0.5 * K23 * l.w * l.w);
    P float ht_view = gc(0.5 * K23 * v.w * v.w);
    P float ht_half = gc(0.5 * (l.w + v.w) * (l.w + v.w) / st.m_min);
    P float ht = est_term == T_ALL ? ht_light + ht_view + ht_half
        : (est_term == T_LIGHT ? ht_light
        : (est_term == T_VIEW ? ht_view : (est_term == T_HALF ? ht_half : 0.0)));
    P float om = 1.0 - t0;
    P float om2 = om * om;
    P float om3 = om * om2;
    P float om4 = om2 * om2;
    P float om5 = om * om4;
    for (int c = 0; c < 3; ++c) {
        P float f0c = material.specular[c];
        P float fm = f0c + (1.0 - f0c) * om5;
        P float f1 = 5.0 * (1.0 - f0c) * om4;
        P float f2 = 20.0 * (1.0 - f0c) * om3;
        Jet fjet = jet_constant(0.0);
        fjet.h = gmul(ht, f1);
        P float gt2 = gmul(gt, gt);
        P float hf = gmul(f2, gt2);
        if (booked(T_F)) {
            fjet.h = gc(fjet.h + hf);
        }
        fjet.m = fm;
        fjet.g = gmul(f1, gt);
        fjet = guard_jet(fjet);
        Jet f[5] = Jet[5](att, djet, fjet, gjet, vjet);
        Jet p = product(f, 5);
        spec[c].m = 0.25 * p.m;
        spec[c].g = 0.25 * p.g;
        spec[c].h = gmul(p.h, 0.25);
    }
}

// The terms that can be non-zero for the scene's material kind, in term order.
int active_term_count() {
    return MATERIAL_KIND == MATERIAL_LAMBERT ? 5 : (MATERIAL_KIND == MATERIAL_BLINN_PHONG ? 7 : 10);
}
int active_term(int pass) {
    const int lambert[5] = int[5](T_NORMAL, T_LIGHT, T_DOT, T_ATTENUATION, T_CROSS);
    const int blinn_phong[7] = int[7](T_NORMAL, T_LIGHT, T_HALF, T_DOT, T_ATTENUATION, T_POWER, T_CROSS);
    const int ggx[10] = int[10](T_NORMAL, T_LIGHT, T_VIEW, T_HALF, T_DOT, T_ATTENUATION, T_D, T_F, T_V, T_CROSS);
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return lambert[pass];
    }
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        return blinn_phong[pass];
    }
    return ggx[pass];
}

// ---------------------------------------------------------------------------------------------
// One light
// ---------------------------------------------------------------------------------------------

// Smallest real n > 0 with a/n^2 + b/n + c <= eps (infinity if none).
P float level_for(float a, float b, float c, float eps) {
    if (a <= 0.0 && b <= 0.0) {
        return c <= eps ? 0.0 : infinity();
    }
    P float room = eps - c;
    if (!(room > 0.0)) {
        return infinity();
    }
    P float n = (b + sqrt(b * b + 4.0 * a * room)) / (2.0 * room);
    return is_nan(n) ? infinity() : n;
}

// The variation sup|f(a) - f(a')| of one light's specular part for a parameter anywhere in
// `param` (see `parameter_variation`).
P vec3 parameter_variation(vec2 param, LightSetup st, vec3 spec_sup) {
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return vec3(0.0);
    }
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        P float s0 = param.x;
        P float s1 = param.y;
        if (!(s1 > s0) || st.psi_nh.x >= HALF_PI) {
            return vec3(0.0);
        }
        P float t_lo = rmax(est_cos(rmin(st.psi_nh.y, HALF_PI)), 0.0);
        P float t_hi = est_cos(st.psi_nh.x);
        P float t = rmin(rmax(est_pow(s0 / s1, 1.0 / (s1 - s0)), t_lo), t_hi);
        P float upper = est_pow(t, s0);
        P float att = st.inv_d > 0.0 ? st.inv_d * st.inv_d : 1.0;
        P float variation = ((upper - est_pow(t, s1)) * SAFETY + 1.0e-6 * upper) * att;
        return vec3(rmax(variation, 0.0));
    }
    P float alpha_lo = max(param.x * param.x, GGX_MIN_ALPHA);
    P float alpha_hi = max(param.y * param.y, GGX_MIN_ALPHA);
    if (!(alpha_hi > alpha_lo)) {
        return vec3(0.0);
    }
    P float share = rmin(4.0 * LN_2 * est_log2(alpha_hi / alpha_lo), 1.0);
    return spec_sup * (share * SAFETY);
}

// The GGX distribution at n.h = c: brdf.glsl's ggx_d, `precise` (no contraction, as in Rust).
P float ggx_d_value(float c, float alpha) {
    P float a2 = alpha * alpha;
    P float d = c * c * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// (2 - v) sup f/p_light + v sup f/p_brdf (see `mis_bound` in Rust).
P float mis_bound(float light_part, float brdf_part) {
    return gc(gmul(2.0 - MIS_VISIBILITY, light_part) + gmul(MIS_VISIBILITY, brdf_part));
}

// An upper bound of a polygonal light's sampled specular part on the triangle, per channel
// (see `polygon_specular_bound` in Rust for the derivation).
P vec3 polygon_specular_bound(GpuMaterial material, vec2 param, LightSetup st, GpuPolygonLight light) {
    if (MATERIAL_KIND == MATERIAL_LAMBERT || !st.area) {
        return vec3(0.0);
    }
    P vec3 radiance = light.radiance.rgb;
    P float cos_l_min = rmax(est_cos(st.psi_nl.y), 0.0);
    P float cos_l_max = rmin(est_cos(st.psi_nl.x), 1.0);
    P float cos_y_max = rmin(est_cos(st.emitter.x), 1.0);
    P float omega = gc(rmin(gmul(light.normal.w * cos_y_max, gmul(st.inv_d, st.inv_d)), 2.0 * PI));
    P float h0 = st.psi_nh.x;
    P float h1 = st.psi_nh.y;
    bool projected = POLYGON_TECHNIQUE == 0;
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        P float s0 = param.x;
        P float peak = h0 < HALF_PI ? est_pow(est_cos(h0), s0) : 0.0;
        P float light_part = gmul(peak, omega);
        if (projected && light_part > 0.0) {
            light_part = gc(light_part * cos_l_max / cos_l_min);
        }
        P float brdf_part = 8.0 * PI / (s0 + 1.0);
        P vec3 b = radiance * material.specular.rgb * mis_bound(light_part, brdf_part);
        return b;
    }
    P float alpha_lo = max(param.x * param.x, GGX_MIN_ALPHA);
    P float alpha_hi = max(param.y * param.y, GGX_MIN_ALPHA);
    P float k = 0.5 * alpha_lo;
    P float cos_h = h0 < HALF_PI ? est_cos(h0) : 0.0;
    P float d_max = rmax(ggx_d_value(cos_h, alpha_lo), ggx_d_value(cos_h, alpha_hi));
    if (alpha_hi > alpha_lo && cos_h > 0.0) {
        P float s2 = rmax(1.0 - cos_h * cos_h, 0.0);
        P float peak = rmin(rmax(sqrt(s2 / (cos_h * cos_h)), alpha_lo), alpha_hi);
        d_max = rmax(d_max, ggx_d_value(cos_h, peak));
    }
    P float cos_v_min = rmax(est_cos(st.psi_nv.y), 0.0);
    P float v_side = cos_v_min * (1.0 - k) + k;
    P float v_max = 1.0 / ((cos_l_min * (1.0 - k) + k) * v_side);
    P float light_part = h0 < HALF_PI ? gmul(gmul(0.25 * d_max, v_max), omega * cos_l_max) : 0.0;
    P float cos_h_min = rmax(est_cos(rmin(h1, HALF_PI)), 0.0);
    P float brdf_part = v_side * cos_h_min > 0.5 / v_max ? 1.0 / (v_side * cos_h_min) : 2.0 * v_max;
    P float om = 1.0 - clamp(est_cos(0.5 * st.psi_lv.y), 0.0, 1.0);
    P float om2 = om * om;
    P float om4 = om2 * om2;
    P float om5 = om * om4;
    P vec3 f_max = material.specular.rgb + (vec3(1.0) - material.specular.rgb) * om5;
    P vec3 b = radiance * f_max * mis_bound(light_part, brdf_part);
    return b;
}

// Relaxed: a bound on |n.l| over a sub-triangle the terminator crosses, of diameters `d` (see
// `terminator_band`).
P float terminator_band(Frame frame, LightSetup st, Scale d) {
    return gc(d.b / frame.r_n + d.a * st.inv_d);
}

// Relaxed: the factor <= 1 by which the specular lobe's sup over the band 0 < n.l <= beta is
// below its sup over the triangle (see `lobe_band_share`).
P float lobe_band_share(vec2 param, LightSetup st, float beta) {
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return 0.0;
    }
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        // The angle from n to h is at least the angle from n to l (>= acos beta) minus half
        // the angle between l and v.
        P float h0 = st.psi_nh.x;
        P float edge = est_acos(rmin(beta, 1.0)) - ANGLE_PAD - 0.5 * st.psi_lv.y;
        if (!(edge > h0)) {
            return 1.0;
        }
        P float ce = est_cos(edge);
        P float ch = est_cos(h0);
        if (!(ch > 0.0) || !(ce < ch)) {
            return 1.0;
        }
        if (!(ce > 0.0)) {
            return 0.0;
        }
        return est_pow(ce / ch, param.x);
    }
    // GGX: G(c) = c/(c(1-k)+k) on the band, at the smallest k, against G(c_max).
    P float k = 0.5 * max(param.x * param.x, GGX_MIN_ALPHA);
    P float c1 = est_cos(st.psi_nl.x);
    if (!(beta < c1)) {
        return 1.0;
    }
    return (beta * (c1 * (1.0 - k) + k)) / (c1 * (beta * (1.0 - k) + k));
}

// Relaxed: the jump of the specular lobe that n.l > 0 switches on, on the band of width beta.
P vec3 terminator_jump(vec3 spec_w, vec3 spec_sup, vec2 param, LightSetup st, float beta) {
    if (!st.straddle || st.area) {
        return vec3(0.0);
    }
    return spec_w * spec_sup * (lobe_band_share(param, st, beta) * SAFETY);
}

// Adds one light's bounds to the sums; returns a fallback reason (REASON_NONE if none), as
// `add_light` in Rust. `polygon` >= 0: the polygonal light of that index (`position` and
// `radiance` unused); else `point`: a point light at `position`, or a directional light whose
// travel direction is `position`.
int add_light(Frame frame, GpuMaterial material, vec2 param, bool point, vec3 position,
              vec3 radiance, int polygon, float top, float eps) {
    bool area = polygon >= 0;
    AreaGeometry geometry;
    GpuPolygonLight light;
    if (area) {
        light = polygon_lights[polygon];
        if (is_zero(light.radiance.rgb)) {
            return REASON_NONE;
        }
        int where_is = area_geometry(frame, light, geometry);
        if (where_is == 1) {
            return REASON_NONE;
        }
        if (where_is == 2) {
            return REASON_DISCONTINUITY;
        }
        if (!(geometry.d_min * geometry.d_min > MIN_D2_SAFE)) {
            return REASON_SINGULAR;
        }
        radiance = light.radiance.rgb * light.normal.w;
    }
    if (is_zero(radiance)) {
        return REASON_NONE;
    }
    vec3 diff_w;
    vec3 spec_w;
    light_weights(material, radiance, diff_w, spec_w);
    Cone l_cone;
    P float inv_d;
    P vec3 l_center;
    P vec3 l_vectors[3];
    if (area) {
        l_cone = geometry.cone;
        inv_d = 1.0 / geometry.d_min;
        l_center = l_cone.axis;
    } else if (point) {
        l_vectors[0] = position - frame.vertices[0];
        l_vectors[1] = position - frame.vertices[1];
        l_vectors[2] = position - frame.vertices[2];
        l_cone = cone_of(l_vectors[0], l_vectors[1], l_vectors[2]);
        P float d_min = min_length(l_vectors[0], l_vectors[1], l_vectors[2], l_cone);
        // The falloff is clamped at d^2 = 1e-8: only smooth (and bounded) beyond it.
        if (!(d_min * d_min > MIN_D2_SAFE)) {
            if (is_zero(diff_w) && is_zero(spec_w)) {
                return REASON_NONE;
            }
            return REASON_SINGULAR;
        }
        inv_d = 1.0 / d_min;
        l_center = unit(position - frame.center);
    } else {
        P vec3 l = unit(-position);
        l_cone = Cone(l, 0.0);
        inv_d = 0.0;
        l_center = l;
        l_vectors = vec3[3](l, l, l);
    }
    if (is_zero(diff_w) && is_zero(spec_w)) {
        return REASON_NONE;
    }
    if (frame.r_n <= 0.0) {
        return REASON_SINGULAR;
    }
    int l_sign;
    P vec2 psi_nl = area ? cosine_range_of(frame, l_cone, geometry.q, geometry.w_max, geometry.d_min, l_sign)
                         : cosine_range(frame, l_cone, l_vectors, l_sign);
    if (l_sign == SIGN_NON_POSITIVE) {
        return REASON_NONE;
    }
    bool straddle = l_sign == SIGN_BOTH;
    if (straddle && DISCONTINUITY == 0) {
        return REASON_DISCONTINUITY;
    }
    LightSetup setup;
    setup.plane_sin = 1.0;
    setup.inv_d = inv_d;
    setup.psi_nl = psi_nl;
    setup.straddle = straddle;
    setup.h_cone = no_cone();
    setup.m_min = 0.0;
    setup.psi_nh = vec2(0.0, PI);
    setup.psi_nv = vec2(0.0, PI);
    setup.nv_sign = SIGN_BOTH;
    setup.psi_lv = vec2(0.0, PI);
    setup.area = area;
    setup.emitter = area ? geometry.emitter : vec2(0.0);
    if (!is_zero(frame.plane) && inv_d > 0.0) {
        P vec2 g = psi_range(l_cone, Cone(frame.plane, 0.0));
        setup.plane_sin = max_sin(g.x, g.y);
    }
    if (MATERIAL_KIND != MATERIAL_LAMBERT) {
        if (!(frame.e_min > 0.0)) {
            return REASON_SINGULAR;
        }
        P vec2 psi_lv = psi_range(l_cone, frame.v_cone);
        P float m_min = 2.0 * est_cos(0.5 * psi_lv.y);
        if (!(psi_lv.y < PI_MINUS_MILLI) || !(m_min > 0.0)) {
            return REASON_SINGULAR;
        }
        // A cone for h, the tighter of two (see Rust).
        P float speed = (inv_d + 1.0 / frame.e_min) / m_min;
        P float half_a = speed * frame.rho_x + ANGLE_PAD;
        P vec3 axis_a = unit(l_center + frame.v_center);
        P vec3 m0 = l_cone.axis + frame.v_cone.axis;
        P float delta = 2.0 * est_sin(0.5 * l_cone.spread) + 2.0 * est_sin(0.5 * frame.v_cone.spread);
        P float half_b = delta < len(m0) ? est_asin(delta / len(m0)) + ANGLE_PAD : PI;
        P vec3 h_axis;
        P float h_half;
        // (a) follows one light point; a polygon needs (b), which holds for all of them.
        if (half_b < half_a || area) {
            h_axis = unit(m0);
            h_half = half_b;
        } else {
            h_axis = axis_a;
            h_half = half_a;
        }
        setup.h_cone = (is_zero(h_axis) || !(h_half < MAX_HALF)) ? no_cone() : Cone(h_axis, h_half);
        setup.m_min = m_min;
        setup.psi_lv = psi_lv;
        P vec2 c_nh = psi_range(frame.n_cone, setup.h_cone);
        if (setup.h_cone.spread < PI) {
            setup.psi_nh = vec2(
                rmax(c_nh.x, hull_distance(setup.h_cone.axis, frame.unit_normals) - setup.h_cone.spread),
                rmin(c_nh.y, hull_max_angle(setup.h_cone.axis, frame.unit_normals) + setup.h_cone.spread));
        } else {
            setup.psi_nh = c_nh;
        }
        P vec3 v_vectors[3] = vec3[3](frame.eye - frame.vertices[0], frame.eye - frame.vertices[1],
                                      frame.eye - frame.vertices[2]);
        int nv_sign;
        setup.psi_nv = cosine_range(frame, frame.v_cone, v_vectors, nv_sign);
        setup.nv_sign = nv_sign;
        // A polygon's sampled specular part is bounded by its range: kinks do not matter.
        if (area) {
        } else if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
            // max(n.h, 0)^s is C^{1,1} across n.h = 0 only for s >= 2.
            if (setup.psi_nh.x < HALF_PI && setup.psi_nh.y >= HALF_PI && param.x < 2.0) {
                return REASON_DISCONTINUITY;
            }
        } else {
            // max(n.v, 0) has a kink in V at n.v = 0.
            if (setup.nv_sign == SIGN_BOTH) {
                return REASON_DISCONTINUITY;
            }
        }
    }

    // This light's bounds at level 1 (index 0) and levels >= 2 (index 1): all terms in one
    // pass, and for the Uniform split one more pass per term (terms that are zero for every
    // light of this material are skipped: they add nothing).
    vec3 h[2][TERM_COUNT];
    P vec3 tot[2];
    if (SPLIT == 0) {
        for (int t = 0; t < TERM_COUNT; ++t) {
            h[0][t] = vec3(0.0);
            h[1][t] = vec3(0.0);
        }
    }
    P vec3 lin1 = vec3(0.0);
    P vec3 linn = vec3(0.0);
    P vec3 range = vec3(0.0);
    P vec3 spec_sup = vec3(0.0);
    // Relaxed: how far n.l can be from 0 on a crossed sub-triangle, at level 1 and per 1/L.
    P float band1 = 0.0;
    P float bandn = 0.0;
    if (setup.straddle) {
        band1 = terminator_band(frame, setup, frame.d1);
        bandn = terminator_band(frame, setup, frame.dn);
    }
    for (int level = 0; level < 2; ++level) {
        Scale s = level == 0 ? frame.s1 : frame.sn;
        Jet diff;
        Jet spec[3];
        if (SPLIT == 0) {
            for (int pass = 0; pass < active_term_count(); ++pass) {
                est_term = active_term(pass);
                light_jets(frame, material, param, setup, s, diff, spec);
                P vec3 spec_h = vec3(spec[0].h, spec[1].h, spec[2].h);
                P vec3 ht = (diff_w * diff.h + spec_w * spec_h) * (0.5 * SAFETY);
                h[level][est_term] = ht;
            }
        }
        est_term = T_ALL;
        light_jets(frame, material, param, setup, s, diff, spec);
        P vec3 spec_t = vec3(spec[0].h, spec[1].h, spec[2].h);
        tot[level] = (diff_w * diff.h + spec_w * spec_t) * (0.5 * SAFETY);
        // (The sups m do not depend on the pass.)
        P vec3 spec_m = vec3(spec[0].m, spec[1].m, spec[2].m);
        spec_sup = spec_m;
        // The contribution lies in [0, sup] and so does its interpolant.
        range = (diff_w * diff.m + spec_w * spec_m) * SAFETY;
        if (setup.straddle && level == 1) {
            // Relaxed: the diffuse kink adds 1/4 sup E' osc(n.l) (see Rust).
            P float att = setup.inv_d > 0.0 ? setup.inv_d * setup.inv_d : 1.0;
            lin1 = diff_w * (TERMINATOR_KINK * SAFETY * gmul(att, band1));
            linn = diff_w * (TERMINATOR_KINK * SAFETY * gmul(att, bandn));
        }
    }
    P vec3 other;
    if (area) {
        // The sampled specular part: no interpolation bound, its range.
        other = polygon_specular_bound(material, param, setup, light) * SAFETY;
        range = range + other;
    } else {
        // A textured parameter: its variation over the range, an n-independent term.
        other = spec_w * parameter_variation(param, setup, spec_sup);
    }
    P vec3 tot1 = tot[0];
    P vec3 totn = tot[1];
    P vec3 zero1 = terminator_jump(spec_w, spec_sup, param, setup, band1) + other;
    P vec3 zero_top = terminator_jump(spec_w, spec_sup, param, setup, bandn / top) + other;
    // Per channel: the smaller of the light's interpolation bound and its range.
    bool interpolated[3];
    for (int c = 0; c < 3; ++c) {
        P float at_n_max = totn[c] / (top * top) + linn[c] / top + zero_top[c];
        interpolated[c] = !(range[c] <= at_n_max);
    }
    // The jump at levels >= 2 at a lower bound of the final level (see Rust).
    P vec3 zero_inf = terminator_jump(spec_w, spec_sup, param, setup, 0.0) + other;
    P float low = 1.0;
    for (int c = 0; c < 3; ++c) {
        if (interpolated[c]) {
            low = rmax(low, level_for(totn[c], linn[c], zero_inf[c], eps));
        }
    }
    P vec3 zeron = terminator_jump(spec_w, spec_sup, param, setup, bandn / low) + other;
    for (int c = 0; c < 3; ++c) {
        P float one = rmin(tot1[c] + lin1[c] + zero1[c], range[c]);
        sum_one[c] = sum_one[c] + one;
        if (interpolated[c]) {
            if (SPLIT == 0) {
                for (int pass = 0; pass < active_term_count(); ++pass) {
                    int t = active_term(pass);
                    sum_h1[t][c] = sum_h1[t][c] + h[0][t][c];
                    sum_hn[t][c] = sum_hn[t][c] + h[1][t][c];
                }
            }
            sum_tn[c] = sum_tn[c] + totn[c];
            sum_lin1[c] = sum_lin1[c] + lin1[c];
            sum_linn[c] = sum_linn[c] + linn[c];
            sum_jumps1[c] = sum_jumps1[c] + zero1[c];
            sum_jumps[c] = sum_jumps[c] + zeron[c];
        } else {
            sum_range[c] = sum_range[c] + range[c];
        }
    }
    return REASON_NONE;
}

// ---------------------------------------------------------------------------------------------
// Shared edges and mixed patterns (see `pattern_level`, `uniform_level`, `patch_levels`)
// ---------------------------------------------------------------------------------------------

// The effective level of the hardware pattern with inner level `inner` and outer level
// `outer` on an edge, in 1/256, two 16-bit entries per word, index (inner-1)*64 + (outer-1).
// The same words as PATTERN_LEVELS in src/shading/estimator.rs (a test compares them).
uint PATTERN_LEVELS[2048] = uint[2048](
    0x01ff0100u, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu,
    0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu,
    0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu,
    0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu,
    0x01ff0100u, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu,
    0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu,
    0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu,
    0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu, 0x01ff01ffu,
    0x02000100u, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu,
    0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu,
    0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu,
    0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu, 0x02ff02ffu,
    0x02000100u, 0x03ff02ffu, 0x03ff0355u, 0x03ff03ffu, 0x03ff0399u, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu,
    0x03ff03c7u, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu,
    0x03ff03e1u, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu,
    0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu, 0x03ff03ffu,
    0x02000100u, 0x040002ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu,
    0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu,
    0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu,
    0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu, 0x04ff04ffu,
    0x02000100u, 0x040002ffu, 0x05ff0355u, 0x040004aau, 0x05000399u, 0x05ff0466u, 0x04aa0533u, 0x04000449u,
    0x048003c7u, 0x05000438u, 0x058004aau, 0x05ff051cu, 0x0533058du, 0x04aa04e8u, 0x04490476u, 0x04000422u,
    0x044003e1u, 0x047f041du, 0x04c0045au, 0x04ff0496u, 0x053f04d2u, 0x057f050eu, 0x05c0054au, 0x05ff0586u,
    0x058e05c2u, 0x0532055eu, 0x04e9050cu, 0x04aa04c8u, 0x0476048fu, 0x0448045fu, 0x04220434u, 0x04000410u,
    0x02000100u, 0x040002ffu, 0x05ff0460u, 0x059906ffu, 0x06ff04d8u, 0x06ff066au, 0x06ff06ffu, 0x0599062du,
    0x06a1052cu, 0x06ff060bu, 0x06ff06ffu, 0x06ff06ffu, 0x06ff06ffu, 0x06ff06ffu, 0x062d068cu, 0x059905ddu,
    0x061a055fu, 0x06a005d4u, 0x06ff0650u, 0x06ff06d2u, 0x06ff06ffu, 0x06ff06ffu, 0x06ff06ffu, 0x06ff06ffu,
    0x06ff06ffu, 0x06ff06ffu, 0x06ff06ffu, 0x06ff06ffu, 0x068c06c4u, 0x062c065bu, 0x05dd0602u, 0x059905b9u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x07ff06ffu, 0x07ff0600u, 0x07ff0755u, 0x07ff07ffu, 0x07ff07ffu,
    0x07ff06ccu, 0x07ff0799u, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu,
    0x07ff0755u, 0x07ff07c5u, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu,
    0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu, 0x07ff07ffu,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu,
    0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu,
    0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu,
    0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu, 0x08ff08ffu,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x05b6065cu, 0x09ff054bu, 0x077f0755u, 0x065c06d7u, 0x05b605ffu,
    0x077f057bu, 0x09ff0709u, 0x08750866u, 0x077f07edu, 0x06d70723u, 0x065d0695u, 0x0600062bu, 0x05b605d9u,
    0x06890597u, 0x077f065cu, 0x08a30740u, 0x09fd084bu, 0x091f091au, 0x087408c5u, 0x07ee082du, 0x077f07b3u,
    0x0724074fu, 0x06d606fcu, 0x069606b5u, 0x065c0678u, 0x062b0643u, 0x05ff0615u, 0x05d905ebu, 0x05b605c7u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x06c406ffu, 0x09ff062fu, 0x096d0affu, 0x07b30869u, 0x06c4072cu,
    0x096d0672u, 0x0aff08b4u, 0x0aff0affu, 0x096d0a1du, 0x086908deu, 0x07b30806u, 0x072c076bu, 0x06c406f5u,
    0x07f50699u, 0x096c07b2u, 0x0aff090au, 0x0aff0ab8u, 0x0aff0affu, 0x0afe0affu, 0x0a1f0a86u, 0x096c09bfu,
    0x08df0921u, 0x086808a1u, 0x08070836u, 0x07b207dcu, 0x076b078eu, 0x072b074bu, 0x06f5070fu, 0x06c406dcu,
    0x02000100u, 0x040002ffu, 0x05ff049du, 0x060006ffu, 0x08920524u, 0x0bfd06f2u, 0x07a308aau, 0x060006aau,
    0x07330583u, 0x08920683u, 0x0a2807a3u, 0x0bfd08e6u, 0x092e09feu, 0x07a3084eu, 0x06ab071au, 0x0600064eu,
    0x069505bdu, 0x07320644u, 0x07dd06d4u, 0x0891076cu, 0x0954080fu, 0x0a2508beu, 0x0b0c0977u, 0x0bfb0a3fu,
    0x0a5a0adeu, 0x092b09b7u, 0x085008b8u, 0x07a207f5u, 0x071a075bu, 0x06aa06e0u, 0x064e0679u, 0x06000625u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x076d06ffu, 0x09ff0628u, 0x0bff08f0u, 0x0a1c0cfdu, 0x076d087au,
    0x095c06b2u, 0x0bd2083bu, 0x0cfd0a1du, 0x0cfd0c74u, 0x0cfd0cfdu, 0x0a1e0b51u, 0x087b0932u, 0x076d07e6u,
    0x08580708u, 0x095a07d7u, 0x0a8408beu, 0x0bcf09beu, 0x0cfd0adeu, 0x0cfd0c26u, 0x0cfd0cfdu, 0x0cfd0cfdu,
    0x0cfd0cfdu, 0x0cfd0cfdu, 0x0b550c1bu, 0x0a1a0aafu, 0x093209a1u, 0x087908d2u, 0x07e6082bu, 0x076d07a6u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x07ff06ffu, 0x09ff0600u, 0x0bfe0755u, 0x0dfe08aau, 0x07ff09ffu,
    0x090006ccu, 0x0a000799u, 0x0b000866u, 0x0c010931u, 0x0d0209feu, 0x0dfe0acbu, 0x0a010b9au, 0x07ff08dbu,
    0x08810755u, 0x08fd07c5u, 0x09810837u, 0x09fd08a8u, 0x0a7c091au, 0x0afb098du, 0x0b8209fdu, 0x0bfb0a6eu,
    0x0c830adeu, 0x0cfb0b54u, 0x0d850bccu, 0x0dfa0c3eu, 0x0b9a0caeu, 0x09fd0abcu, 0x08db095fu, 0x07ff0864u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09ff0780u, 0x0bff09b4u, 0x0dff0c2fu, 0x0ae80efdu,
    0x0cdb08cau, 0x0efd0a2cu, 0x0dbf0babu, 0x0efc0d42u, 0x0efd0efcu, 0x0efd0efdu, 0x0efd0efdu, 0x0ae80c90u,
    0x0bdf09b4u, 0x0cd70a7du, 0x0deb0b51u, 0x0efa0c2cu, 0x0efd0d11u, 0x0dc30e04u, 0x0efd0efau, 0x0efd0efdu,
    0x0efd0efdu, 0x0efd0efdu, 0x0efd0efdu, 0x0efd0efdu, 0x0efd0efdu, 0x0efa0efdu, 0x0c900da1u, 0x0ae80ba7u,
    0x02000100u, 0x040002ffu, 0x055504ffu, 0x080006ffu, 0x08e308ffu, 0x099a0affu, 0x0dff0cfeu, 0x0ffe0effu,
    0x0ffe0b54u, 0x0d540ca9u, 0x0bbb0e01u, 0x0bfe0da2u, 0x0dda0e4bu, 0x0ffe0ffeu, 0x0ffe0ffeu, 0x0ffe0ffeu,
    0x0ffe0d33u, 0x0ffe0dfau, 0x0ffe0ec9u, 0x0d570f92u, 0x0d730e45u, 0x0bbe0ea3u, 0x0d210ca4u, 0x0c020e7au,
    0x0e450d15u, 0x0de20fb1u, 0x0ffe0f61u, 0x0ffe0ffeu, 0x0ffe0ffeu, 0x0ffe0ffeu, 0x0ffe0ffeu, 0x0ffe0ffeu,
    0x02000100u, 0x040002ffu, 0x04db04ffu, 0x080006ffu, 0x081808ffu, 0x08290a63u, 0x0b550b0du, 0x10000effu,
    0x10fe10feu, 0x0c2410feu, 0x0a630dbau, 0x0a320bdau, 0x0b0a0bd0u, 0x0d350d1eu, 0x10fe106cu, 0x10fe10feu,
    0x10fe10feu, 0x10fe10feu, 0x0f0310feu, 0x0c26102eu, 0x0bb60ceau, 0x0a650c9bu, 0x0b010b18u, 0x0a350befu,
    0x0ba10af9u, 0x0b0f0cc0u, 0x0d180bfdu, 0x0d3d0e5bu, 0x106c0ea9u, 0x10fe10feu, 0x10fe10feu, 0x10fe10feu,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09ff08ffu, 0x0bff0affu, 0x0a7f0b24u, 0x099909ffu,
    0x11fd0945u, 0x0eff0ca9u, 0x0d320dffu, 0x0bff0c8au, 0x0b240b88u, 0x0a800accu, 0x0a000a3cu, 0x099909c9u,
    0x0cc0096du, 0x11f60c59u, 0x10490ec9u, 0x0efd0f92u, 0x0dfe0e76u, 0x0d310d93u, 0x0c8b0cd9u, 0x0bfe0c41u,
    0x0b890bc1u, 0x0b230b54u, 0x0acd0af7u, 0x0a7f0aa5u, 0x0a3c0a5du, 0x09ff0a1du, 0x09c909e3u, 0x099909b0u,
    0x02000100u, 0x040002ffu, 0x056d04ffu, 0x080006ffu, 0x09ff08ffu, 0x09e90affu, 0x0b900c59u, 0x0a7b0af6u,
    0x11ff0a18u, 0x114612f8u, 0x0eee0ff6u, 0x0d6a0e18u, 0x0c5a0cd6u, 0x0b910beeu, 0x0af60b3eu, 0x0a7b0ab5u,
    0x0e5c0a47u, 0x12f80dd9u, 0x12f812f8u, 0x11441211u, 0x0ff41091u, 0x0eec0f6au, 0x0e190e7cu, 0x0d680dbcu,
    0x0cd70d1bu, 0x0c590c95u, 0x0bef0c23u, 0x0b900bbeu, 0x0b3e0b67u, 0x0af50b19u, 0x0ab50ad4u, 0x0a7b0a97u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x07ff06ffu, 0x09ff0732u, 0x0bfe0affu, 0x09540a65u, 0x07ff0891u,
    0x0bff078du, 0x13fb0adau, 0x0ea90e01u, 0x0bff0d22u, 0x0a660b1au, 0x095509d0u, 0x089208ecu, 0x07ff0843u,
    0x09b707c3u, 0x0bfd0954u, 0x0f340b60u, 0x13f20e2bu, 0x10c7105du, 0x0ea60fa0u, 0x0d250dd5u, 0x0bfd0c85u,
    0x0b1c0b84u, 0x0a640abbu, 0x09d20a19u, 0x09540991u, 0x08ec091eu, 0x089108bdu, 0x08430868u, 0x07ff0820u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09ff07dfu, 0x0bff0affu, 0x0a7f0bddu, 0x08d7098au,
    0x0dfe084cu, 0x13ff0c76u, 0x11c314fbu, 0x0dff0f91u, 0x0bde0ccbu, 0x0a800b1cu, 0x098b09fbu, 0x08d7092au,
    0x0afc088du, 0x0dfc0a7eu, 0x12900d29u, 0x14fb110au, 0x14f714fbu, 0x11be1332u, 0x0f95108fu, 0x0dfc0eb7u,
    0x0cce0d59u, 0x0bdc0c4eu, 0x0b1e0b7au, 0x0a7e0accu, 0x09fb0a3bu, 0x098a09c1u, 0x092a0958u, 0x08d708feu,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09ff0712u, 0x0bff0affu, 0x099f0b6fu, 0x07a60875u,
    0x0a6b070eu, 0x0eaa0949u, 0x15ff0c7cu, 0x0eab0f51u, 0x0b710cc8u, 0x09a00a6au, 0x087608fcu, 0x07a60805u,
    0x08e80755u, 0x0a6a0875u, 0x0c4c09cdu, 0x0ea60b6eu, 0x11be0d72u, 0x15ee1007u, 0x117611f7u, 0x0ea60fe3u,
    0x0ccc0da0u, 0x0b6e0c10u, 0x0a6d0ae8u, 0x099e0a01u, 0x08fc094au, 0x087508b6u, 0x0805083au, 0x07a607d3u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09ff07f6u, 0x0bff0affu, 0x0b1b0cfeu, 0x088f0996u,
    0x0c2e07d2u, 0x126a0aa9u, 0x15ff0f1bu, 0x126c16eau, 0x0d9a0f8au, 0x0b1c0c2du, 0x09970a44u, 0x088f0907u,
    0x0a2a0829u, 0x0c2c0994u, 0x0ed50b58u, 0x12640d96u, 0x16ea1088u, 0x16ea149cu, 0x16ea16eau, 0x12641461u,
    0x0f8f10ceu, 0x0d960e7cu, 0x0c310cd9u, 0x0b190b9eu, 0x0a440aaau, 0x099409e9u, 0x09070949u, 0x088f08c7u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x07ff06ffu, 0x09ff068bu, 0x0bff09c6u, 0x0b310cfeu, 0x07ff0939u,
    0x0a470727u, 0x0d5308efu, 0x11960b32u, 0x17f90e22u, 0x0edb10a4u, 0x0b330cb1u, 0x093b0a15u, 0x07ff088cu,
    0x0911078au, 0x0a450879u, 0x0bb1098au, 0x0d4f0abeu, 0x0f3e0c20u, 0x118d0dbfu, 0x14730f9eu, 0x17e711dcu,
    0x122f1389u, 0x0ed4104du, 0x0cb60db0u, 0x0b2f0be6u, 0x0a150a9au, 0x093809a1u, 0x088c08dcu, 0x07ff0841u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09fe0742u, 0x0bff0affu, 0x0d780cfeu, 0x09180ab8u,
    0x0c2b0805u, 0x10af0a54u, 0x15ff0d79u, 0x17ff11f8u, 0x132718e5u, 0x0d7b0fb3u, 0x0aba0be5u, 0x091809d0u,
    0x0a810882u, 0x0c2809b8u, 0x0e330b25u, 0x10a90cd3u, 0x13cd0ed9u, 0x17e31159u, 0x18e51471u, 0x18e51875u,
    0x18e518e5u, 0x131c15a1u, 0x0fbb1141u, 0x0d750e81u, 0x0be50ca0u, 0x0ab60b45u, 0x09d00a3bu, 0x0918096eu,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x094907cbu, 0x0bff0a35u, 0x0dff0cfbu, 0x09090b22u,
    0x0b2207bfu, 0x0dac094fu, 0x10ce0b23u, 0x14c90d44u, 0x19f80fd2u, 0x0f2a11fbu, 0x0b240cc5u, 0x090909f1u,
    0x0a0b0853u, 0x0b1f092du, 0x0c590a1du, 0x0da70b1fu, 0x0f210c3au, 0x10c50d73u, 0x12b00ec6u, 0x14ba103fu,
    0x173811e1u, 0x19e013c2u, 0x12fc1546u, 0x0f2110d7u, 0x0cc50dd9u, 0x0b1f0be4u, 0x09f10a7bu, 0x09090974u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x08b408ffu, 0x0bff0affu, 0x0dff0cfeu, 0x0a8a0d81u,
    0x0d8208d4u, 0x0f6b0aeau, 0x10f50d83u, 0x17f410c8u, 0x19fe1516u, 0x13f01aecu, 0x0d850fffu, 0x0a8a0bcbu,
    0x0bf00995u, 0x0d7e0abcu, 0x0f570c09u, 0x11680d7eu, 0x12e90f27u, 0x13d21114u, 0x16221345u, 0x1aec15dau,
    0x1aec18e8u, 0x1aec1aecu, 0x1aec1aecu, 0x13e016f0u, 0x0fff11bau, 0x0d7e0ea3u, 0x0bcb0c8fu, 0x0a8a0b1du,
    0x02000100u, 0x040002ffu, 0x059a04ffu, 0x080006ffu, 0x083c07a1u, 0x0a8209edu, 0x0dff0c88u, 0x0b300effu,
    0x0d3f08f9u, 0x0e000a6bu, 0x0eac0bfdu, 0x12ab0dacu, 0x18400f84u, 0x1bf7118au, 0x0f8d1357u, 0x0b300cf0u,
    0x0c3409edu, 0x0d3a0abfu, 0x0e600b9eu, 0x0f820c85u, 0x10bf0d78u, 0x11250e7bu, 0x12640f82u, 0x14ea109au,
    0x169411beu, 0x18261301u, 0x1a18145bu, 0x1bd815b7u, 0x13c716d8u, 0x0f821162u, 0x0cf00e12u, 0x0b300bf9u,
    0x02000100u, 0x040002ffu, 0x054504ffu, 0x080006ffu, 0x07d608b2u, 0x096809f7u, 0x0dff0cfeu, 0x0da30effu,
    0x0fd10a7cu, 0x0ce30c83u, 0x0d050edau, 0x0f750fe4u, 0x16d2142bu, 0x1bfe186bu, 0x14bc1cf7u, 0x0da31055u,
    0x0f2e0bcfu, 0x10cd0cfdu, 0x125a0e49u, 0x101f0fadu, 0x0f3d1130u, 0x0f3510a1u, 0x0fdd10c0u, 0x116d11bau,
    0x141c13c8u, 0x1933177cu, 0x1cf71cf7u, 0x1cf71cf7u, 0x1cf71cf7u, 0x14a81820u, 0x1055122eu, 0x0da30ed3u,
    0x02000100u, 0x040002ffu, 0x050004ffu, 0x080006ffu, 0x078008ffu, 0x0893096eu, 0x0dff0bd4u, 0x0fff0effu,
    0x0f000b54u, 0x0c000ca9u, 0x0bca0e00u, 0x0d550e19u, 0x11ba10a4u, 0x1bfe11fbu, 0x1df51357u, 0x0fff14a8u,
    0x11070d33u, 0x11f60dfau, 0x11440ec9u, 0x0f040f92u, 0x0e041034u, 0x0dc50f2fu, 0x0e130f05u, 0x0f070f86u,
    0x10a910c0u, 0x138f12e9u, 0x18831546u, 0x1be71613u, 0x1d0416d8u, 0x1dcf17a5u, 0x14a8184du, 0x0fff11f6u,
    0x02000100u, 0x040002ffu, 0x04c404ffu, 0x080006ffu, 0x073508ffu, 0x07ea08f8u, 0x0c650a9au, 0x10000effu,
    0x0e4d0ddeu, 0x0b440fe9u, 0x0ad20d03u, 0x0bcd0cbcu, 0x0ea30e5cu, 0x16341308u, 0x1dfe1c1eu, 0x15911ef6u,
    0x177c10c6u, 0x1578120du, 0x1059136bu, 0x0e191187u, 0x0d070f23u, 0x0ca40e08u, 0x0cb80dafu, 0x0d4c0de3u,
    0x0e550ea0u, 0x10230ff7u, 0x12f81233u, 0x1829160fu, 0x1ef61d5au, 0x1ef61ef6u, 0x1ef61ef6u, 0x1591194cu,
    0x02000100u, 0x040002ffu, 0x049204ffu, 0x080006c9u, 0x06f408ffu, 0x07620895u, 0x0aaa09acu, 0x10000effu,
    0x0db610feu, 0x0aaa0f97u, 0x0a0e0c36u, 0x0aa90bafu, 0x0c980cb4u, 0x11340fb7u, 0x1dfe17c6u, 0x1ff81ef8u,
    0x1ff81600u, 0x14941744u, 0x0f9415edu, 0x0d5710a5u, 0x0c390e45u, 0x0bbe0d1bu, 0x0bac0ca4u, 0x0c020ca6u,
    0x0caf0d15u, 0x0de20df2u, 0x0fad0f61u, 0x12b311bau, 0x17c615abu, 0x1ff81cf7u, 0x1ff81ff8u, 0x1ff81ff8u,
    0x02000100u, 0x040002ffu, 0x046604ffu, 0x0800066au, 0x06bb08ffu, 0x06f2083fu, 0x096d08f0u, 0x10000dc0u,
    0x0d3310feu, 0x0a270eeeu, 0x096d0b8cu, 0x09c60ad9u, 0x0b220b77u, 0x0e330d82u, 0x16011266u, 0x20001ef8u,
    0x20ff20ffu, 0x13cf20ffu, 0x0eeb150fu, 0x0cb30fe6u, 0x0b8e0d8au, 0x0b020c57u, 0x0ad60bcbu, 0x0b020bacu,
    0x0b730be8u, 0x0c450c78u, 0x0d7a0d6du, 0x0f6d0ef8u, 0x12661164u, 0x17a4155cu, 0x20ff1ce5u, 0x20ff20ffu,
    0x02000100u, 0x040002ffu, 0x04db04ffu, 0x080006ffu, 0x081808ffu, 0x082a0a64u, 0x0b580b0fu, 0x10000effu,
    0x11ff10f6u, 0x0d9a12f9u, 0x0c12103bu, 0x0c5d0e80u, 0x0e420f35u, 0x13081266u, 0x12341298u, 0x118a11dau,
    0x21f41140u, 0x1e8f1744u, 0x18d6189fu, 0x12ea19ebu, 0x104014d7u, 0x0efc11d8u, 0x0e7a107bu, 0x0e991003u,
    0x0f2c1038u, 0x106a1105u, 0x1258128du, 0x13061345u, 0x129812ceu, 0x12331265u, 0x11da1205u, 0x118a11b0u,
    0x02000100u, 0x040002ffu, 0x04aa04ffu, 0x080006ffu, 0x07c608ffu, 0x07a209ddu, 0x09fd0a1bu, 0x10000efau,
    0x11ff10feu, 0x0cb712f9u, 0x0b260efcu, 0x0b2f0d31u, 0x0c710d75u, 0x0f820f7bu, 0x13191387u, 0x125e12b6u,
    0x21fd120du, 0x212a22b6u, 0x16e61f99u, 0x11811948u, 0x0f001323u, 0x0dc11059u, 0x0d2c0f00u, 0x0d200e6fu,
    0x0d6f0e6cu, 0x0e380edcu, 0x0f710fccu, 0x1181116eu, 0x138713c3u, 0x1318134fu, 0x12b612e5u, 0x125e1288u,
    0x02000100u, 0x040002ffu, 0x052404ffu, 0x080006ffu, 0x097708ffu, 0x08fe0affu, 0x0bfb0ca3u, 0x0d180dd9u,
    0x11ff0c7eu, 0x11fa12f9u, 0x0ea614ffu, 0x0e5f1264u, 0x101810fcu, 0x0ed50f6eu, 0x0dda0e4eu, 0x0d180d73u,
    0x13c20cc7u, 0x23cf12ceu, 0x1dc8189fu, 0x19b719ebu, 0x16e91832u, 0x13ce15d0u, 0x125a1400u, 0x12001298u,
    0x10fe1176u, 0x1023108cu, 0x0f700fc8u, 0x0ed30f20u, 0x0e4e0e8fu, 0x0dd90e12u, 0x0d730da3u, 0x0d180d43u,
    0x02000100u, 0x040002ffu, 0x04ee04ffu, 0x080006ffu, 0x090508ffu, 0x08600affu, 0x0a900b72u, 0x0dc40e9bu,
    0x11ff0d1bu, 0x106e12f9u, 0x0d55146cu, 0x0cda105du, 0x0deb0ff3u, 0x0fb31060u, 0x0e9c0f1du, 0x0dc40e29u,
    0x15560d6bu, 0x23d9143au, 0x218324ceu, 0x1a711eb0u, 0x14751a9au, 0x11b5170cu, 0x105613d5u, 0x0fdd1251u,
    0x0fea11cbu, 0x109911a3u, 0x106210c5u, 0x0fb21008u, 0x0f1d0f66u, 0x0e9a0edbu, 0x0e290e5fu, 0x0dc40df5u,
    0x02000100u, 0x040002ffu, 0x056e04ffu, 0x080006ffu, 0x09ff08ffu, 0x09ec0affu, 0x0cae0cfeu, 0x0baf0cf2u,
    0x11ff0ac2u, 0x13ff12f3u, 0x123014ffu, 0x10e11293u, 0x0e860f8fu, 0x0cf80dabu, 0x0bdf0c60u, 0x0b0c0b6eu,
    0x0f050ab6u, 0x16070e49u, 0x25fd145au, 0x1d2a19ecu, 0x18231a59u, 0x14dd165cu, 0x129713a0u, 0x10de11a8u,
    0x0f92102bu, 0x0e830f03u, 0x0dad0e15u, 0x0cf60d4fu, 0x0c600ca9u, 0x0bdd0c1du, 0x0b6e0ba3u, 0x0b0c0b3bu,
    0x02000100u, 0x040002ffu, 0x053204ffu, 0x080006ffu, 0x09ff08ffu, 0x092c0affu, 0x0b210cfdu, 0x0c7c0df0u,
    0x11ff0b6fu, 0x13ff12f9u, 0x102b14ffu, 0x0ed41465u, 0x0f9010d1u, 0x0dd50ea1u, 0x0c970d28u, 0x0bab0c18u,
    0x10300b4bu, 0x18a30f57u, 0x25fd168fu, 0x21eb26a4u, 0x1b4e1e2cu, 0x1730190du, 0x146a15acu, 0x125b134cu,
    0x10d41188u, 0x0f9a102eu, 0x0ea40f1bu, 0x0dd30e38u, 0x0d280d7cu, 0x0c950cddu, 0x0c180c53u, 0x0bab0bdfu,
    0x02000100u, 0x040002ffu, 0x05b604ffu, 0x080006ffu, 0x09ff08c8u, 0x0ae70affu, 0x0c2e0cfeu, 0x0a010aeau,
    0x11290951u, 0x13ff0ee9u, 0x15ff14ffu, 0x112a1396u, 0x0e110f64u, 0x0c2f0d04u, 0x0aeb0b7eu, 0x0a010a6cu,
    0x0cd809a3u, 0x11250c2du, 0x18920fecu, 0x27cd15fau, 0x1cf81b3du, 0x172819b3u, 0x139c152eu, 0x11251241u,
    0x0f671032u, 0x0e0e0eb0u, 0x0d070d86u, 0x0c2d0c96u, 0x0b7e0bd3u, 0x0ae90b31u, 0x0a6c0aa8u, 0x0a010a34u,
    0x02000100u, 0x040002ffu, 0x057604ffu, 0x080006ffu, 0x09ff08ffu, 0x0a080affu, 0x0bb20cfeu, 0x0a960b9cu,
    0x11ff09d2u, 0x13ff103du, 0x140214ffu, 0x113815f1u, 0x0f3f10cfu, 0x0d0f0e05u, 0x0b9d0c44u, 0x0a960b0eu,
    0x0dd10a2du, 0x12ed0d0cu, 0x1c661172u, 0x27d018fdu, 0x22722881u, 0x1a871debu, 0x15f917f7u, 0x12ed1449u,
    0x10d311c6u, 0x0f3b0ff9u, 0x0e080e9bu, 0x0d0c0d85u, 0x0c440ca5u, 0x0b9b0bedu, 0x0b0e0b51u, 0x0a960acfu,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09ff08ffu, 0x0bfd0affu, 0x0dfa0cfeu, 0x0a300bacu,
    0x0fc40928u, 0x13ff0d4fu, 0x15ff14ffu, 0x12b2167bu, 0x0e631029u, 0x0c030d0au, 0x0a820b2fu, 0x097809f1u,
    0x0bb80910u, 0x0ed30b0eu, 0x13810dc2u, 0x1b1a119eu, 0x29c81797u, 0x1cde1ca4u, 0x16851934u, 0x12ab145au,
    0x102e114au, 0x0e5f0f34u, 0x0d0e0daeu, 0x0c000c81u, 0x0b2f0b94u, 0x0a800ad5u, 0x09f10a35u, 0x097809b1u,
    0x02000100u, 0x040002ffu, 0x05bb04ffu, 0x080006ffu, 0x09ff08ffu, 0x0afa0affu, 0x0c480cfeu, 0x0aec0ca6u,
    0x119909bfu, 0x13ff0e96u, 0x15ff14ffu, 0x143516eeu, 0x0fc111e9u, 0x0cf40e28u, 0x0b390bfeu, 0x0a0b0a94u,
    0x0c9c0996u, 0x10490bd8u, 0x161c0f01u, 0x206913b7u, 0x29cb1b83u, 0x22f82ae3u, 0x1a111dbcu, 0x150b1734u,
    0x11ef134fu, 0x0fbd10beu, 0x0e2c0eeau, 0x0cf10d87u, 0x0bfe0c73u, 0x0b360b97u, 0x0a940ae1u, 0x0a0b0a4cu,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09ff086eu, 0x0bff0affu, 0x0c540cfeu, 0x09450a7cu,
    0x0dab0868u, 0x13ff0bc8u, 0x15ff1176u, 0x160e16eeu, 0x0f7c120bu, 0x0c560daau, 0x0a7d0b4du, 0x094509d2u,
    0x0b2e08ceu, 0x0da90a7au, 0x11190ca0u, 0x16020f77u, 0x1dd21367u, 0x2bb41944u, 0x1d071de4u, 0x160218ecu,
    0x121313c7u, 0x0f7710a4u, 0x0dae0e85u, 0x0c530cf7u, 0x0b4d0bcau, 0x0a7a0ae0u, 0x09d20a21u, 0x09450987u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09fe08ffu, 0x0bfd0affu, 0x0cd60cfeu, 0x09de0b41u,
    0x0f0408e6u, 0x13f80cc4u, 0x15ff13b8u, 0x17ec16eeu, 0x113c1476u, 0x0d6c0f02u, 0x0b430c35u, 0x09de0a7eu,
    0x0c100958u, 0x0f000b40u, 0x13410dc4u, 0x19b71135u, 0x250e163au, 0x2bb81e47u, 0x23d72c76u, 0x19b71dc8u,
    0x148016b8u, 0x113512adu, 0x0f07100bu, 0x0d670e2bu, 0x0c350cc7u, 0x0b400bb5u, 0x0a7e0ad9u, 0x09de0a29u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x099507f5u, 0x0bff0affu, 0x0dff0cfeu, 0x0a360c18u,
    0x0e4308e1u, 0x12680bccu, 0x15ff1016u, 0x17ff16eau, 0x119415a4u, 0x0d230ef1u, 0x0ac70bccu, 0x094f09f6u,
    0x0b0308c5u, 0x0d1e0a3du, 0x0fe30c0eu, 0x13850e53u, 0x18af1142u, 0x2079153au, 0x2dfd1ac8u, 0x1cef1f35u,
    0x15b118aau, 0x118b135cu, 0x0ef71027u, 0x0d1e0dfbu, 0x0bcc0c6cu, 0x0ac40b42u, 0x09f60a56u, 0x094f099du,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x09350877u, 0x0bff0affu, 0x0d670cfeu, 0x0b110d11u,
    0x0ffc0984u, 0x11110cf3u, 0x15ff1250u, 0x17ff16eeu, 0x141418e6u, 0x0e7c10b6u, 0x0bab0cdfu, 0x09f70ab8u,
    0x0bf10959u, 0x0e770b0bu, 0x11e70d2eu, 0x16a80ff1u, 0x1deb13aau, 0x2a2f18fdu, 0x2dfd210eu, 0x24662e59u,
    0x19a21de4u, 0x14091670u, 0x10bd123eu, 0x0e770f85u, 0x0cdf0d9fu, 0x0ba70c3cu, 0x0ab80b27u, 0x09f70a51u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x08e20795u, 0x0bff0affu, 0x0dff0cfeu, 0x099b0b70u,
    0x0d1b086bu, 0x0ffc0afeu, 0x15160ea1u, 0x17ff1417u, 0x159418e6u, 0x0ea3114bu, 0x0b720cc9u, 0x099b0a6au,
    0x0b3208f4u, 0x0d180a4fu, 0x0f7e0bedu, 0x12770ddeu, 0x16671044u, 0x1bc81350u, 0x23cf173bu, 0x2fb61c8eu,
    0x1d66207du, 0x158518c6u, 0x11551333u, 0x0e9c0fdbu, 0x0cc90da3u, 0x0b6e0c12u, 0x0a6a0ae2u, 0x099b09fbu,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x08960806u, 0x0bff0affu, 0x0df80cfeu, 0x0a530c79u,
    0x0e7c08f7u, 0x0f0e0bf3u, 0x12df105eu, 0x17ff16eeu, 0x199518e6u, 0x106013c7u, 0x0c7b0e18u, 0x0a530b43u,
    0x0c2f0994u, 0x0e770b24u, 0x11740d0eu, 0x15520f6cu, 0x1ab61271u, 0x21281676u, 0x2dfd1bf0u, 0x2fbb2404u,
    0x255f302bu, 0x19811e35u, 0x13d3164fu, 0x105811ebu, 0x0e180f23u, 0x0c770d3au, 0x0b430bd1u, 0x0a530ac3u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x0855087cu, 0x0bff0ac9u, 0x0dff0cfeu, 0x0b1a0d9fu,
    0x0efb096fu, 0x0e4a0bdcu, 0x11330efcu, 0x17ff131eu, 0x19fe18e3u, 0x11111560u, 0x0c7f0e57u, 0x0a1e0b23u,
    0x0ba40950u, 0x0d670a96u, 0x0f920c12u, 0x12210dccu, 0x155a0fd9u, 0x19751257u, 0x1f13155au, 0x26751928u,
    0x31fd1e0fu, 0x1d6621fdu, 0x157018cbu, 0x110612fau, 0x0e570f92u, 0x0c790d58u, 0x0b230bc0u, 0x0a1e0a96u,
    0x02000100u, 0x040002ffu, 0x05ff04ffu, 0x080006ffu, 0x081708ffu, 0x0bff0a63u, 0x0dff0cfeu, 0x0bff0effu,
    0x0e910a33u, 0x0d980d17u, 0x0fcc1038u, 0x17f7143cu, 0x19fe18e6u, 0x13951979u, 0x0dcb1014u, 0x0af30c28u,
    0x0cc20a04u, 0x0ee80b81u, 0x11a30d47u, 0x14a00f66u, 0x15a911ffu, 0x18b51548u, 0x1f331972u, 0x2fbb1f09u,
    0x31fd26dbu, 0x25c332e1u, 0x19901e7du, 0x13871624u, 0x101411a3u, 0x0dc40ed5u, 0x0c280ce4u, 0x0af30b81u,
    0x02000100u, 0x040002ffu, 0x05c604ffu, 0x080006ffu, 0x07e008ffu, 0x0b220a07u, 0x0dff0cfeu, 0x0af50e33u,
    0x0e2d091fu, 0x0cfd0b5du, 0x0ea60e34u, 0x14be11ddu, 0x19fe16d3u, 0x157c1aecu, 0x0e3710fau, 0x0af50c51u,
    0x0c7a09eeu, 0x0e2f0b2bu, 0x103d0c95u, 0x12930e2fu, 0x13dc1008u, 0x16031234u, 0x1a7a14b6u, 0x22ac17bau,
    0x2a411b60u, 0x33aa200cu, 0x1e0f238fu, 0x156a1903u, 0x10fa12f0u, 0x0e2f0f74u, 0x0c510d28u, 0x0af50b94u,
    0x02000100u, 0x040002ffu, 0x059504ffu, 0x080006ffu, 0x07ae08ffu, 0x0a7109b8u, 0x0dff0cfeu, 0x0beb0effu,
    0x0dd409c7u, 0x0c7a0c67u, 0x0dbb0ea7u, 0x127510f7u, 0x19fe18e6u, 0x19861aecu, 0x0fe01367u, 0x0beb0d8cu,
    0x0dbd0ab6u, 0x0fd60c2bu, 0x12720ddeu, 0x12280fd6u, 0x1271122du, 0x140014c1u, 0x173c1703u, 0x1e1c1bd2u,
    0x2e982248u, 0x33af29f1u, 0x269b34dfu, 0x196d1ea8u, 0x13671602u, 0x0fd61170u, 0x0d8c0e92u, 0x0beb0ca8u,
    0x02000100u, 0x040002ffu, 0x056704ffu, 0x080006ffu, 0x078008fdu, 0x09d4096eu, 0x0dff0cfeu, 0x0d110effu,
    0x0d800a89u, 0x0c010d1fu, 0x0cec0e01u, 0x10a00fbfu, 0x19fe1634u, 0x1bfe1adau, 0x10db1566u, 0x0c260e09u,
    0x0db10ac8u, 0x0f600c01u, 0x115f0d60u, 0x112b0ee2u, 0x11371094u, 0x12541285u, 0x14b414abu, 0x19861727u,
    0x238c1a02u, 0x2ccf1d7cu, 0x35e521afu, 0x1e0724e3u, 0x156618fdu, 0x10cf12d4u, 0x0e090f42u, 0x0c260cffu,
    0x02000100u, 0x040002ffu, 0x053d04ffu, 0x080006ffu, 0x075508ffu, 0x094e092bu, 0x0dff0cfeu, 0x0e650effu,
    0x0d340b61u, 0x0b950eadu, 0x0c3b0d6fu, 0x0f2f0ebcu, 0x184613b5u, 0x1bfe1aecu, 0x136119a2u, 0x0d670fbeu,
    0x0f4f0bc3u, 0x11720d3bu, 0x11900eeau, 0x105310d1u, 0x103011eeu, 0x10f811f1u, 0x12bf1317u, 0x164715a0u,
    0x1cfa1a94u, 0x2de02514u, 0x35fb2d86u, 0x271736ddu, 0x19a21ef6u, 0x13511608u, 0x0fbe114cu, 0x0d670e72u,
    0x02000100u, 0x040002ffu, 0x051604ffu, 0x080006ffu, 0x072d08d9u, 0x08d608ecu, 0x0dff0c54u, 0x0e050effu,
    0x0ceb0ab5u, 0x0b310cd5u, 0x0b9d0ce9u, 0x0df90dd8u, 0x14bb11b7u, 0x1bfe19abu, 0x15a11cffu, 0x0e0510e1u,
    0x0fa70c18u, 0x11620d56u, 0x10de0eb5u, 0x0f8f102eu, 0x0f461103u, 0x0fcd10d4u, 0x112211a0u, 0x13c51381u,
    0x18761715u, 0x22ac1cefu, 0x31592030u, 0x379c23bbu, 0x1ec42625u, 0x158b1957u, 0x10e112ddu, 0x0e050f46u,
    0x02000100u, 0x040002ffu, 0x04f504ffu, 0x080006ffu, 0x070908ffu, 0x087308b5u, 0x0dff0b96u, 0x0fb20effu,
    0x0caa0ba9u, 0x0adb0e39u, 0x0b190c78u, 0x0d070d1fu, 0x124c1039u, 0x1bfe19b9u, 0x19e61cffu, 0x0fb21360u,
    0x11c60d53u, 0x138f0ed8u, 0x10471090u, 0x0eeb11a9u, 0x0e871040u, 0x0ede0fedu, 0x0fe21078u, 0x11ed11e7u,
    0x156b149cu, 0x1c5d198bu, 0x2c8123dcu, 0x37a2311bu, 0x283138ddu, 0x19c61f68u, 0x13601608u, 0x0fb2114au,
    0x02000100u, 0x040002ffu, 0x04d504ffu, 0x080006ffu, 0x06e708ffu, 0x08180881u, 0x0dff0aeeu, 0x10000effu,
    0x0c6d0cccu, 0x0a8b0df3u, 0x0aa20c0eu, 0x0c340c79u, 0x10600ef6u, 0x1bfe1615u, 0x1dfe1cfdu, 0x10dc15a3u,
    0x12a00df7u, 0x12fe0f3bu, 0x0fbb109cu, 0x0e551105u, 0x0dda0f8eu, 0x0e0a0f1eu, 0x0ecf0f76u, 0x1067108cu,
    0x130d129eu, 0x1800163fu, 0x21e91d28u, 0x33fd2272u, 0x39e42539u, 0x1eef2777u, 0x15a31956u, 0x10dc12e2u,
    0x02000100u, 0x040002ffu, 0x04b804ffu, 0x080006ffu, 0x06c808ffu, 0x07c80852u, 0x0d1f0a5fu, 0x10000effu,
    0x0c350e1bu, 0x0a420dacu, 0x0a390bb0u, 0x0b830beau, 0x0ee40defu, 0x18a61377u, 0x1dfe1cffu, 0x136d1a0du,
    0x15ce0faeu, 0x127b114bu, 0x0f3f1317u, 0x0dd01073u, 0x0d440ef3u, 0x0d550e6cu, 0x0de90e9cu, 0x0f2c0f6fu,
    0x113e110eu, 0x14f013d2u, 0x1ba818c3u, 0x2c6a232bu, 0x39ff3488u, 0x28d13adbu, 0x1a0d1f9bu, 0x136d1628u,
    0x02000100u, 0x040002ffu, 0x049d04ffu, 0x080006e1u, 0x06aa08ffu, 0x077f0825u, 0x0bfc09deu, 0x10000effu,
    0x0bff0dfeu, 0x09fe0d69u, 0x09d80b58u, 0x0ae50b67u, 0x0da70d0au, 0x14eb1168u, 0x1dfe1ca4u, 0x15df1ef8u,
    0x17d910f5u, 0x12011243u, 0x0eca134du, 0x0d560fecu, 0x0cba0e64u, 0x0cb20dcau, 0x0d1e0dd9u, 0x0e1f0e77u,
    0x0fc00fbcu, 0x129311dfu, 0x175b1585u, 0x219b1c7eu, 0x38982511u, 0x3b8d2738u, 0x1fa12867u, 0x15df19b8u,
    0x02000100u, 0x040002ffu, 0x048404ffu, 0x080006abu, 0x068e08ffu, 0x073e07fcu, 0x0b12096fu, 0x10000effu,
    0x0bcd0fc0u, 0x09c00d2au, 0x09820b08u, 0x0a5e0af5u, 0x0ca80c4bu, 0x124a0fd1u, 0x1dfe19e7u, 0x1a7d1ef8u,
    0x1994139cu, 0x11911560u, 0x0e6112ceu, 0x0ce90f73u, 0x0c420de5u, 0x0c250d3du, 0x0c720d32u, 0x0d3f0da7u,
    0x0e8d0ea8u, 0x10c71058u, 0x145a1325u, 0x1b4e1825u, 0x2b58227eu, 0x3b943909u, 0x2a483bcbu, 0x1a7d2058u,
    0x02000100u, 0x040002ffu, 0x046d04ffu, 0x0800067au, 0x067508ffu, 0x070407d6u, 0x0a54090eu, 0x10000effu,
    0x0b9f10feu, 0x09890cf2u, 0x09360ac1u, 0x09e90a90u, 0x0bd70ba9u, 0x10590e8fu, 0x1dfe162cu, 0x1ffe1ef8u,
    0x19131600u, 0x112d1744u, 0x0e03125au, 0x0c880f06u, 0x0bd70d75u, 0x0bab0cc1u, 0x0bdf0ca2u, 0x0c830cf6u,
    0x0d940dc4u, 0x0f5f0f20u, 0x12251155u, 0x1731151au, 0x213d1c2eu, 0x3b8d2777u, 0x3ddb2864u, 0x1ffe29c8u,
    0x02000100u, 0x040002ffu, 0x045704ffu, 0x0800064cu, 0x065c08ffu, 0x06ce07b2u, 0x09ae08b5u, 0x10000e4cu,
    0x0b7310feu, 0x09540cbbu, 0x08ef0a7eu, 0x097f0a33u, 0x0b1f0b17u, 0x0ec80d7du, 0x191f1362u, 0x20001ef8u,
    0x18981abeu, 0x10cd1a40u, 0x0daa11edu, 0x0c2c0ea0u, 0x0b740d0cu, 0x0b3a0c4eu, 0x0b580c1eu, 0x0bdc0c57u,
    0x0cba0cfau, 0x0e2f0e13u, 0x105f0fd6u, 0x142912beu, 0x1af617d3u, 0x2b71222du, 0x3df13bcbu, 0x2b1a3df1u,
    0x02000100u, 0x040002ffu, 0x044404ffu, 0x08000623u, 0x064608ffu, 0x069f0791u, 0x09240867u, 0x10000d26u,
    0x0b4a10feu, 0x09240c89u, 0x08b00a41u, 0x092309e1u, 0x0a860a9au, 0x0d8f0c9eu, 0x15541155u, 0x20001ef8u,
    0x182920ffu, 0x107619c1u, 0x0d5a118bu, 0x0bdb0e45u, 0x0b1d0cafu, 0x0ad70beau, 0x0ae40babu, 0x0b4d0bceu,
    0x0c040c50u, 0x0d380d36u, 0x0efe0ea6u, 0x11f310f5u, 0x16e514cdu, 0x21391be4u, 0x3df12d2eu, 0x3fd83e0fu);

float pattern_level(uint inner, uint outer) {
    uint index = (clamp(inner, 1u, 64u) - 1u) * 64u + (clamp(outer, 1u, 64u) - 1u);
    uint word = PATTERN_LEVELS[index / 2u];
    uint q = (word >> (16u * (index % 2u))) & 0xffffu;
    return float(q) * (1.0 / 256.0);
}

// The smallest n in 1..n_max whose uniform pattern has effective level >= level; 0 if none.
uint uniform_level(float level, uint n_max) {
    uint top = clamp(n_max, 1u, 64u);
    for (uint n = 1u; n <= top; ++n) {
        if (pattern_level(n, n) >= level) {
            return n;
        }
    }
    return 0u;
}

struct PatchLevels {
    float inner;     // gl_TessLevelInner[0] (1 for fallback)
    vec3 outer;      // gl_TessLevelOuter[0..2]
    bool fallback;   // per-pixel shading (patch_level 0)
};

// The level-combination rule (`patch_levels` in Rust): edge k gets the larger of the two
// triangles' uniform levels (a fallback triangle asks for nothing; 1 if both fall back); the
// inner level is the smallest whose whole pattern, transition strips included, has
// effective level >= own; none, or own itself falls back: per-pixel shading, inner 1.
PatchLevels patch_levels(float own, vec3 neighbours, float n_max_value) {
    uint n_max = uint(clamp(n_max_value, 1.0, 64.0));
    uint own_n = uniform_level(own, n_max);
    uvec3 outer = uvec3(max(max(own_n, uniform_level(neighbours.x, n_max)), 1u),
                        max(max(own_n, uniform_level(neighbours.y, n_max)), 1u),
                        max(max(own_n, uniform_level(neighbours.z, n_max)), 1u));
    uint inner = 0u;
    if (own_n > 0u) {
        for (uint i = 1u; i <= n_max; ++i) {
            float l = min(min(pattern_level(i, outer.x), pattern_level(i, outer.y)),
                          pattern_level(i, outer.z));
            if (l >= own) {
                inner = i;
                break;
            }
        }
    }
    PatchLevels result;
    result.inner = float(max(inner, 1u));
    result.outer = vec3(outer);
    result.fallback = inner == 0u;
    return result;
}

// ---------------------------------------------------------------------------------------------
// The estimate
// ---------------------------------------------------------------------------------------------

int worse(int a, int b) {
    return b > a ? b : a;
}

// Estimate::level of the triangle (p0, p1, p2) with vertex normals n0, n1, n2 seen from
// `eye`: >= 1, or FALLBACK_LEVEL when it must be shaded per pixel. Never NaN.
float required_level(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec3 eye,
                     uint material_index, vec2 param, float epsilon, float n_max_value) {
    uint n_max = uint(clamp(n_max_value, 1.0, 64.0));
    P float eps = epsilon > 0.0 ? epsilon : 0.0;
    P float top = pattern_level(n_max, n_max);
    GpuMaterial material = materials[material_index];
    Frame frame = make_frame(p0, p1, p2, n0, n1, n2, eye);
    est_bad = false;
    if (SPLIT == 0) {
        for (int t = 0; t < TERM_COUNT; ++t) {
            sum_h1[t] = vec3(0.0);
            sum_hn[t] = vec3(0.0);
        }
    }
    sum_tn = vec3(0.0);
    sum_lin1 = vec3(0.0);
    sum_linn = vec3(0.0);
    sum_jumps = vec3(0.0);
    sum_jumps1 = vec3(0.0);
    sum_range = vec3(0.0);
    sum_one = vec3(0.0);
    int reason = REASON_NONE;
    // Point lights first, then directional ones (the buffer's order, and the twin's).
    for (int i = 0; i < POINT_LIGHT_COUNT + DIRECTIONAL_LIGHT_COUNT; ++i) {
        GpuLight light = lights[i];
        reason = worse(reason, add_light(frame, material, param, i < POINT_LIGHT_COUNT,
                                         light.position.xyz, light.radiance.rgb, -1, top, eps));
    }
    for (int i = 0; i < POLYGON_LIGHT_COUNT; ++i) {
        reason = worse(reason, add_light(frame, material, param, false, vec3(0.0), vec3(0.0), i, top, eps));
    }
    if (est_bad) {
        reason = worse(reason, REASON_SINGULAR);
    }

    if (reason != REASON_NONE) {
        return FALLBACK_LEVEL;
    }

    // `decide`: one_ok (the level-1 bound holds) and need (the smallest effective level).
    P vec3 an = sum_tn;
    P vec3 zero = sum_jumps + sum_range;
    bool relaxed_on = max_el(sum_linn) > 0.0 || max_el(sum_jumps) > 0.0;
    bool one_ok;
    P float need = 0.0;
    if (SPLIT == 1) {
        for (int c = 0; c < 3; ++c) {
            need = rmax(need, level_for(an[c], sum_linn[c], zero[c], eps));
        }
        one_ok = max_el(sum_one) <= eps;
    } else {
        // M counts the terms above eps * UNIFORM_TINY; the others share a reserve.
        P float tiny = eps * UNIFORM_TINY;
        uint count = 0u;
        for (int t = 0; t < TERM_COUNT; ++t) {
            if (max_el(sum_hn[t]) > tiny || max_el(sum_h1[t]) > tiny) {
                count += 1u;
            }
        }
        if (max_el(sum_linn) > tiny || max_el(sum_jumps) > tiny || max_el(sum_jumps1) > tiny) {
            count += 1u;
        }
        if (max_el(sum_range) > tiny) {
            count += 1u;
        }
        P float share = eps * (1.0 - 16.0 * UNIFORM_TINY) / float(max(count, 1u));
        one_ok = max_el(sum_lin1 + sum_jumps1) <= share && max_el(sum_range) <= share;
        for (int t = 0; t < TERM_COUNT; ++t) {
            one_ok = one_ok && max_el(sum_h1[t]) <= share;
            for (int c = 0; c < 3; ++c) {
                need = rmax(need, level_for(sum_hn[t][c], 0.0, 0.0, share));
            }
        }
        if (relaxed_on) {
            for (int c = 0; c < 3; ++c) {
                need = rmax(need, level_for(0.0, sum_linn[c], sum_jumps[c], share));
            }
        }
        if (max_el(sum_range) > share) {
            need = infinity();
        }
    }
    P float level = one_ok ? 1.0 : rmax(need, 1.0);
    // false for NaN and infinity
    if (!(level <= top)) {
        return FALLBACK_LEVEL;
    }
    return level;
}

#endif
