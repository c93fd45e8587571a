//! The estimator's entry points, [`estimate`] and [`estimate_textured`] (their input and result
//! are in `terms.rs`), and the loop over the lights that sums their bounds (`light_sums`).
//!
//! GLSL twin: `glsl/include/estimator/estimate.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit). There `estimate_pass` is
//! [`estimate_textured`] after the range class, `required_level` runs it again over the children
//! where it asks for it, and `light_sums` and `refining_futile` are as here.

use super::add_light::add_light;
use super::constants::{REFINE_ABOVE, REFINE_FLOOR_MARGIN};
use super::decide::decide;
use super::frame::Frame;
use super::jet::Guard;
use super::light_setup::Sums;
use super::range::{range_class, range_proves, SpecularCaps};
use super::settings::{EstimatorSettings, Split};
use super::terms::{Estimate, Reason, TriangleInput, TERM_COUNT};
use crate::scene::{Light, MaterialKind, ParameterRange};

/// Estimates the tessellation level of one triangle. See the module docs and
/// `docs/estimator.md`.
pub fn estimate(
    tri: &TriangleInput,
    material: &MaterialKind,
    lights: &[Light],
    settings: &EstimatorSettings,
) -> Estimate {
    estimate_textured(tri, material, ParameterRange::of(material), lights, settings)
}

/// [`estimate`] for a material whose shininess or roughness varies over the triangle within
/// `parameter` (the material's own value is then not used). The bound holds for every
/// sub-vertex and pixel value of the parameter in the range: the interpolation error is
/// bounded over the range (`sup_α* ‖f_α* − L f_α*‖`, paper Eq. 36) and the variation
/// `sup |f(α) − f(α')|` is added as an `n`-independent term (Eq. 37). See `docs/estimator.md`.
pub fn estimate_textured(
    tri: &TriangleInput,
    material: &MaterialKind,
    parameter: ParameterRange,
    lights: &[Light],
    settings: &EstimatorSettings,
) -> Estimate {
    let n_max = settings.n_max.clamp(1, 64);
    // NaN and non-positive ε become 0: only an exactly flat shading passes then.
    let eps = if settings.epsilon > 0.0 { settings.epsilon } else { 0.0 };
    // The range class: where the shading's whole range over the triangle is within ε, level 1
    // holds without an estimate.
    let eye = (tri.eye, settings.eye_radius);
    let class = range_class(tri.positions, tri.normals, eye, material, parameter, lights, eps);
    let range = class.bound;
    if range_proves(range, eps) {
        let predicted_error = range.map_or(0.0, |r| r.max_element());
        return Estimate {
            terms: [0.0; TERM_COUNT],
            level: 1.0,
            n: 1,
            fallback: false,
            reason: Reason::None,
            predicted_error,
            refined: false,
        };
    }
    let capped = class.every_specular_capped;
    let (sum, reason) = light_sums(tri, material, parameter, lights, settings, n_max, eps, capped, false);
    let first = decide(&sum, eps, n_max, settings.split, reason);
    let refining_can_help = !refining_futile(&sum, eps, settings.split);
    if first.level > REFINE_ABOVE && (!first.fallback || first.reason == Reason::Level) && refining_can_help {
        let (sum, reason) = light_sums(tri, material, parameter, lights, settings, n_max, eps, capped, true);
        return Estimate { refined: true, ..decide(&sum, eps, n_max, settings.split, reason) };
    }
    first
}

/// Whether the estimate refined over the children must fall back, as its refining floor
/// ([`Sums::floor`]) exceeds `ε` at every level up to the top: then it is not computed. The
/// Heuristic split only (the Uniform split's decision is not bounded by the floor).
pub(super) fn refining_futile(sum: &Sums, eps: f32, split: Split) -> bool {
    split == Split::Heuristic && sum.floor.max_element() > eps * REFINE_FLOOR_MARGIN
}

/// Every light's bounds, summed, and the worst reason for fallback met on the way; with
/// `every_capped` ([`RangeClass::every_specular_capped`]), each light's specular part bounded by
/// its cap; with `refine`, the ranges of the point and directional lights taken over the patch's
/// children.
///
/// [`RangeClass::every_specular_capped`]: super::range::RangeClass::every_specular_capped
#[allow(clippy::too_many_arguments)]
pub(super) fn light_sums(
    tri: &TriangleInput,
    material: &MaterialKind,
    parameter: ParameterRange,
    lights: &[Light],
    settings: &EstimatorSettings,
    n_max: u32,
    eps: f32,
    every_capped: bool,
    refine: bool,
) -> (Sums, Reason) {
    let frame = Frame::new(tri, settings.eye_radius, material.is_specular());
    let caps = if every_capped { SpecularCaps::new(&frame, material) } else { None };
    let guard = Guard::default();
    let mut sum = Sums::default();
    let mut reason = Reason::None;
    // Point lights first, then directional ones, then polygons: the order of the GPU's light
    // buffers, so that the control stage sums the bounds in the same order (bit-identical).
    let points = lights.iter().filter(|l| matches!(l, Light::Point { .. }));
    let directionals = lights.iter().filter(|l| matches!(l, Light::Directional { .. }));
    let polygons = lights.iter().filter(|l| matches!(l, Light::Polygon(_)));
    for light in points.chain(directionals).chain(polygons) {
        let added = add_light(
            &frame,
            material,
            parameter,
            light,
            settings.discontinuity,
            settings.split,
            n_max,
            eps,
            refine,
            caps.as_ref(),
            &mut sum,
            &guard,
        );
        if let Err(r) = added {
            reason = worse(reason, r);
        }
    }
    if guard.bad.get() {
        reason = worse(reason, Reason::Singular);
    }
    (sum, reason)
}

pub(super) fn worse(a: Reason, b: Reason) -> Reason {
    let rank = |r: Reason| match r {
        Reason::None => 0,
        Reason::Level => 1,
        Reason::Discontinuity => 2,
        Reason::Singular => 3,
    };
    if rank(b) > rank(a) {
        b
    } else {
        a
    }
}
