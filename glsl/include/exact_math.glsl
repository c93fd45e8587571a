// The estimator's own bit-exact elementary functions (est_sin, est_cos, est_atan2, est_acos,
// est_asin, est_log2, est_exp2, est_pow) and the "Rust semantics" helpers (rmax, rmin, dot3,
// cross3, len, ...): from IEEE f32 +, -, *, /, sqrt, floor and bit manipulation only, every
// result `precise` (P), so that they are bit-identical to the Rust twin's (the drivers' sin,
// atan, pow, ... are not). Twin: `src/exact_math.rs`; proven equal through the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`). A leaf: it includes nothing.
#ifndef EXACT_MATH_GLSL
#define EXACT_MATH_GLSL

#define P precise

// std::f32::consts::PI and FRAC_PI_2.
const float EXACT_PI = 3.1415927;
const float HALF_PI = 1.5707964;          // std::f32::consts::FRAC_PI_2

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
    a = x < 0.0 ? EXACT_PI - a : a;
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

#endif
