//! Helpers shared by the GPU tests: lavapipe set up as the tests need it, a validated headless
//! context, the `multirate` binary to run, CPU ray casting of scenes, a check that the
//! validation layer stayed silent, and a virtual display for the window tests (one per test
//! binary: winit allows one event loop per process).
#![allow(dead_code)]

use glam::{DVec3, Vec3};
use multirate::scene::Scene;
use multirate::vk::target::FloatImage;
use multirate::vk::{Context, ContextOptions};
use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Once};

/// What the tests ask of lavapipe: its shaders compiled without LLVM's optimisation passes
/// (`GALLIVM_PERF=nopt`), which builds the estimator's pipelines about a quarter sooner and
/// renders the same images (docs/notebook/speedups.md, "Build and test time"); nothing in a test
/// is timed. A `GALLIVM_PERF` the caller set is kept. llvmpipe reads the setting once, when the
/// process makes its first device, so every helper that leads to a device or a `multirate`
/// process sets it first; the processes a test starts inherit it.
pub const TESTS_GALLIVM_PERF: &str = "nopt";

/// Sets [`TESTS_GALLIVM_PERF`] in this test process unless `GALLIVM_PERF` is set (once).
pub fn lavapipe_as_tests_need() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if std::env::var_os("GALLIVM_PERF").is_none() {
            std::env::set_var("GALLIVM_PERF", TESTS_GALLIVM_PERF);
        }
    });
}

/// The `multirate` binary of this build, to run with lavapipe as the tests need it.
pub fn multirate_command() -> Command {
    lavapipe_as_tests_need();
    Command::new(env!("CARGO_BIN_EXE_multirate"))
}

/// A headless context with the Khronos validation layer on.
pub fn validated_context() -> Arc<Context> {
    lavapipe_as_tests_need();
    Context::headless(&ContextOptions { validate: true, device_name: None })
        .expect("a Vulkan device with tessellation (lavapipe in CI) and the validation layer")
}

/// Fails the test if the validation layer reported anything.
pub fn assert_validation_clean(context: &Context) {
    let log = context.validation();
    assert_eq!(log.count(), 0, "validation messages:\n{}", log.messages().join("\n"));
}

/// A path inside the repository.
pub fn repo_path(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// Where a ray hits the scene: mesh, triangle and barycentric coordinates of the hit.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub distance: f64,
    pub mesh: usize,
    pub triangle: usize,
    pub barycentric: [f64; 3],
}

impl Hit {
    /// Interpolated world position and (unnormalised) normal at the hit, in f64.
    pub fn attributes(&self, scene: &Scene) -> (DVec3, DVec3) {
        let mesh = &scene.meshes[self.mesh];
        let corner = |k: usize| mesh.indices[self.triangle * 3 + k] as usize;
        let mut position = DVec3::ZERO;
        let mut normal = DVec3::ZERO;
        for k in 0..3 {
            position += mesh.positions[corner(k)].as_dvec3() * self.barycentric[k];
            normal += mesh.normals[corner(k)].as_dvec3() * self.barycentric[k];
        }
        (position, normal)
    }
}

/// Nearest intersection of a ray with every triangle of the scene (Möller–Trumbore in f64).
pub fn ray_cast(scene: &Scene, origin: Vec3, direction: Vec3) -> Option<Hit> {
    let origin = origin.as_dvec3();
    let direction = direction.as_dvec3();
    let mut best: Option<Hit> = None;
    for (mesh_index, mesh) in scene.meshes.iter().enumerate() {
        for (triangle, corners) in mesh.indices.chunks_exact(3).enumerate() {
            let a = mesh.positions[corners[0] as usize].as_dvec3();
            let b = mesh.positions[corners[1] as usize].as_dvec3();
            let c = mesh.positions[corners[2] as usize].as_dvec3();
            let e1 = b - a;
            let e2 = c - a;
            let p = direction.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-18 {
                continue;
            }
            let inv = 1.0 / det;
            let s = origin - a;
            let u = s.dot(p) * inv;
            if !(0.0..=1.0).contains(&u) {
                continue;
            }
            let q = s.cross(e1);
            let v = direction.dot(q) * inv;
            if v < 0.0 || u + v > 1.0 {
                continue;
            }
            let t = e2.dot(q) * inv;
            if t > 0.0 && best.is_none_or(|h| t < h.distance) {
                best =
                    Some(Hit { distance: t, mesh: mesh_index, triangle, barycentric: [1.0 - u - v, u, v] });
            }
        }
    }
    best
}

/// Cracks: pixels inside the reference's silhouette (the pixel and its 8 neighbours covered)
/// that `image` leaves uncovered. Silhouette pixels are left out: there a sub-triangle's edge
/// vertex, rounded, can move a pixel centre lying within rounding distance of the edge to the
/// other side, which is not a hole.
pub fn cracks(reference: &FloatImage, image: &FloatImage) -> usize {
    let covered = |x: u32, y: u32| reference.pixel(x, y)[3] == 1.0;
    let mut count = 0;
    for y in 1..reference.height - 1 {
        for x in 1..reference.width - 1 {
            let interior = (0..3).all(|dy| (0..3).all(|dx| covered(x + dx - 1, y + dy - 1)));
            if interior && image.pixel(x, y)[3] != 1.0 {
                count += 1;
            }
        }
    }
    count
}

/// Per pixel of an image `width` wide: whether a pixel of its 3×3 neighbourhood holds
/// another value in `values` (a triangle id, a coverage), that is whether it lies on an edge.
pub fn on_an_edge<T: PartialEq>(values: &[T], width: usize) -> Vec<bool> {
    let height = values.len() / width;
    (0..values.len())
        .map(|i| {
            let (x, y) = (i % width, i / width);
            (y.saturating_sub(1)..(y + 2).min(height)).any(|ny| {
                (x.saturating_sub(1)..(x + 2).min(width)).any(|nx| values[ny * width + nx] != values[i])
            })
        })
        .collect()
}

/// Per pixel: whether multirate shades it by interpolation (its heat-map colour is not the
/// fallback's magenta) — and the same for all 8 neighbours, so that edges between tessellated
/// and fallback triangles, and silhouettes, are left out.
pub fn interior_tessellated(heat: &FloatImage) -> Vec<bool> {
    let tessellated = |x: u32, y: u32| {
        let p = heat.pixel(x, y);
        p[3] == 1.0 && !(p[0] == 1.0 && p[1] == 0.0 && p[2] == 1.0)
    };
    let mut mask = vec![false; (heat.width * heat.height) as usize];
    for y in 1..heat.height - 1 {
        for x in 1..heat.width - 1 {
            mask[(y * heat.width + x) as usize] =
                (0..3).all(|dy| (0..3).all(|dx| tessellated(x + dx - 1, y + dy - 1)));
        }
    }
    mask
}

/// SplitMix64: a small, seedable generator for the randomised tests.
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// Uniform in [lo, hi), in f64.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f()
    }
}

/// Starts `Xvfb` on a free display and returns it (killed on drop) when no display is set.
pub struct VirtualDisplay(Option<Child>);

impl VirtualDisplay {
    pub fn ensure() -> VirtualDisplay {
        lavapipe_as_tests_need();
        if std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty()) {
            return VirtualDisplay(None);
        }
        let (display, name) = VirtualDisplay::start();
        std::env::set_var("DISPLAY", name);
        display
    }

    /// Starts an Xvfb of its own on a free display, whatever `DISPLAY` says; returns it and the
    /// display's name (`:N`).
    pub fn start() -> (VirtualDisplay, String) {
        lavapipe_as_tests_need();
        let mut child = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", "1024x768x24", "-nolisten", "tcp"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("no DISPLAY and no Xvfb to start (Debian package xvfb)");
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut line)
            .expect("Xvfb reports its display number");
        (VirtualDisplay(Some(child)), format!(":{}", line.trim()))
    }
}

impl Drop for VirtualDisplay {
    fn drop(&mut self) {
        if let Some(child) = &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}
