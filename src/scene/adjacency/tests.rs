use super::*;
use glam::Vec3;

fn mesh(positions: Vec<Vec3>, indices: Vec<u32>) -> Mesh {
    Mesh {
        name: "test".into(),
        source: "test.obj".into(),
        material: 0,
        normals: vec![Vec3::Z; positions.len()],
        positions,
        indices,
        uvs: Vec::new(),
        two_sided: true,
    }
}

#[test]
fn two_triangles_see_each_other_across_the_shared_edge() {
    // Square split along the diagonal 0-2; the second triangle duplicates vertex 2 as 4
    // (a seam) to check welding.
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
    ];
    let patches = adjacency_patches(&mesh(positions, vec![0, 1, 2, 0, 4, 3]));
    assert_eq!(patches.len(), 2 * PATCH_SIZE);
    // Triangle 0: edge 1 (opposite vertex 1) is 2-0, shared with triangle 1.
    assert_eq!(&patches[0..3], &[0, 1, 2]);
    assert_eq!(&patches[3..6], &[0, 1, 2], "edge 0 (1-2) is a boundary: itself");
    assert_eq!(&patches[6..9], &[0, 4, 3], "edge 1 (2-0) borders triangle 1");
    assert_eq!(&patches[9..12], &[0, 1, 2], "edge 2 (0-1) is a boundary");
    // Triangle 1: edge 2 (opposite vertex 3) is 0-4, shared with triangle 0.
    assert_eq!(&patches[12 + 9..12 + 12], &[0, 1, 2]);
    assert_eq!(&patches[12 + 3..12 + 6], &[0, 4, 3]);
}

#[test]
fn triangles_with_coincident_corners_are_nobodys_neighbour() {
    // A pole fan: the quad 0-1-2-3 with corners 0 and 3 at one point, triangulated as a
    // real triangle (0, 1, 2) and a degenerate one (0, 2, 3); (4, 2, 1) is across 1-2.
    // Without the rule, edge 0-2 would be shared by three triangles.
    let positions = vec![Vec3::Y, Vec3::X, Vec3::Z, Vec3::Y, Vec3::new(1.0, 0.0, 1.0)];
    let the_mesh = mesh(positions, vec![0, 1, 2, 0, 2, 3, 4, 2, 1, 0, 2, 4]);
    let across = neighbours(&the_mesh);
    assert_eq!(across[0], [2, 3, 0], "real triangles pair up across 1-2 and 2-0");
    assert_eq!(across[1], [1, 1, 1], "the degenerate triangle has no neighbour");
    assert_eq!(across[3][2], 0);
}

#[test]
fn non_manifold_edges_fall_back_to_the_triangle_itself() {
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z];
    let patches = adjacency_patches(&mesh(positions, vec![0, 1, 2, 1, 0, 3, 0, 1, 4]));
    for t in 0..3 {
        let own = &patches[t * PATCH_SIZE..t * PATCH_SIZE + 3];
        assert_eq!(&patches[t * PATCH_SIZE + 9..t * PATCH_SIZE + 12], own, "edge 0-1 is shared by three");
    }
}
