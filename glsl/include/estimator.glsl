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
// Relative rounding allowance of the normal's radial scale (see `RADIAL_PAD` in Rust).
const float RADIAL_PAD = 2.0e-6;
// Relaxed: Lg - g <= E_f + TERMINATOR_KINK osc(f) where g = max(f, 0) has its kink (see Rust).
const float TERMINATOR_KINK = 0.25;
// The light part's peaks along the plane (see `TILT_PEAK` and `TILT_FLAT` in Rust).
const float TILT_PEAK = 3.42857146;       // 24.0 / 7.0 in f32
const float TILT_FLAT = 2.6832817;        // sqrt(7.2), rounded up
const float HALF_PI = 1.5707964;          // std::f32::consts::FRAC_PI_2
const float MAX_HALF = 1.5706964;         // FRAC_PI_2 - 1.0e-4 in f32
const float INV_SQRT3 = 0.57735026;       // 1.0 / 3.0f32.sqrt()
const float THIRD = 0.33333334;           // 1.0 / 3.0
const float TWO_THIRDS = 0.6666667;       // 2.0 / 3.0
const float FOUR_THIRDS = 1.3333334;      // 4.0 / 3.0
const float MIRROR_WORTH = 0.05;          // radians (see Rust)
const float HULL_WORTH = 0.03;            // radians (see Rust)
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
// add_light on a child (ADD_VALUES): its values were taken.
const int VALUES_ADDED = -1;
const float MAX_FINITE = 3.4028235e38;
// A triangle above this level is estimated again with each light's ranges over REFINE_CHILDREN
// children (one midpoint subdivision), for the lights whose range exceeds this share of eps
// (`REFINE_ABOVE`, `REFINE_CHILDREN`, `REFINE_SHARE` in Rust).
const float REFINE_ABOVE = 8.0;
const int REFINE_CHILDREN = 4;
const float REFINE_SHARE = 0.125;
// add_light's modes: a patch's bounds; a child's values only; a patch's bounds with its ranges
// from its children's values.
const int ADD_BOUNDS = 0;
const int ADD_VALUES = 1;
const int ADD_REFINED = 2;

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

vec3 rmin3(vec3 a, vec3 b) {
    return vec3(rmin(a.x, b.x), rmin(a.y, b.y), rmin(a.z, b.z));
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

// Chain rule for phi(c), with the jet `inner` of c, |phi| <= value, |phi'| <= first and
// |phi''| <= second; phi's own curvature is booked under `term` (`chain` in Rust).
Jet chain(Jet inner, float value, float first, float second, int term) {
    Jet j = jet_constant(0.0);
    j.h = gmul(inner.h, first);
    P float inner2 = gmul(inner.g, inner.g);
    P float curvature = gmul(second, inner2);
    if (booked(term)) {
        j.h = gc(j.h + curvature);
    }
    j.m = value;
    j.g = gmul(first, inner.g);
    return guard_jet(j);
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

// A unit vector field u = m/|m|: w >= |Dm|/|m|, radial >= |u.Dm|/|m|, x >= |P m''|/|m|, and
// the term its curvature is booked under.
struct Field {
    float w;
    float radial;
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

// max phi(psi) over [p0, p1], phi = c/2 + sqrt(1 - 3c^2/4), c = |cos psi| (c0, c1 at the ends).
P float max_phi(float p0, float p1, float c0, float c1) {
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

// The power's profile coefficient less the cosine's turning part (see `power_net_coefficient`).
P float power_net_coefficient(float s0, float s1, float c0, float c1) {
    P float p = 0.5 * (s0 - 2.0);
    P float peak = p * (s1 - 1.0) / ((p + 1.0) * s1);
    P float x = rmin(rmax(peak, c1 * c1), c0 * c0);
    P float r = s1 * est_pow(x, p) * rmax((s1 - 1.0) * (1.0 - x) - x, 0.0);
    return r;
}

// The second derivative of a cosine a.b split by sign (see `Curvature` in Rust): turn >=
// |Da|^2 + |Db|^2 (the part -t(|Da|^2 + |Db|^2) <= 0 where t >= 0), rest >= the others.
struct Curvature {
    float turn;
    float rest;
};

Curvature curvature(Field a, Field b, vec2 psi) {
    P float s_max = max_sin(psi.x, psi.y);
    P float across_a = gc(2.0 * gmul(a.w, a.radial) + a.x);
    P float across_b = gc(2.0 * gmul(b.w, b.radial) + b.x);
    P float turn = gc(gmul(a.w, a.w) + gmul(b.w, b.w));
    P float rest = gc(2.0 * a.w * b.w + s_max * gc(across_a + across_b));
    return Curvature(turn, rest);
}

// What the jets need of an angle range between two unit fields (see `Angles` in Rust).
struct Angles {
    float s_max;
    float c_max;
    float phi;
};

// The same with the cosines of the range's ends given (see `Angles::with_cosines`).
Angles angles_with(vec2 psi, vec2 cosines) {
    P float c0 = abs(cosines.x);
    P float c1 = abs(cosines.y);
    return Angles(max_sin(psi.x, psi.y), rmax(c0, c1), max_phi(psi.x, psi.y, c0, c1));
}

Angles angles_of(vec2 psi) {
    return angles_with(psi, vec2(est_cos(psi.x), est_cos(psi.y)));
}

// >= |D^2 u . b| for the field f and a unit b at an angle in the range (`Angles::seen`).
P float seen(Angles an, Field f) {
    P float w2 = gmul(f.w, f.w);
    P float turning = gmul(an.phi, w2);
    P float radial = gc(an.c_max * w2 + 2.0 * an.s_max * gmul(f.w, f.radial));
    P float r = gc(rmin(turning, radial) + an.s_max * f.x);
    return r;
}

// Jet of c = a.b where the angle between them has the Angles `an` (neither a nor b books under
// T_DOT; they may share a term, as a polygon's emitter cosine does).
Jet cosine_at(Field a, Field b, Angles an) {
    P float s_max = an.s_max;
    Jet j = jet_constant(an.c_max);
    P float ha = seen(an, a);
    P float hb = seen(an, b);
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

// The same for the angle range psi.
Jet cosine(Field a, Field b, vec2 psi) {
    return cosine_at(a, b, angles_of(psi));
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

// The distance from the origin to the segment p q (see Rust: segment_distance).
P float segment_distance(vec3 p, vec3 q) {
    P vec3 pq = q - p;
    P float length2 = len2(pq);
    P float t = length2 > 0.0 ? rmin(rmax(-dot3(p, pq) / length2, 0.0), 1.0) : 0.0;
    return len(p + pq * t);
}

// A lower bound on the distance from the origin to the triangle c0 c1 c2: its nearest edge, its
// plane's distance where the origin projects inside, a sliver's longest edge less its height
// (see Rust: origin_distance).
P float origin_distance(vec3 c0, vec3 c1, vec3 c2) {
    P float nearest[3] = float[3](segment_distance(c0, c1), segment_distance(c1, c2), segment_distance(c2, c0));
    P float lengths[3] = float[3](len2(c1 - c0), len2(c2 - c1), len2(c0 - c2));
    P float edge_min = rmin(rmin(nearest[0], nearest[1]), nearest[2]);
    int longest = (lengths[0] >= lengths[1] && lengths[0] >= lengths[2]) ? 0 : (lengths[1] >= lengths[2] ? 1 : 2);
    P vec3 normal = cross3(c1 - c0, c2 - c0);
    P float area2 = len2(normal);
    if (area2 >= 0.01 * lengths[longest] * lengths[longest] && area2 > 0.0) {
        bool inside = dot3(normal, cross3(c1 - c0, -c0)) >= 0.0 && dot3(normal, cross3(c2 - c1, -c1)) >= 0.0
            && dot3(normal, cross3(c0 - c2, -c2)) >= 0.0;
        if (inside) {
            return rmin(edge_min, abs(dot3(c0, normal)) / sqrt(area2));
        }
        return edge_min;
    }
    P float height = lengths[longest] > 0.0 ? sqrt(area2) / sqrt(lengths[longest]) : 0.0;
    return rmin(edge_min, nearest[longest] - height);
}

// The angle range of unit fields a, b narrowed by the interpolant of a - b at the corners, whose
// level-1 error is at most curvature/2 (see Rust: narrowed).
P vec2 narrowed(vec2 range, vec3 a[3], vec3 b[3], float curvature) {
    P vec3 c0 = a[0] - b[0];
    P vec3 c1 = a[1] - b[1];
    P vec3 c2 = a[2] - b[2];
    P float error = 0.5 * curvature + 1.0e-5;
    P float lo = origin_distance(c0, c1, c2) - error;
    P float hi = rmax(rmax(len(c0), len(c1)), len(c2)) + error;
    P float lo_angle = lo > 0.0 ? 2.0 * est_asin(rmin(0.5 * lo, 1.0)) - ANGLE_PAD : 0.0;
    P float hi_angle = hi < 2.0 ? 2.0 * est_asin(0.5 * hi) + ANGLE_PAD : PI;
    P float low = rmax(range.x, lo_angle);
    return vec2(low, rmax(rmin(range.y, hi_angle), low));
}

// Largest angle between a and the spherical triangle u when below pi/2, else PI.
P float hull_max_angle(vec3 a, vec3 u[3]) {
    P float m = rmax(rmax(angle(a, u[0]), angle(a, u[1])), angle(a, u[2])) + ANGLE_PAD;
    return m < HALF_PI ? m : PI;
}

// A lower bound on the angle between n and the half vector of a and b at the same point, where
// n.a > 0 on the whole triangle: n is the half vector of a and its mirror r, and
// angle(h, n) >= angle(b, r)/2; r is within 2 nu_n + nu_a of the axes' mirror r0, and b lies in
// its cone and (when has_vectors) in the spherical triangle of the directions of b_vectors.
// Returns the larger of this and lo (see Rust: mirror_lower_angle).
P float mirror_lower_angle(Cone n, Cone a, Cone b, bool has_vectors, vec3 b_vectors[3], float lo) {
    if (!(n.spread < PI && a.spread < PI && b.spread < PI)) {
        return lo;
    }
    P vec3 r0 = unit(n.axis * (2.0 * dot3(n.axis, a.axis)) - a.axis);
    if (is_zero(r0)) {
        return lo;
    }
    P float spread = 2.0 * n.spread + a.spread;
    P float axis_angle = angle(b.axis, r0);
    P float apart = axis_angle - b.spread;
    if (has_vectors && b.spread > HULL_WORTH && 0.5 * (axis_angle + b.spread - spread) > lo) {
        P vec3 units[3] = vec3[3](unit(b_vectors[0]), unit(b_vectors[1]), unit(b_vectors[2]));
        apart = rmax(apart, hull_distance(r0, units));
    }
    return rmax(lo, 0.5 * (apart - spread) - ANGLE_PAD);
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

// The seven shapes {0, u, v} in the basis (e1, e2): see SHAPES in Rust.
const vec4 PATTERN_SHAPES[7] = vec4[7](
    vec4(1.0, 0.0, 0.0, 1.0),
    vec4(1.0, 0.0, TWO_THIRDS, TWO_THIRDS),
    vec4(1.0, 0.0, -THIRD, TWO_THIRDS),
    vec4(0.0, 1.0, TWO_THIRDS, TWO_THIRDS),
    vec4(0.0, 1.0, TWO_THIRDS, -THIRD),
    vec4(-1.0, 1.0, -FOUR_THIRDS, TWO_THIRDS),
    vec4(-1.0, 1.0, -THIRD, -THIRD));

PatternConstants pattern_constants(vec3 e1, vec3 e2) {
    PatternConstants o = PatternConstants(0.0, 0.0, 0.0, 0.0);
    for (int s = 0; s < 7; ++s) {
        P vec3 u = e1 * PATTERN_SHAPES[s].x + e2 * PATTERN_SHAPES[s].y;
        P vec3 v = e1 * PATTERN_SHAPES[s].z + e2 * PATTERN_SHAPES[s].w;
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

// ---------------------------------------------------------------------------------------------
// Per-triangle and per-light geometry
// ---------------------------------------------------------------------------------------------

// Pattern scales: what |X delta|, |N delta| and |G delta| are replaced by (see `Scale`).
struct Scale {
    float a;
    float b;
    float g;
};

// See `Frame` in Rust.
struct Frame {
    vec3 vertices[3];
    vec3 eye;
    vec3 center;
    float rho_x;
    Scale s1;
    Scale sn;
    float rho;
    Scale d1;
    Scale dn;
    Cone n_cone;
    float r_n;
    float n_max_len;
    vec3 normals[3];
    vec3 unit_normals[3];
    vec3 plane;
    float plane_tilt;
    float n_plane_sin;
    Cone v_cone;
    float e_min;
    vec3 v_center;
};

// max |sin| of the angle between a direction of the cone and the plane normal, 1 without a
// plane (see `plane_sin` in Rust).
P float plane_sin(Cone cone, vec3 plane) {
    if (is_zero(plane)) {
        return 1.0;
    }
    P vec2 g = psi_range(cone, Cone(plane, 0.0));
    return max_sin(g.x, g.y);
}

// s1/sn of one attribute, 0 where sn is (see `Frame::rho` in Rust).
P float scale_ratio(float one, float later) {
    P float r = later > 0.0 ? one / later : 0.0;
    return r;
}

// The jet at a scale rho times this one's: value kept, first derivative times rho, second
// times rho^2 (see `LightJets::scaled`).
Jet scaled_jet(Jet j, float rho) {
    P float rho2 = rho * rho;
    Jet o;
    o.m = j.m;
    o.g = j.g * rho;
    o.h = j.h * rho2;
    return o;
}

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
    P vec3 e1 = n1 - n0;
    P vec3 e2 = n2 - n0;
    P vec2 pg = jung_scales(vec3(dot3(n0, e1), dot3(n1, e1), dot3(n2, e1)),
                            vec3(dot3(n0, e2), dot3(n1, e2), dot3(n2, e2)));
    P float g_pad = RADIAL_PAD * longest;
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
    f.s1 = Scale(px.sqrt_k1, pn.sqrt_k1, pg.x + g_pad * pn.sqrt_k1);
    f.sn = Scale(px.sqrt_k, pn.sqrt_k, pg.y + g_pad * pn.sqrt_k);
    f.rho = rmin(rmax(rmax(scale_ratio(f.s1.a, f.sn.a), scale_ratio(f.s1.b, f.sn.b)), scale_ratio(f.s1.g, f.sn.g)),
                 1.0);
    f.d1 = Scale(px.diam1, pn.diam1, 0.0);
    f.dn = Scale(px.diam, pn.diam, 0.0);
    f.n_max_len = longest;
    f.normals = vec3[3](n0, n1, n2);
    f.unit_normals = vec3[3](unit(n0), unit(n1), unit(n2));
    P vec3 c = cross3(p1 - p0, p2 - p0);
    P float plane_scale = len(p1 - p0) * len(p2 - p0);
    if (len(c) > 1.0e-6 * plane_scale) {
        f.plane = unit(c);
        f.plane_tilt = 4.0e-7 * plane_scale / len(c) + 1.0e-6;
    } else {
        f.plane = vec3(0.0);
        f.plane_tilt = 0.0;
    }
    f.n_plane_sin = plane_sin(f.n_cone, f.plane);
    f.v_center = unit(eye - center);
    return f;
}

// Lower and upper bounds on the height of p over the triangle's plane (see `Frame::height_of`).
P vec2 height_of(Frame frame, vec3 p) {
    if (is_zero(frame.plane)) {
        return vec2(0.0);
    }
    P vec3 r = p - frame.vertices[0];
    P float height = abs(dot3(r, frame.plane));
    P float pad = len(r) * (frame.plane_tilt + 1.0e-6);
    P vec2 range = vec2(rmax(height - pad, 0.0), height + pad);
    return range;
}

// The distance from p to the longest edge of a triangle without a plane, less the third
// corner's distance from it and the rounding (see `Frame::distance_along_line`).
P float distance_to_segment(vec3 a, vec3 b, float length2, vec3 x) {
    P vec3 e = b - a;
    P vec3 f = x - a;
    P float t = length2 > 0.0 ? clamp(dot3(f, e) / length2, 0.0, 1.0) : 0.0;
    P float d = len(f - e * t);
    return d;
}
P float distance_along_line(Frame frame, vec3 p) {
    P vec3 v[3] = frame.vertices;
    P float lengths[3] = float[](len2(v[1] - v[0]), len2(v[2] - v[1]), len2(v[0] - v[2]));
    int k = (lengths[0] >= lengths[1] && lengths[0] >= lengths[2]) ? 0 : (lengths[1] >= lengths[2] ? 1 : 2);
    P vec3 a = v[k];
    P vec3 b = v[(k + 1) % 3];
    P float magnitude = max_el(abs(p)) + max_el(abs(a)) + 2.0 * frame.rho_x;
    P float d = rmax(distance_to_segment(a, b, lengths[k], p) - distance_to_segment(a, b, lengths[k], v[(k + 2) % 3])
                     - 1.0e-6 * magnitude, 0.0);
    return d;
}

// A lower bound on the distance from p to the triangle, its height from below given (see
// `Frame::distance_of`).
P float distance_of(Frame frame, vec3 p, float height) {
    if (is_zero(frame.plane)) {
        return distance_along_line(frame, p);
    }
    P vec3 foot = p - frame.plane * dot3(p - frame.vertices[0], frame.plane);
    // The foot's distance to the triangle: 0 inside, else to the nearest edge.
    bool inside = true;
    P float rho = len(foot - frame.vertices[0]);
    for (int k = 0; k < 3; ++k) {
        P vec3 a = frame.vertices[k];
        P vec3 e = frame.vertices[(k + 1) % 3] - a;
        P vec3 f = foot - a;
        inside = inside && dot3(cross3(e, f), frame.plane) >= 0.0;
        P float t = clamp(dot3(f, e) / len2(e), 0.0, 1.0);
        rho = rmin(rho, len(f - e * t));
    }
    P float reach = len(p - frame.vertices[0]) + 2.0 * frame.rho_x;
    P float magnitude = max_el(abs(foot)) + max_el(abs(frame.vertices[0])) + 2.0 * frame.rho_x;
    P float pad = 2.0 * reach * (frame.plane_tilt + 1.0e-6) + 1.0e-6 * magnitude;
    P float rho_out = (inside || !(rho > pad)) ? 0.0 : rho - pad;
    P float d = sqrt(height * height + rho_out * rho_out);
    return d;
}

// See `LightSetup` in Rust.
struct LightSetup {
    float plane_sin;
    float near_sin;
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
    // <= H/d_min (at most 1): the cosine of gamma where the light is nearest (see Rust).
    float near_cos;
    // >= H/d_min (at most 1; 1 without a plane), and <= inf E' over the triangle (see Rust).
    float far_cos;
    float att_inf;
    // The cosines at the ends of psi_nl.
    vec2 nl_cos;
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
// Heuristic split: the bound at the uniform levels of GRID_LEVELS, each light's parts at the
// smaller of their interpolation bound and their range there (see `GRID_LEVELS` in Rust).
const int GRID_LEVEL_COUNT = 8;
const uint GRID_LEVELS[GRID_LEVEL_COUNT] = uint[](2u, 3u, 4u, 6u, 8u, 12u, 16u, 32u);
vec3 sum_grid[GRID_LEVEL_COUNT];
// The effective levels of the GRID_LEVELS uniform patterns (up to n_max), read once per triangle.
float grid_level[GRID_LEVEL_COUNT];

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

// The distribution's profile coefficient less the turning part at s2 = sin^2 psi (see
// `ggx_net_coefficient` in Rust).
P float ggx_net_at(float a2, float beta, float coef, float x) {
    P float u = a2 + beta * x;
    P float n = (2.0 * a2 + 5.0 * beta - 4.0 * beta * x) * x - a2;
    P float r = coef * rmax(n, 0.0) / ((u * u) * (u * u));
    return r;
}

P float ggx_net_coefficient(float a2, float s0, float s1) {
    P float beta = 1.0 - a2;
    P float coef = 4.0 * a2 * beta / PI;
    P float b = beta * (14.0 * a2 + 15.0 * beta);
    P float c = a2 * (2.0 * a2 + 9.0 * beta);
    P float root = 2.0 * c / rmax(b + sqrt(rmax(b * b - 32.0 * beta * beta * c, 0.0)), 1.0e-30);
    P float r = rmax(rmax(ggx_net_at(a2, beta, coef, rmin(rmax(root, s0), s1)), ggx_net_at(a2, beta, coef, s0)),
                     ggx_net_at(a2, beta, coef, s1));
    return r;
}

// GGX D(n.h) jet (see `ggx_d_jet`).
Jet ggx_d_jet(Jet c, Curvature curv, float p0, float p1, float w, float alpha) {
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
    if (est_term == T_ALL) {
        // D''(Dt)^2 >= 0 and D'(-t(|u|^2 + |v|^2)) <= 0: the larger, plus the rest; the first
        // less the second on the turn's share of w^2 (see `ggx_net_coefficient`).
        P float c0 = est_cos(p0);
        P float turning = gmul(gc(coef * c0 * c0 / (u0 * u0 * u0)), curv.turn);
        P float net = gc(gmul(ggx_net_coefficient(a2, s0, s1), curv.turn)
            + gmul(dd, rmax(w2 - curv.turn, 0.0)));
        P float joint = gc(gmul(slope, curv.rest) + rmax(rmin(net, dh), turning));
        o.h = rmin(o.h, joint);
    }
    return guard_jet(o);
}

// The roughness-dependent GGX factors G, V and D at one alpha (see `ggx_factor_jets`).
void ggx_factor_jets(Field n, Field l, Field v, Field h, LightSetup st, vec2 nh, float w_nh,
                     float alpha, float view_band, out Jet gjet, out Jet vjet, out Jet djet) {
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
    gjet = chain(c_g, c1 / q1, g1, g2, T_V);

    // V_v = 1/(max(n.v, 0)(1-k)+k): constant 1/k where n.v <= 0 throughout.
    if (st.nv_sign == SIGN_NON_POSITIVE) {
        vjet = jet_constant(1.0 / k);
    } else if (st.nv_sign == SIGN_BOTH) {
        // Relaxed, the view's kink inside: the smooth parts (see `smith_v_kink_jet`).
        Jet c_v = cosine(n, v, st.psi_nv);
        P float slope = (1.0 - k) / (k * k);
        P float v2 = 2.0 * (1.0 - k) * (1.0 - k) / (k * k * k);
        vjet = chain(c_v, gc(1.0 / k + gmul(slope, rmin(c_v.m, view_band))), slope, v2, T_V);
    } else {
        P vec2 nv = vec2(st.psi_nv.x, rmin(st.psi_nv.y, HALF_PI));
        Jet c_v = cosine(n, v, nv);
        P float q = rmax(est_cos(nv.y), 0.0) * (1.0 - k) + k;
        P float v1 = (1.0 - k) / (q * q);
        P float v2 = 2.0 * (1.0 - k) * (1.0 - k) / (q * q * q);
        vjet = chain(c_v, 1.0 / q, v1, v2, T_V);
    }

    // D(t), t = n.h.
    if (st.psi_nh.x >= HALF_PI) {
        djet = jet_constant(alpha * alpha / PI);
    } else {
        Jet c_nh = cosine(n, h, vec2(h0, h1));
        Curvature curv = curvature(n, h, vec2(h0, h1));
        djet = ggx_d_jet(c_nh, curv, h0, h1, w_nh, alpha);
    }
}

// Elementwise larger bounds of two jets (see `jet_max`).
Jet jet_max(Jet a, Jet b) {
    return Jet(rmax(a.m, b.m), rmax(a.g, b.g), rmax(a.h, b.h));
}

// The normal part of n.D^2 I with the falloff and sin(gamma) taken together along
// sin^2 = 1 - H^2/d^2 (see `along_plane` in Rust): the coefficient of |a|^2/d_min^4.
P float along_plane(LightSetup st, float nu, float c) {
    P float h2 = st.near_cos * st.near_cos;
    P float q = rmax(1.875 * h2, 1.0);
    P float rising = rmax(12.0 * q - 15.0 * h2, 0.0) / (q * q * q);
    P float k = 6.0 * st.plane_sin * nu + rmax(rising, 3.0) * c;
    return k;
}

// The light part n.D^2 I with the normal split along the plane normal and in the plane (see
// `tilted` in Rust): the coefficient of |a|^2/d_min^4.
P float tilted(LightSetup st, float nu) {
    P float h2 = st.near_cos * st.near_cos;
    P float rising;
    if (7.0 * h2 <= 4.0) {
        rising = 12.0 - 15.0 * h2;
    } else {
        P float x = 4.0 / (7.0 * h2);
        rising = rmax(TILT_PEAK * x * x * sqrt(x), 3.0);
    }
    P float s = st.plane_sin;
    P float s2 = s * s;
    P float turning;
    if (s2 < 0.2) {
        turning = s * (9.0 - 15.0 * s2);
    } else if (s2 <= 0.8) {
        turning = TILT_FLAT;
    } else {
        turning = s * (15.0 * s2 - 9.0);
    }
    P float k = st.far_cos * rising + nu * turning;
    return k;
}

// A point light's diffuse factor n.I with the irradiance field I = r/|r|^3 bounded as one
// field (see `irradiance_jet` in Rust).
Jet irradiance_jet(Frame frame, LightSetup st, Field n, float a) {
    Angles an = angles_with(st.psi_nl, st.nl_cos);
    P float sg = st.plane_sin;
    P float nu = frame.n_plane_sin;
    P float c = an.c_max;
    P float id2 = gmul(st.inv_d, st.inv_d);
    P float a_id = gmul(a, st.inv_d);
    P float a_id2 = gmul(a_id, a_id);
    P float sg2 = sg * sg;
    P float near2 = st.near_sin * st.near_sin;
    P float speed = sqrt(1.0 + 3.0 * near2);
    P float along_normal = rmin(rmin(speed, nu + 3.0 * c * sg), 2.0 * sg * c + an.s_max);
    P float whole = sqrt(rmax(45.0 * near2 * near2 - 18.0 * near2 + 9.0, 9.0));
    P float projected = 6.0 * sg * nu + rmax(abs(15.0 * sg2 - 3.0), 3.0) * c;
    P float product_rule = rmax(8.0 * sg2 - 2.0, 2.0) * c + 4.0 * sg * an.s_max
                           + rmin(an.phi, c + 2.0 * an.s_max * sg);
    P float light_k = rmin(rmin(rmin(rmin(whole, projected), product_rule), along_plane(st, nu, c)), tilted(st, nu));
    P float cross_k = rmin(speed, 2.0 * sg * an.s_max + 1.0);
    P float hn = gmul(seen(an, n), id2);
    P float hd = gmul(gmul(2.0 * cross_k * n.w, a_id), id2);
    P float hl = gmul(light_k * a_id2, id2);
    Jet j = jet_constant(gmul(c, id2));
    if (booked(T_NORMAL)) {
        j.h = hn;
    }
    if (booked(T_DOT)) {
        j.h = j.h + hd;
    }
    if (booked(T_LIGHT)) {
        j.h = j.h + hl;
    }
    j.h = gc(j.h);
    j.g = gc(gmul(an.s_max * n.w, id2) + gmul(along_normal * a_id, id2));
    return j;
}

// The jets of one light's diffuse part and (per channel) specular part at pattern scale s,
// and GGX's view-kink weight (see `LightJets`); view_band bounds |n.v| where the kink crosses.
void light_jets(Frame frame, GpuMaterial material, vec2 param, LightSetup st, Scale s,
                float view_band, out Jet diffuse, out Jet spec[3], out vec3 view_kink) {
    view_kink = vec3(0.0);
    P float n_w = gc(s.b / frame.r_n);
    Field n = Field(n_w, rmin(n_w, gc(s.g / frame.r_n)), 0.0, T_NORMAL);
    P float l_w = gmul(s.a, st.inv_d);
    Field l = Field(l_w, gmul(l_w, st.plane_sin), 0.0, T_LIGHT);
    Jet att;
    if (st.inv_d > 0.0) {
        P float id = st.inv_d;
        P float id2 = gmul(id, id);
        P float a_id = gmul(s.a, id);
        P float sg = st.plane_sin;
        att = jet_constant(id2);
        P float a_id2 = gmul(a_id, a_id);
        P float k = rmax(8.0 * sg * sg - 2.0, 2.0);
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
        Field fixed_direction = Field(0.0, 0.0, 0.0, T_LIGHT);
        att = product2(att, cosine(fixed_direction, l, st.emitter));
    }
    if (st.inv_d > 0.0 && !st.area) {
        diffuse = irradiance_jet(frame, st, n, s.a);
    } else {
        diffuse = product2(att, cosine_at(n, l, angles_with(st.psi_nl, st.nl_cos)));
    }
    Jet zero = jet_constant(0.0);
    spec[0] = zero;
    spec[1] = zero;
    spec[2] = zero;
    if (MATERIAL_KIND == MATERIAL_LAMBERT || st.area) {
        return;
    }

    P float v_w = gc(s.a / frame.e_min);
    Field v = Field(v_w, v_w, 0.0, T_VIEW);
    P float h_w = gc((l.w + v.w) / st.m_min);
    Field h = Field(h_w, h_w, gc(K23 * (l.w * l.w + v.w * v.w) / st.m_min), T_HALF);
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
        P float slope = s1 * est_pow(chi, s0 - 1.0);
        t.h = gmul(c_nh.h, slope);
        P float hp = 0.0;
        P float k = 0.0;
        P float w2 = gmul(w_nh, w_nh);
        if (s1 > 1.0) {
            k = s1 * (s1 - 1.0) * max_cos_sin(s0 - 2.0, 2.0, h0, h1);
            hp = gmul(k, w2);
            if (booked(T_POWER)) {
                t.h = gc(t.h + hp);
            }
        }
        if (est_term == T_ALL) {
            // The power's part >= 0, the cosine's turning part <= 0: the larger, plus the rest.
            Curvature curv = curvature(n, h, vec2(h0, h1));
            P float turning = gmul(gmul(s1, est_pow(chi, s0)), curv.turn);
            // The profile's part less the turning part, on the turn's share of w^2 (see Rust).
            P float net = hp;
            if (s1 > 1.0 && s0 > 2.0) {
                P float c1 = power_net_coefficient(s0, s1, chi, rmax(est_cos(h1), 0.0));
                net = gc(gmul(c1, curv.turn) + gmul(k, rmax(w2 - curv.turn, 0.0)));
            }
            P float joint = gc(gmul(slope, curv.rest) + rmax(rmin(net, hp), turning));
            t.h = rmin(t.h, joint);
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
    ggx_factor_jets(n, l, v, h, st, vec2(h0, h1), w_nh, alphas[0], view_band, gjet, vjet, djet);
    for (int i = 1; i < alpha_count; ++i) {
        Jet g2;
        Jet v2;
        Jet d2;
        ggx_factor_jets(n, l, v, h, st, vec2(h0, h1), w_nh, alphas[i], view_band, g2, v2, d2);
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
    // |V'| at the kink, largest at the smallest k.
    P float k_lo = 0.5 * alpha_lo;
    P float kink_slope = (1.0 - k_lo) / (k_lo * k_lo);
    for (int c = 0; c < 3; ++c) {
        P float f0c = material.specular[c];
        P float fm = f0c + (1.0 - f0c) * om5;
        P float f1 = 5.0 * (1.0 - f0c) * om4;
        P float f2 = 20.0 * (1.0 - f0c) * om3;
        Jet fjet = chain(Jet(0.0, gt, ht), fm, f1, f2, T_F);
        Jet f[5] = Jet[5](att, djet, fjet, gjet, vjet);
        Jet p = product(f, 5);
        spec[c].m = 0.25 * p.m;
        spec[c].g = 0.25 * p.g;
        spec[c].h = gmul(p.h, 0.25);
        if (st.nv_sign == SIGN_BOTH) {
            P float without_v = gmul(gmul(gmul(att.m, djet.m), fjet.m), gjet.m);
            view_kink[c] = gmul(0.25 * without_v, kink_slope);
        }
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
    P float cos_l_min = rmax(st.nl_cos.y, 0.0);
    P float cos_l_max = rmin(st.nl_cos.x, 1.0);
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

// Relaxed: a bound on |n.l| over the sub-triangles the terminator crosses, of diameters d/L,
// with the scalars that do not depend on the level taken once per light (`TerminatorBand`).
struct TerminatorBand {
    float normal;
    float light;
    float nu;
    float sigma;
    float c_max;
    float fixed_point;
    float held;
    float oscillation;
};

TerminatorBand terminator_band(Frame frame, LightSetup st, Scale d) {
    P float normal = d.b / frame.r_n;
    P float light = d.a * st.inv_d;
    P float fixed_point = normal + frame.n_plane_sin * light;
    P float held = st.plane_sin * light;
    P float oscillation = st.nl_cos.x - st.nl_cos.y;
    P float c_max = rmax(abs(st.nl_cos.x), abs(st.nl_cos.y));
    return TerminatorBand(normal, light, frame.n_plane_sin, st.plane_sin, c_max, fixed_point, held, oscillation);
}

// The band per 1/L at the levels L >= above (`TerminatorBand::per_level`), unguarded.
P float band_per_level(TerminatorBand t, float above) {
    P float c_star = t.c_max;
    P float room = above - t.held;
    if (room > 0.0) {
        c_star = rmin(c_star, t.fixed_point / room);
    }
    P float across = rmin(t.nu + t.sigma * c_star, 1.0);
    P float band = t.normal + t.light * across;
    return band;
}

// The same at one effective level l, at most the oscillation of n.l over the triangle.
P float band_at(TerminatorBand t, float l) {
    P float band = rmin(band_per_level(t, l) / l, t.oscillation);
    return band;
}

// The band's floor as the level grows (`TerminatorBand::floor`).
P float band_floor(TerminatorBand t) {
    P float band = t.normal + t.light * rmin(t.nu, 1.0);
    return gc(band);
}

// Relaxed, GGX: |n.v| on a sub-triangle of diameters d that n.v = 0 crosses (`view_band`).
P float view_band(Frame frame, Scale d) {
    return gc(d.b / frame.r_n + d.a / frame.e_min);
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
    P float c1 = st.nl_cos.x;
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

// The shaded diffuse part max(E' c, 0) per unit weight lies in [inf, sup] (`diffuse_values` in
// Rust): (sup, inf).
P vec2 diffuse_values(LightSetup setup, Jet diffuse) {
    P float att = setup.inv_d > 0.0 ? setup.inv_d * setup.inv_d : 1.0;
    P float inf = setup.att_inf * rmax(setup.nl_cos.y, 0.0) * (1.0 - 1.0e-5);
    P float sup = setup.area ? diffuse.m : rmin(diffuse.m, att * rmax(setup.nl_cos.x, 0.0));
    return vec2(sup, inf);
}

// Child k (0..3) of the midpoint subdivision of the triangle with corners c (`midpoint_child`).
void midpoint_child(inout vec3 c[3], int k) {
    P vec3 ab = (c[0] + c[1]) * 0.5;
    P vec3 bc = (c[1] + c[2]) * 0.5;
    P vec3 ca = (c[2] + c[0]) * 0.5;
    if (k == 0) {
        c[1] = ab;
        c[2] = ca;
    } else if (k == 1) {
        c[0] = ab;
        c[2] = bc;
    } else if (k == 2) {
        c[0] = ca;
        c[1] = bc;
    } else {
        c[0] = bc;
        c[1] = ca;
        c[2] = ab;
    }
}

vec3 rmax3(vec3 a, vec3 b) {
    return vec3(rmax(a.x, b.x), rmax(a.y, b.y), rmax(a.z, b.z));
}

// The values of a light's two parts per unit weight over the children of a patch (`ChildValues`
// in Rust), and whether every child could be bounded.
struct ChildValues {
    float diffuse_sup;
    float diffuse_inf;
    vec3 specular_sup;
    bool ok;
};

#ifdef CHILDREN_GIVEN
// Where the including stage took the children's turns itself (refine_levels.comp, the refining
// step, side by side in a workgroup): light `light`'s values over the patch's children, combined
// in the children's order as level_pass combines them, and whether a child's bound went bad.
// level_pass uses it for the first GIVEN_LIGHTS point and directional lights.
ChildValues given_child_values(int light, out bool bad);
#endif

// Adds one light's bounds to the sums; returns a fallback reason (REASON_NONE if none), as
// `add_light` in Rust. `polygon` >= 0: the polygonal light of that index (`position` and
// `radiance` unused); else `point`: a point light at `position`, or a directional light whose
// travel direction is `position`.
//
// `mode` ADD_VALUES: `frame` is a child of a patch (`values_over_children` in Rust); its values
// join `values` and VALUES_ADDED is returned, or REASON_NONE where the light adds 0 on it, or the
// reason it cannot be bounded. ADD_REFINED: the patch's ranges take `values` where they hold.
int add_light(Frame frame, GpuMaterial material, vec2 param, bool point, vec3 position,
              vec3 radiance, int polygon, float top, uint n_max, float eps, int mode,
              inout ChildValues values) {
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
    // A point light's height over the plane, from below and from above.
    P vec2 heights = vec2(0.0);
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
        // Every point of the triangle is at least its height and in-plane distance away.
        heights = height_of(frame, position);
        inv_d = 1.0 / rmax(d_min, distance_of(frame, position, heights.x));
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
    setup.near_sin = 1.0;
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
    setup.near_cos = 0.0;
    setup.far_cos = 1.0;
    if (area) {
        setup.att_inf = 0.0;
    } else if (point) {
        setup.att_inf = 1.0 / (rmax(rmax(len2(l_vectors[0]), len2(l_vectors[1])), len2(l_vectors[2])) * (1.0 + 2.0e-5));
    } else {
        setup.att_inf = 1.0;
    }
    if (inv_d > 0.0) {
        setup.plane_sin = plane_sin(l_cone, frame.plane);
        setup.near_sin = setup.plane_sin;
        if (point && !area && !is_zero(frame.plane)) {
            P float height = heights.x;
            P float q = rmin(height * inv_d, 1.0);
            setup.near_cos = q;
            setup.far_cos = rmin(heights.y * inv_d, 1.0);
            setup.near_sin = rmin(setup.plane_sin, sqrt(rmax(1.0 - q * q, 0.0)));
            // |n.l| <= H/d_min + nu: a light near the plane is seen at grazing angles (see Rust).
            P float grazing = (heights.y * inv_d + frame.n_plane_sin) * (1.0 + 1.0e-5) + 1.0e-6;
            if (grazing < 1.0) {
                P float lo = rmax(est_acos(grazing) - ANGLE_PAD, 0.0);
                P float p0 = rmax(setup.psi_nl.x, lo);
                setup.psi_nl = vec2(p0, rmax(rmin(setup.psi_nl.y, PI - lo), p0));
            }
        }
    }
    setup.nl_cos = vec2(est_cos(setup.psi_nl.x), est_cos(setup.psi_nl.y));
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
        // The same angle at the same point, from the mirror directions, where h's cone is wide
        // enough for it to matter (see Rust).
        if (!area && setup.h_cone.spread > MIRROR_WORTH) {
            P float lo = setup.psi_nh.x;
            if (nv_sign == SIGN_POSITIVE) {
                lo = mirror_lower_angle(frame.n_cone, frame.v_cone, l_cone, point, l_vectors, lo);
            }
            if (!straddle) {
                lo = mirror_lower_angle(frame.n_cone, l_cone, frame.v_cone, true, v_vectors, lo);
            }
            setup.psi_nh.x = rmin(lo, setup.psi_nh.y);
        }
        // The same angle from the interpolant of n - h at the corners (see Rust: narrowed).
        if (!area) {
            P vec3 h_units[3];
            for (int k = 0; k < 3; ++k) {
                P vec3 l_unit = point ? unit(l_vectors[k]) : l_vectors[k];
                h_units[k] = unit(l_unit + unit(v_vectors[k]));
            }
            P float n_w = frame.s1.b / frame.r_n;
            P float l_w = frame.s1.a * inv_d;
            P float v_w = frame.s1.a / frame.e_min;
            P float h_w = (l_w + v_w) / m_min;
            P float curvature = K23 * (n_w * n_w + h_w * h_w) + K23 * (l_w * l_w + v_w * v_w) / m_min;
            setup.psi_nh = narrowed(setup.psi_nh, frame.unit_normals, h_units, curvature);
        }
        // A polygon's sampled specular part is bounded by its range: kinks do not matter.
        if (area) {
        } else if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
            // max(n.h, 0)^s is C^{1,1} across n.h = 0 only for s >= 2.
            if (setup.psi_nh.x < HALF_PI && setup.psi_nh.y >= HALF_PI && param.x < 2.0) {
                return REASON_DISCONTINUITY;
            }
        } else {
            // max(n.v, 0) has a kink in V at n.v = 0: bounded in Relaxed (see Rust).
            if (setup.nv_sign == SIGN_BOTH && DISCONTINUITY == 0) {
                return REASON_DISCONTINUITY;
            }
        }
    }

    // This light's bounds, its diffuse (_d) and specular (_s) part apart, at level 1 (1) and
    // levels >= 2 (n): all terms in one pass, and for the Uniform split one more pass per term
    // (terms that are zero for every light of this material are skipped: they add nothing).
    vec3 h_d[2][TERM_COUNT];
    vec3 h_s[2][TERM_COUNT];
    if (SPLIT == 0) {
        for (int t = 0; t < TERM_COUNT; ++t) {
            h_d[0][t] = vec3(0.0);
            h_d[1][t] = vec3(0.0);
            h_s[0][t] = vec3(0.0);
            h_s[1][t] = vec3(0.0);
        }
    }
    P vec3 tot_d1 = vec3(0.0);
    P vec3 tot_dn = vec3(0.0);
    P vec3 tot_s1 = vec3(0.0);
    P vec3 tot_sn = vec3(0.0);
    P vec3 lin1 = vec3(0.0);
    P vec3 linn = vec3(0.0);
    P vec3 lin1_s = vec3(0.0);
    P vec3 linn_s = vec3(0.0);
    P vec3 range_d = vec3(0.0);
    P vec3 range_s = vec3(0.0);
    P vec3 spec_sup = vec3(0.0);
    P vec2 later_diffuse = vec2(0.0);
    // Relaxed: how far n.l can be from 0 on a crossed sub-triangle, at level 1 and per 1/L.
    P float band1 = 0.0;
    P float bandn = 0.0;
    // sup E' (1 for a directional light).
    P float att = setup.inv_d > 0.0 ? setup.inv_d * setup.inv_d : 1.0;
    TerminatorBand terminator = terminator_band(frame, setup, frame.dn);
    if (setup.straddle) {
        band1 = gc(band_at(terminator_band(frame, setup, frame.d1), 1.0));
        bandn = gc(band_per_level(terminator, 0.0));
    }
    // Relaxed, GGX: the same for n.v where it may change sign (its kink in V).
    bool view_kink = MATERIAL_KIND == MATERIAL_GGX && !setup.area && setup.nv_sign == SIGN_BOTH;
    P float view1 = 0.0;
    P float viewn = 0.0;
    if (view_kink) {
        view1 = view_band(frame, frame.d1);
        viewn = view_band(frame, frame.dn);
    }
    // The jets at levels >= 2, and at level 1 those scaled by rho unless the Uniform split needs
    // each term or GGX's view kink takes another band (see Rust).
    bool derive_one = SPLIT == 1 && !view_kink;
    Jet diff_n;
    Jet spec_n[3];
    P vec3 kink_n;
    est_term = T_ALL;
    // (A child's values take GGX's V at the band 0, where its value is 1/k, its sup.)
    light_jets(frame, material, param, setup, frame.sn, mode == ADD_VALUES ? 0.0 : rmin(view1, viewn), diff_n,
               spec_n, kink_n);
    if (mode == ADD_VALUES) {
        P vec2 diffuse = diffuse_values(setup, diff_n);
        values.diffuse_sup = rmax(values.diffuse_sup, diffuse.x);
        values.diffuse_inf = rmin(values.diffuse_inf, diffuse.y);
        values.specular_sup = rmax3(values.specular_sup, vec3(spec_n[0].m, spec_n[1].m, spec_n[2].m));
        return VALUES_ADDED;
    }
    for (int level = 0; level < 2; ++level) {
        Scale s = level == 0 ? frame.s1 : frame.sn;
        P float view_at = level == 0 ? view1 : rmin(view1, viewn);
        Jet diff;
        Jet spec[3];
        P vec3 kink;
        if (SPLIT == 0) {
            for (int pass = 0; pass < active_term_count(); ++pass) {
                est_term = active_term(pass);
                light_jets(frame, material, param, setup, s, view_at, diff, spec, kink);
                P vec3 spec_h = vec3(spec[0].h, spec[1].h, spec[2].h);
                h_d[level][est_term] = diff_w * (diff.h * (0.5 * SAFETY));
                h_s[level][est_term] = spec_w * spec_h * (0.5 * SAFETY);
            }
        }
        est_term = T_ALL;
        if (level == 1) {
            diff = diff_n;
            spec = spec_n;
            kink = kink_n;
        } else if (derive_one) {
            diff = scaled_jet(diff_n, frame.rho);
            spec[0] = scaled_jet(spec_n[0], frame.rho);
            spec[1] = scaled_jet(spec_n[1], frame.rho);
            spec[2] = scaled_jet(spec_n[2], frame.rho);
            kink = kink_n;
        } else {
            light_jets(frame, material, param, setup, s, view_at, diff, spec, kink);
        }
        P vec3 spec_t = vec3(spec[0].h, spec[1].h, spec[2].h);
        if (level == 0) {
            tot_d1 = diff_w * (diff.h * (0.5 * SAFETY));
            tot_s1 = spec_w * spec_t * (0.5 * SAFETY);
        } else {
            tot_dn = diff_w * (diff.h * (0.5 * SAFETY));
            tot_sn = spec_w * spec_t * (0.5 * SAFETY);
        }
        // (The sups m do not depend on the pass.)
        P vec3 spec_m = vec3(spec[0].m, spec[1].m, spec[2].m);
        spec_sup = spec_m;
        // Each part lies in [inf, sup] and so does its interpolant, the shaded diffuse part in
        // [inf E' cos psi_max, sup E' max(cos psi_min, 0)] (see Rust).
        P vec2 diffuse = diffuse_values(setup, diff);
        later_diffuse = diffuse;
        range_d = diff_w * (rmax(diffuse.x - diffuse.y, 0.0) * SAFETY);
        range_s = spec_w * spec_m * SAFETY;
        if (setup.straddle && level == 1) {
            // Relaxed: the diffuse kink adds 1/4 sup E' osc(n.l) (see Rust).
            lin1 = diff_w * (TERMINATOR_KINK * SAFETY * gmul(att, band1));
            linn = diff_w * (TERMINATOR_KINK * SAFETY * gmul(att, bandn));
        }
        if (view_kink && level == 1) {
            // Relaxed: the view's kink adds 1/4 sup(specular without V) |V'(0)| osc(n.v).
            lin1_s = spec_w * (kink * (TERMINATOR_KINK * SAFETY * view1));
            linn_s = spec_w * (kink * (TERMINATOR_KINK * SAFETY * viewn));
        }
    }
    // A triangle that needs a high level: the parts' values over the children, where this
    // light's range is not small (see Rust).
    bool significant = rmax(max_el(range_d), max_el(range_s)) > REFINE_SHARE * eps;
    if (mode == ADD_REFINED && values.ok && !setup.area && significant) {
        P float diff_sup = rmin(later_diffuse.x, values.diffuse_sup);
        P float diff_inf = rmax(later_diffuse.y, values.diffuse_inf);
        range_d = diff_w * (rmax(diff_sup - diff_inf, 0.0) * SAFETY);
        spec_sup = rmin3(spec_sup, values.specular_sup);
        range_s = spec_w * spec_sup * SAFETY;
    }
    P vec3 other;
    if (area) {
        // The sampled specular part: no interpolation bound, its range.
        other = polygon_specular_bound(material, param, setup, light) * SAFETY;
        range_s = range_s + other;
    } else {
        // A textured parameter: its variation over the range, an n-independent term.
        other = spec_w * parameter_variation(param, setup, spec_sup);
    }
    P vec3 zero1 = terminator_jump(spec_w, spec_sup, param, setup, band1) + other;
    P vec3 zero_top = terminator_jump(spec_w, spec_sup, param, setup, bandn / top) + other;
    // Per part and channel: the smaller of the part's interpolation bound and its range
    // (`!(range <= bound)`, true for NaN, as in Rust).
    bvec3 interp_d = not(lessThanEqual(range_d, tot_dn / (top * top) + linn / top));
    bvec3 interp_s = not(lessThanEqual(range_s, tot_sn / (top * top) + linn_s / top + zero_top));
    // The jump at levels >= 2 at a lower bound of the final level (see Rust).
    P vec3 zero_inf = terminator_jump(spec_w, spec_sup, param, setup, 0.0) + other;
    const vec3 none = vec3(0.0);
    P vec3 a = mix(none, tot_dn, interp_d) + mix(none, tot_sn, interp_s);
    P vec3 z = mix(none, zero_inf, interp_s);
    // Relaxed: the same with the diffuse kink at its floor; the band's fixed point holds from
    // `low` on (see Rust).
    P vec3 floor_kink = setup.straddle
        ? diff_w * (TERMINATOR_KINK * SAFETY * gmul(att, band_floor(terminator)))
        : vec3(0.0);
    P vec3 b = mix(none, floor_kink, interp_d) + mix(none, linn_s, interp_s);
    P float low = 1.0;
    for (int c = 0; c < 3; ++c) {
        if (interp_d[c] || interp_s[c]) {
            low = rmax(low, level_for(a[c], b[c], z[c], eps));
        }
    }
    if (setup.straddle) {
        bandn = rmin(bandn, gc(band_per_level(terminator, low)));
        linn = diff_w * (TERMINATOR_KINK * SAFETY * gmul(att, bandn));
    }
    P vec3 zeron = terminator_jump(spec_w, spec_sup, param, setup, bandn / low) + other;
    if (SPLIT == 1) {
        P vec3 whole_lobe = setup.straddle && !setup.area ? spec_w * spec_sup * SAFETY : vec3(0.0);
        for (int k = 0; k < GRID_LEVEL_COUNT; ++k) {
            if (GRID_LEVELS[k] > n_max) {
                break;
            }
            P float l = grid_level[k];
            // The jump at l: the one at `low` where l >= low, else the whole lobe (see Rust).
            P vec3 zero_l = l >= low ? zeron : whole_lobe + other;
            // The diffuse kink at l itself (valid below `low` too; at most att bandn, guarded).
            P vec3 kink_l = setup.straddle
                ? diff_w * (TERMINATOR_KINK * SAFETY * (att * band_at(terminator, l)))
                : vec3(0.0);
            P vec3 part_d = rmin3(tot_dn / (l * l) + kink_l, range_d);
            P vec3 part_s = rmin3(tot_sn / (l * l) + linn_s / l + zero_l, range_s);
            sum_grid[k] = sum_grid[k] + (part_d + part_s);
        }
    }
    sum_one = sum_one + (rmin3(tot_d1 + lin1, range_d) + rmin3(tot_s1 + lin1_s + zero1, range_s));
    // Each part adds its interpolation bound or its range (diffuse first, as in Rust).
    sum_range = sum_range + mix(range_d, none, interp_d);
    sum_range = sum_range + mix(range_s, none, interp_s);
    sum_tn = sum_tn + mix(none, tot_dn, interp_d);
    sum_tn = sum_tn + mix(none, tot_sn, interp_s);
    sum_lin1 = sum_lin1 + mix(none, lin1, interp_d);
    sum_lin1 = sum_lin1 + mix(none, lin1_s, interp_s);
    sum_linn = sum_linn + mix(none, linn, interp_d);
    sum_linn = sum_linn + mix(none, linn_s, interp_s);
    sum_jumps1 = sum_jumps1 + mix(none, zero1, interp_s);
    sum_jumps = sum_jumps + mix(none, zeron, interp_s);
    if (SPLIT == 0) {
        for (int pass = 0; pass < active_term_count(); ++pass) {
            int t = active_term(pass);
            sum_h1[t] = sum_h1[t] + mix(none, h_d[0][t], interp_d);
            sum_h1[t] = sum_h1[t] + mix(none, h_s[0][t], interp_s);
            sum_hn[t] = sum_hn[t] + mix(none, h_d[1][t], interp_d);
            sum_hn[t] = sum_hn[t] + mix(none, h_s[1][t], interp_s);
        }
    }
    return REASON_NONE;
}

// ---------------------------------------------------------------------------------------------
// Shared edges and mixed patterns (see `pattern_level`, `uniform_level`, `patch_levels`)
// ---------------------------------------------------------------------------------------------

// The effective level of the hardware pattern with inner level `inner` and outer level
// `outer` on an edge: pattern_level_words (bindings.glsl), uploaded from Rust's
// `PATTERN_LEVELS`, in 1/256, two 16-bit entries per word, index (inner-1)*64 + (outer-1).

float pattern_level(uint inner, uint outer) {
    uint index = (clamp(inner, 1u, 64u) - 1u) * 64u + (clamp(outer, 1u, 64u) - 1u);
    uint word = pattern_level_words[index / 2u];
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

// What the level-recording variants write per triangle (bindings.glsl, level_records): the
// level it shades at (0: per-pixel fallback) and its outer levels; CULLED_RECORD if culled.
vec4 level_record(PatchLevels levels) {
    return vec4(levels.fallback ? 0.0 : ceil(levels.inner), ceil(levels.outer.x), ceil(levels.outer.y),
                ceil(levels.outer.z));
}

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

// One estimate of the triangle in `frame` (`light_sums` and `decide` in Rust): the level before
// the n_max test, and the reason to fall back (REASON_NONE if none); with `refine`, each point
// or directional light's ranges over the patch's REFINE_CHILDREN children.
float level_pass(Frame frame, GpuMaterial material, vec2 param, float eps, uint n_max, float top, bool refine,
                 out int reason_out) {
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
    if (SPLIT == 1) {
        for (int k = 0; k < GRID_LEVEL_COUNT; ++k) {
            sum_grid[k] = vec3(0.0);
            grid_level[k] = GRID_LEVELS[k] <= n_max ? pattern_level(GRID_LEVELS[k], GRID_LEVELS[k]) : 0.0;
        }
    }
    int reason = REASON_NONE;
    // Point lights first, then directional ones (the buffer's order, and the twin's). With
    // `refine`, each light takes REFINE_CHILDREN + 1 turns: its children first (their values
    // only, under their own guard), then the patch. One loop and one call site: a second call
    // would inline the whole estimator twice, and a loop over the children inside the loop over
    // the lights made the estimator step twice as slow on lavapipe even where `refine` is a
    // constant false (docs/speedups.md, step 20); every branch tests `refine` first, so that
    // there the children's code folds away.
    // The polygonal lights take the last turns, one each, through the same call site (-1 where
    // the variant has none, so that their code folds away).
    int turns = refine ? REFINE_CHILDREN + 1 : 1;
    int light_turns = (POINT_LIGHT_COUNT + DIRECTIONAL_LIGHT_COUNT) * turns;
    ChildValues values = ChildValues(0.0, MAX_FINITE, vec3(0.0), true);
    bool saved_bad = est_bad;
    for (int turn = 0; turn < light_turns + POLYGON_LIGHT_COUNT; ++turn) {
        int polygon = POLYGON_LIGHT_COUNT > 0 && turn >= light_turns ? turn - light_turns : -1;
        int i = refine ? turn / (REFINE_CHILDREN + 1) : turn;
        int r = refine ? turn % (REFINE_CHILDREN + 1) : REFINE_CHILDREN;
        GpuLight light = GpuLight(vec4(0.0), vec4(0.0));
        if (polygon < 0) {
            light = lights[i];
        }
        Frame at = frame;
        int mode = ADD_BOUNDS;
        if (polygon >= 0) {
            values = ChildValues(0.0, 0.0, vec3(0.0), false);
        } else if (refine && r < REFINE_CHILDREN) {
#ifdef CHILDREN_GIVEN
            if (i < GIVEN_LIGHTS) {
                continue;
            }
#endif
            if (r == 0) {
                values = ChildValues(0.0, MAX_FINITE, vec3(0.0), true);
                saved_bad = est_bad;
                est_bad = false;
            }
            vec3 q[3] = frame.vertices;
            midpoint_child(q, r);
            vec3 m[3] = frame.normals;
            midpoint_child(m, r);
            at = make_frame(q[0], q[1], q[2], m[0], m[1], m[2], frame.eye);
            mode = ADD_VALUES;
        } else if (refine) {
#ifdef CHILDREN_GIVEN
            if (i < GIVEN_LIGHTS) {
                saved_bad = est_bad;
                values = given_child_values(i, est_bad);
            }
#endif
            values.ok = values.ok && !est_bad;
            est_bad = saved_bad;
            mode = ADD_REFINED;
        }
        int added = add_light(at, material, param, polygon < 0 && i < POINT_LIGHT_COUNT, light.position.xyz,
                              light.radiance.rgb, polygon, top, n_max, eps, mode, values);
        if (mode != ADD_VALUES) {
            reason = worse(reason, added);
        } else if (added == REASON_NONE) {
            values.diffuse_inf = 0.0;
        } else if (added != VALUES_ADDED) {
            values.ok = false;
        }
    }
    if (est_bad) {
        reason = worse(reason, REASON_SINGULAR);
    }

    reason_out = reason;
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
    // Heuristic: the lowest grid level whose bound holds (see `decide` in Rust).
    if (SPLIT == 1 && !one_ok) {
        for (int k = 0; k < GRID_LEVEL_COUNT; ++k) {
            uint n = GRID_LEVELS[k];
            if (n > n_max) {
                break;
            }
            if (max_el(sum_grid[k]) <= eps) {
                level = rmin(level, grid_level[k]);
                break;
            }
        }
    }
    return level;
}

// One estimate of the triangle (p0, p1, p2) with vertex normals n0, n1, n2 seen from `eye`:
// >= 1, or FALLBACK_LEVEL when it must be shaded per pixel; never NaN. With `refine`, each light's
// ranges are taken over the triangle's children. `refine_next`: whether this estimate (without
// `refine`) is one that Rust estimates again with it: its `Estimate::level` (FALLBACK_LEVEL above
// n_max) exceeds REFINE_ABOVE (`!(<=)`: true for NaN, as Rust's fallback level).
float estimate_pass(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec3 eye, uint material_index,
                    vec2 param, float epsilon, float n_max_value, bool refine, out bool refine_next) {
    uint n_max = uint(clamp(n_max_value, 1.0, 64.0));
    P float eps = epsilon > 0.0 ? epsilon : 0.0;
    P float top = pattern_level(n_max, n_max);
    GpuMaterial material = materials[material_index];
    Frame frame = make_frame(p0, p1, p2, n0, n1, n2, eye);
    int reason = REASON_NONE;
    P float level = level_pass(frame, material, param, eps, n_max, top, refine, reason);
    refine_next = !refine && reason == REASON_NONE && (!(level <= REFINE_ABOVE) || !(level <= top));
    // false for NaN and infinity
    if (reason != REASON_NONE || !(level <= top)) {
        return FALLBACK_LEVEL;
    }
    return level;
}

// Estimate::level of the triangle: estimate_pass, and again with `refine` where it asks for it.
// One call site in a loop: a second one would inline the whole estimator twice.
float required_level(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec3 eye,
                     uint material_index, vec2 param, float epsilon, float n_max_value) {
    P float level = 0.0;
    bool again = false;
    for (int pass = 0; pass < 2; ++pass) {
        level = estimate_pass(p0, p1, p2, n0, n1, n2, eye, material_index, param, epsilon, n_max_value,
                              pass == 1, again);
        if (!again) {
            break;
        }
    }
    return level;
}


#endif
