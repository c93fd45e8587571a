//! Where each shadow map looks from, and where it lies in the atlas: a directional light's
//! orthographic map fitted to the scene's bounds, a point light's six cube faces, each a square
//! tile of one depth image ([`ShadowLayout`]). Lights and meshes do not move, so the maps are
//! rendered once; the shaders' lookup is `glsl/include/shadow.glsl`.

use super::camera::{look_at, perspective};
use crate::scene::{bounds_of, Light, Scene};
use glam::{Mat4, Vec3, Vec4};

/// A point light's cube faces in tile order: the axis a face looks along (shadow.glsl picks
/// face `2 · axis + (negative ? 1 : 0)` by the largest component of the light-to-point vector).
pub const CUBE_FACES: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];

/// One square tile of the atlas: a directional light's map or one face of a point light's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowTile {
    /// World to the tile's clip space (depth 0 to 1).
    pub view_proj: Mat4,
    /// The tile's first texel in the atlas.
    pub offset: [u32; 2],
    /// Texels along its side.
    pub size: u32,
    /// A texel's width in world units; a point light's face: per unit of distance along the
    /// face's axis.
    pub texel_width: f32,
}

/// Every shadow map of a scene as tiles of one atlas.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadowLayout {
    /// In the order of `Scene::shadow_casters`, a point light's faces in [`CUBE_FACES`] order.
    pub tiles: Vec<ShadowTile>,
    /// The atlas's width and height in texels (1 × 1 without any tile).
    pub extent: [u32; 2],
    /// Per light of the scene (`Scene::lights` order): its first tile and its filter kernel's
    /// radius in texels, where it casts shadows.
    pub lights: Vec<Option<(u32, u32)>>,
}

impl ShadowLayout {
    /// The tiles of `scene`'s shadow casters, packed in rows (largest first).
    pub fn of(scene: &Scene) -> ShadowLayout {
        let (lo, hi) = bounds_of(scene.meshes.iter().flat_map(|m| m.positions.iter().copied()));
        let mut tiles = Vec::new();
        let mut lights = vec![None; scene.lights.len()];
        for caster in &scene.shadow_casters {
            lights[caster.light] = Some((tiles.len() as u32, caster.filter / 2));
            let size = caster.resolution;
            match scene.lights[caster.light] {
                Light::Point { position, .. } => {
                    tiles.extend(point_faces(position, lo, hi).map(|(view_proj, texel)| ShadowTile {
                        view_proj,
                        offset: [0, 0],
                        size,
                        texel_width: texel / size as f32,
                    }))
                }
                Light::Directional { direction, .. } => {
                    let (view_proj, width) = directional_map(direction, lo, hi);
                    tiles.push(ShadowTile {
                        view_proj,
                        offset: [0, 0],
                        size,
                        texel_width: width / size as f32,
                    });
                }
                Light::Polygon(_) => unreachable!("validation refuses shadows of polygonal lights"),
            }
        }
        let extent = pack(&mut tiles);
        ShadowLayout { tiles, extent, lights }
    }
}

/// Places `tiles` in rows, largest first, in an atlas as wide as the smallest power of two
/// that holds them all in about a square; returns its extent.
fn pack(tiles: &mut [ShadowTile]) -> [u32; 2] {
    if tiles.is_empty() {
        return [1, 1];
    }
    let area: u64 = tiles.iter().map(|t| u64::from(t.size).pow(2)).sum();
    let largest = tiles.iter().map(|t| t.size).max().unwrap_or(1);
    let width = ((area as f64).sqrt().ceil() as u32).max(largest).next_power_of_two();
    let mut order: Vec<usize> = (0..tiles.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(tiles[i].size));
    let (mut x, mut y, mut row_height) = (0, 0, 0);
    for i in order {
        let size = tiles[i].size;
        if x + size > width {
            (x, y, row_height) = (0, y + row_height, 0);
        }
        tiles[i].offset = [x, y];
        x += size;
        row_height = row_height.max(size);
    }
    [width, y + row_height]
}

/// The bounds' eight corners.
fn corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// A directional light travelling along `direction`: the orthographic map holding every point
/// of the box `lo`..`hi` (a 1 % margin around its image), and the map's width in world units.
pub fn directional_map(direction: Vec3, lo: Vec3, hi: Vec3) -> (Mat4, f32) {
    let centre = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-6);
    let up = if direction.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
    let view = look_at(centre - 2.0 * radius * direction, centre, up);
    let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for corner in corners(lo, hi) {
        let p = view.transform_point3(corner);
        (min, max) = (min.min(p), max.max(p));
    }
    let half = (0.5 * (max - min).truncate().max_element() * 1.01).max(1e-6);
    let mid = 0.5 * (min + max);
    let depth = (max.z - min.z).max(1e-6);
    // The view looks along -z: the nearest point has the largest z.
    let (near, far) = (-max.z - 0.01 * depth, -min.z + 0.01 * depth);
    let projection = Mat4::from_cols(
        Vec4::new(1.0 / half, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0 / half, 0.0, 0.0),
        Vec4::new(0.0, 0.0, -1.0 / (far - near), 0.0),
        Vec4::new(-mid.x / half, -mid.y / half, -near / (far - near), 1.0),
    );
    (projection * view, 2.0 * half)
}

/// A point light at `light`: its six 90° faces reaching every corner of `lo`..`hi`, each with a
/// texel's width per texel of side and unit of distance along its axis (2, before dividing by
/// the resolution).
pub fn point_faces(light: Vec3, lo: Vec3, hi: Vec3) -> [(Mat4, f32); 6] {
    let reach = corners(lo, hi).iter().map(|c| (*c - light).length()).fold(0.0f32, f32::max);
    let far = (reach * 1.01).max(1e-3);
    let near = (far * 1e-3).max(1e-6);
    let projection = perspective(std::f32::consts::FRAC_PI_2, 1.0, near, far);
    CUBE_FACES.map(|axis| {
        let up = if axis.y == 0.0 { Vec3::Y } else { Vec3::Z };
        (projection * look_at(light, light + axis, up), 2.0)
    })
}

/// The face of a point light's cube map that holds the direction `d` (from the light), as
/// shadow.glsl picks it.
pub fn cube_face(d: Vec3) -> usize {
    let a = d.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(d[axis] < 0.0)
}

#[cfg(test)]
mod tests;
