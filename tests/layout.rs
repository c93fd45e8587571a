//! What the embedded SPIR-V holds, read out of its instructions:
//! - the `#[repr(C)]` twins in `src/gpu_types.rs` have the layout the shaders were compiled with
//!   (OpMemberDecorate Offset, OpDecorate ArrayStride, against `offset_of!` and `size_of`);
//! - every descriptor and specialization constant is where `multirate::gpu_interface` says
//!   (OpName, OpDecorate DescriptorSet, Binding and SpecId), and the check sees a swap;
//! - the GLSL twins of the constants SPIR-V folds away (the `DrawConstants::flags` bits, the
//!   pre-pass's slots) are declared once, with the values of their Rust names;
//! - each shading variant contains only the code of its features: no polygonal-light, texture
//!   or other material code where the scene has none.

use multirate::gpu_interface::bindings::{self, Binding, DescriptorKind, TexelFormat};
use multirate::gpu_interface::specialization::{self, SpecId};
use multirate::gpu_interface::{flags, slots};
use multirate::gpu_types::{DrawConstants, GpuLight, GpuMaterial, GpuPolygonLight, LevelHold};
use multirate::render::level_hold;
use multirate::shaders::{self, Features};
use std::collections::{HashMap, HashSet};
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

/// The instructions of a module: `(opcode, operands)`, after the 5-word header.
fn instructions(words: &[u32]) -> impl Iterator<Item = (u32, &[u32])> {
    assert_eq!(words.first(), Some(&0x0723_0203), "SPIR-V magic number");
    let mut at = 5;
    std::iter::from_fn(move || {
        let first = *words.get(at)?;
        let count = (first >> 16) as usize;
        assert!(count > 0 && at + count <= words.len(), "malformed SPIR-V at word {at}");
        let instruction = (first & 0xffff, &words[at + 1..at + count]);
        at += count;
        Some(instruction)
    })
}

fn reflect(spirv: &[u8]) -> Reflection {
    let words = shaders::words(spirv);
    let mut reflection = Reflection::default();
    for (opcode, operands) in instructions(&words) {
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
        &[
            ("position", offset_of!(GpuLight, position)),
            ("radiance", offset_of!(GpuLight, radiance)),
            ("shadow", offset_of!(GpuLight, shadow)),
        ],
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
fn level_hold_matches_glsl() {
    let checked = check_struct(
        "LevelHold",
        &[
            ("held", offset_of!(LevelHold, held)),
            ("lower", offset_of!(LevelHold, lower)),
            ("estimates", offset_of!(LevelHold, estimates)),
            ("closed", offset_of!(LevelHold, closed)),
        ],
        size_of::<LevelHold>(),
    );
    assert!(checked > 0, "no shader declares LevelHold");
}

#[test]
fn draw_constants_match_glsl() {
    let checked = check_struct(
        "DrawConstants",
        &[
            ("view_proj", offset_of!(DrawConstants, view_proj)),
            ("eye", offset_of!(DrawConstants, eye)),
            ("min_estimated_area", offset_of!(DrawConstants, min_estimated_area)),
            ("viewport_size", offset_of!(DrawConstants, viewport_size)),
            ("epsilon", offset_of!(DrawConstants, epsilon)),
            ("n_max", offset_of!(DrawConstants, n_max)),
            ("material_index", offset_of!(DrawConstants, material_index)),
            ("mesh_index", offset_of!(DrawConstants, mesh_index)),
            ("draw_argument", offset_of!(DrawConstants, draw_argument)),
            ("patch_base", offset_of!(DrawConstants, patch_base)),
            ("flags", offset_of!(DrawConstants, flags)),
            ("eye_radius", offset_of!(DrawConstants, eye_radius)),
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

/// Whether `ids` holds one of the polygonal lights' constants.
fn any_polygon_spec_id(ids: &[u32]) -> bool {
    specialization::POLYGON_LIGHTS.iter().any(|constant| ids.contains(&constant.id))
}

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
    for (opcode, operands) in instructions(&words) {
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
    assert!(any_polygon_spec_id(&full.spec_ids), "{full:?}");
    assert!(full.texture_reads > 0, "{full:?}");
    assert!(!any_polygon_spec_id(&lean.spec_ids), "polygon constants in {lean:?}");
    assert_eq!(lean.texture_reads, 0, "texture reads in the untextured variant");
    // Only the light counts and which lights cast shadows are left to specialise.
    let light_counts = [
        specialization::POINT_LIGHT_COUNT.id,
        specialization::DIRECTIONAL_LIGHT_COUNT.id,
        specialization::SHADOWS.id,
        specialization::SHADOWED_POINT_LIGHTS.id,
        specialization::SHADOWED_DIRECTIONAL_LIGHTS.id,
    ];
    assert_eq!(lean.spec_ids.iter().copied().collect::<std::collections::BTreeSet<_>>(), light_counts.into());
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
                !any_polygon_spec_id(&found.spec_ids),
                "{}: {features:?} holds polygonal-light constants",
                module.stage
            );
        }
        let samples_the_frame = ["present", "post"].contains(&bindings::layout_of(module.stage).name);
        if !features.textured && !samples_the_frame {
            // (present.frag and the post chain sample the rendered image, whatever the scene.)
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
    let pre_pass = [
        "cull_triangles.comp",
        "range_levels.comp",
        "triangle_levels.comp",
        "refine_levels.comp",
        "patch_levels.comp",
    ];
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
    // specialises to record the levels or to count the culled patches; the timed module must not
    // carry those constants (lavapipe runs code that is specialised off).
    let instrumentation = [specialization::RECORD_LEVELS.id, specialization::COUNT_CULLED_PATCHES.id];
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

const OP_TYPE_INT: u32 = 21;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_IMAGE: u32 = 25;
const OP_TYPE_SAMPLED_IMAGE: u32 = 27;
const DIM_BUFFER: u32 = 5;
const OP_TYPE_POINTER: u32 = 32;
const OP_VARIABLE: u32 = 59;
const DECORATION_BINDING: u32 = 33;
const DECORATION_DESCRIPTOR_SET: u32 = 34;
const STORAGE_CLASS_UNIFORM_CONSTANT: u32 = 0;
const STORAGE_CLASS_STORAGE_BUFFER: u32 = 12;

/// A descriptor a module declares: its variable, its name (the block's for a buffer, the
/// variable's otherwise, as `gpu_interface::bindings` names them), set, binding and kind.
#[derive(Clone, Debug, PartialEq)]
struct Descriptor {
    variable: u32,
    name: String,
    set: u32,
    binding: u32,
    /// None: neither a storage buffer, a combined image sampler nor a texel buffer.
    kind: Option<DescriptorKind>,
}

/// What a module declares of the host's interface.
#[derive(Debug, Default)]
struct Declared {
    descriptors: Vec<Descriptor>,
    /// Per `SpecId` decoration: the constant's name ([`specialization::LOCAL_SIZE_X`] for a
    /// workgroup size, empty where SPIR-V names it not) and its id.
    spec_constants: Vec<(String, u32)>,
}

/// The ids of the module's workgroup-size constants in x (`local_size_x_id`): the x operand of
/// `LocalSizeId`, and the first constituent of the `WorkgroupSize` built-in.
fn local_size_x_ids(words: &[u32]) -> Vec<u32> {
    let mut workgroup_size = None;
    let mut composites = HashMap::new();
    let mut ids = Vec::new();
    for (opcode, operands) in instructions(words) {
        match opcode {
            OP_EXECUTION_MODE_ID if operands[1] == EXECUTION_MODE_LOCAL_SIZE_ID => ids.push(operands[2]),
            OP_DECORATE if operands[1] == DECORATION_BUILT_IN && operands[2] == BUILT_IN_WORKGROUP_SIZE => {
                workgroup_size = Some(operands[0])
            }
            OP_SPEC_CONSTANT_COMPOSITE => {
                composites.insert(operands[1], operands[2]);
            }
            _ => {}
        }
    }
    ids.extend(workgroup_size.and_then(|id| composites.get(&id)));
    ids
}

fn declared_interface(words: &[u32]) -> Declared {
    let mut names = HashMap::new();
    let (mut sets, mut bindings, mut spec_ids) = (HashMap::new(), HashMap::new(), Vec::new());
    let (mut pointers, mut sampled_images, mut variables) = (HashMap::new(), HashSet::new(), Vec::new());
    // Per image type: whether it is a buffer's texels, and its texels' format where it is.
    let (mut images, mut scalar_kinds) = (HashMap::new(), HashMap::new());
    for (opcode, operands) in instructions(words) {
        match opcode {
            OP_NAME => {
                names.insert(operands[0], literal_string(&operands[1..]));
            }
            OP_DECORATE if operands[1] == DECORATION_DESCRIPTOR_SET => {
                sets.insert(operands[0], operands[2]);
            }
            OP_DECORATE if operands[1] == DECORATION_BINDING => {
                bindings.insert(operands[0], operands[2]);
            }
            OP_DECORATE if operands[1] == DECORATION_SPEC_ID => spec_ids.push((operands[0], operands[2])),
            OP_TYPE_POINTER => {
                pointers.insert(operands[0], operands[2]);
            }
            OP_TYPE_INT => {
                scalar_kinds.insert(operands[0], TexelFormat::Uint4);
            }
            OP_TYPE_FLOAT => {
                scalar_kinds.insert(operands[0], TexelFormat::Float4);
            }
            OP_TYPE_IMAGE => {
                images.insert(operands[0], (operands[2] == DIM_BUFFER, operands[1]));
            }
            OP_TYPE_SAMPLED_IMAGE => {
                sampled_images.insert(operands[0]);
            }
            OP_VARIABLE => variables.push((operands[1], operands[0], operands[2])),
            _ => {}
        }
    }
    let name_of = |id: &u32| names.get(id).cloned().unwrap_or_default();
    let mut declared = Declared::default();
    for (variable, pointer, storage_class) in variables {
        let (Some(&set), Some(&binding)) = (sets.get(&variable), bindings.get(&variable)) else { continue };
        let pointee = pointers.get(&pointer).copied().unwrap_or_default();
        let (kind, name) = match storage_class {
            STORAGE_CLASS_STORAGE_BUFFER => (Some(DescriptorKind::StorageBuffer), name_of(&pointee)),
            // A texel buffer's variable is of its image type, a sampler's of a sampled image.
            STORAGE_CLASS_UNIFORM_CONSTANT => {
                let kind = match (sampled_images.contains(&pointee), images.get(&pointee)) {
                    (true, _) => Some(DescriptorKind::CombinedImageSampler),
                    (false, Some(&(true, sampled_type))) => scalar_kinds
                        .get(&sampled_type)
                        .map(|&format| DescriptorKind::UniformTexelBuffer(format)),
                    _ => None,
                };
                (kind, name_of(&variable))
            }
            _ => (None, name_of(&variable)),
        };
        declared.descriptors.push(Descriptor { variable, name, set, binding, kind });
    }
    // glslang gives `gl_WorkGroupSize` a copy of the size's constant, unnamed, of the same id.
    let local_size_x = local_size_x_ids(words);
    let local_size_x_spec_ids: Vec<u32> =
        spec_ids.iter().filter(|(constant, _)| local_size_x.contains(constant)).map(|&(_, id)| id).collect();
    for (constant, id) in spec_ids {
        let name = match name_of(&constant) {
            name if name.is_empty() && local_size_x_spec_ids.contains(&id) => {
                specialization::LOCAL_SIZE_X.into()
            }
            name => name,
        };
        declared.spec_constants.push((name, id));
    }
    declared
}

/// Where `declared`, a module of `stage`, differs from `gpu_interface`: a descriptor or
/// specialization constant it does not name, or names elsewhere, or of another kind.
fn interface_mismatches(stage: &str, declared: &Declared) -> Vec<String> {
    let layout = bindings::layout_of(stage);
    let mut mismatches = Vec::new();
    for d in &declared.descriptors {
        let found = (d.name.as_str(), d.set, d.binding, d.kind);
        match layout.find(&d.name) {
            None => mismatches.push(format!(
                "{stage}: descriptor {:?} (set {}, binding {}) is not in gpu_interface::bindings's {} layout",
                d.name, d.set, d.binding, layout.name
            )),
            Some(Binding { name, set, binding, kind }) if (name, set, binding, Some(kind)) != found => {
                mismatches.push(format!(
                    "{stage}: descriptor {:?} is at set {}, binding {} ({:?}); gpu_interface::bindings \
                     says set {set}, binding {binding} ({kind:?})",
                    d.name, d.set, d.binding, d.kind
                ))
            }
            Some(_) => {}
        }
    }
    for (name, id) in &declared.spec_constants {
        match specialization::ALL.iter().find(|constant| constant.name == name.as_str()) {
            None => mismatches.push(format!(
                "{stage}: specialization constant {name:?} (id {id}) is not in gpu_interface::specialization"
            )),
            Some(SpecId { id: expected, .. }) if expected != id => mismatches.push(format!(
                "{stage}: specialization constant {name} has id {id}; gpu_interface says {expected}"
            )),
            Some(_) => {}
        }
    }
    mismatches
}

#[test]
fn every_module_declares_the_interface_the_host_binds() {
    let mut mismatches = Vec::new();
    let (mut descriptors, mut constants) = (HashSet::new(), HashSet::new());
    for module in shaders::ALL {
        let declared = declared_interface(&shaders::words(module.spirv));
        mismatches.extend(interface_mismatches(module.stage, &declared));
        descriptors.extend(declared.descriptors.into_iter().map(|d| d.name));
        constants.extend(declared.spec_constants.into_iter().map(|(name, _)| name));
    }
    assert!(mismatches.is_empty(), "{} mismatches:\n{}", mismatches.len(), mismatches.join("\n"));
    // And no Rust name is stale: each is declared by some module.
    for layout in bindings::LAYOUTS {
        for b in layout.sets.iter().flat_map(|set| set.iter()) {
            assert!(
                descriptors.contains(b.name),
                "no module declares {} of the {} layout",
                b.name,
                layout.name
            );
        }
    }
    for constant in specialization::ALL {
        assert!(constants.contains(constant.name), "no module declares specialization constant {constant:?}");
    }
}

/// `words` with the Binding decorations of the variables `a` and `b` exchanged.
fn with_bindings_swapped(words: &[u32], a: u32, b: u32) -> Vec<u32> {
    let mut swapped = words.to_vec();
    let mut literal_of = HashMap::new();
    let mut at = 5;
    for (opcode, operands) in instructions(words) {
        if opcode == OP_DECORATE && operands[1] == DECORATION_BINDING {
            literal_of.insert(operands[0], at + 3);
        }
        at += operands.len() + 1;
    }
    let (a, b) = (literal_of[&a], literal_of[&b]);
    swapped.swap(a, b);
    swapped
}

#[test]
fn the_check_reports_two_storage_buffers_swapped() {
    let stage = "deferred.frag";
    let words = shaders::words(shaders::spirv(stage, Features::default()));
    let declared = declared_interface(&words);
    assert_eq!(interface_mismatches(stage, &declared), Vec::<String>::new());
    let storage: Vec<&Descriptor> =
        declared.descriptors.iter().filter(|d| d.kind == Some(DescriptorKind::StorageBuffer)).collect();
    assert!(storage.len() >= 2, "{stage} has {} storage buffers", storage.len());
    let (a, b) = (storage[0], storage[1]);
    let swapped = declared_interface(&with_bindings_swapped(&words, a.variable, b.variable));
    let found = |name: &str| swapped.descriptors.iter().find(|d| d.name == name).map(|d| d.binding);
    assert_eq!((found(&a.name), found(&b.name)), (Some(b.binding), Some(a.binding)), "the swap took");
    let mismatches = interface_mismatches(stage, &swapped);
    assert_eq!(mismatches.len(), 2, "{mismatches:?}");
    for name in [&a.name, &b.name] {
        assert!(
            mismatches.iter().any(|m| m.contains(&format!("{name:?}"))),
            "{name} not reported: {mismatches:?}"
        );
    }
}

/// Every GLSL file under `glsl/`, with its path relative to it.
fn glsl_sources() -> Vec<(String, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("glsl");
    let mut folders = vec![root.clone()];
    let mut sources = Vec::new();
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("a readable shader folder") {
            let path = entry.expect("a readable folder entry").path();
            if path.is_dir() {
                folders.push(path);
            } else {
                let relative = path.strip_prefix(&root).expect("under glsl/").display().to_string();
                sources.push((relative, std::fs::read_to_string(&path).expect("a readable shader")));
            }
        }
    }
    sources.sort();
    sources
}

/// The `const uint NAME = VALUEu;` declarations of `source` (names and values).
fn uint_constants(source: &str) -> Vec<(String, u32)> {
    source
        .lines()
        .filter_map(|line| line.trim().strip_prefix("const uint "))
        .filter_map(|rest| rest.split_once(" = "))
        .filter_map(|(name, value)| {
            let value = value.trim_end_matches(';').trim_end_matches('u');
            Some((name.to_string(), value.parse().ok()?))
        })
        .collect()
}

/// Checks that the GLSL declares each of `rust` (names and values) once, in `file`, with its
/// value, and declares nothing else starting with one of `prefixes` anywhere.
fn check_glsl_twins(rust: &[(&str, u32)], file: &str, prefixes: &[&str]) {
    let mut declared = Vec::new();
    for (path, source) in glsl_sources() {
        for (name, value) in uint_constants(&source) {
            let ours = rust.iter().any(|&(r, _)| r == name) || prefixes.iter().any(|p| name.starts_with(p));
            if ours {
                declared.push((path.clone(), name, value));
            }
        }
    }
    let mut expected: Vec<(String, String, u32)> =
        rust.iter().map(|&(name, value)| (file.to_string(), name.to_string(), value)).collect();
    declared.sort();
    expected.sort();
    assert_eq!(declared, expected, "(file, GLSL constant, value) against their Rust twins");
}

#[test]
fn the_flags_are_declared_once_in_glsl_with_their_rust_values() {
    check_glsl_twins(flags::ALL, "include/types.glsl", &["FLAG_"]);
}

#[test]
fn the_hold_rule_has_the_constants_of_its_rust_twin() {
    let rust = [("HOLD_ESTIMATES", level_hold::HOLD_ESTIMATES), ("HOLD_STAGGER", level_hold::HOLD_STAGGER)];
    check_glsl_twins(&rust, "include/level_hold.glsl", &["HOLD_"]);
}

#[test]
fn the_pre_pass_slots_are_declared_once_in_glsl_with_their_rust_values() {
    check_glsl_twins(slots::ALL, "include/bindings.glsl", &[]);
}

#[test]
fn bindings_glsl_declares_its_descriptors_in_binding_order() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("glsl/include/bindings.glsl");
    let source = std::fs::read_to_string(path).expect("bindings.glsl");
    let number = |text: &str, key: &str| -> Option<u32> {
        let rest = &text[text.find(key)? + key.len()..];
        rest.split(|c: char| !c.is_ascii_digit()).next()?.parse().ok()
    };
    let declared: Vec<(u32, u32)> = source
        .lines()
        .filter(|line| line.starts_with("layout(set = "))
        .map(|line| (number(line, "set = ").expect("a set"), number(line, "binding = ").expect("a binding")))
        .collect();
    let mut sorted = declared.clone();
    sorted.sort();
    assert_eq!(declared, sorted, "bindings.glsl's (set, binding) order");
    let forward: Vec<(u32, u32)> = bindings::forward::LAYOUT.sets[..2]
        .iter()
        .flat_map(|set| set.iter().map(|b| (b.set, b.binding)))
        .collect();
    assert_eq!(declared, forward, "bindings.glsl declares sets 0 and 1 of the forward layout");
}
