//! The random cases of every distribution: triangles, lights, materials and eyes.

use super::*;

pub(crate) type Rng = SplitMix64;

/// The distributions the random cases draw from.
pub(crate) trait Draws {
    /// Log-uniform in [lo, hi].
    fn log(&mut self, lo: f32, hi: f32) -> f32;
    fn chance(&mut self, p: f32) -> bool;
    fn unit(&mut self) -> Vec3;
    fn color(&mut self, lo: f32, hi: f32) -> Vec3;
}

impl Draws for Rng {
    fn log(&mut self, lo: f32, hi: f32) -> f32 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.f()).exp()
    }
    fn chance(&mut self, p: f32) -> bool {
        self.f() < p
    }
    fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let l2 = v.length_squared();
            if l2 > 1e-4 && l2 <= 1.0 {
                return v / l2.sqrt();
            }
        }
    }
    fn color(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
}

/// A unit vector at angle `theta` from `axis`, in a random direction around it.
pub(crate) fn tilt(rng: &mut Rng, axis: Vec3, theta: f32) -> Vec3 {
    let side = axis.cross(rng.unit()).normalize_or_zero();
    let side = if side == Vec3::ZERO { axis.any_orthonormal_vector() } else { side };
    (axis * theta.cos() + side * theta.sin()).normalize()
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Brdf {
    Lambert,
    BlinnPhong,
    Ggx,
}

pub(crate) struct Case {
    pub(crate) tri: TriangleInput,
    pub(crate) material: MaterialKind,
    pub(crate) lights: Vec<Light>,
    pub(crate) epsilon: f32,
    pub(crate) n_max: u32,
    /// The estimate is asked to hold for every eye within this distance of `tri.eye`
    /// ([`EstimatorSettings::eye_radius`]); the truth is then measured from an eye on that
    /// sphere ([`ball_case`]).
    pub(crate) eye_radius: f32,
    /// Where the truth is measured from: `tri.eye`, or a point of the ball.
    pub(crate) truth_eye: Vec3,
}

pub(crate) fn random_case(rng: &mut Rng, brdf: Brdf) -> Case {
    let eye = Vec3::ZERO;
    let view_dir = rng.unit();
    let view_dist = rng.log(0.3, 30.0);
    let centre = eye + view_dir * view_dist;
    // Base normal: mostly towards the eye, sometimes grazing or away.
    let tilt_angle = rng.range(0.0, 1.75);
    let base = tilt(rng, -view_dir, tilt_angle);
    let (t1, t2) = base.any_orthonormal_pair();
    // Size and shape (in the plane ⊥ base): general, needle, or exactly degenerate.
    let size = view_dist * rng.log(0.002, 0.5);
    let mut corners = [Vec3::ZERO; 3];
    for c in &mut corners {
        let (x, y) = (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        *c = centre + (t1 * x + t2 * y) * size;
    }
    let shape = rng.f();
    if shape < 0.15 {
        // Needle: the third corner close to the segment of the first two.
        let k = rng.f();
        let off = rng.log(1e-4, 0.05);
        corners[2] = corners[0].lerp(corners[1], k)
            + (t1 * rng.range(-1.0, 1.0) + t2 * rng.range(-1.0, 1.0)) * (off * size);
    } else if shape < 0.18 {
        corners[2] = corners[0].lerp(corners[1], rng.range(-0.5, 1.5));
    }
    // Normals: spread from 0 to ~60°, unit (or, rarely, scaled).
    let spread = if rng.chance(0.05) { 0.0 } else { rng.log(1e-4, 1.0) };
    let mut normals = [base; 3];
    for n in &mut normals {
        let angle = spread * rng.f();
        *n = tilt(rng, base, angle);
        if rng.chance(0.05) {
            *n *= rng.range(0.5, 2.0);
        }
    }
    // Lights.
    let count = 1 + (rng.next_u64() % 3) as usize;
    let mut lights = Vec::with_capacity(count);
    for _ in 0..count {
        let angle = rng.range(0.0, 1.8);
        let dir = tilt(rng, base, angle);
        let color = rng.color(0.2, 1.0);
        if rng.chance(0.7) {
            let dist = size * rng.log(0.3, 300.0);
            lights.push(Light::Point {
                position: centre + dir * dist,
                color,
                intensity: dist * dist * rng.range(0.3, 3.0),
            });
        } else {
            lights.push(Light::Directional { direction: -dir, color, intensity: rng.range(0.3, 3.0) });
        }
    }
    let material = match brdf {
        Brdf::Lambert => MaterialKind::Lambert { kd: rng.color(0.0, 1.0) },
        Brdf::BlinnPhong => MaterialKind::BlinnPhong {
            kd: rng.color(0.0, 0.8),
            ks: rng.color(0.0, 1.0),
            shininess: if rng.chance(0.05) { 1.0 } else { rng.log(1.0, 1.0e4) },
        },
        Brdf::Ggx => MaterialKind::Ggx {
            albedo: rng.color(0.0, 0.8),
            f0: rng.color(0.02, 1.0),
            roughness: match rng.next_u64() % 20 {
                0 => 0.0,
                1 => 1.0,
                _ => rng.f(),
            },
        },
    };
    let epsilon = [0.01, 0.03, 0.075, 0.2][(rng.next_u64() % 4) as usize];
    let tri = TriangleInput { positions: corners, normals, eye };
    Case { tri, material, lights, epsilon, n_max: N_MAX, eye_radius: 0.0, truth_eye: eye }
}

pub(crate) fn hardware(n: u32) -> Pattern {
    triangle_pattern(n as f32, [n as f32; 3])
}

/// [`random_case`] with its lights replaced by 1 to 3 random polygonal lights: regular 3- to
/// 8-gons, from tiny to as wide as they are far, facing the triangle or tilted by up to 60°
/// (sometimes far enough that the triangle is partly or wholly behind the emitter), sampled
/// with either technique and a random MIS visibility.
pub(crate) fn random_polygon_case(rng: &mut Rng, brdf: Brdf) -> Case {
    let mut case = random_case(rng, brdf);
    let [a, b, c] = case.tri.positions;
    let centre = (a + b + c) / 3.0;
    let size = (b - a).length().max((c - a).length()).max(1e-6);
    let base = case.tri.normals[0].normalize();
    let count = 1 + (rng.next_u64() % 3) as usize;
    case.lights.clear();
    for _ in 0..count {
        let angle = rng.range(0.0, 1.8);
        let dir = tilt(rng, base, angle);
        let dist = size * rng.log(0.5, 300.0);
        let radius = dist * rng.log(1e-3, 1.0);
        let lean = if rng.chance(0.2) { rng.range(0.0, 1.05) } else { 0.0 };
        let facing = tilt(rng, -dir, lean);
        let (u, w) = facing.any_orthonormal_pair();
        let sides = 3 + (rng.next_u64() % 6) as usize;
        let turn = rng.range(0.0, 1.0);
        let vertices: Vec<Vec3> = (0..sides)
            .map(|k| {
                let t = std::f32::consts::TAU * (k as f32 + turn) / sides as f32;
                centre + dir * dist + (u * t.cos() + w * t.sin()) * radius
            })
            .collect();
        // Solid angle up to about π: radiance so that the diffuse part is of order 1.
        let intensity = rng.range(0.3, 3.0) * (dist / radius).powi(2).min(1.0e6) / std::f32::consts::PI;
        let color = rng.color(0.2, 1.0);
        let Ok(mut light) = PolygonLight::new(&vertices, color, intensity) else {
            continue;
        };
        if light.normal.dot(facing) < 0.0 {
            let reversed: Vec<Vec3> = vertices.iter().rev().copied().collect();
            light = PolygonLight::new(&reversed, light.color, intensity).expect("the same polygon");
        }
        light.sampling = LightSampling {
            samples: 4,
            technique: if rng.chance(0.5) {
                PolygonSampling::ProjectedSolidAngle
            } else {
                PolygonSampling::SolidAngle
            },
            mis_visibility: [0.0, 0.5, 1.0][(rng.next_u64() % 3) as usize],
        };
        case.lights.push(Light::Polygon(light));
    }
    case
}

/// [`random_case`] with every light moved to the terminator: `n·l` changes sign on most of
/// the triangles (Relaxed keeps tessellating them).
pub(crate) fn terminator_case(rng: &mut Rng, brdf: Brdf) -> Case {
    let mut case = random_case(rng, brdf);
    let [a, b, c] = case.tri.positions;
    let centre = (a + b + c) / 3.0;
    let base = (case.tri.normals[0] + case.tri.normals[1] + case.tri.normals[2]).normalize_or_zero();
    if base == Vec3::ZERO {
        return case;
    }
    for light in &mut case.lights {
        let angle = rng.range(1.35, 1.8);
        let dir = tilt(rng, base, angle);
        match light {
            Light::Point { position, .. } => *position = centre + dir * (*position - centre).length(),
            Light::Directional { direction, .. } => *direction = -dir,
            Light::Polygon(_) => {}
        }
    }
    case
}

/// [`random_case`] seen edge-on: the eye moved to 83–97° from the mean normal, at the same
/// distance, so that `n·v` changes sign on most triangles (GGX's kink in `V`, which Relaxed
/// bounds and Conservative shades per pixel).
pub(crate) fn silhouette_case(rng: &mut Rng, brdf: Brdf) -> Case {
    let mut case = random_case(rng, brdf);
    let [a, b, c] = case.tri.positions;
    let centre = (a + b + c) / 3.0;
    let base = (case.tri.normals[0] + case.tri.normals[1] + case.tri.normals[2]).normalize_or_zero();
    if base != Vec3::ZERO {
        let angle = rng.range(1.45, 1.7);
        let dir = tilt(rng, base, angle);
        case.tri.eye = centre + dir * (case.tri.eye - centre).length();
        case.truth_eye = case.tri.eye;
    }
    case
}

/// [`random_case`], half of them with the lights at the terminator ([`terminator_case`]) or,
/// for GGX, seen edge-on ([`silhouette_case`]), estimated for a ball of eyes of 0.1 to 20 % of
/// the distance to the triangle and measured from a point of its sphere: in a random
/// direction, or towards or across the triangle, where the view turns most.
pub(crate) fn ball_case(rng: &mut Rng, brdf: Brdf) -> Case {
    let mut case = match rng.next_u64() % 4 {
        0 => terminator_case(rng, brdf),
        1 if brdf == Brdf::Ggx => silhouette_case(rng, brdf),
        _ => random_case(rng, brdf),
    };
    let [a, b, c] = case.tri.positions;
    let to_triangle = (a + b + c) / 3.0 - case.tri.eye;
    case.eye_radius = to_triangle.length() * rng.log(0.001, 0.2);
    let across = to_triangle.cross(rng.unit()).normalize_or(rng.unit());
    let direction = match rng.next_u64() % 3 {
        0 => rng.unit(),
        1 => to_triangle.normalize_or(rng.unit()),
        _ => across,
    };
    case.truth_eye = case.tri.eye + direction * (case.eye_radius * 0.999);
    case
}

/// Random triangles per BRDF estimated for a ball of eyes.
pub(crate) const BALL_TRIANGLES: usize = 4_000;

/// [`ball_case`] estimated for its centre alone: the truth still measured from the sphere.
pub(crate) fn ball_case_for_its_centre(rng: &mut Rng, brdf: Brdf) -> Case {
    Case { eye_radius: 0.0, ..ball_case(rng, brdf) }
}

/// The extended distribution: [`random_case`] with `n_max` from 1 to 32 instead of 16, and
/// point lights moved closer (down to 1/50 of the triangle's size from its centre) or exactly
/// into the triangle's plane (grazing), their intensity scaled with the squared distance.
pub(crate) fn extended_case(rng: &mut Rng, brdf: Brdf) -> Case {
    let mut case = random_case(rng, brdf);
    case.n_max = [1, 2, 3, 4, 8, 16, 32][(rng.next_u64() % 7) as usize];
    let [a, b, c] = case.tri.positions;
    let centre = (a + b + c) / 3.0;
    let size = (b - a).length().max((c - a).length()).max(1e-6);
    let plane = (b - a).cross(c - a).normalize_or_zero();
    for light in &mut case.lights {
        let Light::Point { position, intensity, .. } = light else { continue };
        let offset = *position - centre;
        let distance = offset.length();
        let mut direction = offset / distance.max(1e-30);
        let mut new_distance = distance;
        if rng.chance(0.3) {
            new_distance = size * rng.log(0.02, 0.3);
        }
        if plane != Vec3::ZERO && rng.chance(0.15) {
            direction = (direction - plane * direction.dot(plane)).normalize_or(direction);
        }
        *position = centre + direction * new_distance;
        *intensity *= (new_distance / distance.max(1e-30)).powi(2);
    }
    case
}

/// A textured parameter over the patch: values in `[lo, hi]` as a function of the barycentric
/// point, from smooth to far finer than any sub-triangle, and hard steps (a checker).
pub(crate) fn parameter_field(rng: &mut Rng, lo: f32, hi: f32) -> impl Fn([f64; 3]) -> f32 {
    let kind = rng.next_u64() % 4;
    let frequency = f64::from(rng.log(0.5, 200.0));
    let direction = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)].map(f64::from);
    let phase = f64::from(rng.range(0.0, 6.3));
    move |b: [f64; 3]| {
        let x = frequency * (direction[0] * b[0] + direction[1] * b[1] + direction[2] * b[2]) + phase;
        let t = match kind {
            0 => 0.5 + 0.5 * x.sin(),
            1 => {
                if (x.floor() as i64 + (frequency * b[1]).floor() as i64) % 2 == 0 {
                    0.0
                } else {
                    1.0
                }
            }
            2 => 0.5 + 0.5 * (x.sin() * (3.1 * x).cos()),
            _ => (x.fract() + 1.0).fract(),
        };
        lo + (hi - lo) * t as f32
    }
}
