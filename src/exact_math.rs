//! Bit-exact elementary functions: sine, cosine, arc tangent, arc cosine, arc sine, log₂, 2ˣ and
//! power, built from IEEE-754 f32 additions, multiplications, divisions, square roots, `floor`
//! and exact bit manipulation only, so that the GLSL twin (the same functions, operation for
//! operation, all `precise`) computes bit-identical values on any Vulkan device whose basic f32
//! arithmetic is IEEE (the drivers' `sin`, `atan`, `pow`, ... differ from libm and from each
//! other in the last bits, which flipped levels). The error estimator
//! ([`crate::shading::estimator`]) and the texture parameter mappings ([`crate::scene`]) use
//! them; this module imports nothing of the crate. Accuracy (tested in
//! `elementary_functions_are_accurate`): ~1 ulp-level, far inside the estimator's `ANGLE_PAD`
//! and `SAFETY`.
//!
//! GLSL twin: `glsl/include/exact_math.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels, which hang on
//! these functions bit for bit, equal the Rust twin's on every triangle of the shipped scenes,
//! textured ones included).

// `!(x >= y)` is used on purpose: it is also true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::f32::consts::{FRAC_2_PI, FRAC_PI_2, FRAC_PI_4, LN_2, LOG2_E, PI, SQRT_2};

/// π/2 split for Cody–Waite reduction: `P1 + P2` is exact in few bits (k·P1, k·P2 exact for
/// the small quadrant counts used here), `P3` the rest.
const PIO2_P1: f32 = 1.5703125;
const PIO2_P2: f32 = 0.0004837513;
const PIO2_P3: f32 = 7.54979e-8;
const TAN_PI_8: f32 = 0.41421357;

/// `x` reduced to `r ∈ [−π/4, π/4]` and the quadrant `x = r + n·π/2` (`n` mod 4).
fn reduce_quadrant(x: f32) -> (f32, i32) {
    let k = (x * FRAC_2_PI + 0.5).floor();
    let r = x - k * PIO2_P1 - k * PIO2_P2 - k * PIO2_P3;
    (r, (k as i32) & 3)
}

/// sin and cos on [−π/4, π/4]: Taylor polynomials (remainders below 2·10⁻⁹).
fn sin_poly(r: f32) -> f32 {
    let z = r * r;
    r + r * z * (-0.16666667 + z * (0.008333334 + z * (-0.0001984127 + z * 2.7557319e-6)))
}

fn cos_poly(r: f32) -> f32 {
    let z = r * r;
    1.0 - 0.5 * z + z * z * (0.041666668 + z * (-0.0013888889 + z * (2.4801588e-5 + z * -2.755732e-7)))
}

pub fn est_sin(x: f32) -> f32 {
    let (r, n) = reduce_quadrant(x);
    match n {
        0 => sin_poly(r),
        1 => cos_poly(r),
        2 => -sin_poly(r),
        _ => -cos_poly(r),
    }
}

pub fn est_cos(x: f32) -> f32 {
    let (r, n) = reduce_quadrant(x);
    match n {
        0 => cos_poly(r),
        1 => -sin_poly(r),
        2 => -cos_poly(r),
        _ => sin_poly(r),
    }
}

/// atan on [−tan(π/8), tan(π/8)]: Taylor series to t¹⁹ (remainder below 5·10⁻¹⁰).
fn atan_poly(t: f32) -> f32 {
    let z = t * t;
    let p = 0.06666667 + z * (-0.05882353 + z * 0.05263158);
    let p = -0.07692308 + z * p;
    let p = 0.09090909 + z * p;
    let p = -0.11111111 + z * p;
    let p = 0.14285715 + z * p;
    let p = -0.2 + z * p;
    let p = 0.33333334 + z * p;
    t - t * z * p
}

/// atan on [0, 1].
fn atan_unit(t: f32) -> f32 {
    if t > TAN_PI_8 {
        FRAC_PI_4 + atan_poly((t - 1.0) / (t + 1.0))
    } else {
        atan_poly(t)
    }
}

/// atan2 (0 for (0, 0)).
pub fn est_atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    if ax == 0.0 && ay == 0.0 {
        return 0.0;
    }
    let a = if ay <= ax { atan_unit(ay / ax) } else { FRAC_PI_2 - atan_unit(ax / ay) };
    let a = if x < 0.0 { PI - a } else { a };
    if y < 0.0 {
        -a
    } else {
        a
    }
}

/// acos on [−1, 1] (clamped), through atan2 of the sine `√((1 − x)(1 + x))`.
pub fn est_acos(x: f32) -> f32 {
    est_atan2(((1.0 - x) * (1.0 + x)).max(0.0).sqrt(), x)
}

/// asin on [−1, 1] (clamped).
pub fn est_asin(x: f32) -> f32 {
    est_atan2(x, ((1.0 - x) * (1.0 + x)).max(0.0).sqrt())
}

/// log₂ of a positive normal `x`: exponent and `ln m = 2 atanh((m−1)/(m+1))`, `m ∈ [√½, √2)`.
pub fn est_log2(x: f32) -> f32 {
    let bits = x.to_bits();
    let mut e = ((bits >> 23) & 0xff) as i32 - 127;
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let t = (m - 1.0) / (m + 1.0);
    let z = t * t;
    let ln_m = 2.0 * t * (1.0 + z * (0.33333334 + z * (0.2 + z * (0.14285715 + z * 0.11111111))));
    e as f32 + ln_m * LOG2_E
}

/// 2^z; 0 below 2⁻¹²⁶ (no subnormals: GPUs may flush them), ∞ from 2¹²⁸ on.
fn est_exp2(z: f32) -> f32 {
    if z.is_nan() {
        return z;
    }
    if z >= 128.0 {
        return f32::INFINITY;
    }
    if !(z >= -126.0) {
        return 0.0;
    }
    let n = z.floor();
    let u = (z - n) * LN_2;
    let p = 1.0
        + u * (1.0
            + u * (0.5
                + u * (0.16666667
                    + u * (0.041666668
                        + u * (0.008333334
                            + u * (0.0013888889
                                + u * (0.0001984127 + u * (2.4801588e-5 + u * 2.7557319e-6))))))));
    p * f32::from_bits(((n as i32 + 127) as u32) << 23)
}

/// `x^y` for `x ≥ 0` (NaN for negative `x`): `x⁰ = 1`, `x¹ = x`, `0^y = 0` or ∞.
pub fn est_pow(x: f32, y: f32) -> f32 {
    if y == 0.0 {
        return 1.0;
    }
    if y == 1.0 {
        return x;
    }
    if x == 0.0 {
        return if y > 0.0 { 0.0 } else { f32::INFINITY };
    }
    if !(x > 0.0) {
        return f32::NAN;
    }
    if x == f32::INFINITY {
        return if y > 0.0 { f32::INFINITY } else { 0.0 };
    }
    if x < f32::MIN_POSITIVE {
        // Subnormal: as 0 (GPUs may flush them).
        return if y > 0.0 { 0.0 } else { f32::INFINITY };
    }
    est_exp2(y * est_log2(x))
}

#[cfg(test)]
mod tests;
