//! `view`: the interactive window on a scene.

use super::common::{default_scene, load_scene, options, GpuArgs};
use super::shading::ShadingArgs;
use anyhow::{Context as _, Result};
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct ViewArgs {
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
    #[arg(long, default_value_os_t = default_scene())]
    pub scene: PathBuf,
    /// Initial shading (keys P, V, F, M, + and - change the mode in the window).
    #[command(flatten)]
    pub shading: ShadingArgs,
}

/// `view`: the window on `--scene`.
pub fn run(args: &ViewArgs, gpu: &GpuArgs) -> Result<()> {
    view(&args.scene, &args.shading, gpu).with_context(|| format!("viewing {}", args.scene.display()))
}

pub fn view(scene: &Path, shading: &ShadingArgs, gpu: &GpuArgs) -> Result<()> {
    let loaded = load_scene(scene)?;
    let view = shading.view(&loaded)?;
    multirate::window::view(loaded, view, &options(gpu), None)?;
    Ok(())
}
