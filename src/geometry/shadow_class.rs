//! Whether a shadow-casting light reaches every pixel of a triangle (lit), none (shadowed) or
//! some (mixed), from the rendered maps' depths and their min/max pyramid ([`ShadowDepths`]).
//! Conservative for everything `glsl/include/shadow.glsl`'s lookup does at any point of the
//! triangle: the lift off its plane, the filter kernel, the clamp to the map's edge and the
//! rounding of the GPU's arithmetic; where it cannot prove either, mixed. Multirate sums a lit
//! light with the unshadowed ones, leaves a shadowed one out of the triangle's estimate and
//! shading, and looks the visibility up per pixel only for a mixed one (`docs/estimator.md`
//! section 18).
//!
//! What one map square shows of a triangle's lookups is `shadow_footprint`'s; a point light's
//! triangle is split by the cube faces its pixels may look up in, and is lit or shadowed only
//! where every face's part is.

use super::shadow_footprint::{cube_images, directional_image};
pub use super::shadow_footprint::{DepthSquare, Visibility};
use super::shadow_view::{shader_order, Projection, ShadowLayout};
use crate::scene::{Light, Scene};
use glam::Vec3;

/// Every map's depths: a square for a directional map, six (by face) for a point light's.
pub struct ShadowDepths {
    maps: Vec<Vec<DepthSquare>>,
}

impl ShadowDepths {
    /// The squares of `layout`'s maps in `atlas`, the atlas's depths read back row by row.
    pub fn new(layout: &ShadowLayout, atlas: &[f32]) -> ShadowDepths {
        let width = layout.extent[0];
        let maps = layout
            .maps
            .iter()
            .map(|map| {
                let faces = match map.projection {
                    Projection::Orthographic(_) => 1,
                    Projection::Cube { .. } => 6,
                };
                (0..faces)
                    .map(|f| {
                        let origin = [map.offset[0] + (f % 3) * map.size, map.offset[1] + (f / 3) * map.size];
                        DepthSquare::new(atlas, width, origin, map.size)
                    })
                    .collect()
            })
            .collect();
        ShadowDepths { maps }
    }

    /// The squares of the maps `maps` of `layout`, each given as its index and its footprint's
    /// depths read back row by row; the other maps have none (a light of theirs is not
    /// classified).
    pub fn of_maps(layout: &ShadowLayout, maps: &[(usize, Vec<f32>)]) -> ShadowDepths {
        let mut squares: Vec<Vec<DepthSquare>> = layout.maps.iter().map(|_| Vec::new()).collect();
        for (m, texels) in maps {
            let record = &layout.maps[*m];
            let faces = match record.projection {
                Projection::Orthographic(_) => 1,
                Projection::Cube { .. } => 6,
            };
            let width = record.footprint()[0];
            squares[*m] = (0..faces)
                .map(|f| {
                    DepthSquare::new(
                        texels,
                        width,
                        [(f % 3) * record.size, (f / 3) * record.size],
                        record.size,
                    )
                })
                .collect();
        }
        ShadowDepths { maps: squares }
    }

    /// Light `light`'s visibility over the triangle `corners`, where it casts shadows through
    /// map `map` of `layout` with a kernel of `radius` texels.
    pub fn classify(
        &self,
        layout: &ShadowLayout,
        map: u32,
        radius: u32,
        light: &Light,
        corners: [Vec3; 3],
    ) -> Visibility {
        let record = &layout.maps[map as usize];
        let squares = &self.maps[map as usize];
        let corners = corners.map(|c| c.as_dvec3());
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        if normal.length().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
            || !corners.iter().all(|c| c.is_finite())
        {
            return Visibility::Mixed;
        }
        let images = match (record.projection, light) {
            (Projection::Orthographic(_), Light::Directional { direction, .. }) => directional_image(
                record,
                radius,
                -direction.as_dvec3().normalize(),
                normal.normalize(),
                corners,
            )
            .map(|image| vec![image]),
            (Projection::Cube { light: at, .. }, Light::Point { .. }) => {
                cube_images(record, radius, at.as_dvec3(), corners)
            }
            _ => None,
        };
        let mut verdicts =
            images.into_iter().flatten().map(|image| image.visibility(&squares[image.face], radius));
        match verdicts.next() {
            Some(first) if verdicts.all(|v| v == first) => first,
            _ => Visibility::Mixed,
        }
    }
}

/// Light `light` (of `lights`)'s class over the triangle `corners`, through its map of `layout`.
fn classify_one(
    lights: &[Light],
    layout: &ShadowLayout,
    depths: &ShadowDepths,
    light: usize,
    corners: [Vec3; 3],
) -> Visibility {
    let shadow = layout.lights[light].expect("a slot's light has a map");
    depths.classify(layout, shadow.map, shadow.radius, &lights[light], corners)
}

/// Every shadow-casting light's visibility over every triangle of a scene's meshes (in the
/// order the renderer numbers them: mesh by mesh, each mesh's triangles in order), by slot
/// (`LightShadow::slot`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadowClasses {
    /// Per slot, the light (its index in `Scene::lights`); their count is the stride of `classes`.
    lights: Vec<usize>,
    /// Per triangle, per slot.
    classes: Vec<Visibility>,
}

impl ShadowClasses {
    /// The classes of every triangle of `scene` against its maps, laid out by `layout` and
    /// rendered into `depths`.
    pub fn of(scene: &Scene, layout: &ShadowLayout, depths: &ShadowDepths) -> ShadowClasses {
        ShadowClasses::of_triangles(&scene.lights, layout, depths, scene.triangles())
    }

    /// The classes of `triangles` (their corners, in the renderer's order) lit by `lights`
    /// (the scene's) against the maps laid out by `layout` and rendered into `depths`.
    pub fn of_triangles(
        lights: &[Light],
        layout: &ShadowLayout,
        depths: &ShadowDepths,
        triangles: impl Iterator<Item = [Vec3; 3]>,
    ) -> ShadowClasses {
        let mut classes = Vec::new();
        for corners in triangles {
            classes.extend(
                layout.by_slot.iter().map(|&light| classify_one(lights, layout, depths, light, corners)),
            );
        }
        ShadowClasses { lights: layout.by_slot.clone(), classes }
    }

    /// The classes of the lights in `slots` anew, their maps drawn again into `depths`; the
    /// other slots' are kept. `triangles` are those the classes were first made of.
    pub fn reclassify(
        &mut self,
        lights: &[Light],
        layout: &ShadowLayout,
        depths: &ShadowDepths,
        triangles: impl Iterator<Item = [Vec3; 3]>,
        slots: &[usize],
    ) {
        let stride = self.lights.len();
        for (triangle, corners) in triangles.enumerate() {
            for &slot in slots {
                let class = classify_one(lights, layout, depths, self.lights[slot], corners);
                self.classes[triangle * stride + slot] = class;
            }
        }
    }

    /// The light in slot `slot` (its index in `Scene::lights`).
    pub fn light(&self, slot: usize) -> usize {
        self.lights[slot]
    }

    /// Triangle `triangle`'s class against the light in slot `slot`.
    pub fn visibility(&self, triangle: usize, slot: usize) -> Visibility {
        self.classes[triangle * self.lights.len() + slot]
    }

    /// Every triangle's classes, by slot.
    pub fn per_triangle(&self) -> impl Iterator<Item = &[Visibility]> {
        self.classes.chunks_exact(self.lights.len().max(1))
    }

    /// Triangle `triangle`'s lights as its estimate sums them (docs/estimator.md section 18):
    /// `lights` (the scene's) in the shaders' order ([`shader_order`]), without those that reach
    /// none of it.
    pub fn lights_reaching(&self, lights: &[Light], triangle: usize) -> Vec<Light> {
        let slot = |i: usize| self.lights.iter().position(|&light| light == i);
        shader_order(lights, |i| slot(i).is_some())
            .into_iter()
            .filter(|&i| slot(i).is_none_or(|s| self.visibility(triangle, s) != Visibility::Shadowed))
            .map(|i| lights[i])
            .collect()
    }

    /// Per slot, how many triangles are lit, shadowed and mixed.
    pub fn counts(&self) -> Vec<[usize; 3]> {
        let mut counts = vec![[0; 3]; self.lights.len()];
        for (i, class) in self.classes.iter().enumerate() {
            let column = match class {
                Visibility::Lit => 0,
                Visibility::Shadowed => 1,
                Visibility::Mixed => 2,
            };
            counts[i % self.lights.len()][column] += 1;
        }
        counts
    }
}

#[cfg(test)]
mod tests;
