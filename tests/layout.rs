//! The `#[repr(C)]` twins in `src/gpu_types.rs` have the layout the shaders were compiled with.
//! The member offsets and array strides are read out of the embedded SPIR-V (OpMemberDecorate
//! Offset, OpDecorate ArrayStride) and compared with `offset_of!` and `size_of`.

use multirate::gpu_types::{DrawConstants, GpuLight, GpuMaterial, GpuPolygonLight};
use multirate::shaders;
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
    for (stage, spirv) in shaders::ALL {
        let reflection = reflect(spirv);
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
            ("pad1", offset_of!(DrawConstants, pad1)),
            ("pad2", offset_of!(DrawConstants, pad2)),
        ],
        size_of::<DrawConstants>(),
    );
    assert!(checked > 0, "no shader declares DrawConstants");
    assert!(size_of::<DrawConstants>() <= 128, "push constants beyond the guaranteed 128 bytes");
}
