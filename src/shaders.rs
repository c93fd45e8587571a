//! SPIR-V of every stage under `glsl/`, compiled by `build.rs` and embedded in the binary.

macro_rules! spirv {
    ($file:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/spirv/", $file, ".spv"))
    };
}

pub const FORWARD_VERT: &[u8] = spirv!("forward.vert");
pub const PIXEL_FRAG: &[u8] = spirv!("pixel.frag");
pub const FULLSCREEN_VERT: &[u8] = spirv!("fullscreen.vert");
pub const PRESENT_FRAG: &[u8] = spirv!("present.frag");
pub const GOURAUD_VERT: &[u8] = spirv!("gouraud.vert");
pub const COLOR_FRAG: &[u8] = spirv!("color.frag");
pub const PATCH_VERT: &[u8] = spirv!("patch.vert");
pub const FIXED_TESC: &[u8] = spirv!("fixed.tesc");
pub const SHADE_TESE: &[u8] = spirv!("shade.tese");
pub const MULTIRATE_TESC: &[u8] = spirv!("multirate.tesc");
pub const MULTIRATE_TESE: &[u8] = spirv!("multirate.tese");
pub const MULTIRATE_FRAG: &[u8] = spirv!("multirate.frag");
pub const VISIBILITY_VERT: &[u8] = spirv!("visibility.vert");
pub const VISIBILITY_FRAG: &[u8] = spirv!("visibility.frag");
pub const DEFERRED_FRAG: &[u8] = spirv!("deferred.frag");
pub const CAPTURE_VERT: &[u8] = spirv!("capture.vert");
pub const CAPTURE_TESC: &[u8] = spirv!("capture.tesc");
pub const CAPTURE_TESE: &[u8] = spirv!("capture.tese");
pub const CAPTURE_GEOM: &[u8] = spirv!("capture.geom");
pub const POLYGON_CHECK_COMP: &[u8] = spirv!("polygon_check.comp");
pub const EMITTER_FRAG: &[u8] = spirv!("emitter.frag");

/// Every embedded module, by stage file name (used by the layout test).
pub const ALL: &[(&str, &[u8])] = &[
    ("forward.vert", FORWARD_VERT),
    ("pixel.frag", PIXEL_FRAG),
    ("fullscreen.vert", FULLSCREEN_VERT),
    ("present.frag", PRESENT_FRAG),
    ("gouraud.vert", GOURAUD_VERT),
    ("color.frag", COLOR_FRAG),
    ("patch.vert", PATCH_VERT),
    ("fixed.tesc", FIXED_TESC),
    ("shade.tese", SHADE_TESE),
    ("multirate.tesc", MULTIRATE_TESC),
    ("multirate.tese", MULTIRATE_TESE),
    ("multirate.frag", MULTIRATE_FRAG),
    ("visibility.vert", VISIBILITY_VERT),
    ("visibility.frag", VISIBILITY_FRAG),
    ("deferred.frag", DEFERRED_FRAG),
    ("capture.vert", CAPTURE_VERT),
    ("capture.tesc", CAPTURE_TESC),
    ("capture.tese", CAPTURE_TESE),
    ("capture.geom", CAPTURE_GEOM),
    ("polygon_check.comp", POLYGON_CHECK_COMP),
    ("emitter.frag", EMITTER_FRAG),
];

/// Decodes SPIR-V bytes into aligned words.
pub fn words(bytes: &[u8]) -> Vec<u32> {
    ash::util::read_spv(&mut std::io::Cursor::new(bytes)).expect("build.rs wrote valid SPIR-V")
}
