//! Compiles every shader stage under `glsl/` to SPIR-V with shaderc.
//!
//! Stages are recognised by extension (`.vert .tesc .tese .geom .frag .comp`); headers live in
//! `glsl/include/` and are pulled in with `#include "name.glsl"`. Warnings are errors, and a
//! compile error fails the build with the file and line shaderc reports. Every stage and every
//! header is a `rerun-if-changed` input, so editing any of them rebuilds the SPIR-V.
//! The SPIR-V lands in `$OUT_DIR/spirv/<file name>.spv` and is embedded by `src/shaders.rs`.

use std::path::{Path, PathBuf};

fn stage_kind(path: &Path) -> Option<shaderc::ShaderKind> {
    Some(match path.extension()?.to_str()? {
        "vert" => shaderc::ShaderKind::Vertex,
        "tesc" => shaderc::ShaderKind::TessControl,
        "tese" => shaderc::ShaderKind::TessEvaluation,
        "geom" => shaderc::ShaderKind::Geometry,
        "frag" => shaderc::ShaderKind::Fragment,
        "comp" => shaderc::ShaderKind::Compute,
        _ => return None,
    })
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|entry| entry.expect("readable directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

fn main() {
    let glsl = Path::new("glsl");
    let include_dir = glsl.join("include");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("spirv");
    std::fs::create_dir_all(&out_dir).expect("create the SPIR-V output folder");

    println!("cargo:rerun-if-changed={}", glsl.display());
    println!("cargo:rerun-if-changed={}", include_dir.display());
    for header in files_in(&include_dir) {
        println!("cargo:rerun-if-changed={}", header.display());
    }

    let compiler = shaderc::Compiler::new().expect("shaderc compiler");
    let mut options = shaderc::CompileOptions::new().expect("shaderc options");
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_3 as u32);
    options.set_source_language(shaderc::SourceLanguage::GLSL);
    options.set_warnings_as_errors();
    options.set_generate_debug_info();
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    let include_root = include_dir.clone();
    options.set_include_callback(move |name, _kind, requester, _depth| {
        let path = include_root.join(name);
        let content = std::fs::read_to_string(&path)
            .map_err(|e| format!("{requester}: cannot include {}: {e}", path.display()))?;
        Ok(shaderc::ResolvedInclude { resolved_name: path.display().to_string(), content })
    });

    let mut failures = Vec::new();
    for stage in files_in(glsl) {
        let Some(kind) = stage_kind(&stage) else { continue };
        println!("cargo:rerun-if-changed={}", stage.display());
        let source = std::fs::read_to_string(&stage)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", stage.display()));
        let name = stage.display().to_string();
        match compiler.compile_into_spirv(&source, kind, &name, "main", Some(&options)) {
            Ok(artifact) => {
                let file = stage.file_name().expect("stage has a file name").to_string_lossy();
                let out = out_dir.join(format!("{file}.spv"));
                std::fs::write(&out, artifact.as_binary_u8())
                    .unwrap_or_else(|e| panic!("cannot write {}: {e}", out.display()));
            }
            Err(error) => failures.push(error.to_string()),
        }
    }
    if !failures.is_empty() {
        for failure in &failures {
            for line in failure.lines() {
                println!("cargo:warning={line}");
            }
        }
        panic!("{} shader(s) failed to compile:\n{}", failures.len(), failures.join("\n"));
    }
}
