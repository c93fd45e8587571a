//! The pre-pass's compute pipelines ([`PrePassPipelines`], one set per material kind, estimator
//! configuration and instrumentation), built on first use and kept in a [`PrePassCache`].

use super::steps::refine_lanes;
use crate::error::Result;
use crate::gpu_interface::specialization as spec;
use crate::render::multirate_config::MultirateConfig;
use crate::render::pipelines::{estimator_specialization, variant_module, Instrumentation};
use crate::shaders::Features;
use crate::vk::pipeline::{Pipeline, PipelineLayout, Specialization};
use crate::vk::Context;
use std::cell::OnceCell;
use std::sync::Arc;

/// The steps of the triangle-level pre-pass (`Placement::Compute`).
pub(crate) struct PrePassPipelines {
    /// cull_triangles.comp, the culling step.
    pub cull: Pipeline,
    /// range_levels.comp, the range class's step.
    pub range: Pipeline,
    /// triangle_levels.comp, the estimator step.
    pub estimate: Pipeline,
    /// triangle_levels.comp without specular code (`SPECULAR_ALL_CAPPED`), over the triangles
    /// whose every light's specular part is capped: for a specular material without polygonal
    /// lights (no other variant lists such triangles).
    pub capped_estimate: Option<Pipeline>,
    /// refine_levels.comp, the refining step.
    pub refine: Pipeline,
    /// patch_levels.comp, the patch step: patch levels, lists and indirect draws.
    pub patches: Pipeline,
}

impl PrePassPipelines {
    /// The pre-pass of `variant`, its estimator steps specialised with `specialization`.
    fn new(
        context: &Arc<Context>,
        layout: &PipelineLayout,
        features: Features,
        instrumentation: Instrumentation,
        specialization: &Specialization,
    ) -> Result<PrePassPipelines> {
        let module = variant_module(context, "triangle_levels.comp", features)?;
        let name = format!("estimator step, material kind {}", features.material_kind);
        let optimization = instrumentation.optimization();
        let estimate =
            Pipeline::compute(context, &name, layout, &module, Some(specialization), optimization)?;
        let capped_estimate = if features.material_kind != 0 && !features.polygon_lights {
            let capped = specialization.clone().boolean(spec::SPECULAR_ALL_CAPPED.id, true);
            let name =
                format!("estimator step, specular parts capped, material kind {}", features.material_kind);
            Some(Pipeline::compute(context, &name, layout, &module, Some(&capped), optimization)?)
        } else {
            None
        };
        let module = variant_module(context, "range_levels.comp", features)?;
        let name = format!("range step, material kind {}", features.material_kind);
        let range = Pipeline::compute(context, &name, layout, &module, Some(specialization), optimization)?;
        let module = variant_module(context, "refine_levels.comp", features)?;
        let refining = specialization.clone().int(spec::REFINE_LANES.id, refine_lanes(&context.info) as i32);
        let name = format!("refining step, material kind {}", features.material_kind);
        let refine = Pipeline::compute(context, &name, layout, &module, Some(&refining), optimization)?;
        let module = variant_module(context, "cull_triangles.comp", features)?;
        let cull = Pipeline::compute(context, "culling step", layout, &module, None, optimization)?;
        let module = variant_module(context, "patch_levels.comp", features)?;
        let patches = Pipeline::compute(context, "patch step", layout, &module, None, optimization)?;
        Ok(PrePassPipelines { cull, range, estimate, capped_estimate, refine, patches })
    }
}

/// The pre-pass pipelines built so far: per instrumentation, per material kind (the scene's
/// variant order), per `split` and `discontinuity` of the estimator.
#[derive(Default)]
pub(crate) struct PrePassCache {
    cells: [Vec<[[OnceCell<PrePassPipelines>; 2]; 2]>; Instrumentation::COUNT],
}

impl PrePassCache {
    /// A cache for a scene of `kinds` material kinds, nothing built yet.
    pub(crate) fn new(kinds: usize) -> PrePassCache {
        PrePassCache { cells: std::array::from_fn(|_| (0..kinds).map(|_| Default::default()).collect()) }
    }

    /// The cell of material kind `kind`'s pipelines for `config` and `instrumentation`.
    fn cell(
        &self,
        instrumentation: Instrumentation,
        kind: usize,
        config: &MultirateConfig,
    ) -> &OnceCell<PrePassPipelines> {
        let (split, discontinuity) = config.estimator_ids();
        &self.cells[instrumentation.index()][kind][split as usize][discontinuity as usize]
    }

    /// The pipelines of material kind `kind` (None: not prepared).
    pub(crate) fn get(
        &self,
        instrumentation: Instrumentation,
        kind: usize,
        config: &MultirateConfig,
    ) -> Option<&PrePassPipelines> {
        self.cell(instrumentation, kind, config).get()
    }

    /// Builds the pipelines `config` needs with `instrumentation` for every material kind of
    /// `specializations` (their features and specialization constants) that lacks them.
    pub(crate) fn prepare(
        &self,
        context: &Arc<Context>,
        layout: &PipelineLayout,
        specializations: &[(Features, Specialization)],
        instrumentation: Instrumentation,
        config: &MultirateConfig,
    ) -> Result<()> {
        for (kind, (features, specialization)) in specializations.iter().enumerate() {
            let cell = self.cell(instrumentation, kind, config);
            if cell.get().is_none() {
                let specialization = estimator_specialization(specialization, config);
                let features = instrumentation.features(*features);
                let built =
                    PrePassPipelines::new(context, layout, features, instrumentation, &specialization)?;
                let _ = cell.set(built);
            }
        }
        Ok(())
    }
}
