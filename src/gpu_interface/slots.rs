//! The per-mesh slots of the pre-pass's indirect buffers (twins: the constants of the same names
//! in `glsl/include/bindings.glsl`).
//!
//! Each mesh has [`LEVEL_DISPATCHES`] indirect dispatches in `LevelDispatches`, one per step
//! that runs over the triangles an earlier step listed, and [`PATCH_LISTS`] lists of patches:
//! the count of each and of its draws in `PatchCounts`, the flat triangles' draw of each in
//! `FlatDraws` ([`FLAT_DRAW_WORDS`] words a mesh), and `InterpolatedDraws` and `FallbackDraws`
//! for the tessellated ones.

use super::named_constants::named_constants;

const _: () = assert!(MAX_SHADOWED_LIGHTS as usize == crate::scene::ShadowCaster::MAX_LIGHTS);
const _: () = assert!(SHADOWED_CLASS_BIT << MAX_SHADOWED_LIGHTS <= MIXED_CLASS_BIT);

named_constants! {
    /// Shadow-casting lights whose unshadowed shading multirate's interpolants carry apart, a
    /// diffuse and a specular `vec3` each (`glsl/include/shadow.glsl`); a scene may have no
    /// more (`scene::ShadowCaster::MAX_LIGHTS`).
    MAX_SHADOWED_LIGHTS = 4;
    /// A triangle's visibility classes (`geometry::shadow_class`, in `triangle_corners`): this
    /// bit shifted by a shadow-casting light's slot where the light reaches none of the
    /// triangle.
    SHADOWED_CLASS_BIT = 1;
    /// This bit shifted by the slot where the light may reach part of it (neither bit: all).
    MIXED_CLASS_BIT = 16;
    /// `DRAWN_SHADOW_CLASSES` (multirate_flat.vert): the draw shows every flat patch.
    EVERY_SHADOW_CLASS = 0;
    /// The draw shows the listed flat patches that no light reaches only in part.
    WITHOUT_MIXED_LIGHTS = 1;
    /// The draw shows the listed flat patches that some light reaches only in part.
    WITH_MIXED_LIGHTS = 2;
    /// Dispatches per mesh in `LevelDispatches`.
    LEVEL_DISPATCHES = 5;
    /// The range step's dispatch (`range_levels.comp`) over the triangles to estimate, counted
    /// by the culling step.
    RANGE_DISPATCH = 0;
    /// The patch step's dispatch (`patch_levels.comp`), counted by the culling step.
    PATCH_DISPATCH = 1;
    /// The refining step's dispatch (`refine_levels.comp`), counted by the estimator step.
    REFINE_DISPATCH = 2;
    /// The estimator step's dispatch (`triangle_levels.comp`) over the triangles the range step
    /// leaves, counted by it.
    FULL_ESTIMATE_DISPATCH = 3;
    /// The estimator step's variant without specular code (`SPECULAR_ALL_CAPPED`) over the
    /// triangles whose every light's specular part is capped, listed by the range step from the
    /// end of the mesh's range down.
    CAPPED_ESTIMATE_DISPATCH = 4;
    /// Marks a back face of a two-sided mesh in `VisibleTriangles`' part listed from the end
    /// (the culling step's), beside the triangles whose level a ball of eyes kept: the
    /// triangle's index with bit 31 set. `render::limits` refuses scenes with more triangles.
    BACK_FACE_ENTRY = 0x8000_0000;
    /// Patch lists per mesh.
    PATCH_LISTS = 2;
    /// The list of patches shaded on their sub-vertices (flat triangles: on their corners).
    INTERPOLATED_LIST = 0;
    /// The list of patches shaded per pixel, the fallback (flat triangles: likewise).
    FALLBACK_LIST = 1;
    /// Words per list in `PatchCounts`.
    PATCH_COUNT_WORDS = 2;
    /// A list's word in `PatchCounts` that counts its patches.
    LISTED_PATCHES = 0;
    /// A list's word in `PatchCounts` that counts the indirect draws its patches open: the
    /// count of its `vkCmdDrawIndirectCount` draw.
    OPENED_DRAWS = 1;
    /// Words per mesh in `FlatDraws`: the flat list's `VkDrawIndirectCommand` at
    /// [`FLAT_LIST_DRAW`], the per-pixel flat patches' `VkDrawIndexedIndirectCommand` at
    /// [`FALLBACK_FLAT_DRAW`], padded to whole 16-byte words.
    FLAT_DRAW_WORDS = 12;
    /// A mesh's first word in `FlatDraws` of its flat list's draw (its flat patches shaded on
    /// their corners, where they are listed).
    FLAT_LIST_DRAW = 0;
    /// A mesh's first word in `FlatDraws` of the indexed draw of its flat patches shaded per
    /// pixel, compacted in `FallbackIndices` from the mesh's first index on.
    FALLBACK_FLAT_DRAW = 4;
    /// The vertex index of no vertex in `FlatIndices`, 2^24 - 1 (Vulkan's least
    /// `maxDrawIndexedIndexValue`): a triangle that is not a flat patch shaded on its corners
    /// is this index three times. `render::limits` refuses scenes with more vertices.
    SKIPPED_VERTEX = 0xff_ffff;
}
