//! [`Texture`]: a PNG file as an image and its full mip chain, as albedo or as a parameter, and
//! the twin of Vulkan's trilinear sampling over it.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use image::{ImageDecoder, ImageFormat};

/// The largest width or height a texture may have, in texels.
pub const MAX_TEXTURE_SIZE: u32 = 16384;

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
        let bytes = crate::scene::file::read_file(path)
            .map_err(|error| TextureError::Io { path: path.to_path_buf(), error })?;
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

#[cfg(test)]
mod tests;
