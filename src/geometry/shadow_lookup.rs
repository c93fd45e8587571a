//! The shadow lookup on the CPU: a light's visibility at a surface point, read from the maps'
//! depths as `glsl/include/shadow.glsl`'s `shadow_visibility` reads the atlas (its twin, step
//! for step in `f32`). The tests of the visibility class check it against this.

use super::shadow_view::{face_basis, LightShadow, Projection, ShadowLayout};
use crate::scene::Light;
use glam::{IVec2, Vec3, Vec4Swizzles};

/// The kernel reaches this far (texels) beyond the point's own texel, plus rounding
/// (`SHADOW_TEXEL_SLACK`).
pub const SHADOW_TEXEL_SLACK: f32 = 1.5;

/// `light`'s visibility at `position` on a surface of unit normal `normal` (either side): the
/// share of its kernel's texels whose depth in `atlas` (read back row by row, `layout.extent[0]`
/// wide) is not nearer the light than the lifted point.
pub fn shadow_visibility(
    layout: &ShadowLayout,
    atlas: &[f32],
    light: &Light,
    shadow: LightShadow,
    position: Vec3,
    normal: Vec3,
) -> f32 {
    let map = &layout.maps[shadow.map as usize];
    let radius = shadow.radius as i32;
    let l = match *light {
        Light::Point { position: at, .. } => {
            let to_light = at - position;
            to_light / to_light.length_squared().max(1.0e-8).sqrt()
        }
        Light::Directional { direction, .. } => -direction,
        Light::Polygon(_) => return 1.0,
    };
    let mut texel = map.texel_width;
    let (mut face, mut cube) = (0usize, None);
    if let Projection::Cube { light: at, near, far } = map.projection {
        let d = position - at;
        let a = d.abs();
        let major = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        face = 2 * major + usize::from(d[major] < 0.0);
        texel *= d[major].abs();
        cube = Some((at, near, far));
    }
    let cos_theta = normal.dot(l).clamp(-1.0, 1.0);
    let n = if cos_theta < 0.0 { -normal } else { normal };
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let lift = (radius as f32 + SHADOW_TEXEL_SLACK) * texel;
    let lookup = position + n * (lift * sin_theta) + l * (0.5 * texel);
    let ndc = match (map.projection, cube) {
        (Projection::Orthographic(view_proj), _) => {
            let clip = view_proj * lookup.extend(1.0);
            clip.xyz() / clip.w
        }
        (_, Some((at, near, far))) => {
            let [axis, side, up] = face_basis(face);
            let d = lookup - at;
            let along = axis.dot(d);
            Vec3::new(side.dot(d), -up.dot(d), far * (along - near) / (far - near)) / along
        }
        _ => unreachable!("a cube map has its light"),
    };
    let size = map.size as i32;
    let origin = IVec2::new(map.offset[0] as i32, map.offset[1] as i32)
        + IVec2::new(face as i32 % 3, face as i32 / 3) * size;
    let centre = ((ndc.truncate() * 0.5 + 0.5) * map.size as f32).floor().as_ivec2();
    let width = layout.extent[0] as usize;
    let mut lit = 0;
    for y in -radius..=radius {
        for x in -radius..=radius {
            let at = origin + (centre + IVec2::new(x, y)).clamp(IVec2::ZERO, IVec2::splat(size - 1));
            let stored = atlas[at.y as usize * width + at.x as usize];
            lit += i32::from(ndc.z <= stored);
        }
    }
    let side = 2 * radius + 1;
    lit as f32 / (side * side) as f32
}
