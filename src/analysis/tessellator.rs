//! A model of Vulkan's fixed-function triangle tessellator with `equal_spacing`: the
//! vertices (as `gl_TessCoord`) and triangles it emits for given inner and outer levels.
//!
//! The model follows lavapipe, Mesa's software Vulkan driver. Lavapipe hands the patch to
//! gallium's draw module, which runs Mesa's port of Microsoft's D3D11 reference
//! tessellator (`CHWTessellator::TessellateTriDomain`) with integer partitioning. The code
//! here is an independent re-statement of that algorithm's rules, not a transcription; the
//! rules as this module understands them:
//!
//! * **Levels.** Outer levels `(o0, o1, o2)` belong to the edges `u = 0`, `v = 0`, `w = 0`
//!   (`gl_TessLevelOuter[i]` is the D3D `TessFactor_{U,V,W}eq0`). If any outer level is not
//!   `> 0` (zero, negative or NaN) the patch is culled. Every level is then clamped to
//!   `[1, 64]` (a NaN *inner* level becomes 1) and rounded up to an integer.
//! * **All ones.** Inner = outer = 1 gives one triangle on the three corners.
//! * **Inner 1 with an outer level > 1.** The reference treats inner level 1 as an *even*
//!   level with a half-segment count of one, which is exactly what inner level 2 gives: a
//!   single centre point that every outer segment is fanned to. (The spec says the inner
//!   level is taken as `1 + ε`, which rounds up to 2 under `equal_spacing`.)
//! * **1-D placement.** A level-`n` edge has `n + 1` points. Point `p` sits at
//!   `p · R(n)` in 16.16 fixed point, where `R(n) = round(2¹⁶ / n)`, when `p < n/2`; the
//!   second half is mirrored (`1 − (n − p) · R(n)`), and the midpoint of an even level is
//!   exactly ½. Every coordinate is therefore a multiple of 2⁻¹⁶, which this model
//!   reproduces bit for bit; `gl_TessCoord.z` is `1 − u − v`, also exact.
//! * **Points, in emission order.** First the outer ring, clockwise in D3D terms: edge
//!   `u = 0` from the `v = 1` corner towards `w = 1`, then edge `v = 0` from `w = 1` towards
//!   `u = 1`, then edge `w = 0` from `u = 1` towards `v = 1` (each edge omits its final
//!   corner, which is the next edge's first point). Then the inner rings, outermost first,
//!   in the same edge order; ring `r` of an inner level `n` uses the inner 1-D points
//!   `r ..= n − r` pushed inward: the edge's constant coordinate is
//!   `round(x_r · ⅔)` (with ⅔ truncated to `0xaaaa`), and the along-edge coordinate is the
//!   1-D point minus `⌊(that + 1) / 2⌋`. An even inner level ends in the centre point
//!   `(0x5555, 0x5555)·2⁻¹⁶`; an odd one ends in a ring of three points.
//! * **Triangles, in emission order.** Ring by ring from the outside in; within a ring,
//!   the strip along edge `u = 0`, then `v = 0`, then `w = 0`; an odd inner level adds the
//!   centre triangle last. The outermost strip is a *transition* stitch (the outer edge
//!   and the first inner ring differ in level and parity; which side advances next is
//!   decided by a ruler-function split order, see [`ruler_position`]); deeper strips are
//!   *regular* stitches whose diagonals mirror about the middle of the strip.
//! * **Winding.** Every triangle is stored in the order the reference produces for its
//!   `TRIANGLE_CW` output: its barycentric determinant `det[(u,v,w)ᵢ]` is positive, i.e.
//!   it turns the same way as the corner sequence `(u=1, v=1, w=1)`. Lavapipe picks that
//!   output when the evaluation shader declares `VertexOrderCw` (GLSL `cw`) with the
//!   default `VK_TESSELLATION_DOMAIN_ORIGIN_UPPER_LEFT`: it flips the shader's `ccw` flag
//!   for the upper-left origin, and the draw module maps GL/NIR `ccw` to D3D CW. That
//!   agrees with the spec: in the upper-left figure (y pointing down) positive-determinant
//!   triangles are clockwise. A `VertexOrderCcw` shader (GLSL `ccw`, also GLSL's default)
//!   with the upper-left origin, or a `cw` one with the lower-left origin, gets every
//!   triangle `[a, b, c]` of this model as `[a, c, b]`, with the triangle order unchanged.
//!   Whether a triangle then faces front on screen depends on how the evaluation shader
//!   maps `(u, v, w)` to positions (for `P = u·A + v·B + w·C` the winding is the
//!   determinant's sign times the winding of `A, B, C`) and on the viewport's y direction.
//!
//! Checked against the real thing: lavapipe of Mesa 22.3.6 (llvmpipe, LLVM 15), capturing
//! the evaluation shader's `gl_TessCoord` per emitted triangle with transform feedback,
//! reproduced this model exactly (bit-identical coordinates, same triangle order, same
//! vertex order within each triangle) for the uniform levels 1…64, every level set in
//! 1…6, about 100 000 random integer and 5 000 random fractional level sets up to 66,
//! and the culling cases; with `cw` + upper-left it matched `[a, b, c]`, with `ccw` +
//! upper-left and with `cw` + lower-left it matched `[a, c, b]`. Only the order of the
//! vertex list itself is unobservable that way (the model keeps the driver's point order).

/// One tessellated patch in the triangle's barycentric domain.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pattern {
    /// Barycentric coordinates (u, v, w), u + v + w = 1: what the TES sees as `gl_TessCoord`.
    pub vertices: Vec<[f64; 3]>,
    /// Indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

/// Fraction bits of the reference tessellator's fixed-point domain coordinates.
const FRAC_BITS: u32 = 16;
/// 1.0 in 16.16 fixed point.
const FX_ONE: u32 = 1 << FRAC_BITS;
/// 0.5 in 16.16 fixed point (also the rounding bias for a 16-bit right shift).
const FX_HALF: u32 = FX_ONE / 2;
/// ⅓ truncated to 16.16 (`0x5555`): both barycentric coordinates of the centre point.
const FX_THIRD: u32 = FX_ONE / 3;
/// ⅔ truncated to 16.16 (`0xaaaa`): the factor that turns an inner 1-D position into the
/// distance of an inner ring from the patch edge.
const FX_TWO_THIRDS: u32 = 2 * FX_ONE / 3;
/// `maxTessellationGenerationLevel` of lavapipe (and the D3D11 limit).
const MAX_LEVEL: u32 = 64;

/// Levels as the TCS writes them (gl_TessLevelInner[0], gl_TessLevelOuter[0..3]); applies
/// Vulkan's clamping and rounding for equal_spacing (max level 64).
///
/// Returns the vertices and triangles lavapipe emits for the patch, vertices in the
/// driver's emission order (each exactly once) and triangles in its emission order and
/// winding (see the module docs: `VertexOrderCw` with the upper-left domain origin).
///
/// Culling: the spec discards the patch when any outer level it uses is `≤ 0` or NaN, and
/// so does the driver; an empty [`Pattern`] is returned then. The inner level is never a
/// reason to cull: like the driver, a zero, negative or NaN inner level is clamped to 1.
pub fn triangle_pattern(inner: f32, outer: [f32; 3]) -> Pattern {
    match round_levels(inner, outer) {
        None => Pattern::default(),
        Some((inner, outer)) => tessellate(inner, outer),
    }
}

/// Number of distinct vertices at inner = outer = n: must equal ceil(3(n+1)²/4); triangles
/// floor(3n²/2) for n ≥ 1 (n = 1: 3 vertices, 1 triangle).
///
/// `n = 0` is a culled patch (0 vertices); `n > 64` counts as 64, the clamped level.
pub fn uniform_vertex_count(n: u32) -> usize {
    if n == 0 {
        return 0;
    }
    let n = n.min(MAX_LEVEL) as usize;
    (3 * (n + 1) * (n + 1)).div_ceil(4)
}

/// Number of triangles at inner = outer = n: floor(3n²/2) for n ≥ 1 (n = 1: one triangle).
///
/// `n = 0` is a culled patch (no triangles); `n > 64` counts as 64, the clamped level.
pub fn uniform_triangle_count(n: u32) -> usize {
    let n = n.min(MAX_LEVEL) as usize;
    3 * n * n / 2
}

/// For a patch triangle with the given corner positions, the largest sub-triangle
/// diameter (longest edge) of `pattern`, divided by `patch diameter / n` (the patch
/// diameter being the patch's longest edge). This is the pattern factor of the error
/// estimator: a sub-triangle is at most `diameter_ratio · D / n` across.
///
/// `corners[0]`, `corners[1]`, `corners[2]` are where `gl_TessCoord` = (1,0,0), (0,1,0),
/// (0,0,1) land, i.e. a vertex (u, v, w) maps to `u·c0 + v·c1 + w·c2`; for points in the
/// plane set the third coordinate to 0. Returns 0 for an empty pattern.
///
/// Values measured by this module's tests over the uniform patterns (inner = outer = n):
/// * equilateral patch, n = 1…16: max **1.1553** (at n = 13). The ideal pattern gives
///   2/√3 ≈ 1.1547 (first at n = 2, the fan to the centre point); the excess is the
///   driver's fixed-point placement (rounded segment lengths, a truncated ⅔ for the ring
///   offsets, the middle segment absorbing the rounding). Over n = 1…64 the max is
///   **1.1721** (at n = 61).
/// * thin patches (right-angled, obtuse and needle-shaped slivers, aspect 20 : 1 to
///   1000 : 1, in every rotation), n = 1…16: max **1.3340** (right-angled 1000 : 1 at
///   n = 13); the ideal limit is 4/3 as the sliver gets thinner (1.3321 for a 20 : 1
///   right triangle at n = 2), and again the fixed point adds a little. Over n = 1…64
///   the max is **1.3534** (at n = 61). Isosceles slivers (apex over the middle of the
///   long edge) stay near 1.0.
///
/// # Panics
/// If `n` is 0.
pub fn diameter_ratio(pattern: &Pattern, corners: [[f64; 3]; 3], n: u32) -> f64 {
    assert!(n > 0, "diameter_ratio needs n >= 1");
    let patch_diameter = diameter(&corners);
    let place = |b: &[f64; 3]| -> [f64; 3] {
        std::array::from_fn(|k| b[0] * corners[0][k] + b[1] * corners[1][k] + b[2] * corners[2][k])
    };
    let positions: Vec<[f64; 3]> = pattern.vertices.iter().map(place).collect();
    let largest = pattern
        .triangles
        .iter()
        .map(|t| diameter(&[positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize]]))
        .fold(0.0, f64::max);
    largest / (patch_diameter / f64::from(n))
}

/// Longest edge of a triangle.
fn diameter(t: &[[f64; 3]; 3]) -> f64 {
    let dist = |a: &[f64; 3], b: &[f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    dist(&t[0], &t[1]).max(dist(&t[1], &t[2])).max(dist(&t[2], &t[0]))
}

/// Applies culling, clamping and `equal_spacing` rounding. `None` means the patch is culled.
fn round_levels(inner: f32, outer: [f32; 3]) -> Option<(u32, [u32; 3])> {
    if outer.iter().any(|&o| o.is_nan() || o <= 0.0) {
        return None;
    }
    let round = |level: f32| -> u32 {
        // The reference's IEEE-754R min/max return the non-NaN operand, so NaN clamps to 1.
        let clamped = if level.is_nan() { 1.0 } else { level.clamp(1.0, MAX_LEVEL as f32) };
        clamped.ceil() as u32
    };
    Some((round(inner), outer.map(round)))
}

/// `round(2¹⁶ / n)`: the 16.16 length of one of `n` equal segments, as the reference
/// tabulates it for `n = 1..=64` (no ties occur, so the rounding direction of halves is moot).
fn segment_length(n: u32) -> u32 {
    (FX_ONE + n / 2) / n
}

/// 16.16 position of point `p` (0 ..= n) on an edge split into `n` equal segments.
///
/// Points up to the middle are multiples of the rounded segment length; the other half
/// is the mirror image, so that the two patches sharing an edge agree exactly however
/// they walk it; an even level's midpoint is exactly ½.
fn edge_point(n: u32, p: u32) -> u32 {
    debug_assert!(p <= n);
    match (2 * p).cmp(&n) {
        std::cmp::Ordering::Equal => FX_HALF,
        std::cmp::Ordering::Less => p * segment_length(n),
        std::cmp::Ordering::Greater => FX_ONE - (n - p) * segment_length(n),
    }
}

/// Where the `i`-th split (0 ..= 32) lands on a half edge of the largest level, in the
/// ruler-function order the transition stitch uses to interleave its two rows.
///
/// Split 0 is position 0 and split 1 is position 32 (never reached, as a half edge has at
/// most 32 segments). For `i ≥ 2` write `i − 1 = 2ᵃ·(2b + 1)`; the split lands at
/// `2^(4−a) + b`: first the quarter point 16, then 8, 17, 4, 18, 9, 19, 2, …, 31.
fn ruler_position(i: u32) -> u32 {
    match i {
        0 => 0,
        1 => 32,
        _ => {
            let j = i - 1;
            let a = j.trailing_zeros();
            let b = (j >> a) >> 1;
            (1 << (4 - a)) + b
        }
    }
}

/// Builder for the points and the triangle list.
struct Mesh {
    /// Fixed-point (u, v); w = 1 − u − v.
    points: Vec<(u32, u32)>,
    triangles: Vec<[u32; 3]>,
}

impl Mesh {
    fn point(&mut self, u: u32, v: u32) -> u32 {
        debug_assert!(u + v <= FX_ONE);
        self.points.push((u, v));
        (self.points.len() - 1) as u32
    }

    /// Stores a triangle given in the reference's "clockwise" (positive determinant) order.
    fn triangle(&mut self, a: u32, b: u32, c: u32) {
        self.triangles.push([a, b, c]);
    }
}

/// The point indices along one side of a ring, in walking order, both ends included (the
/// last one is the first point of the next side). A degenerate ring, the centre point of
/// an even inner level, has one point on every side.
type Row = Vec<u32>;

/// Tessellates with already rounded levels.
fn tessellate(inner: u32, outer: [u32; 3]) -> Pattern {
    let mut mesh = Mesh { points: Vec::new(), triangles: Vec::new() };

    if inner == 1 && outer == [1, 1, 1] {
        let v1 = mesh.point(0, FX_ONE); // (0, 1, 0)
        let w1 = mesh.point(0, 0); // (0, 0, 1)
        let u1 = mesh.point(FX_ONE, 0); // (1, 0, 0)
        mesh.triangle(v1, w1, u1);
        return finish(mesh);
    }
    // Inner level 1 next to a finer edge behaves exactly as inner level 2.
    let inner = inner.max(2);

    // rings[0] is the outer ring, rings[k] the k-th inner ring (the last may be the centre).
    let mut rings: Vec<[Row; 3]> = vec![outer_ring(&mut mesh, outer)];
    // Inner rings r = 1, 2, … while the ring still has a point strictly inside each side.
    for r in 1..inner.div_ceil(2) {
        rings.push(inner_ring(&mut mesh, inner, r));
    }
    if inner % 2 == 0 {
        let centre = mesh.point(FX_THIRD, FX_THIRD);
        rings.push(std::array::from_fn(|_| vec![centre]));
    }

    for (k, pair) in rings.windows(2).enumerate() {
        for side in 0..3 {
            let (out_row, in_row) = (&pair[0][side], &pair[1][side]);
            if k == 0 {
                stitch_transition(&mut mesh, out_row, in_row, outer[side], inner);
            } else {
                stitch_regular(&mut mesh, out_row, in_row);
            }
        }
    }
    if inner % 2 == 1 {
        // The innermost ring of an odd level is a triangle of three points.
        let last = rings.last().expect("an odd inner level >= 3 has an inner ring");
        mesh.triangle(last[0][0], last[1][0], last[2][0]);
    }
    finish(mesh)
}

/// Emits the outer ring's points and returns its three sides.
fn outer_ring(mesh: &mut Mesh, outer: [u32; 3]) -> [Row; 3] {
    let mut starts = [0u32; 3];
    for (side, &m) in outer.iter().enumerate() {
        starts[side] = mesh.points.len() as u32;
        for k in 0..m {
            match side {
                // u = 0: v falls from 1.
                0 => mesh.point(0, edge_point(m, m - k)),
                // v = 0: u rises from 0 (w falls from 1).
                1 => mesh.point(edge_point(m, k), 0),
                // w = 0: u falls from 1.
                _ => {
                    let u = edge_point(m, m - k);
                    mesh.point(u, FX_ONE - u)
                }
            };
        }
    }
    std::array::from_fn(|side| {
        let mut row: Row = (starts[side]..starts[side] + outer[side]).collect();
        row.push(starts[(side + 1) % 3]);
        row
    })
}

/// Emits inner ring `r` (1 ≤ r < ⌈inner/2⌉) of an inner level `inner` and returns its sides.
fn inner_ring(mesh: &mut Mesh, inner: u32, r: u32) -> [Row; 3] {
    // The ring uses the inner edge's 1-D points r ..= inner − r.
    let (first, last) = (r, inner - r);
    // Points per side, the far corner excluded (it starts the next side).
    let count = last - first;
    // Distance of the ring from the patch edges, in the coordinate that is constant on
    // a side: the 1-D position of point r scaled by (truncated) 2/3, rounded.
    let offset =
        (u64::from(edge_point(inner, r)) * u64::from(FX_TWO_THIRDS) + u64::from(FX_HALF)) >> FRAC_BITS;
    let offset = offset as u32;
    // Moving inward by `offset` in one coordinate shifts the other two by half of it.
    let shift = offset.div_ceil(2);
    let start = mesh.points.len() as u32;
    for side in 0..3 {
        for k in 0..count {
            match side {
                0 => mesh.point(offset, edge_point(inner, last - k) - shift),
                1 => mesh.point(edge_point(inner, first + k) - shift, offset),
                _ => {
                    let u = edge_point(inner, last - k) - shift;
                    mesh.point(u, FX_ONE - u - offset)
                }
            };
        }
    }
    std::array::from_fn(|side| {
        let side = side as u32;
        let mut row: Row = (start + side * count..start + (side + 1) * count).collect();
        row.push(start + ((side + 1) % 3) * count);
        row
    })
}

/// Stitches an outer side (`outer_level` segments) to the matching side of the first
/// inner ring (`inner_level − 2` segments).
///
/// Each half of the strip advances along the outer row `⌊outer/2⌋` times and along the
/// inner row `⌊inner/2⌋ − 1` times, interleaved in ruler-function order; the first half
/// walks the split order forwards (the inner row moving first at each step), the second
/// half walks it backwards (the outer row first), and odd levels put one more segment
/// between the halves.
fn stitch_transition(mesh: &mut Mesh, out_row: &[u32], in_row: &[u32], outer_level: u32, inner_level: u32) {
    let out_half = outer_level / 2;
    let in_half = inner_level / 2;
    let (mut o, mut i) = (0usize, 0usize);
    // A triangle on the next outer segment, with its apex on the current inner point.
    let advance_out = |mesh: &mut Mesh, o: &mut usize, i: usize| {
        mesh.triangle(out_row[*o], out_row[*o + 1], in_row[i]);
        *o += 1;
    };
    // A triangle on the next inner segment, with its apex on the current outer point.
    let advance_in = |mesh: &mut Mesh, o: usize, i: &mut usize| {
        mesh.triangle(in_row[*i], out_row[o], in_row[*i + 1]);
        *i += 1;
    };

    // First half. Split 0 (position 0) only ever advances the outer row.
    if out_half > 0 {
        advance_out(mesh, &mut o, i);
    }
    for split in 1..=32 {
        let pos = ruler_position(split);
        if pos < in_half {
            advance_in(mesh, o, &mut i);
        }
        if pos < out_half {
            advance_out(mesh, &mut o, i);
        }
    }

    // Middle: the extra segment(s) of odd levels.
    match (outer_level % 2 == 1, inner_level % 2 == 1) {
        (true, true) => {
            // A quad, split along (inner[i+1], outer[o]).
            mesh.triangle(in_row[i], out_row[o], in_row[i + 1]);
            mesh.triangle(in_row[i + 1], out_row[o], out_row[o + 1]);
            i += 1;
            o += 1;
        }
        (true, false) => {
            mesh.triangle(in_row[i], out_row[o], out_row[o + 1]);
            o += 1;
        }
        (false, true) => {
            mesh.triangle(in_row[i], out_row[o], in_row[i + 1]);
            i += 1;
        }
        (false, false) => {}
    }

    // Second half: the same splits in reverse, outer row first at each step.
    for split in (1..=32).rev() {
        let pos = ruler_position(split);
        if pos < out_half {
            advance_out(mesh, &mut o, i);
        }
        if pos < in_half {
            advance_in(mesh, o, &mut i);
        }
    }
    if out_half > 0 {
        advance_out(mesh, &mut o, i);
    }
    debug_assert_eq!((o, i), (out_row.len() - 1, in_row.len() - 1));
}

/// Stitches two consecutive inner rings' sides: the outer row has two more points than
/// the inner one. A corner triangle at each end, and in between one quad per inner
/// segment, its diagonal running from the outer row's earlier point to the inner row's
/// later point in the first half and the other way in the second half.
fn stitch_regular(mesh: &mut Mesh, out_row: &[u32], in_row: &[u32]) {
    let n = in_row.len();
    debug_assert_eq!(out_row.len(), n + 2);
    mesh.triangle(out_row[0], out_row[1], in_row[0]);
    for j in 0..n - 1 {
        let (o, o_next, i, i_next) = (out_row[j + 1], out_row[j + 2], in_row[j], in_row[j + 1]);
        if j < n / 2 {
            mesh.triangle(o, i_next, i);
            mesh.triangle(o, o_next, i_next);
        } else {
            mesh.triangle(i, o, o_next);
            mesh.triangle(i, o_next, i_next);
        }
    }
    mesh.triangle(out_row[n], out_row[n + 1], in_row[n - 1]);
}

/// Converts the fixed-point points to `gl_TessCoord` values.
fn finish(mesh: Mesh) -> Pattern {
    let scale = f64::from(FX_ONE);
    let vertices = mesh
        .points
        .iter()
        .map(|&(u, v)| [f64::from(u) / scale, f64::from(v) / scale, f64::from(FX_ONE - u - v) / scale])
        .collect();
    Pattern { vertices, triangles: mesh.triangles }
}

#[cfg(test)]
mod tests;
