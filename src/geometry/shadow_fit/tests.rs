//! Tests of `geometry::shadow_fit`: every point of the box the camera sees lands in the fitted
//! map, kernel and all; a fit serves the view it was made for; a view of part of the box gets a
//! finer map than the whole box's; a camera looking away sees nothing.

use super::*;
use crate::geometry::camera::view_projection;
use crate::test_rng::Rng;

fn camera(eye: Vec3, target: Vec3) -> Camera {
    Camera { eye, target, up: Vec3::Y, fov_y_degrees: 45.0, near: 0.05, far: 500.0 }
}

/// Whether `p` lies inside `camera`'s frustum on a `width` × `height` target.
fn visible(camera: &Camera, (width, height): (u32, u32), p: Vec3) -> bool {
    let clip = view_projection(camera, width, height) * p.extend(1.0);
    clip.w > 0.0 && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w && clip.z >= 0.0 && clip.z <= clip.w
}

/// A random camera over the box `lo`..`hi`: outside it or inside, close to what it looks at or
/// far from it, looking at a point of the box.
fn random_camera(rng: &mut Rng, lo: Vec3, hi: Vec3) -> Camera {
    let span = (hi - lo) * rng.range(0.05, 1.0);
    let target = rng.point(lo, hi);
    let eye = target + rng.point(-span, span);
    Camera { fov_y_degrees: rng.range(20.0, 90.0), ..camera(eye, target) }
}

/// A random box (flat ones too) and a directional light from above it.
fn random_box_and_light(rng: &mut Rng) -> (Vec3, Vec3, DirectionalFrame) {
    let lo = rng.point(Vec3::splat(-50.0), Vec3::ZERO);
    let hi = lo + rng.point(Vec3::new(1.0, 0.0, 1.0), Vec3::splat(40.0));
    let direction = rng.point(Vec3::splat(-1.0), Vec3::new(1.0, -0.2, 1.0)).normalize();
    (lo, hi, DirectionalFrame::new(direction, lo, hi))
}

#[test]
fn every_point_the_camera_sees_lies_in_the_seen_rectangle() {
    let mut rng = Rng(0x5eed_0f17);
    let mut checked = 0;
    for _ in 0..200 {
        let (lo, hi, frame) = random_box_and_light(&mut rng);
        let camera = random_camera(&mut rng, lo, hi);
        let size = (320, 180);
        let seen = frame.seen(&camera, 320.0 / 180.0, lo, hi);
        for _ in 0..300 {
            let p = rng.point(lo, hi);
            if !visible(&camera, size, p) {
                continue;
            }
            let (min, max) = seen.expect("a visible point, yet nothing seen");
            let q = frame.view.transform_point3(p).truncate();
            let slack = 1e-4 * (hi - lo).length();
            assert!(
                q.cmpge(min - slack).all() && q.cmple(max + slack).all(),
                "{p} seen at {q}, outside {min}..{max}"
            );
            checked += 1;
        }
    }
    assert!(checked > 5000, "only {checked} visible points checked");
}

#[test]
fn a_camera_looking_away_sees_nothing() {
    let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
    let frame = DirectionalFrame::new(Vec3::NEG_Y, lo, hi);
    let away = camera(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, 10.0));
    assert_eq!(frame.seen(&away, 1.0, lo, hi), None);
    let towards = camera(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO);
    assert!(frame.seen(&towards, 1.0, lo, hi).is_some());
}

#[test]
fn a_refitted_map_holds_the_view_with_its_kernel_and_serves_it() {
    let mut rng = Rng(0x5eed_0f18);
    let mut finer = 0;
    for _ in 0..200 {
        let (lo, hi, frame) = random_box_and_light(&mut rng);
        let (size, radius) = (512, rng.below(3));
        let camera = random_camera(&mut rng, lo, hi);
        let seen = frame.seen(&camera, 16.0 / 9.0, lo, hi);
        let whole = DirectionalFit::whole(frame);
        let fit = match whole.refit_for(seen, size, radius) {
            Some(square) => DirectionalFit { frame, square },
            None => whole,
        };
        assert!(fit.square.half <= frame.whole.half * (1.0 + 1e-6));
        assert_eq!(fit.refit_for(seen, size, radius), None, "the fit does not serve its own view");
        finer += usize::from(fit.square.half < 0.5 * frame.whole.half);
        let (view_proj, width) = frame.map(fit.square);
        assert!((width - 2.0 * fit.square.half).abs() <= 1e-6 * width);
        // Every visible point, with the kernel's texels around it where the box's square has
        // them, lands inside the map.
        let pad = 2.0 * (radius + 2) as f32 / size as f32;
        let whole_edge = |q: Vec2| {
            let d = (q - frame.whole.centre).abs() + Vec2::splat(2.0 * fit.square.half * pad);
            d.cmpge(Vec2::splat(frame.whole.half)).any()
        };
        for _ in 0..200 {
            let p = rng.point(lo, hi);
            if !visible(&camera, (160, 90), p) {
                continue;
            }
            let ndc = view_proj.project_point3(p);
            assert!(ndc.z >= -1e-4 && ndc.z <= 1.0 + 1e-4, "{p}: depth {}", ndc.z);
            let reach = if whole_edge(frame.view.transform_point3(p).truncate()) { 1.0 } else { 1.0 - pad };
            assert!(
                ndc.x.abs() <= reach + 1e-4 && ndc.y.abs() <= reach + 1e-4,
                "{p} at {ndc} of a map fitted to {:?}",
                fit.square
            );
        }
    }
    assert!(finer > 20, "only {finer} of 200 views got a map finer than half the box's");
}

#[test]
fn a_map_is_refitted_when_the_view_leaves_it_or_is_much_smaller() {
    // A ground 100 wide under a light from straight above.
    let (lo, hi) = (Vec3::new(-50.0, 0.0, -50.0), Vec3::new(50.0, 1.0, 50.0));
    let frame = DirectionalFrame::new(Vec3::NEG_Y, lo, hi);
    let looking_down = |x: f32| camera(Vec3::new(x, 20.0, 0.01), Vec3::new(x, 0.0, 0.0));
    let seen = |x: f32| frame.seen(&looking_down(x), 1.0, lo, hi);
    let square = DirectionalFit::whole(frame).refit_for(seen(0.0), 1024, 1).expect("a finer map");
    let fit = DirectionalFit { frame, square };
    // The camera sees 2·20·tan 22.5° ≈ 16.6 of the ground across.
    assert!(square.half < 0.25 * frame.whole.half, "{square:?}");
    assert_eq!(fit.refit_for(seen(0.5), 1024, 1), None, "a small step keeps the map");
    assert!(fit.refit_for(seen(10.0), 1024, 1).is_some(), "a step out of the map refits it");
    let closer = frame.seen(&camera(Vec3::new(0.0, 5.0, 0.01), Vec3::ZERO), 1.0, lo, hi);
    assert!(fit.refit_for(closer, 1024, 1).is_some(), "a view four times smaller refits it");
    assert_eq!(fit.refit_for(None, 1024, 1), None, "nothing seen keeps the map");
}
