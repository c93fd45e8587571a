use super::bindings::{forward, in_binding_order, LAYOUTS};
use super::{flags, slots, specialization};
use std::collections::HashSet;

#[test]
fn every_set_lists_its_bindings_in_order_from_zero() {
    for layout in LAYOUTS {
        for (set, bindings) in layout.sets.iter().enumerate() {
            for (binding, b) in bindings.iter().enumerate() {
                assert_eq!((b.set, b.binding), (set as u32, binding as u32), "{} in {}", b.name, layout.name);
            }
        }
    }
}

#[test]
fn descriptor_names_are_unique_across_layouts() {
    let mut seen = HashSet::new();
    for layout in LAYOUTS {
        for b in layout.sets.iter().flat_map(|set| set.iter()) {
            assert!(seen.insert(b.name), "{} named twice", b.name);
        }
    }
}

#[test]
fn specialization_ids_and_names_are_unique() {
    let ids: HashSet<u32> = specialization::ALL.iter().map(|s| s.id).collect();
    let names: HashSet<&str> = specialization::ALL.iter().map(|s| s.name).collect();
    assert_eq!(ids.len(), specialization::ALL.len());
    assert_eq!(names.len(), specialization::ALL.len());
}

#[test]
fn flags_are_distinct_bits() {
    let mut all = 0;
    for &(name, bit) in flags::ALL {
        assert_eq!(bit.count_ones(), 1, "{name}");
        assert_eq!(all & bit, 0, "{name} shares its bit");
        all |= bit;
    }
}

#[test]
fn slots_lie_within_their_counts() {
    for slot in [slots::RANGE_DISPATCH, slots::PATCH_DISPATCH, slots::REFINE_DISPATCH] {
        assert!(slot < slots::LEVEL_DISPATCHES);
    }
    let in_range = |slots: &[u32], count: u32| {
        slots.iter().all(|&slot| slot < count)
            && (1..slots.len()).all(|k| !slots[k..].contains(&slots[k - 1]))
    };
    assert!(in_range(&[slots::INTERPOLATED_LIST, slots::FALLBACK_LIST], slots::PATCH_LISTS));
    assert!(in_range(&[slots::LISTED_PATCHES, slots::OPENED_DRAWS], slots::PATCH_COUNT_WORDS));
}

#[test]
fn a_mesh_s_flat_draws_do_not_overlap_and_fill_whole_vectors() {
    let word = std::mem::size_of::<u32>();
    let list = slots::FLAT_LIST_DRAW as usize
        ..slots::FLAT_LIST_DRAW as usize + std::mem::size_of::<ash::vk::DrawIndirectCommand>() / word;
    let fallback = slots::FALLBACK_FLAT_DRAW as usize
        ..slots::FALLBACK_FLAT_DRAW as usize
            + std::mem::size_of::<ash::vk::DrawIndexedIndirectCommand>() / word;
    assert!(list.end <= fallback.start || fallback.end <= list.start);
    assert!(list.end.max(fallback.end) <= slots::FLAT_DRAW_WORDS as usize);
    assert_eq!(slots::FLAT_DRAW_WORDS % 4, 0, "a mesh's draws begin on a uvec4");
}

#[test]
fn resources_are_put_in_binding_order_whatever_order_they_are_given_in() {
    let given = [
        (forward::PARAMETER_PYRAMID, 'c'),
        (forward::SHADOW_ATLAS, 'd'),
        (forward::ALBEDO_MAP, 'a'),
        (forward::PARAMETER_MAP, 'b'),
    ];
    assert_eq!(in_binding_order(&forward::MATERIAL_TEXTURES, given), ['a', 'b', 'c', 'd']);
}

#[test]
#[should_panic(expected = "two resources for binding albedo_map")]
fn a_binding_given_twice_is_refused() {
    let given = [
        (forward::ALBEDO_MAP, 'a'),
        (forward::ALBEDO_MAP, 'b'),
        (forward::PARAMETER_PYRAMID, 'c'),
        (forward::SHADOW_ATLAS, 'd'),
    ];
    in_binding_order(&forward::MATERIAL_TEXTURES, given);
}
