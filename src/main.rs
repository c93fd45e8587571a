//! The `multirate` binary: parses the command line and runs the subcommand asked for (`cli`).

mod cli;

use anyhow::{Context as _, Result};
use clap::Parser;
use cli::{Cli, Command};

fn main() -> Result<()> {
    let cli = Cli::parse();
    match &cli.command {
        Some(Command::Render(args)) => cli::render::render(args, &cli.gpu),
        Some(Command::Analyze(args)) => cli::analyze::analyze(args, &cli.gpu),
        Some(Command::Bench(args)) => cli::bench::run_bench(args, &cli.gpu).map(|_| ()),
        Some(Command::Demo(args)) => cli::demo::run_demo(args, &cli.gpu),
        Some(Command::Experiments(args)) => cli::experiments::run_experiments(args, &cli.gpu),
        Some(Command::Soak(args)) => {
            cli::soak::soak(args, &cli.gpu).with_context(|| format!("soaking {}", args.scene.display()))
        }
        Some(Command::Calibrate(args)) => cli::calibrate::calibrate(args, &cli.gpu)
            .with_context(|| format!("calibrating with {}", args.scene.display())),
        Some(Command::View(args)) => cli::view::run(args, &cli.gpu),
        None => cli::first_run::run(&cli.gpu),
    }
}
