//! Culling before the estimate: which triangles of the multirate pass cannot be seen and get
//! outer level 0 without running the estimator, and which are shaded per pixel without it (the
//! back faces of two-sided meshes). The Rust twin of `patch_culled` and `visible_level` in
//! `glsl/include/triangle_level.glsl`, operation for operation (no fused multiply-adds on
//! either side), so that the level records of the GPU and of `analysis::report` agree bit for
//! bit; `tests/multirate.rs` checks that.

use glam::{Mat4, Vec3, Vec4};

/// Back faces are culled before the estimate only when the eye is more than this sine (squared)
/// away from their plane; the rasteriser culls the nearly edge-on rest, so what is drawn never
/// differs from `pixel` mode, which leaves all back-face culling to the rasteriser.
pub const BACKFACE_MARGIN_SQUARED: f32 = 1.0e-6;

/// The level of a culled triangle (`CULLED_LEVEL` in triangle_level.glsl): below every real
/// level, so that a culled neighbour asks for no more than level 1 on the shared edge. The
/// level records of a culled triangle read `[CULLED_LEVEL, 0, 0, 0]`.
pub const CULLED_LEVEL: f32 = -1.0;

/// Clip-space position of world point `p`, summed in the shader's order.
pub fn clip_of(view_proj: &Mat4, p: Vec3) -> Vec4 {
    ((view_proj.x_axis * p.x + view_proj.y_axis * p.y) + view_proj.z_axis * p.z) + view_proj.w_axis
}

fn dot3(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

fn cross3(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y)
}

/// Whether the triangle `p` lies wholly outside one plane of the view frustum of `view_proj`,
/// or, on a one-sided mesh, faces away from `eye` (front faces wind anticlockwise).
pub fn culled(view_proj: &Mat4, eye: Vec3, p: [Vec3; 3], one_sided: bool) -> bool {
    let c = p.map(|p| clip_of(view_proj, p));
    let all = |outside: &dyn Fn(&Vec4) -> bool| c.iter().all(outside);
    if all(&|c| c.x > c.w)
        || all(&|c| c.x < -c.w)
        || all(&|c| c.y > c.w)
        || all(&|c| c.y < -c.w)
        || all(&|c| c.z > c.w)
        || all(&|c| c.z < 0.0)
    {
        return true;
    }
    one_sided && faces_away(eye, p)
}

/// Whether `eye` lies clearly behind the plane of the triangle `p` (more than the sine
/// [`BACKFACE_MARGIN_SQUARED`] away from it; front faces wind anticlockwise).
pub fn faces_away(eye: Vec3, p: [Vec3; 3]) -> bool {
    let normal = cross3(p[1] - p[0], p[2] - p[0]);
    let to_eye = eye - p[0];
    let facing = dot3(normal, to_eye);
    let margin = BACKFACE_MARGIN_SQUARED * dot3(normal, normal) * dot3(to_eye, to_eye);
    facing < 0.0 && facing * facing > margin
}

/// Whether a triangle that is not [`culled`] is shaded per pixel without an estimate
/// (`visible_level` in triangle_level.glsl): a back face of a two-sided mesh. The fallback
/// draw comes after the others, so where the mesh's front faces hide such a face (the far side
/// of an open mesh) the early depth test rejects its fragments before they shade, where
/// interpolated shading would shade all of its sub-vertices.
pub fn shaded_per_pixel(eye: Vec3, p: [Vec3; 3], one_sided: bool) -> bool {
    !one_sided && faces_away(eye, p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::camera::view_projection;
    use crate::scene::Camera;

    fn camera() -> Camera {
        Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_degrees: 60.0,
            near: 0.1,
            far: 100.0,
        }
    }

    #[test]
    fn a_facing_triangle_in_view_is_kept_and_its_back_culled_when_one_sided() {
        let cam = camera();
        let vp = view_projection(&cam, 640, 480);
        let front = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let back = [front[0], front[2], front[1]];
        assert!(!culled(&vp, cam.eye, front, true));
        assert!(culled(&vp, cam.eye, back, true));
        assert!(!culled(&vp, cam.eye, back, false), "two-sided meshes keep back faces");
        assert!(shaded_per_pixel(cam.eye, back, false), "and shade them per pixel");
        assert!(!shaded_per_pixel(cam.eye, front, false) && !shaded_per_pixel(cam.eye, back, true));
    }

    #[test]
    fn triangles_outside_one_plane_are_culled_and_straddling_ones_kept() {
        let cam = camera();
        let vp = view_projection(&cam, 640, 480);
        let shifted = |d: Vec3| {
            [Vec3::new(-0.5, -0.5, 0.0) + d, Vec3::new(0.5, -0.5, 0.0) + d, Vec3::new(0.0, 0.5, 0.0) + d]
        };
        for d in [Vec3::X * 50.0, -Vec3::X * 50.0, Vec3::Y * 50.0, -Vec3::Y * 50.0, Vec3::Z * 10.0] {
            assert!(culled(&vp, cam.eye, shifted(d), false), "{d}");
        }
        assert!(culled(&vp, cam.eye, shifted(-Vec3::Z * 200.0), false), "beyond the far plane");
        // One corner far outside on the right, the others inside: kept.
        let straddling = [Vec3::new(-0.5, 0.0, 0.0), Vec3::new(50.0, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0)];
        assert!(!culled(&vp, cam.eye, straddling, false));
        // Corners outside different planes (left and right) span the view: kept.
        let spanning = [Vec3::new(-50.0, -0.1, 0.0), Vec3::new(50.0, -0.1, 0.0), Vec3::new(0.0, 0.1, 0.0)];
        assert!(!culled(&vp, cam.eye, spanning, false));
    }

    #[test]
    fn nearly_edge_on_back_faces_are_left_to_the_rasteriser() {
        let cam = camera();
        let vp = view_projection(&cam, 640, 480);
        // A back face in the plane y = −h, seen from the eye at a sine of about h / 5.
        let back_face =
            |h: f32| [Vec3::new(-1.0, -h, 0.0), Vec3::new(0.0, -h, -1.0), Vec3::new(1.0, -h, 0.0)];
        assert!(!culled(&vp, cam.eye, back_face(5.0e-4), true), "sine 1e-4: left to the rasteriser");
        assert!(culled(&vp, cam.eye, back_face(0.05), true), "sine 1e-2: culled");
    }
}
