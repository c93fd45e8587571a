//! The viewer's camera path: the scene file's `[[path]]` played from the window's start and
//! looped; Space pauses and resumes it, and a drag or a scroll takes the camera over from where
//! the path left it (Space then follows the path again from there).

use crate::scene::path::CameraPath;
use crate::scene::Camera;
use glam::Vec3;
use std::time::Instant;

/// A camera path as the viewer plays it.
pub(super) struct PathPlayer {
    path: CameraPath,
    /// The scene's box, which the far plane follows (`Camera::on_path`).
    bounds: (Vec3, Vec3),
    /// Seconds into the path when it was last paused or resumed.
    position: f32,
    /// Since when it plays; none while paused.
    playing_since: Option<Instant>,
    /// Whether the window's camera follows it (false once a drag or a scroll took over).
    pub following: bool,
}

impl PathPlayer {
    /// `path` in a scene of box `bounds`, playing from its start now.
    pub fn new(path: CameraPath, bounds: (Vec3, Vec3)) -> PathPlayer {
        PathPlayer { path, bounds, position: 0.0, playing_since: Some(Instant::now()), following: true }
    }

    /// Seconds into the path now (looped).
    pub fn time(&self) -> f32 {
        let elapsed = self.playing_since.map_or(0.0, |since| since.elapsed().as_secs_f32());
        let duration = self.path.duration();
        if duration > 0.0 {
            (self.position + elapsed) % duration
        } else {
            0.0
        }
    }

    pub fn playing(&self) -> bool {
        self.following && self.playing_since.is_some()
    }

    /// Space: pauses a playing path, and plays a paused one (following it again, from where it
    /// was left, after a drag took the camera over).
    pub fn toggle(&mut self) {
        if self.playing() {
            self.pause();
        } else {
            self.following = true;
            self.playing_since = Some(Instant::now());
        }
    }

    /// Stops the path where it is.
    pub fn pause(&mut self) {
        self.position = self.time();
        self.playing_since = None;
    }

    /// `camera` where the path is now.
    pub fn camera(&self, camera: &Camera) -> Camera {
        camera.on_path(&self.path, self.time(), self.bounds)
    }
}
