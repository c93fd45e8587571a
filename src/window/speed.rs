//! The viewer's speed against `pixel` mode, measured in the same session: the per-pixel
//! reference's GPU time at the window's camera and size, timed for a few frames when the
//! window opens, when its size changes, when the camera has moved and `RETIME_EVERY` has
//! passed, and when the user presses T. The title divides it by the live frame time.

use crate::bench::Timing;
use crate::error::Result;
use crate::render::{Mode, Renderer, View};
use crate::scene::Camera;
use crate::vk::target::RenderTarget;
use ash::vk;
use std::time::{Duration, Instant};

/// Frames of `pixel` mode timed per reference (after one warm-up frame); the median counts.
const REFERENCE_FRAMES: u32 = 3;

/// The least time between two references taken because the camera moved.
const RETIME_EVERY: Duration = Duration::from_secs(2);

/// `pixel` mode's GPU time at one camera and size.
pub(super) struct PixelReference {
    /// The median of `REFERENCE_FRAMES` frames, in milliseconds.
    pub ms: f64,
    camera: Camera,
    extent: vk::Extent2D,
    at: Instant,
}

impl PixelReference {
    /// Whether a new reference is due for `view` at `extent` (`asked`: the user pressed T).
    pub fn due(reference: Option<&PixelReference>, view: &View, extent: vk::Extent2D, asked: bool) -> bool {
        let Some(reference) = reference else { return true };
        asked
            || reference.extent != extent
            || (reference.camera != view.camera && reference.at.elapsed() >= RETIME_EVERY)
    }

    /// Times `pixel` mode at `view`'s camera on `target`; the GPU must be done with the target.
    pub fn measure(renderer: &Renderer, target: &RenderTarget, view: &View) -> Result<PixelReference> {
        let pixel = View { mode: Mode::Pixel, heat_map: false, wireframe: false, ..view.clone() };
        let ms = renderer.measure(target, &pixel, 1, REFERENCE_FRAMES)?.gpu_ms();
        Ok(PixelReference {
            ms: Timing::of(&ms).median,
            camera: view.camera,
            extent: target.extent(),
            at: Instant::now(),
        })
    }
}

/// The title's speed: how many times faster than `pixel` a frame of `live_ms` is.
pub(super) fn speed_text(reference_ms: f64, live_ms: f64) -> String {
    format!("{:.2}× pixel's speed (pixel {reference_ms:.2} ms)", reference_ms / live_ms)
}

#[cfg(test)]
mod tests;
