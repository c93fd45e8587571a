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

/// Every embedded module, by stage file name (used by the layout test).
pub const ALL: &[(&str, &[u8])] = &[
    ("forward.vert", FORWARD_VERT),
    ("pixel.frag", PIXEL_FRAG),
    ("fullscreen.vert", FULLSCREEN_VERT),
    ("present.frag", PRESENT_FRAG),
];

/// Decodes SPIR-V bytes into aligned words.
pub fn words(bytes: &[u8]) -> Vec<u32> {
    ash::util::read_spv(&mut std::io::Cursor::new(bytes)).expect("build.rs wrote valid SPIR-V")
}
