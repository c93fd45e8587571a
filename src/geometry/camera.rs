//! Camera matrices for Vulkan's clip space (y down, depth 0 at near, 1 at far), and the orbit
//! state of the interactive viewer.

use crate::scene::Camera;
use glam::{Mat4, Vec3, Vec4};

/// Right-handed perspective projection into Vulkan clip space.
pub fn perspective(fov_y_radians: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let f = 1.0 / (0.5 * fov_y_radians).tan();
    let depth = far / (near - far);
    Mat4::from_cols(
        Vec4::new(f / aspect, 0.0, 0.0, 0.0),
        Vec4::new(0.0, -f, 0.0, 0.0),
        Vec4::new(0.0, 0.0, depth, -1.0),
        Vec4::new(0.0, 0.0, near * depth, 0.0),
    )
}

/// Right-handed view matrix: camera at `eye` looking at `target`, `up` roughly up.
pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    let forward = (target - eye).normalize();
    let side = forward.cross(up).normalize();
    let up = side.cross(forward);
    Mat4::from_cols(
        Vec4::new(side.x, up.x, -forward.x, 0.0),
        Vec4::new(side.y, up.y, -forward.y, 0.0),
        Vec4::new(side.z, up.z, -forward.z, 0.0),
        Vec4::new(-side.dot(eye), -up.dot(eye), forward.dot(eye), 1.0),
    )
}

/// World to clip space for `camera` on a target of `width`×`height` pixels.
pub fn view_projection(camera: &Camera, width: u32, height: u32) -> Mat4 {
    let aspect = width as f32 / height.max(1) as f32;
    let view = look_at(camera.eye, camera.target, camera.up);
    perspective(camera.fov_y_degrees.to_radians(), aspect, camera.near, camera.far) * view
}

/// World-space ray (origin, unit direction) through framebuffer position (x, y), in pixels
/// from the top-left corner (the centre of pixel (i, j) is (i + 0.5, j + 0.5)).
pub fn pixel_ray(camera: &Camera, width: u32, height: u32, x: f32, y: f32) -> (Vec3, Vec3) {
    let inverse = view_projection(camera, width, height).inverse();
    let ndc_x = x / width as f32 * 2.0 - 1.0;
    let ndc_y = y / height as f32 * 2.0 - 1.0;
    let far = inverse.project_point3(Vec3::new(ndc_x, ndc_y, 1.0));
    (camera.eye, (far - camera.eye).normalize())
}

/// Orbit camera of the viewer: spherical coordinates around the scene camera's target.
#[derive(Clone, Debug)]
pub struct Orbit {
    pub target: Vec3,
    pub distance: f32,
    pub yaw: f32,
    pub pitch: f32,
}

impl Orbit {
    pub fn from_camera(camera: &Camera) -> Orbit {
        let offset = camera.eye - camera.target;
        let distance = offset.length();
        Orbit {
            target: camera.target,
            distance,
            yaw: offset.x.atan2(offset.z),
            pitch: (offset.y / distance).clamp(-1.0, 1.0).asin(),
        }
    }

    /// Rotates by pixel deltas of a mouse drag.
    pub fn rotate(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.005;
        self.pitch = (self.pitch + dy * 0.005).clamp(-1.5, 1.5);
    }

    /// Zooms by wheel steps (positive: closer).
    pub fn zoom(&mut self, steps: f32) {
        self.distance *= 0.9f32.powf(steps);
    }

    /// The scene camera moved to this orbit position (up stays +Y).
    pub fn apply(&self, camera: &Camera) -> Camera {
        let direction =
            Vec3::new(self.pitch.cos() * self.yaw.sin(), self.pitch.sin(), self.pitch.cos() * self.yaw.cos());
        Camera { eye: self.target + direction * self.distance, target: self.target, up: Vec3::Y, ..*camera }
    }
}

#[cfg(test)]
mod tests;
