//! `--path`: the camera path a command follows (the scene file's `[[path]]`, or an orbit), and
//! the frames it numbers.

use anyhow::Result;
use multirate::scene::path::CameraPath;
pub use multirate::scene::path::PathChoice;
use multirate::scene::Scene;
use std::path::{Path, PathBuf};

/// Parses `scene` or `orbit:SECONDS`.
pub fn parse_path_choice(text: &str) -> Result<PathChoice, String> {
    match text.split_once(':') {
        None if text == "scene" => Ok(PathChoice::Scene),
        Some(("orbit", seconds)) => match seconds.parse::<f32>() {
            Ok(s) if s.is_finite() && s > 0.0 => Ok(PathChoice::Orbit(s)),
            _ => Err(format!("orbit:{seconds}: the seconds of one turn must be a positive number")),
        },
        _ => Err(format!("`{text}`: expected `scene` (the scene file's [[path]]) or `orbit:SECONDS`")),
    }
}

/// The path `choice` asks for of `scene`.
pub fn camera_path(choice: PathChoice, scene: &Scene) -> Result<CameraPath> {
    CameraPath::chosen(choice, scene.camera_path.as_ref())
        .ok_or_else(|| multirate::Error::NoCameraPath { scene: scene.path.clone() }.into())
}

/// Checks `--fps`.
pub fn check_fps(fps: f32) -> Result<()> {
    anyhow::ensure!(fps.is_finite() && fps > 0.0 && fps <= 1000.0, "--fps must be in (0, 1000] (got {fps})");
    Ok(())
}

/// Frame `index` of a sequence written to `out`: `shot.png` → `shot_0007.png`.
pub fn numbered(out: &Path, index: usize) -> PathBuf {
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "frame".into());
    let name = match out.extension() {
        Some(ext) => format!("{stem}_{index:04}.{}", ext.to_string_lossy()),
        None => format!("{stem}_{index:04}"),
    };
    out.with_file_name(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_choices_parse_and_frames_are_numbered() {
        assert_eq!(parse_path_choice("scene"), Ok(PathChoice::Scene));
        assert_eq!(parse_path_choice("orbit:8"), Ok(PathChoice::Orbit(8.0)));
        for bad in ["orbit", "orbit:0", "orbit:-1", "orbit:nan", "circle:3", ""] {
            assert!(parse_path_choice(bad).is_err(), "{bad}");
        }
        assert_eq!(numbered(Path::new("out/shot.png"), 7), PathBuf::from("out/shot_0007.png"));
        assert_eq!(numbered(Path::new("shot.exr"), 12), PathBuf::from("shot_0012.exr"));
        assert!(check_fps(30.0).is_ok() && check_fps(0.0).is_err() && check_fps(f32::NAN).is_err());
    }
}
