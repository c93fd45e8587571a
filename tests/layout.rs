//! What the embedded SPIR-V holds, read out of its instructions:
//! - the `#[repr(C)]` twins in `src/gpu_types.rs` have the layout the shaders were compiled with
//!   (OpMemberDecorate Offset, OpDecorate ArrayStride, against `offset_of!` and `size_of`);
//! - each shading variant contains only the code of its features: no polygonal-light, texture
//!   or other material code where the scene has none.

use multirate::gpu_types::{DrawConstants, GpuLight, GpuMaterial, GpuPolygonLight};
use multirate::shaders::{self, Features};
use std::collections::HashMap;
use std::mem::{offset_of, size_of};

const OP_NAME: u32 = 5;
const OP_MEMBER_NAME: u32 = 6;
const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const DECORATION_ARRAY_STRIDE: u32 = 6;
const DECORATION_OFFSET: u32 = 35;

#[derive(Default)]
struct Reflection {
    names: HashMap<u32, String>,
    member_names: HashMap<(u32, u32), String>,
    member_offsets: HashMap<(u32, u32), u32>,
    array_strides: HashMap<u32, u32>,
    runtime_array_element: HashMap<u32, u32>,
}

fn literal_string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

fn reflect(spirv: &[u8]) -> Reflection {
    let words = shaders::words(spirv);
    assert_eq!(words[0], 0x0723_0203, "SPIR-V magic number");
    let mut reflection = Reflection::default();
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        let opcode = words[at] & 0xffff;
        let operands = &words[at + 1..at + count];
        match opcode {
            OP_NAME => {
                reflection.names.insert(operands[0], literal_string(&operands[1..]));
            }
            OP_MEMBER_NAME => {
                reflection.member_names.insert((operands[0], operands[1]), literal_string(&operands[2..]));
            }
            OP_MEMBER_DECORATE if operands[2] == DECORATION_OFFSET => {
                reflection.member_offsets.insert((operands[0], operands[1]), operands[3]);
            }
            OP_DECORATE if operands[1] == DECORATION_ARRAY_STRIDE => {
                reflection.array_strides.insert(operands[0], operands[2]);
            }
            OP_TYPE_RUNTIME_ARRAY => {
                reflection.runtime_array_element.insert(operands[0], operands[1]);
            }
            _ => {}
        }
        assert!(count > 0, "malformed SPIR-V");
        at += count;
    }
    reflection
}

/// Checks every struct named `name` in every module; returns how many were checked.
fn check_struct(name: &str, expected: &[(&str, usize)], size: usize) -> usize {
    let mut checked = 0;
    for module in shaders::ALL {
        let (stage, reflection) = (module.stage, reflect(module.spirv));
        for (&type_id, type_name) in &reflection.names {
            if type_name != name {
                continue;
            }
            // Local copies (`GpuMaterial m = materials[i];`) get an undecorated twin type.
            let decorated = reflection.member_offsets.keys().any(|&(id, _)| id == type_id);
            if !decorated {
                continue;
            }
            for (member, &(member_name, offset)) in expected.iter().enumerate() {
                let key = (type_id, member as u32);
                assert_eq!(
                    reflection.member_names.get(&key).map(String::as_str),
                    Some(member_name),
                    "{stage}: member {member} of {name}"
                );
                assert_eq!(
                    reflection.member_offsets.get(&key).copied(),
                    Some(offset as u32),
                    "{stage}: offset of {name}.{member_name}"
                );
            }
            assert!(
                !reflection.member_names.contains_key(&(type_id, expected.len() as u32)),
                "{stage}: {name} has more members in GLSL than in Rust"
            );
            for (&array, &element) in &reflection.runtime_array_element {
                if element == type_id {
                    assert_eq!(
                        reflection.array_strides.get(&array).copied(),
                        Some(size as u32),
                        "{stage}: array stride of {name}[] vs size_of"
                    );
                }
            }
            checked += 1;
        }
    }
    checked
}

#[test]
fn gpu_light_matches_glsl() {
    let checked = check_struct(
        "GpuLight",
        &[("position", offset_of!(GpuLight, position)), ("radiance", offset_of!(GpuLight, radiance))],
        size_of::<GpuLight>(),
    );
    assert!(checked > 0, "no shader declares GpuLight: the test would check nothing");
}

#[test]
fn gpu_polygon_light_matches_glsl() {
    let checked = check_struct(
        "GpuPolygonLight",
        &[
            ("vertices", offset_of!(GpuPolygonLight, vertices)),
            ("normal", offset_of!(GpuPolygonLight, normal)),
            ("radiance", offset_of!(GpuPolygonLight, radiance)),
            ("info", offset_of!(GpuPolygonLight, info)),
        ],
        size_of::<GpuPolygonLight>(),
    );
    assert!(checked > 0, "no shader declares GpuPolygonLight");
}

#[test]
fn gpu_material_matches_glsl() {
    let checked = check_struct(
        "GpuMaterial",
        &[
            ("diffuse", offset_of!(GpuMaterial, diffuse)),
            ("specular", offset_of!(GpuMaterial, specular)),
            ("params", offset_of!(GpuMaterial, params)),
            ("maps", offset_of!(GpuMaterial, maps)),
            ("parameter_range", offset_of!(GpuMaterial, parameter_range)),
        ],
        size_of::<GpuMaterial>(),
    );
    assert!(checked > 0, "no shader declares GpuMaterial");
}

#[test]
fn draw_constants_match_glsl() {
    let checked = check_struct(
        "DrawConstants",
        &[
            ("view_proj", offset_of!(DrawConstants, view_proj)),
            ("eye", offset_of!(DrawConstants, eye)),
            ("viewport", offset_of!(DrawConstants, viewport)),
            ("material_index", offset_of!(DrawConstants, material_index)),
            ("mesh_index", offset_of!(DrawConstants, mesh_index)),
            ("fixed_level", offset_of!(DrawConstants, fixed_level)),
            ("patch_base", offset_of!(DrawConstants, patch_base)),
            ("flags", offset_of!(DrawConstants, flags)),
            ("light_index", offset_of!(DrawConstants, light_index)),
            ("triangle_count", offset_of!(DrawConstants, triangle_count)),
            ("patches_per_draw", offset_of!(DrawConstants, patches_per_draw)),
        ],
        size_of::<DrawConstants>(),
    );
    assert!(checked > 0, "no shader declares DrawConstants");
    assert!(size_of::<DrawConstants>() <= 128, "push constants beyond the guaranteed 128 bytes");
}

const OP_EXT_INST: u32 = 12;
const OP_IMAGE_SAMPLE_FIRST: u32 = 87; // OpImageSampleImplicitLod
const OP_IMAGE_SAMPLE_LAST: u32 = 94; // OpImageSampleProjDrefExplicitLod
const OP_IMAGE_QUERY_SIZE_LOD: u32 = 103;
const DECORATION_SPEC_ID: u32 = 1;
const OP_EXECUTION_MODE: u32 = 16;
const OP_CONSTANT: u32 = 43;
const OP_EXECUTION_MODE_ID: u32 = 331;
const EXECUTION_MODE_LOCAL_SIZE: u32 = 17;
const EXECUTION_MODE_LOCAL_SIZE_ID: u32 = 38;
const OP_SPEC_CONSTANT: u32 = 50;
const OP_SPEC_CONSTANT_COMPOSITE: u32 = 51;
const DECORATION_BUILT_IN: u32 = 11;
const BUILT_IN_WORKGROUP_SIZE: u32 = 25;
const GLSL_STD_450_POW: u32 = 26;
/// brdf.glsl's polygonal-light constants (count, samples, technique, MIS v).
const POLYGON_SPEC_IDS: std::ops::RangeInclusive<u32> = 8..=11;

/// The instructions of a module that tell which code it holds.
#[derive(Debug, Default)]
struct Contents {
    instructions: usize,
    spec_ids: Vec<u32>,
    texture_reads: usize,
    pows: usize,
    /// A compute shader's `local_size_x` (SPIR-V 1.6 gives it as the id of a constant).
    local_size_x: Option<u32>,
    local_size_x_id: Option<u32>,
    /// Constants' and specialization constants' (default) values by id.
    constants: HashMap<u32, u32>,
    /// The `WorkgroupSize` built-in (`local_size_x_id` in GLSL): its id, and each
    /// specialization-constant composite's first component by id.
    workgroup_size: Option<u32>,
    composites_x: HashMap<u32, u32>,
}

fn contents(spirv: &[u8]) -> Contents {
    let words = shaders::words(spirv);
    let mut contents = Contents::default();
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        assert!(count > 0, "malformed SPIR-V");
        let opcode = words[at] & 0xffff;
        let operands = &words[at + 1..at + count];
        contents.instructions += 1;
        match opcode {
            OP_DECORATE if operands[1] == DECORATION_SPEC_ID => contents.spec_ids.push(operands[2]),
            OP_DECORATE if operands[1] == DECORATION_BUILT_IN && operands[2] == BUILT_IN_WORKGROUP_SIZE => {
                contents.workgroup_size = Some(operands[0])
            }
            OP_IMAGE_SAMPLE_FIRST..=OP_IMAGE_SAMPLE_LAST | OP_IMAGE_QUERY_SIZE_LOD => {
                contents.texture_reads += 1
            }
            OP_EXT_INST if operands[3] == GLSL_STD_450_POW => contents.pows += 1,
            OP_EXECUTION_MODE if operands[1] == EXECUTION_MODE_LOCAL_SIZE => {
                contents.local_size_x = Some(operands[2])
            }
            OP_EXECUTION_MODE_ID if operands[1] == EXECUTION_MODE_LOCAL_SIZE_ID => {
                contents.local_size_x_id = Some(operands[2])
            }
            OP_CONSTANT | OP_SPEC_CONSTANT if operands.len() == 3 => {
                contents.constants.insert(operands[1], operands[2]);
            }
            OP_SPEC_CONSTANT_COMPOSITE if operands.len() >= 3 => {
                contents.composites_x.insert(operands[1], operands[2]);
            }
            _ => {}
        }
        at += count;
    }
    if let Some(id) = contents.local_size_x_id {
        contents.local_size_x = contents.constants.get(&id).copied();
    }
    // The built-in, where present, is the size (SPIR-V: it overrides LocalSize).
    if let Some(x) = contents.workgroup_size.and_then(|id| contents.composites_x.get(&id)) {
        contents.local_size_x = contents.constants.get(x).copied();
    }
    contents
}

fn pixel_shader(material_kind: u32, polygon_lights: bool, textured: bool) -> Contents {
    let features = Features { material_kind, polygon_lights, textured, ..Features::default() };
    contents(shaders::spirv("pixel.frag", features))
}

#[test]
fn untextured_pixel_shader_without_polygon_lights_has_neither() {
    let lean = pixel_shader(1, false, false);
    let full = pixel_shader(1, true, true);
    // The detectors see the code where it is there.
    assert!(full.spec_ids.iter().any(|id| POLYGON_SPEC_IDS.contains(id)), "{full:?}");
    assert!(full.texture_reads > 0, "{full:?}");
    assert!(!lean.spec_ids.iter().any(|id| POLYGON_SPEC_IDS.contains(id)), "polygon constants in {lean:?}");
    assert_eq!(lean.texture_reads, 0, "texture reads in the untextured variant");
    // Only the light counts are left to specialise.
    assert_eq!(lean.spec_ids.iter().copied().collect::<std::collections::BTreeSet<_>>(), [1, 2].into());
    assert!(
        lean.instructions * 10 < full.instructions,
        "the lean variant has {} instructions against {} with polygons and textures",
        lean.instructions,
        full.instructions
    );
}

#[test]
fn lambert_pixel_shader_has_no_specular_lobe() {
    // Blinn-Phong's lobe is the only pow of an untextured variant without polygonal lights.
    assert!(pixel_shader(1, false, false).pows > 0);
    assert_eq!(pixel_shader(0, false, false).pows, 0);
}

#[test]
fn every_shading_variant_holds_only_its_features() {
    let mut checked = 0;
    for module in shaders::ALL {
        let features = module.features();
        let found = contents(module.spirv);
        if !features.polygon_lights {
            assert!(
                !found.spec_ids.iter().any(|id| POLYGON_SPEC_IDS.contains(id)),
                "{}: {features:?} holds polygonal-light constants",
                module.stage
            );
        }
        if !features.textured && module.stage != "present.frag" {
            // (present.frag samples the rendered image, whatever the scene.)
            assert_eq!(found.texture_reads, 0, "{}: {features:?} reads textures", module.stage);
        }
        checked += 1;
    }
    assert!(checked > 100, "only {checked} modules: build.rs compiled no variants");
}

#[test]
fn pre_pass_workgroups_have_the_size_the_host_dispatches() {
    // The host sizes the culling step's dispatch, and the culling step the later steps', by
    // render::PRE_PASS_GROUP (the refining step's by blocks; PRE_PASS_GROUP is its default size,
    // a CPU device's pipeline takes render::REFINE_BLOCK).
    let pre_pass = ["cull_triangles.comp", "triangle_levels.comp", "refine_levels.comp", "patch_levels.comp"];
    let mut checked = 0;
    for module in shaders::ALL.iter().filter(|m| pre_pass.contains(&m.stage)) {
        let size = contents(module.spirv).local_size_x;
        assert_eq!(size, Some(multirate::render::PRE_PASS_GROUP), "{} {:?}", module.stage, module.features());
        checked += 1;
    }
    assert!(checked >= pre_pass.len(), "only {checked} pre-pass modules");
}

#[test]
fn both_sides_of_the_refining_step_block_the_triangles_as_the_host_does() {
    // The estimator step opens a refining workgroup per block, the refining step takes the
    // block's triangles, and a CPU device's refining workgroup is the block: the three
    // definitions must agree (a folded GLSL constant leaves no trace in the SPIR-V to read).
    for stage in ["triangle_levels.comp", "refine_levels.comp"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("glsl").join(stage);
        let source = std::fs::read_to_string(&path).expect("the stage's source");
        let defined: Vec<u32> = source
            .lines()
            .filter_map(|line| line.trim().strip_prefix("const uint REFINE_BLOCK = "))
            .map(|value| value.trim_end_matches(';').trim_end_matches('u').parse().expect("a uint literal"))
            .collect();
        assert_eq!(defined, [multirate::render::REFINE_BLOCK], "{stage}'s REFINE_BLOCK");
    }
}

#[test]
fn only_the_instrumented_control_stage_is_specialised_to_record_or_count() {
    // multirate.tesc's analysis pipelines share its instrumented module, which the host
    // specialises with constants 14 (record the levels) and 15 (count the culled patches); the
    // timed module must not carry them (lavapipe runs code that is specialised off).
    let instrumentation = [14, 15];
    let (mut timed, mut instrumented) = (0, 0);
    for module in shaders::ALL.iter().filter(|m| m.stage == "multirate.tesc") {
        let found = contents(module.spirv);
        let has = |id: &u32| found.spec_ids.contains(id);
        if module.features().count_evaluations {
            assert!(instrumentation.iter().all(has), "{:?}: {:?}", module.features(), found.spec_ids);
            instrumented += 1;
        } else {
            assert!(!instrumentation.iter().any(has), "{:?}: {:?}", module.features(), found.spec_ids);
            timed += 1;
        }
    }
    assert_eq!((timed, instrumented), (12, 12), "a timed and an instrumented module per feature set");
}
