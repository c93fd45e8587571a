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
use image::{ImageDecoder, ImageFormat};

/// The largest width or height a texture may have, in texels.
pub const MAX_TEXTURE_SIZE: u32 = 16384;

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
    /// The file is not a PNG, JPEG or TGA image the `image` crate can decode.
    #[error("{}: cannot decode as PNG, JPEG or TGA: {error}", path.display())]
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
    /// An image of a format the `image` crate reads but textures do not take.
    #[error("{}: is {format} image; textures must be PNG, JPEG or TGA", path.display())]
    Format { path: PathBuf, format: String },
    /// The file is shorter than any complete image of the size its header declares.
    #[error(
        "{}: declares {width}×{height} texels, which take at least {least} bytes in this format, \
         but the file has {bytes}: it is truncated or corrupt",
        path.display()
    )]
    Truncated { path: PathBuf, width: u32, height: u32, bytes: usize, least: u64 },
    /// [`Texture::from_level0`] was given a texel array of the wrong length.
    #[error("{}: {actual} bytes of texels given, {expected} expected", path.display())]
    TexelCount { path: PathBuf, expected: usize, actual: usize },
}

impl Texture {
    /// Reads the PNG, JPEG or TGA file at `path` (any colour type and bit depth) as a texture of `usage`:
    /// albedo takes the image as RGBA8, a parameter takes its luma as 8 bits. Builds the chain.
    ///
    /// The size the file's header declares is checked before anything of that size is
    /// allocated: against [`MAX_TEXTURE_SIZE`], and against the file's length (a file too short
    /// to hold an image of that size in its format is refused as truncated).
    pub fn load(path: &Path, usage: TextureUsage) -> Result<Texture, TextureError> {
        let bytes =
            super::read_file(path).map_err(|error| TextureError::Io { path: path.to_path_buf(), error })?;
        let decode_error = |error| TextureError::Decode { path: path.to_path_buf(), error };
        // The contents name the format where they can (TGA has no signature: its extension does).
        let format = image::guess_format(&bytes)
            .or_else(|e| ImageFormat::from_path(path).map_err(|_| e))
            .map_err(decode_error)?;
        if !matches!(format, ImageFormat::Png | ImageFormat::Jpeg | ImageFormat::Tga) {
            let format = format!("{} {format:?}", if format == ImageFormat::OpenExr { "an" } else { "a" });
            return Err(TextureError::Format { path: path.to_path_buf(), format });
        }
        let decoder = image::ImageReader::with_format(std::io::Cursor::new(&bytes), format)
            .into_decoder()
            .map_err(decode_error)?;
        let (width, height) = decoder.dimensions();
        check_size(path, usage, width, height)?;
        let least = least_file_size(format, &bytes, width, height);
        if (bytes.len() as u64) < least {
            return Err(TextureError::Truncated {
                path: path.to_path_buf(),
                width,
                height,
                bytes: bytes.len(),
                least,
            });
        }
        let image = image::DynamicImage::from_decoder(decoder).map_err(decode_error)?;
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
        check_size(&path, usage, width, height)?;
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

/// Checks a texture's size for `usage`: not empty, at most [`MAX_TEXTURE_SIZE`] a side, and
/// powers of two for a parameter map.
fn check_size(path: &Path, usage: TextureUsage, width: u32, height: u32) -> Result<(), TextureError> {
    let path = path.to_path_buf();
    if width == 0 || height == 0 {
        return Err(TextureError::Empty { path, width, height });
    }
    if width > MAX_TEXTURE_SIZE || height > MAX_TEXTURE_SIZE {
        return Err(TextureError::TooLarge { path, width, height });
    }
    if usage == TextureUsage::Parameter && !(width.is_power_of_two() && height.is_power_of_two()) {
        return Err(TextureError::NotPowerOfTwo { path, width, height });
    }
    Ok(())
}

/// The fewest bytes in which a complete `format` file (`bytes`, for its header) can hold a
/// `width`×`height` image: its densest encoding of its smallest texel. A shorter file is
/// truncated or corrupt, and is refused before a buffer of the declared size is allocated.
fn least_file_size(format: ImageFormat, bytes: &[u8], width: u32, height: u32) -> u64 {
    let (w, h) = (u64::from(width), u64::from(height));
    match format {
        // Rows of the header's bits per texel after a filter byte each, deflated at most
        // 1032:1 (a 258-byte match coded in two bits).
        ImageFormat::Png => (h * (1 + (w * png_bits_per_texel(bytes)).div_ceil(8))).div_ceil(1032),
        // At least one bit, the Huffman code of its DC difference, per 8×8 block of the
        // full-resolution component (arithmetic coding, which could go below, is not decoded).
        ImageFormat::Jpeg => (w.div_ceil(8) * h.div_ceil(8)).div_ceil(8),
        // The 18-byte header, then run-length packets of up to 128 texels of at least a byte.
        _ => 18 + 2 * (w * h).div_ceil(128),
    }
}

/// Bits per texel a PNG file's header declares (bit depth × channels), 1 where it has none.
fn png_bits_per_texel(bytes: &[u8]) -> u64 {
    match bytes.get(12..26) {
        Some([b'I', b'H', b'D', b'R', .., depth, colour]) => {
            let channels = match colour {
                2 => 3,
                4 => 2,
                6 => 4,
                _ => 1,
            };
            u64::from(*depth).max(1) * channels
        }
        _ => 1,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::tonemap::srgb_encode;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A fresh folder under the system temporary folder, removed when dropped.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> TempDir {
            static COUNTER: AtomicUsize = AtomicUsize::new(0);
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let dir =
                std::env::temp_dir().join(format!("multirate-texture-{}-{name}-{n}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            TempDir(dir)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    use crate::test_rng::Rng;

    fn parameter(width: u32, height: u32, texels: Vec<u8>) -> Texture {
        Texture::from_level0(PathBuf::from("test.png"), TextureUsage::Parameter, width, height, texels)
            .unwrap()
    }

    fn random_parameter(rng: &mut Rng, width: u32, height: u32) -> Texture {
        let texels = (0..width * height).map(|_| rng.byte()).collect();
        parameter(width, height, texels)
    }

    fn fixture(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/textures").join(name)
    }

    #[test]
    fn load_errors_name_the_file_and_the_problem() {
        let dir = TempDir::new("errors");
        let missing = dir.0.join("missing.png");
        let e = Texture::load(&missing, TextureUsage::Albedo).unwrap_err();
        assert!(matches!(e, TextureError::Io { .. }), "{e:?}");
        assert!(e.to_string().starts_with(&missing.display().to_string()), "{e}");
        assert!(e.to_string().contains("cannot read"), "{e}");

        let garbage = dir.0.join("garbage.png");
        std::fs::write(&garbage, b"this is not a PNG file at all").unwrap();
        let e = Texture::load(&garbage, TextureUsage::Parameter).unwrap_err();
        assert!(matches!(e, TextureError::Decode { .. }), "{e:?}");
        assert!(e.to_string().starts_with(&garbage.display().to_string()), "{e}");
        assert!(e.to_string().contains("cannot decode"), "{e}");

        let odd = dir.0.join("three_by_two.png");
        image::GrayImage::from_raw(3, 2, vec![1, 2, 3, 4, 5, 6]).unwrap().save(&odd).unwrap();
        let e = Texture::load(&odd, TextureUsage::Parameter).unwrap_err();
        assert!(matches!(e, TextureError::NotPowerOfTwo { width: 3, height: 2, .. }), "{e:?}");
        assert!(e.to_string().starts_with(&odd.display().to_string()), "{e}");
        assert!(e.to_string().contains("power of two"), "{e}");
        // Albedo textures may have any size.
        let albedo = Texture::load(&odd, TextureUsage::Albedo).unwrap();
        assert_eq!((albedo.width(), albedo.height(), albedo.levels.len()), (3, 2, 2));
    }

    #[test]
    fn from_level0_rejects_empty_huge_and_mis_sized_input() {
        let name = PathBuf::from("procedural/spots");
        let starts = |e: TextureError, what: &str| {
            let text = e.to_string();
            assert!(text.starts_with("procedural/spots: "), "{text}");
            assert!(text.contains(what), "{text}");
        };
        let e = Texture::from_level0(name.clone(), TextureUsage::Albedo, 0, 4, vec![]).unwrap_err();
        assert!(matches!(e, TextureError::Empty { .. }));
        starts(e, "empty");
        let e = Texture::from_level0(name.clone(), TextureUsage::Parameter, MAX_TEXTURE_SIZE * 2, 1, vec![])
            .unwrap_err();
        assert!(matches!(e, TextureError::TooLarge { .. }));
        starts(e, "too large");
        let e = Texture::from_level0(name.clone(), TextureUsage::Albedo, 2, 2, vec![0; 15]).unwrap_err();
        assert!(matches!(e, TextureError::TexelCount { expected: 16, actual: 15, .. }));
        starts(e, "15 bytes");
        let e = Texture::from_level0(name, TextureUsage::Parameter, 4, 6, vec![0; 24]).unwrap_err();
        starts(e, "power of two");
    }

    #[test]
    fn load_reads_any_png_layout() {
        let dir = TempDir::new("layouts");
        let grey16 = dir.0.join("grey16.png");
        let values16: Vec<u16> = vec![0, 0x1234, 0x8080, 0xffff];
        image::ImageBuffer::<image::Luma<u16>, _>::from_raw(2, 2, values16.clone())
            .unwrap()
            .save(&grey16)
            .unwrap();
        let t = Texture::load(&grey16, TextureUsage::Parameter).unwrap();
        for (&got, &v) in t.levels[0].texels.iter().zip(&values16) {
            assert!((got as f32 - v as f32 / 257.0).abs() <= 1.0, "{got} from {v}");
        }

        let rgba = dir.0.join("rgba.png");
        let texels: Vec<u8> = (0..4 * 4 * 2).map(|i| (i * 37 % 256) as u8).collect();
        image::RgbaImage::from_raw(4, 2, texels.clone()).unwrap().save(&rgba).unwrap();
        let t = Texture::load(&rgba, TextureUsage::Albedo).unwrap();
        assert_eq!(t.levels[0].texels, texels);

        let grey_alpha = dir.0.join("grey_alpha.png");
        image::GrayAlphaImage::from_raw(1, 2, vec![10, 255, 200, 128]).unwrap().save(&grey_alpha).unwrap();
        let t = Texture::load(&grey_alpha, TextureUsage::Albedo).unwrap();
        assert_eq!(t.levels[0].texels, vec![10, 10, 10, 255, 200, 200, 200, 128]);
        let t = Texture::load(&grey_alpha, TextureUsage::Parameter).unwrap();
        assert_eq!(t.levels[0].texels, vec![10, 200]);
    }

    #[test]
    fn shipped_test_textures_load() {
        let one = Texture::load(&fixture("one_texel.png"), TextureUsage::Parameter).unwrap();
        assert_eq!(one.levels.len(), 1);
        let value = one.levels[0].texels[0];
        let albedo = Texture::load(&fixture("one_texel.png"), TextureUsage::Albedo).unwrap();
        assert_eq!(albedo.levels[0].texels, vec![value, value, value, 255]);

        let checker = Texture::load(&fixture("checker_8.png"), TextureUsage::Parameter).unwrap();
        assert_eq!(checker.levels.len(), 4);
        for j in 0..8 {
            for i in 0..8 {
                let expected = if (i + j) % 2 == 0 { 0 } else { 255 };
                assert_eq!(checker.levels[0].texels[j * 8 + i], expected, "texel ({i}, {j})");
            }
        }
        // Every 2×2 block holds two black and two white texels: the mean is 127.5.
        for level in &checker.levels[1..] {
            assert!(level.texels.iter().all(|&v| v == 127 || v == 128), "{:?}", level.texels);
        }
    }

    #[test]
    fn mip_chain_halves_down_to_one_texel() {
        for (w, h) in [(1, 1), (2, 1), (1, 8), (5, 3), (7, 7), (256, 64), (3, 1), (1000, 3)] {
            let t = Texture::from_level0(
                PathBuf::from("a"),
                TextureUsage::Albedo,
                w,
                h,
                vec![9; 4 * (w * h) as usize],
            )
            .unwrap();
            let expected_levels = 1 + (w.max(h) as f64).log2().floor() as usize;
            assert_eq!(t.levels.len(), expected_levels, "{w}×{h}");
            for pair in t.levels.windows(2) {
                assert_eq!(pair[1].width, (pair[0].width / 2).max(1));
                assert_eq!(pair[1].height, (pair[0].height / 2).max(1));
            }
            for l in &t.levels {
                assert_eq!(l.texels.len(), 4 * (l.width * l.height) as usize);
            }
            let last = t.levels.last().unwrap();
            assert_eq!((last.width, last.height), (1, 1));
        }
    }

    #[test]
    fn constant_textures_stay_constant_at_every_level() {
        let mut rng = Rng(0x1234_5678_9abc_def1);
        for _ in 0..8 {
            let v = rng.byte();
            let t = parameter(32, 8, vec![v; 256]);
            assert!(t.levels.iter().all(|l| l.texels.iter().all(|&x| x == v)), "parameter {v}");
            let rgba = [rng.byte(), rng.byte(), rng.byte(), rng.byte()];
            let texels = rgba.repeat(7 * 5);
            let t = Texture::from_level0(PathBuf::from("a"), TextureUsage::Albedo, 7, 5, texels).unwrap();
            for l in &t.levels {
                assert!(l.texels.chunks(4).all(|x| x == rgba), "albedo {rgba:?}: {:?}", l.texels);
            }
        }
    }

    #[test]
    fn mip_levels_average_their_footprint() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let t = random_parameter(&mut rng, 8, 4);
        let (l0, l1) = (&t.levels[0], &t.levels[1]);
        for j in 0..2 {
            for i in 0..4 {
                let sum: u32 = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .iter()
                    .map(|(x, y)| l0.texels[(2 * j + y) * 8 + 2 * i + x] as u32)
                    .sum();
                // Round half up of sum / 4.
                assert_eq!(l1.texels[j * 4 + i] as u32, (sum + 2) / 4, "texel ({i}, {j})");
            }
        }
        // An odd width shares the middle texel instead of dropping the last one.
        let t = parameter(1, 1, vec![0]);
        assert_eq!(t.levels.len(), 1);
        let t = Texture::from_level0(
            PathBuf::from("a"),
            TextureUsage::Albedo,
            3,
            1,
            [[0, 0, 0, 255], [0, 0, 0, 255], [255, 255, 255, 255]].concat(),
        )
        .unwrap();
        let third = (255.0 * srgb_encode(1.0 / 3.0) + 0.5).floor() as u8;
        assert_eq!(t.levels[1].texels, vec![third, third, third, 255]);
        // Albedo is averaged in linear space: black and white make sRGB 188, not 128.
        let t = Texture::from_level0(
            PathBuf::from("a"),
            TextureUsage::Albedo,
            2,
            1,
            vec![0, 0, 0, 0, 255, 255, 255, 255],
        )
        .unwrap();
        let half = (255.0 * srgb_encode(0.5) + 0.5).floor() as u8;
        assert!(half > 180);
        assert_eq!(t.levels[1].texels, vec![half, half, half, 128]);
    }

    #[test]
    fn samples_at_texel_centres_and_of_one_texel_are_the_texels() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let one = parameter(1, 1, vec![77]);
        for _ in 0..20 {
            let uv = Vec2::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
            // The four bilinear weights sum to one up to rounding.
            assert!((one.sample_parameter(uv, rng.range(-2.0, 3.0)) - 77.0 / 255.0).abs() < 1e-6);
        }
        let t = random_parameter(&mut rng, 8, 4);
        for (k, level) in t.levels.iter().enumerate() {
            for j in 0..level.height {
                for i in 0..level.width {
                    let uv = Vec2::new(
                        (i as f32 + 0.5) / level.width as f32,
                        (j as f32 + 0.5) / level.height as f32,
                    );
                    let expected = level.texels[(j * level.width + i) as usize] as f32 / 255.0;
                    assert_eq!(t.sample_parameter(uv, k as f32), expected, "level {k} texel ({i}, {j})");
                }
            }
        }
        let texels: Vec<u8> = (0..4 * 6 * 3).map(|_| rng.byte()).collect();
        let albedo =
            Texture::from_level0(PathBuf::from("a"), TextureUsage::Albedo, 6, 3, texels.clone()).unwrap();
        for j in 0..3 {
            for i in 0..6 {
                let uv = Vec2::new((i as f32 + 0.5) / 6.0, (j as f32 + 0.5) / 3.0);
                let linear = albedo.sample_albedo(uv, 0.0);
                for c in 0..3 {
                    let encoded = 255.0 * srgb_encode(linear[c]);
                    let texel = texels[4 * (j * 6 + i) + c] as f32;
                    assert!(
                        (encoded - texel).abs() < 0.01,
                        "texel ({i}, {j}) channel {c}: {encoded} vs {texel}"
                    );
                }
            }
        }
    }

    #[test]
    fn sampling_repeats_across_the_seam() {
        let mut rng = Rng(0xdead_beef_cafe_f00d);
        let t = random_parameter(&mut rng, 16, 8);
        for _ in 0..200 {
            let uv = Vec2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            let lod = rng.range(-1.0, 5.0);
            let a = t.sample_parameter(uv, lod);
            let b = t.sample_parameter(uv + Vec2::new(1.0, -3.0), lod);
            assert!((a - b).abs() < 1e-4, "{uv} lod {lod}: {a} vs {b}");
        }
        // u = 0 lies halfway between the centres of the last and the first texel of a row.
        let row = 3;
        let v = (row as f32 + 0.5) / 8.0;
        let level = &t.levels[0];
        let mean = (level.texels[row * 16] as f32 + level.texels[row * 16 + 15] as f32) / 2.0 / 255.0;
        assert!((t.sample_parameter(Vec2::new(0.0, v), 0.0) - mean).abs() < 1e-6);
        assert!((t.sample_parameter(Vec2::new(1.0, v), 0.0) - mean).abs() < 1e-6);
    }

    #[test]
    fn trilinear_blends_the_two_nearest_levels() {
        let mut rng = Rng(0x0123_4567_89ab_cdef);
        let t = random_parameter(&mut rng, 32, 16);
        let top = (t.levels.len() - 1) as f32;
        for _ in 0..100 {
            let uv = Vec2::new(rng.range(-1.0, 2.0), rng.range(-1.0, 2.0));
            let fine = rng.below(t.levels.len() as u32 - 1) as f32;
            let delta = rng.f();
            let blended = t.sample_parameter(uv, fine + delta);
            let expected =
                (1.0 - delta) * t.sample_parameter(uv, fine) + delta * t.sample_parameter(uv, fine + 1.0);
            assert!((blended - expected).abs() < 1e-5, "{uv} lod {}", fine + delta);
            assert_eq!(t.sample_parameter(uv, -3.0), t.sample_parameter(uv, 0.0));
            assert_eq!(t.sample_parameter(uv, top + 2.0), t.sample_parameter(uv, top));
        }
    }

    #[test]
    fn pyramid_levels_hold_block_extremes() {
        let mut rng = Rng(0x5555_aaaa_3333_cccc);
        for (w, h) in [(1, 1), (8, 8), (16, 2), (1, 32), (64, 16)] {
            let t = random_parameter(&mut rng, w, h);
            let pyramid = MinMaxPyramid::new(&t);
            assert_eq!(pyramid.levels.len(), t.levels.len());
            for (k, level) in pyramid.levels.iter().enumerate() {
                assert_eq!((level.width, level.height), (t.levels[k].width, t.levels[k].height));
                let block = 1u32 << k;
                for j in 0..level.height {
                    for i in 0..level.width {
                        let mut lo = 255u8;
                        let mut hi = 0u8;
                        for y in j * block..((j + 1) * block).min(h) {
                            for x in i * block..((i + 1) * block).min(w) {
                                let v = t.levels[0].texels[(y * w + x) as usize];
                                lo = lo.min(v);
                                hi = hi.max(v);
                            }
                        }
                        let index = 2 * (j * level.width + i) as usize;
                        assert_eq!(
                            &level.texels[index..index + 2],
                            &[lo, hi],
                            "{w}×{h} level {k} ({i}, {j})"
                        );
                    }
                }
            }
        }
    }

    /// A random box: tiny, about a texel, a good part of the texture, or several periods wide,
    /// anywhere (negative uv and across the seams included). With `far`, it may also lie tens of
    /// thousands of periods away, where f32 uv often falls exactly on a texel edge (a tie for
    /// the nearest texel centre).
    fn random_box(rng: &mut Rng, texels: f32, far: bool) -> (Vec2, Vec2) {
        let extent = match rng.below(5) {
            0 => Vec2::splat(rng.range(0.0, 1e-4)),
            1 => Vec2::new(rng.range(0.0, 2.0), rng.range(0.0, 2.0)) / texels,
            2 => Vec2::new(rng.range(0.0, 0.5), rng.range(0.0, 0.5)),
            3 => Vec2::new(rng.range(0.0, 4.0), rng.range(0.0, 0.1)),
            _ => Vec2::new(rng.range(0.0, 0.05), rng.range(0.0, 0.05)),
        };
        let corner = match rng.below(if far { 5 } else { 4 }) {
            0 => Vec2::new(1.0 - 0.5 * extent.x, rng.range(-1.0, 1.0)),
            1 => Vec2::new(rng.range(-3.0, 0.0), rng.range(-0.01, 0.01) - 0.5 * extent.y),
            2 => Vec2::new(rng.range(-40.0, 40.0), rng.range(-40.0, 40.0)),
            3 => Vec2::new(rng.f(), rng.f()),
            _ => Vec2::new(rng.range(-1e5, 1e5), rng.range(-1e5, 1e5)),
        };
        (corner, corner + extent)
    }

    #[test]
    fn pyramid_query_bounds_every_sample() {
        let mut rng = Rng(0x7777_1111_9999_3333);
        for a in 0..=6 {
            for b in 0..=6 {
                let (w, h) = (1u32 << a, 1u32 << b);
                for kind in 0..4 {
                    let t = structured_parameter(&mut rng, w, h, kind);
                    check_pyramid_query(&mut rng, &t);
                }
            }
        }
    }

    /// Noise (kind 0), a smooth tileable wave (1), a few bright texels on a dark background (2)
    /// or a ramp in u with its jump at the seam (3): structure makes most queries narrow, so that
    /// a reach too short shows.
    fn structured_parameter(rng: &mut Rng, width: u32, height: u32, kind: u32) -> Texture {
        let (fx, fy, phase) = (rng.below(3) as f32, rng.below(3) as f32, rng.range(0.0, 6.3));
        let spikes: Vec<u32> = (0..3).map(|_| rng.below(width * height)).collect();
        let texels = (0..width * height)
            .map(|k| {
                let (i, j) = ((k % width) as f32, (k / width) as f32);
                match kind {
                    0 => rng.byte(),
                    1 => {
                        let angle = std::f32::consts::TAU * (fx * i / width as f32 + fy * j / height as f32);
                        (127.5 + 127.0 * (angle + phase).sin()) as u8
                    }
                    2 => {
                        if spikes.contains(&k) {
                            235
                        } else {
                            20
                        }
                    }
                    _ => (255.0 * i / width as f32) as u8,
                }
            })
            .collect();
        parameter(width, height, texels)
    }

    /// Every sample over random boxes and lods lies in the range the pyramid gives.
    fn check_pyramid_query(rng: &mut Rng, t: &Texture) {
        let (w, h) = (t.width(), t.height());
        let pyramid = MinMaxPyramid::new(t);
        let top = (t.levels.len() - 1) as f32;
        for _ in 0..24 {
            let (uv_min, uv_max) = random_box(rng, w.max(h) as f32, true);
            let lod_bound = match rng.below(4) {
                0 => rng.range(-2.0, 0.0),
                1 => rng.below(t.levels.len() as u32 + 1) as f32,
                _ => rng.range(0.0, top + 1.0),
            };
            // The corners may come in either order.
            let (a, b) = match rng.below(3) {
                0 => (uv_max, uv_min),
                1 => (Vec2::new(uv_min.x, uv_max.y), Vec2::new(uv_max.x, uv_min.y)),
                _ => (uv_min, uv_max),
            };
            let (lo, hi) = pyramid.query(a, b, lod_bound);
            assert!(0.0 <= lo && lo <= hi && hi <= 1.0);
            for s in 0..24 {
                let f = match s {
                    0 => Vec2::ZERO,
                    1 => Vec2::ONE,
                    2 => Vec2::X,
                    3 => Vec2::Y,
                    _ => Vec2::new(rng.f(), rng.f()),
                };
                let uv = uv_min + (uv_max - uv_min) * f;
                let lod = if s % 3 == 0 { lod_bound } else { lod_bound - rng.range(0.0, 3.0) };
                let v = t.sample_parameter(uv, lod);
                assert!(
                    lo <= v && v <= hi,
                    "{w}×{h}: box {uv_min}..{uv_max} lod ≤ {lod_bound}: sample {v} at {uv} lod {lod} \
                             outside [{lo}, {hi}]"
                );
            }
        }
    }

    #[test]
    fn pyramid_query_is_tight_inside_a_constant_region() {
        let (dark, bright) = (40u8, 200u8);
        let texels = (0..64 * 64).map(|i| if i % 64 < 32 { dark } else { bright }).collect();
        let t = parameter(64, 64, texels);
        let pyramid = MinMaxPyramid::new(&t);
        let tight = |(lo, hi): (f32, f32), v: u8| {
            let v = v as f32 / 255.0;
            lo <= v && v <= hi && hi - lo <= 2.0 * PYRAMID_SLACK + 1e-6
        };
        let inside_dark = (Vec2::new(0.2, 0.3), Vec2::new(0.3, 0.45));
        for lod_bound in [-1.0, 0.0, 0.5, 1.0, 2.0] {
            assert!(tight(pyramid.query(inside_dark.0, inside_dark.1, lod_bound), dark), "lod {lod_bound}");
        }
        // The bright half, seen one period over and with the corners swapped.
        let r = pyramid.query(Vec2::new(-0.2, 3.9), Vec2::new(-0.3, 3.7), 1.0);
        assert!(tight(r, bright), "{r:?}");
        // Straddling the middle, or the seam at u = 1, covers both halves.
        for (a, b) in
            [(Vec2::new(0.45, 0.5), Vec2::new(0.55, 0.5)), (Vec2::new(0.98, 0.1), Vec2::new(1.02, 0.2))]
        {
            let (lo, hi) = pyramid.query(a, b, 0.0);
            assert!(lo <= dark as f32 / 255.0 && hi >= bright as f32 / 255.0, "{a}..{b}: {lo}, {hi}");
        }
        // A bound lod so coarse that every level blends both halves needs the whole range.
        let (lo, hi) = pyramid.query(inside_dark.0, inside_dark.1, 6.0);
        assert!(lo <= dark as f32 / 255.0 && hi >= bright as f32 / 255.0);
    }

    #[test]
    fn pyramid_query_of_non_finite_input_is_the_whole_range() {
        let mut rng = Rng(0x4242_4242_4242_4243);
        let t = random_parameter(&mut rng, 16, 16);
        let pyramid = MinMaxPyramid::new(&t);
        let lo = *t.levels[0].texels.iter().min().unwrap() as f32 / 255.0;
        let hi = *t.levels[0].texels.iter().max().unwrap() as f32 / 255.0;
        let whole = ((lo - PYRAMID_SLACK).max(0.0), (hi + PYRAMID_SLACK).min(1.0));
        let a = Vec2::new(0.1, 0.1);
        assert_eq!(pyramid.query(a, Vec2::new(f32::NAN, 0.2), 0.0), whole);
        assert_eq!(pyramid.query(Vec2::NEG_INFINITY, a, 0.0), whole);
        assert_eq!(pyramid.query(a, a, f32::NAN), whole);
        assert_eq!(pyramid.query(a, a, f32::INFINITY), whole);
        assert_eq!(pyramid.query(a, Vec2::splat(1e30), 0.0), whole);
    }

    /// The texels of an axis of `n` whose centres lie in [lo, hi] modulo 1, found one by one;
    /// the one nearest the middle when there is none.
    fn centres_in(lo: f32, hi: f32, n: u32) -> Vec<usize> {
        let (lo, hi) = (lo as f64, hi as f64);
        let inside: Vec<usize> = (0..n as usize)
            .filter(|&i| {
                let c = (i as f64 + 0.5) / n as f64;
                c + (lo - c).ceil() <= hi
            })
            .collect();
        if !inside.is_empty() {
            return inside;
        }
        let middle = 0.5 * (lo + hi);
        let nearest = (0..n as usize)
            .min_by(|&a, &b| {
                let d = |i: usize| {
                    let c = (i as f64 + 0.5) / n as f64 - middle;
                    (c - c.round()).abs()
                };
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        vec![nearest]
    }

    fn box_values(t: &Texture, uv_min: Vec2, uv_max: Vec2) -> Vec<f64> {
        let level = &t.levels[0];
        let mut values = Vec::new();
        for j in centres_in(uv_min.y, uv_max.y, level.height) {
            for &i in &centres_in(uv_min.x, uv_max.x, level.width) {
                values.push(level.texels[j * level.width as usize + i] as f64);
            }
        }
        values
    }

    #[test]
    fn power_sat_is_the_power_mean_over_the_box() {
        let mut rng = Rng(0x3141_5926_5358_9793);
        let p = 3.0;
        for (w, h) in [(1, 1), (8, 8), (16, 4), (2, 32)] {
            let t = random_parameter(&mut rng, w, h);
            let sat = PowerSat::new(&t, p);
            for _ in 0..60 {
                let (uv_min, uv_max) = random_box(&mut rng, w.max(h) as f32, false);
                let values = box_values(&t, uv_min, uv_max);
                let n = values.len() as f64;
                let high = (values.iter().map(|v| (v + 1.0).powf(p)).sum::<f64>() / n).powf(1.0 / p) - 1.0;
                let low = (values.iter().map(|v| (v + 1.0).powf(-p)).sum::<f64>() / n).powf(-1.0 / p) - 1.0;
                let (min, max) = sat.query(uv_min, uv_max);
                assert!(
                    (max as f64 - high / 255.0).abs() < 1e-5,
                    "{w}×{h} {uv_min}..{uv_max}: {max} vs {high}"
                );
                assert!(
                    (min as f64 - low / 255.0).abs() < 1e-5,
                    "{w}×{h} {uv_min}..{uv_max}: {min} vs {low}"
                );
            }
        }
    }

    #[test]
    fn power_sat_stays_inside_the_true_range_and_approaches_it() {
        let mut rng = Rng(0x2718_2818_2845_9045);
        // Texels in [100, 255]: f64 resolves every power sum up to p = 16.
        let texels: Vec<u8> = (0..32 * 16).map(|_| 100 + rng.below(156) as u8).collect();
        let t = parameter(32, 16, texels);
        let exponents = [1.0, 2.0, 4.0, 8.0, 16.0];
        let sats: Vec<PowerSat> = exponents.iter().map(|&p| PowerSat::new(&t, p)).collect();
        let mut improved = 0;
        for _ in 0..100 {
            let (uv_min, uv_max) = random_box(&mut rng, 32.0, false);
            let values = box_values(&t, uv_min, uv_max);
            let n = values.len() as f64;
            let x_min = values.iter().cloned().fold(f64::INFINITY, f64::min) + 1.0;
            let x_max = values.iter().cloned().fold(0.0, f64::max) + 1.0;
            let mut previous = (f64::INFINITY, f64::INFINITY);
            for (&p, sat) in exponents.iter().zip(&sats) {
                let (min, max) = sat.query(uv_min, uv_max);
                let (min, max) = (min as f64 * 255.0 + 1.0, max as f64 * 255.0 + 1.0);
                // Inside the true range, and no farther from it than the power-mean bound
                // x_max·n^(−1/p) ≤ M_p ≤ x_max (likewise for the minimum) allows.
                assert!(
                    max <= x_max + 1e-4 && max >= x_max * n.powf(-1.0 / p) - 1e-4,
                    "p {p}: {max} vs {x_max}"
                );
                assert!(
                    min >= x_min - 1e-4 && min <= x_min * n.powf(1.0 / p) + 1e-4,
                    "p {p}: {min} vs {x_min}"
                );
                let error = (min - x_min, x_max - max);
                assert!(error.0 <= previous.0 + 1e-4 && error.1 <= previous.1 + 1e-4, "p {p} is worse");
                previous = error;
            }
            let first = sats[0].query(uv_min, uv_max);
            let last = sats[sats.len() - 1].query(uv_min, uv_max);
            if last.1 - last.0 > first.1 - first.0 + 1e-3 {
                improved += 1;
            }
        }
        assert!(improved > 30, "only {improved} boxes widen from p = 1 to p = 16");
    }

    #[test]
    fn power_sat_never_leaves_the_true_range_even_where_f64_cannot_resolve_it() {
        let mut rng = Rng(0x1616_1616_6161_6161);
        let t = random_parameter(&mut rng, 32, 32);
        for p in [32.0, 64.0, 200.0] {
            let sat = PowerSat::new(&t, p);
            for _ in 0..100 {
                let (uv_min, uv_max) = random_box(&mut rng, 32.0, false);
                let values = box_values(&t, uv_min, uv_max);
                let x_min = values.iter().cloned().fold(f64::INFINITY, f64::min);
                let x_max = values.iter().cloned().fold(0.0, f64::max);
                let (min, max) = sat.query(uv_min, uv_max);
                assert!(max as f64 * 255.0 <= x_max + 1e-3, "p {p}: max {} above {x_max}", max * 255.0);
                assert!(min as f64 * 255.0 >= x_min - 1e-3, "p {p}: min {} below {x_min}", min * 255.0);
            }
        }
    }
}
