//! The GLSL twin of the polygonal-light module (`glsl/include/polygon.glsl`, driven by
//! `glsl/polygon_check.comp`) agrees with the CPU reference `multirate::shading::polygon` on
//! random convex polygons: tiny and huge ones, ones partly or wholly below the horizon, and
//! nearly edge-on ones.
//!
//! Tolerances. Clipping only compares the input z against 0, so clipped vertex counts, sampler
//! emptiness, the central/decentral case and the Hammersley points must agree exactly. The rest
//! differs by rounding: the GLSL twin emulates `mul_add` and `atan2` to within an ulp or so
//! (Vulkan lets `fma()` round twice and `atan()` err by 4096 ulps), while `sin`, `cos` and division
//! are the driver's. A few ulps of difference per operation are then amplified by the conditioning
//! that the module documentation describes, and each tolerance is a plain relative part plus that
//! amplification:
//! - (projected) solid angles and the densities `1/Ω`, `1/Ω_proj`: relative [`VALUE_TOLERANCE`]
//!   plus, for the projected solid angle, [`CANCELLATION_ULPS`] ε · `Ω/Ω_proj`: the closed form
//!   sums terms of the size of the solid angle that cancel down to the projected one when the
//!   polygon lies close to the horizon;
//! - sample directions: [`DIRECTION_TOLERANCE`] times the polygon's angular size (the largest
//!   distance between two unit vertex directions; a sample is a smooth function of the polygon at
//!   that scale) plus, for projected-solid-angle samples, [`HORIZON_ULPS`] ε / z: they are built in
//!   the xy-plane with z = √(1 − |xy|²), accurate to about ε/z (module documentation);
//! - the projected sample's density per solid angle, `z / Ω_proj`, inherits relative
//!   [`HORIZON_ULPS`] ε / z² from its z;
//! - MIS weights lie in [0, 1] and move by at most the relative change of a density: absolute
//!   [`WEIGHT_TOLERANCE`] plus the density tolerance;
//! - the densities at a probe direction agree as values (within the density tolerance) and as
//!   inside/outside decisions, which differ only within rounding of an edge, where random probes
//!   never land.

mod common;

use ash::vk;
use common::{assert_validation_clean, validated_context, SplitMix64};
use glam::Vec3;
use gpu_allocator::MemoryLocation;
use multirate::shaders;
use multirate::shading::polygon::{
    clamped_optimal_mis_weights, clip_to_horizon, prepare_projected_solid_angle, prepare_solid_angle,
    projected_solid_angle, projected_solid_angle_density, projected_to_solid_angle_density, sample_point,
    sample_projected_solid_angle, sample_solid_angle, solid_angle_density, Polygon, DEFAULT_MIS_VISIBILITY,
    MAX_POLYGON_VERTICES,
};
use multirate::vk::memory::Buffer;
use multirate::vk::pipeline::{
    bind_storage_buffers, DescriptorPool, Optimization, Pipeline, PipelineLayout, ShaderModule,
};
use std::time::Instant;

/// Random cases compared.
const CASE_COUNT: usize = 2048;
/// Threads per workgroup of `polygon_check.comp`.
const WORKGROUP_SIZE: usize = 64;
/// 32-bit words per `PolygonCase` (std430: 8 + 3 vec4s/uvec4s).
const CASE_WORDS: usize = 4 * (MAX_POLYGON_VERTICES + 3);
/// 32-bit words per `PolygonResult` (6 vec4s/uvec4s).
const RESULT_WORDS: usize = 24;
/// Relative tolerance of projected solid angles, solid angles and densities.
const VALUE_TOLERANCE: f32 = 1.0e-4;
/// Ulps of the closed form's terms that may survive their cancellation near the horizon.
const CANCELLATION_ULPS: f32 = 64.0;
/// Tolerance of sample directions, relative to the polygon's angular size.
const DIRECTION_TOLERANCE: f32 = 1.0e-3;
/// Ulps, divided by z, of a projected-solid-angle sample (z is rebuilt from xy).
const HORIZON_ULPS: f32 = 16.0;
/// Absolute tolerance of MIS weights.
const WEIGHT_TOLERANCE: f32 = 1.0e-4;

/// Uniform on the unit sphere.
fn direction(rng: &mut SplitMix64) -> Vec3 {
    let z = rng.range(-1.0, 1.0);
    let phi = rng.range(0.0, std::f32::consts::TAU);
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// One test case: the polygon, the random numbers of both samplers, a probe direction and the
/// index and count of a Hammersley point.
struct Case {
    polygon: Polygon,
    u: [f32; 4],
    probe: Vec3,
    point: [u32; 2],
}

/// A convex planar polygon: 3–8 vertices at increasing random angles on a circle (an ellipse for
/// some) whose centre lies in a random direction (down to 0.3 below the horizon), with a radius
/// from 10⁻⁴ to 10× the distance and a random plane orientation.
fn random_case(rng: &mut SplitMix64) -> Case {
    let count = 3 + (rng.next_u64() % (MAX_POLYGON_VERTICES as u64 - 2)) as usize;
    let mut centre_direction = direction(rng);
    centre_direction.z = centre_direction.z.abs() * 1.3 - 0.3;
    let centre = centre_direction.normalize() * rng.range(0.5, 4.0);
    let radius = centre.length() * 10f32.powf(rng.range(-4.0, 1.0));
    // Mostly facing the shading point, sometimes any orientation (nearly edge-on included)
    let normal =
        if rng.f() < 0.7 { (-centre.normalize() + 0.6 * direction(rng)).normalize() } else { direction(rng) };
    let tangent = normal.any_orthonormal_vector();
    let bitangent = normal.cross(tangent);
    let stretch = if rng.f() < 0.3 { rng.range(0.05, 1.0) } else { 1.0 };
    let mut angles: Vec<f32> = (0..count).map(|_| rng.range(0.0, std::f32::consts::TAU)).collect();
    angles.sort_by(f32::total_cmp);
    let vertices: Vec<Vec3> = angles
        .iter()
        .map(|&angle| centre + radius * (angle.cos() * tangent + stretch * angle.sin() * bitangent))
        .collect();
    let polygon = Polygon::new(&vertices);
    let u = [rng.f(), rng.f(), rng.f(), rng.f()];
    // Half the probes at the polygon's centre, half random in the upper hemisphere
    let probe = if rng.f() < 0.5 {
        centre.normalize()
    } else {
        let d = direction(rng);
        Vec3::new(d.x, d.y, d.z.abs())
    };
    let point_count = 1 + (rng.next_u64() % 4096) as u32;
    let point_index = (rng.next_u64() % u64::from(point_count)) as u32;
    Case { polygon, u, probe, point: [point_index, point_count] }
}

/// The case in the std430 layout of `PolygonCase`.
fn case_words(case: &Case) -> [u32; CASE_WORDS] {
    let mut words = [0; CASE_WORDS];
    for (j, vertex) in case.polygon.as_slice().iter().enumerate() {
        for k in 0..3 {
            words[4 * j + k] = vertex[k].to_bits();
        }
    }
    let base = 4 * MAX_POLYGON_VERTICES;
    for k in 0..4 {
        words[base + k] = case.u[k].to_bits();
    }
    for k in 0..3 {
        words[base + 4 + k] = case.probe[k].to_bits();
    }
    words[base + 8] = case.polygon.count as u32;
    words[base + 9] = case.point[0];
    words[base + 10] = case.point[1];
    words
}

/// What one case yields, on either side.
#[derive(Clone, Copy, Debug)]
struct Outcome {
    projected_sample: Vec3,
    projected_density: f32,
    solid_angle_sample: Vec3,
    solid_angle_density: f32,
    projected_solid_angle: f32,
    solid_angle: f32,
    weights: [f32; 2],
    probe_densities: [f32; 2],
    projected_in_solid_angle: f32,
    point: [f32; 2],
    clipped_count: u32,
    projected_count: u32,
    central: bool,
    solid_angle_count: u32,
}

/// The Rust twin of `polygon_check.comp`'s `main`.
fn cpu_outcome(case: &Case) -> Outcome {
    let clipped = clip_to_horizon(&case.polygon);
    let projected = prepare_projected_solid_angle(&clipped);
    let solid = prepare_solid_angle(&clipped);
    let (projected_sample, projected_density) =
        sample_projected_solid_angle(&projected, [case.u[0], case.u[1]]);
    let (solid_angle_sample, solid_density) = sample_solid_angle(&solid, [case.u[2], case.u[3]]);
    let projected_in_solid_angle = projected_to_solid_angle_density(projected_density, projected_sample);
    let weights = clamped_optimal_mis_weights(
        [projected_in_solid_angle, solid_density],
        [projected.projected_solid_angle(), solid.solid_angle()],
        DEFAULT_MIS_VISIBILITY,
    );
    Outcome {
        projected_sample,
        projected_density,
        solid_angle_sample,
        solid_angle_density: solid_density,
        projected_solid_angle: projected_solid_angle(&clipped),
        solid_angle: solid.solid_angle(),
        weights,
        probe_densities: [
            projected_solid_angle_density(&projected, case.probe),
            solid_angle_density(&solid, case.probe),
        ],
        projected_in_solid_angle,
        point: sample_point(case.point[0], case.point[1]),
        clipped_count: clipped.count as u32,
        projected_count: if projected.is_empty() { 0 } else { clipped.count as u32 },
        central: !projected.is_empty() && projected.is_central(),
        solid_angle_count: if solid.is_empty() { 0 } else { clipped.count as u32 },
    }
}

/// Decodes one `PolygonResult`.
fn gpu_outcome(words: &[u32]) -> Outcome {
    let f = |k: usize| f32::from_bits(words[k]);
    let vec3 = |k: usize| Vec3::new(f(k), f(k + 1), f(k + 2));
    Outcome {
        projected_sample: vec3(0),
        projected_density: f(3),
        solid_angle_sample: vec3(4),
        solid_angle_density: f(7),
        projected_solid_angle: f(8),
        solid_angle: f(9),
        weights: [f(10), f(11)],
        probe_densities: [f(12), f(13)],
        projected_in_solid_angle: f(14),
        point: [f(16), f(17)],
        clipped_count: words[20],
        projected_count: words[21],
        central: words[22] != 0 && words[21] != 0,
        solid_angle_count: words[23],
    }
}

/// Runs `polygon_check.comp` over the cases and reads back the raw results.
fn run_on_gpu(context: &std::sync::Arc<multirate::vk::Context>, cases: &[Case]) -> Vec<u32> {
    let input: Vec<u32> = cases.iter().flat_map(case_words).collect();
    let input = Buffer::with_data(context, "polygon cases", vk::BufferUsageFlags::STORAGE_BUFFER, &input)
        .expect("case buffer");
    let output = Buffer::new(
        context,
        "polygon results",
        (cases.len() * RESULT_WORDS * 4) as vk::DeviceSize,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )
    .expect("result buffer");
    let bindings: Vec<vk::DescriptorSetLayoutBinding<'_>> = (0..2)
        .map(|binding| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        })
        .collect();
    let layout = PipelineLayout::new(context, "polygon check layout", &[&bindings], &[]).expect("layout");
    let pool = DescriptorPool::new(
        context,
        "polygon check descriptors",
        1,
        &[vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 2 }],
    )
    .expect("descriptor pool");
    let set = pool.allocate(layout.set_layouts[0]).expect("descriptor set");
    bind_storage_buffers(context, set, 0, &[input.raw, output.raw]);
    let module = ShaderModule::new(context, "polygon_check.comp", shaders::single("polygon_check.comp"))
        .expect("shader module");
    let pipeline =
        Pipeline::compute(context, "polygon check", &layout, &module, None, Optimization::Optimized)
            .expect("pipeline");
    let device = &context.device;
    context
        .run_once(|cmd| {
            let barrier = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
                .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                .dst_access_mask(vk::AccessFlags2::HOST_READ)];
            // SAFETY: `cmd` is recording; every object outlives `run_once`, which waits for the
            // work; the upload in `with_data` finished before this submission.
            unsafe {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    layout.raw,
                    0,
                    &[set],
                    &[],
                );
                device.cmd_dispatch(cmd, cases.len().div_ceil(WORKGROUP_SIZE) as u32, 1, 1);
                device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barrier));
            }
        })
        .expect("dispatch");
    let bytes = output.mapped().expect("GpuToCpu memory is mapped");
    bytemuck::pod_collect_to_vec::<u8, u32>(&bytes[..cases.len() * RESULT_WORDS * 4])
}

/// The largest distance between two unit vertex directions of the clipped polygon.
fn angular_size(case: &Case) -> f32 {
    let clipped = clip_to_horizon(&case.polygon);
    let directions: Vec<Vec3> = clipped.as_slice().iter().map(|v| v.normalize()).collect();
    let mut size: f32 = 0.0;
    for a in &directions {
        for b in &directions {
            size = size.max(a.distance(*b));
        }
    }
    size
}

/// `|a − b| / max(|a|, |b|)`, and 0 when both are equal (0 and infinities included).
fn relative(a: f32, b: f32) -> f32 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / b.abs().max(a.abs())
    }
}

/// The largest difference of one quantity seen so far and the largest ratio of a difference to
/// its tolerance, each with the case it came from.
#[derive(Default)]
struct Worst {
    difference: f32,
    difference_case: usize,
    ratio: f32,
    ratio_case: usize,
}

impl Worst {
    /// Records one comparison; returns whether it is within tolerance.
    fn check(&mut self, difference: f32, tolerance: f32, case: usize) -> bool {
        if difference > self.difference || difference.is_nan() {
            (self.difference, self.difference_case) = (difference, case);
        }
        let ratio = if difference == 0.0 { 0.0 } else { difference / tolerance };
        if ratio > self.ratio || ratio.is_nan() {
            (self.ratio, self.ratio_case) = (ratio, case);
        }
        difference <= tolerance
    }

    fn report(&self, what: &str) {
        eprintln!(
            "{what}: max {:.3e} (case {}); at most {:.2} of its tolerance (case {})",
            self.difference, self.difference_case, self.ratio, self.ratio_case
        );
    }
}

#[test]
fn glsl_twin_agrees_with_the_cpu_reference() {
    let started = Instant::now();
    let mut rng = SplitMix64(0x5eed_0001_9017_90a1);
    let cases: Vec<Case> = (0..CASE_COUNT).map(|_| random_case(&mut rng)).collect();
    let context = validated_context();
    let raw = run_on_gpu(&context, &cases);
    let gpu_seconds = started.elapsed().as_secs_f64();

    let mut solid_angle = Worst::default();
    let mut projected_solid_angle = Worst::default();
    let mut density = Worst::default();
    let mut horizon_density = Worst::default();
    let mut projected_direction = Worst::default();
    let mut solid_angle_direction = Worst::default();
    let mut weight = Worst::default();
    let mut failures = Vec::new();
    let (mut clipped_empty, mut central, mut decentral, mut below) = (0, 0, 0, 0);
    for (index, case) in cases.iter().enumerate() {
        let cpu = cpu_outcome(case);
        let gpu = gpu_outcome(&raw[index * RESULT_WORDS..(index + 1) * RESULT_WORDS]);
        let mut fail = |what: &str| failures.push(format!("case {index} {what}: cpu {cpu:?}\n  gpu {gpu:?}"));
        if case.polygon.as_slice().iter().any(|v| v.z < 0.0) {
            below += 1;
        }
        if cpu.clipped_count == 0 {
            clipped_empty += 1;
        } else if cpu.central {
            central += 1;
        } else {
            decentral += 1;
        }
        if (cpu.clipped_count, cpu.projected_count, cpu.central, cpu.solid_angle_count)
            != (gpu.clipped_count, gpu.projected_count, gpu.central, gpu.solid_angle_count)
        {
            fail("counts");
            continue;
        }
        if cpu.point != gpu.point {
            fail("sample point");
        }
        let eps = f32::EPSILON;
        let cancellation = if cpu.projected_solid_angle > 0.0 {
            CANCELLATION_ULPS * eps * cpu.solid_angle / cpu.projected_solid_angle
        } else {
            0.0
        };
        let projected_tolerance = VALUE_TOLERANCE + cancellation;
        let z = cpu.projected_sample.z.max(eps);
        let horizon_tolerance = projected_tolerance + HORIZON_ULPS * eps / (z * z);
        let size = angular_size(case);
        let mut ok = solid_angle.check(relative(gpu.solid_angle, cpu.solid_angle), VALUE_TOLERANCE, index);
        ok &=
            density.check(relative(gpu.solid_angle_density, cpu.solid_angle_density), VALUE_TOLERANCE, index);
        ok &= density.check(relative(gpu.probe_densities[1], cpu.probe_densities[1]), VALUE_TOLERANCE, index);
        if !ok {
            fail("solid angle or its density");
        }
        let mut ok = projected_solid_angle.check(
            relative(gpu.projected_solid_angle, cpu.projected_solid_angle),
            projected_tolerance,
            index,
        );
        ok &=
            density.check(relative(gpu.projected_density, cpu.projected_density), projected_tolerance, index);
        ok &= density.check(
            relative(gpu.probe_densities[0], cpu.probe_densities[0]),
            projected_tolerance,
            index,
        );
        ok &= horizon_density.check(
            relative(gpu.projected_in_solid_angle, cpu.projected_in_solid_angle),
            horizon_tolerance,
            index,
        );
        if !ok {
            fail("projected solid angle or its density");
        }
        if !solid_angle_direction.check(
            (gpu.solid_angle_sample - cpu.solid_angle_sample).length(),
            DIRECTION_TOLERANCE * size,
            index,
        ) {
            fail("solid-angle sample");
        }
        if !projected_direction.check(
            (gpu.projected_sample - cpu.projected_sample).length(),
            DIRECTION_TOLERANCE * size + HORIZON_ULPS * eps / z,
            index,
        ) {
            fail("projected-solid-angle sample");
        }
        let weight_tolerance = WEIGHT_TOLERANCE + horizon_tolerance.max(VALUE_TOLERANCE);
        let mut ok = true;
        for k in 0..2 {
            ok &= weight.check((gpu.weights[k] - cpu.weights[k]).abs(), weight_tolerance, index);
        }
        if !ok {
            fail("MIS weights");
        }
    }
    eprintln!(
        "{CASE_COUNT} cases ({below} partly or wholly below the horizon; {clipped_empty} empty after \
         clipping, {central} central, {decentral} decentral) on {}; GPU part {gpu_seconds:.2} s",
        context.info.name
    );
    solid_angle.report("relative difference of solid angles");
    projected_solid_angle.report("relative difference of projected solid angles");
    density.report("relative difference of densities 1/Ω, 1/Ω_proj (samples and probes)");
    horizon_density.report("relative difference of projected samples' densities per solid angle");
    solid_angle_direction.report("solid-angle sample direction difference");
    projected_direction.report("projected-solid-angle sample direction difference");
    weight.report("MIS weight difference");
    assert!(failures.is_empty(), "{} of {CASE_COUNT} cases differ:\n{}", failures.len(), failures.join("\n"));
    assert_validation_clean(&context);
}
