//! A camera path ([`CameraPath`]): a scene file's keyframes of eye and target at times, or an
//! orbit about the camera's target that the command line asks for, and the camera at any time
//! of it. Keyframes are joined by cubic Hermite segments whose tangents are the Catmull–Rom
//! differences over uneven times (`(p₊ − p₋)/(t₊ − t₋)`), at rest at the first and the last
//! key: the eye and the target pass through every key, with a velocity that does not jump.
//! `Camera::on_path` (`model`) is the camera there.

use glam::{Quat, Vec3};

/// One keyframe: where the eye is and what it looks at, `time` seconds into the path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathKey {
    pub time: f32,
    pub eye: Vec3,
    pub target: Vec3,
}

/// How the camera moves over time.
#[derive(Clone, Debug, PartialEq)]
pub enum CameraPath {
    /// Through keyframes, in increasing time (at least two; the path begins at the first).
    Keys(Vec<PathKey>),
    /// One turn about the camera's target (about its up direction), in `seconds`.
    Orbit { seconds: f32 },
}

/// Which path a command follows (`--path`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathChoice {
    /// The scene file's `[[path]]`.
    Scene,
    /// One turn about the camera's target in this many seconds.
    Orbit(f32),
}

/// Samples per keyframe segment at which a scene file's path is checked (`validate`).
pub const CHECK_SAMPLES: usize = 32;

impl CameraPath {
    /// The path `choice` asks for, where the scene's own is `scene_path` (none: the scene has
    /// none to give).
    pub fn chosen(choice: PathChoice, scene_path: Option<&CameraPath>) -> Option<CameraPath> {
        match choice {
            PathChoice::Scene => scene_path.cloned(),
            PathChoice::Orbit(seconds) => Some(CameraPath::Orbit { seconds }),
        }
    }

    /// The path's length in seconds.
    pub fn duration(&self) -> f32 {
        match self {
            CameraPath::Keys(keys) => {
                keys.last().map_or(0.0, |k| k.time) - keys.first().map_or(0.0, |k| k.time)
            }
            CameraPath::Orbit { seconds } => *seconds,
        }
    }

    /// The times of its frames at `fps` frames a second: 0, 1/fps, … up to its duration
    /// (at least one frame).
    pub fn frame_times(&self, fps: f32) -> Vec<f32> {
        let count = (self.duration() * fps + 1e-3).floor().max(0.0) as usize + 1;
        (0..count).map(|k| k as f32 / fps).collect()
    }

    /// The eye and the target `time` seconds into the path (clamped to it); an orbit turns
    /// from the camera's `start` (its eye, target and up).
    pub fn eye_and_target(&self, start: (Vec3, Vec3, Vec3), time: f32) -> (Vec3, Vec3) {
        let (start_eye, start_target, up) = start;
        match self {
            CameraPath::Keys(keys) => {
                let t = keys[0].time + time.clamp(0.0, self.duration());
                let segment = keys.windows(2).position(|w| t <= w[1].time).unwrap_or(keys.len() - 2);
                let point = |f: fn(&PathKey) -> Vec3| hermite(keys, segment, t, f);
                (point(|k| k.eye), point(|k| k.target))
            }
            CameraPath::Orbit { seconds } => {
                let share = if *seconds > 0.0 { (time / seconds).clamp(0.0, 1.0) } else { 0.0 };
                let turn = Quat::from_axis_angle(up.normalize(), std::f32::consts::TAU * share);
                (start_target + turn * (start_eye - start_target), start_target)
            }
        }
    }
}

/// Segment `segment` (from key `segment` to the next) of the Hermite spline through `keys`'
/// points `f` at time `t`.
fn hermite(keys: &[PathKey], segment: usize, t: f32, f: fn(&PathKey) -> Vec3) -> Vec3 {
    let (k0, k1) = (&keys[segment], &keys[segment + 1]);
    let span = k1.time - k0.time;
    let tangent = |i: usize| {
        if i == 0 || i == keys.len() - 1 {
            Vec3::ZERO
        } else {
            (f(&keys[i + 1]) - f(&keys[i - 1])) / (keys[i + 1].time - keys[i - 1].time)
        }
    };
    let s = ((t - k0.time) / span).clamp(0.0, 1.0);
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    f(k0) * h00 + tangent(segment) * (h10 * span) + f(k1) * h01 + tangent(segment + 1) * (h11 * span)
}

#[cfg(test)]
mod tests;
