//! Tests of `geometry::shadow_class`: on maps ray cast on the CPU, a triangle classed lit or
//! shadowed reads V = 1 or V = 0 at every point the lookup twin (`shadow_lookup`) is asked
//! at, for directional and point lights, hard and filtered; and the class decides most of a
//! finely cut ground, or it would be of no use.

use super::*;
use crate::geometry::shadow_lookup::shadow_visibility;
use crate::geometry::shadow_view::{directional_map, face_basis, point_depth_range, LightShadow, ShadowMap};
use crate::test_rng::Rng;
use glam::Mat4;

/// The ray `origin + t·direction`'s nearest hit among `triangles`, as t.
fn nearest_hit(origin: Vec3, direction: Vec3, triangles: &[[Vec3; 3]]) -> Option<f32> {
    let mut nearest: Option<f32> = None;
    for [a, b, c] in triangles {
        let (e1, e2) = (*b - *a, *c - *a);
        let p = direction.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-12 {
            continue;
        }
        let s = origin - *a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = direction.dot(q) / det;
        let t = e2.dot(q) / det;
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 && nearest.is_none_or(|n| t < n) {
            nearest = Some(t);
        }
    }
    nearest
}

/// A one-map layout of `light`'s map of `size` texels over the box `lo`..`hi`, its depths
/// ray cast through the texels' centres against `occluders` (1 where nothing is hit).
fn rendered(
    light: &Light,
    size: u32,
    radius: u32,
    lo: Vec3,
    hi: Vec3,
    occluders: &[[Vec3; 3]],
) -> (ShadowLayout, Vec<f32>) {
    let (projection, width) = match *light {
        Light::Directional { direction, .. } => {
            let (view_proj, width) = directional_map(direction, lo, hi);
            (Projection::Orthographic(view_proj), width)
        }
        Light::Point { position, .. } => {
            let (near, far) = point_depth_range(position, lo, hi);
            (Projection::Cube { light: position, near, far }, 2.0)
        }
        Light::Polygon(_) => unreachable!(),
    };
    let map = ShadowMap { projection, offset: [0, 0], size, texel_width: width / size as f32 };
    let extent = map.footprint();
    let mut atlas = vec![1.0f32; (extent[0] * extent[1]) as usize];
    let centre = |i: u32| (i as f32 + 0.5) / size as f32 * 2.0 - 1.0;
    match projection {
        Projection::Orthographic(view_proj) => {
            let inverse: Mat4 = view_proj.inverse();
            for y in 0..size {
                for x in 0..size {
                    let front = inverse.project_point3(Vec3::new(centre(x), centre(y), 0.0));
                    let back = inverse.project_point3(Vec3::new(centre(x), centre(y), 1.0));
                    if let Some(t) = nearest_hit(front, back - front, occluders) {
                        atlas[(y * extent[0] + x) as usize] = t;
                    }
                }
            }
        }
        Projection::Cube { light, near, far } => {
            for face in 0..6u32 {
                let [axis, side, up] = face_basis(face as usize);
                for y in 0..size {
                    for x in 0..size {
                        let direction = axis + side * centre(x) - up * centre(y);
                        if let Some(along) = nearest_hit(light, direction, occluders) {
                            let at = (face / 3 * size + y) * extent[0] + face % 3 * size + x;
                            atlas[at as usize] = far * (along - near) / ((far - near) * along);
                        }
                    }
                }
            }
        }
    }
    let shadow = LightShadow { map: 0, radius, slot: 0 };
    (ShadowLayout { maps: vec![map], extent, lights: vec![Some(shadow)], by_slot: vec![0] }, atlas)
}

/// Points spread over the triangle: its corners, points along its edges and inside.
fn points_of(corners: [Vec3; 3], rng: &mut Rng) -> Vec<Vec3> {
    let mut points = corners.to_vec();
    for _ in 0..150 {
        let (mut u, mut v) = (rng.f(), rng.f());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        // Every third on an edge.
        if rng.below(3) == 0 {
            v = 0.0;
        }
        points.push(corners[0] + (corners[1] - corners[0]) * u + (corners[2] - corners[0]) * v);
    }
    points
}

/// The ground: 20 × 20 in two triangles at y = 0; above it a tilted square and a triangle.
fn occluders() -> Vec<[Vec3; 3]> {
    let g = |x: f32, z: f32| Vec3::new(x, 0.0, z);
    let q = |x: f32, z: f32| Vec3::new(x, 3.0 + 0.3 * x, z);
    vec![
        [g(-10.0, -10.0), g(-10.0, 10.0), g(10.0, 10.0)],
        [g(-10.0, -10.0), g(10.0, 10.0), g(10.0, -10.0)],
        [q(-2.0, -2.0), q(-2.0, 2.0), q(2.0, 2.0)],
        [q(-2.0, -2.0), q(2.0, 2.0), q(2.0, -2.0)],
        [Vec3::new(4.0, 1.5, 4.0), Vec3::new(6.0, 1.5, 4.0), Vec3::new(5.0, 2.5, 6.0)],
    ]
}

/// The ground cut into a grid of `cells` × `cells` squares (two triangles each) over `half`
/// units either side of the origin.
fn ground_triangles(cells: u32, half: f32) -> Vec<[Vec3; 3]> {
    let step = 2.0 * half / cells as f32;
    let at = |i: u32, j: u32| Vec3::new(-half + i as f32 * step, 0.0, -half + j as f32 * step);
    (0..cells * cells)
        .flat_map(|k| {
            let (i, j) = (k % cells, k / cells);
            [[at(i, j), at(i, j + 1), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i + 1, j)]]
        })
        .collect()
}

/// A closed, bumpy ball of `2 × around × (around / 2)` triangles at `centre`: a surface that
/// shadows itself (not convex) and that the map holds as its own occluder.
fn bumpy_ball(centre: Vec3, radius: f32, around: u32) -> Vec<[Vec3; 3]> {
    let rings = around / 2;
    let at = |i: u32, j: u32| {
        let (phi, theta) = (
            std::f32::consts::TAU * i as f32 / around as f32,
            std::f32::consts::PI * j as f32 / rings as f32,
        );
        let r = radius * (1.0 + 0.15 * (3.0 * phi).sin() * (4.0 * theta).sin());
        centre + r * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin())
    };
    (0..around * rings)
        .flat_map(|k| {
            let (i, j) = (k % around, k / around);
            [[at(i, j), at(i + 1, j + 1), at(i, j + 1)], [at(i, j), at(i + 1, j), at(i + 1, j + 1)]]
        })
        .filter(|[a, b, c]| (*b - *a).cross(*c - *a).length() > 1e-6)
        .collect()
}

/// Classes `receivers` against `light`'s map of `casters` and checks every decided one against
/// the lookup twin; returns how many were lit, shadowed and mixed.
fn check_sound(
    light: Light,
    size: u32,
    radius: u32,
    casters: &[[Vec3; 3]],
    receivers: &[[Vec3; 3]],
    rng: &mut Rng,
) -> [usize; 3] {
    check_sound_scaled(light, size, radius, casters, receivers, 1.0, rng)
}

/// [`check_sound`] in a scene `scale` times as large (its maps' box too).
fn check_sound_scaled(
    light: Light,
    size: u32,
    radius: u32,
    casters: &[[Vec3; 3]],
    receivers: &[[Vec3; 3]],
    scale: f32,
    rng: &mut Rng,
) -> [usize; 3] {
    let (lo, hi) = (Vec3::new(-10.0, -0.5, -10.0) * scale, Vec3::new(10.0, 6.0, 10.0) * scale);
    let (layout, atlas) = rendered(&light, size, radius, lo, hi, casters);
    let depths = ShadowDepths::new(&layout, &atlas);
    let shadow = layout.lights[0].expect("one map");
    let mut counts = [0; 3];
    for corners in receivers {
        let class = depths.classify(&layout, 0, radius, &light, *corners);
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize();
        let expected = match class {
            Visibility::Lit => 1.0,
            Visibility::Shadowed => 0.0,
            Visibility::Mixed => {
                counts[2] += 1;
                continue;
            }
        };
        counts[usize::from(class == Visibility::Shadowed)] += 1;
        for p in points_of(*corners, rng) {
            let v = shadow_visibility(&layout, &atlas, &light, shadow, p, normal);
            assert_eq!(v, expected, "{light:?} r {radius}: {corners:?} classed {class:?} reads {v} at {p}");
        }
    }
    counts
}

fn directional(direction: Vec3) -> Light {
    Light::Directional { direction: direction.normalize(), color: Vec3::ONE, intensity: 1.0 }
}

fn point(position: Vec3) -> Light {
    Light::Point { position, color: Vec3::ONE, intensity: 1.0 }
}

#[test]
fn lit_and_shadowed_ground_triangles_read_one_and_zero_everywhere() {
    let mut rng = Rng(0x5eed_0c1a);
    let ground = ground_triangles(40, 8.0);
    for (light, radius) in [
        (directional(Vec3::new(-0.3, -1.0, -0.2)), 0),
        (directional(Vec3::new(0.5, -1.0, 0.4)), 1),
        (point(Vec3::new(1.0, 8.0, 2.0)), 0),
        (point(Vec3::new(-3.0, 6.0, 1.0)), 2),
    ] {
        let [lit, shadowed, mixed] = check_sound(light, 256, radius, &occluders(), &ground, &mut rng);
        // A shadow's boundary crosses few of the cells: most are decided.
        assert!(
            lit + shadowed > 3 * mixed,
            "{light:?} r {radius}: {lit} lit, {shadowed} shadowed, {mixed} mixed"
        );
        assert!(shadowed > 20, "{light:?}: the square's shadow holds whole cells ({shadowed})");
    }
}

#[test]
fn the_class_is_sound_for_random_lights_and_triangles() {
    let mut rng = Rng(0x5eed_0c1b);
    let mut decided = 0;
    for _ in 0..100 {
        let light = if rng.below(2) == 0 {
            directional(Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, -0.2), rng.range(-1.0, 1.0)))
        } else {
            point(rng.point(Vec3::new(-8.0, 2.0, -8.0), Vec3::new(8.0, 10.0, 8.0)))
        };
        let radius = rng.below(3);
        let size = [32, 64, 128][rng.below(3) as usize];
        // Small triangles anywhere in the box, at any angle, and pieces of the ground.
        let receivers: Vec<[Vec3; 3]> = (0..120)
            .map(|_| {
                let a = rng.point(Vec3::new(-9.0, 0.0, -9.0), Vec3::new(9.0, 5.0, 9.0));
                let span = rng.range(0.05, 2.0);
                [
                    a,
                    a + rng.point(Vec3::splat(-span), Vec3::splat(span)),
                    a + rng.point(Vec3::splat(-span), Vec3::splat(span)),
                ]
            })
            .chain(ground_triangles(12, 9.0))
            .collect();
        let [lit, shadowed, _] = check_sound(light, size, radius, &occluders(), &receivers, &mut rng);
        decided += lit + shadowed;
    }
    assert!(decided > 100 * 100, "the class decides too little to be of use: {decided}");
}

#[test]
fn a_surface_that_shadows_itself_is_classed_soundly_and_mostly_decided() {
    let mut rng = Rng(0x5eed_0c1d);
    let ball = bumpy_ball(Vec3::new(-5.0, 2.5, -5.0), 1.8, 24);
    let casters: Vec<[Vec3; 3]> = occluders().into_iter().chain(ball.iter().copied()).collect();
    let mut mixed_in_all = 0;
    for (light, radius) in [
        (directional(Vec3::new(-0.3, -1.0, -0.2)), 0),
        (directional(Vec3::new(0.7, -0.5, 0.4)), 1),
        (point(Vec3::new(-1.0, 5.5, -2.0)), 0),
        (point(Vec3::new(-8.0, 4.0, -9.0)), 1),
    ] {
        let [lit, shadowed, mixed] = check_sound(light, 128, radius, &casters, &ball, &mut rng);
        assert!(
            lit > 0 && shadowed > 0,
            "{light:?} r {radius}: {lit} lit, {shadowed} shadowed, {mixed} mixed"
        );
        mixed_in_all += mixed;
    }
    // Its own texels in the map must not leave the ball's lit side mixed: the terminator, the
    // bumps' shadows and the cube faces' edges cross a share of its triangles.
    assert!(10 * mixed_in_all < 3 * 4 * ball.len(), "{mixed_in_all} of 4 × {} triangles mixed", ball.len());
}

/// The extremes the class must survive: a light inside a closed caster, light grazing the
/// ground, a caster touching its receiver, and a scene 10⁴ units wide.
#[test]
fn the_class_is_sound_at_the_extremes() {
    let mut rng = Rng(0x5eed_0c1e);
    let centre = Vec3::new(-5.0, 2.5, -5.0);
    let ball = bumpy_ball(centre, 1.8, 24);
    let ground = ground_triangles(16, 10.0);
    let with_ball = |extra: &[[Vec3; 3]]| -> Vec<[Vec3; 3]> {
        occluders().into_iter().chain(extra.iter().copied()).collect()
    };
    // A point light inside the ball: the ball's inside is lit, the whole ground shadowed.
    let [lit, shadowed, _] = check_sound(point(centre), 128, 1, &with_ball(&ball), &ground, &mut rng);
    assert!(
        lit == 0 && shadowed > ground.len() / 2,
        "light inside: the ground {lit} lit, {shadowed} shadowed"
    );
    // Light grazing the ground at under 2°, hard and filtered.
    for radius in [0, 2] {
        let grazing = directional(Vec3::new(1.0, -0.03, 0.2));
        let [lit, shadowed, mixed] = check_sound(grazing, 128, radius, &with_ball(&ball), &ground, &mut rng);
        assert!(lit + shadowed > 0, "grazing r {radius}: {lit} lit, {shadowed} shadowed, {mixed} mixed");
    }
    // The ball resting on the ground (its lowest bumps dip into it), under either kind of light.
    let resting = bumpy_ball(Vec3::new(-5.0, 1.8, -5.0), 1.8, 24);
    let near_it: Vec<[Vec3; 3]> = ground_triangles(40, 10.0)
        .into_iter()
        .filter(|t| t.iter().any(|c| (*c - Vec3::new(-5.0, 0.0, -5.0)).length() < 3.0))
        .chain(resting.iter().copied())
        .collect();
    for light in [point(Vec3::new(-2.0, 7.0, -3.0)), directional(Vec3::new(0.4, -1.0, 0.3))] {
        let [lit, shadowed, mixed] = check_sound(light, 128, 1, &with_ball(&resting), &near_it, &mut rng);
        assert!(
            lit > 0 && shadowed > 0,
            "touching, {light:?}: {lit} lit, {shadowed} shadowed, {mixed} mixed"
        );
    }
    // The ground, the ball and the occluders 500 times as large: 10⁴ units wide.
    let scale = 500.0;
    let scaled = |triangles: &[[Vec3; 3]]| -> Vec<[Vec3; 3]> {
        triangles.iter().map(|t| t.map(|c| c * scale)).collect()
    };
    let (casters, receivers) = (scaled(&with_ball(&ball)), scaled(&ground));
    for light in [point(Vec3::new(1.0, 8.0, 2.0) * scale), directional(Vec3::new(-0.3, -1.0, -0.2))] {
        let [lit, shadowed, mixed] = check_sound_scaled(light, 128, 1, &casters, &receivers, scale, &mut rng);
        assert!(
            lit + shadowed > 3 * mixed,
            "10⁴ units wide, {light:?}: {lit} lit, {shadowed} shadowed, {mixed} mixed"
        );
    }
}

#[test]
fn the_pyramid_holds_each_blocks_least_and_greatest_depth() {
    let mut rng = Rng(0x5eed_0c1c);
    let (width, size) = (40u32, 37u32);
    let atlas: Vec<f32> = (0..width * width).map(|_| rng.f()).collect();
    let square = DepthSquare::new(&atlas, width, [2, 3], size);
    for level in 0..=square.coarse.len() {
        let block = 1u32 << level;
        let side = size.div_ceil(block);
        for y in 0..side {
            for x in 0..side {
                let texels = (y * block..((y + 1) * block).min(size))
                    .flat_map(|ty| (x * block..((x + 1) * block).min(size)).map(move |tx| (tx, ty)))
                    .map(|(tx, ty)| atlas[((3 + ty) * width + 2 + tx) as usize]);
                let (lo, hi) =
                    texels.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), d| (lo.min(d), hi.max(d)));
                assert_eq!(square.range(level, x, y), [lo, hi], "level {level} cell ({x}, {y})");
            }
        }
    }
}

#[test]
fn degenerate_triangles_are_mixed_and_those_across_cube_faces_decided() {
    let light = point(Vec3::new(0.0, 5.0, 0.0));
    let (lo, hi) = (Vec3::splat(-10.0), Vec3::splat(10.0));
    let (layout, atlas) = rendered(&light, 64, 0, lo, hi, &occluders());
    let depths = ShadowDepths::new(&layout, &atlas);
    let classify = |c: [Vec3; 3]| depths.classify(&layout, 0, 0, &light, c);
    let a = Vec3::new(1.0, 0.0, 1.0);
    assert_eq!(classify([a, a, a]), Visibility::Mixed, "a point");
    assert_eq!(classify([a, 2.0 * a, 3.0 * a]), Visibility::Mixed, "a line");
    assert_eq!(classify([a, Vec3::NAN, a]), Visibility::Mixed, "NaN");
    // The light in the triangle's plane: which side a pixel lifts to may flip.
    assert_eq!(
        classify([Vec3::new(-3.0, 5.0, -3.0), Vec3::new(-4.0, 5.0, -3.0), Vec3::new(-3.0, 5.0, -4.0)]),
        Visibility::Mixed,
        "the light in its plane"
    );
    // Under the light, far from any occluder's shadow: decided, also across two cube faces
    // (the ground below the light and beside it meet at |x| = 5).
    assert_eq!(
        classify([Vec3::new(-4.5, 0.0, -1.0), Vec3::new(-4.7, 0.0, -1.0), Vec3::new(-4.5, 0.0, -1.2)]),
        Visibility::Lit
    );
    assert_eq!(
        classify([Vec3::new(-4.8, 0.0, -1.0), Vec3::new(-5.2, 0.0, -1.0), Vec3::new(-4.8, 0.0, -1.4)]),
        Visibility::Lit,
        "across two faces"
    );
}
