//! The deterministic generator, how a case seeds it, and the seed corpus.

use super::*;

impl Rng {
    /// The generator of case `index` of a run with `seed`: each case can be rerun alone.
    pub(crate) fn for_case(seed: u64, index: u64) -> Rng {
        let mut rng = Rng(seed ^ index.wrapping_mul(0xd1b5_4a32_d192_ed03));
        rng.next_u64();
        rng
    }

    /// True with probability `1 / n`.
    pub(crate) fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }

    pub(crate) fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

// ---------------------------------------------------------------------------------------------
// The seed corpus.

/// A closed cube with texture coordinates and normals, in two objects, faces in three
/// materials; some faces index backwards (negative indices).
pub(crate) const CUBE_OBJ: &str = "\
# a unit cube for the fuzz corpus
mtllib model.mtl
o front
v -0.5 -0.5 0.5
v 0.5 -0.5 0.5
v 0.5 0.5 0.5
v -0.5 0.5 0.5
v -0.5 -0.5 -0.5
v 0.5 -0.5 -0.5
v 0.5 0.5 -0.5
v -0.5 0.5 -0.5
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
vn 0 0 -1
vn 1 0 0
vn -1 0 0
vn 0 1 0
vn 0 -1 0
usemtl painted
f 1/1/1 2/2/1 3/3/1 4/4/1
f 6/1/2 5/2/2 8/3/2 7/4/2
s 1
g sides
usemtl shiny
f 2/1 6/2 7/3 3/4
f 5/1 1/2 4/3 8/4
o caps
usemtl metal
f -5/1 -6/2 -2/3 -1/4
f -3/1 -4/2 -8/3 -7/4
l 1 7
p 3
";

/// Materials of every kind the OBJ loader tells apart, and the statements it leaves out.
pub(crate) const MODEL_MTL: &str = "\
# materials for the fuzz corpus
newmtl clay
Kd 0.8 0.7 0.6

newmtl shiny
Ka 0.1 0.1 0.1
Kd 0.5 0.1 0.1
Ks 0.4 0.4 0.4
Ns 64
illum 2

newmtl metal
Kd 0.9 0.6 0.3
Pr 0.3
Pm 1

newmtl painted
Kd 1 1 1
map_Kd -s 1 1 1 textures\\albedo.png

newmtl glass
Kd 0.2 0.3 0.4
d 0.5
Tr 0.5
Ke 0.1 0.1 0.1
Ni 1.5
map_Bump -bm 0.5 textures/bump.png
map_Ks textures/spec.tga
map_d textures/alpha.png
";

/// A seed file: its name (which decides where it is written) and its bytes.
#[derive(Clone)]
pub(crate) struct Seed {
    pub(crate) name: String,
    pub(crate) bytes: Vec<u8>,
}

pub(crate) struct Corpus {
    /// The shipped scene files.
    pub(crate) scenes: Vec<Seed>,
    /// Meshes named by scenes are written with one of these (a grid or a sphere).
    pub(crate) grid: Vec<u8>,
    pub(crate) sphere: Vec<u8>,
    /// OBJ files given as the scene: the shipped small meshes, as they are and with a material
    /// library, and [`CUBE_OBJ`].
    pub(crate) models: Vec<Seed>,
    pub(crate) mtl: Vec<u8>,
    /// Small shipped textures and the JPEG and TGA files made here.
    pub(crate) textures: Vec<Seed>,
    /// Albedo and parameter maps written where a scene or library names a texture.
    pub(crate) albedo_map: Vec<u8>,
    pub(crate) parameter_map: Vec<u8>,
    /// Every line of every text seed, for splicing.
    pub(crate) lines: Vec<String>,
}

pub(crate) fn repo(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

pub(crate) fn read(relative: &str) -> Vec<u8> {
    std::fs::read(repo(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

impl Corpus {
    pub(crate) fn new() -> Corpus {
        let mut scenes = Vec::new();
        for folder in ["scenes", "scenes/test"] {
            let mut names: Vec<String> = std::fs::read_dir(repo(folder))
                .unwrap_or_else(|e| panic!("{folder}: {e}"))
                .map(|entry| entry.expect("a folder entry").file_name().to_string_lossy().into_owned())
                .filter(|name| name.ends_with(".toml"))
                .collect();
            names.sort();
            for name in names {
                let bytes = read(&format!("{folder}/{name}"));
                scenes.push(Seed { name, bytes });
            }
        }
        assert!(scenes.len() >= 10, "the shipped scenes are the TOML seeds: {} found", scenes.len());
        let grid = read("scenes/test/grid_8.obj");
        let sphere = read("scenes/test/icosphere.obj");
        let with_library = |mesh: &[u8], first: &str, second: &str| {
            let text = String::from_utf8_lossy(mesh);
            let lines: Vec<&str> = text.lines().collect();
            let face = lines.iter().position(|l| l.starts_with("f ")).unwrap_or(lines.len());
            let middle = face + (lines.len() - face) / 2;
            let mut out = String::from("mtllib model.mtl\n");
            for (i, line) in lines.iter().enumerate() {
                if i == face {
                    out.push_str(&format!("usemtl {first}\n"));
                }
                if i == middle {
                    out.push_str(&format!("usemtl {second}\n"));
                }
                out.push_str(line);
                out.push('\n');
            }
            out.into_bytes()
        };
        let models = vec![
            Seed { name: "grid".into(), bytes: grid.clone() },
            Seed { name: "sphere".into(), bytes: sphere.clone() },
            Seed { name: "grid+mtl".into(), bytes: with_library(&grid, "clay", "painted") },
            Seed { name: "sphere+mtl".into(), bytes: with_library(&sphere, "shiny", "metal") },
            Seed { name: "cube".into(), bytes: CUBE_OBJ.as_bytes().to_vec() },
        ];
        let textures = vec![
            Seed { name: "checker_8.png".into(), bytes: read("scenes/textures/checker_8.png") },
            Seed { name: "one_texel.png".into(), bytes: read("scenes/textures/one_texel.png") },
            Seed { name: "fabric_roughness.png".into(), bytes: read("scenes/textures/fabric_roughness.png") },
            Seed { name: "fabric_albedo.png".into(), bytes: read("scenes/textures/fabric_albedo.png") },
            Seed { name: "rgb.jpg".into(), bytes: jpeg_seed(16, 8, false) },
            Seed { name: "grey.jpg".into(), bytes: jpeg_seed(8, 16, true) },
            Seed { name: "rgb.tga".into(), bytes: tga_seed(TgaKind::TrueColour) },
            Seed { name: "grey_rle.tga".into(), bytes: tga_seed(TgaKind::GreyRle) },
            Seed { name: "mapped.tga".into(), bytes: tga_seed(TgaKind::ColourMapped) },
        ];
        let mut lines = Vec::new();
        for seed in scenes.iter().chain(&models) {
            lines.extend(String::from_utf8_lossy(&seed.bytes).lines().map(str::to_string));
        }
        lines.extend(MODEL_MTL.lines().map(str::to_string));
        Corpus {
            scenes,
            grid,
            sphere,
            models,
            mtl: MODEL_MTL.as_bytes().to_vec(),
            textures,
            albedo_map: read("scenes/textures/fabric_albedo.png"),
            parameter_map: read("scenes/textures/fabric_roughness.png"),
            lines,
        }
    }
}

/// A small JPEG with a colour gradient (or its grey version), made with the `image` crate.
pub(crate) fn jpeg_seed(width: u32, height: u32, grey: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let mut encoder = image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, 85);
    let texels: Vec<u8> = (0..width * height)
        .flat_map(|k| {
            let (i, j) = (k % width, k / width);
            let rgb = [(i * 255 / width) as u8, (j * 255 / height) as u8, ((i + j) * 8) as u8];
            if grey {
                vec![rgb[0] / 2 + rgb[1] / 2]
            } else {
                rgb.to_vec()
            }
        })
        .collect();
    let colour = if grey { image::ExtendedColorType::L8 } else { image::ExtendedColorType::Rgb8 };
    encoder.encode(&texels, width, height, colour).expect("encode the JPEG seed");
    out
}

pub(crate) enum TgaKind {
    TrueColour,
    GreyRle,
    ColourMapped,
}

/// A small TGA file written here by hand: 8×4 true colour (24 bits), 16×4 grey run-length
/// encoded, or 4×4 colour mapped (a palette of 4).
pub(crate) fn tga_seed(kind: TgaKind) -> Vec<u8> {
    let (image_type, width, height, bits): (u8, u16, u16, u8) = match kind {
        TgaKind::TrueColour => (2, 8, 4, 24),
        TgaKind::GreyRle => (11, 16, 4, 8),
        TgaKind::ColourMapped => (1, 4, 4, 8),
    };
    let mapped = matches!(kind, TgaKind::ColourMapped);
    let mut out = vec![0u8, mapped as u8, image_type];
    // Colour map: first entry, length, entry size in bits.
    if mapped {
        out.extend_from_slice(&[0, 0, 4, 0, 24]);
    } else {
        out.extend_from_slice(&[0; 5]);
    }
    out.extend_from_slice(&[0, 0, 0, 0]);
    out.extend_from_slice(&width.to_le_bytes());
    out.extend_from_slice(&height.to_le_bytes());
    out.push(bits);
    out.push(0x20); // Top-left origin.
    match kind {
        TgaKind::TrueColour => {
            for k in 0..u32::from(width * height) {
                out.extend_from_slice(&[(k * 8) as u8, (k * 5) as u8, 200]);
            }
        }
        TgaKind::GreyRle => {
            for row in 0..height {
                // A run of 10 texels, then 6 raw ones.
                out.extend_from_slice(&[0x80 | 9, (row * 60) as u8, 5]);
                out.extend((0..6u8).map(|i| i * 40));
            }
        }
        TgaKind::ColourMapped => {
            out.extend_from_slice(&[0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255]);
            out.extend((0..16u8).map(|k| k % 4));
        }
    }
    out
}
