//! Tests of `geometry::shadow_view`: every point of the scene's box lands inside the map that
//! shadow.glsl looks it up in, and the atlas's maps do not overlap.

use super::*;
use crate::test_rng::Rng;

/// `p`'s position in clip space divided through.
fn ndc(view_proj: Mat4, p: Vec3) -> Vec3 {
    view_proj.project_point3(p)
}

fn inside(v: Vec3) -> bool {
    let slack = 1e-4;
    v.x.abs() <= 1.0 + slack && v.y.abs() <= 1.0 + slack && v.z >= -slack && v.z <= 1.0 + slack
}

#[test]
fn a_directional_map_holds_every_point_of_the_box() {
    let mut rng = Rng(0x5eed_0001);
    for _ in 0..200 {
        let lo = rng.point(Vec3::splat(-50.0), Vec3::splat(0.0));
        let hi = lo + rng.point(Vec3::splat(0.01), Vec3::splat(30.0));
        let direction = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or(Vec3::NEG_Y);
        let (view_proj, width) = directional_map(direction, lo, hi);
        assert!(width > 0.0 && width.is_finite());
        let mut widest = 0.0f32;
        for _ in 0..50 {
            let p = rng.point(lo, hi);
            let v = ndc(view_proj, p);
            assert!(inside(v), "{p} of {lo}..{hi} lies at {v} of the map along {direction}");
            widest = widest.max(v.x.abs()).max(v.y.abs());
        }
        for corner in box_corners(lo, hi) {
            assert!(inside(ndc(view_proj, corner)));
        }
        // Fitted: the box is not lost in a map far larger than it.
        assert!(widest > 0.3, "the box fills {widest} of the map");
    }
}

#[test]
fn the_directional_map_looks_along_the_light() {
    let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
    let direction = Vec3::new(0.3, -1.0, 0.2).normalize();
    let (view_proj, _) = directional_map(direction, lo, hi);
    // Moving with the light: deeper, at the same place in the map.
    let a = ndc(view_proj, Vec3::ZERO);
    let b = ndc(view_proj, 0.5 * direction);
    assert!(b.z > a.z);
    assert!((a.truncate() - b.truncate()).length() < 1e-5);
}

#[test]
fn a_point_light_face_holds_every_direction_it_is_chosen_for() {
    let mut rng = Rng(0x5eed_0002);
    for _ in 0..100 {
        let lo = rng.point(Vec3::splat(-20.0), Vec3::splat(0.0));
        let hi = lo + rng.point(Vec3::splat(0.5), Vec3::splat(20.0));
        // Inside the box or outside it.
        let light = rng.point(lo - 5.0, hi + 5.0);
        let (near, far) = point_depth_range(light, lo, hi);
        for _ in 0..100 {
            let p = rng.point(lo, hi);
            let d = p - light;
            if d.length() < 1e-2 {
                continue;
            }
            let face = cube_face(d);
            let [axis, side, up] = face_basis(face);
            assert_eq!(axis.dot(d), d.abs().max_element());
            let v = ndc(point_face(light, face, near, far), p);
            assert!(inside(v), "{p} seen from {light} lies at {v} of face {face}");
            // shadow.glsl's projection without the matrix: the same point of the face.
            let along = axis.dot(d);
            let expected = Vec3::new(side.dot(d), -up.dot(d), far * (along - near) / (far - near)) / along;
            assert!((v - expected).abs().max_element() < 1e-4, "{v} against {expected}");
            // Farther along the same ray: deeper.
            assert!(ndc(point_face(light, face, near, far), light + 1.05 * d).z > v.z);
        }
    }
}

#[test]
fn maps_lie_inside_the_atlas_and_apart() {
    let mut rng = Rng(0x5eed_0003);
    for _ in 0..50 {
        let count = 1 + rng.below(8) as usize;
        let mut maps: Vec<ShadowMap> = (0..count)
            .map(|_| ShadowMap {
                projection: if rng.below(2) == 0 {
                    Projection::Orthographic(Mat4::IDENTITY)
                } else {
                    Projection::Cube { light: Vec3::ZERO, near: 0.1, far: 10.0 }
                },
                offset: [0, 0],
                size: 16 << rng.below(5),
                texel_width: 1.0,
            })
            .collect();
        let [width, height] = pack(&mut maps);
        let squares: Vec<([u32; 2], u32)> =
            maps.iter().flat_map(|m| m.views().into_iter().map(|(_, at)| (at, m.size))).collect();
        for (i, &(a, size_a)) in squares.iter().enumerate() {
            assert!(a[0] + size_a <= width && a[1] + size_a <= height);
            for &(b, size_b) in &squares[i + 1..] {
                let apart = a[0] + size_a <= b[0]
                    || b[0] + size_b <= a[0]
                    || a[1] + size_a <= b[1]
                    || b[1] + size_b <= a[1];
                assert!(apart, "{a:?} ({size_a}) overlaps {b:?} ({size_b})");
            }
        }
        let area: u32 = squares.iter().map(|(_, s)| s * s).sum();
        assert!(
            u64::from(width) * u64::from(height) <= 4 * u64::from(area),
            "{width}x{height} for {area} texels"
        );
    }
}
