//! Degenerate meshes, generated at random from a fixed seed, on lavapipe with the validation
//! layer on: needles (widths 0 to 10⁻² over lengths 0.2 to 1.5), zero-area triangles with
//! coincident or collinear corners, random, opposite and zero-length vertex normals, at unit,
//! huge (10⁶) and tiny (10⁻⁶) scales, in Lambert, Blinn-Phong and GGX. In every mode and with
//! the estimator in either place:
//! - every value of the image is finite;
//! - no holes: no pixel inside `pixel` mode's coverage is left uncovered, and no covered pixel
//!   is lost with its whole neighbourhood (a culled patch; on needles narrower than a pixel a
//!   moved edge may uncover single pixels), but for the pixels of triangles whose image is a
//!   segment to float precision, which `multirate` culls (`geometry::cull::degenerate_image`);
//! - `multirate`: every pixel that shows the same triangle as in `pixel` mode is within ε of it.

mod common;

use ash::vk;
use common::{assert_validation_clean, cracks, validated_context, SplitMix64};
use multirate::analysis::metrics;
use multirate::geometry::camera::view_projection;
use multirate::geometry::cull;
use multirate::render::{Analysis, Mode, Placement, Renderer, View};
use multirate::scene::Scene;
use multirate::shading::estimator::EstimatorSettings;
use multirate::vk::target::{FloatImage, RenderTarget};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

impl SplitMix64 {
    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len())]
    }

    /// A random unit vector.
    fn direction(&mut self) -> [f64; 3] {
        loop {
            let v = [self.uniform(-1.0, 1.0), self.uniform(-1.0, 1.0), self.uniform(-1.0, 1.0)];
            let length = dot(v, v).sqrt();
            if (0.1..=1.0).contains(&length) {
                return v.map(|c| c / length);
            }
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn along(p: [f64; 3], d: [f64; 3], t: f64) -> [f64; 3] {
    [p[0] + d[0] * t, p[1] + d[1] * t, p[2] + d[2] * t]
}

/// The corners of one degenerate triangle: a needle of `width` across its `length`, or one with
/// two coincident corners, or three collinear ones.
fn degenerate_triangle(rng: &mut SplitMix64) -> [[f64; 3]; 3] {
    let base = [rng.uniform(-1.0, 1.0), rng.uniform(-0.6, 0.6), rng.uniform(-1.0, 1.0)];
    let axis = rng.direction();
    let length = rng.uniform(0.2, 1.5);
    let end = along(base, axis, length);
    let across = cross(axis, rng.direction());
    let across = across.map(|c| c / dot(across, across).sqrt().max(1e-12));
    match rng.next_u64() % 6 {
        0 => [base, end, base],
        1 => [base, base, end],
        2 => [base, end, along(base, axis, length * rng.uniform(-0.5, 1.5))],
        _ => {
            let width = rng.pick(&[0.0, 1e-7, 1e-4, 1e-2, 0.2]);
            [base, end, along(along(base, axis, length * rng.uniform(0.0, 1.0)), across, width)]
        }
    }
}

/// An OBJ of `count` degenerate triangles, each with its own vertices and normals that are
/// random, opposite at two corners, or zero (which the loader replaces by smooth normals).
fn degenerate_obj(rng: &mut SplitMix64, count: usize) -> String {
    let mut obj = String::from("# degenerate triangles (tests/degenerate.rs)\n");
    let mut normals = String::new();
    let mut faces = String::new();
    for triangle in 0..count {
        let corners = degenerate_triangle(rng);
        let n = rng.direction();
        let corner_normals = match rng.next_u64() % 4 {
            0 => [n, n.map(|c| -c), rng.direction()],
            1 => [[0.0; 3], n, [0.0; 3]],
            _ => [rng.direction(), rng.direction(), rng.direction()],
        };
        for (p, n) in corners.iter().zip(corner_normals) {
            writeln!(obj, "v {:.9e} {:.9e} {:.9e}", p[0], p[1], p[2]).expect("string");
            writeln!(normals, "vn {:.9e} {:.9e} {:.9e}", n[0], n[1], n[2]).expect("string");
        }
        let first = 3 * triangle + 1;
        writeln!(faces, "f {0}//{0} {1}//{1} {2}//{2}", first, first + 1, first + 2).expect("string");
    }
    obj + &normals + &faces
}

const MATERIALS: [&str; 3] = [
    "type = \"lambert\"\nkd = [0.7, 0.6, 0.5]",
    "type = \"blinn_phong\"\nkd = [0.4, 0.4, 0.4]\nks = [0.6, 0.6, 0.6]\nshininess = 80.0",
    "type = \"ggx\"\nalbedo = [0.2, 0.2, 0.2]\nf0 = [0.8, 0.8, 0.8]\nroughness = 0.15",
];

/// A two-sided scene of `obj` in `material`, scaled by `scale` (camera and lights along), with a
/// point light and a directional one, written beside the OBJ.
fn degenerate_scene(dir: &Path, name: &str, obj: &str, material: &str, scale: f64) -> PathBuf {
    let obj_path = dir.join(format!("{name}.obj"));
    std::fs::write(&obj_path, obj).expect("write the OBJ");
    let s = |v: [f64; 3]| format!("[{:e}, {:e}, {:e}]", v[0] * scale, v[1] * scale, v[2] * scale);
    let toml = format!(
        "description = \"degenerate triangles {name}\"\n\
         [camera]\neye = {eye}\ntarget = [0.0, 0.0, 0.0]\nfov_y_degrees = 55.0\n\
         [render]\nepsilon = 0.075\nn_max = 8\n\
         [[materials]]\nname = \"m\"\n{material}\n\
         [[meshes]]\nobj = \"{name}.obj\"\nmaterial = \"m\"\nscale = {scale:e}\ntwo_sided = true\n\
         [[lights]]\ntype = \"point\"\nposition = {light}\ncolor = [1.0, 1.0, 1.0]\nintensity = {intensity:e}\n\
         [[lights]]\ntype = \"directional\"\ndirection = [0.3, -1.0, -0.4]\ncolor = [1.0, 0.9, 0.8]\nintensity = 0.6\n",
        eye = s([0.3, 0.8, 3.2]),
        light = s([1.0, 2.0, 2.0]),
        intensity = 6.0 * scale * scale,
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, toml).expect("write the scene");
    path
}

fn assert_finite(image: &FloatImage, what: &str) {
    let bad = image.pixels.iter().flatten().filter(|v| !v.is_finite()).count();
    assert_eq!(bad, 0, "{what}: {bad} non-finite values");
}

/// Per scene triangle (a triangle id less one): whether its image is a segment to float
/// precision, which `multirate` culls (`cull::degenerate_image`) and `pixel` mode may show as
/// single pixels.
fn degenerate_images(scene: &Scene, view: &View, target: &RenderTarget) -> Vec<bool> {
    let extent = target.extent();
    let view_proj = view_projection(&view.camera, extent.width, extent.height);
    let mut degenerate = Vec::new();
    for mesh in &scene.meshes {
        for corners in mesh.indices.chunks_exact(3) {
            let clip: Vec<_> =
                corners.iter().map(|&i| cull::clip_of(&view_proj, mesh.positions[i as usize])).collect();
            degenerate.push(cull::degenerate_image(clip[0], clip[1], clip[2]));
        }
    }
    degenerate
}

/// Pixels that `reference` covers and `image` leaves uncovered with its whole 3×3
/// neighbourhood: a lost piece of surface (a culled patch), not an edge moved by rounding, which
/// on a needle less than a pixel wide can uncover a pixel of the reference's. Pixels of
/// triangles whose image is a segment (`skip`, by triangle id) are left out.
fn lost_pixels(reference: &Analysis, image: &FloatImage, skip: &[bool]) -> usize {
    let ids = &reference.triangles;
    let reference = &reference.image;
    let (width, height) = (reference.width as i64, reference.height as i64);
    let covered = |x: i64, y: i64| {
        (0..width).contains(&x) && (0..height).contains(&y) && image.pixel(x as u32, y as u32)[3] == 1.0
    };
    let mut lost = 0;
    for y in 0..height {
        for x in 0..width {
            let near = (-1..=1).any(|dy| (-1..=1).any(|dx| covered(x + dx, y + dy)));
            let id = ids[(y * width + x) as usize] as usize;
            let skipped = id > 0 && skip.get(id - 1).copied().unwrap_or(false);
            if reference.pixel(x as u32, y as u32)[3] == 1.0 && !near && !skipped {
                lost += 1;
            }
        }
    }
    lost
}

/// Degenerate case `case` (0, 1, 2: Lambert at unit scale, Blinn-Phong at 10⁶, GGX at 10⁻⁶),
/// in every mode and placement. The cases draw their meshes from one seeded sequence, in turn.
fn degenerate_meshes_render_finite_without_holes(case: usize) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("degenerate");
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 128, height: 96 }).expect("target");
    let mut rng = SplitMix64(0x6465_6765_6e65_7261);
    for _ in 0..case {
        degenerate_obj(&mut rng, 240);
    }
    let scales = [1.0, 1.0e6, 1.0e-6];
    let mut checked = 0;
    let start = std::time::Instant::now();
    let (material, scale) = (MATERIALS[case], scales[case]);
    let name = format!("case_{case}");
    let obj = degenerate_obj(&mut rng, 240);
    let path = degenerate_scene(&dir, &name, &obj, material, scale);
    let what = format!("{} (scale {scale:e})", path.display());
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{what}: {e}"));
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let pixel = View::of_scene(&scene);
    let reference = renderer.analyze(&target, &pixel).expect("analyze pixel");
    assert_finite(&reference.image, &format!("{what} pixel"));
    let covered = reference.image.pixels.iter().filter(|p| p[3] == 1.0).count();
    let degenerate = degenerate_images(&scene, &pixel, &target);
    assert!(covered > 50, "{what}: the reference shows the needles ({covered} pixels)");
    let mut views = vec![
        View { mode: Mode::PixelDeferred, ..pixel.clone() },
        View { mode: Mode::Vertex, ..pixel.clone() },
        View { mode: Mode::Fixed(3), ..pixel.clone() },
    ];
    for placement in [Placement::Compute, Placement::Tcs] {
        for (epsilon, n_max) in [(0.075, 8), (1.0e-3, 16), (1.0e3, 1)] {
            let estimator = EstimatorSettings { epsilon, n_max, ..pixel.estimator };
            views.push(View { mode: Mode::Multirate, placement, estimator, ..pixel.clone() });
        }
    }
    for view in views {
        let label = format!(
            "{what} {:?} {:?} ε {} n_max {}",
            view.mode, view.placement, view.estimator.epsilon, view.estimator.n_max
        );
        let image = renderer.render(&target, &view).unwrap_or_else(|e| panic!("{label}: {e}"));
        assert_finite(&image, &label);
        assert_eq!(cracks(&reference.image, &image), 0, "{label}: holes inside the reference's coverage");
        let lost = lost_pixels(&reference, &image, &degenerate);
        assert_eq!(lost, 0, "{label}: {lost} of {covered} covered pixels lost with their neighbourhood");
        if view.mode == Mode::Multirate {
            let analysis = renderer.analyze(&target, &view).unwrap_or_else(|e| panic!("{label}: {e}"));
            assert_finite(&analysis.image, &label);
            let over =
                metrics::pixels_over(reference.frame(), analysis.frame(), f64::from(view.estimator.epsilon));
            assert_eq!(over, 0, "{label}: {over} pixels of the same triangle over ε");
        }
        checked += 1;
    }
    eprintln!(
        "{checked} renders of degenerate case {case} checked in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    assert_validation_clean(&context);
}

// One test per case, so that the cases run side by side.
#[test]
fn degenerate_lambert_meshes_render_finite_without_holes_in_every_mode_and_placement() {
    degenerate_meshes_render_finite_without_holes(0);
}

#[test]
fn huge_degenerate_blinn_phong_meshes_render_finite_without_holes_in_every_mode_and_placement() {
    degenerate_meshes_render_finite_without_holes(1);
}

#[test]
fn tiny_degenerate_ggx_meshes_render_finite_without_holes_in_every_mode_and_placement() {
    degenerate_meshes_render_finite_without_holes(2);
}
