//! The binary's `calibrate` subcommand: measures this device's costs for the cost model
//! (`bench::calibrate`), prints them with the break-even areas they give, and stores them
//! where the renderer looks for them (`CostModel::for_device`), under the device's
//! `calibration_key`.

use super::common::{check_frames, default_scene, load_scene, options, progress_bar, GpuArgs};
use anyhow::{Context as _, Result};
use clap::Args;
use multirate::bench::{calibrate, BenchScene};
use multirate::render::cost_model::{calibration_key, CostModel, LavapipeCompiler};
use multirate::vk::Context;
use std::path::PathBuf;

#[derive(Args)]
pub struct CalibrateArgs {
    /// The scene measured (its camera, resolution and meshes; its lights are replaced).
    #[arg(long, default_value_os_t = default_scene())]
    pub scene: PathBuf,
    /// Measured frames per configuration.
    #[arg(long, default_value_t = 6)]
    frames: u32,
    /// Where to store the calibration (default: $MULTIRATE_COST_MODEL, else
    /// $XDG_CONFIG_HOME/multirate/cost_model.toml or ~/.config/multirate/cost_model.toml).
    #[arg(long)]
    store: Option<PathBuf>,
    /// Print the figures without storing them.
    #[arg(long)]
    dry_run: bool,
}

pub fn calibrate(args: &CalibrateArgs, gpu: &GpuArgs) -> Result<()> {
    check_frames(args.frames)?;
    let scene = BenchScene { name: "calibration".into(), scene: load_scene(&args.scene)? };
    let context = Context::headless(&options(gpu))?;
    let bar = progress_bar();
    let (calibration, samples) = calibrate::calibrate(&context, &scene, args.frames, &mut |progress| {
        bar.set_length(progress.total as u64);
        bar.set_position(progress.done as u64);
        bar.set_message(progress.label.to_string());
    })?;
    bar.finish_and_clear();
    println!("{} ({}), {}:", context.info.name, context.info.driver, args.scene.display());
    for s in &samples {
        println!(
            "  {:>2} lights: estimate {:.0} ns per triangle ({} estimated); pixel {:.1} ns per fragment ({} shaded); multirate's per-pixel path {:.1} ns per fragment ({} and {} shaded) and {:.0} ns per visible triangle ({}); a patch at level 1 {:.0} ns ({}), a sub-vertex {:.0} ns ({} added at level 4)",
            s.lights,
            s.estimate_ns,
            s.estimated_triangles,
            s.pixel_ns,
            s.fragments,
            s.fallback_ns,
            s.fallback_fragments[0],
            s.fallback_fragments[1],
            s.fallback_triangle_ns,
            s.visible_triangles,
            s.patch_ns,
            s.patches,
            s.sub_vertex_ns,
            s.added_sub_vertices
        );
    }
    let (e, p, f) = (&calibration.estimate, &calibration.pixel, &calibration.fallback);
    println!(
        "  estimate {:.0} + {:.0}·L ns, pixel {:.1} + {:.1}·L ns, per-pixel path {:.1} + {:.1}·L ns per fragment",
        e.fixed_ns, e.per_light_ns, p.fixed_ns, p.per_light_ns, f.fixed_ns, f.per_light_ns
    );
    if let Some(t) = &calibration.fallback_triangle {
        println!("  per-pixel path {:.0} + {:.0}·L ns per visible triangle", t.fixed_ns, t.per_light_ns);
    }
    if let (Some(t), Some(v)) = (&calibration.tessellated_patch, &calibration.sub_vertex) {
        println!(
            "  a patch at level 1 {:.0} + {:.0}·L ns, a sub-vertex {:.0} + {:.0}·L ns",
            t.fixed_ns, t.per_light_ns, v.fixed_ns, v.per_light_ns
        );
    }
    let model = CostModel { calibration: calibration.clone(), source: "this calibration".into() };
    let areas: Vec<String> =
        [1, 4, 16, 64].iter().map(|&l| format!("{l} lights {:.1} px", model.min_estimated_area(l))).collect();
    println!("  estimated above: {}", areas.join(", "));
    let levels: Vec<String> = [2, 4, 8, 16]
        .iter()
        .filter_map(|&n| Some(format!("level {n} {:.0} px", model.tessellation_break_even(n, 1)?)))
        .collect();
    println!("  with 1 light, tessellating pays against the per-pixel path above: {}", levels.join(", "));
    let messages = context.validation().count();
    anyhow::ensure!(messages == 0, "the validation layer reported {messages} message(s)");
    if args.dry_run {
        return Ok(());
    }
    let store = args.store.clone().or_else(CostModel::default_store).context(
        "no place to store the calibration: set --store, MULTIRATE_COST_MODEL, XDG_CONFIG_HOME or HOME",
    )?;
    let key = calibration_key(&context.info.name, LavapipeCompiler::current());
    CostModel::store(&store, &key, &calibration)?;
    println!("stored for \"{key}\" in {}", store.display());
    Ok(())
}
