use super::*;
use crate::scene::texture::{MinMaxPyramid, PowerSat, PYRAMID_SLACK};
use crate::shading::tonemap::srgb_encode;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh folder under the system temporary folder, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("multirate-texture-{}-{name}-{n}", std::process::id()));
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
    Texture::from_level0(PathBuf::from("test.png"), TextureUsage::Parameter, width, height, texels).unwrap()
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
                let uv =
                    Vec2::new((i as f32 + 0.5) / level.width as f32, (j as f32 + 0.5) / level.height as f32);
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
                assert!((encoded - texel).abs() < 0.01, "texel ({i}, {j}) channel {c}: {encoded} vs {texel}");
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
                    assert_eq!(&level.texels[index..index + 2], &[lo, hi], "{w}×{h} level {k} ({i}, {j})");
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
    for (a, b) in [(Vec2::new(0.45, 0.5), Vec2::new(0.55, 0.5)), (Vec2::new(0.98, 0.1), Vec2::new(1.02, 0.2))]
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
            assert!((max as f64 - high / 255.0).abs() < 1e-5, "{w}×{h} {uv_min}..{uv_max}: {max} vs {high}");
            assert!((min as f64 - low / 255.0).abs() < 1e-5, "{w}×{h} {uv_min}..{uv_max}: {min} vs {low}");
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
            assert!(max <= x_max + 1e-4 && max >= x_max * n.powf(-1.0 / p) - 1e-4, "p {p}: {max} vs {x_max}");
            assert!(min >= x_min - 1e-4 && min <= x_min * n.powf(1.0 / p) + 1e-4, "p {p}: {min} vs {x_min}");
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
