//! What every subcommand shares: the GPU options (`--validate`, `--device`), the default scene,
//! loading a scene with its warnings printed, the progress bar, the checks of `--frames` and
//! `WIDTHxHEIGHT` resolutions, and a subcommand's arguments parsed from words.

use anyhow::Result;
use clap::{Args, Parser};
use multirate::scene::settings::check_image_size;
use multirate::scene::Scene;
use multirate::vk::ContextOptions;
use std::path::{Path, PathBuf};

#[derive(Args, Clone)]
pub struct GpuArgs {
    /// Enable the Khronos validation layer; its messages are printed to stderr.
    #[arg(long, global = true)]
    pub validate: bool,
    /// Use the first Vulkan device whose name contains this text.
    #[arg(long, global = true)]
    pub device: Option<String>,
}

/// `scenes/bunny.toml` from the working directory, or from the source tree.
pub fn default_scene() -> PathBuf {
    shipped_scene("bunny.toml")
}

/// The shipped scene file `name` (`scenes/NAME`) from the working directory, or from the source
/// tree.
pub fn shipped_scene(name: &str) -> PathBuf {
    let relative = Path::new("scenes").join(name);
    if relative.exists() {
        relative
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
    }
}

/// [`Scene::load`], with what loading stood in for printed as warnings.
pub fn load_scene(path: &Path) -> Result<Scene> {
    let scene = Scene::load(path)?;
    print_warnings(&scene);
    Ok(scene)
}

pub fn print_warnings(scene: &Scene) {
    for warning in &scene.warnings {
        eprintln!("warning: {warning}");
    }
}

pub fn options(gpu: &GpuArgs) -> ContextOptions {
    ContextOptions { validate: gpu.validate, device_name: gpu.device.clone() }
}

/// The progress bar of `bench` and `experiments` (hidden when stderr is not a terminal).
pub fn progress_bar() -> indicatif::ProgressBar {
    let style =
        indicatif::ProgressStyle::with_template("{prefix} {bar:30} {pos}/{len} [{elapsed} / ~{eta}] {msg}")
            .expect("valid template");
    indicatif::ProgressBar::new(0).with_style(style)
}

/// `--frames`: at least one measured frame.
pub fn check_frames(frames: u32) -> Result<u32> {
    anyhow::ensure!(frames >= 1, "--frames must be at least 1");
    Ok(frames)
}

pub fn parse_resolution(text: &str) -> Result<(u32, u32), String> {
    let parsed = text.split_once(['x', 'X']).and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)));
    match parsed {
        Some((w, h)) if check_image_size(w, h).is_ok() => Ok((w, h)),
        _ => Err(format!("\"{text}\": expected WIDTHxHEIGHT, each in 1..=16384, such as 1920x1080")),
    }
}

/// A subcommand's arguments parsed from words, as its command line would give them.
#[derive(Parser)]
struct Parsed<T: Args> {
    #[command(flatten)]
    args: T,
}

/// `T` parsed from `words` (a subcommand's arguments, without the program's name) as clap parses
/// a command line: what `demo` hands to `bench`, and what the tests check parsing with.
pub fn parsed<T: Args>(words: &[&str]) -> Result<T> {
    let line = std::iter::once("multirate").chain(words.iter().copied());
    Ok(Parsed::<T>::try_parse_from(line)?.args)
}
