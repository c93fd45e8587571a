//! Every specialization constant of the shaders: its id and its GLSL name (twins: the
//! `layout(constant_id = N)` declarations named below).

/// A specialization constant: the `constant_id` the host sets and the name of the GLSL constant
/// it sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpecId {
    /// The GLSL constant's name; [`LOCAL_SIZE_X`] for a workgroup's size (`local_size_x_id`),
    /// which has none in SPIR-V.
    pub name: &'static str,
    pub id: u32,
}

/// The name [`SpecId::name`] gives a compute stage's `local_size_x_id`.
pub const LOCAL_SIZE_X: &str = "local_size_x";

/// present.frag, post_composite.frag: encode the tone-mapped image as sRGB.
pub const ENCODE_SRGB: SpecId = SpecId { name: "ENCODE_SRGB", id: 0 };
/// brdf.glsl: the scene's point lights, first in the light buffer.
pub const POINT_LIGHT_COUNT: SpecId = SpecId { name: "POINT_LIGHT_COUNT", id: 1 };
/// brdf.glsl: the scene's directional lights, after the point lights.
pub const DIRECTIONAL_LIGHT_COUNT: SpecId = SpecId { name: "DIRECTIONAL_LIGHT_COUNT", id: 2 };
/// estimator/constants.glsl: the split of ε between the terms (0 uniform, 1 heuristic).
pub const SPLIT: SpecId = SpecId { name: "SPLIT", id: 3 };
/// estimator/constants.glsl: the terminator handling (0 conservative, 1 relaxed).
pub const DISCONTINUITY: SpecId = SpecId { name: "DISCONTINUITY", id: 4 };
/// brdf.glsl: the scene's polygonal lights (only the variants with polygonal lights).
pub const POLYGON_LIGHT_COUNT: SpecId = SpecId { name: "POLYGON_LIGHT_COUNT", id: 8 };
/// brdf.glsl: samples per technique of a polygonal light.
pub const POLYGON_SAMPLES: SpecId = SpecId { name: "POLYGON_SAMPLES", id: 9 };
/// brdf.glsl: the polygonal lights' sampling technique (0 projected solid angle, 1 solid angle).
pub const POLYGON_TECHNIQUE: SpecId = SpecId { name: "POLYGON_TECHNIQUE", id: 10 };
/// brdf.glsl: MIS's visibility estimate v (polygon_light.glsl).
pub const MIS_VISIBILITY: SpecId = SpecId { name: "MIS_VISIBILITY", id: 11 };
/// refine_levels.comp: the refining step's workgroup size (`local_size_x_id`).
pub const REFINE_LANES: SpecId = SpecId { name: LOCAL_SIZE_X, id: 13 };
/// multirate.tesc (its instrumented module): write each triangle's levels.
pub const RECORD_LEVELS: SpecId = SpecId { name: "RECORD_LEVELS", id: 14 };
/// multirate.tesc (its instrumented module): count the patches culled before their estimate.
pub const COUNT_CULLED_PATCHES: SpecId = SpecId { name: "COUNT_CULLED_PATCHES", id: 15 };
/// estimator/constants.glsl: the estimator step's variant over the triangles whose every light's
/// specular part is capped (no specular setup or jets).
pub const SPECULAR_ALL_CAPPED: SpecId = SpecId { name: "SPECULAR_ALL_CAPPED", id: 16 };
/// shadow.glsl: some light casts shadows (without, no shadow code is compiled in).
pub const SHADOWS: SpecId = SpecId { name: "SHADOWS", id: 17 };
/// shadow.glsl: the fragment stage may look a visibility up; false in the draw of the flat
/// patches no light reaches only in part, which then holds no lookup code.
pub const SHADOW_LOOKUPS: SpecId = SpecId { name: "SHADOW_LOOKUPS", id: 18 };
/// multirate_flat.vert: which of the listed flat patches a draw shows, by visibility class
/// (`slots::EVERY_SHADOW_CLASS`, `WITHOUT_MIXED_LIGHTS`, `WITH_MIXED_LIGHTS`).
pub const DRAWN_SHADOW_CLASSES: SpecId = SpecId { name: "DRAWN_SHADOW_CLASSES", id: 19 };
/// shadow.glsl: the point lights that cast shadows, the first in the light buffer
/// (`render::ShaderLights`).
pub const SHADOWED_POINT_LIGHTS: SpecId = SpecId { name: "SHADOWED_POINT_LIGHTS", id: 20 };
/// shadow.glsl: the directional lights that cast shadows, the first after the point lights.
pub const SHADOWED_DIRECTIONAL_LIGHTS: SpecId = SpecId { name: "SHADOWED_DIRECTIONAL_LIGHTS", id: 21 };

/// The polygonal lights' constants, which only the variants with polygonal lights contain.
pub const POLYGON_LIGHTS: [SpecId; 4] =
    [POLYGON_LIGHT_COUNT, POLYGON_SAMPLES, POLYGON_TECHNIQUE, MIS_VISIBILITY];

/// Every specialization constant, by id.
pub const ALL: [SpecId; 18] = [
    ENCODE_SRGB,
    POINT_LIGHT_COUNT,
    DIRECTIONAL_LIGHT_COUNT,
    SPLIT,
    DISCONTINUITY,
    POLYGON_LIGHT_COUNT,
    POLYGON_SAMPLES,
    POLYGON_TECHNIQUE,
    MIS_VISIBILITY,
    REFINE_LANES,
    RECORD_LEVELS,
    COUNT_CULLED_PATCHES,
    SPECULAR_ALL_CAPPED,
    SHADOWS,
    SHADOW_LOOKUPS,
    DRAWN_SHADOW_CLASSES,
    SHADOWED_POINT_LIGHTS,
    SHADOWED_DIRECTIONAL_LIGHTS,
];
