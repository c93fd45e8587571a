//! Fuzzing of the loaders of `src/scene/` on the CPU (no Vulkan): the scene TOML loader
//! (`Scene::load`), an OBJ file given as the scene with its MTL library (`obj_scene`), and the
//! texture loader (`Texture::load`: PNG, JPEG, TGA).
//!
//! This file owns the deterministic mutation loop, its seed corpus (built from the shipped
//! scenes, meshes and textures, plus a hand-written MTL library, a JPEG and TGA files made
//! here) and what is asserted of every case:
//! - no panic, including one a loader catches itself (a panic hook sees it);
//! - no hang: each case runs on its own thread, is given up after [`HANG_LIMIT`] and must
//!   finish within [`CASE_LIMIT`]; the whole run within its total budget;
//! - bounded memory: a counting global allocator tracks the peak of live bytes of the case's
//!   thread, which must stay under [`MEMORY_LIMIT`] plus [`BYTES_PER_LOADED_TEXEL`] for each
//!   texel of a texture the case loaded; a case that would pass [`HARD_CAP`] aborts the run
//!   at once, naming itself, rather than take the machine's memory;
//! - a refused file is an `Err` whose message names the file at fault (the loader's input, or
//!   the file among the case's that is to blame);
//! - a loaded scene or texture keeps the invariants its types document.
//!
//! `cargo test --release --test fuzz_loaders` runs [`DEFAULT_CASES`] cases. Longer:
//! `MULTIRATE_FUZZ_CASES=200000 MULTIRATE_FUZZ_SEED=7 cargo test --release --test fuzz_loaders -- --nocapture`
//! (`MULTIRATE_FUZZ_SECONDS` stops it after that many seconds instead); one case again:
//! `MULTIRATE_FUZZ_SEED=S MULTIRATE_FUZZ_CASE=I cargo test --release --test fuzz_loaders -- --nocapture`.

mod common;

use common::SplitMix64 as Rng;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::{Cell, RefCell};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::Once;
use std::time::{Duration, Instant};

use multirate::scene::texture::{Texture, TextureUsage, MAX_TEXTURE_SIZE};
use multirate::scene::{Light, MaterialKind, Scene, SceneError};

/// Cases that `cargo test` runs.
const DEFAULT_CASES: usize = 2000;
/// The seed without `MULTIRATE_FUZZ_SEED`.
const DEFAULT_SEED: u64 = 0x6d75_6c74_6972_6174;
/// What one case may take, checked after it returns: every input is at most a few hundred
/// kilobytes, which every loader reads in milliseconds.
const CASE_LIMIT: Duration = Duration::from_secs(5);
/// After this long a case is declared hung and the run fails without waiting for it.
const HANG_LIMIT: Duration = Duration::from_secs(30);
/// The time budget of a run: this much, plus [`MEAN_CASE_BUDGET`] per case.
const RUN_BUDGET: Duration = Duration::from_secs(60);
const MEAN_CASE_BUDGET: Duration = Duration::from_millis(50);
/// The largest file a case writes: mutations that grow a file past it are cut there.
const MAX_INPUT: usize = 300_000;
/// Peak live bytes a case may reach, besides the textures it loads. The inputs are at most
/// [`MAX_INPUT`] bytes (the seeds are under 12 kB, a mutation adds at most 100 kB) and a
/// loaded test scene takes about a megabyte, so 64 MiB is room for the loaders' working copies,
/// not for anything an input declares: a file that declares a large image or mesh must be
/// refused before that is allocated.
const MEMORY_LIMIT: usize = 64 << 20;
/// Peak bytes a successfully loaded texture may add per level-0 texel: the decoded image (at
/// most 8 bytes a texel, RGBA16), its RGBA8 copy (4) and the mip chain (4/3 of that), or the
/// luma copy, chain and min/max pyramid of a parameter map.
const BYTES_PER_LOADED_TEXEL: usize = 16;
/// A case whose thread would hold more than this is stopped at once (the process aborts with
/// the case named on standard error), before it can exhaust the machine's memory.
const HARD_CAP: isize = 1 << 30;

// ---------------------------------------------------------------------------------------------
// The counting allocator: live and peak bytes of the current thread while it runs a case.

struct CountingAllocator;

thread_local! {
    /// Whether this thread is running a case (only such threads are counted).
    static TRACKED: Cell<bool> = const { Cell::new(false) };
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
    /// The case being run, for the message of [`HARD_CAP`]: seed and index.
    static CASE_ID: Cell<(u64, u64)> = const { Cell::new((0, 0)) };
    /// The message of a panic on this thread during a case, caught or not.
    static PANIC_NOTE: RefCell<Option<String>> = const { RefCell::new(None) };
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

/// Counts `delta` bytes more (or fewer) live on this thread, if it is running a case; stops
/// the process where that passes [`HARD_CAP`].
fn count(delta: isize) {
    if !TRACKED.try_with(Cell::get).unwrap_or(false) {
        return;
    }
    let live = LIVE.try_with(|l| {
        l.set(l.get() + delta);
        l.get()
    });
    if let Ok(live) = live {
        let _ = PEAK.try_with(|p| p.set(p.get().max(live)));
        if live > HARD_CAP {
            hard_cap_exceeded(live);
        }
    }
}

/// Writes which case passed [`HARD_CAP`] without allocating, and aborts.
fn hard_cap_exceeded(live: isize) -> ! {
    let _ = TRACKED.try_with(|t| t.set(false));
    let (seed, index) = CASE_ID.try_with(Cell::get).unwrap_or((0, 0));
    let mut err = std::io::stderr();
    let mut digits = [0u8; 20];
    let _ = err.write_all(b"\nfuzz_loaders: a case would hold ");
    let _ = err.write_all(decimal(live as u64, &mut digits));
    let _ = err.write_all(b" bytes, past the hard cap; rerun it with MULTIRATE_FUZZ_SEED=");
    let _ = err.write_all(decimal(seed, &mut digits));
    let _ = err.write_all(b" MULTIRATE_FUZZ_CASE=");
    let _ = err.write_all(decimal(index, &mut digits));
    let _ = err.write_all(b"\n");
    std::process::abort();
}

/// `v` in decimal, in `buffer`, without allocating.
fn decimal(mut v: u64, buffer: &mut [u8; 20]) -> &[u8] {
    let mut start = buffer.len();
    loop {
        start -= 1;
        buffer[start] = b'0' + (v % 10) as u8;
        v /= 10;
        if v == 0 {
            return &buffer[start..];
        }
    }
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size() as isize);
        System.alloc(layout)
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size() as isize);
        System.alloc_zeroed(layout)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        count(-(layout.size() as isize));
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size as isize - layout.size() as isize);
        System.realloc(ptr, layout, new_size)
    }
}

/// Every panic on a thread running a case is noted there (the loaders may catch their own);
/// others go to the usual hook.
fn install_panic_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let usual = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if TRACKED.try_with(Cell::get).unwrap_or(false) {
                let note = format!("{info}");
                let _ = PANIC_NOTE.try_with(|n| {
                    let mut n = n.borrow_mut();
                    if n.is_none() {
                        *n = Some(note);
                    }
                });
            } else {
                usual(info);
            }
        }));
    });
}

/// What running a closure on a counted thread gave.
struct Tracked<T> {
    /// The closure's value, or the message of the panic that ended it.
    value: Result<T, String>,
    /// The first panic during the run, also one caught inside it.
    panic: Option<String>,
    /// Peak live bytes on the thread, over what it held when the closure started.
    peak: usize,
    elapsed: Duration,
}

/// Runs `f` on a fresh thread with the allocator counting, as case `id`. `Err` if it has not
/// returned after [`HANG_LIMIT`] (the thread is left behind).
fn run_tracked<T: Send + 'static>(
    id: (u64, u64),
    f: impl FnOnce() -> T + Send + 'static,
) -> Result<Tracked<T>, Duration> {
    install_panic_hook();
    let (send, receive) = mpsc::channel();
    std::thread::Builder::new()
        .name(format!("fuzz-case-{}", id.1))
        .spawn(move || {
            CASE_ID.with(|c| c.set(id));
            PANIC_NOTE.with(|n| n.borrow_mut().take());
            LIVE.with(|l| l.set(0));
            PEAK.with(|p| p.set(0));
            let start = Instant::now();
            TRACKED.with(|t| t.set(true));
            let value = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
            TRACKED.with(|t| t.set(false));
            let elapsed = start.elapsed();
            let peak = PEAK.with(Cell::get).max(0) as usize;
            let panic = PANIC_NOTE.with(|n| n.borrow_mut().take());
            let value = value.map_err(|payload| {
                payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a panic without a message".into())
            });
            let _ = send.send(Tracked { value, panic, peak, elapsed });
        })
        .expect("spawn a case thread");
    receive.recv_timeout(HANG_LIMIT).map_err(|_| HANG_LIMIT)
}

// ---------------------------------------------------------------------------------------------
// The deterministic generator (tests/common) and how a case seeds it.

impl Rng {
    /// The generator of case `index` of a run with `seed`: each case can be rerun alone.
    fn for_case(seed: u64, index: u64) -> Rng {
        let mut rng = Rng(seed ^ index.wrapping_mul(0xd1b5_4a32_d192_ed03));
        rng.next_u64();
        rng
    }

    /// True with probability `1 / n`.
    fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

// ---------------------------------------------------------------------------------------------
// The seed corpus.

/// A closed cube with texture coordinates and normals, in two objects, faces in three
/// materials; some faces index backwards (negative indices).
const CUBE_OBJ: &str = "\
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
const MODEL_MTL: &str = "\
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
struct Seed {
    name: String,
    bytes: Vec<u8>,
}

struct Corpus {
    /// The shipped scene files.
    scenes: Vec<Seed>,
    /// Meshes named by scenes are written with one of these (a grid or a sphere).
    grid: Vec<u8>,
    sphere: Vec<u8>,
    /// OBJ files given as the scene: the shipped small meshes, as they are and with a material
    /// library, and [`CUBE_OBJ`].
    models: Vec<Seed>,
    mtl: Vec<u8>,
    /// Small shipped textures and the JPEG and TGA files made here.
    textures: Vec<Seed>,
    /// Albedo and parameter maps written where a scene or library names a texture.
    albedo_map: Vec<u8>,
    parameter_map: Vec<u8>,
    /// Every line of every text seed, for splicing.
    lines: Vec<String>,
}

fn repo(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

fn read(relative: &str) -> Vec<u8> {
    std::fs::read(repo(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

impl Corpus {
    fn new() -> Corpus {
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
fn jpeg_seed(width: u32, height: u32, grey: bool) -> Vec<u8> {
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

enum TgaKind {
    TrueColour,
    GreyRle,
    ColourMapped,
}

/// A small TGA file written here by hand: 8×4 true colour (24 bits), 16×4 grey run-length
/// encoded, or 4×4 colour mapped (a palette of 4).
fn tga_seed(kind: TgaKind) -> Vec<u8> {
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

// ---------------------------------------------------------------------------------------------
// Mutations.

/// Numbers that loaders get wrong: not finite, at the edges of integer and float types, zero,
/// negative, written oddly.
const NUMBERS: &[&str] = &[
    "NaN",
    "nan",
    "inf",
    "-inf",
    "+inf",
    "-1",
    "0",
    "-0",
    "1",
    "2",
    "65",
    "257",
    "16384",
    "16385",
    "60000",
    "65536",
    "2147483647",
    "2147483648",
    "-2147483648",
    "-2147483649",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775809",
    "18446744073709551616",
    "99999999999999999999999",
    "1e-45",
    "1e-320",
    "3.4028235e38",
    "3.5e38",
    "1e39",
    "-1e39",
    "1e308",
    "1e309",
    "0.0000001",
    "1.",
    "-.5",
    "0x10",
    "1_000",
    "00012",
    "1e",
];

/// Tokens for text files: TOML, OBJ and MTL syntax out of place, odd characters.
const TOKENS: &[&str] = &[
    "\"\"",
    "\"",
    "'",
    "'''",
    "\"\"\"",
    "[]",
    "[",
    "]",
    "[[",
    "]]",
    "{}",
    "{",
    "=",
    "==",
    ",",
    ".",
    "#",
    "\\",
    "\\u0000",
    "\\uD800",
    "/",
    "//",
    "///",
    "\t",
    "\r",
    "\r\n",
    "\n\n",
    "\0",
    "é",
    "\u{feff}",
    "\u{202e}",
    "\u{1f4a5}",
    "[camera]",
    "[render]",
    "[[meshes]]",
    "[[materials]]",
    "[[lights]]",
    "description = \"again\"",
    "type = \"polygon\"",
    "type = \"ggx\"",
    "vertices = []",
    "vertices = [[0, 0, 0], [0, 0, 0], [0, 0, 0]]",
    "scale = [0, 0, 0]",
    "scale = []",
    "two_sided = 1",
    "uv_projection = \"spherical\"",
    "obj = \"\"",
    "kd_map = \"textures\"",
    "v",
    "vt",
    "vn",
    "f",
    "f 1 2 3",
    "f -1 -2 -3",
    "f 1/1/1 2/2/2 3/3/3",
    "f 1//1 2//1 3//1",
    "f 1/1 2/2 3/3 4/4 5/5 6/6",
    "f 0 0 0",
    "f 2147483648 1 2",
    "f -2147483649 1 2",
    "f 1 2",
    "f 1/2/3/4 2 3",
    "f 1/ 2/ 3/",
    "v 1e39 0 0",
    "v 0 0 0 0",
    "v 1 1 1 1e-45",
    "v 0 0 0 1 0 0",
    "vt nan nan",
    "vt 1e39 0",
    "vn 0 0 0",
    "o",
    "g",
    "s off",
    "l 1 2",
    "p 1",
    "usemtl",
    "usemtl nosuch",
    "mtllib",
    "mtllib model.mtl",
    "mtllib model.mtl model.mtl",
    "mtllib textures",
    "newmtl",
    "newmtl clay",
    "Kd",
    "Kd 1 1",
    "Ks 2 2 2",
    "Ns -5",
    "Ns 1e39",
    "Pr nan",
    "Pm 2",
    "d -1",
    "map_Kd",
    "map_Kd -bm",
    "map_Kd textures/albedo.png",
    "map_Kd textures",
    "map_Kd model.mtl",
];

/// Strings put in place of a quoted string or a file name: empty, folders, missing files,
/// files of another kind, devices.
const PATHS: &[&str] = &[
    "",
    " ",
    ".",
    "..",
    "/",
    "textures",
    "textures/",
    "nosuch.obj",
    "nosuch.png",
    "model.mtl",
    "scene.toml",
    "model.obj",
    "a\\b.png",
    "/dev/null",
    "/dev/zero",
    "\u{0}",
    "name with spaces.obj",
];

/// Interesting 16- and 32-bit values for binary headers.
const WORDS: &[u32] = &[
    0,
    1,
    2,
    7,
    8,
    255,
    256,
    4096,
    16384,
    16385,
    32767,
    32768,
    60000,
    65535,
    65536,
    0x7fff_ffff,
    0xffff_ffff,
];

/// File signatures (one makes the texture loader see another format).
const MAGICS: &[&[u8]] = &[
    b"\x89PNG\r\n\x1a\n",
    b"\xff\xd8\xff",
    b"\xff\xd8\xff\xe0",
    b"v/1\x01",
    b"GIF89a",
    b"BM",
    b"RIFF\0\0\0\0WEBP",
    b"II*\0",
    b"#?RADIANCE\n",
    b"P6\n",
    b"qoif",
];

/// Applies one random byte-level mutation to `data`. `text` allows the large insertions (very
/// long lines) that only text formats can take without being cut short by a size check.
fn mutate_bytes(rng: &mut Rng, data: &mut Vec<u8>, corpus: &Corpus, text: bool, log: &mut String) {
    let position = |rng: &mut Rng, data: &Vec<u8>| rng.below(data.len() + 1);
    match rng.below(11) {
        0 if !data.is_empty() => {
            let i = rng.below(data.len());
            data[i] = rng.next_u64() as u8;
            let _ = write!(log, "set byte {i}; ");
        }
        1 if !data.is_empty() => {
            let i = rng.below(data.len());
            data[i] ^= 1 << rng.below(8);
            let _ = write!(log, "flip a bit of byte {i}; ");
        }
        2 => {
            let at = position(rng, data);
            data.truncate(at);
            let _ = write!(log, "truncate at {at}; ");
        }
        3 => {
            let at = position(rng, data);
            let token = if rng.one_in(2) { *rng.pick(NUMBERS) } else { *rng.pick(TOKENS) };
            data.splice(at..at, token.bytes());
            let _ = write!(log, "insert {token:?} at {at}; ");
        }
        4 if !data.is_empty() => {
            let at = rng.below(data.len());
            let most = if rng.one_in(4) { data.len() / 4 + 1 } else { 16 };
            let len = 1 + rng.below(most);
            let end = (at + len).min(data.len());
            data.drain(at..end);
            let _ = write!(log, "delete {at}..{end}; ");
        }
        5 if !data.is_empty() => {
            let from = rng.below(data.len());
            let end = (from + 1 + rng.below(256)).min(data.len());
            let chunk = data[from..end].to_vec();
            let at = position(rng, data);
            data.splice(at..at, chunk);
            let _ = write!(log, "copy {from}..{end} to {at}; ");
        }
        6 => {
            let junk: Vec<u8> = (0..1 + rng.below(64)).map(|_| rng.next_u64() as u8).collect();
            let at = position(rng, data);
            let _ = write!(log, "insert {} random bytes at {at}; ", junk.len());
            data.splice(at..at, junk);
        }
        7 => {
            let other = match rng.below(3) {
                0 => &rng.pick(&corpus.scenes).bytes,
                1 => &rng.pick(&corpus.models).bytes,
                _ => &rng.pick(&corpus.textures).bytes,
            };
            let from = rng.below(other.len());
            let end = (from + 1 + rng.below(512)).min(other.len());
            let at = position(rng, data);
            data.splice(at..at, other[from..end].iter().copied());
            let _ = write!(log, "splice {} bytes of another seed at {at}; ", end - from);
        }
        8 if text => {
            let unit = if rng.one_in(2) { *rng.pick(NUMBERS) } else { *rng.pick(TOKENS) };
            let unit = if unit.is_empty() { "9" } else { unit };
            let length = 1000 + rng.below(100_000);
            let long: String = unit.repeat(length / unit.len() + 1);
            let at = position(rng, data);
            let line = if rng.one_in(2) { format!("\n{long}\n") } else { long };
            let _ = write!(log, "insert a {}-byte run of {unit:?} at {at}; ", line.len());
            data.splice(at..at, line.into_bytes());
        }
        9 if data.len() >= 4 => {
            let i = rng.below(data.len() - 3);
            let word = *rng.pick(WORDS);
            let bytes = match rng.below(4) {
                0 => word.to_le_bytes().to_vec(),
                1 => word.to_be_bytes().to_vec(),
                2 => (word as u16).to_le_bytes().to_vec(),
                _ => (word as u16).to_be_bytes().to_vec(),
            };
            data[i..i + bytes.len()].copy_from_slice(&bytes);
            let _ = write!(log, "write {word} ({} bytes) at {i}; ", bytes.len());
        }
        _ => {
            let magic = *rng.pick(MAGICS);
            let at = if rng.one_in(2) { 0 } else { position(rng, data) };
            if rng.one_in(2) && data.len() >= at + magic.len() {
                data[at..at + magic.len()].copy_from_slice(magic);
                let _ =
                    write!(log, "overwrite with signature {:?} at {at}; ", magic.escape_ascii().to_string());
            } else {
                data.splice(at..at, magic.iter().copied());
                let _ = write!(log, "insert signature {:?} at {at}; ", magic.escape_ascii().to_string());
            }
        }
    }
}

/// Applies one line-level mutation to a text file.
fn mutate_lines(rng: &mut Rng, data: &mut Vec<u8>, corpus: &Corpus, log: &mut String) {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut lines: Vec<String> = text.split('\n').map(str::to_string).collect();
    let n = lines.len();
    let i = rng.below(n);
    match rng.below(9) {
        0 => {
            lines.remove(i);
            let _ = write!(log, "delete line {}; ", i + 1);
        }
        1 => {
            let most = (100_000 / (lines[i].len() + 1)).max(1);
            let copies = if rng.one_in(8) { 1 + rng.below(2000).min(most) } else { 1 };
            for _ in 0..copies {
                lines.insert(i, lines[i].clone());
            }
            let _ = write!(log, "repeat line {} {copies} times; ", i + 1);
        }
        2 => {
            let j = rng.below(n);
            lines.swap(i, j);
            let _ = write!(log, "swap lines {} and {}; ", i + 1, j + 1);
        }
        3 => {
            let number = *rng.pick(NUMBERS);
            let replaced = replace_number(rng, &lines[i], number);
            let _ = write!(log, "line {}: a number to {number:?}; ", i + 1);
            lines[i] = replaced;
        }
        4 => {
            let line = rng.pick(&corpus.lines).clone();
            let _ = write!(log, "insert {line:?} before line {}; ", i + 1);
            lines.insert(i, line);
        }
        5 => {
            let token = *rng.pick(TOKENS);
            let _ = write!(log, "line {} becomes {token:?}; ", i + 1);
            lines[i] = token.to_string();
        }
        6 => {
            // A whole section (from a header or `newmtl`/`o` line to the next) again, at the end.
            let starts: Vec<usize> = (0..n)
                .filter(|&k| {
                    let l = lines[k].trim_start();
                    l.starts_with('[') || l.starts_with("newmtl") || l.starts_with("o ")
                })
                .collect();
            if let Some(&start) = starts.get(rng.below(starts.len().max(1))) {
                let end = starts.iter().copied().find(|&k| k > start).unwrap_or(n);
                let section: Vec<String> = lines[start..end].to_vec();
                let _ = write!(log, "repeat lines {}..{} at the end; ", start + 1, end);
                lines.extend(section);
            }
        }
        7 => {
            let path = *rng.pick(PATHS);
            let replaced = replace_name(&lines[i], path);
            let _ = write!(log, "line {}: a name to {path:?}; ", i + 1);
            lines[i] = replaced;
        }
        _ => {
            let j = rng.below(n);
            let line = lines.remove(i);
            lines.insert(j.min(lines.len()), line);
            let _ = write!(log, "move line {} to {}; ", i + 1, j + 1);
        }
    }
    *data = lines.join("\n").into_bytes();
}

/// `line` with one of its numbers (chosen by `rng`) replaced by `number`; the line as it is
/// when it has none.
fn replace_number(rng: &mut Rng, line: &str, number: &str) -> String {
    let bytes = line.as_bytes();
    let mut spans = Vec::new();
    let mut k = 0;
    while k < bytes.len() {
        let starts = bytes[k].is_ascii_digit()
            || (matches!(bytes[k], b'-' | b'+' | b'.') && bytes.get(k + 1).is_some_and(u8::is_ascii_digit));
        if starts && (k == 0 || !bytes[k - 1].is_ascii_alphanumeric()) {
            let begin = k;
            k += 1;
            while k < bytes.len()
                && (bytes[k].is_ascii_digit() || matches!(bytes[k], b'.' | b'e' | b'E' | b'-' | b'+'))
            {
                k += 1;
            }
            spans.push(begin..k);
        } else {
            k += 1;
        }
    }
    if spans.is_empty() {
        return line.to_string();
    }
    let span = spans[rng.below(spans.len())].clone();
    format!("{}{number}{}", &line[..span.start], &line[span.end..])
}

/// `line` with its quoted string (TOML) or last word (OBJ and MTL statements) replaced by `name`.
fn replace_name(line: &str, name: &str) -> String {
    if let (Some(open), Some(close)) = (line.find('"'), line.rfind('"')) {
        if close > open {
            return format!("{}\"{name}\"{}", &line[..open], &line[close + 1..]);
        }
    }
    match line.trim_end().rfind(char::is_whitespace) {
        Some(k) => format!("{} {name}", &line[..k]),
        None => format!("{line} {name}"),
    }
}

/// The IEEE CRC-32 of PNG chunks.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xffff_ffffu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

/// The chunks of a PNG file: (offset of the length field, data length), as far as they parse.
fn png_chunks(data: &[u8]) -> Vec<(usize, usize)> {
    let mut chunks = Vec::new();
    let mut at = 8;
    while at + 12 <= data.len() {
        let length = u32::from_be_bytes([data[at], data[at + 1], data[at + 2], data[at + 3]]) as usize;
        if at + 12 + length > data.len() {
            break;
        }
        chunks.push((at, length));
        at += 12 + length;
    }
    chunks
}

/// A mutation that knows the format's header, so that the file still passes its checksums or
/// reaches the size fields: PNG (a field of a chunk, CRC fixed), JPEG (the frame header's
/// size and components), TGA (the header's sizes, type, depth and colour map).
fn mutate_header(rng: &mut Rng, data: &mut [u8], name: &str, log: &mut String) {
    let word = *rng.pick(WORDS);
    if data.starts_with(b"\x89PNG") {
        let chunks = png_chunks(data);
        let Some(&(at, length)) = chunks.get(rng.below(chunks.len().max(1))) else { return };
        let kind = [data[at + 4], data[at + 5], data[at + 6], data[at + 7]];
        let field = match (&kind, rng.below(4)) {
            (b"IHDR", 0) if length >= 8 => {
                data[at + 8..at + 12].copy_from_slice(&word.to_be_bytes());
                format!("IHDR width {word}")
            }
            (b"IHDR", 1) if length >= 8 => {
                data[at + 12..at + 16].copy_from_slice(&word.to_be_bytes());
                format!("IHDR height {word}")
            }
            (b"IHDR", 2) if length >= 13 => {
                let offset = at + 16 + rng.below(5);
                let value = *rng.pick(&[0u8, 1, 2, 3, 4, 6, 7, 8, 16, 255]);
                data[offset] = value;
                format!("IHDR byte {} = {value}", offset - at - 8)
            }
            _ if length > 0 => {
                let offset = at + 8 + rng.below(length);
                data[offset] = rng.next_u64() as u8;
                format!("byte {} of chunk {}", offset - at - 8, String::from_utf8_lossy(&kind))
            }
            _ => return,
        };
        let crc = crc32(&data[at + 4..at + 8 + length]);
        data[at + 8 + length..at + 12 + length].copy_from_slice(&crc.to_be_bytes());
        let _ = write!(log, "PNG {field}, CRC fixed; ");
    } else if data.starts_with(b"\xff\xd8") {
        let Some(sof) = (2..data.len().saturating_sub(9))
            .find(|&k| data[k] == 0xff && matches!(data[k + 1], 0xc0..=0xc2))
        else {
            return;
        };
        let value = (word as u16).to_be_bytes();
        match rng.below(4) {
            0 => data[sof + 5..sof + 7].copy_from_slice(&value),
            1 => data[sof + 7..sof + 9].copy_from_slice(&value),
            2 => data[sof + 9] = *rng.pick(&[0u8, 1, 2, 3, 4, 255]),
            _ => {
                let k = (sof + 11).min(data.len() - 1);
                data[k] = rng.next_u64() as u8;
            }
        }
        let _ = write!(log, "JPEG frame header with {word}; ");
    } else if name.ends_with(".tga") && data.len() >= 18 {
        match rng.below(5) {
            0 => data[12..14].copy_from_slice(&(word as u16).to_le_bytes()),
            1 => data[14..16].copy_from_slice(&(word as u16).to_le_bytes()),
            2 => data[2] = *rng.pick(&[0u8, 1, 2, 3, 9, 10, 11, 32, 33, 255]),
            3 => data[16] = *rng.pick(&[0u8, 1, 8, 15, 16, 24, 32, 255]),
            _ => {
                let k = 1 + rng.below(7);
                data[k] = word as u8;
            }
        }
        let _ = write!(log, "TGA header with {word}; ");
    }
}

// ---------------------------------------------------------------------------------------------
// Cases.

#[derive(Debug, Clone, Copy, PartialEq)]
enum Target {
    /// `Scene::load` on `scene.toml`.
    SceneToml,
    /// `Scene::load` on `model.obj`, with `model.mtl`.
    ObjScene,
    /// `Texture::load`.
    Texture(TextureUsage),
}

/// One case: the files to write (name in the case's folder, bytes), the file the loader is
/// given, the names of the files that were mutated, and what was done to them.
struct Case {
    target: Target,
    files: Vec<(String, Vec<u8>)>,
    input: String,
    mutated: Vec<String>,
    log: String,
}

/// `count` random mutations of `data`, mixing byte- and (for text) line-level ones.
fn mutate(rng: &mut Rng, data: &mut Vec<u8>, name: &str, corpus: &Corpus, text: bool, log: &mut String) {
    let _ = write!(log, "{name}: ");
    let most = if rng.one_in(4) { 8 } else { 3 };
    let count = 1 + rng.below(most);
    for _ in 0..count {
        if text && rng.one_in(2) {
            mutate_lines(rng, data, corpus, log);
        } else if !text && rng.one_in(3) {
            mutate_header(rng, data, name, log);
        } else {
            mutate_bytes(rng, data, corpus, text, log);
        }
        if data.len() > MAX_INPUT {
            data.truncate(MAX_INPUT);
            let _ = write!(log, "cut to {MAX_INPUT} bytes; ");
        }
    }
    log.push('\n');
}

/// The quoted names after `key = ` in a scene file (its OBJ files or texture maps).
fn named_files(text: &str, keys: &[&str]) -> Vec<(String, String)> {
    text.lines()
        .filter_map(|line| {
            let (key, value) = line.split_once('=')?;
            let key = key.trim();
            let value = value.trim().strip_prefix('"')?.split('"').next()?;
            keys.contains(&key).then(|| (key.to_string(), value.to_string()))
        })
        .collect()
}

fn build_case(corpus: &Corpus, rng: &mut Rng) -> Case {
    let mut log = String::new();
    let mut mutated = Vec::new();
    match rng.below(10) {
        0..=3 => {
            let seed = rng.pick(&corpus.scenes);
            let text = String::from_utf8_lossy(&seed.bytes).into_owned();
            let _ = writeln!(log, "seed {}", seed.name);
            let mut files: Vec<(String, Vec<u8>)> = Vec::new();
            for (_, name) in named_files(&text, &["obj"]) {
                let mesh = if name.contains("plane") || name.contains("grid") {
                    &corpus.grid
                } else {
                    &corpus.sphere
                };
                if !files.iter().any(|(n, _)| *n == name) {
                    files.push((name, mesh.clone()));
                }
            }
            for (key, name) in named_files(&text, &["kd_map", "albedo_map", "shininess_map", "roughness_map"])
            {
                let map = if key.ends_with("albedo_map") || key == "kd_map" {
                    &corpus.albedo_map
                } else {
                    &corpus.parameter_map
                };
                if !files.iter().any(|(n, _)| *n == name) {
                    files.push((name, map.clone()));
                }
            }
            let mut scene = seed.bytes.clone();
            if !rng.one_in(5) || files.is_empty() {
                mutate(rng, &mut scene, "scene.toml", corpus, true, &mut log);
                mutated.push("scene.toml".to_string());
            }
            if mutated.is_empty() || rng.one_in(6) {
                let k = rng.below(files.len());
                let (name, bytes) = &mut files[k];
                let text = name.ends_with(".obj");
                mutate(rng, bytes, name, corpus, text, &mut log);
                mutated.push(name.clone());
            }
            files.push(("scene.toml".into(), scene));
            Case { target: Target::SceneToml, files, input: "scene.toml".into(), mutated, log }
        }
        4..=6 => {
            let seed = rng.pick(&corpus.models);
            let _ = writeln!(log, "seed {}", seed.name);
            let mut model = seed.bytes.clone();
            let mut mtl = corpus.mtl.clone();
            let choice = rng.below(4);
            if choice != 0 {
                mutate(rng, &mut model, "model.obj", corpus, true, &mut log);
                mutated.push("model.obj".to_string());
            }
            if choice != 1 {
                mutate(rng, &mut mtl, "model.mtl", corpus, true, &mut log);
                mutated.push("model.mtl".to_string());
            }
            let files = vec![
                ("model.obj".into(), model),
                ("model.mtl".into(), mtl),
                ("textures/albedo.png".into(), corpus.albedo_map.clone()),
                ("textures/bump.png".into(), corpus.parameter_map.clone()),
            ];
            Case { target: Target::ObjScene, files, input: "model.obj".into(), mutated, log }
        }
        _ => {
            let seed = rng.pick(&corpus.textures);
            let _ = writeln!(log, "seed {}", seed.name);
            let usage = if rng.one_in(2) { TextureUsage::Albedo } else { TextureUsage::Parameter };
            let extension = if rng.one_in(8) {
                *rng.pick(&["png", "jpg", "jpeg", "tga", "exr", "bin"])
            } else {
                seed.name.rsplit('.').next().unwrap_or("png")
            };
            let name = format!("texture.{extension}");
            let mut bytes = seed.bytes.clone();
            mutate(rng, &mut bytes, &name, corpus, false, &mut log);
            mutated.push(name.clone());
            Case {
                target: Target::Texture(usage),
                files: vec![(name.clone(), bytes)],
                input: name,
                mutated,
                log,
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Running a case and checking what it gave.

/// What a loader made of a case, summarised on the case's thread.
enum Outcome {
    /// Loaded: the level-0 texels of the textures it holds, and any broken invariant.
    Loaded { texels: usize, broken: Vec<String> },
    /// Refused, with the error's message (and a note where the error lacks what it should have).
    Refused { message: String, missing: Option<String> },
}

fn load_case(target: Target, input: PathBuf) -> Outcome {
    match target {
        Target::SceneToml | Target::ObjScene => match Scene::load(&input) {
            Ok(scene) => {
                let mut broken = Vec::new();
                check_scene(&scene, &mut broken);
                let mut texels = 0;
                for material in &scene.materials {
                    let maps = [
                        material.maps.albedo.as_deref(),
                        material.maps.parameter.as_ref().map(|p| &*p.texture),
                    ];
                    for texture in maps.into_iter().flatten() {
                        texels += texture.width() as usize * texture.height() as usize;
                        check_texture(texture, &mut broken);
                    }
                }
                Outcome::Loaded { texels, broken }
            }
            Err(error) => {
                let missing = match &error {
                    SceneError::Parse { line: None, .. } => Some("a TOML error without a line".to_string()),
                    _ => None,
                };
                Outcome::Refused { message: error.to_string(), missing }
            }
        },
        Target::Texture(usage) => match Texture::load(&input, usage) {
            Ok(texture) => {
                let mut broken = Vec::new();
                check_texture(&texture, &mut broken);
                if texture.usage != usage {
                    broken.push(format!("usage {:?}, asked for {usage:?}", texture.usage));
                }
                Outcome::Loaded { texels: texture.width() as usize * texture.height() as usize, broken }
            }
            Err(error) => Outcome::Refused { message: error.to_string(), missing: None },
        },
    }
}

/// Notes in `broken` each documented invariant of a loaded scene that does not hold.
fn check_scene(scene: &Scene, broken: &mut Vec<String>) {
    let mut fail = |what: String| broken.push(what);
    let finite3 = |v: glam::Vec3| v.is_finite();
    if scene.meshes.is_empty() {
        fail("no meshes".into());
    }
    if !scene.origin.is_finite() {
        fail(format!("origin {}", scene.origin));
    }
    for (k, mesh) in scene.meshes.iter().enumerate() {
        let n = mesh.positions.len();
        if mesh.material >= scene.materials.len() {
            fail(format!("mesh {k}: material {} of {}", mesh.material, scene.materials.len()));
        }
        if let Some(p) = mesh.positions.iter().find(|p| !finite3(**p)) {
            fail(format!("mesh {k}: position {p}"));
        }
        if mesh.normals.len() != n {
            fail(format!("mesh {k}: {} normals for {n} positions", mesh.normals.len()));
        }
        if let Some(v) = mesh.normals.iter().find(|v| !(v.is_finite() && (v.length() - 1.0).abs() < 1e-3)) {
            fail(format!("mesh {k}: normal {v} is not unit length"));
        }
        if mesh.indices.is_empty() || mesh.indices.len() % 3 != 0 {
            fail(format!("mesh {k}: {} indices", mesh.indices.len()));
        }
        if let Some(i) = mesh.indices.iter().find(|&&i| i as usize >= n) {
            fail(format!("mesh {k}: index {i} of {n} positions"));
        }
        if !(mesh.uvs.is_empty() || mesh.uvs.len() == n) || mesh.uvs.iter().any(|uv| !uv.is_finite()) {
            fail(format!("mesh {k}: {} uvs for {n} positions, or one not finite", mesh.uvs.len()));
        }
    }
    let c = &scene.camera;
    let camera_ok = finite3(c.eye)
        && finite3(c.target)
        && c.eye != c.target
        && (c.up.length() - 1.0).abs() < 1e-3
        && c.fov_y_degrees > 0.0
        && c.fov_y_degrees < 180.0
        && c.near > 0.0
        && c.near < c.far
        && c.far.is_finite();
    if !camera_ok {
        fail(format!("camera {c:?}"));
    }
    let s = &scene.settings;
    let settings_ok = (1..=16384).contains(&s.width)
        && (1..=16384).contains(&s.height)
        && s.epsilon > 0.0
        && s.epsilon.is_finite()
        && (1..=64).contains(&s.n_max)
        && s.exposure > 0.0
        && s.exposure.is_finite()
        && finite3(s.clear_color)
        && s.clear_color.min_element() >= 0.0
        && (1..=256).contains(&s.light_sampling.samples)
        && (0.0..=1.0).contains(&s.light_sampling.mis_visibility);
    if !settings_ok {
        fail(format!("settings {s:?}"));
    }
    let unit = |v: glam::Vec3| finite3(v) && v.min_element() >= 0.0 && v.max_element() <= 1.0;
    for m in &scene.materials {
        let ok = match m.kind {
            MaterialKind::Lambert { kd } => unit(kd),
            MaterialKind::BlinnPhong { kd, ks, shininess } => {
                unit(kd) && unit(ks) && (1.0..=1.0e4).contains(&shininess)
            }
            MaterialKind::Ggx { albedo, f0, roughness } => {
                unit(albedo) && unit(f0) && (0.0..=1.0).contains(&roughness)
            }
        };
        if !ok || m.name.trim().is_empty() {
            fail(format!("material {:?}: {:?}", m.name, m.kind));
        }
    }
    if scene.lights.is_empty() {
        fail("no lights".into());
    }
    for light in &scene.lights {
        let ok = match light {
            Light::Point { position, color, intensity } => {
                finite3(*position) && finite3(*color) && color.min_element() >= 0.0 && *intensity >= 0.0
            }
            Light::Directional { direction, color, intensity } => {
                (direction.length() - 1.0).abs() < 1e-3
                    && finite3(*color)
                    && color.min_element() >= 0.0
                    && *intensity >= 0.0
            }
            Light::Polygon(p) => {
                (3..=p.vertices.len()).contains(&p.count)
                    && p.vertices().iter().all(|v| finite3(*v))
                    && p.area > 0.0
                    && p.area.is_finite()
                    && (p.normal.length() - 1.0).abs() < 1e-3
            }
        };
        if !ok || !light_intensity_finite(light) {
            fail(format!("light {light:?}"));
        }
    }
}

fn light_intensity_finite(light: &Light) -> bool {
    match light {
        Light::Point { intensity, .. } | Light::Directional { intensity, .. } => intensity.is_finite(),
        Light::Polygon(p) => p.intensity.is_finite() && p.color.is_finite(),
    }
}

/// Notes in `broken` where a loaded texture's mip chain is not as [`Texture`] documents it.
fn check_texture(texture: &Texture, broken: &mut Vec<String>) {
    let name = texture.path.display();
    let Some(first) = texture.levels.first() else {
        broken.push(format!("{name}: no levels"));
        return;
    };
    if !(1..=MAX_TEXTURE_SIZE).contains(&first.width) || !(1..=MAX_TEXTURE_SIZE).contains(&first.height) {
        broken.push(format!("{name}: level 0 is {}×{}", first.width, first.height));
    }
    if texture.usage == TextureUsage::Parameter
        && !(first.width.is_power_of_two() && first.height.is_power_of_two())
    {
        broken.push(format!("{name}: parameter map {}×{}", first.width, first.height));
    }
    for (k, level) in texture.levels.iter().enumerate() {
        let expected = level.width as usize * level.height as usize * texture.usage.bytes_per_texel();
        if level.texels.len() != expected {
            broken.push(format!("{name}: level {k} has {} bytes, not {expected}", level.texels.len()));
        }
        if let Some(next) = texture.levels.get(k + 1) {
            if (next.width, next.height) != ((level.width / 2).max(1), (level.height / 2).max(1)) {
                broken.push(format!("{name}: level {} is {}×{}", k + 1, next.width, next.height));
            }
        }
    }
    let last = texture.levels.last().map(|l| (l.width, l.height));
    if last != Some((1, 1)) {
        broken.push(format!("{name}: the chain ends at {last:?}"));
    }
}

/// A case's folder under the system's temporary folder, removed when dropped unless kept.
struct CaseDir {
    path: PathBuf,
    keep: bool,
}

impl CaseDir {
    fn new(seed: u64, index: u64) -> CaseDir {
        let path =
            std::env::temp_dir().join(format!("multirate-fuzz-{}-{seed:x}-{index}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        CaseDir { path, keep: false }
    }

    fn write(&self, name: &str, bytes: &[u8]) {
        let path = self.path.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).unwrap_or_else(|e| panic!("{}: {e}", parent.display()));
        }
        std::fs::write(&path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
}

impl Drop for CaseDir {
    fn drop(&mut self) {
        if !self.keep {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

/// What a run found and how it went.
#[derive(Default)]
struct Tally {
    cases: usize,
    loaded: usize,
    refused: usize,
    by_target: [usize; 3],
    slowest: (Duration, u64),
    largest_peak: (usize, u64),
    failures: Vec<String>,
    failed_cases: usize,
}

/// Runs case `index` of the run with `seed` and checks it; a failure goes into `tally` with
/// what reproduces it.
fn run_case(corpus: &Corpus, seed: u64, index: u64, verbose: bool, tally: &mut Tally) {
    let mut rng = Rng::for_case(seed, index);
    let case = build_case(corpus, &mut rng);
    let mut dir = CaseDir::new(seed, index);
    for (name, bytes) in &case.files {
        dir.write(name, bytes);
    }
    let input = dir.path.join(&case.input);
    let target = case.target;
    let tracked = run_tracked((seed, index), {
        let input = input.clone();
        move || load_case(target, input)
    });

    let mut problems = Vec::new();
    match tracked {
        Err(limit) => problems.push(format!("did not return within {limit:?} (hung)")),
        Ok(tracked) => {
            if tracked.elapsed > tally.slowest.0 {
                tally.slowest = (tracked.elapsed, index);
            }
            if tracked.peak > tally.largest_peak.0 {
                tally.largest_peak = (tracked.peak, index);
            }
            if let Some(note) = &tracked.panic {
                problems.push(format!("panicked: {note}"));
            }
            if tracked.elapsed > CASE_LIMIT {
                problems.push(format!("took {:?}, more than {CASE_LIMIT:?}", tracked.elapsed));
            }
            let mut allowed = MEMORY_LIMIT;
            match &tracked.value {
                Err(message) => problems.push(format!("unwound with {message}")),
                Ok(Outcome::Loaded { texels, broken }) => {
                    if verbose {
                        println!("case {index}: {}: loaded", case.input);
                    }
                    tally.loaded += 1;
                    allowed += BYTES_PER_LOADED_TEXEL * texels;
                    problems.extend(broken.iter().map(|b| format!("loaded, but {b}")));
                }
                Ok(Outcome::Refused { message, missing }) => {
                    if verbose {
                        println!("case {index}: refused: {message}");
                    }
                    tally.refused += 1;
                    let names_input = message.contains(&input.display().to_string());
                    let names_culprit = case
                        .files
                        .iter()
                        .any(|(name, _)| message.starts_with(&dir.path.join(name).display().to_string()));
                    if !(names_input || names_culprit) {
                        problems
                            .push(format!("refused with a message that names none of its files: {message}"));
                    }
                    if let Some(missing) = missing {
                        problems.push(format!("refused with {missing}: {message}"));
                    }
                }
            }
            if tracked.peak > allowed {
                problems.push(format!("peak {} bytes live, more than the {allowed} allowed", tracked.peak));
            }
        }
    }
    tally.cases += 1;
    tally.by_target[match target {
        Target::SceneToml => 0,
        Target::ObjScene => 1,
        Target::Texture(_) => 2,
    }] += 1;
    if !problems.is_empty() {
        tally.failed_cases += 1;
        dir.keep = true;
        if tally.failures.len() < 12 {
            let mut report = format!(
                "case {index} of seed {seed} ({target:?}, input {}): {}\n  rerun: MULTIRATE_FUZZ_SEED={seed} \
                 MULTIRATE_FUZZ_CASE={index} cargo test --release --test fuzz_loaders -- --nocapture\n  files kept in {}\n  mutations:\n",
                case.input,
                problems.join("; "),
                dir.path.display()
            );
            for line in case.log.lines() {
                let _ = writeln!(report, "    {}", shorten(line, 600));
            }
            for name in &case.mutated {
                if let Some((_, bytes)) = case.files.iter().find(|(n, _)| n == name) {
                    let _ = writeln!(
                        report,
                        "  {name} ({} bytes): {}",
                        bytes.len(),
                        shorten(&bytes.escape_ascii().to_string(), 1500)
                    );
                }
            }
            tally.failures.push(report);
        }
    }
}

fn shorten(text: &str, at: usize) -> String {
    if text.len() <= at {
        return text.to_string();
    }
    let mut end = at;
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}... ({} bytes in all)", &text[..end], text.len())
}

fn env_number(name: &str) -> Option<u64> {
    let value = std::env::var(name).ok()?;
    let value = value.trim();
    let parsed = match value.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => value.parse(),
    };
    Some(parsed.unwrap_or_else(|_| panic!("{name}={value} is not a number")))
}

// ---------------------------------------------------------------------------------------------
// The tests.

/// The mutation loop: [`DEFAULT_CASES`] cases, or as the environment says (see the header).
#[test]
fn loaders_survive_mutated_input() {
    let corpus = Corpus::new();
    let seed = env_number("MULTIRATE_FUZZ_SEED").unwrap_or(DEFAULT_SEED);
    let (first, cases) = match env_number("MULTIRATE_FUZZ_CASE") {
        Some(index) => (index, 1),
        None => (0, env_number("MULTIRATE_FUZZ_CASES").unwrap_or(DEFAULT_CASES as u64)),
    };
    let seconds = env_number("MULTIRATE_FUZZ_SECONDS").map(Duration::from_secs);
    let budget = RUN_BUDGET + MEAN_CASE_BUDGET * cases.min(u32::MAX as u64) as u32;
    let budget = seconds.map_or(budget, |s| s + RUN_BUDGET);
    let start = Instant::now();
    let mut tally = Tally::default();
    for index in first..first + cases {
        if seconds.is_some_and(|s| start.elapsed() >= s) {
            break;
        }
        run_case(&corpus, seed, index, cases == 1, &mut tally);
        if cases >= 10_000 && (index - first + 1) % 10_000 == 0 {
            println!(
                "fuzz_loaders: {} cases in {:.0} s, {} failed",
                index - first + 1,
                start.elapsed().as_secs_f64(),
                tally.failed_cases
            );
        }
    }
    let elapsed = start.elapsed();
    println!(
        "fuzz_loaders: seed {seed:#x}: {} cases ({} scene TOML, {} OBJ scene, {} texture) in {:.1} s: \
         {} loaded, {} refused, {} failed; slowest case {} ({:?}), largest peak {:.1} MiB (case {})",
        tally.cases,
        tally.by_target[0],
        tally.by_target[1],
        tally.by_target[2],
        elapsed.as_secs_f64(),
        tally.loaded,
        tally.refused,
        tally.failed_cases,
        tally.slowest.1,
        tally.slowest.0,
        tally.largest_peak.0 as f64 / (1 << 20) as f64,
        tally.largest_peak.1,
    );
    assert!(
        tally.failures.is_empty(),
        "{} of {} cases failed; the first ones:\n{}",
        tally.failed_cases,
        tally.cases,
        tally.failures.join("\n")
    );
    assert!(elapsed <= budget, "{} cases took {elapsed:?}, more than the budget of {budget:?}", tally.cases);
    assert!(tally.cases as u64 == cases || seconds.is_some(), "{} of {cases} cases ran", tally.cases);
    if cases >= 1000 {
        // Mutations of valid files mostly make invalid ones, but not all: both kinds are tried.
        assert!(
            tally.loaded * 50 >= tally.cases && tally.refused * 4 >= tally.cases,
            "{} loaded, {} refused",
            tally.loaded,
            tally.refused
        );
    }
}

/// Every seed loads as it is: the mutations start from valid files.
#[test]
fn the_seeds_load_unmutated() {
    let corpus = Corpus::new();
    let dir = CaseDir::new(0, u64::MAX);
    let mut seeds = Vec::new();
    for seed in &corpus.scenes {
        let text = String::from_utf8_lossy(&seed.bytes).into_owned();
        let folder = seed.name.trim_end_matches(".toml");
        for (_, name) in named_files(&text, &["obj"]) {
            let mesh =
                if name.contains("plane") || name.contains("grid") { &corpus.grid } else { &corpus.sphere };
            dir.write(&format!("{folder}/{name}"), mesh);
        }
        for (key, name) in named_files(&text, &["kd_map", "albedo_map", "shininess_map", "roughness_map"]) {
            let map = if key == "kd_map" || key == "albedo_map" {
                &corpus.albedo_map
            } else {
                &corpus.parameter_map
            };
            dir.write(&format!("{folder}/{name}"), map);
        }
        dir.write(&format!("{folder}/scene.toml"), &seed.bytes);
        seeds.push((Target::SceneToml, format!("{folder}/scene.toml")));
    }
    for seed in &corpus.models {
        dir.write(&format!("{}/model.obj", seed.name), &seed.bytes);
        dir.write(&format!("{}/model.mtl", seed.name), &corpus.mtl);
        dir.write(&format!("{}/textures/albedo.png", seed.name), &corpus.albedo_map);
        seeds.push((Target::ObjScene, format!("{}/model.obj", seed.name)));
    }
    for seed in &corpus.textures {
        dir.write(&seed.name, &seed.bytes);
        seeds.push((Target::Texture(TextureUsage::Albedo), seed.name.clone()));
    }
    for (target, name) in seeds {
        match load_case(target, dir.path.join(&name)) {
            Outcome::Loaded { broken, .. } => assert!(broken.is_empty(), "{name}: {broken:?}"),
            Outcome::Refused { message, .. } => panic!("the seed {name} does not load: {message}"),
        }
    }
}

/// The harness itself: the allocator counts, and a panic caught inside the closure is seen.
#[test]
fn the_harness_counts_memory_and_sees_caught_panics() {
    let tracked = run_tracked((0, 0), || {
        let big = vec![1u8; 10 << 20];
        big.iter().map(|&b| b as usize).sum::<usize>()
    })
    .expect("returns at once");
    assert_eq!(tracked.value.as_ref().ok(), Some(&(10 << 20)));
    assert!(tracked.peak >= 10 << 20 && tracked.peak < 11 << 20, "peak {}", tracked.peak);
    assert!(tracked.panic.is_none());

    let tracked = run_tracked((0, 1), || std::panic::catch_unwind(|| panic!("deliberate")).is_err())
        .expect("returns at once");
    assert_eq!(tracked.value.ok(), Some(true));
    assert!(tracked.panic.is_some_and(|p| p.contains("deliberate")));
}

/// Runs `load` on a counted thread and returns its error message and peak bytes; fails if it
/// loads, panics, or takes more than [`CASE_LIMIT`].
fn refused(what: &str, load: impl FnOnce() -> Result<(), String> + Send + 'static) -> (String, usize) {
    let tracked = run_tracked((0, 0), load).unwrap_or_else(|_| panic!("{what}: hung"));
    assert!(tracked.panic.is_none(), "{what}: {:?}", tracked.panic);
    assert!(tracked.elapsed < CASE_LIMIT, "{what}: took {:?}", tracked.elapsed);
    match tracked.value {
        Ok(Err(message)) => (message, tracked.peak),
        Ok(Ok(())) => panic!("{what}: loaded"),
        Err(message) => panic!("{what}: panicked: {message}"),
    }
}

fn texture_error(path: PathBuf, usage: TextureUsage) -> Result<(), String> {
    Texture::load(&path, usage).map(|_| ()).map_err(|e| e.to_string())
}

/// The sizes a texture file declares are checked before anything of that size is allocated:
/// the inputs the fuzzing found (a PNG 8×11,927,560 in 73 bytes took 91 MiB; a 353-byte JPEG
/// of 16384×4096 took 405 MiB and 21 s) and the declared sizes around the limits.
#[test]
fn declared_texture_sizes_are_checked_before_allocating() {
    let dir = CaseDir::new(1, u64::MAX);
    let png = read("scenes/textures/checker_8.png");
    let png_sized = |width: u32, height: u32, depth: u8, colour: u8| {
        let mut bytes = png.clone();
        bytes[16..20].copy_from_slice(&width.to_be_bytes());
        bytes[20..24].copy_from_slice(&height.to_be_bytes());
        bytes[24] = depth;
        bytes[25] = colour;
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        bytes
    };
    let jpeg_sized = |width: u16, height: u16| {
        let mut bytes = jpeg_seed(8, 16, true);
        let sof = (2..bytes.len() - 9).find(|&k| bytes[k] == 0xff && bytes[k + 1] == 0xc0).expect("SOF0");
        bytes[sof + 5..sof + 7].copy_from_slice(&height.to_be_bytes());
        bytes[sof + 7..sof + 9].copy_from_slice(&width.to_be_bytes());
        bytes
    };
    let tga_sized = |width: u16, height: u16| {
        let mut bytes = tga_seed(TgaKind::TrueColour);
        bytes[12..14].copy_from_slice(&width.to_le_bytes());
        bytes[14..16].copy_from_slice(&height.to_le_bytes());
        bytes
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("tall.png", png_sized(8, 11_927_560, 8, 0), "8×11927560 is too large"),
        ("huge.png", png_sized(60_000, 60_000, 8, 6), "60000×60000 is too large"),
        ("edge.png", png_sized(16384, 16384, 8, 0), "declares 16384×16384 texels"),
        ("edge16.png", png_sized(4096, 4096, 16, 6), "declares 4096×4096 texels"),
        ("long.jpg", jpeg_sized(16384, 4096), "declares 16384×4096 texels"),
        ("wide.jpg", jpeg_sized(60000, 8), "60000×8 is too large"),
        ("huge.tga", tga_sized(65535, 65535), "65535×65535 is too large"),
        ("edge.tga", tga_sized(16384, 16384), "declares 16384×16384 texels"),
        ("image.exr", b"v/1\x01\x02\0\0\0channels\0".to_vec(), "is an OpenExr image"),
    ];
    for (name, bytes, expected) in cases {
        dir.write(name, &bytes);
        let path = dir.path.join(name);
        for usage in [TextureUsage::Albedo, TextureUsage::Parameter] {
            let (message, peak) = refused(name, {
                let path = path.clone();
                move || texture_error(path, usage)
            });
            assert!(message.starts_with(&path.display().to_string()), "{name}: {message}");
            assert!(message.contains(expected), "{name}: {message}");
            assert!(peak < 1 << 20, "{name}: {peak} bytes live before it was refused");
        }
    }
    // The same files, whole, still load: the check refuses only what cannot be complete.
    for seed in Corpus::new().textures {
        let path = dir.path.join(&seed.name);
        dir.write(&seed.name, &seed.bytes);
        assert!(Texture::load(&path, TextureUsage::Albedo).is_ok(), "{}", seed.name);
    }
}

/// Folders and devices are refused without being read: `/dev/zero` as a mesh, a scene, a
/// texture or a material library would otherwise be read until memory runs out.
#[cfg(unix)]
#[test]
fn devices_and_folders_are_refused_unread() {
    let dir = CaseDir::new(2, u64::MAX);
    let corpus = Corpus::new();
    let scene = String::from_utf8_lossy(&corpus.scenes[0].bytes).into_owned();
    let (_, obj) = named_files(&scene, &["obj"]).into_iter().next().expect("a mesh");
    for (name, target) in [("dev_zero.toml", "/dev/zero"), ("folder.toml", "textures")] {
        let path = dir.path.join(name);
        dir.write(name, scene.replace(&obj, target).as_bytes());
        dir.write("textures/albedo.png", &corpus.albedo_map);
        let (message, peak) = refused(name, {
            let path = path.clone();
            move || Scene::load(&path).map(|_| ()).map_err(|e| e.to_string())
        });
        assert!(message.contains(&path.display().to_string()), "{message}");
        assert!(message.contains("not a regular file"), "{message}");
        assert!(peak < 1 << 20, "{name}: {peak} bytes live");
    }
    let (message, _) =
        refused("/dev/zero as a texture", || texture_error("/dev/zero".into(), TextureUsage::Albedo));
    assert!(message.starts_with("/dev/zero: cannot read file") && message.contains("device"), "{message}");
    let (message, _) = refused("/dev/zero as a scene", || {
        Scene::load(Path::new("/dev/zero")).map(|_| ()).map_err(|e| e.to_string())
    });
    assert!(message.starts_with("/dev/zero: cannot read file"), "{message}");

    // A material library or `map_Kd` that is a device stands aside with a warning.
    dir.write("model.obj", format!("mtllib /dev/zero\nmtllib model.mtl\n{CUBE_OBJ}").as_bytes());
    dir.write("model.mtl", MODEL_MTL.replace("textures\\albedo.png", "/dev/zero").as_bytes());
    let path = dir.path.join("model.obj");
    let tracked = run_tracked((0, 0), move || Scene::load(&path).map(|s| s.warnings)).expect("returns");
    let warnings = tracked.value.expect("no panic").expect("the model loads");
    assert!(warnings.iter().any(|w| w.contains("/dev/zero") && w.contains("library")), "{warnings:?}");
    assert!(warnings.iter().any(|w| w.contains("map_Kd") && w.contains("/dev/zero")), "{warnings:?}");
    assert!(tracked.peak < 16 << 20, "{} bytes live", tracked.peak);
}

/// An OBJ model so large that the framed camera's lights leave f32 (found by the fuzzing: a
/// coordinate of 2⁶³ gave point lights of infinite intensity) is refused, naming the file.
#[test]
fn a_model_too_large_to_frame_is_refused() {
    let dir = CaseDir::new(3, u64::MAX);
    dir.write("far.obj", "v 0 0 0\nv 9223372036854775807 0 0\nv 0 1 0\nf 1 2 3\n".as_bytes());
    let path = dir.path.join("far.obj");
    let (message, _) = refused("far.obj", {
        let path = path.clone();
        move || Scene::load(&path).map(|_| ()).map_err(|e| e.to_string())
    });
    assert!(message.starts_with(&path.display().to_string()), "{message}");
    assert!(message.contains("too large to frame"), "{message}");
    // A large model that f32 still holds is framed with finite lights.
    dir.write("large.obj", "v 0 0 0\nv 1e15 0 0\nv 0 1e15 0\nf 1 2 3\n".as_bytes());
    let scene = Scene::load(&dir.path.join("large.obj")).expect("loads");
    let mut broken = Vec::new();
    check_scene(&scene, &mut broken);
    assert!(broken.is_empty(), "{broken:?}");
}
