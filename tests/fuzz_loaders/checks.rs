//! Running a case and checking what it gave.

use super::*;

/// What a loader made of a case, summarised on the case's thread.
pub(crate) enum Outcome {
    /// Loaded: the level-0 texels of the textures it holds, and any broken invariant.
    Loaded { texels: usize, broken: Vec<String> },
    /// Refused, with the error's message (and a note where the error lacks what it should have).
    Refused { message: String, missing: Option<String> },
}

pub(crate) fn load_case(target: Target, input: PathBuf) -> Outcome {
    match target {
        Target::SceneToml | Target::ObjScene => match Scene::load(&input) {
            Ok(scene) => {
                let mut broken = Vec::new();
                check_scene(&scene, &mut broken);
                let mut texels = 0;
                for material in &scene.materials {
                    let maps = [
                        material.maps.albedo.as_deref(),
                        material.maps.parameter.as_ref().map(|p| &*p.texture),
                    ];
                    for texture in maps.into_iter().flatten() {
                        texels += texture.width() as usize * texture.height() as usize;
                        check_texture(texture, &mut broken);
                    }
                }
                Outcome::Loaded { texels, broken }
            }
            Err(error) => {
                let missing = match &error {
                    SceneError::Parse { line: None, .. } => Some("a TOML error without a line".to_string()),
                    _ => None,
                };
                Outcome::Refused { message: error.to_string(), missing }
            }
        },
        Target::Texture(usage) => match Texture::load(&input, usage) {
            Ok(texture) => {
                let mut broken = Vec::new();
                check_texture(&texture, &mut broken);
                if texture.usage != usage {
                    broken.push(format!("usage {:?}, asked for {usage:?}", texture.usage));
                }
                Outcome::Loaded { texels: texture.width() as usize * texture.height() as usize, broken }
            }
            Err(error) => Outcome::Refused { message: error.to_string(), missing: None },
        },
    }
}

/// Notes in `broken` each documented invariant of a loaded scene that does not hold.
pub(crate) fn check_scene(scene: &Scene, broken: &mut Vec<String>) {
    let mut fail = |what: String| broken.push(what);
    let finite3 = |v: glam::Vec3| v.is_finite();
    if scene.meshes.is_empty() {
        fail("no meshes".into());
    }
    if !scene.origin.is_finite() {
        fail(format!("origin {}", scene.origin));
    }
    for (k, mesh) in scene.meshes.iter().enumerate() {
        let n = mesh.positions.len();
        if mesh.material >= scene.materials.len() {
            fail(format!("mesh {k}: material {} of {}", mesh.material, scene.materials.len()));
        }
        if let Some(p) = mesh.positions.iter().find(|p| !finite3(**p)) {
            fail(format!("mesh {k}: position {p}"));
        }
        if mesh.normals.len() != n {
            fail(format!("mesh {k}: {} normals for {n} positions", mesh.normals.len()));
        }
        if let Some(v) = mesh.normals.iter().find(|v| !(v.is_finite() && (v.length() - 1.0).abs() < 1e-3)) {
            fail(format!("mesh {k}: normal {v} is not unit length"));
        }
        if mesh.indices.is_empty() || mesh.indices.len() % 3 != 0 {
            fail(format!("mesh {k}: {} indices", mesh.indices.len()));
        }
        if let Some(i) = mesh.indices.iter().find(|&&i| i as usize >= n) {
            fail(format!("mesh {k}: index {i} of {n} positions"));
        }
        if !(mesh.uvs.is_empty() || mesh.uvs.len() == n) || mesh.uvs.iter().any(|uv| !uv.is_finite()) {
            fail(format!("mesh {k}: {} uvs for {n} positions, or one not finite", mesh.uvs.len()));
        }
    }
    let c = &scene.camera;
    let camera_ok = finite3(c.eye)
        && finite3(c.target)
        && c.eye != c.target
        && (c.up.length() - 1.0).abs() < 1e-3
        && c.fov_y_degrees > 0.0
        && c.fov_y_degrees < 180.0
        && c.near > 0.0
        && c.near < c.far
        && c.far.is_finite();
    if !camera_ok {
        fail(format!("camera {c:?}"));
    }
    let s = &scene.settings;
    let settings_ok = (1..=16384).contains(&s.width)
        && (1..=16384).contains(&s.height)
        && s.epsilon > 0.0
        && s.epsilon.is_finite()
        && (1..=64).contains(&s.n_max)
        && s.exposure > 0.0
        && s.exposure.is_finite()
        && finite3(s.clear_color)
        && s.clear_color.min_element() >= 0.0
        && (1..=256).contains(&s.light_sampling.samples)
        && (0.0..=1.0).contains(&s.light_sampling.mis_visibility);
    if !settings_ok {
        fail(format!("settings {s:?}"));
    }
    let unit = |v: glam::Vec3| finite3(v) && v.min_element() >= 0.0 && v.max_element() <= 1.0;
    for m in &scene.materials {
        let ok = match m.kind {
            MaterialKind::Lambert { kd } => unit(kd),
            MaterialKind::BlinnPhong { kd, ks, shininess } => {
                unit(kd) && unit(ks) && (1.0..=1.0e4).contains(&shininess)
            }
            MaterialKind::Ggx { albedo, f0, roughness } => {
                unit(albedo) && unit(f0) && (0.0..=1.0).contains(&roughness)
            }
        };
        if !ok || m.name.trim().is_empty() {
            fail(format!("material {:?}: {:?}", m.name, m.kind));
        }
    }
    if scene.lights.is_empty() {
        fail("no lights".into());
    }
    for light in &scene.lights {
        let ok = match light {
            Light::Point { position, color, intensity } => {
                finite3(*position) && finite3(*color) && color.min_element() >= 0.0 && *intensity >= 0.0
            }
            Light::Directional { direction, color, intensity } => {
                (direction.length() - 1.0).abs() < 1e-3
                    && finite3(*color)
                    && color.min_element() >= 0.0
                    && *intensity >= 0.0
            }
            Light::Polygon(p) => {
                (3..=p.vertices.len()).contains(&p.count)
                    && p.vertices().iter().all(|v| finite3(*v))
                    && p.area > 0.0
                    && p.area.is_finite()
                    && (p.normal.length() - 1.0).abs() < 1e-3
            }
        };
        if !ok || !light_intensity_finite(light) {
            fail(format!("light {light:?}"));
        }
    }
}

pub(crate) fn light_intensity_finite(light: &Light) -> bool {
    match light {
        Light::Point { intensity, .. } | Light::Directional { intensity, .. } => intensity.is_finite(),
        Light::Polygon(p) => p.intensity.is_finite() && p.color.is_finite(),
    }
}

/// Notes in `broken` where a loaded texture's mip chain is not as [`Texture`] documents it.
pub(crate) fn check_texture(texture: &Texture, broken: &mut Vec<String>) {
    let name = texture.path.display();
    let Some(first) = texture.levels.first() else {
        broken.push(format!("{name}: no levels"));
        return;
    };
    if !(1..=MAX_TEXTURE_SIZE).contains(&first.width) || !(1..=MAX_TEXTURE_SIZE).contains(&first.height) {
        broken.push(format!("{name}: level 0 is {}×{}", first.width, first.height));
    }
    if texture.usage == TextureUsage::Parameter
        && !(first.width.is_power_of_two() && first.height.is_power_of_two())
    {
        broken.push(format!("{name}: parameter map {}×{}", first.width, first.height));
    }
    for (k, level) in texture.levels.iter().enumerate() {
        let expected = level.width as usize * level.height as usize * texture.usage.bytes_per_texel();
        if level.texels.len() != expected {
            broken.push(format!("{name}: level {k} has {} bytes, not {expected}", level.texels.len()));
        }
        if let Some(next) = texture.levels.get(k + 1) {
            if (next.width, next.height) != ((level.width / 2).max(1), (level.height / 2).max(1)) {
                broken.push(format!("{name}: level {} is {}×{}", k + 1, next.width, next.height));
            }
        }
    }
    let last = texture.levels.last().map(|l| (l.width, l.height));
    if last != Some((1, 1)) {
        broken.push(format!("{name}: the chain ends at {last:?}"));
    }
}

/// A case's folder under the system's temporary folder, removed when dropped unless kept.
pub(crate) struct CaseDir {
    pub(crate) path: PathBuf,
    pub(crate) keep: bool,
}

impl CaseDir {
    pub(crate) fn new(seed: u64, index: u64) -> CaseDir {
        let path =
            std::env::temp_dir().join(format!("multirate-fuzz-{}-{seed:x}-{index}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        CaseDir { path, keep: false }
    }

    pub(crate) fn write(&self, name: &str, bytes: &[u8]) {
        let path = self.path.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).unwrap_or_else(|e| panic!("{}: {e}", parent.display()));
        }
        std::fs::write(&path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
}

impl Drop for CaseDir {
    fn drop(&mut self) {
        if !self.keep {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

/// What a run found and how it went.
#[derive(Default)]
pub(crate) struct Tally {
    pub(crate) cases: usize,
    pub(crate) loaded: usize,
    pub(crate) refused: usize,
    pub(crate) by_target: [usize; 3],
    pub(crate) slowest: (Duration, u64),
    pub(crate) largest_peak: (usize, u64),
    pub(crate) failures: Vec<String>,
    pub(crate) failed_cases: usize,
}

/// Runs case `index` of the run with `seed` and checks it; a failure goes into `tally` with
/// what reproduces it.
pub(crate) fn run_case(corpus: &Corpus, seed: u64, index: u64, verbose: bool, tally: &mut Tally) {
    let mut rng = Rng::for_case(seed, index);
    let case = build_case(corpus, &mut rng);
    let mut dir = CaseDir::new(seed, index);
    for (name, bytes) in &case.files {
        dir.write(name, bytes);
    }
    let input = dir.path.join(&case.input);
    let target = case.target;
    let tracked = run_tracked((seed, index), {
        let input = input.clone();
        move || load_case(target, input)
    });

    let mut problems = Vec::new();
    match tracked {
        Err(limit) => problems.push(format!("did not return within {limit:?} (hung)")),
        Ok(tracked) => {
            if tracked.elapsed > tally.slowest.0 {
                tally.slowest = (tracked.elapsed, index);
            }
            if tracked.peak > tally.largest_peak.0 {
                tally.largest_peak = (tracked.peak, index);
            }
            if let Some(note) = &tracked.panic {
                problems.push(format!("panicked: {note}"));
            }
            if tracked.elapsed > CASE_LIMIT {
                problems.push(format!("took {:?}, more than {CASE_LIMIT:?}", tracked.elapsed));
            }
            let mut allowed = MEMORY_LIMIT;
            match &tracked.value {
                Err(message) => problems.push(format!("unwound with {message}")),
                Ok(Outcome::Loaded { texels, broken }) => {
                    if verbose {
                        println!("case {index}: {}: loaded", case.input);
                    }
                    tally.loaded += 1;
                    allowed += BYTES_PER_LOADED_TEXEL * texels;
                    problems.extend(broken.iter().map(|b| format!("loaded, but {b}")));
                }
                Ok(Outcome::Refused { message, missing }) => {
                    if verbose {
                        println!("case {index}: refused: {message}");
                    }
                    tally.refused += 1;
                    let names_input = message.contains(&input.display().to_string());
                    let names_culprit = case
                        .files
                        .iter()
                        .any(|(name, _)| message.starts_with(&dir.path.join(name).display().to_string()));
                    if !(names_input || names_culprit) {
                        problems
                            .push(format!("refused with a message that names none of its files: {message}"));
                    }
                    if let Some(missing) = missing {
                        problems.push(format!("refused with {missing}: {message}"));
                    }
                }
            }
            if tracked.peak > allowed {
                problems.push(format!("peak {} bytes live, more than the {allowed} allowed", tracked.peak));
            }
        }
    }
    tally.cases += 1;
    tally.by_target[match target {
        Target::SceneToml => 0,
        Target::ObjScene => 1,
        Target::Texture(_) => 2,
    }] += 1;
    if !problems.is_empty() {
        tally.failed_cases += 1;
        dir.keep = true;
        if tally.failures.len() < 12 {
            let mut report = format!(
                "case {index} of seed {seed} ({target:?}, input {}): {}\n  rerun: MULTIRATE_FUZZ_SEED={seed} \
                 MULTIRATE_FUZZ_CASE={index} cargo test --release --test fuzz_loaders -- --nocapture\n  files kept in {}\n  mutations:\n",
                case.input,
                problems.join("; "),
                dir.path.display()
            );
            for line in case.log.lines() {
                let _ = writeln!(report, "    {}", shorten(line, 600));
            }
            for name in &case.mutated {
                if let Some((_, bytes)) = case.files.iter().find(|(n, _)| n == name) {
                    let _ = writeln!(
                        report,
                        "  {name} ({} bytes): {}",
                        bytes.len(),
                        shorten(&bytes.escape_ascii().to_string(), 1500)
                    );
                }
            }
            tally.failures.push(report);
        }
    }
}

pub(crate) fn shorten(text: &str, at: usize) -> String {
    if text.len() <= at {
        return text.to_string();
    }
    let mut end = at;
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}... ({} bytes in all)", &text[..end], text.len())
}

pub(crate) fn env_number(name: &str) -> Option<u64> {
    let value = std::env::var(name).ok()?;
    let value = value.trim();
    let parsed = match value.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => value.parse(),
    };
    Some(parsed.unwrap_or_else(|_| panic!("{name}={value} is not a number")))
}
