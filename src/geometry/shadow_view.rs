//! Where each shadow map looks from, and where it lies in the atlas: a directional light's
//! orthographic map (fitted to the scene's bounds here; a renderer fits it to what its camera
//! sees, `shadow_fit`), a point light's six cube faces in a block of 3 × 2, all in one depth
//! image ([`ShadowLayout`]). Lights and meshes do not move, so a point light's maps are drawn
//! once; the shaders' lookup is `glsl/include/shadow.glsl`.

use super::camera::perspective;
use super::shadow_fit::{box_corners, DirectionalFrame};
use crate::scene::{bounds_of, Light, Scene, ShadowCaster};
use glam::{Mat4, Vec3, Vec4};

/// A point light's cube faces in order: the axis a face looks along (shadow.glsl picks face
/// `2 · axis + (negative ? 1 : 0)` by the largest component of the light-to-point vector). In
/// the atlas face `f` lies at (`f mod 3`, `f div 3`) sides from its map's first texel.
pub const CUBE_FACES: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];

/// How a map projects: orthographically, or as a point light's six faces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// A directional light's map: world to its clip space (depth 0 to 1).
    Orthographic(Mat4),
    /// A point light's cube: at `light`, its faces' depth from `near` to `far` along their
    /// axes (`point_face`).
    Cube { light: Vec3, near: f32, far: f32 },
}

/// One shadow map in the atlas: a directional light's square, or a point light's six square
/// faces in a block of 3 × 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowMap {
    pub projection: Projection,
    /// Its first texel in the atlas.
    pub offset: [u32; 2],
    /// Texels along a side of the map (of each face).
    pub size: u32,
    /// A texel's width in world units; a point light's face: per unit of distance along the
    /// face's axis.
    pub texel_width: f32,
}

impl ShadowMap {
    /// Texels it takes in the atlas, across and down.
    pub fn footprint(&self) -> [u32; 2] {
        match self.projection {
            Projection::Orthographic(_) => [self.size, self.size],
            Projection::Cube { .. } => [3 * self.size, 2 * self.size],
        }
    }

    /// What the shadow pass renders: each square's world-to-clip matrix and first texel.
    pub fn views(&self) -> Vec<(Mat4, [u32; 2])> {
        match self.projection {
            Projection::Orthographic(view_proj) => vec![(view_proj, self.offset)],
            Projection::Cube { light, near, far } => (0..6)
                .map(|face| {
                    let at =
                        [self.offset[0] + (face % 3) * self.size, self.offset[1] + (face / 3) * self.size];
                    (point_face(light, face as usize, near, far), at)
                })
                .collect(),
        }
    }
}

/// A shadow-casting light's map and its part of multirate's interpolants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightShadow {
    /// Its map's index in [`ShadowLayout::maps`].
    pub map: u32,
    /// Its filter kernel's radius in texels.
    pub radius: u32,
    /// Its slot in the interpolants that carry its unshadowed shading apart: the shadow-casting
    /// point lights first, then the directional ones, each in `Scene::lights` order (the order
    /// the shaders number them in, `render::gpu_lights`).
    pub slot: u32,
}

/// Every shadow map of a scene in one atlas.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadowLayout {
    /// By slot ([`LightShadow::slot`]).
    pub maps: Vec<ShadowMap>,
    /// The atlas's width and height in texels (1 × 1 without any map).
    pub extent: [u32; 2],
    /// Per light of the scene (`Scene::lights` order), where it casts shadows.
    pub lights: Vec<Option<LightShadow>>,
    /// Per slot, the light (its index in `Scene::lights`).
    pub by_slot: Vec<usize>,
}

impl ShadowLayout {
    /// The maps of `scene`'s shadow casters, packed in rows (tallest first).
    pub fn of(scene: &Scene) -> ShadowLayout {
        let (lo, hi) = bounds_of(scene.meshes.iter().flat_map(|m| m.positions.iter().copied()));
        let mut maps = Vec::new();
        let mut lights = vec![None; scene.lights.len()];
        let mut casters: Vec<&ShadowCaster> = scene.shadow_casters.iter().collect();
        casters.sort_by_key(|c| (matches!(scene.lights[c.light], Light::Directional { .. }), c.light));
        let by_slot = casters.iter().map(|c| c.light).collect();
        for (slot, caster) in casters.into_iter().enumerate() {
            let map = maps.len() as u32;
            lights[caster.light] = Some(LightShadow { map, radius: caster.filter / 2, slot: slot as u32 });
            let size = caster.resolution;
            let (projection, width) = match scene.lights[caster.light] {
                Light::Point { position, .. } => {
                    let (near, far) = point_depth_range(position, lo, hi);
                    (Projection::Cube { light: position, near, far }, 2.0)
                }
                Light::Directional { direction, .. } => {
                    let (view_proj, width) = directional_map(direction, lo, hi);
                    (Projection::Orthographic(view_proj), width)
                }
                Light::Polygon(_) => unreachable!("validation refuses shadows of polygonal lights"),
            };
            maps.push(ShadowMap { projection, offset: [0, 0], size, texel_width: width / size as f32 });
        }
        let extent = pack(&mut maps);
        ShadowLayout { maps, extent, lights, by_slot }
    }
}

/// The order the shaders number `lights` in (`render::ShaderLights`): the point lights, then the
/// directional ones, then the polygonal ones; among the point and among the directional lights,
/// those that cast shadows (`casts(i)` for light `i`) first; otherwise in `Scene::lights` order.
/// The shadow casters' slots ([`ShadowLayout::of`]) follow it.
pub fn shader_order(lights: &[Light], casts: impl Fn(usize) -> bool) -> Vec<usize> {
    let kind = |i: usize| match lights[i] {
        Light::Point { .. } => 0,
        Light::Directional { .. } => 1,
        Light::Polygon(_) => 2,
    };
    let mut order: Vec<usize> = (0..lights.len()).collect();
    order.sort_by_key(|&i| (kind(i), !casts(i), i));
    order
}

/// Places `maps` in rows, tallest first, in an atlas as wide as the smallest power of two that
/// holds them all in about a square; returns its extent.
fn pack(maps: &mut [ShadowMap]) -> [u32; 2] {
    if maps.is_empty() {
        return [1, 1];
    }
    let area: u64 = maps.iter().map(|m| m.footprint().iter().map(|&t| u64::from(t)).product::<u64>()).sum();
    let widest = maps.iter().map(|m| m.footprint()[0]).max().unwrap_or(1);
    let width = ((area as f64).sqrt().ceil() as u32).max(widest).next_power_of_two();
    let mut order: Vec<usize> = (0..maps.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(maps[i].footprint()[1]));
    let (mut x, mut y, mut row_height) = (0, 0, 0);
    for i in order {
        let [across, down] = maps[i].footprint();
        if x + across > width {
            (x, y, row_height) = (0, y + row_height, 0);
        }
        maps[i].offset = [x, y];
        x += across;
        row_height = row_height.max(down);
    }
    [width, y + row_height]
}

/// A directional light travelling along `direction`: the orthographic map holding every point
/// of the box `lo`..`hi` (a 1 % margin around its image), and the map's width in world units.
/// A renderer fits it to what its camera sees (`shadow_fit`).
pub fn directional_map(direction: Vec3, lo: Vec3, hi: Vec3) -> (Mat4, f32) {
    let frame = DirectionalFrame::new(direction, lo, hi);
    frame.map(frame.whole)
}

/// A point light at `light`'s depth range: its faces reach every corner of `lo`..`hi`, and
/// begin short of the box's nearest point. A point at distance `d` from the light lies at least
/// `d/√3` from it along its face's axis, so a near plane at half that clips nothing, nor the
/// lookups' lift towards the light (a few texels); a light outside the box gets the depth
/// precision of its distance to it. Inside, or close to it, near is far·10⁻³.
pub fn point_depth_range(light: Vec3, lo: Vec3, hi: Vec3) -> (f32, f32) {
    let reach = box_corners(lo, hi).iter().map(|c| (*c - light).length()).fold(0.0f32, f32::max);
    let far = (reach * 1.01).max(1e-3);
    let nearest = (lo - light).max(light - hi).max(Vec3::ZERO).length();
    ((0.5 * nearest / 3.0f32.sqrt()).max(far * 1e-3), far)
}

/// The basis of cube face `face` ([`CUBE_FACES`]): its axis, and the directions of its map's
/// x and y (shadow.glsl builds the same three).
pub fn face_basis(face: usize) -> [Vec3; 3] {
    let axis = CUBE_FACES[face];
    let up = if axis.y == 0.0 { Vec3::Y } else { Vec3::Z };
    let side = axis.cross(up);
    [axis, side, side.cross(axis)]
}

/// World to the clip space of face `face` of a point light at `light`, 90° wide, its depth from
/// `near` to `far` along the face's axis: x = side·d / (axis·d), y = −up·d / (axis·d), with
/// d the light-to-point vector, as shadow.glsl projects.
pub fn point_face(light: Vec3, face: usize, near: f32, far: f32) -> Mat4 {
    let [axis, side, up] = face_basis(face);
    let view = Mat4::from_cols(
        Vec4::new(side.x, up.x, -axis.x, 0.0),
        Vec4::new(side.y, up.y, -axis.y, 0.0),
        Vec4::new(side.z, up.z, -axis.z, 0.0),
        Vec4::new(-side.dot(light), -up.dot(light), axis.dot(light), 1.0),
    );
    perspective(std::f32::consts::FRAC_PI_2, 1.0, near, far) * view
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
