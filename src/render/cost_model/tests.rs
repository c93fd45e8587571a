//! Tests of `render::cost_model`: the break-even area and the calibration store.

use super::*;
use glam::{Vec2, Vec3};

#[test]
fn the_break_even_area_weighs_an_estimate_against_its_pixels() {
    let model = CostModel {
        calibration: Calibration {
            estimate: LinearCost { fixed_ns: 1000.0, per_light_ns: 500.0 },
            pixel: LinearCost { fixed_ns: 50.0, per_light_ns: 25.0 },
            fallback: LinearCost { fixed_ns: 100.0, per_light_ns: 50.0 },
            fallback_triangle: None,
            tessellated_patch: Some(LinearCost { fixed_ns: 400.0, per_light_ns: 0.0 }),
            sub_vertex: Some(LinearCost { fixed_ns: 200.0, per_light_ns: 50.0 }),
            measured_with: String::new(),
        },
        source: String::new(),
    };
    // The estimate and three corners shaded, 1500 + 3 · 75 ns, against 150 ns a pixel.
    assert_eq!(model.min_estimated_area(1), 11.5);
    assert_eq!(model.min_estimated_area(2), (2000.0 + 300.0) / 200.0);
    // Level 4 adds 12 sub-vertices to the corners: 400 + 12 · 250 ns against 150 ns a pixel.
    assert_eq!(model.tessellation_break_even(4, 1), Some(3400.0 / 150.0));
    assert_eq!(model.tessellation_break_even(1, 1), Some(400.0 / 150.0));
    let mut unmeasured = model.clone();
    unmeasured.calibration.sub_vertex = None;
    assert_eq!(unmeasured.tessellation_break_even(4, 1), None);
    // The per-pixel path's cost per triangle, 600 + 100 · L ns, is spent either way on what an
    // estimate would save: (1500 + 225 − 700) / 150 pixels with one light.
    let mut per_triangle = model.clone();
    per_triangle.calibration.fallback_triangle = Some(LinearCost { fixed_ns: 600.0, per_light_ns: 100.0 });
    assert_eq!(per_triangle.min_estimated_area(1), (1725.0 - 700.0) / 150.0);
    assert_eq!(per_triangle.tessellation_break_even(4, 1), Some((3400.0 - 700.0) / 150.0));
    // Where it alone exceeds an estimate, every image is estimated.
    per_triangle.calibration.fallback_triangle = Some(LinearCost { fixed_ns: 3000.0, per_light_ns: 0.0 });
    assert_eq!(per_triangle.min_estimated_area(1), 0.0);
    assert_eq!(per_triangle.tessellation_break_even(4, 1), Some((3400.0 - 3000.0) / 150.0));
    assert_eq!(per_triangle.tessellation_break_even(1, 1), Some(0.0));
    let line = LinearCost::through((1, 1500.0), (8, 5000.0));
    assert_eq!((line.fixed_ns, line.per_light_ns), (1000.0, 500.0));
    let free = LinearCost { fixed_ns: -5.0, per_light_ns: 0.0 };
    assert!(free.at(3) > 0.0, "a measured cost below zero stays a finite ratio");
}

#[test]
fn calibrations_are_stored_per_device_and_read_back() {
    let folder = std::env::temp_dir().join(format!("multirate-cost-model-{}", std::process::id()));
    let path = folder.join("nested").join("cost_model.toml");
    let mut calibration = CostModel::lavapipe().calibration;
    CostModel::store(&path, "device A", &calibration).unwrap();
    calibration.estimate.fixed_ns = 42.0;
    calibration.tessellated_patch = Some(LinearCost { fixed_ns: 300.0, per_light_ns: 20.0 });
    calibration.sub_vertex = Some(LinearCost { fixed_ns: 500.0, per_light_ns: 40.0 });
    calibration.fallback_triangle = Some(LinearCost { fixed_ns: 900.0, per_light_ns: 60.0 });
    CostModel::store(&path, "device B", &calibration).unwrap();
    let store = load_store(&path).unwrap();
    assert_eq!(store.devices.len(), 2);
    assert_eq!(store.devices["device B"], calibration);
    assert_eq!(store.devices["device A"], CostModel::lavapipe().calibration);
    // A store written before the tessellation costs and the per-pixel path's cost per triangle
    // were measured still reads, without them.
    let mut text = std::fs::read_to_string(&path).unwrap();
    let measured = text.find("[devices.\"device B\".fallback_triangle]").expect("stored");
    assert!(text[measured..].find("[devices.\"device B\".tessellated_patch]").is_some(), "{text}");
    text.truncate(measured);
    std::fs::write(&path, text).unwrap();
    let older = load_store(&path).unwrap();
    assert_eq!(older.devices["device B"].tessellated_patch, None);
    assert_eq!(older.devices["device B"].fallback_triangle, None);
    assert_eq!(older.devices["device B"].estimate.fixed_ns, 42.0);
    std::fs::write(&path, "devices = 3").unwrap();
    let error = CostModel::store(&path, "device C", &calibration).unwrap_err().to_string();
    assert!(error.contains("cost_model.toml") && error.contains("not a cost-model store"), "{error}");
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn the_lavapipe_compiler_setting_is_read_from_gallivm_perf() {
    use LavapipeCompiler::{Optimising, Unoptimised};
    assert_eq!(LavapipeCompiler::of(None), Optimising);
    assert_eq!(LavapipeCompiler::of(Some("")), Optimising);
    assert_eq!(LavapipeCompiler::of(Some("nopt")), Unoptimised);
    assert_eq!(LavapipeCompiler::of(Some("brilinear,nopt")), Unoptimised);
    assert_eq!(LavapipeCompiler::of(Some("no_quad_lod")), Optimising);
    assert_eq!(LavapipeCompiler::of(Some("noptx")), Optimising);
}

#[test]
fn a_calibration_is_looked_up_for_the_device_and_its_compiler_setting() {
    use LavapipeCompiler::{Optimising, Unoptimised};
    let lavapipe = "llvmpipe (LLVM 15.0.6, 256 bits)";
    assert_eq!(calibration_key(lavapipe, Optimising), lavapipe);
    assert_eq!(calibration_key(lavapipe, Unoptimised), format!("{lavapipe}, GALLIVM_PERF=nopt"));
    assert_eq!(calibration_key("NVIDIA H200", Unoptimised), "NVIDIA H200");
    // Without a store, the built-in figures of the setting; elsewhere those of `nopt`.
    assert_eq!(CostModel::from_store(None, lavapipe, Optimising), CostModel::lavapipe_optimising());
    assert_eq!(CostModel::from_store(None, lavapipe, Unoptimised), CostModel::lavapipe());
    assert_eq!(CostModel::from_store(None, "NVIDIA H200", Optimising), CostModel::lavapipe());
    assert!(
        CostModel::lavapipe_optimising().min_estimated_area(1) > CostModel::lavapipe().min_estimated_area(1),
        "a pixel costs less with LLVM's passes, so estimating pays only on larger images"
    );
    // A store holding one setting's calibration serves that setting only.
    let folder = std::env::temp_dir().join(format!("multirate-cost-model-key-{}", std::process::id()));
    let path = folder.join("cost_model.toml");
    let mut calibration = CostModel::lavapipe().calibration;
    calibration.estimate.fixed_ns = 7.0;
    CostModel::store(&path, &calibration_key(lavapipe, Unoptimised), &calibration).unwrap();
    let stored = CostModel::from_store(Some(&path), lavapipe, Unoptimised);
    assert_eq!(stored.calibration.estimate.fixed_ns, 7.0);
    assert!(stored.source.contains("cost_model.toml"), "{}", stored.source);
    assert_eq!(CostModel::from_store(Some(&path), lavapipe, Optimising), CostModel::lavapipe_optimising());
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn a_mesh_is_drawn_per_pixel_when_most_of_its_visible_triangles_are_small() {
    use crate::geometry::camera::view_projection;
    use crate::scene::Camera;
    let camera = Camera {
        eye: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_degrees: 60.0,
        near: 0.1,
        far: 100.0,
    };
    let vp = view_projection(&camera, 640, 480);
    let viewport = Vec2::new(640.0, 480.0);
    // Right triangles facing the eye with legs of `size` units (83 pixels a unit here), their
    // normals spread (the shading varies over them), lit from the front.
    let triangle =
        |size: f32, x: f32| [Vec3::new(x, 0.0, 0.0), Vec3::new(x + size, 0.0, 0.0), Vec3::new(x, size, 0.0)];
    let spread = [Vec3::new(-0.2, 0.0, 1.0), Vec3::new(0.2, 0.0, 1.0), Vec3::new(0.0, 0.2, 1.0)];
    let lights =
        [Light::Directional { direction: Vec3::new(0.3, -0.2, -1.0), color: Vec3::ONE, intensity: 2.0 }];
    let sample = |sizes: &[f32]| MeshSample {
        triangles: sizes.iter().enumerate().map(|(k, &s)| triangle(s, k as f32 * 0.3 - 1.0)).collect(),
        normals: vec![spread; sizes.len()],
        one_sided: true,
        material: Some(MaterialKind::Lambert { kd: Vec3::splat(0.8) }),
    };
    let mostly_small = |sample: &MeshSample, area: f32, epsilon: f32| {
        sample.mostly_small(&vp, camera.eye, viewport, area, &lights, epsilon)
    };
    // 0.05 units: about 8.6 pixels; 0.2 units: about 138.
    assert!(mostly_small(&sample(&[0.05, 0.05, 0.2]), 30.0, 0.075));
    assert!(!mostly_small(&sample(&[0.05, 0.2, 0.2]), 30.0, 0.075));
    assert!(!mostly_small(&sample(&[0.05, 0.05, 0.2]), 0.0, 0.075), "no area floor");
    // Back faces of a one-sided mesh are culled, and do not count.
    let mut behind = sample(&[0.05, 0.2, 0.2]);
    behind.triangles[1].swap(1, 2);
    behind.triangles[2].swap(1, 2);
    assert!(mostly_small(&behind, 30.0, 0.075));
    // Small triangles the range class settles at level 1 are not shaded per pixel: with an ε
    // above the shading's whole range they do not count, unless a parameter map keeps the
    // class from trying them.
    let small = sample(&[0.05, 0.05, 0.2]);
    assert!(!mostly_small(&small, 30.0, 10.0));
    assert!(mostly_small(&MeshSample { material: None, ..small }, 30.0, 10.0));
    // More small triangles than the class is tried on: the share of those tried stands for all.
    let mut sizes = vec![0.005; 3 * RANGE_TRIED];
    sizes.extend([0.2; 8]);
    let many = MeshSample {
        triangles: sizes
            .iter()
            .enumerate()
            .map(|(k, &s)| triangle(s, (k % 40) as f32 * 0.05 - 1.0))
            .collect(),
        ..sample(&sizes)
    };
    assert!(mostly_small(&many, 30.0, 0.075));
    assert!(!mostly_small(&many, 30.0, 10.0));
}
