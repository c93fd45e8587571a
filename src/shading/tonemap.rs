//! The display transform: exposure, the ACES filmic tone curve and sRGB encoding. The twin of
//! `glsl/include/tonemap.glsl` (the viewer's); PNG output and the image metrics use it.

/// The ACES filmic curve (Narkowicz 2015 fit), clamped to [0, 1].
pub fn aces_filmic(x: f32) -> f32 {
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// The sRGB opto-electronic transfer function.
pub fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        linear * 12.92
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Linear radiance to an 8-bit sRGB display value.
pub fn display_value(linear: f32, exposure: f32) -> u8 {
    let mapped = aces_filmic(linear.max(0.0) * exposure);
    (srgb_encode(mapped) * 255.0 + 0.5).clamp(0.0, 255.0) as u8
}
