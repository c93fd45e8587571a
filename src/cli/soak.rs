//! The binary's `soak` subcommand: a long run of the window on a script, or of `bench` on one
//! scene, with the validation layer on; resident and device memory sampled after the warm-up
//! and at the end, printed and written as JSON; fails on any validation message or a growth
//! over `--max-growth`.

use super::common::{
    check_frames, default_scene, load_scene, options, parse_resolution, print_warnings, progress_bar, GpuArgs,
};
use anyhow::{Context as _, Result};
use clap::Args;
use multirate::bench::{self, BenchConfig, BenchScene};
use multirate::render::{Mode, View, EYE_BALL_SHARE};
use multirate::shading::estimator::{Discontinuity, Split};
use multirate::vk::budget::{self, MemoryUse};
use multirate::vk::{Context, ContextOptions};
use std::path::PathBuf;

#[derive(Args)]
pub struct SoakArgs {
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
    #[arg(long, default_value_os_t = default_scene())]
    pub scene: PathBuf,
    /// Frames presented by the window; with --bench, measured frames per configuration.
    #[arg(long, default_value_t = 10_000)]
    pub frames: u32,
    /// The window's initial size, or with --bench the resolution, as WxH (default: the
    /// scene's).
    #[arg(long, value_parser = parse_resolution)]
    pub size: Option<(u32, u32)>,
    /// Soak `bench` (the pixel reference and --modes, timed in turns) instead of the window.
    #[arg(long)]
    pub bench: bool,
    /// --bench: the modes measured besides the pixel reference.
    #[arg(long, value_delimiter = ',', default_value = "pixel,vertex,fixed:1,fixed:2,fixed:4,multirate")]
    pub modes: Vec<Mode>,
    /// The largest growth of each memory figure from the first sample to the last, in percent.
    #[arg(long, default_value_t = 1.0)]
    pub max_growth: f64,
    /// Also write the figures as JSON into this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
}

/// What a soak did, for the printed report and its JSON.
struct Soak {
    /// "window" or "bench".
    kind: &'static str,
    device: String,
    frames: u64,
    seconds: f64,
    /// Memory figures: (frame, figures), the first after the warm-up.
    samples: Vec<(u64, MemoryUse)>,
    validation_messages: usize,
    /// What else the run did, as (name, value) lines.
    details: Vec<(String, serde_json::Value)>,
}

/// Reads one memory figure from a sample (None where the system or device lacks it).
type Figure = fn(&MemoryUse) -> Option<u64>;

/// One memory figure's first and last samples and its growth between them.
struct Growth {
    name: &'static str,
    start: u64,
    end: u64,
    peak: u64,
    growth: f64,
}

impl Soak {
    fn growths(&self) -> Vec<Growth> {
        let figures: [(&'static str, Figure); 4] = [
            ("resident set", |m| m.resident),
            ("device heaps (VK_EXT_memory_budget)", |m| m.device),
            ("device memory blocks (allocator)", |m| Some(m.allocator_blocks)),
            ("device memory allocated (allocator)", |m| Some(m.allocated)),
        ];
        figures
            .iter()
            .filter_map(|&(name, figure)| {
                let values: Vec<u64> = self.samples.iter().map(|(_, m)| figure(m)).collect::<Option<_>>()?;
                let (&start, &end) = (values.first()?, values.last()?);
                let peak = values.iter().copied().max()?;
                Some(Growth { name, start, end, peak, growth: budget::growth(start, end)? })
            })
            .collect()
    }

    fn print(&self) {
        let mib = |bytes: u64| bytes as f64 / (1024.0 * 1024.0);
        println!(
            "{} soak on {}: {} frames in {:.1} s, validation layer on: {} message(s)",
            self.kind, self.device, self.frames, self.seconds, self.validation_messages
        );
        for (name, value) in &self.details {
            println!("  {name}: {value}");
        }
        if let (Some((first, _)), Some((last, _))) = (self.samples.first(), self.samples.last()) {
            println!(
                "  memory: {} samples, the first after the warm-up (frame {first}), the last at frame {last}:",
                self.samples.len()
            );
        }
        if self.samples.first().is_some_and(|(_, m)| m.device.is_none()) {
            println!("    device heaps: the device has no VK_EXT_memory_budget");
        }
        for g in self.growths() {
            println!(
                "    {:<36} {:>9.2} MiB -> {:>9.2} MiB ({:+.3} %), peak {:.2} MiB",
                g.name,
                mib(g.start),
                mib(g.end),
                100.0 * g.growth,
                mib(g.peak)
            );
        }
    }

    fn json(&self) -> serde_json::Value {
        let growths: Vec<serde_json::Value> = self
            .growths()
            .iter()
            .map(|g| {
                serde_json::json!({
                    "figure": g.name, "start_bytes": g.start, "end_bytes": g.end,
                    "peak_bytes": g.peak, "growth": g.growth,
                })
            })
            .collect();
        let samples: Vec<serde_json::Value> = self
            .samples
            .iter()
            .map(|(frame, m)| {
                serde_json::json!({
                    "frame": frame, "resident_bytes": m.resident, "device_bytes": m.device,
                    "allocator_block_bytes": m.allocator_blocks, "allocated_bytes": m.allocated,
                })
            })
            .collect();
        serde_json::json!({
            "kind": self.kind,
            "device": self.device,
            "frames": self.frames,
            "seconds": self.seconds,
            "validation_messages": self.validation_messages,
            "details": self.details.iter().cloned().collect::<serde_json::Map<_, _>>(),
            "memory": growths,
            "samples": samples,
        })
    }
}

pub fn soak(args: &SoakArgs, gpu: &GpuArgs) -> Result<()> {
    check_frames(args.frames)?;
    anyhow::ensure!(
        args.max_growth.is_finite() && args.max_growth >= 0.0,
        "--max-growth must be a percentage, 0 or more"
    );
    let options = ContextOptions { validate: true, ..options(gpu) };
    let report = if args.bench { soak_bench(args, &options)? } else { soak_window(args, &options)? };
    report.print();
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&report.json()).expect("figures serialise");
        std::fs::write(path, text).with_context(|| format!("{}: cannot write", path.display()))?;
    }
    anyhow::ensure!(
        report.validation_messages == 0,
        "the validation layer reported {} message(s)",
        report.validation_messages
    );
    anyhow::ensure!(report.samples.len() >= 2, "fewer than two memory samples: the run was too short");
    for g in report.growths() {
        anyhow::ensure!(
            100.0 * g.growth <= args.max_growth,
            "{} grew by {:.3} %, more than {} %",
            g.name,
            100.0 * g.growth,
            args.max_growth
        );
    }
    Ok(())
}

/// The window on [`multirate::window::ViewScript::soak`], starting in multirate mode.
fn soak_window(args: &SoakArgs, options: &ContextOptions) -> Result<Soak> {
    let mut scene = load_scene(&args.scene)?;
    if let Some((width, height)) = args.size {
        (scene.settings.width, scene.settings.height) = (width, height);
    }
    let size = (scene.settings.width, scene.settings.height);
    let view = View { mode: Mode::Multirate, ..View::of_scene(&scene) };
    let script = multirate::window::ViewScript::soak(args.frames, size);
    let report = multirate::window::view(scene, view, options, Some(script))?;
    let modes: serde_json::Map<_, _> =
        report.frames_by_mode.iter().map(|(mode, frames)| (mode.clone(), (*frames).into())).collect();
    let events: serde_json::Map<_, _> =
        report.events.iter().map(|(event, count)| (event.clone(), (*count).into())).collect();
    let details = vec![
        ("initial size".into(), format!("{}x{}", size.0, size.1).into()),
        ("turns".into(), report.turns.into()),
        ("turns minimised".into(), report.turns_minimised.into()),
        ("swapchain recreations".into(), report.swapchain_recreations.into()),
        ("scripted events".into(), events.into()),
        ("frames by mode".into(), modes.into()),
        ("heat map frames".into(), report.heat_map_frames.into()),
        ("wireframe frames".into(), report.wireframe_frames.into()),
        ("n_max values".into(), report.n_max_values.iter().copied().collect::<Vec<_>>().into()),
        ("epsilon range".into(), report.epsilon_range.map(|(low, high)| vec![low, high]).into()),
    ];
    Ok(Soak {
        kind: "window",
        device: report.device.clone(),
        frames: u64::from(report.frames_presented),
        seconds: report.duration.as_secs_f64(),
        samples: report.memory.iter().map(|s| (u64::from(s.frame), s.memory)).collect(),
        validation_messages: report.validation_messages,
        details,
    })
}

/// `bench` of one scene at one resolution, memory sampled after each timing turn (the first
/// follows every configuration's images, counts and warm-up frames).
fn soak_bench(args: &SoakArgs, options: &ContextOptions) -> Result<Soak> {
    let scene = BenchScene::load(&args.scene)?;
    print_warnings(&scene.scene);
    let resolution = args.size.unwrap_or((scene.scene.settings.width, scene.scene.settings.height));
    let context = Context::headless(options)?;
    let config = BenchConfig {
        modes: args.modes.clone(),
        epsilons: Vec::new(),
        n_maxes: Vec::new(),
        resolutions: vec![resolution],
        warmup: 5,
        frames: args.frames,
        split: Split::Heuristic,
        discontinuity: Discontinuity::Relaxed,
        placements: Vec::new(),
        images: None,
        min_estimated_areas: Vec::new(),
        orbit_degrees: 0.0,
        draw_parts: false,
        pre_pass_steps: false,
        eye_ball_share: EYE_BALL_SHARE,
        level_holds: Vec::new(),
        path: None,
    };
    let bar = progress_bar();
    let started = std::time::Instant::now();
    let mut samples = Vec::new();
    let result = bench::run(&context, std::slice::from_ref(&scene), &config, &mut |progress| {
        bar.set_length(progress.total as u64);
        bar.set_position(progress.done as u64);
        bar.set_message(progress.label.to_string());
        if progress.turns_done > 0 {
            let frames = u64::from(bench::FRAMES_PER_TURN) * progress.turns_done as u64;
            let frames = frames.min(u64::from(args.frames));
            samples.push((frames, MemoryUse::now(&context)));
        }
    })?;
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    let configurations: Vec<serde_json::Value> =
        result.rows.iter().map(|row| bench::plot::row_label(row).into()).collect();
    let rendered: u64 = result.measurements.iter().map(|m| m.frames.len() as u64).sum();
    let details = vec![
        ("resolution".into(), format!("{}x{}", resolution.0, resolution.1).into()),
        ("configurations".into(), configurations.into()),
        ("measured frames, all configurations".into(), rendered.into()),
        ("timing turns".into(), args.frames.div_ceil(bench::FRAMES_PER_TURN).into()),
    ];
    Ok(Soak {
        kind: "bench",
        device: context.info.name.clone(),
        frames: u64::from(args.frames),
        seconds,
        samples,
        validation_messages: context.validation().count(),
        details,
    })
}
