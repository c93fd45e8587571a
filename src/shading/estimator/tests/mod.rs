//! The estimator's unit tests, one file per topic (each against the brute-force truth: finite
//! differences, sampled points, the oracle or the model of the tessellator), and the fixtures
//! they share: triangles, materials, lights, and the shading in f64.

use super::add_light::*;
use super::cone::*;
use super::constants::*;
use super::estimate::*;
use super::frame::*;
use super::irradiance::*;
use super::jet::*;
use super::light_setup::*;
use super::lobe::*;
use super::patch_levels::*;
use super::pattern::*;
use super::settings::*;
use super::terminator::*;
use super::terms::*;
use crate::analysis::tessellator::{triangle_pattern, Pattern};
use crate::exact_math::*;
use crate::scene::{Light, MaterialKind, ParameterRange};
use crate::shading::brdf::ggx_alpha;
use glam::{DVec3, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

mod geometry;
mod irradiance;
mod jets;
mod light_bounds;
mod patch_levels;
mod pattern;
mod range;
mod refine_floor;
mod robustness;
mod terminator;

struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn base() -> TriangleInput {
    TriangleInput {
        positions: [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.3, 0.8, 0.0)],
        normals: [
            Vec3::new(-0.1, -0.05, 1.0).normalize(),
            Vec3::new(0.1, -0.05, 1.0).normalize(),
            Vec3::new(0.0, 0.1, 1.0).normalize(),
        ],
        eye: Vec3::new(0.4, -1.0, 3.0),
    }
}

fn materials() -> Vec<MaterialKind> {
    vec![
        MaterialKind::Lambert { kd: Vec3::new(0.8, 0.5, 0.2) },
        MaterialKind::BlinnPhong { kd: Vec3::splat(0.4), ks: Vec3::splat(0.6), shininess: 1.0 },
        MaterialKind::BlinnPhong { kd: Vec3::splat(0.4), ks: Vec3::splat(0.6), shininess: 60.0 },
        MaterialKind::BlinnPhong { kd: Vec3::splat(0.4), ks: Vec3::splat(0.6), shininess: 1.0e4 },
        MaterialKind::Ggx { albedo: Vec3::splat(0.5), f0: Vec3::new(0.04, 0.5, 1.0), roughness: 0.0 },
        MaterialKind::Ggx { albedo: Vec3::splat(0.5), f0: Vec3::splat(0.04), roughness: 0.5 },
        MaterialKind::Ggx { albedo: Vec3::splat(0.5), f0: Vec3::splat(0.9), roughness: 1.0 },
    ]
}

fn point(p: Vec3) -> Light {
    Light::Point { position: p, color: Vec3::new(1.0, 0.9, 0.8), intensity: 4.0 }
}

fn sun(d: Vec3) -> Light {
    Light::Directional { direction: d.normalize(), color: Vec3::ONE, intensity: 2.0 }
}

fn light_sets(t: &TriangleInput) -> Vec<(&'static str, Vec<Light>)> {
    let c = (t.positions[0] + t.positions[1] + t.positions[2]) / 3.0;
    let size = (t.positions[1] - t.positions[0]).length().max(1e-30);
    vec![
        ("point above", vec![point(c + Vec3::new(0.1, 0.2, 1.0) * size)]),
        ("sun", vec![sun(Vec3::new(0.2, 0.3, -1.0))]),
        ("grazing sun", vec![sun(Vec3::new(1.0, 0.0, -0.02))]),
        ("sun in the plane", vec![sun(Vec3::new(1.0, 0.3, 0.0))]),
        ("back-facing sun", vec![sun(Vec3::new(0.0, 0.2, 1.0))]),
        ("light at a vertex", vec![point(t.positions[1])]),
        ("light on the surface", vec![point(c)]),
        ("light just above", vec![point(c + Vec3::Z * 1e-3 * size)]),
        ("far point", vec![point(c + Vec3::new(3.0, 1.0, 1e4) * size)]),
        (
            "dark light at a vertex",
            vec![Light::Point { position: t.positions[0], color: Vec3::ONE, intensity: 0.0 }],
        ),
        (
            "three lights",
            vec![
                point(c + Vec3::new(-1.0, 0.0, 2.0) * size),
                sun(Vec3::new(0.0, 0.0, -1.0)),
                sun(Vec3::new(0.0, 1.0, 0.3)),
            ],
        ),
    ]
}

fn triangles() -> Vec<(&'static str, TriangleInput)> {
    let b = base();
    let mut out = vec![("base", b)];
    let mut t = b;
    t.positions[2] = t.positions[0].lerp(t.positions[1], 0.3);
    out.push(("zero area", t));
    let mut t = b;
    t.positions = [Vec3::new(0.2, 0.1, 0.0); 3];
    out.push(("a point", t));
    let mut t = b;
    t.positions[2] = Vec3::new(0.5, 1e-5, 0.0);
    out.push(("needle", t));
    let mut t = b;
    t.normals = [Vec3::Z; 3];
    out.push(("identical normals", t));
    let mut t = b;
    t.normals = [Vec3::Z, -Vec3::Z, Vec3::X];
    out.push(("opposite normals", t));
    let mut t = b;
    let r = |a: f32| Vec3::new(a.cos(), a.sin(), 0.0);
    t.normals = [r(0.0), r(2.094_395), r(4.188_79)];
    out.push(("120 degrees in a plane", t));
    let mut t = b;
    t.normals = [Vec3::ZERO, Vec3::Z, Vec3::Z];
    out.push(("a zero normal", t));
    let mut t = b;
    t.normals = [b.normals[0] * 3.0, b.normals[1] * 0.2, b.normals[2]];
    out.push(("unnormalised normals", t));
    let mut t = b;
    t.normals = [
        Vec3::new(0.7, 0.0, 0.7).normalize(),
        Vec3::new(-0.7, 0.0, 0.7).normalize(),
        Vec3::new(0.0, 0.7, 0.7).normalize(),
    ];
    out.push(("strongly curved", t));
    let mut t = b;
    t.eye = (b.positions[0] + b.positions[1] + b.positions[2]) / 3.0;
    out.push(("eye on the surface", t));
    let mut t = b;
    t.eye = b.positions[0] + Vec3::new(5.0, 0.0, 0.0);
    out.push(("eye in the plane", t));
    for (name, scale, offset) in [
        ("at 1e6", 1.0, 1.0e6),
        ("size 1e6", 1.0e6, 0.0),
        ("size 1e-6", 1.0e-6, 0.0),
        ("1e-6 at 1e3", 1.0e-6, 1.0e3),
    ] {
        let mut t = b;
        t.positions = b.positions.map(|p| p * scale + Vec3::splat(offset));
        t.eye = b.eye * scale + Vec3::splat(offset);
        out.push((name, t));
    }
    out
}

fn all_settings(eps: f32) -> Vec<EstimatorSettings> {
    let mut v = Vec::new();
    for split in [Split::Uniform, Split::Heuristic] {
        for discontinuity in [Discontinuity::Conservative, Discontinuity::Relaxed] {
            v.push(EstimatorSettings {
                epsilon: eps,
                n_max: 16,
                split,
                discontinuity,
                min_estimated_area: 0.0,
                eye_radius: 0.0,
            });
        }
    }
    v
}

/// `f`, `f'` and `f''` at `t` by central differences of step `h`.
fn differences(f: &dyn Fn(f64) -> f64, t: f64, h: f64) -> [f64; 3] {
    let (fm, f0, fp) = (f(t - h), f(t), f(t + h));
    [f0, (fp - fm) / (2.0 * h), (fp - 2.0 * f0 + fm) / (h * h)]
}

/// The irradiance jet (`n̂·I`, `I = (p − x)/|p − x|³`, as the estimator sets it up) against
/// f64 central differences along random steps at points of random triangles: lights far,
/// close above the triangle (nearer than its size) and grazing (near its plane, outside it);
/// flat normals (the light part alone: `projected` and `whole` reach their bound) and
/// curved ones (the normal and cross parts too).
/// A random triangle of size `size` with flat or (`curved`) bent normals, and a point
/// light far (`kind` 0), close above it (nearer than its size, 1) or grazing (near its
/// plane, outside it, 2). `None` for a near-degenerate triangle.
fn irradiance_case(
    rng: &mut crate::test_rng::Rng,
    size: f32,
    curved: bool,
    kind: usize,
) -> Option<(TriangleInput, Vec3)> {
    let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
    let positions = [0; 3].map(|_| centre + rng.point(Vec3::splat(-size), Vec3::splat(size)));
    let plane = (positions[1] - positions[0]).cross(positions[2] - positions[0]);
    if plane.length() < 0.05 * size * size {
        return None;
    }
    let plane = plane.normalize();
    let normals = positions.map(|x| {
        let bend = if curved { (x - centre) * rng.range(0.0, 1.5) / size } else { Vec3::ZERO };
        (plane + bend).normalize() * if curved { 0.8 + 0.4 * rng.f() } else { 1.0 }
    });
    let toward = |k: usize| positions[k] - centre;
    let position = match kind {
        0 => centre + (plane + rng.point(Vec3::splat(-1.0), Vec3::ONE)).normalize() * rng.range(3.0, 30.0),
        1 => {
            centre + plane * size * rng.range(0.05, 1.0) + toward(rng.below(3) as usize) * rng.range(0.0, 0.9)
        }
        _ => {
            centre + toward(rng.below(3) as usize) * rng.range(1.3, 3.0) + plane * size * rng.range(0.0, 0.1)
        }
    };
    Some((TriangleInput { positions, normals, eye: centre + plane * 5.0 }, position))
}

/// The jets' scale along the domain step `(du, dv)` of a patch, in f64: `|Xδ|`, `|Nδ|` and
/// `|Gδ|` (see [`Scale`]).
fn scale_along(tri: &TriangleInput, du: f64, dv: f64) -> Scale {
    let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
    let [np, nq, nr] = tri.normals.map(|x| x.as_dvec3());
    let n_step = (nq - np) * du + (nr - np) * dv;
    Scale {
        a: ((q - p) * du + (r - p) * dv).length() as f32,
        b: n_step.length() as f32,
        g: DVec3::new(np.dot(n_step), nq.dot(n_step), nr.dot(n_step)).length() as f32,
    }
}

/// [`irradiance_case`] with its light planned for a white Lambert material (Relaxed):
/// `None` also where the light adds nothing.
fn planned_irradiance_case(
    rng: &mut crate::test_rng::Rng,
    size: f32,
    curved: bool,
    kind: usize,
) -> Option<(TriangleInput, Vec3, Frame, LightSetup)> {
    let (tri, position) = irradiance_case(rng, size, curved, kind)?;
    let light = Light::Point { position, color: Vec3::ONE, intensity: 1.0 };
    let frame = Frame::new(&tri, 0.0, true);
    let material = MaterialKind::Lambert { kd: Vec3::ONE };
    let own = ParameterRange::of(&material);
    let (setup, _, _) = plan_light(&frame, &material, own, &light, Discontinuity::Relaxed).ok()??;
    Some((tri, position, frame, setup))
}

/// Sorts `v` and names its 10th percentile, median and 90th percentile.
fn percentiles(v: &mut [f64]) -> String {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    format!("10th percentile {:.2}, median {:.2}, 90th {:.2}", v[n / 10], v[n / 2], v[9 * n / 10])
}

fn est(t: &TriangleInput, m: &MaterialKind, lights: &[Light], eps: f32) -> Estimate {
    estimate(t, m, lights, &EstimatorSettings { epsilon: eps, ..EstimatorSettings::default() })
}

/// One light's contribution in f64, as `reflect_split` × irradiance shades it (per
/// channel): the exact function whose derivatives the light's jets bound.
fn shade_f64(x: DVec3, normal: DVec3, eye: DVec3, material: &MaterialKind, light: &Light) -> [f64; 3] {
    let n = normal.normalize();
    let v = (eye - x).normalize();
    let (l, irradiance) = match *light {
        Light::Point { position, color, intensity } => {
            let to = position.as_dvec3() - x;
            (to.normalize(), color.as_dvec3() * f64::from(intensity) / to.length_squared())
        }
        Light::Directional { direction, color, intensity } => {
            (-direction.as_dvec3().normalize(), color.as_dvec3() * f64::from(intensity))
        }
        Light::Polygon(_) => unreachable!("point and directional lights only"),
    };
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 {
        return [0.0; 3];
    }
    let h = (l + v).normalize();
    let n_dot_h = n.dot(h).max(0.0);
    let radiance = match *material {
        MaterialKind::Lambert { kd } => kd.as_dvec3() * n_dot_l,
        MaterialKind::BlinnPhong { kd, ks, shininess } => {
            kd.as_dvec3() * n_dot_l + ks.as_dvec3() * n_dot_h.powf(f64::from(shininess))
        }
        MaterialKind::Ggx { albedo, f0, roughness } => {
            let alpha = f64::from(ggx_alpha(roughness));
            let k = 0.5 * alpha;
            let n_dot_v = n.dot(v).max(0.0);
            let v_dot_h = v.dot(h).clamp(0.0, 1.0);
            let a2 = alpha * alpha;
            let q = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
            let d = a2 / (std::f64::consts::PI * q * q);
            let f = f0.as_dvec3() + (DVec3::ONE - f0.as_dvec3()) * (1.0 - v_dot_h).powi(5);
            let visibility = 1.0 / ((n_dot_l * (1.0 - k) + k) * (n_dot_v * (1.0 - k) + k));
            albedo.as_dvec3() * n_dot_l + f * (d * visibility * 0.25 * n_dot_l)
        }
    };
    (radiance * irradiance).to_array()
}

/// A light for a patch of `size` at `centre` with mean normal `base`: a point light 3–30
/// away, one closer than the patch's size (`tangent` spreads it along the patch), one near
/// grazing, or a directional light.
fn random_light(rng: &mut crate::test_rng::Rng, centre: Vec3, base: Vec3, tangent: Vec3, size: f32) -> Light {
    match rng.below(4) {
        0 => Light::Point {
            position: centre + tilt(rng, base, 0.0, 1.4) * (3.0 + 27.0 * rng.f()),
            color: Vec3::ONE,
            intensity: rng.range(5.0, 500.0),
        },
        1 => Light::Point {
            position: centre + base * size * rng.range(0.3, 1.5) + tangent * size * rng.range(-1.0, 1.0),
            color: Vec3::ONE,
            intensity: rng.range(0.01, 1.0),
        },
        2 => Light::Point {
            position: centre + tilt(rng, base, 1.35, 1.55) * (1.0 + 4.0 * rng.f()),
            color: Vec3::ONE,
            intensity: rng.range(1.0, 20.0),
        },
        _ => Light::Directional {
            direction: -tilt(rng, base, 0.0, 1.5),
            color: Vec3::ONE,
            intensity: rng.range(0.3, 3.0),
        },
    }
}

/// A random material of kind `brdf` (0 Lambert, 1 Blinn-Phong, 2 GGX): colours 0.05–1,
/// shininess log-uniform 1–10⁴, roughness 0.02–1 and one in eight exactly 0.
fn random_material(rng: &mut crate::test_rng::Rng, brdf: usize) -> MaterialKind {
    let colour = |rng: &mut crate::test_rng::Rng| rng.point(Vec3::splat(0.05), Vec3::ONE);
    match brdf {
        0 => MaterialKind::Lambert { kd: colour(rng) },
        1 => MaterialKind::BlinnPhong {
            kd: colour(rng),
            ks: colour(rng),
            shininess: rng.range(0.0, 10_000f32.ln()).exp(),
        },
        _ => MaterialKind::Ggx {
            albedo: colour(rng),
            f0: colour(rng) * 0.5,
            roughness: if rng.below(8) == 0 { 0.0 } else { rng.range(0.02, 1.0) },
        },
    }
}

/// `axis` turned by an angle in `[lo, hi)` towards a random side.
fn tilt(rng: &mut crate::test_rng::Rng, axis: Vec3, lo: f32, hi: f32) -> Vec3 {
    let angle = rng.range(lo, hi);
    let side = axis.any_orthonormal_pair();
    let turn = rng.range(0.0, std::f32::consts::TAU);
    let across = side.0 * turn.cos() + side.1 * turn.sin();
    (axis * angle.cos() + across * angle.sin()).normalize()
}

/// A random patch of corner offsets up to `size` around a centre in `[−1, 1]³`, and an eye
/// 2–10 away: `(centre, positions, direction to the eye, eye)`.
fn random_patch(rng: &mut crate::test_rng::Rng, size: f32) -> (Vec3, [Vec3; 3], Vec3, Vec3) {
    let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
    let positions = [0; 3].map(|_| centre + rng.point(Vec3::splat(-size), Vec3::splat(size)));
    let eye_dir = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or_zero();
    (centre, positions, eye_dir, centre + eye_dir * rng.range(2.0, 10.0))
}
