//! The frame guard of `multirate` mode: a frame is never drawn the slower way for long.
//!
//! The cost model ([`super::cost_model`]) decides per triangle and per mesh from figures
//! measured once, in one setting. A scene can still lose against `pixel`, and the model cannot
//! see why: spotlight cones that send most evaluations to the per-pixel fallback after the
//! estimate, a driver setting in which a pixel costs a quarter of the calibration's, a frame
//! with so little shading to save that the pre-pass's fixed cost alone outweighs it. The guard
//! measures instead of predicting. It draws a few frames the multirate way, then a probe whose
//! frames alternate between the other way and the chosen one (`pixel` mode's way: every mesh
//! whole, no pre-pass; the reference, so accuracy is never lost), and from then on draws the
//! way whose recent frames were faster, probing the other again now and then ([`PathGuard`]),
//! since the camera and the scene's costs move.
//!
//! The renderer keeps one guard per configuration ([`GuardKey`]: extent, ε, `n_max`, how the
//! estimator runs); the camera is not part of it. The guard only schedules and compares:
//! callers that time their frames (`Renderer::measure`, the window) ask it how to draw the
//! next frame ([`PathGuard::next_frame`]) and report each frame's GPU time with the way it
//! was drawn ([`PathGuard::record`]), in whatever order the times come back.

use super::mode::Mode;
use super::multirate_config::MultirateConfig;
use super::view::View;

/// Frames drawn the other way in a probe (each followed by one of the chosen way), and the
/// recent frames of each way that are compared.
pub const PROBE_FRAMES: u32 = 3;
/// Frames of the chosen way from one probe to the next after a close decision.
pub const REPROBE_EVERY: u32 = 120;
/// The most frames between probes: after each decisive decision that keeps the choice, the gap
/// doubles up to this (about half a minute at 60 frames a second).
pub const LONGEST_GAP: u32 = 16 * REPROBE_EVERY;
/// A decision is decisive where the slower way took at least this many times the faster's.
pub const DECISIVE: f64 = 1.25;
/// Where each of the chosen way's latest [`PROBE_FRAMES`] frames took more than this factor times
/// what the way was chosen on (and more than the other way took then), or each less than that
/// time divided by it (the camera, the scene or the machine changed), the guard probes at once.
pub const MOVED: f64 = 1.5;

/// How a guarded `multirate` frame is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FramePath {
    /// The pre-pass, then the meshes as the cost model chose.
    Multirate,
    /// Every mesh as `pixel` mode draws it, without the pre-pass.
    Pixel,
}

impl FramePath {
    fn other(self) -> FramePath {
        match self {
            FramePath::Multirate => FramePath::Pixel,
            FramePath::Pixel => FramePath::Multirate,
        }
    }

    fn index(self) -> usize {
        match self {
            FramePath::Multirate => 0,
            FramePath::Pixel => 1,
        }
    }
}

/// Which way to draw, from the GPU times of recent frames drawn each way.
///
/// It draws [`PROBE_FRAMES`] frames the chosen way (multirate at first), then the probe:
/// [`PROBE_FRAMES`] frames the other way, each followed by one the chosen way. Once the probe's
/// times are in, the choice becomes the way whose fastest frame among its latest
/// [`PROBE_FRAMES`] is faster (the fastest, since a frame is only ever slowed by what else the
/// device does); a tie keeps multirate. It decides only then, and the probe alternates the
/// ways, so that the frames compared were drawn side by side: a machine's speed drifts over
/// seconds, and a probe of three frames one way after three the other may compare two speeds
/// of the machine rather than the two ways (docs/cost_model.md, "Per frame, the guard").
///
/// A probe costs what the slower way costs more, and shows as a hitch in a window, so the gap
/// to the next probe starts at [`REPROBE_EVERY`] frames and doubles (up to [`LONGEST_GAP`])
/// each time a probe decisively ([`DECISIVE`]) confirms the choice. Where the chosen way's
/// latest [`PROBE_FRAMES`] frames all moved by more than [`MOVED`] from what it was chosen on,
/// the same way, and, slower, beyond what the other way took then (before that the choice still
/// holds unless the other way sped up, which the next probe finds), the next frame probes and
/// the gap starts over; a single frame never does.
#[derive(Clone, Debug)]
pub struct PathGuard {
    choice: FramePath,
    /// Frames of the chosen way still to draw before the next probe.
    until_probe: u32,
    /// Frames of the current probe still to draw (both ways).
    probe_left: u32,
    /// Frames between the last decision and the next probe.
    gap: u32,
    /// Per way ([`FramePath::index`]), the latest GPU times in milliseconds, oldest first.
    recent: [Vec<f64>; 2],
    /// Times of the way not chosen that came back since the current probe began.
    probed: u32,
    /// The last decision's times, until the chosen way's frames move away from them.
    decision: Option<Decision>,
    decided: bool,
}

/// The times a probe's decision was made with: each way's fastest recent frame.
#[derive(Clone, Copy, Debug)]
struct Decision {
    /// The way chosen.
    chosen_ms: f64,
    /// The other way.
    beaten_ms: f64,
}

impl Default for PathGuard {
    fn default() -> PathGuard {
        PathGuard {
            choice: FramePath::Multirate,
            until_probe: PROBE_FRAMES,
            probe_left: 0,
            gap: REPROBE_EVERY,
            recent: [Vec::new(), Vec::new()],
            probed: 0,
            decision: None,
            decided: false,
        }
    }
}

impl PathGuard {
    /// How to draw the next frame.
    pub fn next_frame(&mut self) -> FramePath {
        if self.probe_left > 0 {
            self.probe_left -= 1;
            // The other way's frames are those with an odd count left after them.
            return if self.probe_left % 2 == 1 { self.choice.other() } else { self.choice };
        }
        if self.until_probe == 0 {
            // Times of the other way still on their way back were drawn before a switch.
            self.probed = 0;
            self.probe_left = 2 * PROBE_FRAMES - 1;
            self.until_probe = self.gap;
            return self.choice.other();
        }
        self.until_probe -= 1;
        self.choice
    }

    /// A frame drawn `path`'s way took `gpu_ms`. Times that are not finite and positive (a
    /// frame whose timestamps the device did not write) are ignored.
    pub fn record(&mut self, path: FramePath, gpu_ms: f64) {
        if !(gpu_ms.is_finite() && gpu_ms > 0.0) {
            return;
        }
        let recent = &mut self.recent[path.index()];
        if recent.len() == PROBE_FRAMES as usize {
            recent.remove(0);
        }
        recent.push(gpu_ms);
        if path == self.choice {
            let recent = &self.recent[path.index()];
            // Every one of the latest frames beyond the factor, the same way: one frame slowed by
            // the machine, or sped up by a frame that reused its levels, is not a move.
            // Slower counts only where it may have lost: beyond what the other way took then.
            let moved = self.decision.is_some_and(|Decision { chosen_ms, beaten_ms }| {
                fastest(recent) > (chosen_ms * MOVED).max(beaten_ms) || slowest(recent) * MOVED < chosen_ms
            });
            if moved && recent.len() == PROBE_FRAMES as usize && self.probe_left == 0 {
                self.until_probe = 0;
                self.gap = REPROBE_EVERY;
                self.decision = None;
            }
            return;
        }
        self.probed += 1;
        if self.probed >= PROBE_FRAMES {
            let [multirate, pixel] = self.recent.each_ref().map(|times| fastest(times));
            let winner = if pixel < multirate { FramePath::Pixel } else { FramePath::Multirate };
            let decisive = multirate.max(pixel) >= DECISIVE * multirate.min(pixel);
            self.gap = if decisive && winner == self.choice {
                (2 * self.gap).min(LONGEST_GAP)
            } else {
                REPROBE_EVERY
            };
            self.choice = winner;
            // The probe's last frame of the chosen way, if still to draw, is drawn the way chosen.
            self.probe_left = 0;
            self.until_probe = self.gap;
            self.decision =
                Some(Decision { chosen_ms: multirate.min(pixel), beaten_ms: multirate.max(pixel) });
            self.probed = 0;
            self.decided = true;
        }
    }

    /// The way unprobed frames are drawn now.
    pub fn choice(&self) -> FramePath {
        self.choice
    }

    /// Whether a probe's times have come in and decided the choice at least once.
    pub fn decided(&self) -> bool {
        self.decided
    }
}

/// The fastest of `times` (infinite where there are none).
fn fastest(times: &[f64]) -> f64 {
    times.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The slowest of `times` (zero where there are none).
fn slowest(times: &[f64]) -> f64 {
    times.iter().copied().fold(0.0, f64::max)
}

/// The key of a frame of `view` in the multirate configuration `config`, or None where the guard
/// does not apply: outside `multirate` mode, without the cost model (a view that fixes the
/// estimated area asks for the multirate way itself), and in the debug views (heat map,
/// wireframe), which show the multirate way's own work. Frames of another key draw other work;
/// the camera, and with it the ball of eyes, is not part of it.
pub fn key_of(view: &View, config: &MultirateConfig) -> Option<MultirateConfig> {
    let guarded = view.mode == Mode::Multirate && view.cost_model && !view.heat_map && !view.wireframe;
    guarded.then(|| config.without_eye())
}

/// The renderer's guards, one per key seen.
#[derive(Debug, Default)]
pub struct Guards {
    guards: Vec<(MultirateConfig, PathGuard)>,
}

impl Guards {
    /// The guard of `key`, new where the key was not seen.
    pub fn of(&mut self, key: MultirateConfig) -> &mut PathGuard {
        let at = match self.guards.iter().position(|(seen, _)| *seen == key) {
            Some(at) => at,
            None => {
                self.guards.push((key, PathGuard::default()));
                self.guards.len() - 1
            }
        };
        &mut self.guards[at].1
    }
}

#[cfg(test)]
mod tests;
