//! SPIR-V of every stage under `glsl/`, compiled by `build.rs` and embedded in the binary.
//!
//! Stages that shade are compiled once per feature set ([`Features`]): a scene's pipelines are
//! built from the variant of exactly the features it uses, so a Lambert scene without polygonal
//! lights or textures runs no polygon, texture or GGX code at all.

/// What code a shader variant contains. Each field is a preprocessor define of `build.rs`
/// (`VARIANT_MATERIAL_KIND`, ...); a stage compiled without an axis ignores that field.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Features {
    /// 0 Lambert, 1 Blinn-Phong, 2 GGX (`MATERIAL_KIND` in brdf.glsl).
    pub material_kind: u32,
    /// Polygonal lights: their shading and their estimator bounds.
    pub polygon_lights: bool,
    /// Texture maps: albedo and parameter lookups, the parameter ranges of the control stage.
    pub textured: bool,
    /// Every shading run adds to the evaluation counters (never in a timed pipeline).
    pub count_evaluations: bool,
    /// The control stage writes each triangle's levels (the analysis pipelines).
    pub record_levels: bool,
}

impl Features {
    /// The values of `build.rs`'s axes, in its order.
    fn values(&self) -> [u32; 5] {
        [
            self.material_kind,
            u32::from(self.polygon_lights),
            u32::from(self.textured),
            u32::from(self.count_evaluations),
            u32::from(self.record_levels),
        ]
    }
}

/// One compiled module: a stage for one combination of the axes it varies over.
pub struct Module {
    /// The stage's file name under `glsl/`.
    pub stage: &'static str,
    /// Bit `i` set: the module varies over axis `i` of [`Features::values`].
    varied: u32,
    values: [u32; 5],
    pub spirv: &'static [u8],
}

impl Module {
    /// The features this module was compiled with (axes it does not vary over read as off).
    pub fn features(&self) -> Features {
        let v = self.values;
        Features {
            material_kind: v[0],
            polygon_lights: v[1] != 0,
            textured: v[2] != 0,
            count_evaluations: v[3] != 0,
            record_levels: v[4] != 0,
        }
    }

    fn matches(&self, features: &Features) -> bool {
        let wanted = features.values();
        (0..wanted.len()).all(|axis| self.varied & (1 << axis) == 0 || self.values[axis] == wanted[axis])
    }
}

/// Every embedded module (the layout test reads them all).
pub const ALL: &[Module] = include!(concat!(env!("OUT_DIR"), "/spirv/variants.rs"));

/// The SPIR-V of `stage` (a file name under `glsl/`) compiled for `features`.
///
/// # Panics
/// If `glsl/` has no such stage: stage names are constants of this crate.
pub fn spirv(stage: &str, features: Features) -> &'static [u8] {
    ALL.iter()
        .find(|m| m.stage == stage && m.matches(&features))
        .unwrap_or_else(|| panic!("no shader stage glsl/{stage}"))
        .spirv
}

/// The SPIR-V of a stage that is compiled once (no `// variants:` line).
pub fn single(stage: &str) -> &'static [u8] {
    spirv(stage, Features::default())
}

/// Decodes SPIR-V bytes into aligned words.
pub fn words(bytes: &[u8]) -> Vec<u32> {
    ash::util::read_spv(&mut std::io::Cursor::new(bytes)).expect("build.rs wrote valid SPIR-V")
}
