//! Fuzzing of the loaders of `src/scene/` on the CPU (no Vulkan): the scene TOML loader
//! (`Scene::load`), an OBJ file given as the scene with its MTL library (`obj_scene`), and the
//! texture loader (`Texture::load`: PNG, JPEG, TGA).
//!
//! This test (its files: `allocator.rs`, `corpus.rs`, `mutations.rs`, `cases.rs`, `checks.rs`, and
//! the tests here) owns the deterministic mutation loop, its seed corpus (built from the shipped
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

mod allocator;
mod cases;
mod checks;
#[path = "../common/mod.rs"]
mod common;
mod corpus;
mod mutations;

use allocator::*;
use cases::*;
use checks::*;
use corpus::*;
use mutations::*;

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
pub(crate) const DEFAULT_CASES: usize = 2000;
/// The seed without `MULTIRATE_FUZZ_SEED`.
pub(crate) const DEFAULT_SEED: u64 = 0x6d75_6c74_6972_6174;
/// What one case may take, checked after it returns: every input is at most a few hundred
/// kilobytes, which every loader reads in milliseconds.
pub(crate) const CASE_LIMIT: Duration = Duration::from_secs(5);
/// After this long a case is declared hung and the run fails without waiting for it.
pub(crate) const HANG_LIMIT: Duration = Duration::from_secs(30);
/// The time budget of a run: this much, plus [`MEAN_CASE_BUDGET`] per case.
pub(crate) const RUN_BUDGET: Duration = Duration::from_secs(60);
pub(crate) const MEAN_CASE_BUDGET: Duration = Duration::from_millis(50);
/// The largest file a case writes: mutations that grow a file past it are cut there.
pub(crate) const MAX_INPUT: usize = 300_000;
/// Peak live bytes a case may reach, besides the textures it loads. The inputs are at most
/// [`MAX_INPUT`] bytes (the seeds are under 12 kB, a mutation adds at most 100 kB) and a
/// loaded test scene takes about a megabyte, so 64 MiB is room for the loaders' working copies,
/// not for anything an input declares: a file that declares a large image or mesh must be
/// refused before that is allocated.
pub(crate) const MEMORY_LIMIT: usize = 64 << 20;
/// Peak bytes a successfully loaded texture may add per level-0 texel: the decoded image (at
/// most 8 bytes a texel, RGBA16), its RGBA8 copy (4) and the mip chain (4/3 of that), or the
/// luma copy, chain and min/max pyramid of a parameter map.
pub(crate) const BYTES_PER_LOADED_TEXEL: usize = 16;
/// A case whose thread would hold more than this is stopped at once (the process aborts with
/// the case named on standard error), before it can exhaust the machine's memory.
pub(crate) const HARD_CAP: isize = 1 << 30;

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
