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
