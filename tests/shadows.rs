//! Shadow maps on lavapipe (validation layer on): every mode renders the shadow scene; the
//! maps shadow what a ray cast towards the light finds occluded (no acne on lit surfaces, no
//! light leaking under the caster); a shadow only ever darkens; multirate keeps every pixel of
//! the same triangle within ε of `pixel` with the same maps, interpolating the shadowed lights;
//! a triangle classed lit or shadowed shows V = 1 or V = 0 at every pixel `pixel` shades.

mod common;

use ash::vk;
use common::{assert_validation_clean, ray_cast, repo_path, validated_context, SplitMix64};
use glam::Vec3;
use multirate::analysis::metrics;
use multirate::geometry::camera::pixel_ray;
use multirate::geometry::shadow_class::{ShadowClasses, Visibility};
use multirate::geometry::shadow_view::ShadowLayout;
use multirate::render::{Mode, Placement, Renderer, View};
use multirate::scene::{Camera, Light, Scene, ShadowCaster};
use multirate::shading::estimator::EstimatorSettings;
use multirate::vk::target::{FloatImage, RenderTarget};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;
/// The ground's index in scenes/shadows.toml.
const GROUND: usize = 1;

fn shadow_scene() -> Scene {
    Scene::load(&repo_path("scenes/shadows.toml")).expect("scenes/shadows.toml loads")
}

/// `scene` lit by its light `index` alone, with that light's shadow where `shadowed`.
fn one_light(scene: &Scene, index: usize, shadowed: bool) -> Scene {
    let caster = scene.shadow_casters.iter().find(|c| c.light == index).expect("the light casts shadows");
    Scene {
        lights: vec![scene.lights[index]],
        shadow_casters: if shadowed { vec![ShadowCaster { light: 0, ..*caster }] } else { Vec::new() },
        ..scene.clone()
    }
}

/// `scene`'s view in multirate mode with the estimator in `placement`, at `epsilon`.
fn multirate_view(scene: &Scene, placement: Placement, epsilon: f32) -> View {
    let base = View::of_scene(scene);
    let estimator = EstimatorSettings { epsilon, ..base.estimator };
    View { mode: Mode::Multirate, placement, estimator, ..base }
}

fn render(scene: &Scene, views: &[View]) -> Vec<FloatImage> {
    let context = validated_context();
    let renderer = Renderer::new(&context, scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    let images = views.iter().map(|view| renderer.render(&target, view).expect("render")).collect();
    assert_validation_clean(&context);
    images
}

#[test]
fn every_mode_renders_the_shadow_scene() {
    let scene = shadow_scene();
    assert_eq!(scene.shadow_casters.len(), 2);
    let base = View::of_scene(&scene);
    let modes = [Mode::Pixel, Mode::PixelDeferred, Mode::Vertex, Mode::Fixed(2), Mode::Multirate];
    let views: Vec<View> = modes.iter().map(|&mode| View { mode, ..base.clone() }).collect();
    let images = render(&scene, &views);
    let pixel = &images[0];
    let covered = pixel.pixels.iter().filter(|p| p[3] == 1.0).count();
    assert!(covered > (WIDTH * HEIGHT / 3) as usize, "{covered} pixels covered");
    for (view, image) in views.iter().zip(&images) {
        assert!(image.pixels.iter().flatten().all(|v| v.is_finite()), "{:?}: not finite", view.mode);
        assert!(image.pixels.iter().any(|p| p[0] + p[1] + p[2] > 0.05), "{:?}: black", view.mode);
    }
    // pixel-deferred looks its shadows up at the same points as pixel (shadow_point) and
    // rebuilds the rest of the shading from the triangle.
    let apart = pixel
        .pixels
        .iter()
        .zip(&images[1].pixels)
        .filter(|(p, q)| (0..3).any(|c| (p[c] - q[c]).abs() > 0.02))
        .count();
    assert!(apart * 200 < covered, "pixel-deferred differs from pixel at {apart} of {covered} pixels");
}

/// `scene`'s lights in another order, the directional one first, and an unshadowed point light
/// between: the shaders number the lights that cast shadows first in their kind (their slots),
/// so this order differs from the scene's, and from the shipped one's.
fn lights_reordered(scene: &Scene, filter: u32) -> Scene {
    let [point, directional] = [0, 1].map(|i| scene.lights[i]);
    let unshadowed = Light::Point {
        position: Vec3::new(-6.0, 8.0, -4.0),
        color: Vec3::new(0.9, 0.9, 1.0),
        intensity: 40.0,
    };
    let caster = |light, of: usize| ShadowCaster { light, filter, ..scene.shadow_casters[of] };
    Scene {
        lights: vec![directional, unshadowed, point],
        shadow_casters: vec![caster(0, 1), caster(2, 0)],
        ..scene.clone()
    }
}

/// Multirate, both placements, with hard and filtered shadows: every pixel of the same triangle
/// within ε of `pixel` with the same maps, and the shadowed lights interpolated on sub-vertices
/// (not shaded per pixel). The filtered case has its lights reordered (`lights_reordered`).
#[test]
fn multirate_keeps_the_bound_with_shadows_applied_per_pixel() {
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    let loaded = shadow_scene();
    assert!(matches!(loaded.lights[..], [Light::Point { .. }, Light::Directional { .. }]));
    for filter in [1, 5] {
        let scene = if filter == 1 {
            let casters = loaded.shadow_casters.iter().map(|c| ShadowCaster { filter, ..*c }).collect();
            Scene { shadow_casters: casters, ..loaded.clone() }
        } else {
            lights_reordered(&loaded, filter)
        };
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        let reference = renderer.analyze(&target, &View::of_scene(&scene)).expect("pixel");
        for placement in [Placement::Compute, Placement::Tcs] {
            let what = format!("filter {filter}, {placement:?}");
            let view = View { mode: Mode::Multirate, placement, ..View::of_scene(&scene) };
            let analysis = renderer.analyze(&target, &view).expect("multirate");
            let epsilon = f64::from(view.estimator.epsilon);
            let over = metrics::pixels_over(reference.frame(), analysis.frame(), epsilon);
            let error = metrics::image_error(reference.frame(), analysis.frame(), scene.settings.exposure);
            eprintln!(
                "{what}: L∞ {:.4} on pixels of the same triangle, {over} over ε",
                error.l_inf_same_triangle
            );
            assert_eq!(over, 0, "{what}: {over} pixels of the same triangle over ε ({error:?})");
            let counts = analysis.evaluations;
            assert!(
                counts.sub_vertices > 0 && counts.fragments * 2 < reference.evaluations.fragments,
                "{what}: {counts:?} against pixel's {:?}",
                reference.evaluations
            );
        }
    }
    assert_validation_clean(&context);
}

/// Per light of the shadow scene, lit alone: at every pixel of the ground whose unshadowed
/// shading is not black, the shadowed image's share of it (the visibility; the ground is
/// Lambertian) against a ray cast from the ground point towards the light.
#[test]
fn shadows_fall_where_a_ray_towards_the_light_is_blocked() {
    let scene = shadow_scene();
    for index in 0..scene.lights.len() {
        let view = View::of_scene(&scene);
        let unshadowed = &render(&one_light(&scene, index, false), std::slice::from_ref(&view))[0];
        let shadowed = &render(&one_light(&scene, index, true), std::slice::from_ref(&view))[0];
        for (p, q) in unshadowed.pixels.iter().zip(&shadowed.pixels) {
            assert!((0..3).all(|c| q[c] <= p[c] * (1.0 + 1e-6) + 1e-7), "a shadow brightened {p:?} to {q:?}");
        }
        let (mut ground, mut blocked, mut mismatched) = (0, 0, 0);
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                let lit = unshadowed.pixel(x, y)[1];
                if lit < 1e-4 {
                    continue;
                }
                let (origin, direction) =
                    pixel_ray(&scene.camera, WIDTH, HEIGHT, x as f32 + 0.5, y as f32 + 0.5);
                let Some(hit) = ray_cast(&scene, origin, direction) else { continue };
                if hit.mesh != GROUND {
                    continue;
                }
                let point = origin + direction * hit.distance as f32 + Vec3::Y * 1e-3;
                let (towards, reach) = match scene.lights[index] {
                    Light::Point { position, .. } => {
                        ((position - point).normalize(), (position - point).length())
                    }
                    Light::Directional { direction, .. } => (-direction, f32::INFINITY),
                    Light::Polygon(_) => unreachable!(),
                };
                let occluded = ray_cast(&scene, point, towards).is_some_and(|h| (h.distance as f32) < reach);
                let visibility = shadowed.pixel(x, y)[1] / lit;
                ground += 1;
                blocked += usize::from(occluded);
                mismatched += usize::from((visibility > 0.5) == occluded);
            }
        }
        eprintln!("light {index}: {ground} ground pixels, {blocked} in shadow, {mismatched} disagree");
        assert!(
            blocked * 20 > ground && blocked * 2 < ground,
            "light {index}: {blocked} of {ground} in shadow"
        );
        assert!(mismatched * 100 <= ground, "light {index}: {mismatched} of {ground} ground pixels disagree");
    }
}

/// Each light of the shadow scene alone, hard shadows, ε 0.02 (the ground tessellated where the
/// point light's shading varies): on the ground, where the shading is at least 0.08 (4 ε)
/// and multirate's interpolation error under ε, a pixel that differs from `pixel` by half its
/// value reads another visibility. None may: both look it up at the same point with the same
/// filter and bias. (A flip from rounding alone is rare at this size: with the lookup moved to
/// the interpolated position this found none either; the shadow point rules it out.)
#[test]
fn multirate_and_pixel_read_the_same_visibility() {
    let loaded = shadow_scene();
    let ground_first = loaded.meshes[0].indices.len() as u32 / 3;
    let context = validated_context();
    let extent = vk::Extent2D { width: 4 * WIDTH, height: 4 * HEIGHT };
    let target = RenderTarget::new(&context, extent).expect("target");
    for light in 0..loaded.lights.len() {
        let lit = one_light(&loaded, light, true);
        let scene =
            Scene { shadow_casters: vec![ShadowCaster { filter: 1, ..lit.shadow_casters[0] }], ..lit };
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        let reference = renderer.analyze(&target, &View::of_scene(&scene)).expect("pixel");
        for placement in [Placement::Compute, Placement::Tcs] {
            let view = multirate_view(&scene, placement, 0.02);
            let analysis = renderer.analyze(&target, &view).expect("multirate");
            let (mut ground, mut differing) = (0, 0);
            for (i, (&id, p)) in reference.triangles.iter().zip(&reference.image.pixels).enumerate() {
                let q = analysis.image.pixels[i];
                if id <= ground_first || analysis.triangles[i] != id || p[1].max(q[1]) < 0.08 {
                    continue;
                }
                ground += 1;
                differing += usize::from((p[1] - q[1]).abs() > 0.5 * p[1].max(q[1]));
            }
            eprintln!(
                "light {light} {placement:?}: {ground} lit ground pixels, {differing} differ, {:?}",
                analysis.evaluations
            );
            assert!(ground > 1000, "light {light} {placement:?}: {ground} ground pixels");
            assert_eq!(
                differing, 0,
                "light {light} {placement:?}: {differing} ground pixels read another visibility"
            );
        }
    }
    assert_validation_clean(&context);
}

/// Pixels of triangles `scene`'s only light (which casts shadows) is classed lit for or
/// shadowed for, and of those, how many `pixel` mode shows with another visibility: a lit
/// pixel not as bright as without the shadow, a shadowed one not black.
fn class_against_pixel(context: &std::sync::Arc<multirate::vk::Context>, scene: &Scene) -> [usize; 3] {
    let target =
        RenderTarget::new(context, vk::Extent2D { width: 2 * WIDTH, height: 2 * HEIGHT }).expect("target");
    let shadowed = Renderer::new(context, scene).expect("renderer");
    let with = shadowed.analyze(&target, &View::of_scene(scene)).expect("pixel");
    // The classes of the maps that frame was drawn with (a directional map follows the view).
    let classes = shadowed.shadow_classes();
    drop(shadowed);
    let unshadowed = Scene { shadow_casters: Vec::new(), ..scene.clone() };
    let without =
        Renderer::new(context, &unshadowed).expect("renderer").analyze(&target, &View::of_scene(&unshadowed));
    let without = without.expect("pixel");
    let [mut lit, mut dark, mut wrong] = [0; 3];
    for (i, (&id, p)) in with.triangles.iter().zip(&with.image.pixels).enumerate() {
        if id == 0 || without.triangles[i] != id {
            continue;
        }
        let q = without.image.pixels[i];
        let brightest = q[..3].iter().fold(0.0f32, |m, c| m.max(c.abs()));
        match classes.visibility(id as usize - 1, 0) {
            Visibility::Lit => {
                lit += 1;
                wrong += usize::from((0..3).any(|c| (p[c] - q[c]).abs() > 1e-5 * (1.0 + brightest)));
            }
            Visibility::Shadowed => {
                dark += 1;
                wrong += usize::from(p[..3].iter().any(|c| c.abs() > 1e-6));
            }
            Visibility::Mixed => {}
        }
    }
    [lit, dark, wrong]
}

#[test]
fn triangles_classed_lit_or_shadowed_show_that_visibility_at_every_pixel() {
    let loaded = shadow_scene();
    let context = validated_context();
    let mut rng = SplitMix64(0x5eed_0c1d);
    let mut scenes: Vec<(String, Scene)> = (0..loaded.lights.len())
        .map(|light| (format!("light {light}"), one_light(&loaded, light, true)))
        .collect();
    // A random point light above the ground, hard, and a random directional one, filtered.
    let caster = |light, filter| ShadowCaster { light, resolution: 512, filter };
    let point = Light::Point {
        position: Vec3::new(rng.range(-10.0, 10.0), rng.range(6.0, 14.0), rng.range(-10.0, 10.0)),
        color: Vec3::ONE,
        intensity: 200.0,
    };
    let direction = Vec3::new(rng.range(-1.0, 1.0), -1.0, rng.range(-1.0, 1.0)).normalize();
    let directional = Light::Directional { direction, color: Vec3::ONE, intensity: 1.0 };
    for (name, light, filter) in [("random point", point, 1), ("random directional", directional, 3)] {
        let scene = Scene { lights: vec![light], shadow_casters: vec![caster(0, filter)], ..loaded.clone() };
        scenes.push((format!("{name} {light:?}"), scene));
    }
    for (name, scene) in &scenes {
        let [lit, dark, wrong] = class_against_pixel(&context, scene);
        eprintln!(
            "{name}: {lit} pixels of lit triangles, {dark} of shadowed ones, {wrong} show another visibility"
        );
        assert_eq!(wrong, 0, "{name}: {wrong} pixels of decided triangles show another visibility");
        assert!(lit > 2000, "{name}: the class decides few lit pixels ({lit})");
        assert!(dark > 100, "{name}: the class decides few shadowed pixels ({dark})");
    }
    assert_validation_clean(&context);
}

/// A directional light's map follows the view: a close view of the bunny's shadow draws the map
/// again for what it sees (its texels finer), whose classes are sound and which multirate reads
/// within ε of `pixel` in both placements without drawing it again; back at the scene's own
/// camera, which sees the whole ground, it is drawn again for the whole box. (The camera of
/// docs/notebook/scenes/shadows_close.toml.)
#[test]
fn a_directional_map_follows_the_view() {
    let loaded = shadow_scene();
    let mut scene = one_light(&loaded, 1, true);
    assert!(matches!(scene.lights[0], Light::Directional { .. }));
    scene.camera =
        Camera { eye: Vec3::new(-10.0, 12.0, 5.0), target: Vec3::new(-6.0, 0.0, -1.0), ..scene.camera };
    let context = validated_context();
    let target =
        RenderTarget::new(&context, vk::Extent2D { width: 2 * WIDTH, height: 2 * HEIGHT }).expect("target");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let (whole, whole_layout) = (renderer.shadow_classes(), renderer.shadow_layout());
    assert_eq!(renderer.shadow_refits().count, 0, "no view yet");
    let reference = renderer.analyze(&target, &View::of_scene(&scene)).expect("pixel");
    assert_eq!(renderer.shadow_refits().count, 1, "the close view draws the map again");
    let fitted = renderer.shadow_classes();
    let shown: std::collections::BTreeSet<usize> =
        reference.triangles.iter().filter(|&&id| id > 0).map(|&id| id as usize - 1).collect();
    let mixed = |classes: &ShadowClasses| {
        shown.iter().filter(|&&t| classes.visibility(t, 0) == Visibility::Mixed).count()
    };
    let texel = |layout: &ShadowLayout| layout.maps[0].texel_width;
    let (whole_texel, fitted_texel) = (texel(&whole_layout), texel(&renderer.shadow_layout()));
    eprintln!(
        "close view: texels {whole_texel:.4} → {fitted_texel:.4} wide; of {} triangles shown, {} → {} mixed",
        shown.len(),
        mixed(&whole),
        mixed(&fitted)
    );
    assert!(
        fitted_texel < 0.7 * whole_texel,
        "the close view's map is not finer: {fitted_texel} against {whole_texel}"
    );
    for placement in [Placement::Compute, Placement::Tcs] {
        let analysis =
            renderer.analyze(&target, &multirate_view(&scene, placement, 0.075)).expect("multirate");
        let over = metrics::pixels_over(reference.frame(), analysis.frame(), 0.075);
        assert_eq!(over, 0, "{placement:?}: {over} pixels of the same triangle over ε");
    }
    assert_eq!(renderer.shadow_refits().count, 1, "the same view serves the map it was drawn for");
    let [lit, dark, wrong] = class_against_pixel(&context, &scene);
    eprintln!("close view: {lit} pixels of lit triangles, {dark} of shadowed ones, {wrong} wrong");
    assert_eq!(wrong, 0, "{wrong} pixels of decided triangles show another visibility");
    assert!(lit > 2000 && dark > 100, "the class decides few pixels ({lit} lit, {dark} shadowed)");
    let far = View { camera: loaded.camera, ..View::of_scene(&scene) };
    renderer.render(&target, &far).expect("render");
    assert_eq!(renderer.shadow_refits().count, 2, "the scene's camera draws the map again");
    assert_eq!(renderer.shadow_classes(), whole, "for the whole box, as when the renderer was made");
    assert_eq!(renderer.shadow_layout(), whole_layout);
    assert_validation_clean(&context);
}

/// The room with shadows (scenes/room_shadows.toml: a hard and a filtered point light, and an
/// unshadowed polygonal panel) at its done-when ε: multirate within ε of `pixel` with the same
/// maps in both placements, and every triangle that each light's class decides showing that
/// visibility wherever `pixel` shades it.
#[test]
fn the_room_with_shadows_keeps_the_bound_and_its_classes_are_sound() {
    let scene = Scene::load(&repo_path("scenes/room_shadows.toml")).expect("scenes/room_shadows.toml loads");
    let filters: Vec<u32> = scene.shadow_casters.iter().map(|c| c.filter).collect();
    assert_eq!(filters, [1, 3], "a hard and a filtered shadow");
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let reference = renderer.analyze(&target, &View::of_scene(&scene)).expect("pixel");
    for placement in [Placement::Compute, Placement::Tcs] {
        let view = multirate_view(&scene, placement, 0.075);
        let analysis = renderer.analyze(&target, &view).expect("multirate");
        let over = metrics::pixels_over(reference.frame(), analysis.frame(), 0.075);
        let error = metrics::image_error(reference.frame(), analysis.frame(), scene.settings.exposure);
        eprintln!("room, {placement:?}: L∞ {:.4} on pixels of the same triangle", error.l_inf_same_triangle);
        assert_eq!(over, 0, "room, {placement:?}: {over} pixels of the same triangle over ε ({error:?})");
    }
    drop(renderer);
    for caster in &scene.shadow_casters {
        let [lit, dark, wrong] = class_against_pixel(&context, &one_light(&scene, caster.light, true));
        eprintln!("room, light {}: {lit} pixels lit, {dark} shadowed, {wrong} wrong", caster.light);
        assert_eq!(
            wrong, 0,
            "room, light {}: {wrong} pixels of decided triangles show another",
            caster.light
        );
        assert!(lit > 1000 && dark > 100, "room, light {}: the class decides little", caster.light);
    }
    assert_validation_clean(&context);
}
