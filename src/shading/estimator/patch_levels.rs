//! Shared edges and mixed patterns: the effective level of a hardware pattern ([`pattern_level`],
//! read from [`PATTERN_LEVELS`] by [`pattern_level_entry`]), the uniform level of a real level
//! ([`uniform_level`]), and the rule that turns a triangle's and its neighbours' levels into
//! crack-free patch levels ([`patch_levels`]).
//!
//! GLSL twin: `glsl/include/estimator/patch_levels.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).
//!
//! [`PATTERN_LEVELS`]: super::PATTERN_LEVELS

use super::pattern_table::PATTERN_LEVELS;

/// [`Estimate::level`] of a triangle that falls back to per-pixel shading: above every
/// effective level, so it raises the shared edges to `n_max`.
///
/// [`Estimate::level`]: super::terms::Estimate::level
pub const FALLBACK_LEVEL: f32 = 1.0e6;

/// Levels of one patch as the control stage writes them (whole numbers; the driver rounds
/// real values up anyway).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchLevels {
    /// `gl_TessLevelInner[0]`; 1 for a fallback patch.
    pub inner: f32,
    /// `gl_TessLevelOuter[k]`, the edge opposite vertex `k`: the same on both sides.
    pub outer: [f32; 3],
    /// Per-pixel shading (the control stage's `patch_level` 0).
    pub fallback: bool,
}

/// The effective level of the hardware pattern (lavapipe's, which is the D3D11 reference
/// tessellator's) with inner level `inner` and outer level `outer` on an edge: every
/// sub-triangle of the patch's interior and of that edge's transition strip has enclosing
/// radius² `≤ K_W/L²` and diameter `≤ D_W/L` under every attribute map `W` (`K_W`, `D_W`:
/// the seven shapes' constants, [`pattern_constants`]). A patch's level is the smallest
/// over its three edges. Levels are clamped to `1..=64`. See `docs/estimator.md`.
///
/// [`pattern_constants`]: super::pattern::pattern_constants
pub fn pattern_level(inner: u32, outer: u32) -> f32 {
    pattern_level_entry(&PATTERN_LEVELS, inner, outer) as f32 * (1.0 / 256.0)
}

/// Above every effective level the table holds (16-bit entries in 1/256): a level above it has
/// no uniform level, whatever `n_max`.
pub const ABOVE_EVERY_PATTERN: f32 = 256.0;

/// The smallest `n` in `1..=n_max` whose uniform pattern has effective level `≥ level`;
/// 0 when there is none (NaN included). A level above [`ABOVE_EVERY_PATTERN`] (the fallback
/// level of a triangle shaded per pixel) gives 0 without searching.
pub fn uniform_level(level: f32, n_max: u32) -> u32 {
    if level > ABOVE_EVERY_PATTERN {
        return 0;
    }
    for n in 1..=n_max.clamp(1, 64) {
        if pattern_level(n, n) >= level {
            return n;
        }
    }
    0
}

/// The level-combination rule: what the control stage sets for a triangle with real level
/// `own` ([`Estimate::level`]) whose neighbour across edge `k` has level `neighbours[k]`.
///
/// Edge `k` gets the larger of the two triangles' uniform levels ([`uniform_level`]), a
/// triangle that falls back (no uniform level up to `n_max`, or NaN) asking for nothing (1
/// if both do): both sides compute the same value, so no T-junctions. The inner level is
/// the smallest in `1..=n_max` for which the *whole* pattern, transition strips included,
/// has effective level `≥ own` ([`pattern_level`] of each edge); if there is none, or the
/// triangle itself falls back, the patch is shaded per pixel (inner 1) and keeps its outer
/// levels.
///
/// [`Estimate::level`]: super::terms::Estimate::level
pub fn patch_levels(own: f32, neighbours: [f32; 3], n_max: u32) -> PatchLevels {
    let n_max = n_max.clamp(1, 64);
    let own_n = uniform_level(own, n_max);
    let outer = neighbours.map(|neighbour| own_n.max(uniform_level(neighbour, n_max)).max(1));
    let mut inner = 0;
    if own_n > 0 {
        for i in 1..=n_max {
            let l =
                pattern_level(i, outer[0]).min(pattern_level(i, outer[1])).min(pattern_level(i, outer[2]));
            if l >= own {
                inner = i;
                break;
            }
        }
    }
    PatchLevels { inner: inner.max(1) as f32, outer: outer.map(|o| o as f32), fallback: inner == 0 }
}

/// The entry `(inner, outer)` of a table packed as [`PATTERN_LEVELS`] (levels clamped to
/// `1..=64`): index `(inner − 1)·64 + (outer − 1)`, two 16-bit entries per word, the even index
/// low.
pub fn pattern_level_entry(words: &[u32], inner: u32, outer: u32) -> u32 {
    let index = (inner.clamp(1, 64) - 1) * 64 + (outer.clamp(1, 64) - 1);
    (words[(index / 2) as usize] >> (16 * (index % 2))) & 0xffff
}
