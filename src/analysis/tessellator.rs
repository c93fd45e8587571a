//! A model of Vulkan's fixed-function triangle tessellator with `equal_spacing`: the
//! vertices (as `gl_TessCoord`) and triangles it emits for given inner and outer levels.

/// One tessellated patch in the triangle's barycentric domain.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pattern {
    /// Barycentric coordinates (u, v, w), u + v + w = 1: what the TES sees as `gl_TessCoord`.
    pub vertices: Vec<[f64; 3]>,
    /// Indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}
