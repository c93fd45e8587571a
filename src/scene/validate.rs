//! The checks between the scene file as written (`schema.rs`) and a [`Scene`]: every value in
//! range, every name defined, the textures and OBJ files read, and everything placed relative to
//! the scene's floating origin. Each [`SceneError`] names the file, the item (`[[meshes]] #2
//! ("bunny.obj")`, `[camera]`) and the problem.

use super::error::SceneError;
use super::model::{
    bounds_of, Camera, Light, LightSampling, Material, MaterialKind, MaterialMaps, Mesh, ParameterMap,
    ParameterMapping, PolygonLight, RenderSettings, Scene, ShadowCaster,
};
use super::path::{CameraPath, PathKey, CHECK_SAMPLES};
use super::schema::{
    CameraFile, LightFile, LightType, MaterialFile, MaterialType, MeshFile, MeshMaterials, PathKeyFile,
    RenderFile, Scale, SceneFile,
};
use super::settings::{check_n_max, range_text, IMAGE_SIZE_RANGE, N_MAX_RANGE};
use super::texture::{MinMaxPyramid, Texture, TextureUsage};
use super::{adjacency, mesh, mtl};

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Vec2, Vec3};

use Bound::{Closed, Open};

/// Builds errors for one item of one file.
struct Item<'a> {
    path: &'a Path,
    item: String,
}

impl Item<'_> {
    fn error(&self, problem: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            path: self.path.to_path_buf(),
            item: self.item.clone(),
            problem: problem.into(),
        }
    }

    fn finite(&self, key: &str, v: f32) -> Result<f32, SceneError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(format!("`{key}` = {v} is not a finite number")))
        }
    }

    /// A world position (f64 in the file) relative to the scene's `origin`, in f32.
    fn point(&self, key: &str, v: [f64; 3], origin: DVec3) -> Result<Vec3, SceneError> {
        let world = self.dvec3(key, v)?;
        let placed = (world - origin).as_vec3();
        if placed.is_finite() {
            Ok(placed)
        } else {
            Err(self.error(format!(
                "`{key}` = {} is too far from the scene's meshes: not a finite number in f32",
                fmt_array(v)
            )))
        }
    }

    fn dvec3(&self, key: &str, v: [f64; 3]) -> Result<DVec3, SceneError> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(DVec3::from_array(v))
        } else {
            Err(self.error(format!("`{key}` = {} has a component that is not a finite number", fmt_array(v))))
        }
    }

    fn vec3(&self, key: &str, v: [f32; 3]) -> Result<Vec3, SceneError> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(Vec3::from_array(v))
        } else {
            Err(self.error(format!("`{key}` = {} has a component that is not a finite number", fmt_array(v))))
        }
    }

    /// A finite number in `lo..=hi` (or `lo < v` / `v < hi` where the bound is open).
    fn range(&self, key: &str, v: f32, lo: Bound, hi: Bound) -> Result<f32, SceneError> {
        let v = self.finite(key, v)?;
        if lo.below(v) && hi.above(v) {
            Ok(v)
        } else {
            Err(self.error(format!("`{key}` = {v} is outside {}", fmt_interval(lo, hi))))
        }
    }

    fn vec3_range(&self, key: &str, v: [f32; 3], lo: Bound, hi: Bound) -> Result<Vec3, SceneError> {
        let v3 = self.vec3(key, v)?;
        if v.iter().all(|&c| lo.below(c) && hi.above(c)) {
            Ok(v3)
        } else {
            Err(self.error(format!(
                "`{key}` = {} has a component outside {}",
                fmt_array(v),
                fmt_interval(lo, hi)
            )))
        }
    }

    fn required<T>(&self, key: &str, v: Option<T>, why: &str) -> Result<T, SceneError> {
        v.ok_or_else(|| self.error(format!("missing `{key}` (required {why})")))
    }

    fn forbidden<T>(&self, key: &str, v: &Option<T>, why: &str) -> Result<(), SceneError> {
        match v {
            Some(_) => Err(self.error(format!("`{key}` does not apply {why}"))),
            None => Ok(()),
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum Bound {
    Closed(f32),
    Open(f32),
    None,
}

impl Bound {
    /// Whether `v` is on the allowed side of this bound taken as a lower bound.
    fn below(self, v: f32) -> bool {
        match self {
            Bound::Closed(b) => v >= b,
            Bound::Open(b) => v > b,
            Bound::None => true,
        }
    }

    /// Whether `v` is on the allowed side of this bound taken as an upper bound.
    fn above(self, v: f32) -> bool {
        match self {
            Bound::Closed(b) => v <= b,
            Bound::Open(b) => v < b,
            Bound::None => true,
        }
    }
}

fn fmt_interval(lo: Bound, hi: Bound) -> String {
    let lo = match lo {
        Bound::Closed(b) => format!("[{b}"),
        Bound::Open(b) => format!("({b}"),
        Bound::None => "(-inf".to_string(),
    };
    let hi = match hi {
        Bound::Closed(b) => format!("{b}]"),
        Bound::Open(b) => format!("{b})"),
        Bound::None => "inf)".to_string(),
    };
    format!("{lo}, {hi}")
}

fn fmt_array<T: std::fmt::Display>(v: [T; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

pub(super) fn build(path: &Path, file: SceneFile) -> Result<Scene, SceneError> {
    let top = |key: &str| Item { path, item: format!("`{key}`") };
    if file.source.as_deref().is_some_and(|s| s.trim().is_empty()) {
        return Err(top("source").error("is empty: say where the meshes come from, or leave the key out"));
    }

    let settings = check_render(path, &file.render)?;

    let folder = path.parent().unwrap_or(Path::new(""));
    let mut materials: Vec<Material> = Vec::with_capacity(file.materials.len());
    for (i, m) in file.materials.iter().enumerate() {
        let material = check_material(path, folder, i, m)?;
        if materials.iter().any(|other| other.name == material.name) {
            return Err(Item { path, item: format!("[[materials]] #{} (\"{}\")", i + 1, m.name) }
                .error(format!("duplicate material name \"{}\"", m.name)));
        }
        materials.push(material);
    }

    if file.lights.is_empty() {
        return Err(top("lights").error("the scene has no lights; add at least one [[lights]] table"));
    }
    let check_lights = |origin| {
        file.lights
            .iter()
            .enumerate()
            .map(|(i, l)| check_light(path, i, l, settings.light_sampling, origin))
            .collect::<Result<Vec<_>, _>>()
    };
    let mut lights = check_lights(DVec3::ZERO)?;
    let shadow_casters = file
        .lights
        .iter()
        .enumerate()
        .filter_map(|(i, l)| check_shadow(path, i, l).transpose())
        .collect::<Result<Vec<_>, _>>()?;
    if shadow_casters.len() > ShadowCaster::MAX_LIGHTS {
        return Err(top("lights").error(format!(
            "{} lights cast shadows; at most {} may (remove `shadow` from the others)",
            shadow_casters.len(),
            ShadowCaster::MAX_LIGHTS
        )));
    }

    // The camera checks that do not need the meshes come first, so that a mistake there is
    // reported without reading any OBJ file.
    let camera_item = Item { path, item: "[camera]".to_string() };
    let mut camera = check_camera(&camera_item, &file.camera, DVec3::ZERO)?;

    if file.meshes.is_empty() {
        return Err(top("meshes").error("the scene has no meshes; add at least one [[meshes]] table"));
    }
    let mut geometry = Vec::with_capacity(file.meshes.len());
    let mut warnings = Vec::new();
    for (i, m) in file.meshes.iter().enumerate() {
        geometry.extend(read_mesh(path, folder, i, m, &mut materials, &mut warnings)?);
    }
    // The floating origin: lights and camera were checked at the world origin above, so that
    // their mistakes are reported before any OBJ file is read; far from it they are placed again.
    let (lo, hi) = geometry
        .iter()
        .map(|g| g.geometry.bounds())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), (l, h)| (lo.min(l), hi.max(h)));
    let origin = mesh::recentring_origin(lo, hi);
    if origin != DVec3::ZERO {
        lights = check_lights(origin)?;
        camera = check_camera(&camera_item, &file.camera, origin)?;
    }
    let entries: Vec<usize> = geometry.iter().map(|g| g.entry).collect();
    let mut meshes = Vec::with_capacity(geometry.len());
    for unplaced in geometry {
        meshes.push(finish_mesh(path, &file.meshes[unplaced.entry], &materials, unplaced, origin)?);
    }
    close_split_entries(&file.meshes, &entries, &mut meshes);

    // Emitters are drawn too, so the default far plane must reach them.
    let emitters = lights.iter().flat_map(|l| match l {
        Light::Polygon(p) => p.vertices().to_vec(),
        _ => Vec::new(),
    });
    let (lo, hi) = bounds_of(meshes.iter().flat_map(|m: &Mesh| m.positions.iter().copied()).chain(emitters));
    let camera = finish_camera(&camera_item, camera, &file.camera, lo, hi)?;
    let camera_path = check_path(path, &file.path, origin, &camera)?;

    Ok(Scene {
        path: path.to_path_buf(),
        description: file.description.unwrap_or_default(),
        camera,
        camera_path,
        settings,
        materials,
        lights,
        shadow_casters,
        meshes,
        origin,
        warnings,
    })
}

/// Light `index`'s shadow map, where its entry has a `shadow` table.
fn check_shadow(path: &Path, index: usize, l: &LightFile) -> Result<Option<ShadowCaster>, SceneError> {
    let Some(shadow) = &l.shadow else { return Ok(None) };
    let item = Item { path, item: format!("[[lights]] #{} `shadow`", index + 1) };
    if l.kind == LightType::Polygon {
        return Err(item.error(
            "polygonal lights cast no shadows (their light is unshadowed); remove `shadow` from this light",
        ));
    }
    let resolution = shadow.resolution.unwrap_or(ShadowCaster::DEFAULT_RESOLUTION);
    let range = ShadowCaster::RESOLUTIONS;
    if !range.contains(&resolution) {
        return Err(item.error(format!(
            "`resolution` = {resolution} is outside {}..={} (texels along a side of the map)",
            range.start(),
            range.end()
        )));
    }
    let filter = shadow.filter.unwrap_or(1);
    if filter % 2 == 0 || filter > ShadowCaster::MAX_FILTER {
        return Err(item.error(format!(
            "`filter` = {filter} is not an odd width from 1 to {} (texels along a side of the kernel; 1: hard shadows)",
            ShadowCaster::MAX_FILTER
        )));
    }
    Ok(Some(ShadowCaster { light: index, resolution, filter }))
}

fn check_render(path: &Path, r: &RenderFile) -> Result<RenderSettings, SceneError> {
    let item = Item { path, item: "[render]".to_string() };
    let size = |key: &str, v: u32| {
        if IMAGE_SIZE_RANGE.contains(&v) {
            Ok(v)
        } else {
            Err(item.error(format!("`{key}` = {v} is outside {}", range_text(&IMAGE_SIZE_RANGE))))
        }
    };
    let width = size("width", r.width)?;
    let height = size("height", r.height)?;
    if check_n_max(r.n_max).is_err() {
        return Err(item.error(format!("`n_max` = {} is outside {}", r.n_max, range_text(&N_MAX_RANGE))));
    }
    if !(1..=256).contains(&r.polygon_samples) {
        return Err(item.error(format!("`polygon_samples` = {} is outside 1..=256", r.polygon_samples)));
    }
    Ok(RenderSettings {
        width,
        height,
        epsilon: item.range("epsilon", r.epsilon, Open(0.0), Bound::None)?,
        n_max: r.n_max,
        exposure: item.range("exposure", r.exposure, Open(0.0), Bound::None)?,
        clear_color: item.vec3_range("clear_color", r.clear_color, Closed(0.0), Bound::None)?,
        light_sampling: LightSampling {
            samples: r.polygon_samples,
            technique: r.polygon_sampling,
            mis_visibility: item.range("mis_visibility", r.mis_visibility, Closed(0.0), Closed(1.0))?,
        },
    })
}

fn check_material(
    path: &Path,
    folder: &Path,
    index: usize,
    m: &MaterialFile,
) -> Result<Material, SceneError> {
    let item = Item { path, item: format!("[[materials]] #{} (\"{}\")", index + 1, m.name) };
    if m.name.trim().is_empty() {
        return Err(item.error("`name` is empty"));
    }
    let why = format!("for type \"{}\"", m.kind.as_str());
    let why_not = format!("to type \"{}\"", m.kind.as_str());
    let unit = |key: &str, v: [f32; 3]| item.vec3_range(key, v, Closed(0.0), Closed(1.0));
    let kind = match m.kind {
        MaterialType::Lambert => {
            for (key, v) in [("ks", &m.ks), ("albedo", &m.albedo), ("f0", &m.f0)] {
                item.forbidden(key, v, &why_not)?;
            }
            item.forbidden("shininess", &m.shininess, &why_not)?;
            item.forbidden("roughness", &m.roughness, &why_not)?;
            MaterialKind::Lambert { kd: unit("kd", item.required("kd", m.kd, &why)?)? }
        }
        MaterialType::BlinnPhong => {
            for (key, v) in [("albedo", &m.albedo), ("f0", &m.f0)] {
                item.forbidden(key, v, &why_not)?;
            }
            item.forbidden("roughness", &m.roughness, &why_not)?;
            let shininess = match m.shininess_range {
                Some(range) => {
                    item.forbidden("shininess", &m.shininess, "together with `shininess_range`")?;
                    check_parameter_range(&item, "shininess_range", range, 1.0, 1e4)?[0]
                }
                None => item.range(
                    "shininess",
                    item.required("shininess", m.shininess, &why)?,
                    Closed(1.0),
                    Closed(1e4),
                )?,
            };
            MaterialKind::BlinnPhong {
                kd: unit("kd", item.required("kd", m.kd, &why)?)?,
                ks: unit("ks", item.required("ks", m.ks, &why)?)?,
                shininess,
            }
        }
        MaterialType::Ggx => {
            for (key, v) in [("kd", &m.kd), ("ks", &m.ks)] {
                item.forbidden(key, v, &why_not)?;
            }
            item.forbidden("shininess", &m.shininess, &why_not)?;
            let roughness = match m.roughness_range {
                Some(range) => {
                    item.forbidden("roughness", &m.roughness, "together with `roughness_range`")?;
                    check_parameter_range(&item, "roughness_range", range, 0.0, 1.0)?[0]
                }
                None => item.range(
                    "roughness",
                    item.required("roughness", m.roughness, &why)?,
                    Closed(0.0),
                    Closed(1.0),
                )?,
            };
            MaterialKind::Ggx {
                albedo: unit("albedo", item.required("albedo", m.albedo, &why)?)?,
                f0: unit("f0", item.required("f0", m.f0, &why)?)?,
                roughness,
            }
        }
    };
    let maps = check_maps(&item, folder, m, &why_not)?;
    Ok(Material { name: m.name.clone(), kind, maps })
}

/// `[lo, hi]` with `min ≤ lo ≤ hi ≤ max`.
fn check_parameter_range(
    item: &Item,
    key: &str,
    range: [f32; 2],
    min: f32,
    max: f32,
) -> Result<[f32; 2], SceneError> {
    let [lo, hi] = range;
    if !(lo.is_finite() && hi.is_finite() && min <= lo && lo <= hi && hi <= max) {
        return Err(item.error(format!("`{key}` = [{lo}, {hi}] must satisfy {min} <= lo <= hi <= {max}")));
    }
    Ok(range)
}

/// The material's texture keys: which apply to its type, that a map and its range come
/// together, and the files themselves (read here, so that a bad file names the material).
fn check_maps(
    item: &Item,
    folder: &Path,
    m: &MaterialFile,
    why_not: &str,
) -> Result<MaterialMaps, SceneError> {
    let (albedo_key, albedo_path, other_albedo) = match m.kind {
        MaterialType::Ggx => ("albedo_map", &m.albedo_map, ("kd_map", &m.kd_map)),
        _ => ("kd_map", &m.kd_map, ("albedo_map", &m.albedo_map)),
    };
    item.forbidden(other_albedo.0, other_albedo.1, why_not)?;
    let (map_key, range_key, map, range, other_map, other_range, mapping) = match m.kind {
        MaterialType::Lambert => {
            item.forbidden("shininess_map", &m.shininess_map, why_not)?;
            item.forbidden("roughness_map", &m.roughness_map, why_not)?;
            item.forbidden("shininess_range", &m.shininess_range, why_not)?;
            item.forbidden("roughness_range", &m.roughness_range, why_not)?;
            ("", "", &None, &None, ("", &None), ("", &None), ParameterMapping::Linear)
        }
        MaterialType::BlinnPhong => (
            "shininess_map",
            "shininess_range",
            &m.shininess_map,
            &m.shininess_range,
            ("roughness_map", &m.roughness_map),
            ("roughness_range", &m.roughness_range),
            ParameterMapping::Exponential,
        ),
        MaterialType::Ggx => (
            "roughness_map",
            "roughness_range",
            &m.roughness_map,
            &m.roughness_range,
            ("shininess_map", &m.shininess_map),
            ("shininess_range", &m.shininess_range),
            ParameterMapping::Linear,
        ),
    };
    item.forbidden(other_map.0, other_map.1, why_not)?;
    item.forbidden(other_range.0, other_range.1, why_not)?;
    let load = |key: &str, file: &Path, usage: TextureUsage| {
        Texture::load(&folder.join(file), usage)
            .map(Arc::new)
            .map_err(|e| item.error(format!("`{key}`: {e}")))
    };
    let albedo = match albedo_path {
        Some(file) => Some(load(albedo_key, file, TextureUsage::Albedo)?),
        None => None,
    };
    let parameter = match (map, range) {
        (Some(file), Some([lo, hi])) => {
            let texture = load(map_key, file, TextureUsage::Parameter)?;
            let pyramid = Arc::new(MinMaxPyramid::new(&texture));
            Some(ParameterMap { texture, pyramid, lo: *lo, hi: *hi, mapping })
        }
        (Some(_), None) => return Err(item.error(format!("`{map_key}` needs `{range_key}` = [lo, hi]"))),
        (None, Some(_)) => return Err(item.error(format!("`{range_key}` is given without `{map_key}`"))),
        (None, None) => None,
    };
    Ok(MaterialMaps { albedo, parameter })
}

fn check_light(
    path: &Path,
    index: usize,
    l: &LightFile,
    sampling: LightSampling,
    origin: DVec3,
) -> Result<Light, SceneError> {
    let kind = match l.kind {
        LightType::Point => "point",
        LightType::Directional => "directional",
        LightType::Polygon => "polygon",
    };
    let item = Item { path, item: format!("[[lights]] #{} ({kind})", index + 1) };
    let color = item.vec3_range("color", l.color, Closed(0.0), Bound::None)?;
    let intensity = item.range("intensity", l.intensity, Closed(0.0), Bound::None)?;
    let why = format!("for type \"{kind}\"");
    let why_not = format!("to type \"{kind}\"");
    Ok(match l.kind {
        LightType::Point => {
            let position = item.point("position", item.required("position", l.position, &why)?, origin)?;
            item.forbidden("direction", &l.direction, &why_not)?;
            item.forbidden("vertices", &l.vertices, &why_not)?;
            Light::Point { position, color, intensity }
        }
        LightType::Polygon => {
            let raw = item.required("vertices", l.vertices.as_ref(), &why)?;
            item.forbidden("position", &l.position, &why_not)?;
            item.forbidden("direction", &l.direction, &why_not)?;
            let vertices =
                raw.iter().map(|v| item.point("vertices", *v, origin)).collect::<Result<Vec<_>, _>>()?;
            let light = PolygonLight::new(&vertices, color, intensity)
                .map_err(|problem| item.error(format!("`vertices`: {problem}")))?;
            Light::Polygon(PolygonLight { sampling, ..light })
        }
        LightType::Directional => {
            let raw = item.required("direction", l.direction, &why)?;
            item.forbidden("position", &l.position, &why_not)?;
            item.forbidden("vertices", &l.vertices, &why_not)?;
            let direction = item.vec3("direction", raw)?.normalize_or_zero();
            if direction == Vec3::ZERO || !direction.is_finite() {
                return Err(item.error(format!("`direction` = {} is zero", fmt_array(raw))));
            }
            Light::Directional { direction, color, intensity }
        }
    })
}

/// Checks everything about the camera except `near`/`far`, which may need the scene bounds.
fn check_camera(item: &Item, c: &CameraFile, origin: DVec3) -> Result<Camera, SceneError> {
    let eye = item.point("eye", c.eye, origin)?;
    let target = item.point("target", c.target, origin)?;
    let raw_up = c.up.unwrap_or([0.0, 1.0, 0.0]);
    let up = item.vec3("up", raw_up)?;
    let fov_y_degrees = item.range("fov_y_degrees", c.fov_y_degrees, Open(0.0), Open(180.0))?;
    // In f64: two points far from zero can differ by less than f32's spacing there.
    let view = (item.dvec3("target", c.target)? - item.dvec3("eye", c.eye)?).normalize_or_zero().as_vec3();
    if view == Vec3::ZERO || !view.is_finite() {
        return Err(item.error(format!("`eye` and `target` are the same point {}", fmt_array(c.eye))));
    }
    let up = up.normalize_or_zero();
    if up == Vec3::ZERO || !up.is_finite() {
        return Err(item.error(format!("`up` = {} is zero", fmt_array(raw_up))));
    }
    if view.cross(up).length() < 1e-4 {
        return Err(item.error(format!(
            "`up` = {} is parallel to the view direction (from `eye` to `target`)",
            fmt_array(raw_up)
        )));
    }
    if let Some(near) = c.near {
        item.range("near", near, Open(0.0), Bound::None)?;
    }
    if let Some(far) = c.far {
        item.range("far", far, Open(0.0), Bound::None)?;
    }
    Ok(Camera { eye, target, up, fov_y_degrees, near: 0.0, far: 0.0 })
}

/// The scene file's camera path, placed relative to `origin`: at least two keys, in increasing
/// time, and at every key and along the path (at [`CHECK_SAMPLES`] points a segment) an eye
/// apart from its target that does not look along `camera.up`.
fn check_path(
    path: &Path,
    keys: &[PathKeyFile],
    origin: DVec3,
    camera: &Camera,
) -> Result<Option<CameraPath>, SceneError> {
    if keys.is_empty() {
        return Ok(None);
    }
    let item = |i: usize| Item { path, item: format!("[[path]] #{}", i + 1) };
    if keys.len() < 2 {
        return Err(item(0).error("a path needs at least two keys"));
    }
    let mut checked: Vec<PathKey> = Vec::with_capacity(keys.len());
    for (i, key) in keys.iter().enumerate() {
        let time = item(i).finite("time", key.time)?;
        if let Some(before) = checked.last().filter(|before| time <= before.time) {
            return Err(
                item(i).error(format!("`time` = {time} is not after the key before's ({})", before.time))
            );
        }
        let (eye, target) =
            (item(i).point("eye", key.eye, origin)?, item(i).point("target", key.target, origin)?);
        checked.push(PathKey { time, eye, target });
    }
    let camera_path = CameraPath::Keys(checked.clone());
    for (i, pair) in checked.windows(2).enumerate() {
        for k in 0..=CHECK_SAMPLES {
            let time = pair[0].time + (pair[1].time - pair[0].time) * k as f32 / CHECK_SAMPLES as f32;
            let (eye, target) =
                camera_path.eye_and_target((camera.eye, camera.target, camera.up), time - checked[0].time);
            let view = (target - eye).normalize_or_zero();
            let problem = if view == Vec3::ZERO {
                "the eye meets the target"
            } else if view.cross(camera.up).length() < 1e-4 {
                "the camera looks along `up` ([camera])"
            } else {
                continue;
            };
            return Err(
                item(i).error(format!("between this key and the next, at `time` = {time}, {problem}"))
            );
        }
    }
    Ok(Some(camera_path))
}

/// Fills in `near` and `far`: a missing `far` lies just past the bounds corner farthest from
/// the eye (and past the target), a missing `near` is `far / 1000`.
fn finish_camera(
    item: &Item,
    mut camera: Camera,
    c: &CameraFile,
    lo: Vec3,
    hi: Vec3,
) -> Result<Camera, SceneError> {
    let far = match c.far {
        Some(far) => far,
        None => {
            let eye = camera.eye.as_dvec3();
            let mut farthest = (camera.target.as_dvec3() - eye).length();
            for i in 0..8 {
                let corner = Vec3::select(glam::BVec3::new(i & 1 == 0, i & 2 == 0, i & 4 == 0), lo, hi);
                farthest = farthest.max((corner.as_dvec3() - eye).length());
            }
            let far = (farthest * 1.01) as f32;
            if !far.is_finite() {
                return Err(item.error("cannot derive `far` from the scene bounds (too large); give `far`"));
            }
            far
        }
    };
    let near = c.near.unwrap_or(far * 1e-3);
    if !(near > 0.0 && near.is_finite()) {
        return Err(item.error(format!("derived `near` = {near} is not a positive number; give `near`")));
    }
    if near >= far {
        return Err(item.error(format!("`near` = {near} is not less than `far` = {far}")));
    }
    camera.near = near;
    camera.far = far;
    Ok(camera)
}

/// One mesh of the scene before it is placed relative to the scene's origin: its `[[meshes]]`
/// entry, name, OBJ file, material and geometry (with the entry's transform).
struct Unplaced {
    entry: usize,
    name: String,
    source: PathBuf,
    material: usize,
    geometry: mesh::TransformedMesh,
}

/// Reads the OBJ file of `[[meshes]]` entry `index` and applies its transform: one mesh, or with
/// `materials = "mtl"` one per MTL material used (those materials added to `materials`).
fn read_mesh(
    path: &Path,
    folder: &Path,
    index: usize,
    m: &MeshFile,
    materials: &mut Vec<Material>,
    warnings: &mut Vec<String>,
) -> Result<Vec<Unplaced>, SceneError> {
    let item = mesh_item(path, index, m);
    let material = match (&m.material, m.materials) {
        (Some(_), Some(_)) => {
            return Err(item.error("`material` and `materials` exclude each other: give one"));
        }
        (None, None) => {
            return Err(item.error(
                "missing `material` (a [[materials]] name) or `materials = \"mtl\"` (the OBJ file's own)",
            ));
        }
        (Some(name), None) => match materials.iter().position(|mat| mat.name == *name) {
            Some(material) => Some(material),
            None => return Err(item.error(format!("material \"{name}\" is not defined"))),
        },
        (None, Some(MeshMaterials::Mtl)) => {
            let why = "with `materials = \"mtl\"` (its textures take the OBJ file's `vt`)";
            item.forbidden("uv_projection", &m.uv_projection, why)?;
            item.forbidden("uv_scale", &m.uv_scale, why)?;
            None
        }
    };
    let scale = item.vec3("scale", m.scale.unwrap_or(Scale([1.0; 3])).0)?;
    if scale.to_array().contains(&0.0) {
        return Err(item.error(format!("`scale` = {} has a zero component", fmt_array(scale.to_array()))));
    }
    let transform = mesh::Transform {
        scale,
        rotate_degrees: item.vec3("rotate_degrees", m.rotate_degrees.unwrap_or([0.0; 3]))?,
        translate: item.dvec3("translate", m.translate.unwrap_or([0.0; 3]))?,
    };
    let source = folder.join(&m.obj);
    let name = match &m.name {
        Some(name) => name.clone(),
        None => m.obj.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
    };
    let Some(material) = material else {
        let bytes = super::file::read_file(&source).map_err(|e| {
            obj_error(path, &source, index, mesh::ObjProblem::new(format!("cannot read file: {e}")))
        })?;
        let error = |file: &Path, problem| obj_error(path, file, index, problem);
        let parts = mtl::load_parts(&source, &bytes, &transform, &error, warnings)?;
        let mut split = Vec::with_capacity(parts.len());
        for mtl::Part { mut material, geometry } in parts {
            let part = format!("{name}/{}", material.name);
            material.name = part.clone();
            for k in 2.. {
                if !materials.iter().any(|other| other.name == material.name) {
                    break;
                }
                material.name = format!("{part} ({k})");
            }
            materials.push(material);
            let material = materials.len() - 1;
            split.push(Unplaced { entry: index, name: part, source: source.clone(), material, geometry });
        }
        return Ok(split);
    };
    let geometry = mesh::load_obj(&source, &transform).map_err(|p| obj_error(path, &source, index, p))?;
    Ok(vec![Unplaced { entry: index, name, source, material, geometry }])
}

/// Without `two_sided`, the meshes of a `[[meshes]]` entry split by its MTL materials (`entries`:
/// each mesh's entry) are one-sided where they are closed together, as one model.
fn close_split_entries(files: &[MeshFile], entries: &[usize], meshes: &mut [Mesh]) {
    let mut start = 0;
    while start < meshes.len() {
        let entry = entries[start];
        let end = start + entries[start..].iter().take_while(|&&e| e == entry).count();
        if files[entry].materials.is_some() && files[entry].two_sided.is_none() {
            let closed = adjacency::is_closed_together(&meshes[start..end]);
            meshes[start..end].iter_mut().for_each(|mesh| mesh.two_sided = !closed);
        }
        start = end;
    }
}

/// `problem` with the OBJ file `source` of `[[meshes]]` entry `index` of the scene at `path`.
fn obj_error(path: &Path, source: &Path, index: usize, problem: mesh::ObjProblem) -> SceneError {
    SceneError::Obj {
        path: source.to_path_buf(),
        line: problem.line,
        problem: problem.message,
        scene: path.to_path_buf(),
        mesh: index + 1,
    }
}

fn mesh_item<'a>(path: &'a Path, index: usize, m: &MeshFile) -> Item<'a> {
    Item { path, item: format!("[[meshes]] #{} (\"{}\")", index + 1, m.obj.display()) }
}

/// The [`Mesh`] of `unplaced` (of `[[meshes]]` entry `m`), placed relative to `origin`.
fn finish_mesh(
    path: &Path,
    m: &MeshFile,
    materials: &[Material],
    unplaced: Unplaced,
    origin: DVec3,
) -> Result<Mesh, SceneError> {
    let Unplaced { entry: index, name, source, material, geometry } = unplaced;
    let item = mesh_item(path, index, m);
    let loaded = geometry.place(origin).map_err(|p| obj_error(path, &source, index, p))?;
    let mut mesh = Mesh {
        name,
        source,
        material,
        positions: loaded.positions,
        normals: loaded.normals,
        indices: loaded.indices,
        uvs: loaded.uvs,
        two_sided: true,
    };
    mesh.two_sided = m.two_sided.unwrap_or_else(|| !adjacency::is_closed(&mesh));
    if let Some(projection) = m.uv_projection {
        let uv_scale = m.uv_scale.unwrap_or([1.0, 1.0]);
        if !uv_scale.iter().all(|s| s.is_finite() && *s != 0.0) {
            return Err(item.error(format!(
                "`uv_scale` = [{}, {}] must be finite and non-zero",
                uv_scale[0], uv_scale[1]
            )));
        }
        mesh::project_uvs(&mut mesh, projection, Vec2::from_array(uv_scale));
    } else if m.uv_scale.is_some() {
        return Err(item.error("`uv_scale` applies only with `uv_projection`"));
    }
    let maps = &materials[material].maps;
    if (maps.albedo.is_some() || maps.parameter.is_some()) && mesh.uvs.is_empty() {
        return Err(item.error(format!(
            "material \"{}\" is textured but {} has no texture coordinates (add `vt` lines or `uv_projection`)",
            materials[material].name,
            mesh.source.display()
        )));
    }
    Ok(mesh)
}
