//! The `multirate` binary end to end: a successful render with validation, the default scene
//! found from any working directory, and bad inputs that must fail with a message naming the
//! file and the problem, never a panic. Also, through
//! the library (lavapipe, validation layer on and silent): scenes over a device limit, and
//! allocations over a heap, refused with an error naming the scene or resource and the limit
//! before Vulkan sees them.

mod common;

use ash::vk;
use common::{assert_validation_clean, repo_path, validated_context};
use gpu_allocator::MemoryLocation;
use multirate::error::mib;
use multirate::render::limits::SceneSizes;
use multirate::render::Renderer;
use multirate::scene::Scene;
use multirate::vk::context::DeviceLimits;
use multirate::vk::memory::{Buffer, Image};
use multirate::vk::Context;
use multirate::Error;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli").join(name);
    std::fs::create_dir_all(&dir).expect("create scratch folder");
    dir
}

fn multirate(args: &[&str]) -> (bool, String, String) {
    let output =
        common::multirate_command().args(args).env_remove("DISPLAY").output().expect("run multirate");
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// Every subcommand that has a default scene finds it from any working directory (the
/// source tree's `scenes/bunny.toml` when the directory has no `scenes/`): the default its
/// `--help` shows is a file that exists.
#[test]
fn default_scenes_exist_from_any_working_directory() {
    let elsewhere = scratch("elsewhere");
    for subcommand in ["view", "calibrate"] {
        let output = common::multirate_command()
            .args([subcommand, "--help"])
            .current_dir(&elsewhere)
            .output()
            .expect("run multirate");
        let help = String::from_utf8_lossy(&output.stdout);
        let default = help
            .lines()
            .find_map(|line| line.rsplit_once("[default: ")?.1.strip_suffix(".toml]"))
            .unwrap_or_else(|| panic!("{subcommand} --help names no default scene:\n{help}"));
        let path = elsewhere.join(format!("{default}.toml"));
        assert!(path.is_file(), "{subcommand}: the default scene {} does not exist", path.display());
    }
}

/// Runs `render` on `scene` and asserts it fails cleanly with every `expected` text in stderr.
fn assert_render_fails(scene: &Path, expected: &[&str]) {
    let out = scratch("failures").join("never.png");
    let (ok, _, stderr) =
        multirate(&["render", "--scene", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!ok, "rendering {} should fail", scene.display());
    assert!(!stderr.contains("panicked"), "panic instead of an error:\n{stderr}");
    for text in expected {
        assert!(stderr.contains(text), "stderr lacks {text:?}:\n{stderr}");
    }
    assert!(!out.exists(), "a failed render must not leave an image");
}

const VALID_SCENE: &str = r#"
description = "one triangle"
source = "written by the test"
[camera]
eye = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 50.0
[[materials]]
name = "grey"
type = "lambert"
kd = [0.5, 0.5, 0.5]
[[meshes]]
obj = "MESH"
material = "grey"
[[lights]]
type = "directional"
direction = [0.0, 0.0, -1.0]
color = [1.0, 1.0, 1.0]
intensity = 1.0
"#;

fn write_scene(name: &str, toml: &str, obj: Option<&str>) -> PathBuf {
    let dir = scratch(name);
    let mesh = dir.join("mesh.obj");
    if let Some(obj) = obj {
        std::fs::write(&mesh, obj).unwrap();
    }
    let path = dir.join("scene.toml");
    std::fs::write(&path, toml.replace("MESH", "mesh.obj")).unwrap();
    path
}

const TRIANGLE: &str = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";

/// `multirate --validate render` of `scene` into `out` at 64 × 48, with `extra` arguments.
fn render_64x48(scene: &Path, out: &Path, extra: &[&str]) -> (bool, String, String) {
    let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let size = ["--width", "64", "--height", "48"];
    multirate(&[&["--validate", "render", "--scene", scene, "--out", out][..], &size, extra].concat())
}

#[test]
fn renders_png_and_exr_with_coverage() {
    let scene = repo_path("scenes/test/lambert_directional.toml");
    let dir = scratch("success");
    let png = dir.join("out.png");
    let exr = dir.join("out.exr");
    for out in [&png, &exr] {
        let (ok, stdout, stderr) = render_64x48(&scene, out, &[]);
        assert!(ok, "render failed:\n{stderr}");
        assert!(stdout.contains(out.to_str().unwrap()), "prints where the image went: {stdout}");
        assert!(stdout.contains("mode multirate"), "multirate without --mode: {stdout}");
        assert!(!stderr.contains("vulkan:"), "validation messages:\n{stderr}");
    }
    let png = image::open(&png).expect("PNG decodes").to_rgba8();
    assert_eq!(png.dimensions(), (64, 48));
    let exr = image::open(&exr).expect("EXR decodes").to_rgba32f();
    assert_eq!(exr.dimensions(), (64, 48));
    let covered = exr.pixels().filter(|p| p.0[3] == 1.0).count();
    let empty = exr.pixels().filter(|p| p.0[3] == 0.0).count();
    assert_eq!(covered + empty, 64 * 48, "alpha is exactly coverage: 0 or 1");
    assert!(covered > 0 && empty > 0, "the test scene shows surface and background");
    assert!(exr.pixels().filter(|p| p.0[3] == 1.0).any(|p| p.0[0] > 0.0), "lit surface");
}

/// `render --post`: the PNG through the post chain differs from the plain tone map of the same
/// frame; along a path every frame is written; an EXR is refused by name.
#[test]
fn renders_through_the_post_chain() {
    let scene = repo_path("scenes/test/lambert_directional.toml");
    let dir = scratch("post");
    let (plain, post) = (dir.join("plain.png"), dir.join("post.png"));
    for (out, extra) in [(&plain, &[][..]), (&post, &["--post"][..])] {
        let (ok, _, stderr) = render_64x48(&scene, out, extra);
        assert!(ok && !stderr.contains("vulkan:"), "render {extra:?} failed:\n{stderr}");
    }
    let (plain, post) = (image::open(&plain).unwrap().to_rgba8(), image::open(&post).unwrap().to_rgba8());
    assert_eq!(post.dimensions(), (64, 48));
    let differ = plain.pixels().zip(post.pixels()).filter(|(p, q)| p.0 != q.0).count();
    assert!(differ > 100, "the post chain changed only {differ} pixels");
    let frames = dir.join("shot.png");
    let (ok, stdout, stderr) =
        render_64x48(&scene, &frames, &["--post", "--path", "orbit:0.2", "--fps", "10"]);
    assert!(ok && stdout.contains("(3 frames)"), "render --post --path failed:\n{stdout}\n{stderr}");
    assert!(dir.join("shot_0002.png").exists());
    let (ok, _, stderr) = render_64x48(&scene, &dir.join("post.exr"), &["--post"]);
    assert!(!ok && stderr.contains("--post writes PNG"), "{stderr}");
}

/// `render --path`: an orbit's frames, numbered, each a turn of the camera (the frames differ,
/// the first and the last, a whole turn apart, agree), in a folder it makes; a scene without a
/// path is refused by name.
#[test]
fn renders_a_camera_path_into_numbered_frames() {
    let scene = repo_path("scenes/bunny.toml");
    let dir = scratch("path").join("frames");
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("shot.png");
    let (ok, stdout, stderr) = render_64x48(&scene, &out, &["--path", "orbit:0.3", "--fps", "10"]);
    assert!(ok, "render --path failed:\n{stderr}");
    assert!(stdout.contains("(4 frames)"), "{stdout}");
    assert!(!stderr.contains("vulkan:"), "validation messages:\n{stderr}");
    let frame =
        |k: usize| image::open(dir.join(format!("shot_{k:04}.png"))).expect("frame decodes").to_rgba8();
    assert!(!dir.join("shot_0004.png").exists(), "no frame past the path");
    // Pixels that differ by more than rounding between two frames.
    let differ = |a: usize, b: usize| {
        let (a, b) = (frame(a), frame(b));
        a.pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 2))
            .count()
    };
    let (turned, round) = (differ(0, 1), differ(0, 3));
    assert!(turned > 100, "the camera turns between frames: {turned} pixels differ");
    assert!(round * 20 < turned, "a whole turn comes back to the first frame: {round} pixels differ");
    let (ok, _, stderr) = multirate(&[
        "render",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--path",
        "scene",
    ]);
    assert!(!ok && stderr.contains("bunny.toml") && stderr.contains("no camera path"), "{stderr}");
}

/// `demo` on the chapel's path (the room's takes minutes): every mode timed along the path,
/// their stability, the frames kept through the post chain, and a page that shows them; a scene
/// without a path is refused, naming it.
#[test]
fn the_demo_writes_its_page_plot_stability_and_frames() {
    let dir = scratch("demo");
    let scene = repo_path("scenes/chapel.toml");
    let (ok, _, stderr) = multirate(&[
        "--validate",
        "demo",
        "--scene",
        scene.to_str().unwrap(),
        "--resolution",
        "64x36",
        "--still-size",
        "64x36",
        "--fps",
        "0.5",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "demo failed:\n{stderr}");
    assert!(!stderr.contains("vulkan:"), "validation messages:\n{stderr}");
    let page = std::fs::read_to_string(dir.join("README.md")).expect("the page");
    // The chapel's path lasts 8 s: 5 frames at one every 2 s, each kept.
    for mode in ["| pixel | 5 |", "| vertex | 5 |", "| fixed:4 | 5 |", "| multirate ε=0.075"] {
        assert!(page.contains(mode), "{mode} in the timing table:\n{page}");
    }
    for run in ["chapel 64x36 vertex |", "chapel 64x36 fixed:4 |", "chapel 64x36 multirate"] {
        assert!(page.contains(run), "{run} in the stability table:\n{page}");
    }
    assert!(page.contains("![GPU time per frame along the path](path.svg)"), "{page}");
    let svg = std::fs::read_to_string(dir.join("path.svg")).expect("the plot");
    assert!(svg.contains("<svg"), "{svg}");
    let stability = std::fs::read_to_string(dir.join("stability.csv")).expect("stability.csv");
    assert_eq!(stability.lines().count(), 1 + 3 * 4, "three configurations, four steps each:\n{stability}");
    for k in 0..5 {
        let frame = dir.join("frames").join(format!("frame_{k:04}.png"));
        assert!(page.contains(&format!("frames/frame_{k:04}.png")), "{page}");
        let image = image::open(&frame).expect("a kept frame decodes").to_rgba8();
        assert_eq!(image.dimensions(), (64, 36));
        assert!(image.pixels().any(|p| p.0[..3].iter().any(|&c| c > 20)), "frame {k} is not black");
    }
    assert!(!dir.join("frames").join("frame_0005.png").exists(), "no frame past the path");
    let without = repo_path("scenes/bunny.toml");
    let (ok, _, stderr) =
        multirate(&["demo", "--scene", without.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert!(!ok && stderr.contains("bunny.toml") && stderr.contains("no [[path]]"), "{stderr}");
}

#[test]
fn missing_scene_names_the_file() {
    let missing = scratch("missing").join("no-such-scene.toml");
    assert_render_fails(&missing, &["no-such-scene.toml", "cannot read"]);
}

#[test]
fn malformed_toml_names_the_file_and_line() {
    let path = write_scene("malformed", "description = \"x\"\n[camera\neye = [0, 0, 1]\n", Some(TRIANGLE));
    assert_render_fails(&path, &[path.to_str().unwrap(), "line 2"]);
}

#[test]
fn unknown_key_names_the_file_and_key() {
    let toml = VALID_SCENE.replace("kd = [0.5, 0.5, 0.5]", "kd = [0.5, 0.5, 0.5]\ncolour = [1.0, 0.0, 0.0]");
    let path = write_scene("unknown-key", &toml, Some(TRIANGLE));
    assert_render_fails(&path, &[path.to_str().unwrap(), "colour"]);
}

#[test]
fn missing_mesh_names_the_obj() {
    let path = write_scene("missing-mesh", VALID_SCENE, None);
    assert_render_fails(&path, &["mesh.obj"]);
}

#[test]
fn nan_coordinates_name_the_obj() {
    let obj = "v -1 -1 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n";
    let path = write_scene("nan", VALID_SCENE, Some(obj));
    assert_render_fails(&path, &["mesh.obj", "NaN"]);
}

#[test]
fn unknown_material_is_named() {
    let toml = VALID_SCENE.replace("material = \"grey\"", "material = \"steel\"");
    let path = write_scene("unknown-material", &toml, Some(TRIANGLE));
    assert_render_fails(&path, &[path.to_str().unwrap(), "steel"]);
}

#[test]
fn unknown_output_format_is_named() {
    let scene = repo_path("scenes/test/lambert_directional.toml");
    let out = scratch("format").join("image.bmp");
    let (ok, _, stderr) =
        multirate(&["render", "--scene", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!ok && !stderr.contains("panicked"));
    assert!(stderr.contains("image.bmp") && stderr.contains(".png or .exr"), "{stderr}");
}

#[test]
fn unknown_mode_is_rejected_by_the_parser() {
    let scene = repo_path("scenes/test/lambert_directional.toml");
    let (ok, _, stderr) =
        multirate(&["render", "--scene", scene.to_str().unwrap(), "--out", "x.png", "--mode", "sparkly"]);
    assert!(!ok && !stderr.contains("panicked"));
    assert!(stderr.contains("sparkly"), "{stderr}");
}

#[test]
fn analyze_writes_one_row_per_visible_triangle() {
    let scene = repo_path("scenes/test/lambert_directional.toml");
    let out = scratch("analyze").join("triangles.csv");
    let (ok, stdout, stderr) = multirate(&[
        "analyze",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--oracle",
        "--epsilon",
        "0.05",
    ]);
    assert!(ok, "analyze failed:\n{stderr}");
    let csv = std::fs::read_to_string(&out).expect("CSV written");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    for column in ["mesh", "triangle", "n", "fallback", "predicted_error", "oracle_n", "true_error"] {
        assert!(header.contains(&column), "column {column} missing: {header:?}");
    }
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(!rows.is_empty() && rows.len() <= 320, "the icosphere has 320 triangles: {} rows", rows.len());
    let fallback = header.iter().position(|c| *c == "fallback").unwrap();
    let error = header.iter().position(|c| *c == "true_error").unwrap();
    for row in &rows {
        assert_eq!(row.len(), header.len(), "every column filled: {row:?}");
        if row[fallback] == "false" {
            let true_error: f64 = row[error].parse().expect("true error of a tessellated triangle");
            assert!(true_error <= 0.05, "the estimator's level keeps the true error under ε: {row:?}");
        }
    }
    assert!(stdout.contains("shading evaluations"), "prints a summary: {stdout}");
    assert!(stdout.contains("exceeds ε: 0"), "no violations on the shipped scene: {stdout}");
}

#[test]
fn analyze_reports_each_shadow_casting_lights_classes() {
    let scene = repo_path("scenes/shadows.toml");
    let out = scratch("analyze_shadows").join("triangles.csv");
    let (ok, stdout, stderr) =
        multirate(&["analyze", "--scene", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(ok, "analyze failed:\n{stderr}");
    let triangles = |line: &str| -> usize {
        ["lit", "shadowed", "mixed"]
            .iter()
            .map(|class| {
                let before = line.split(&format!(" {class} (")).next().expect("the class");
                before.rsplit(' ').next().and_then(|n| n.parse::<usize>().ok()).expect("its count")
            })
            .sum()
    };
    for light in [0, 1] {
        let line = stdout
            .lines()
            .find(|l| l.contains(&format!("light {light} casts shadows")))
            .unwrap_or_else(|| panic!("no classes of light {light}: {stdout}"));
        // Every triangle of the bunny (3,674) and the ground (8,192) is in one class.
        assert_eq!(triangles(line), 3674 + 8192, "{line}");
    }
}

/// `multirate` with no command and no display, as a newcomer's `cargo run --release` runs it:
/// the default scene in multirate mode, its level map, and the trade against `pixel` measured
/// in the same run.
#[test]
fn first_run_shows_multirate_and_the_trade() {
    let dir = scratch("first_run");
    let output = common::multirate_command()
        .arg("--validate")
        .current_dir(&dir)
        .env_remove("DISPLAY")
        .output()
        .expect("run multirate");
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "first run failed:\n{stderr}");
    assert!(!stderr.contains("vulkan:"), "validation messages:\n{stderr}");
    let needles = [
        "multirate ε = 0.075",
        "GPU time",
        "camera still",
        "turning 1° a frame",
        "ms, pixel",
        "shading evaluations",
        "level map",
    ];
    for needle in needles {
        assert!(stdout.contains(needle), "{needle:?} missing from:\n{stdout}");
    }
    // "shading evaluations: multirate A, pixel B (…)": multirate shades a fraction of pixel's.
    let counts: Vec<u64> = stdout
        .lines()
        .find(|l| l.contains("shading evaluations"))
        .expect("evaluations line")
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|w| w.parse().ok())
        .collect();
    assert!(counts.len() >= 2 && counts[0] > 0 && counts[0] < counts[1], "{stdout}");
    // "largest error against pixel: X inside silhouettes": within ε.
    let line = stdout.lines().find(|l| l.contains("largest error against pixel")).expect("error line");
    let inside: f64 = line
        .split(": ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|x| x.parse().ok())
        .expect("error value");
    assert!(inside <= 0.075, "{line}");
    for image in ["multirate.png", "multirate_levels.png"] {
        let bytes = std::fs::metadata(dir.join(image)).map(|m| m.len()).unwrap_or(0);
        assert!(bytes > 1000, "{image}: {bytes} bytes");
    }
}

/// The tests set lavapipe up themselves (`common::lavapipe_as_tests_need`), so that the README's
/// `cargo test --release`, run as written, compiles the pipelines as CI does: once a test has a
/// device, `GALLIVM_PERF` is set in its process (the `multirate` processes it starts inherit it).
#[test]
fn the_tests_choose_lavapipe_s_setting_themselves() {
    let context = validated_context();
    let setting = std::env::var("GALLIVM_PERF").expect("GALLIVM_PERF set once a test has a device");
    assert!(!setting.is_empty(), "GALLIVM_PERF is empty");
    assert_validation_clean(&context);
}

/// Every device limit `render::limits` checks, lowered below what a shipped scene needs: the
/// renderer refuses the scene, naming its file and the limit, before creating anything.
#[test]
fn scenes_over_a_device_limit_are_refused_before_the_gpu_sees_them() {
    let context = validated_context();
    let real = context.limits;
    let bunny = Scene::load(&repo_path("scenes/bunny.toml")).expect("load the bunny");
    let spots = Scene::load(&repo_path("scenes/bunny_spots.toml")).expect("load the spotted bunny");
    let needed = SceneSizes::of(&bunny).device_local_bytes();
    // Texels enough for the bunny's vertices (two each) and neighbours (one a triangle), not
    // for its corners (three a triangle).
    let bunny_sizes = SceneSizes::of(&bunny);
    let texels = (2 * bunny_sizes.vertices).max(bunny_sizes.triangles());
    assert!(texels < 3 * bunny_sizes.triangles());
    let cases: [(&Scene, DeviceLimits, &[&str]); 6] = [
        (
            &bunny,
            DeviceLimits { max_storage_buffer_range: 1024, ..real },
            &["the buffer \"scene indices\"", "maxStorageBufferRange (1024 bytes)"],
        ),
        (
            &bunny,
            DeviceLimits { max_texel_buffer_elements: texels, ..real },
            &["the buffer \"triangle corners\"", "maxTexelBufferElements ("],
        ),
        (
            &bunny,
            DeviceLimits { max_draw_indexed_index_value: 99, ..real },
            &["maxDrawIndexedIndexValue (99"],
        ),
        (
            &bunny,
            DeviceLimits { max_compute_work_group_count_x: 1, ..real },
            &["maxComputeWorkGroupCount[0] (1)"],
        ),
        (
            &spots,
            DeviceLimits { max_image_dimension_2d: 16, ..real },
            &["spots_albedo.png", "maxImageDimension2D (16)"],
        ),
        (&bunny, DeviceLimits { device_local_heap: needed - 1, ..real }, &["device-local heap"]),
    ];
    for (scene, limits, expected) in cases {
        let message = match Renderer::with_limits(&context, scene, &limits) {
            Ok(_) => panic!("{} renders under {limits:?}", scene.path.display()),
            Err(error @ Error::SceneLimit { .. }) => error.to_string(),
            Err(other) => panic!("not a limit error: {other}"),
        };
        assert!(message.starts_with(&format!("{}: ", scene.path.display())), "{message}");
        for text in expected {
            assert!(message.contains(text), "{text:?} missing from: {message}");
        }
    }
    assert_eq!(allocations(&context), [], "a refused scene allocated memory");
    // Within the device's own limits the scene is accepted, and what it allocates is what
    // `SceneSizes` counted: each of its buffers (up to the driver's rounding) and textures, and
    // nothing unaccounted for.
    let renderer = Renderer::new(&context, &spots).expect("the spotted bunny fits lavapipe");
    let allocated = allocations(&context);
    let size_of = |name: &str| {
        let mut found = allocated.iter().filter(|(n, _)| n == name);
        let (_, size) = found.next().unwrap_or_else(|| panic!("no allocation named {name:?}"));
        assert!(found.next().is_none(), "two allocations named {name:?}");
        *size
    };
    let sizes = SceneSizes::of(&spots);
    for buffer in sizes.buffers() {
        let size = size_of(buffer.name);
        assert!((buffer.bytes..buffer.bytes + 256).contains(&size), "{buffer:?}: {size} bytes allocated");
    }
    for texture in &sizes.textures {
        assert!(size_of(&texture.name) >= texture.bytes, "{texture:?}");
    }
    let counted: Vec<&str> = sizes
        .buffers()
        .iter()
        .map(|b| b.name)
        .chain(sizes.textures.iter().map(|t| t.name.as_str()))
        .chain(["white texture", "evaluation counters"])
        .collect();
    for (name, _) in &allocated {
        assert!(counted.contains(&name.as_str()), "{name:?} is not in SceneSizes");
    }
    drop(renderer);
    assert_validation_clean(&context);
}

/// Name and size of every live allocation of `context`.
fn allocations(context: &Context) -> Vec<(String, u64)> {
    let allocator = context.allocator.lock().expect("allocator lock");
    allocator.generate_report().allocations.into_iter().map(|a| (a.name, a.size)).collect()
}

/// A buffer of twice the device-local heap and an image wider than the device allows are
/// refused with the resource's name, its size and the heap's, and Vulkan never sees them.
#[test]
fn resources_over_the_device_limits_name_the_resource_its_size_and_the_heap() {
    let context = validated_context();
    let heap = context.limits.device_local_heap;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let message =
        match Buffer::new(&context, "oversized test buffer", 2 * heap, usage, MemoryLocation::GpuOnly) {
            Ok(_) => panic!("a buffer of twice the heap ({heap} bytes) was allocated"),
            Err(error @ Error::ResourceMemory { .. }) => error.to_string(),
            Err(other) => panic!("not a memory error: {other}"),
        };
    for text in [
        "oversized test buffer".to_string(),
        format!("({} MiB)", mib(2 * heap)),
        "more than the heap holds".to_string(),
        format!("device-local heap holds {} MiB", mib(heap)),
    ] {
        assert!(message.contains(&text), "{text:?} missing from: {message}");
    }
    let max = context.limits.max_image_dimension_2d;
    let extent = vk::Extent2D { width: max + 1, height: 1 };
    let image = Image::new(
        &context,
        "too wide an image",
        extent,
        vk::Format::R8G8B8A8_UNORM,
        vk::ImageUsageFlags::SAMPLED,
        vk::ImageAspectFlags::COLOR,
    );
    let message = match image {
        Ok(_) => panic!("an image {} texels wide was created", max + 1),
        Err(error @ Error::ImageTooLarge { .. }) => error.to_string(),
        Err(other) => panic!("not an image size error: {other}"),
    };
    assert!(message.contains("too wide an image"), "{message}");
    assert!(message.contains(&format!("maxImageDimension2D ({max})")), "{message}");
    assert_validation_clean(&context);
}
