//! Each render setting's one default and one check: the scene file's `[render]` keys, the
//! command line, `bench` and the viewer take their defaults and bounds from here, so that a
//! value one of them accepts the others accept too.

use std::ops::RangeInclusive;

/// ε, the shading-error bound, where neither the scene nor the command line gives one.
pub const DEFAULT_EPSILON: f32 = 0.075;
/// The ε values the viewer's keys halve and double it within: inside what [`check_epsilon`]
/// accepts.
pub const EPSILON_KEYS: RangeInclusive<f32> = 1.0e-4..=10.0;
/// n_max, the largest tessellation level before per-pixel fallback, where none is given.
pub const DEFAULT_N_MAX: u32 = 16;
/// The values n_max may take: the hardware tessellator's levels.
pub const N_MAX_RANGE: RangeInclusive<u32> = 1..=64;
/// The image width where none is given.
pub const DEFAULT_WIDTH: u32 = 1280;
/// The image height where none is given.
pub const DEFAULT_HEIGHT: u32 = 720;
/// The values an image's width and height may each take.
pub const IMAGE_SIZE_RANGE: RangeInclusive<u32> = 1..=16384;

/// A setting's value outside its bounds; displays as "must be EXPECTED (got VALUE)", for the
/// caller to put the setting's name in front.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("must be {expected} (got {value})")]
pub struct OutOfRange {
    /// What the setting must be, such as "a positive number".
    pub expected: String,
    /// The value given, as written in messages.
    pub value: String,
}

/// ε: a positive, finite number.
pub fn check_epsilon(epsilon: f32) -> Result<f32, OutOfRange> {
    if epsilon.is_finite() && epsilon > 0.0 {
        Ok(epsilon)
    } else {
        Err(OutOfRange { expected: "a positive number".into(), value: epsilon.to_string() })
    }
}

/// n_max: in [`N_MAX_RANGE`].
pub fn check_n_max(n_max: u32) -> Result<u32, OutOfRange> {
    if N_MAX_RANGE.contains(&n_max) {
        Ok(n_max)
    } else {
        Err(OutOfRange { expected: format!("in {}", range_text(&N_MAX_RANGE)), value: n_max.to_string() })
    }
}

/// An image size: width and height each in [`IMAGE_SIZE_RANGE`].
pub fn check_image_size(width: u32, height: u32) -> Result<(u32, u32), OutOfRange> {
    if IMAGE_SIZE_RANGE.contains(&width) && IMAGE_SIZE_RANGE.contains(&height) {
        Ok((width, height))
    } else {
        Err(OutOfRange {
            expected: format!("between {} and {}", IMAGE_SIZE_RANGE.start(), IMAGE_SIZE_RANGE.end()),
            value: format!("{width}x{height}"),
        })
    }
}

/// A range as messages write it: `1..=64`.
pub fn range_text(range: &RangeInclusive<u32>) -> String {
    format!("{}..={}", range.start(), range.end())
}
