//! SPIR-V of every stage under `glsl/`, compiled by `build.rs` and embedded in the binary.
//!
//! Stages that shade are compiled once per feature set ([`Features`]): a scene's pipelines are
//! built from the variant of exactly the features it uses, so a Lambert scene without polygonal
//! lights or textures runs no polygon, texture or GGX code at all.

/// What code a shader variant contains. Each field is an [`Axis`] of `build.rs`, a preprocessor
/// define (`VARIANT_MATERIAL_KIND`, ...); a stage compiled without an axis ignores that field.
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
    /// Some light casts shadows: multirate's stages pass each one's unshadowed shading on apart
    /// (without, they hold none of those interpolants).
    pub shadows: bool,
}

/// A feature axis of `build.rs`: a field of [`Features`], named alike in a stage's
/// `// variants:` line and in its define (`VARIANT_` and the name in capitals).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    MaterialKind,
    PolygonLights,
    Textured,
    CountEvaluations,
    RecordLevels,
    Shadows,
}

impl Axis {
    /// Every axis, in `build.rs`'s order (the order of a module's values).
    pub const ALL: [Axis; 6] = [
        Axis::MaterialKind,
        Axis::PolygonLights,
        Axis::Textured,
        Axis::CountEvaluations,
        Axis::RecordLevels,
        Axis::Shadows,
    ];

    /// Its name in `build.rs` and in the `// variants:` lines.
    pub const fn name(self) -> &'static str {
        match self {
            Axis::MaterialKind => "material_kind",
            Axis::PolygonLights => "polygon_lights",
            Axis::Textured => "textured",
            Axis::CountEvaluations => "count_evaluations",
            Axis::RecordLevels => "record_levels",
            Axis::Shadows => "shadows",
        }
    }
}

/// The names of `build.rs`'s axes, in its order, as it wrote them.
const BUILT_AXES: [&str; Axis::ALL.len()] = include!(concat!(env!("OUT_DIR"), "/spirv/axes.rs"));

const fn same_str(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// Whether [`Axis::ALL`] is in declaration order (an axis's discriminant indexes a module's
/// values) and names `build.rs`'s axes in its order.
const fn axes_are_built_in_order() -> bool {
    let mut i = 0;
    while i < Axis::ALL.len() {
        if Axis::ALL[i] as usize != i || !same_str(Axis::ALL[i].name(), BUILT_AXES[i]) {
            return false;
        }
        i += 1;
    }
    true
}

const _: () = assert!(axes_are_built_in_order(), "build.rs's AXES differ from shaders::Axis::ALL");

impl Features {
    /// Its value on `axis`.
    fn value(&self, axis: Axis) -> u32 {
        match axis {
            Axis::MaterialKind => self.material_kind,
            Axis::PolygonLights => u32::from(self.polygon_lights),
            Axis::Textured => u32::from(self.textured),
            Axis::CountEvaluations => u32::from(self.count_evaluations),
            Axis::RecordLevels => u32::from(self.record_levels),
            Axis::Shadows => u32::from(self.shadows),
        }
    }

    /// The values of `build.rs`'s axes, in its order.
    fn values(&self) -> [u32; Axis::ALL.len()] {
        Axis::ALL.map(|axis| self.value(axis))
    }
}

/// One compiled module: a stage for one combination of the axes it varies over.
pub struct Module {
    /// The stage's file name under `glsl/`.
    pub stage: &'static str,
    /// Bit `i` set: the module varies over axis `i` of [`Axis::ALL`].
    varied: u32,
    /// Its value on each axis of [`Axis::ALL`] (0 where it does not vary).
    values: [u32; Axis::ALL.len()],
    pub spirv: &'static [u8],
}

impl Module {
    /// The features this module was compiled with (axes it does not vary over read as off).
    pub fn features(&self) -> Features {
        let value = |axis: Axis| self.values[axis as usize];
        Features {
            material_kind: value(Axis::MaterialKind),
            polygon_lights: value(Axis::PolygonLights) != 0,
            textured: value(Axis::Textured) != 0,
            count_evaluations: value(Axis::CountEvaluations) != 0,
            record_levels: value(Axis::RecordLevels) != 0,
            shadows: value(Axis::Shadows) != 0,
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
