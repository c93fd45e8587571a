//! Edge adjacency for crack-free adaptive tessellation. Each triangle becomes a 12-index patch:
//! its own three vertices, then, for each edge k (the edge opposite vertex k, which is the edge
//! of `gl_TessLevelOuter[k]`), the three vertices of the triangle across that edge in that
//! triangle's own order. The control stage estimates its own level and its neighbours' from the
//! neighbours' own data, so both sides of a shared edge compute the same outer level.
//!
//! With `--estimator compute` the control stage reads levels by triangle instead, and needs only
//! each triangle's `neighbours`.
//!
//! Vertices are matched by position (welded), so seams that duplicate vertices still connect.
//! Triangles with two corners at one position are nobody's neighbour. An edge with no
//! neighbour, or shared by more than two triangles (non-manifold), gets the triangle itself as
//! its "neighbour"; at a non-manifold edge levels can then disagree.

use super::model::Mesh;
use std::collections::HashMap;

/// Control points per patch of the adaptive (multirate) pipeline with `--estimator tcs`.
pub const PATCH_SIZE: usize = 12;

/// Per triangle of `mesh`, the triangle across each edge k (opposite vertex k), as a triangle
/// index local to the mesh: the triangle itself where the edge has no neighbour or more than one.
pub fn neighbours(mesh: &Mesh) -> Vec<[u32; 3]> {
    let (triangles, edges, edge_key) = edge_map(mesh);
    triangles
        .iter()
        .enumerate()
        .map(|(index, triangle)| {
            [0, 1, 2].map(|k| match edges.get(&edge_key(triangle, k)).map_or(&[][..], Vec::as_slice) {
                [a, b] if *a == index => *b as u32,
                [a, b] if *b == index => *a as u32,
                _ => index as u32,
            })
        })
        .collect()
}

/// Whether `mesh` is closed: every edge (positions welded) is shared by exactly two triangles.
pub fn is_closed(mesh: &Mesh) -> bool {
    let (_, edges, _) = edge_map(mesh);
    !edges.is_empty() && edges.values().all(|sharing| sharing.len() == 2)
}

/// Whether `meshes` taken together are closed (each alone may be open: the parts of one model
/// split by material).
pub fn is_closed_together(meshes: &[Mesh]) -> bool {
    let mut all = Mesh {
        name: String::new(),
        source: std::path::PathBuf::new(),
        material: 0,
        positions: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
        uvs: Vec::new(),
        two_sided: true,
    };
    for mesh in meshes {
        let base = all.positions.len() as u32;
        all.positions.extend_from_slice(&mesh.positions);
        all.indices.extend(mesh.indices.iter().map(|i| base + i));
    }
    is_closed(&all)
}

type EdgeKey = (u32, u32);

/// The mesh's triangles, the triangles sharing each welded edge, and the key of edge k of a
/// triangle.
#[allow(clippy::type_complexity)]
fn edge_map(
    mesh: &Mesh,
) -> (Vec<[u32; 3]>, HashMap<EdgeKey, Vec<usize>>, impl Fn(&[u32; 3], usize) -> EdgeKey) {
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
    let edge_key = move |t: &[u32; 3], k: usize| {
        let a = canonical[t[(k + 1) % 3] as usize];
        let b = canonical[t[(k + 2) % 3] as usize];
        (a.min(b), a.max(b))
    };
    let mut edges: HashMap<EdgeKey, Vec<usize>> = HashMap::new();
    for (index, triangle) in triangles.iter().enumerate() {
        // Two corners at one position (the fans at a UV sphere's poles): no pixel of its own,
        // and counted it would make the edges of the real triangles beside it non-manifold.
        if (0..3).any(|k| edge_key(triangle, k).0 == edge_key(triangle, k).1) {
            continue;
        }
        for k in 0..3 {
            edges.entry(edge_key(triangle, k)).or_default().push(index);
        }
    }
    (triangles, edges, edge_key)
}

/// The 12-index patches of `mesh`, indices local to the mesh.
pub fn adjacency_patches(mesh: &Mesh) -> Vec<u32> {
    let triangle = |t: u32| &mesh.indices[3 * t as usize..3 * t as usize + 3];
    let mut patches = Vec::with_capacity(mesh.indices.len() / 3 * PATCH_SIZE);
    for (index, across) in neighbours(mesh).iter().enumerate() {
        patches.extend_from_slice(triangle(index as u32));
        for &neighbour in across {
            patches.extend_from_slice(triangle(neighbour));
        }
    }
    patches
}

#[cfg(test)]
mod tests;
