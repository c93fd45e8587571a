//! Edge adjacency for crack-free adaptive tessellation. Each triangle becomes a 12-index patch:
//! its own three vertices, then, for each edge k (the edge opposite vertex k, which is the edge
//! of `gl_TessLevelOuter[k]`), the three vertices of the triangle across that edge in that
//! triangle's own order. The control stage estimates its own level and its neighbours' from the
//! neighbours' own data, so both sides of a shared edge compute the same outer level.
//!
//! Vertices are matched by position (welded), so seams that duplicate vertices still connect.
//! An edge with no neighbour, or shared by more than two triangles (non-manifold), gets the
//! triangle itself as its "neighbour"; at a non-manifold edge levels can then disagree.

use super::Mesh;
use std::collections::HashMap;

/// Control points per patch of the adaptive (multirate) pipeline.
pub const PATCH_SIZE: usize = 12;

/// The 12-index patches of `mesh`, indices local to the mesh.
pub fn adjacency_patches(mesh: &Mesh) -> Vec<u32> {
    let mut welded: HashMap<[u32; 3], u32> = HashMap::new();
    let canonical: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let key = p.to_array().map(|c| if c == 0.0 { 0 } else { c.to_bits() });
            let next = welded.len() as u32;
            *welded.entry(key).or_insert(next)
        })
        .collect();
    let triangles: Vec<[u32; 3]> = mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    let edge_key = |t: &[u32; 3], k: usize| {
        let a = canonical[t[(k + 1) % 3] as usize];
        let b = canonical[t[(k + 2) % 3] as usize];
        (a.min(b), a.max(b))
    };
    let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (index, triangle) in triangles.iter().enumerate() {
        for k in 0..3 {
            edges.entry(edge_key(triangle, k)).or_default().push(index);
        }
    }
    let mut patches = Vec::with_capacity(triangles.len() * PATCH_SIZE);
    for (index, triangle) in triangles.iter().enumerate() {
        patches.extend_from_slice(triangle);
        for k in 0..3 {
            let sharing = &edges[&edge_key(triangle, k)];
            let neighbour = match sharing.as_slice() {
                [a, b] if *a == index => *b,
                [a, b] if *b == index => *a,
                _ => index,
            };
            patches.extend_from_slice(&triangles[neighbour]);
        }
    }
    patches
}

#[cfg(test)]
mod tests {
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
    fn non_manifold_edges_fall_back_to_the_triangle_itself() {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z];
        let patches = adjacency_patches(&mesh(positions, vec![0, 1, 2, 1, 0, 3, 0, 1, 4]));
        for t in 0..3 {
            let own = &patches[t * PATCH_SIZE..t * PATCH_SIZE + 3];
            assert_eq!(&patches[t * PATCH_SIZE + 9..t * PATCH_SIZE + 12], own, "edge 0-1 is shared by three");
        }
    }
}
