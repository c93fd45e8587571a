//! The bits of `DrawConstants::flags` (twins: the `FLAG_` constants of
//! `glsl/include/types.glsl`, their only GLSL declaration).

use super::named_constants::named_constants;

named_constants! {
    /// Colour by tessellation level instead of shading.
    FLAG_HEAT_MAP = 1;
    /// `pixel-deferred` writes the analytic against hardware uv derivative difference instead
    /// of shading (see [`crate::render::View::derivative_check`]).
    FLAG_DERIVATIVE_CHECK = 2;
    /// The mesh is one-sided: its back-facing triangles are culled (by the rasteriser, and in
    /// multirate mode before their estimate).
    FLAG_ONE_SIDED = 4;
    /// The multirate draw (`--estimator compute`) of a mesh's list of fallback patches, or of
    /// its flat triangles shaded per pixel; without it, of its patches shaded on their
    /// sub-vertices (or its flat triangles shaded on their corners).
    FLAG_FALLBACK_PATCHES = 16;
    /// The mesh's material has no parameter map, so a flat patch's corner shades the same in
    /// every triangle that shares it (`DrawCall::shared_corners`): the compute placement draws
    /// its flat patches shaded on their corners indexed, from `flat_indices`.
    FLAG_SHARED_CORNERS = 32;
    /// The multirate pre-pass (`--estimator compute`) reuses the levels it found earlier in the
    /// current ball of eyes (`estimated_levels`) and keeps those it finds now.
    FLAG_REUSE_LEVELS = 64;
    /// Where the pre-pass keeps levels (`FLAG_REUSE_LEVELS`), it also holds them: a lower
    /// estimate is used only once it has come several times in a row (`render::level_hold`).
    FLAG_HOLD_LEVELS = 128;
}
