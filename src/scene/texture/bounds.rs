//! The two ways of bounding a parameter texture over a region that the error estimator needs:
//!
//! - [`MinMaxPyramid`]: per-block minima and maxima of a parameter texture, and a conservative
//!   range of every value the sampler can return over a box of texture coordinates. Its GPU
//!   twin is `glsl/include/texture_bounds.glsl`, operation for operation; `tests/textures.rs`
//!   and the unit tests in `texture/tests.rs` check it bounds every sample;
//! - [`PowerSat`]: the paper's estimate of the same range (seed 003 Sec. 4.2, normalized
//!   power-weighted filtering over summed-area tables), which is not conservative.

use glam::{IVec2, Vec2};

use super::image::{MipLevel, Texture, TextureUsage};

/// One 8-bit UNORM step, 1/255 as an f32. [`MinMaxPyramid::query`] and its GPU twin multiply by
/// it (a product is correctly rounded on the GPU, a quotient need not be); `c · step` may differ
/// from `c / 255.0` in the last bit, far inside [`PYRAMID_SLACK`].
pub const PYRAMID_UNORM_STEP: f32 = 0.003_921_569;

/// The slack [`MinMaxPyramid::query`] adds on each side of its range, half of one 8-bit UNORM
/// step (1/510): room for the GPU's fixed-point filter weights, whose sum may differ from one.
pub const PYRAMID_SLACK: f32 = 0.001_960_784_4;

/// How far [`MinMaxPyramid::query`] widens the box for a lookup at mip level j, in texels of
/// level j: 1/2 (every texel a bilinear lookup reads overlaps the lookup point ± 1/2 texel), plus
/// 1/16 texel for the GPU's fixed-point texel coordinates.
const PYRAMID_REACH: f32 = 0.5625;

/// Texel coordinates `|uv|·size` from this far (2²⁰ texels) give the whole range: samplers
/// address texels in fixed point of limited range (lavapipe in Mesa 22.3 reads texels from
/// elsewhere beyond 2²³), and f32 uv no longer resolves a fraction of a texel.
const PYRAMID_FAR_TEXELS: f32 = 1_048_576.0;

/// Extra reach per unit of |uv| per texel of width, 2⁻²⁰: covers the rounding of `uv·size − 0.5`
/// in f32 (at most 2⁻²⁴ relative), here and in the sampler, with room to spare.
const PYRAMID_MAGNITUDE_MARGIN: f32 = 1.0 / 1_048_576.0;

/// Per-texel (min, max) of a parameter texture's level-0 texels over aligned 2^k×2^k blocks:
/// level `k` texel `(i, j)` holds the min and max of level-0 texels `[i·2^k, (i+1)·2^k) ×
/// [j·2^k, (j+1)·2^k)` (clipped to the image). Levels have the sizes of the texture's mip
/// chain. Uploaded as an `R8G8_UNORM` image with one mip level per `k`.
///
/// Every texel of the texture's mip level `k` is a rounded average of the level-0 texels of its
/// block, so it lies within that block's (min, max): this is what makes [`MinMaxPyramid::query`]
/// conservative for trilinear sampling.
#[derive(Debug, Clone, PartialEq)]
pub struct MinMaxPyramid {
    /// Texels: 2 bytes (min, max) per texel.
    pub levels: Vec<MipLevel>,
}

impl MinMaxPyramid {
    /// The pyramid of a parameter texture.
    ///
    /// # Panics
    /// If the texture is not a [`TextureUsage::Parameter`] texture.
    pub fn new(texture: &Texture) -> MinMaxPyramid {
        assert_eq!(
            texture.usage,
            TextureUsage::Parameter,
            "{}: not a parameter texture",
            texture.path.display()
        );
        let base = &texture.levels[0];
        let first = MipLevel {
            width: base.width,
            height: base.height,
            texels: base.texels.iter().flat_map(|&v| [v, v]).collect(),
        };
        let mut levels = vec![first];
        while let Some(last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
            let (width, height) = ((last.width / 2).max(1), (last.height / 2).max(1));
            let mut texels = Vec::with_capacity(2 * width as usize * height as usize);
            for j in 0..height {
                for i in 0..width {
                    let (mut lo, mut hi) = (u8::MAX, u8::MIN);
                    for y in [2 * j, (2 * j + 1).min(last.height - 1)] {
                        for x in [2 * i, (2 * i + 1).min(last.width - 1)] {
                            let index = 2 * (y as usize * last.width as usize + x as usize);
                            lo = lo.min(last.texels[index]);
                            hi = hi.max(last.texels[index + 1]);
                        }
                    }
                    texels.extend([lo, hi]);
                }
            }
            levels.push(MipLevel { width, height, texels });
        }
        MinMaxPyramid { levels }
    }

    /// A conservative range `(lo, hi)` in [0, 1] of every value `texture.sample_parameter(uv,
    /// lod)` can return for `uv` in the box `[uv_min, uv_max]` (any real uv: REPEAT) and any
    /// `lod ≤ lod_bound`, widened by [`PYRAMID_SLACK`] on each side (within [0, 1]).
    ///
    /// A bilinear lookup at level j at `a = u·w_j` reads the level-j texels `floor(a − 0.5)` and
    /// `floor(a − 0.5) + 1`, up to 1.5·2^j level-0 texels from `u·w_0`; both overlap
    /// `[a − 0.5, a + 0.5]`. A level-j texel is a whole 2^j×2^j block of level 0, and pyramid
    /// blocks nest, so the pyramid blocks that overlap the box widened by 0.5·2^j level-0
    /// texels contain every texel read, the far ones whole. The coarsest level read is
    /// `ceil(lod_bound)` (clamped to the chain; a lookup at an integer lod gives the next level
    /// weight zero). The widening adds margins for rounding (see the constants).
    ///
    /// The query reads 3×3 texels of the finest pyramid level whose texels are at least half
    /// the widened box's larger extent, or the top 1×1 level (the whole texture's range) when
    /// there is none, when a corner lies 2²⁰ texels or more from the origin, or when an input is
    /// NaN or infinite (`lod_bound = +∞` is allowed and means any lod). The box may be given
    /// with its corners in either order.
    ///
    /// `glsl/include/texture_bounds.glsl` is the same computation in the same f32 operations.
    /// The GPU's own LOD computation is not modelled: `lod_bound` must already cover it.
    pub fn query(&self, uv_min: Vec2, uv_max: Vec2, lod_bound: f32) -> (f32, f32) {
        let base = (self.levels[0].width, self.levels[0].height);
        // The chain is full: its top level is log2 of the larger side (the GPU twin's findMSB).
        let top = 31 - base.0.max(base.1).leading_zeros() as i32;
        let lo = uv_min.min(uv_max);
        let hi = uv_min.max(uv_max);
        let size = Vec2::new(base.0 as f32, base.1 as f32);
        let mut level = top;
        let mut first = IVec2::ZERO;
        let mut last = IVec2::ZERO;
        let magnitude = lo.abs().max(hi.abs()) * size;
        let near = magnitude.max_element() < PYRAMID_FAR_TEXELS;
        if uv_min.is_finite() && uv_max.is_finite() && !lod_bound.is_nan() && near {
            let lod = lod_bound.max(0.0).min(top as f32);
            let reach = PYRAMID_REACH * (1 << (lod.ceil() as i32)) as f32;
            let pad = magnitude * PYRAMID_MAGNITUDE_MARGIN + reach;
            let shift = lo.floor();
            let x0 = (lo - shift) * size - pad;
            let x1 = (hi - shift) * size + pad;
            let extent = (x1 - x0).max_element();
            let mut span = 2.0;
            level = 0;
            while level < top && extent > span {
                span *= 2.0;
                level += 1;
            }
            if level < top {
                let scale = 1.0 / (1 << level) as f32;
                first = (x0 * scale).floor().as_ivec2();
                last = (x1 * scale).floor().as_ivec2();
            }
        }
        let texels = &self.levels[level as usize];
        let mask = (IVec2::new(base.0 as i32, base.1 as i32) >> level).max(IVec2::ONE) - 1;
        let mut range = (u8::MAX, u8::MIN);
        for dy in 0..3 {
            for dx in 0..3 {
                let t = (first + IVec2::new(dx, dy)).min(last) & mask;
                let index = 2 * (t.y as usize * texels.width as usize + t.x as usize);
                range.0 = range.0.min(texels.texels[index]);
                range.1 = range.1.max(texels.texels[index + 1]);
            }
        }
        (
            (range.0 as f32 * PYRAMID_UNORM_STEP - PYRAMID_SLACK).max(0.0),
            (range.1 as f32 * PYRAMID_UNORM_STEP + PYRAMID_SLACK).min(1.0),
        )
    }
}

/// The paper's estimate of a parameter texture's range over a box (seed 003 Sec. 4.2:
/// normalized power-weighted filtering [Vliet 2004] over summed-area tables):
/// `max ≈ (mean of x^p)^(1/p)` and `min ≈ (mean of x^−p)^(−1/p)` over the texels of the box.
///
/// `x` is the texel's 8-bit value plus one (the UNORM value plus 1/255), so that `x^−p` is
/// finite for black texels; one is subtracted again from the result. To keep every term in
/// (0, 1], the tables hold `(x / x_max)^p` and `(x_min / x)^p` with `x_max`, `x_min` the
/// texture's extremes. The tables are f64, `(w+1)×(h+1)` each.
///
/// Power means never exceed the maximum nor go below the minimum, so the estimate is not
/// conservative: it lies inside the true range, approaching it as `p` grows. Where a box's
/// power sum is below what the f64 table can resolve (large `p`, values far below the
/// texture's extreme), the low end of the sums the table allows is used, which keeps the
/// estimate inside the true range but far from it (even with min above max).
#[derive(Debug, Clone)]
pub struct PowerSat {
    width: u32,
    height: u32,
    p: f64,
    x_min: f64,
    x_max: f64,
    high: Vec<f64>,
    low: Vec<f64>,
}

impl PowerSat {
    /// The tables of a parameter texture's level 0 for exponent `p`.
    ///
    /// # Panics
    /// If the texture is not a [`TextureUsage::Parameter`] texture, or `p` is not positive and
    /// finite.
    pub fn new(texture: &Texture, p: f64) -> PowerSat {
        assert_eq!(
            texture.usage,
            TextureUsage::Parameter,
            "{}: not a parameter texture",
            texture.path.display()
        );
        assert!(p > 0.0 && p.is_finite(), "PowerSat exponent {p} is not positive and finite");
        let base = &texture.levels[0];
        let x = |v: u8| v as f64 + 1.0;
        let x_min = x(*base.texels.iter().min().expect("a texture has texels"));
        let x_max = x(*base.texels.iter().max().expect("a texture has texels"));
        let table = |term: &dyn Fn(f64) -> f64| {
            let stride = base.width as usize + 1;
            let mut sat = vec![0.0; stride * (base.height as usize + 1)];
            for (j, row) in base.texels.chunks(base.width as usize).enumerate() {
                let mut row_sum = 0.0;
                for (i, &v) in row.iter().enumerate() {
                    row_sum += term(x(v));
                    sat[(j + 1) * stride + i + 1] = sat[j * stride + i + 1] + row_sum;
                }
            }
            sat
        };
        let high = table(&|x| (x / x_max).powf(p));
        let low = table(&|x| (x_min / x).powf(p));
        PowerSat { width: base.width, height: base.height, p, x_min, x_max, high, low }
    }

    /// The estimated `(min, max)` UNORM value in [0, 1] over the texels whose centres
    /// `((i + 0.5)/w, (j + 0.5)/h)` lie in the box `[uv_min, uv_max]` modulo 1 (REPEAT: a box
    /// across the seam is split, a box a period wide or more takes whole rows or columns), or,
    /// along an axis where no centre does, the texel nearest the middle of the box. Corners may
    /// come in either order; a non-finite corner gives the whole texture's range.
    pub fn query(&self, uv_min: Vec2, uv_max: Vec2) -> (f32, f32) {
        let unorm = |x: f64| (x - 1.0) / 255.0;
        let (global_min, global_max) = (unorm(self.x_min), unorm(self.x_max));
        let lo = uv_min.min(uv_max);
        let hi = uv_min.max(uv_max);
        if !(uv_min.is_finite() && uv_max.is_finite()) {
            return (global_min as f32, global_max as f32);
        }
        let xs = axis_ranges(lo.x, hi.x, self.width);
        let ys = axis_ranges(lo.y, hi.y, self.height);
        let mut count = 0usize;
        let (mut high, mut low) = ((0.0, 0.0), (0.0, 0.0));
        for &(x0, x1) in xs.iter().flatten() {
            for &(y0, y1) in ys.iter().flatten() {
                count += (x1 - x0) * (y1 - y0);
                let h = self.box_sum(&self.high, x0, x1, y0, y1);
                let l = self.box_sum(&self.low, x0, x1, y0, y1);
                high = (high.0 + h.0, high.1 + h.1);
                low = (low.0 + l.0, low.1 + l.1);
            }
        }
        let n = count as f64;
        let high_mean = ((high.0 - high.1) / n).max(0.0);
        let low_mean = ((low.0 - low.1) / n).max(0.0);
        let max = unorm(self.x_max * high_mean.powf(1.0 / self.p)).clamp(global_min, global_max);
        let min = unorm(self.x_min * low_mean.powf(-1.0 / self.p)).clamp(global_min, global_max);
        (min as f32, max as f32)
    }

    /// The sum of `table` over texels `[x0, x1) × [y0, y1)`, and a bound on its rounding error:
    /// each table entry is a sum of at most `w + h` positive terms (relative error below
    /// `(w + h)·2⁻⁵³`), and three subtractions follow.
    fn box_sum(&self, table: &[f64], x0: usize, x1: usize, y0: usize, y1: usize) -> (f64, f64) {
        let stride = self.width as usize + 1;
        let at = |x: usize, y: usize| table[y * stride + x];
        let (a, b, c, d) = (at(x1, y1), at(x1, y0), at(x0, y1), at(x0, y0));
        let sum = (a - b) - (c - d);
        let error = (a + b + c + d) * (self.width + self.height + 8) as f64 * f64::EPSILON;
        (sum, error)
    }
}

/// Half-open texel ranges (at most two, after wrapping into `[0, n)`) of the texels of an axis
/// of `n` texels whose centres lie in `[lo, hi]` modulo 1, or the texel nearest the middle.
fn axis_ranges(lo: f32, hi: f32, n: u32) -> [Option<(usize, usize)>; 2] {
    let size = n as f64;
    let (lo, hi) = (lo as f64, hi as f64);
    let mut first = (lo * size - 0.5).ceil();
    let mut last = (hi * size - 0.5).floor();
    if first > last {
        first = (0.5 * (lo + hi) * size).floor();
        last = first;
    }
    let count = last - first + 1.0;
    if count >= size {
        return [Some((0, n as usize)), None];
    }
    let (n, count) = (n as usize, count as usize);
    let start = (first.rem_euclid(size) as usize).min(n - 1);
    if start + count <= n {
        [Some((start, start + count)), None]
    } else {
        [Some((start, n)), Some((0, start + count - n))]
    }
}
