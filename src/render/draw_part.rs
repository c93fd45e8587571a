//! The parts of a frame's forward draws that a measured frame may time apart ([`DrawPart`]):
//! `bench --draw-parts` accounts for the gap between `multirate` and `vertex` with them.

/// A part of one mesh's forward draws (or, for [`DrawPart::Emitters`], of the frame's).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawPart {
    /// The mesh drawn whole: `pixel`, `vertex` and `fixed` modes, a multirate mesh drawn as
    /// `pixel` does, and the control-stage placement's adjacency patches.
    Whole,
    /// The pre-pass's flat list: level-1 patches, shaded on their corners.
    Flat,
    /// The pre-pass's tessellated list, shaded on its sub-vertices.
    Tessellated,
    /// The per-pixel fallback's depth prime (its tessellated and flat patches).
    FallbackDepth,
    /// The per-pixel fallback's shading (its tessellated and flat patches).
    FallbackShading,
    /// A two-sided mesh's back faces, shaded per pixel.
    BackFaces,
    /// The polygonal lights' emissive geometry (the frame's, counted with its first mesh).
    Emitters,
}

/// How many parts a mesh's draws have.
pub const DRAW_PARTS: usize = 7;

impl DrawPart {
    /// Every part, in the order a mesh draws them.
    pub const ALL: [DrawPart; DRAW_PARTS] = [
        DrawPart::Whole,
        DrawPart::Flat,
        DrawPart::Tessellated,
        DrawPart::FallbackDepth,
        DrawPart::FallbackShading,
        DrawPart::BackFaces,
        DrawPart::Emitters,
    ];

    /// Its name in `bench`'s columns (`draw_<name>_ms_median`).
    pub fn name(self) -> &'static str {
        match self {
            DrawPart::Whole => "whole",
            DrawPart::Flat => "flat",
            DrawPart::Tessellated => "tessellated",
            DrawPart::FallbackDepth => "fallback_depth",
            DrawPart::FallbackShading => "fallback_shading",
            DrawPart::BackFaces => "back_faces",
            DrawPart::Emitters => "emitters",
        }
    }
}
