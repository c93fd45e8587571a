//! What a frame samples shading with: the shading [`Mode`], where `multirate` mode runs its
//! estimator ([`Placement`]), and their names on the command line (`FromStr`, `Display`).

/// How shading is sampled. Every mode runs the same BRDF code (`glsl/include/brdf.glsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    /// Full shading in the fragment shader at every pixel: the reference.
    #[default]
    Pixel,
    /// The same reference, deferred: a visibility buffer of triangle ids, then per pixel the
    /// attributes and their derivatives rebuilt analytically (seed 002) and shaded.
    PixelDeferred,
    /// Gouraud: shade the triangle's three vertices, interpolate; no subdivision, no fallback.
    Vertex,
    /// Tessellate every triangle at inner = outer = N and shade the sub-vertices in the TES.
    Fixed(u32),
    /// Per triangle, the smallest level whose error bound is under ε (the estimator, in the
    /// compute pre-pass or the control stage: [`Placement`]); triangles that would need more
    /// than n_max are shaded per pixel.
    Multirate,
}

/// Highest tessellation level Vulkan guarantees (`maxTessellationGenerationLevel` ≥ 64).
pub const MAX_LEVEL: u32 = 64;

/// Where `multirate` mode runs the estimator. Both give the same levels (tests/multirate.rs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Placement {
    /// In the tessellation control stage, as the seeds describe it: each patch carries its
    /// neighbours' vertices, and its four invocations estimate the triangle and its three
    /// neighbours, one each.
    Tcs,
    /// In a compute pre-pass, once per visible triangle and frame; the control stage reads its
    /// own and its neighbours' levels and only combines them, and the interpolated and the
    /// fallback patches are drawn apart. The default: 2–4× faster frames than `Tcs` on
    /// lavapipe, the only device measured, and its pipelines build as fast (docs/notebook/speedups.md).
    #[default]
    Compute,
}

impl std::str::FromStr for Placement {
    type Err = String;
    fn from_str(text: &str) -> Result<Placement, String> {
        match text {
            "tcs" => Ok(Placement::Tcs),
            "compute" => Ok(Placement::Compute),
            _ => Err(format!("unknown estimator placement \"{text}\" (known: tcs, compute)")),
        }
    }
}

impl std::fmt::Display for Placement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Placement::Tcs => "tcs",
            Placement::Compute => "compute",
        })
    }
}

impl std::str::FromStr for Mode {
    type Err = String;
    fn from_str(text: &str) -> Result<Mode, String> {
        match text {
            "pixel" => Ok(Mode::Pixel),
            "pixel-deferred" => Ok(Mode::PixelDeferred),
            "vertex" => Ok(Mode::Vertex),
            "multirate" => Ok(Mode::Multirate),
            _ => match text.strip_prefix("fixed:").map(str::parse::<u32>) {
                Some(Ok(level)) if (1..=MAX_LEVEL).contains(&level) => Ok(Mode::Fixed(level)),
                Some(_) => {
                    Err(format!("\"{text}\": the level of fixed:N must be an integer in 1..={MAX_LEVEL}"))
                }
                None => Err(format!(
                    "unknown mode \"{text}\" (known: pixel, pixel-deferred, vertex, fixed:N, multirate)"
                )),
            },
        }
    }
}

impl std::fmt::Display for Mode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Mode::Pixel => write!(f, "pixel"),
            Mode::PixelDeferred => write!(f, "pixel-deferred"),
            Mode::Vertex => write!(f, "vertex"),
            Mode::Fixed(level) => write!(f, "fixed:{level}"),
            Mode::Multirate => write!(f, "multirate"),
        }
    }
}
