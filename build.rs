//! Compiles every shader stage under `glsl/` to SPIR-V with shaderc, once per feature variant.
//!
//! Stages are recognised by extension (`.vert .tesc .tese .geom .frag .comp`); headers live in
//! `glsl/include/` and are pulled in with `#include "name.glsl"`. Warnings are errors, and a
//! compile error fails the build with the file and line shaderc reports. Every stage and every
//! header is a `rerun-if-changed` input, so editing any of them rebuilds the SPIR-V.
//!
//! A stage that shades declares, in a line `// variants: AXIS ...`, the features it is compiled
//! for; it is then compiled once per combination, each feature a preprocessor define
//! (`VARIANT_MATERIAL_KIND` 0 to 2, the others 0 or 1), so that a scene's pipelines contain only
//! the code the scene uses (specialization constants do not remove dead code on every driver).
//! Stages without the line are compiled once with every feature off.
//!
//! The SPIR-V lands in `$OUT_DIR/spirv/<stage>[.<variant>].spv`, `$OUT_DIR/spirv/variants.rs`
//! lists every module for `src/shaders.rs` to embed, and `$OUT_DIR/spirv/axes.rs` the axes' names
//! in order, for it to check against its own, and `$OUT_DIR/spirv/compile_times.tsv` the seconds
//! each module compiled in this build took. A module is compiled again only when its
//! preprocessed text (or the compile settings) changed since the last build in that folder.
//! The estimator's stages and the analysis variants are only lightly optimised (`Optimisation`):
//! shaderc's optimiser cost most of a fresh build and made their frames no faster.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A feature axis: its name in the `// variants:` line, its define and its values.
struct Axis {
    name: &'static str,
    define: &'static str,
    values: u32,
}

/// In `shaders::Axis::ALL` order (the names are written to `$OUT_DIR/spirv/axes.rs`, which
/// `src/shaders.rs` checks against it at compile time).
const AXES: [Axis; 6] = [
    Axis { name: "material_kind", define: "VARIANT_MATERIAL_KIND", values: 3 },
    Axis { name: "polygon_lights", define: "VARIANT_POLYGON_LIGHTS", values: 2 },
    Axis { name: "textured", define: "VARIANT_TEXTURED", values: 2 },
    Axis { name: "count_evaluations", define: "VARIANT_COUNT_EVALUATIONS", values: 2 },
    Axis { name: "record_levels", define: "VARIANT_RECORD_LEVELS", values: 2 },
    Axis { name: "shadows", define: "VARIANT_SHADOWS", values: 2 },
];

/// Stack of each shader-compiling thread (address space; only what is touched is committed).
const COMPILER_STACK_BYTES: usize = 256 << 20;

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

/// Every header under `dir`, its subfolders' (`estimator/`, `polygon/`) included.
fn headers_in(dir: &Path) -> Vec<PathBuf> {
    let mut headers = files_in(dir);
    let mut folders: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|entry| entry.expect("readable directory entry").path())
        .filter(|p| p.is_dir())
        .collect();
    folders.sort();
    for folder in folders {
        headers.extend(headers_in(&folder));
    }
    headers
}

/// The axes (indices into `AXES`) a stage's `// variants:` line names.
fn axes_of(stage: &Path, source: &str) -> Vec<usize> {
    let Some(line) = source.lines().find_map(|l| l.trim().strip_prefix("// variants:")) else {
        return Vec::new();
    };
    line.split_whitespace()
        .map(|name| {
            AXES.iter().position(|a| a.name == name).unwrap_or_else(|| {
                panic!("{}: unknown variant axis `{name}` in `// variants:`", stage.display())
            })
        })
        .collect()
}

/// One module to compile: the stage, its feature values (all axes; 0 where not varied), the
/// axes it varies over and how it is optimised.
struct Job {
    stage: PathBuf,
    kind: shaderc::ShaderKind,
    source: String,
    values: [u32; AXES.len()],
    varied: Vec<usize>,
    level: Level,
}

impl Job {
    /// `pixel.frag` or `pixel.frag.material_kind1.polygon_lights0...`.
    fn module_name(&self) -> String {
        let file = self.stage.file_name().expect("stage has a file name").to_string_lossy();
        let mut name = file.into_owned();
        for &axis in &self.varied {
            let _ = write!(name, ".{}{}", AXES[axis].name, self.values[axis]);
        }
        name
    }
}

/// Axes never both on: a pipeline either counts or records, never both.
const EXCLUSIVE_AXES: [&str; 2] = ["count_evaluations", "record_levels"];

/// The index in `AXES` of the axis named `name`.
fn axis_index(name: &str) -> usize {
    AXES.iter().position(|a| a.name == name).unwrap_or_else(|| panic!("no variant axis `{name}`"))
}

/// Every combination of the values of `varied`, the other axes 0, without two of the
/// `EXCLUSIVE_AXES` on.
fn combinations(varied: &[usize]) -> Vec<[u32; AXES.len()]> {
    let mut all = vec![[0u32; AXES.len()]];
    for &axis in varied {
        all = all
            .into_iter()
            .flat_map(|values| {
                (0..AXES[axis].values).map(move |v| {
                    let mut next = values;
                    next[axis] = v;
                    next
                })
            })
            .collect();
    }
    let exclusive = EXCLUSIVE_AXES.map(axis_index);
    all.retain(|values| exclusive.iter().filter(|&&axis| values[axis] != 0).count() <= 1);
    all
}

/// What a module's SPIR-V depends on besides its preprocessed text: the compile settings below.
/// Change it whenever they change, so that no cached module outlives them. (A new shaderc
/// library is not seen here, nor by cargo: after upgrading it, `cargo clean`.)
const SETTINGS: &str = "vulkan1.3 glsl warnings-as-errors debug-info without-source";

/// The estimator's stages, lightly optimised (`Level::Light`): shaderc's optimiser took 7 to 34 s
/// a module of theirs, most of a fresh build, and their frames on lavapipe ran no faster for it.
/// The shading stages keep it: without it most of their frames were slower (docs/build.md
/// has the measurements).
const LIGHT_STAGES: [&str; 3] = ["multirate.tesc", "refine_levels.comp", "triangle_levels.comp"];

/// The axes of the analysis variants, which count or record and are never timed: their modules
/// are lightly optimised too.
const ANALYSIS_AXES: [&str; 2] = EXCLUSIVE_AXES;

/// How a module is optimised.
#[derive(Clone, Copy, PartialEq)]
enum Level {
    /// shaderc's `-O`.
    Performance,
    /// No optimiser, then `spirv-opt` with `LIGHT_PASSES`.
    Light,
    /// No optimiser.
    Zero,
}

impl Level {
    /// Its name in the cache key.
    fn name(self) -> &'static str {
        match self {
            Level::Performance => "performance",
            Level::Light => "light",
            Level::Zero => "zero",
        }
    }
}

/// Which modules are optimised how: `MULTIRATE_SHADER_OPTIMISATION` = `measured` (the default:
/// `LIGHT_STAGES` and the analysis variants lightly, the rest with `-O`), `all` (every module
/// with `-O`) or `none` (none), the last two to measure the choice again (docs/build.md).
#[derive(Clone, Copy, PartialEq)]
enum Optimisation {
    Measured,
    All,
    None,
}

const OPTIMISATION_VARIABLE: &str = "MULTIRATE_SHADER_OPTIMISATION";

impl Optimisation {
    fn from_environment() -> Optimisation {
        match std::env::var(OPTIMISATION_VARIABLE).as_deref() {
            Err(_) | Ok("measured") => Optimisation::Measured,
            Ok("all") => Optimisation::All,
            Ok("none") => Optimisation::None,
            Ok(other) => panic!("{OPTIMISATION_VARIABLE}={other}: expected measured, all or none"),
        }
    }

    /// How the module of `stage` with feature `values` is optimised.
    fn level(self, stage: &Path, values: &[u32; AXES.len()]) -> Level {
        let file = stage.file_name().expect("stage has a file name").to_string_lossy();
        let analysis = ANALYSIS_AXES.iter().any(|&axis| values[axis_index(axis)] != 0);
        match self {
            Optimisation::Measured if analysis || LIGHT_STAGES.contains(&file.as_ref()) => Level::Light,
            Optimisation::Measured | Optimisation::All => Level::Performance,
            Optimisation::None => Level::Zero,
        }
    }
}

fn options<'a>(job: &Job, include_dir: &Path) -> shaderc::CompileOptions<'a> {
    let mut options = shaderc::CompileOptions::new().expect("shaderc options");
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_3 as u32);
    options.set_source_language(shaderc::SourceLanguage::GLSL);
    options.set_warnings_as_errors();
    // Names (OpName, OpMemberName) for the layout test and debuggers; `without_source` then
    // drops the embedded source text, which would make every variant ~300 kB.
    options.set_generate_debug_info();
    options.set_optimization_level(match job.level {
        Level::Performance => shaderc::OptimizationLevel::Performance,
        Level::Light | Level::Zero => shaderc::OptimizationLevel::Zero,
    });
    for (axis, value) in AXES.iter().zip(job.values) {
        options.add_macro_definition(axis.define, Some(&value.to_string()));
    }
    let include_root = include_dir.to_path_buf();
    options.set_include_callback(move |name, _kind, requester, _depth| {
        let path = include_root.join(name);
        let content = std::fs::read_to_string(&path)
            .map_err(|e| format!("{requester}: cannot include {}: {e}", path.display()))?;
        Ok(shaderc::ResolvedInclude { resolved_name: path.display().to_string(), content })
    });
    options
}

/// The module's cache key: a hash of its stage kind, the settings and its preprocessed text
/// (every include expanded, every variant define applied), so that editing a header recompiles
/// only the stages that include it, and only where the edit survives preprocessing.
fn cache_key(job: &Job, include_dir: &Path, compiler: &shaderc::Compiler) -> Result<String, String> {
    use std::hash::{Hash as _, Hasher as _};
    let name = job.module_name();
    let expanded = compiler
        .preprocess(&job.source, &job.stage.display().to_string(), "main", Some(&options(job, include_dir)))
        .map_err(|e| format!("{name}: {e}"))?;
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    (job.kind as u32, SETTINGS, job.level.name(), LIGHT_PASSES, expanded.as_text()).hash(&mut hasher);
    Ok(format!("{:016x}", hasher.finish()))
}

/// Compiles `job` unless `$OUT_DIR/spirv` holds its module under the same cache key (a
/// `.spv.key` file beside the `.spv`, written after it). Returns the seconds compiling took,
/// None where the cache held the module.
fn compile(job: &Job, include_dir: &Path, out_dir: &Path) -> Result<Option<f64>, String> {
    let compiler = shaderc::Compiler::new().expect("shaderc compiler");
    let name = job.module_name();
    let out = out_dir.join(format!("{name}.spv"));
    let key_file = out_dir.join(format!("{name}.spv.key"));
    let key = cache_key(job, include_dir, &compiler)?;
    if out.is_file() && std::fs::read_to_string(&key_file).is_ok_and(|cached| cached == key) {
        return Ok(None);
    }
    let started = std::time::Instant::now();
    let artifact = compiler
        .compile_into_spirv(
            &job.source,
            job.kind,
            &job.stage.display().to_string(),
            "main",
            Some(&options(job, include_dir)),
        )
        .map_err(|e| format!("{name}: {e}"))?;
    // No key may vouch for a module while it is being replaced.
    let _ = std::fs::remove_file(&key_file);
    let mut words = without_source(artifact.as_binary());
    if job.level == Level::Light {
        words = light_optimised(&words, &out).map_err(|e| format!("{name}: {e}"))?;
    }
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    std::fs::write(&out, bytes).map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    std::fs::write(&key_file, key).map_err(|e| format!("cannot write {}: {e}", key_file.display()))?;
    Ok(Some(started.elapsed().as_secs_f64()))
}

/// The passes of the light optimisation: each function's locals into SSA form and the dead code
/// out, without inlining (the driver inlines), in a fraction of a second a module.
const LIGHT_PASSES: [&str; 7] = [
    "--eliminate-local-single-block",
    "--eliminate-local-single-store",
    "--ssa-rewrite",
    "--eliminate-dead-branches",
    "--eliminate-dead-code-aggressive",
    "--merge-blocks",
    "--eliminate-dead-functions",
];

/// `module` after `spirv-opt` ran `LIGHT_PASSES` on it, through files beside `out`.
fn light_optimised(module: &[u32], out: &Path) -> Result<Vec<u32>, String> {
    let input = out.with_extension("spv.in");
    let output = out.with_extension("spv.light");
    let bytes: Vec<u8> = module.iter().flat_map(|w| w.to_le_bytes()).collect();
    std::fs::write(&input, bytes).map_err(|e| format!("cannot write {}: {e}", input.display()))?;
    let status = std::process::Command::new("spirv-opt")
        .args(LIGHT_PASSES)
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .status()
        .map_err(|e| format!("cannot run spirv-opt (package spirv-tools): {e}"))?;
    if !status.success() {
        return Err(format!("spirv-opt failed ({status})"));
    }
    let bytes = std::fs::read(&output).map_err(|e| format!("cannot read {}: {e}", output.display()))?;
    let _ = std::fs::remove_file(&input);
    let _ = std::fs::remove_file(&output);
    Ok(bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect())
}

/// The module without its source-level debug instructions (OpSourceContinued, OpSource,
/// OpSourceExtension, OpString, OpLine, OpNoLine, OpModuleProcessed): only OpLine and OpSource
/// refer to OpString's ids, and none of them changes what the module does.
fn without_source(module: &[u32]) -> Vec<u32> {
    const SOURCE_ONLY: [u32; 7] = [2, 3, 4, 7, 8, 317, 330];
    let (header, mut rest) = module.split_at(5);
    let mut kept = header.to_vec();
    while let Some(&first) = rest.first() {
        let count = ((first >> 16) as usize).clamp(1, rest.len());
        if !SOURCE_ONLY.contains(&(first & 0xffff)) {
            kept.extend_from_slice(&rest[..count]);
        }
        rest = &rest[count..];
    }
    kept
}

/// `src/shaders.rs`'s table: per module, its stage, the features it varies over and their values.
fn variant_table(jobs: &[Job]) -> String {
    let mut table = String::from("&[\n");
    for job in jobs {
        let stage = job.stage.file_name().expect("stage has a file name").to_string_lossy();
        let mask: u32 = job.varied.iter().map(|&a| 1 << a).sum();
        let _ = writeln!(
            table,
            "    Module {{ stage: {stage:?}, varied: {mask}, values: {:?}, spirv: \
             include_bytes!(concat!(env!(\"OUT_DIR\"), \"/spirv/{}.spv\")) }},",
            job.values,
            job.module_name()
        );
    }
    table.push(']');
    table
}

fn main() {
    let glsl = Path::new("glsl");
    let include_dir = glsl.join("include");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("spirv");
    std::fs::create_dir_all(&out_dir).expect("create the SPIR-V output folder");

    println!("cargo:rerun-if-changed={}", glsl.display());
    println!("cargo:rerun-if-changed={}", include_dir.display());
    for header in headers_in(&include_dir) {
        println!("cargo:rerun-if-changed={}", header.display());
    }

    println!("cargo:rerun-if-env-changed={OPTIMISATION_VARIABLE}");
    let optimisation = Optimisation::from_environment();
    let mut jobs = Vec::new();
    for stage in files_in(glsl) {
        let Some(kind) = stage_kind(&stage) else { continue };
        println!("cargo:rerun-if-changed={}", stage.display());
        let source = std::fs::read_to_string(&stage)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", stage.display()));
        let varied = axes_of(&stage, &source);
        for values in combinations(&varied) {
            jobs.push(Job {
                stage: stage.clone(),
                kind,
                source: source.clone(),
                values,
                varied: varied.clone(),
                level: optimisation.level(&stage, &values),
            });
        }
    }

    // Compile on every core: the biggest stages take seconds each, and there are many variants.
    // The optimiser recurses deeply on the estimator's stages: a thread's default 2 MiB stack
    // overflows, so each compiling thread gets a large one.
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(jobs.len().max(1));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let failures = std::sync::Mutex::new(Vec::new());
    let compiled = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..threads {
            std::thread::Builder::new()
                .stack_size(COMPILER_STACK_BYTES)
                .spawn_scoped(scope, || loop {
                    let index = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(job) = jobs.get(index) else { break };
                    match compile(job, &include_dir, &out_dir) {
                        Ok(Some(seconds)) => compiled
                            .lock()
                            .expect("no thread panicked holding the lock")
                            .push((job.module_name(), seconds)),
                        Ok(None) => {}
                        Err(error) => {
                            failures.lock().expect("no thread panicked holding the lock").push(error)
                        }
                    }
                })
                .expect("a compiling thread starts");
        }
    });
    let failures = failures.into_inner().expect("no thread panicked holding the lock");
    if !failures.is_empty() {
        for failure in &failures {
            for line in failure.lines() {
                println!("cargo:warning={line}");
            }
        }
        panic!("{} shader(s) failed to compile:\n{}", failures.len(), failures.join("\n"));
    }
    // Shown by `cargo build -vv`: how much of the build the cache saved.
    let mut compiled = compiled.into_inner().expect("no thread panicked holding the lock");
    println!("{} of {} shader modules compiled, the others cached", compiled.len(), jobs.len());
    // What each module compiled in this build took, for docs/build.md.
    compiled.sort_by(|a, b| a.0.cmp(&b.0));
    let times: String = compiled.iter().map(|(name, seconds)| format!("{name}\t{seconds:.3}\n")).collect();
    let times_file = out_dir.join("compile_times.tsv");
    std::fs::write(&times_file, times)
        .unwrap_or_else(|e| panic!("cannot write {}: {e}", times_file.display()));
    let table = out_dir.join("variants.rs");
    std::fs::write(&table, variant_table(&jobs))
        .unwrap_or_else(|e| panic!("cannot write {}: {e}", table.display()));
    let axes = out_dir.join("axes.rs");
    std::fs::write(&axes, format!("{:?}", AXES.map(|a| a.name)))
        .unwrap_or_else(|e| panic!("cannot write {}: {e}", axes.display()));
}
