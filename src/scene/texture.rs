//! Textures on the CPU: PNG loading, the mip chain, a twin of Vulkan's trilinear sampling, and
//! the two ways of bounding a parameter texture over a region that the error estimator needs.
//!
//! This module owns everything between a PNG file and the texel arrays the renderer uploads:
//!
//! - [`Texture`]: the image and its full mip chain, as albedo (sRGB colour, RGBA8) or as a
//!   parameter (one linear UNORM channel, R8) such as shininess or roughness;
//! - [`Texture::sample_parameter`] and [`Texture::sample_albedo`]: what a Vulkan sampler with
//!   REPEAT addressing and LINEAR mag, min and mipmap filtering returns, computed as the Vulkan
//!   specification writes it ("Texel Filtering", "Level-of-Detail Operation");
//! - [`MinMaxPyramid`]: per-block minima and maxima of a parameter texture, and a conservative
//!   range of every value the sampler can return over a box of texture coordinates. Its GPU
//!   half is `glsl/include/texture_bounds.glsl`, operation for operation;
//! - [`PowerSat`]: the paper's estimate of the same range (seed 003 Sec. 4.2, normalized
//!   power-weighted filtering over summed-area tables), which is not conservative.
//!
//! It knows nothing of Vulkan objects; the renderer uploads [`MipLevel`]s as they are.

use std::path::{Path, PathBuf};

use glam::{IVec2, Vec2, Vec3};

/// The largest width or height a texture may have, in texels.
pub const MAX_TEXTURE_SIZE: u32 = 16384;

/// The slack [`MinMaxPyramid::query`] adds on each side of its range, half of one 8-bit UNORM
/// step (1/510): room for the GPU's fixed-point filter weights, whose sum may differ from one.
pub const PYRAMID_SLACK: f32 = 0.001_960_784_4;

/// Reach of one bilinear lookup at mip level j, in texels of level j, from the sample point to
/// the far edge of the farthest texel it reads (1.5), plus 1/16 texel for the GPU's fixed-point
/// texel coordinates.
const PYRAMID_REACH: f32 = 1.5625;

/// Extra reach per unit of |uv| per texel of width, 2⁻²⁰: covers the rounding of `uv·size − 0.5`
/// in f32 (at most 2⁻²⁴ relative), here and in the sampler, with room to spare.
const PYRAMID_MAGNITUDE_MARGIN: f32 = 9.536_743_164_062_5e-7;

/// How a texture's texels are interpreted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureUsage {
    /// sRGB-encoded colour (with alpha), sampled as a `*_SRGB` format: decoded to linear
    /// before filtering.
    Albedo,
    /// One linear channel with values in [0, 1] (the image's luma), sampled as `R8_UNORM`.
    /// Width and height must be powers of two.
    Parameter,
}

impl TextureUsage {
    /// Bytes per texel of this usage's texel format: 4 (RGBA8) for albedo, 1 (R8) for a parameter.
    pub fn bytes_per_texel(self) -> usize {
        match self {
            TextureUsage::Albedo => 4,
            TextureUsage::Parameter => 1,
        }
    }
}

/// One mip level, texels in rows from the top-left corner, tightly packed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MipLevel {
    pub width: u32,
    pub height: u32,
    /// Albedo: RGBA8 sRGB-encoded, 4 bytes per texel. Parameter: R8 UNORM, 1 byte per texel.
    /// [`MinMaxPyramid`] levels: (min, max) UNORM, 2 bytes per texel.
    pub texels: Vec<u8>,
}

/// A texture with its full mip chain.
///
/// Level `k + 1` has size `max(w_k / 2, 1) × max(h_k / 2, 1)` (rounded down), down to 1×1.
/// Each of its texels is the area-weighted average of the level-`k` texels its footprint
/// covers: the footprint of texel `i` is `[i·w_k/w_{k+1}, (i+1)·w_k/w_{k+1})` in level-`k`
/// texels, and likewise in y. For even sizes this is the 2×2 box filter; a dimension that is
/// already 1 keeps its one texel; for an odd size the texel straddling two footprints is shared
/// between them, so no texel is dropped. Albedo levels are averaged in linear space (sRGB
/// decoded, averaged, re-encoded; alpha averaged as is), parameter levels on the 8-bit values;
/// both round to the nearest 8-bit value.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// The file the texture was loaded from (or the name given to [`Texture::from_level0`]).
    pub path: PathBuf,
    pub usage: TextureUsage,
    /// `levels[0]` is the image; the chain goes down to 1×1.
    pub levels: Vec<MipLevel>,
}

/// Why a texture could not be loaded or built. `Display` starts with the path of the file.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    /// The file could not be read.
    #[error("{}: cannot read file: {error}", path.display())]
    Io { path: PathBuf, error: std::io::Error },
    /// The file is not a PNG image the `image` crate can decode.
    #[error("{}: cannot decode as PNG: {error}", path.display())]
    Decode { path: PathBuf, error: image::ImageError },
    /// A parameter texture whose width or height is not a power of two.
    #[error(
        "{}: {width}×{height} is not a power of two in width and height (parameter textures must be)",
        path.display()
    )]
    NotPowerOfTwo { path: PathBuf, width: u32, height: u32 },
    /// Wider or taller than [`MAX_TEXTURE_SIZE`].
    #[error("{}: {width}×{height} is too large (at most {MAX_TEXTURE_SIZE} texels a side)", path.display())]
    TooLarge { path: PathBuf, width: u32, height: u32 },
    /// Zero width or height.
    #[error("{}: the image is empty ({width}×{height})", path.display())]
    Empty { path: PathBuf, width: u32, height: u32 },
    /// [`Texture::from_level0`] was given a texel array of the wrong length.
    #[error("{}: {actual} bytes of texels given, {expected} expected", path.display())]
    TexelCount { path: PathBuf, expected: usize, actual: usize },
}

impl Texture {
    /// Reads the PNG file at `path` (any colour type and bit depth) as a texture of `usage`:
    /// albedo takes the image as RGBA8, a parameter takes its luma as 8 bits. Builds the chain.
    pub fn load(path: &Path, usage: TextureUsage) -> Result<Texture, TextureError> {
        let bytes =
            std::fs::read(path).map_err(|error| TextureError::Io { path: path.to_path_buf(), error })?;
        let image = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
            .map_err(|error| TextureError::Decode { path: path.to_path_buf(), error })?;
        let (width, height) = (image.width(), image.height());
        let texels = match usage {
            TextureUsage::Albedo => image.to_rgba8().into_raw(),
            TextureUsage::Parameter => image.to_luma8().into_raw(),
        };
        Texture::from_level0(path.to_path_buf(), usage, width, height, texels)
    }

    /// A texture from its level-0 texels (in the layout of [`MipLevel::texels`] for `usage`),
    /// with the mip chain built from them. `path` only names the texture in errors.
    pub fn from_level0(
        path: PathBuf,
        usage: TextureUsage,
        width: u32,
        height: u32,
        texels: Vec<u8>,
    ) -> Result<Texture, TextureError> {
        if width == 0 || height == 0 {
            return Err(TextureError::Empty { path, width, height });
        }
        if width > MAX_TEXTURE_SIZE || height > MAX_TEXTURE_SIZE {
            return Err(TextureError::TooLarge { path, width, height });
        }
        if usage == TextureUsage::Parameter && !(width.is_power_of_two() && height.is_power_of_two()) {
            return Err(TextureError::NotPowerOfTwo { path, width, height });
        }
        let expected = width as usize * height as usize * usage.bytes_per_texel();
        if texels.len() != expected {
            return Err(TextureError::TexelCount { path, expected, actual: texels.len() });
        }
        let mut levels = vec![MipLevel { width, height, texels }];
        while let Some(last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
            let next = downsample(usage, last);
            levels.push(next);
        }
        Ok(Texture { path, usage, levels })
    }

    /// Width of level 0, in texels.
    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    /// Height of level 0, in texels.
    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// What `textureLod(sampler, uv, lod)` returns for this parameter texture (`R8_UNORM`,
    /// REPEAT addressing, LINEAR filters and mipmap mode), in [0, 1]. `lod` is clamped to
    /// `[0, levels − 1]`; a NaN `lod` counts as 0 and a non-finite `uv` as (0, 0).
    ///
    /// # Panics
    /// If the texture is not a [`TextureUsage::Parameter`] texture.
    pub fn sample_parameter(&self, uv: Vec2, lod: f32) -> f32 {
        assert_eq!(self.usage, TextureUsage::Parameter, "{}: not a parameter texture", self.path.display());
        self.trilinear(uv, lod, |level, index| level.texels[index] as f32 / 255.0)
    }

    /// What `textureLod(sampler, uv, lod).rgb` returns for this albedo texture (`R8G8B8A8_SRGB`,
    /// REPEAT addressing, LINEAR filters and mipmap mode): linear colour, each texel decoded
    /// from sRGB before filtering. `lod` and `uv` as in [`Texture::sample_parameter`].
    ///
    /// # Panics
    /// If the texture is not a [`TextureUsage::Albedo`] texture.
    pub fn sample_albedo(&self, uv: Vec2, lod: f32) -> Vec3 {
        assert_eq!(self.usage, TextureUsage::Albedo, "{}: not an albedo texture", self.path.display());
        self.trilinear(uv, lod, |level, index| {
            let t = &level.texels[4 * index..4 * index + 3];
            Vec3::new(srgb_decode(t[0]), srgb_decode(t[1]), srgb_decode(t[2]))
        })
    }

    /// Vulkan's LINEAR mipmap mode: `d = clamp(lod, 0, q)`, levels `floor(d)` and
    /// `min(floor(d) + 1, q)`, blended as `(1 − δ)·τ_fine + δ·τ_coarse` with `δ = frac(d)`.
    fn trilinear<T>(&self, uv: Vec2, lod: f32, fetch: impl Fn(&MipLevel, usize) -> T) -> T
    where
        T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
    {
        let top = (self.levels.len() - 1) as f32;
        let lod = if lod.is_nan() { 0.0 } else { lod.clamp(0.0, top) };
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        let fine = lod.floor();
        let coarse = (fine + 1.0).min(top);
        let delta = lod - fine;
        let a = bilinear(&self.levels[fine as usize], uv, &fetch);
        let b = bilinear(&self.levels[coarse as usize], uv, &fetch);
        a * (1.0 - delta) + b * delta
    }
}

/// Vulkan's LINEAR filter with REPEAT addressing on one level: `i₀ = floor(u·w − 0.5)`,
/// `α = frac(u·w − 0.5)`, texels `i₀` and `i₀ + 1` wrapped, likewise in v, weighted
/// `(1−α)(1−β), α(1−β), (1−α)β, αβ`.
fn bilinear<T>(level: &MipLevel, uv: Vec2, fetch: &impl Fn(&MipLevel, usize) -> T) -> T
where
    T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    let t = uv * Vec2::new(level.width as f32, level.height as f32) - 0.5;
    let base = t.floor();
    let frac = t - base;
    let wrap = |i: i64, n: u32| i.rem_euclid(n as i64) as usize;
    let (ix, iy) = (base.x as i64, base.y as i64);
    let (x0, x1) = (wrap(ix, level.width), wrap(ix + 1, level.width));
    let (y0, y1) = (wrap(iy, level.height), wrap(iy + 1, level.height));
    let row0 = y0 * level.width as usize;
    let row1 = y1 * level.width as usize;
    let (a, b) = (frac.x, frac.y);
    fetch(level, row0 + x0) * ((1.0 - a) * (1.0 - b))
        + fetch(level, row0 + x1) * (a * (1.0 - b))
        + fetch(level, row1 + x0) * ((1.0 - a) * b)
        + fetch(level, row1 + x1) * (a * b)
}

/// The sRGB electro-optical transfer function of an 8-bit value, as Vulkan decodes `*_SRGB`.
fn srgb_decode(c: u8) -> f32 {
    srgb_to_linear(c as f64 / 255.0) as f32
}

fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(l: f64) -> f64 {
    if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

fn to_u8(v: f64) -> u8 {
    (v + 0.5).floor().clamp(0.0, 255.0) as u8
}

/// The level-`k` texels under the footprint of level-`k+1` texel `i` (see [`Texture`]), with
/// weights that sum to one.
fn footprint(source: u32, target: u32, i: u32) -> Vec<(usize, f64)> {
    let ratio = source as f64 / target as f64;
    let (a, b) = (i as f64 * ratio, (i + 1) as f64 * ratio);
    (a.floor() as u32..(b.ceil() as u32).min(source))
        .filter_map(|k| {
            let overlap = b.min(k as f64 + 1.0) - a.max(k as f64);
            (overlap > 0.0).then_some((k as usize, overlap / ratio))
        })
        .collect()
}

fn downsample(usage: TextureUsage, source: &MipLevel) -> MipLevel {
    let (width, height) = ((source.width / 2).max(1), (source.height / 2).max(1));
    let channels = usage.bytes_per_texel();
    let taps_x: Vec<_> = (0..width).map(|i| footprint(source.width, width, i)).collect();
    let mut texels = Vec::with_capacity(width as usize * height as usize * channels);
    for j in 0..height {
        let taps_y = footprint(source.height, height, j);
        for tx in &taps_x {
            for c in 0..channels {
                let mut sum = 0.0;
                for &(y, wy) in &taps_y {
                    for &(x, wx) in tx {
                        let v = source.texels[(y * source.width as usize + x) * channels + c];
                        let v = match (usage, c) {
                            (TextureUsage::Albedo, 0..=2) => srgb_to_linear(v as f64 / 255.0),
                            (TextureUsage::Albedo, _) => v as f64 / 255.0,
                            (TextureUsage::Parameter, _) => v as f64,
                        };
                        sum += wx * wy * v;
                    }
                }
                texels.push(match (usage, c) {
                    (TextureUsage::Albedo, 0..=2) => to_u8(255.0 * linear_to_srgb(sum)),
                    (TextureUsage::Albedo, _) => to_u8(255.0 * sum),
                    (TextureUsage::Parameter, _) => to_u8(sum),
                });
            }
        }
    }
    MipLevel { width, height, texels }
}

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
    /// A bilinear lookup at level j reads texels at most 1.5·2^j level-0 texels from `uv·size`;
    /// the coarsest level read is `ceil(lod_bound)` (clamped to the chain), so the box, widened
    /// by that reach (plus a margin for rounding), covers every level-0 block the sampler can
    /// touch. The query reads 3×3 texels of the finest pyramid level whose texels are at least
    /// half that widened extent, or the top 1×1 level (the whole texture's range) when there is
    /// none, or when an input is NaN or infinite (`lod_bound = +∞` is allowed and means any lod).
    /// The box may be given with its corners in either order.
    ///
    /// `glsl/include/texture_bounds.glsl` is the same computation in the same f32 operations.
    /// The GPU's own LOD computation is not modelled: `lod_bound` must already cover it.
    pub fn query(&self, uv_min: Vec2, uv_max: Vec2, lod_bound: f32) -> (f32, f32) {
        let top = self.levels.len() as i32 - 1;
        let lo = uv_min.min(uv_max);
        let hi = uv_min.max(uv_max);
        let size = Vec2::new(self.levels[0].width as f32, self.levels[0].height as f32);
        let mut level = top;
        let mut first = IVec2::ZERO;
        let mut last = IVec2::ZERO;
        if lo.is_finite() && hi.is_finite() && !lod_bound.is_nan() {
            let lod = lod_bound.max(0.0).min(top as f32);
            let reach = PYRAMID_REACH * (1 << (lod.ceil() as i32)) as f32;
            let pad = lo.abs().max(hi.abs()) * size * PYRAMID_MAGNITUDE_MARGIN + reach;
            let shift = lo.floor();
            let x0 = (lo - shift) * size - pad;
            let x1 = ((hi - shift) * size + pad).min(x0 + 2.0 * size);
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
        let mask = IVec2::new(texels.width as i32 - 1, texels.height as i32 - 1);
        let mut range = (1.0f32, 0.0f32);
        for dy in 0..3 {
            for dx in 0..3 {
                let t = (first + IVec2::new(dx, dy)).min(last) & mask;
                let index = 2 * (t.y as usize * texels.width as usize + t.x as usize);
                range.0 = range.0.min(texels.texels[index] as f32 / 255.0);
                range.1 = range.1.max(texels.texels[index + 1] as f32 / 255.0);
            }
        }
        ((range.0 - PYRAMID_SLACK).max(0.0), (range.1 + PYRAMID_SLACK).min(1.0))
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
        if !(lo.is_finite() && hi.is_finite()) {
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

#[cfg(test)]
mod tests {
    use super::*;
}
