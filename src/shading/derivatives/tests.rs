use super::*;
use crate::geometry::camera::{look_at, perspective};
use glam::{DMat3, DVec2, DVec3, DVec4, Mat4};

const VIEWPORT: Vec2 = Vec2::new(1280.0, 720.0);

use crate::test_rng::Rng;

fn view_projection() -> Mat4 {
    let aspect = VIEWPORT.x / VIEWPORT.y;
    perspective(50f32.to_radians(), aspect, 0.1, 100.0)
        * look_at(Vec3::new(0.3, 0.5, 4.0), Vec3::ZERO, Vec3::Y)
}

fn pixel_of(m: Mat4, p: Vec3) -> Vec2 {
    let c = m * p.extend(1.0);
    (c.xy() / c.w + 1.0) * 0.5 * VIEWPORT
}

/// A world-space triangle in front of the camera covering at least 20 pixels, no sliver (every
/// altitude at least 2 pixels), with a vertex far behind the others a third of the time
/// (strong perspective), and a world point on its plane that projects into the viewport,
/// inside the triangle or (when `outside`) near it.
fn random_case(rng: &mut Rng, m: Mat4, outside: bool) -> ([Vec3; 3], Vec3) {
    loop {
        let mut v = [Vec3::ZERO; 3];
        for p in &mut v {
            *p = rng.point(Vec3::splat(-1.5), Vec3::splat(1.5));
        }
        if rng.f() < 0.33 {
            v[2] = rng.point(Vec3::new(-3.0, -3.0, -40.0), Vec3::new(3.0, 3.0, -10.0));
        }
        let s = v.map(|p| pixel_of(m, p));
        let area = 0.5 * ((s[1] - s[0]).perp_dot(s[2] - s[0])).abs();
        let longest = (s[1] - s[0]).length().max((s[2] - s[1]).length()).max((s[0] - s[2]).length());
        let mut b = Vec3::new(rng.f(), rng.f(), rng.f()) + 0.01;
        if outside {
            b = Vec3::new(rng.range(-0.5, 1.5), rng.range(-0.5, 1.5), rng.range(-0.5, 1.5));
        }
        if (b.x + b.y + b.z).abs() < 0.2 {
            continue;
        }
        b /= b.x + b.y + b.z;
        let point = v[0] * b.x + v[1] * b.y + v[2] * b.z;
        let pixel = pixel_of(m, point);
        let visible = pixel.cmpge(Vec2::ZERO).all() && pixel.cmple(VIEWPORT).all();
        if area >= 20.0 && 2.0 * area / longest >= 2.0 && visible && (m * point.extend(1.0)).w > 0.2 {
            return (v, point);
        }
    }
}

/// Perspective-correct barycentrics by another route, in f64: the λ with Σλ = 1 whose
/// clip-space point Σ λᵢ cᵢ has NDC x and y equal to the pixel's, a 3×3 linear system.
fn reference_lambda(clip: [Vec4; 3], pixel: DVec2) -> DVec3 {
    let ndc = pixel / VIEWPORT.as_dvec2() * 2.0 - 1.0;
    let column = |c: DVec4| DVec3::new(c.x - ndc.x * c.w, c.y - ndc.y * c.w, 1.0);
    let [a, b, c] = clip.map(|c| column(c.as_dvec4()));
    DMat3::from_cols(a, b, c).inverse() * DVec3::Z
}

/// Central differences of `f` over ±1e-2 pixel in x and y.
fn central<T: std::ops::Sub<Output = T> + std::ops::Mul<f64, Output = T>>(
    f: impl Fn(DVec2) -> T,
    pixel: Vec2,
) -> (T, T) {
    let (p, h) = (pixel.as_dvec2(), 1e-2);
    let dx = (f(p + DVec2::X * h) - f(p - DVec2::X * h)) * (0.5 / h);
    let dy = (f(p + DVec2::Y * h) - f(p - DVec2::Y * h)) * (0.5 / h);
    (dx, dy)
}

/// `|got − want| ≤ tolerance · scale` component-wise, `scale` the largest |want| component
/// of the pair of derivatives (a relative tolerance that a zero component does not defeat).
fn close(got: DVec3, want: DVec3, scale: f64, tolerance: f64) -> bool {
    (got - want).abs().max_element() <= tolerance * scale
}

#[test]
fn lambda_reproduces_the_pixel() {
    let m = view_projection();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for case in 0..300 {
        let (v, point) = random_case(&mut rng, m, case % 2 == 1);
        let pixel = pixel_of(m, point);
        let clip = v.map(|p| m * p.extend(1.0));
        let d = barycentric_derivatives(clip, pixel, VIEWPORT);
        let seen = v[0] * d.lambda.x + v[1] * d.lambda.y + v[2] * d.lambda.z;
        let error = (pixel_of(m, seen) - pixel).abs().max_element();
        assert!(error < 2e-3, "case {case}: Σλᵢ Vᵢ lands {error} pixels from the pixel");
        let reference = reference_lambda(clip, pixel.as_dvec2());
        assert!((d.lambda.as_dvec3() - reference).abs().max_element() < 1e-4, "case {case}");
        assert!((d.lambda.x + d.lambda.y + d.lambda.z - 1.0).abs() < 1e-5);
    }
}

#[test]
fn barycentric_derivatives_match_finite_differences() {
    let m = view_projection();
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for case in 0..300 {
        let (v, point) = random_case(&mut rng, m, case % 2 == 1);
        let pixel = pixel_of(m, point);
        let clip = v.map(|p| m * p.extend(1.0));
        let d = barycentric_derivatives(clip, pixel, VIEWPORT);
        let (fx, fy) = central(|p| reference_lambda(clip, p), pixel);
        let scale = fx.abs().max(fy.abs()).max_element();
        assert!(close(d.ddx.as_dvec3(), fx, scale, 2e-4), "case {case}: {} vs {fx}", d.ddx);
        assert!(close(d.ddy.as_dvec3(), fy, scale, 2e-4), "case {case}: {} vs {fy}", d.ddy);
        assert!(((d.ddx.x + d.ddx.y + d.ddx.z) as f64).abs() <= 1e-5 * scale);
    }
}

#[test]
fn attribute_derivatives_of_an_affine_uv_match_finite_differences() {
    let m = view_projection();
    let mut rng = Rng(0x0123_4567_89ab_cdef);
    for case in 0..300 {
        let (v, point) = random_case(&mut rng, m, case % 3 == 2);
        let pixel = pixel_of(m, point);
        let clip = v.map(|p| m * p.extend(1.0));
        let d = barycentric_derivatives(clip, pixel, VIEWPORT);
        let rows =
            [rng.point(Vec3::splat(-2.0), Vec3::splat(2.0)), rng.point(Vec3::splat(-2.0), Vec3::splat(2.0))];
        let offset = Vec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let uv_of = |p: Vec3| Vec2::new(rows[0].dot(p), rows[1].dot(p)) + offset;
        let (uv, du_dx, du_dy) = interpolate2(&d, v.map(uv_of));
        let magnitude = v.map(|p| uv_of(p).abs().max_element()).into_iter().fold(1.0, f32::max);
        let error = (uv - uv_of(point)).abs().max_element();
        assert!(error < 1e-5 * magnitude, "case {case}: {uv} vs {}", uv_of(point));

        let world_at = |p: DVec2| {
            let l = reference_lambda(clip, p);
            v[0].as_dvec3() * l.x + v[1].as_dvec3() * l.y + v[2].as_dvec3() * l.z
        };
        let uv_at = |p: DVec2| {
            let w = world_at(p);
            DVec3::new(
                rows[0].as_dvec3().dot(w) + offset.x as f64,
                rows[1].as_dvec3().dot(w) + offset.y as f64,
                0.0,
            )
        };
        let (fx, fy) = central(uv_at, pixel);
        let scale = fx.abs().max(fy.abs()).max_element();
        assert!(close(du_dx.extend(0.0).as_dvec3(), fx, scale, 2e-4), "case {case}: {du_dx} vs {fx}");
        assert!(close(du_dy.extend(0.0).as_dvec3(), fy, scale, 2e-4), "case {case}: {du_dy} vs {fy}");

        let (p, dp_dx, dp_dy) = interpolate3(&d, v);
        assert!((p - point).abs().max_element() < 1e-4 * (1.0 + point.abs().max_element()), "case {case}");
        let (fx, fy) = central(world_at, pixel);
        let scale = fx.abs().max(fy.abs()).max_element();
        assert!(close(dp_dx.as_dvec3(), fx, scale, 2e-4), "case {case}: {dp_dx} vs {fx}");
        assert!(close(dp_dy.as_dvec3(), fy, scale, 2e-4), "case {case}: {dp_dy} vs {fy}");
    }
}

#[test]
fn texture_lod_is_log2_of_the_longer_footprint() {
    let size = Vec2::new(512.0, 128.0);
    // 3 and 4 texels along x and y per pixel step in x: a footprint of 5 texels.
    let dx = Vec2::new(3.0 / 512.0, 4.0 / 128.0);
    let dy = Vec2::new(0.0, 2.0 / 128.0);
    assert!((texture_lod(dx, dy, size) - 5f32.log2()).abs() < 1e-6);
    assert!((texture_lod(dy, dx, size) - 5f32.log2()).abs() < 1e-6);
    assert!((texture_lod(dx * 0.25, dy * 0.25, size) - (1.25f32).log2()).abs() < 1e-6);
    // A footprint of exactly one texel is level 0; of 2^k texels, level k.
    assert!(texture_lod(Vec2::new(1.0 / 512.0, 0.0), Vec2::ZERO, size).abs() < 1e-6);
    assert!((texture_lod(Vec2::ZERO, Vec2::new(0.0, 8.0 / 128.0), size) - 3.0).abs() < 1e-6);
    let zero = texture_lod(Vec2::ZERO, Vec2::ZERO, size);
    assert!(zero.is_finite() && zero < -60.0, "{zero}");
}

#[test]
fn degenerate_inputs_give_the_finite_centroid() {
    let m = view_projection();
    let clip = |v: [Vec3; 3]| v.map(|p| m * p.extend(1.0));
    let pixel = Vec2::new(640.0, 360.0);
    let line = clip([Vec3::ZERO, Vec3::X, Vec3::X * 2.0]);
    let point = clip([Vec3::Y; 3]);
    let good = clip([Vec3::ZERO, Vec3::X, Vec3::Y]);
    let mut behind = good;
    behind[1].w = -0.5;
    let mut on_eye = good;
    on_eye[2] = Vec4::new(0.1, 0.2, 0.0, 0.0);
    let mut nan = good;
    nan[0].x = f32::NAN;
    // A ground triangle reaching towards the horizon, seen at the top row: above the horizon
    // the plane is behind the eye (1/w ≤ 0 there).
    let ground = clip([Vec3::new(-1.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -90.0)]);
    let cases = [
        (line, pixel, VIEWPORT),
        (point, pixel, VIEWPORT),
        (behind, pixel, VIEWPORT),
        (on_eye, pixel, VIEWPORT),
        (nan, pixel, VIEWPORT),
        (ground, Vec2::new(640.0, 0.5), VIEWPORT),
        (good, pixel, Vec2::ZERO),
        (good, Vec2::splat(f32::INFINITY), VIEWPORT),
    ];
    for (i, (c, p, viewport)) in cases.into_iter().enumerate() {
        let d = barycentric_derivatives(c, p, viewport);
        assert_eq!(d, BarycentricDerivatives::DEGENERATE, "case {i}");
        assert!(d.lambda.is_finite() && d.ddx.is_finite() && d.ddy.is_finite());
    }
    // The good triangle itself is not degenerate.
    assert_ne!(barycentric_derivatives(good, pixel, VIEWPORT), BarycentricDerivatives::DEGENERATE);
    // The ground triangle below the horizon is fine too.
    assert_ne!(
        barycentric_derivatives(ground, Vec2::new(640.0, 700.0), VIEWPORT),
        BarycentricDerivatives::DEGENERATE
    );
}
