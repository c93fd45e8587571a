//! Culling before the estimate: which triangles of the multirate pass cannot be seen (outside
//! the frustum, an image that is a segment, a back face of a one-sided mesh) and get outer
//! level 0 without running the estimator, and which are shaded per pixel without it (the
//! back faces of two-sided meshes, and images too small for an estimate to pay, by the cost
//! model's `min_estimated_area`). The Rust twin of `patch_culled` and `visible_level` in
//! `glsl/include/triangle_level.glsl`, operation for operation (no fused multiply-adds on
//! either side), so that the level records of the GPU and of `analysis::report` agree bit for
//! bit; `tests/multirate.rs` checks that.

use glam::{Mat4, Vec2, Vec3, Vec4};

/// Back faces are culled before the estimate only when the eye is more than this sine (squared)
/// away from their plane; the rasteriser culls the nearly edge-on rest, so what is drawn never
/// differs from `pixel` mode, which leaves all back-face culling to the rasteriser.
pub const BACKFACE_MARGIN_SQUARED: f32 = 1.0e-6;

/// The sine below which a triangle's image counts as a segment ([`degenerate_image`]): 2⁻¹⁸, some
/// 64 times the relative rounding of a float area, so that the image of a triangle that is not
/// culled has an area that rounds to a number of the right sign.
pub const DEGENERATE_IMAGE_SINE: f32 = 1.0 / 262_144.0;

/// The level of a culled triangle (`CULLED_LEVEL` in triangle_level.glsl): below every real
/// level, so that a culled neighbour asks for no more than level 1 on the shared edge. The
/// level records of a culled triangle read `[CULLED_LEVEL, 0, 0, 0]`.
pub const CULLED_LEVEL: f32 = -1.0;

/// Clip-space position of world point `p`, summed in the shader's order.
pub fn clip_of(view_proj: &Mat4, p: Vec3) -> Vec4 {
    ((view_proj.x_axis * p.x + view_proj.y_axis * p.y) + view_proj.z_axis * p.z) + view_proj.w_axis
}

fn dot3(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

fn cross3(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y)
}

/// Whether the triangle `p` lies wholly outside one plane of the view frustum of `view_proj`,
/// its image is a segment ([`degenerate_image`]), or, on a one-sided mesh, it faces away from
/// `eye` (front faces wind anticlockwise).
pub fn culled(view_proj: &Mat4, eye: Vec3, p: [Vec3; 3], one_sided: bool) -> bool {
    let c = p.map(|p| clip_of(view_proj, p));
    let all = |outside: &dyn Fn(&Vec4) -> bool| c.iter().all(outside);
    if all(&|c| c.x > c.w)
        || all(&|c| c.x < -c.w)
        || all(&|c| c.y > c.w)
        || all(&|c| c.y < -c.w)
        || all(&|c| c.z > c.w)
        || all(&|c| c.z < 0.0)
    {
        return true;
    }
    if degenerate_image(c[0], c[1], c[2]) {
        return true;
    }
    one_sided && faces_away(eye, p)
}

/// Whether `eye` lies clearly behind the plane of the triangle `p` (more than the sine
/// [`BACKFACE_MARGIN_SQUARED`] away from it; front faces wind anticlockwise).
pub fn faces_away(eye: Vec3, p: [Vec3; 3]) -> bool {
    let normal = cross3(p[1] - p[0], p[2] - p[0]);
    let to_eye = eye - p[0];
    let facing = dot3(normal, to_eye);
    let margin = BACKFACE_MARGIN_SQUARED * dot3(normal, normal) * dot3(to_eye, to_eye);
    facing < 0.0 && facing * facing > margin
}

/// The image edge from the corner at clip position `a` to the one at `b`, times `a.w·b.w`:
/// `b.xy/b.w − a.xy/a.w` without a division.
fn scaled_edge(a: Vec4, b: Vec4) -> [f32; 2] {
    [b.x * a.w - a.x * b.w, b.y * a.w - a.y * b.w]
}

/// `|v.x| + |v.y|`, a norm between `|v|` and `√2·|v|` that needs no square root.
fn norm1(v: [f32; 2]) -> f32 {
    v[0].abs() + v[1].abs()
}

/// Twice the signed area of the image of the triangle at clip positions `a`, `b`, `c`, times
/// `a.w·b.w·c.w`: the determinant of the rows (x, y, w).
pub fn image_determinant(a: Vec4, b: Vec4, c: Vec4) -> f32 {
    (a.x * (b.y * c.w - c.y * b.w) - b.x * (a.y * c.w - c.y * a.w)) + c.x * (a.y * b.w - b.y * a.w)
}

/// Whether the image of the triangle at clip positions `a`, `b`, `c`, in front of the eye, is a
/// segment or a point to floating-point precision: twice its area is at most
/// [`DEGENERATE_IMAGE_SINE`] times the product of its two edges at one corner (in `|·|₁`). The
/// rasteriser can still cover a sample of such an image (from its snapped corners) while its
/// interpolation, from the float corners, divides by an area that rounded to zero: not a number
/// at every attribute. Such a triangle shows no surface; `pixel` mode shows at most single
/// pixels of it. A triangle with a corner at or behind the eye's plane is left to clipping.
pub fn degenerate_image(a: Vec4, b: Vec4, c: Vec4) -> bool {
    if !(a.w > 0.0 && b.w > 0.0 && c.w > 0.0) {
        return false;
    }
    let size = image_determinant(a, b, c).abs();
    let (ab, bc, ca) = (scaled_edge(a, b), scaled_edge(b, c), scaled_edge(c, a));
    // At corner a the edges are ab/(a.w·b.w) and ca/(c.w·a.w): the area over their product,
    // times a.w·b.w·c.w, is size·a.w over |ab|·|ca|; likewise at b and c.
    let at_a = DEGENERATE_IMAGE_SINE * (norm1(ab) * norm1(ca));
    let at_b = DEGENERATE_IMAGE_SINE * (norm1(bc) * norm1(ab));
    let at_c = DEGENERATE_IMAGE_SINE * (norm1(ca) * norm1(bc));
    size * a.w <= at_a || size * b.w <= at_b || size * c.w <= at_c
}

/// Whether the image of the triangle at clip positions `a`, `b`, `c`, all in front of the eye,
/// covers fewer than `min_area` pixels of a `viewport` (width, height) target: its area in
/// pixels is `|det| / (a.w·b.w·c.w) · width·height/8` (the image spans 2 units of normalised
/// device coordinates per viewport side). The area of the whole triangle bounds that of its
/// visible part from above. A triangle with a corner at or behind the eye's plane is never small.
pub fn small_image(a: Vec4, b: Vec4, c: Vec4, viewport: Vec2, min_area: f32) -> bool {
    if !(a.w > 0.0 && b.w > 0.0 && c.w > 0.0) {
        return false;
    }
    let pixels = image_determinant(a, b, c).abs() * (0.125 * (viewport.x * viewport.y));
    let least = min_area * ((a.w * b.w) * c.w);
    pixels < least
}

/// What decides, besides the triangle, whether it is shaded per pixel without an estimate
/// ([`back_face_per_pixel`], [`small_per_pixel`]): the draw's push constants `view_proj`, `eye`,
/// `viewport_size`, `min_estimated_area` and its `FLAG_ONE_SIDED`.
#[derive(Clone, Copy, Debug)]
pub struct PerPixelRule {
    pub view_proj: Mat4,
    pub eye: Vec3,
    /// The target's width and height in pixels.
    pub viewport: Vec2,
    /// Images smaller than this many pixels are shaded per pixel (0: every triangle is
    /// estimated); `render::cost_model` chooses it.
    pub min_estimated_area: f32,
}

/// Whether a triangle that is not [`culled`] is a back face shaded per pixel without an
/// estimate (`back_face_per_pixel` in triangle_level.glsl): a back face of a two-sided mesh. The
/// fallback draw comes after the others, so where the mesh's front faces hide such a face (the
/// far side of an open mesh) the early depth test rejects its fragments before they shade,
/// where interpolated shading would shade all of its sub-vertices.
pub fn back_face_per_pixel(rule: &PerPixelRule, p: [Vec3; 3], one_sided: bool) -> bool {
    !one_sided && faces_away(rule.eye, p)
}

/// Whether a triangle that is not [`culled`] and that the range class does not settle is
/// shaded per pixel without an estimate (`small_per_pixel` in triangle_level.glsl): a
/// [`small_image`], whose estimate would cost more than shading its few pixels. The range class
/// costs a fraction of an estimate, so it is tried first (`visible_level` in
/// triangle_level.glsl).
pub fn small_per_pixel(rule: &PerPixelRule, p: [Vec3; 3]) -> bool {
    rule.min_estimated_area > 0.0 && {
        let [a, b, c] = p.map(|p| clip_of(&rule.view_proj, p));
        small_image(a, b, c, rule.viewport, rule.min_estimated_area)
    }
}

#[cfg(test)]
mod tests;
