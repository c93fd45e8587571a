//! Tests of `bench::experiments`: the tessellated plane grid, the trade page's table heads.

use super::*;

#[test]
fn plane_grid_has_2n2_upward_triangles() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let plane = Scene::load(&root.join("scenes/plane_lights.toml")).expect("plane scene");
    let grid = plane_grid(&plane, 5);
    let mesh = &grid.meshes[0];
    assert_eq!(grid.triangle_count(), 50);
    assert_eq!(mesh.positions.len(), 36);
    for triangle in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[triangle[k] as usize]);
        let normal = (b - a).cross(c - a);
        assert!(normal.y > 0.0 && normal.x == 0.0 && normal.z == 0.0, "counter-clockwise from +Y");
    }
    let area: f32 = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
            (b - a).cross(c - a).length() / 2.0
        })
        .sum();
    assert!((area - 4.0).abs() < 1e-4, "the grid tiles the 2×2 square: {area}");
}

#[test]
fn a_table_head_has_its_title_its_explanation_and_aligned_columns() {
    let mut md = String::new();
    trade::table_head(&mut md, "Title", None, &["scene", "pixel"]);
    trade::table_head(&mut md, "Next", Some("Why."), &["scene", "a", "b"]);
    let expected =
        "## Title\n\nThe columns are those of the table above.\n\n| scene | pixel |\n| --- | ---: |\n\
                    ## Next\n\nWhy.\n\n| scene | a | b |\n| --- | ---: | ---: |\n";
    assert_eq!(md, expected);
}

/// A measured row of `mode` (multirate: with the cost model where `area` > 0) at 1920×1080.
fn row(mode: &str, gpu_ms: f64, area: Option<f32>) -> Row {
    use crate::bench::row::Timing;
    let timing = Timing { median: gpu_ms, p10: gpu_ms, p90: gpu_ms };
    Row {
        scene: "bunny".to_string(),
        triangles: 3674,
        mode: mode.to_string(),
        epsilon: None,
        n_max: None,
        estimator: None,
        levels_held: None,
        width: 1920,
        height: 1080,
        frames: 7,
        gpu_ms: timing,
        pre_pass_ms: area.map(|_| Timing { median: 1.0, p10: 1.0, p90: 1.0 }),
        pre_pass_steps_ms: None,
        draw_parts_ms: None,
        min_estimated_area: area,
        frames_drawn_as_pixel: area.filter(|&a| a > 0.0).map(|_| 0),
        speedup: 1.0,
        trade: Some(crate::bench::row::Trade::of(gpu_ms, 60.0, 10.0)),
        empty_ms: 5.0,
        evaluations: Default::default(),
        evaluation_ratio: 1.0,
        l_inf: 0.0,
        l_inf_same_triangle: 0.0,
        other_triangle_pixels: 0,
        pixels_over_epsilon: None,
        mean_l2: 0.0,
        psnr_db: 0.0,
        flip: 0.0,
        fallback_fraction: None,
        statistics: None,
        device: String::new(),
        driver: String::new(),
    }
}

#[test]
fn the_turning_table_needs_only_the_cost_models_rows() {
    // The still run has both multirate configurations, the turning run only the cost model's.
    let still = [
        row("pixel", 60.0, None),
        row("vertex", 10.0, None),
        row("multirate", 20.0, Some(5.0)),
        row("multirate", 22.0, Some(0.0)),
    ];
    let turning = [row("pixel", 61.0, None), row("vertex", 11.0, None), row("multirate", 30.0, Some(5.0))];
    let mut md = String::new();
    trade::turning_table(&mut md, &still, &turning, (1920, 1080), false);
    let bunny: Vec<&str> = md.lines().filter(|line| line.starts_with("| bunny |")).collect();
    assert_eq!(
        bunny,
        ["| bunny | 60.0 | 20.0 (1.0) | 80 % | 61.0 | 11.0 | 30.0 (1.0) | 100 % | 60 % | 0 of 7 |"],
        "{md}"
    );
}
