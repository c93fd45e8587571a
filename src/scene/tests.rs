//! Tests of scene loading: the schema, every kind of error, and the shipped scenes.

use super::*;
use glam::Vec2;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh folder under the system temporary folder, removed when dropped (also used by the
/// tests of OBJ files as scenes).
pub(in crate::scene) struct TempDir(pub(in crate::scene) PathBuf);

impl TempDir {
    pub(in crate::scene) fn new(name: &str) -> TempDir {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("multirate-scene-{}-{name}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    /// Writes `bytes` to `name` in the folder (creating its subfolders) and returns its path.
    pub(in crate::scene) fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

const QUAD_OBJ: &str = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 4 3 2\n";

const MINIMAL: &str = r#"
description = "one quad"
source = "written by the test"
[camera]
eye = [0, 1, 3]
target = [0, 0, 0]
fov_y_degrees = 45
[[materials]]
name = "clay"
type = "lambert"
kd = [0.8, 0.8, 0.8]
[[meshes]]
obj = "quad.obj"
material = "clay"
[[lights]]
type = "directional"
direction = [0, -2, 0]
color = [1, 1, 1]
intensity = 1.0
"#;

/// Writes `quad.obj` and a scene, and loads the scene.
fn load_text(dir: &TempDir, scene: &str) -> (PathBuf, Result<Scene, SceneError>) {
    dir.write("quad.obj", QUAD_OBJ);
    let path = dir.write("scene.toml", scene);
    let result = Scene::load(&path);
    (path, result)
}

/// Loads `scene` and asserts that it fails with a message that starts with the path of the
/// file at fault and contains every one of `needles`.
#[track_caller]
fn expect_error(scene: &str, needles: &[&str]) -> String {
    let dir = TempDir::new("err");
    let (path, result) = load_text(&dir, scene);
    let message = result.expect_err("the scene should not load").to_string();
    assert!(
        message.starts_with(&path.display().to_string()),
        "{message:?} does not start with {}",
        path.display()
    );
    for needle in needles {
        assert!(message.contains(needle), "{message:?} does not mention {needle:?}");
    }
    message
}

/// `MINIMAL` with `from` replaced by `to` (which must change it).
#[track_caller]
fn minimal_with(from: &str, to: &str) -> String {
    assert!(MINIMAL.contains(from), "{from:?}");
    MINIMAL.replacen(from, to, 1)
}

/// `source` is optional: a scene without it loads as one with it.
#[test]
fn source_is_optional() {
    let dir = TempDir::new("no_source");
    let with = load_text(&dir, MINIMAL).1.unwrap();
    let without = load_text(&dir, &minimal_with("source = \"written by the test\"\n", "")).1.unwrap();
    assert_eq!(without.description, with.description);
    assert_eq!(without.meshes.len(), with.meshes.len());
    assert_eq!(without.materials, with.materials);
}

/// `description` is optional too: without it the scene loads, its meshes and materials as with
/// it, and its description is empty.
#[test]
fn description_is_optional() {
    let dir = TempDir::new("no_description");
    let with = load_text(&dir, MINIMAL).1.unwrap();
    let without = load_text(&dir, &minimal_with("description = \"one quad\"\n", "")).1.unwrap();
    assert_eq!(with.description, "one quad");
    assert_eq!(without.description, "");
    assert_eq!(without.meshes.len(), 1);
    assert_eq!(without.meshes[0].indices.len(), 6, "the quad's two triangles");
    assert_eq!(without.meshes, with.meshes);
    assert_eq!(without.materials, with.materials);
    assert_eq!(without.camera, with.camera);
    // With neither `description` nor `source` the file still loads.
    let bare = minimal_with("description = \"one quad\"\nsource = \"written by the test\"\n", "");
    let bare = load_text(&dir, &bare).1.unwrap();
    assert_eq!(bare.meshes, with.meshes);
}

#[test]
fn minimal_scene_loads_with_defaults() {
    let dir = TempDir::new("minimal");
    let (path, result) = load_text(&dir, MINIMAL);
    let scene = result.unwrap();
    assert_eq!(scene.path, path);
    assert_eq!(scene.description, "one quad");
    assert_eq!(scene.settings, RenderSettings::default());
    assert_eq!(scene.settings.width, 1280);
    assert_eq!(scene.settings.epsilon, 0.075);
    assert_eq!(scene.settings.n_max, 16);
    assert_eq!(scene.camera.up, Vec3::Y);
    assert_eq!(scene.camera.eye, Vec3::new(0.0, 1.0, 3.0));
    assert_eq!(
        scene.materials,
        vec![Material {
            name: "clay".into(),
            kind: MaterialKind::Lambert { kd: Vec3::splat(0.8) },
            maps: Default::default()
        }]
    );
    assert_eq!(
        scene.lights,
        vec![Light::Directional { direction: -Vec3::Y, color: Vec3::ONE, intensity: 1.0 }]
    );
    assert_eq!(scene.meshes.len(), 1);
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.name, "quad");
    assert_eq!(mesh.source, dir.0.join("quad.obj"));
    assert_eq!(mesh.material, 0);
    assert_eq!(scene.triangle_count(), 2);
    assert_eq!(scene.bounds(), (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0)));
    for n in &mesh.normals {
        assert_eq!(*n, Vec3::Y);
    }
    // far: just past the farthest corner, (±1, 0, -1) from (0, 1, 3): √(1 + 1 + 16).
    let far = 18f32.sqrt() * 1.01;
    assert!((scene.camera.far - far).abs() < 1e-5, "{}", scene.camera.far);
    assert!((scene.camera.near - far * 1e-3).abs() < 1e-7, "{}", scene.camera.near);
}

#[test]
fn every_key_is_read() {
    let dir = TempDir::new("full");
    let scene = r#"
description = "all keys"
source = "test"
[camera]
eye = [0, 1, 3]
target = [0, 0, 0]
up = [0, 0, 2]
fov_y_degrees = 30.0
near = 0.5
far = 50
[render]
width = 640
height = 480
epsilon = 0.1
n_max = 8
exposure = 2.0
clear_color = [0.1, 0.2, 0.3]
[[materials]]
name = "shiny"
type = "blinn_phong"
kd = [0.5, 0.1, 0.1]
ks = [0.4, 0.4, 0.4]
shininess = 64.0
[[materials]]
name = "metal"
type = "ggx"
albedo = [0.1, 0.1, 0.1]
f0 = [0.9, 0.6, 0.3]
roughness = 0.3
[[meshes]]
obj = "quad.obj"
material = "metal"
name = "floor"
translate = [0, -1, 0]
rotate_degrees = [0, 90, 0]
scale = [2, 1, 3]
[[meshes]]
obj = "./quad.obj"
material = "shiny"
scale = 0.5
[[lights]]
type = "point"
position = [1, 1, 1]
color = [1, 0.5, 0]
intensity = 2
"#;
    let scene = load_text(&dir, scene).1.unwrap();
    assert_eq!(scene.camera.up, Vec3::Z);
    assert_eq!((scene.camera.near, scene.camera.far), (0.5, 50.0));
    assert_eq!(
        scene.settings,
        RenderSettings {
            width: 640,
            height: 480,
            epsilon: 0.1,
            n_max: 8,
            exposure: 2.0,
            clear_color: Vec3::new(0.1, 0.2, 0.3),
            light_sampling: LightSampling::default(),
        }
    );
    assert_eq!(
        scene.materials[0].kind,
        MaterialKind::BlinnPhong { kd: Vec3::new(0.5, 0.1, 0.1), ks: Vec3::splat(0.4), shininess: 64.0 }
    );
    assert_eq!(
        scene.materials[1].kind,
        MaterialKind::Ggx { albedo: Vec3::splat(0.1), f0: Vec3::new(0.9, 0.6, 0.3), roughness: 0.3 }
    );
    assert_eq!(
        scene.lights[0],
        Light::Point { position: Vec3::ONE, color: Vec3::new(1.0, 0.5, 0.0), intensity: 2.0 }
    );
    let floor = &scene.meshes[0];
    assert_eq!((floor.name.as_str(), floor.material), ("floor", 1));
    // x in ±2, z in ±3, then 90° about Y swaps them (x' = z, z' = -x), then down by 1.
    let (lo, hi) = bounds_of(floor.positions.iter().copied());
    assert!((lo - Vec3::new(-3.0, -1.0, -2.0)).length() < 1e-5, "{lo}");
    assert!((hi - Vec3::new(3.0, -1.0, 2.0)).length() < 1e-5, "{hi}");
    let small = &scene.meshes[1];
    assert_eq!((small.name.as_str(), small.material), ("quad", 0));
    assert_eq!(
        bounds_of(small.positions.iter().copied()),
        (Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 0.0, 0.5))
    );
    assert_eq!(scene.triangle_count(), 4);
}

#[test]
fn unknown_key_is_an_error_with_its_line() {
    let text = minimal_with("color = [1, 1, 1]", "colour = [1, 1, 1]");
    expect_error(
        &text,
        &["unknown field `colour`", "expected one of", "line 18, column 1: `colour = [1, 1, 1]`"],
    );
    expect_error(
        &minimal_with("fov_y_degrees = 45", "fov_y_degrees = 45\nfov = 3"),
        &["unknown field `fov`", "line 8, column 1: `fov = 3`"],
    );
    expect_error(&format!("{MINIMAL}\n[extra]\nx = 1\n"), &["unknown field `extra`"]);
}

#[test]
fn malformed_toml_is_an_error_with_its_line() {
    expect_error(&minimal_with("kd = [0.8, 0.8, 0.8]", "kd = [0.8, 0.8"), &["line 12"]);
    expect_error(
        &minimal_with("intensity = 1.0", "intensity = \"bright\""),
        &["intensity = \"bright\"", "line 19, column 13"],
    );
    expect_error(
        &minimal_with("kd = [0.8, 0.8, 0.8]", "kd = [0.8, 0.8]"),
        &["invalid length 2", "line 11", "kd = [0.8, 0.8]"],
    );
    expect_error(
        &minimal_with("type = \"directional\"", "type = \"spot\""),
        &["unknown variant `spot`", "line 16"],
    );
    expect_error(&minimal_with("fov_y_degrees = 45\n", ""), &["missing field `fov_y_degrees`"]);
    expect_error(
        &minimal_with("source = \"written by the test\"", "source = \" \""),
        &["`source`", "is empty"],
    );
    let text = minimal_with("material = \"clay\"", "material = \"clay\"\nscale = \"big\"");
    expect_error(&text, &["scale", "a number or an array of three numbers", "line 15"]);
    let text = minimal_with("material = \"clay\"", "material = \"clay\"\nscale = [1, 2, 3, 4]");
    expect_error(&text, &["invalid length 4", "line 15"]);
}

#[test]
fn missing_scene_file_is_an_error() {
    let dir = TempDir::new("missing");
    let path = dir.0.join("missing.toml");
    let message = Scene::load(&path).unwrap_err().to_string();
    assert!(message.starts_with(&path.display().to_string()), "{message}");
    assert!(message.contains("cannot read file"), "{message}");
    assert!(message.contains("No such file or directory") || message.contains("not found"), "{message}");
}

#[test]
fn missing_obj_is_an_error_naming_it() {
    let dir = TempDir::new("noobj");
    let path = dir.write("scene.toml", MINIMAL.replace("quad.obj", "nothing.obj"));
    let message = Scene::load(&path).unwrap_err().to_string();
    let obj = dir.0.join("nothing.obj");
    assert!(message.starts_with(&obj.display().to_string()), "{message}");
    assert!(message.contains("cannot read file"), "{message}");
    assert!(message.contains("[[meshes]] #1"), "{message}");
    assert!(message.contains(&path.display().to_string()), "the scene is named too: {message}");
}

#[test]
fn nan_coordinate_in_obj_is_an_error_naming_the_vertex() {
    let dir = TempDir::new("nan");
    dir.write("quad.obj", "# a comment\nv -1 0 -1\nv 1 0 -1\nv 1 NaN 1\nv -1 0 1\nf 1 4 3 2\n");
    let path = dir.write("scene.toml", MINIMAL);
    let error = Scene::load(&path).unwrap_err();
    let message = error.to_string();
    let obj = dir.0.join("quad.obj");
    assert!(message.starts_with(&obj.display().to_string()), "{message}");
    assert!(message.contains("vertex 3 has a non-finite coordinate (NaN)"), "{message}");
    assert!(message.contains("line 4"), "{message}");
    assert!(matches!(error, SceneError::Obj { line: Some(4), mesh: 1, .. }), "{error:?}");
}

#[test]
fn bad_obj_files_are_errors_naming_them() {
    for (obj, needle) in [
        ("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "vertex 3"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no triangles"),
        ("v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", "line 2"),
    ] {
        let dir = TempDir::new("badobj");
        dir.write("quad.obj", obj);
        let path = dir.write("scene.toml", MINIMAL);
        let message = Scene::load(&path).unwrap_err().to_string();
        assert!(message.starts_with(&dir.0.join("quad.obj").display().to_string()), "{message}");
        assert!(message.contains(needle), "{message}");
    }
}

#[test]
fn unknown_material_is_an_error() {
    expect_error(
        &minimal_with("material = \"clay\"", "material = \"steel\""),
        &["[[meshes]] #1", "material \"steel\" is not defined"],
    );
}

#[test]
fn duplicate_material_is_an_error() {
    let text = minimal_with(
        "[[meshes]]",
        "[[materials]]\nname = \"clay\"\ntype = \"lambert\"\nkd = [0, 0, 0]\n[[meshes]]",
    );
    expect_error(&text, &["[[materials]] #2", "duplicate material name \"clay\""]);
}

#[test]
fn out_of_range_values_are_errors_naming_the_key() {
    let cases: &[(&str, &str, &[&str])] = &[
        ("kd = [0.8, 0.8, 0.8]", "kd = [0.8, 1.5, 0.8]", &["[[materials]] #1 (\"clay\")", "`kd`", "[0, 1]"]),
        ("kd = [0.8, 0.8, 0.8]", "kd = [0.8, nan, 0.8]", &["`kd`", "not a finite number"]),
        ("kd = [0.8, 0.8, 0.8]", "kd = [0.8, 0.8, 0.8]\nroughness = 0.5", &["`roughness` does not apply"]),
        (
            "type = \"lambert\"\nkd = [0.8, 0.8, 0.8]",
            "type = \"ggx\"\nalbedo = [1, 1, 1]\nf0 = [0.04, 0.04, 0.04]\nroughness = 1.5",
            &["`roughness` = 1.5", "[0, 1]"],
        ),
        (
            "type = \"lambert\"\nkd = [0.8, 0.8, 0.8]",
            "type = \"ggx\"\nalbedo = [1, 1, 1]\nroughness = 0.5",
            &["missing `f0`"],
        ),
        (
            "type = \"lambert\"\nkd = [0.8, 0.8, 0.8]",
            "type = \"blinn_phong\"\nkd = [0, 0, 0]\nks = [1, 1, 1]\nshininess = 0.5",
            &["`shininess` = 0.5"],
        ),
        (
            "type = \"lambert\"\nkd = [0.8, 0.8, 0.8]",
            "type = \"blinn_phong\"\nkd = [0, 0, 0]\nks = [1, 1, 1]\nshininess = 20000",
            &["`shininess` = 20000"],
        ),
        ("fov_y_degrees = 45", "fov_y_degrees = 180", &["[camera]", "`fov_y_degrees` = 180", "(0, 180)"]),
        ("fov_y_degrees = 45", "fov_y_degrees = inf", &["`fov_y_degrees` = inf", "not a finite number"]),
        (
            "fov_y_degrees = 45",
            "fov_y_degrees = 45\nnear = 2\nfar = 1",
            &["`near` = 2 is not less than `far` = 1"],
        ),
        ("fov_y_degrees = 45", "fov_y_degrees = 45\nnear = 0", &["`near` = 0"]),
        ("fov_y_degrees = 45", "fov_y_degrees = 45\nnear = 10", &["`near` = 10 is not less than `far`"]),
        ("eye = [0, 1, 3]", "eye = [0, 0, 0]", &["`eye` and `target` are the same point"]),
        ("eye = [0, 1, 3]", "eye = [0, 3, 0]", &["`up`", "parallel"]),
        ("eye = [0, 1, 3]", "eye = [0, 1, 3]\nup = [0, 0, 0]", &["`up`", "zero"]),
        ("intensity = 1.0", "intensity = -1.0", &["[[lights]] #1 (directional)", "`intensity` = -1"]),
        ("color = [1, 1, 1]", "color = [1, -1, 1]", &["`color`", "outside [0, inf)"]),
        ("direction = [0, -2, 0]", "direction = [0, 0, 0]", &["`direction`", "zero"]),
        ("direction = [0, -2, 0]", "position = [0, -2, 0]", &["missing `direction`"]),
        (
            "direction = [0, -2, 0]",
            "direction = [0, -2, 0]\nposition = [0, 0, 0]",
            &["`position` does not apply"],
        ),
        (
            "type = \"directional\"\ndirection = [0, -2, 0]",
            "type = \"point\"\nposition = [0, 1e40, 0]",
            &["`position`", "not a finite number"],
        ),
        (
            "material = \"clay\"",
            "material = \"clay\"\nscale = [1, 0, 1]",
            &["[[meshes]] #1 (\"quad.obj\")", "`scale`", "zero"],
        ),
        ("material = \"clay\"", "material = \"clay\"\ntranslate = [1, nan, 1]", &["`translate`"]),
        ("material = \"clay\"", "material = \"clay\"\nrotate_degrees = [1, 2, -inf]", &["`rotate_degrees`"]),
        ("source = \"written by the test\"", "source = \" \"", &["`source`"]),
        ("name = \"clay\"", "name = \"\"", &["`name` is empty"]),
    ];
    for (from, to, needles) in cases {
        expect_error(&minimal_with(from, to), needles);
    }

    let render_cases: &[(&str, &[&str])] = &[
        ("width = 0", &["[render]", "`width` = 0", "1..=16384"]),
        ("height = 16385", &["`height` = 16385"]),
        ("epsilon = 0.0", &["`epsilon` = 0"]),
        ("n_max = 0", &["`n_max` = 0", "1..=64"]),
        ("n_max = 65", &["`n_max` = 65"]),
        ("exposure = -1", &["`exposure` = -1"]),
        ("clear_color = [0, 0, -0.5]", &["`clear_color`"]),
        ("width = -3", &["width", "line 5"]),
        ("polygon_samples = 0", &["`polygon_samples` = 0", "1..=256"]),
        ("mis_visibility = 1.5", &["`mis_visibility` = 1.5"]),
        ("polygon_sampling = \"area\"", &["polygon_sampling", "area"]),
    ];
    for (line, needles) in render_cases {
        let text = minimal_with("[camera]", &format!("[render]\n{line}\n[camera]"));
        expect_error(&text, needles);
    }
}

/// A polygonal light as the last light of [`MINIMAL`], with `vertices` and extra lines.
fn with_polygon(vertices: &str, extra: &str) -> String {
    format!("{MINIMAL}\n[[lights]]\ntype = \"polygon\"\nvertices = {vertices}\ncolor = [1, 1, 1]\nintensity = 4\n{extra}")
}

#[test]
fn polygon_lights_load_with_normal_area_and_sampling() {
    let dir = TempDir::new("polygon");
    // Anticlockwise seen from below: emits downwards.
    let text = format!(
        "{}\n[render]\npolygon_samples = 4\npolygon_sampling = \"solid_angle\"\nmis_visibility = 0.25\n",
        with_polygon("[[0, 2, 0], [1, 2, 0], [1, 2, 1], [0, 2, 1]]", "")
    );
    let scene = load_text(&dir, &text).1.unwrap();
    let Light::Polygon(light) = scene.lights[1] else { panic!("{:?}", scene.lights[1]) };
    assert_eq!(light.count, 4);
    assert!((light.normal - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-6, "{:?}", light.normal);
    assert!((light.area - 1.0).abs() < 1e-6);
    assert_eq!(light.radiance(), Vec3::splat(4.0));
    let sampling = LightSampling { samples: 4, technique: PolygonSampling::SolidAngle, mis_visibility: 0.25 };
    assert_eq!(light.sampling, sampling);
    assert_eq!(scene.settings.light_sampling, sampling);
    // The default far plane reaches the emitter.
    assert!(scene.camera.far > (Vec3::new(1.0, 2.0, 1.0) - scene.camera.eye).length());
}

#[test]
fn bad_polygon_lights_are_named() {
    let cases: &[(&str, &[&str])] = &[
        ("[[0, 2, 0], [1, 2, 0]]", &["[[lights]] #2 (polygon)", "`vertices`", "3 to 8 vertices, not 2"]),
        (
            "[[0,2,0],[1,2,0],[2,2,1],[2,2,2],[1,2,3],[0,2,3],[-1,2,2],[-1,2,1],[-0.5,2,0.2]]",
            &["3 to 8 vertices, not 9"],
        ),
        ("[[0, 2, 0], [1, 2, 0], [2, 2, 0]]", &["no area"]),
        ("[[0, 2, 0], [1, 2, 0], [1, 2.5, 1], [0, 2, 1]]", &["not planar", "vertex"]),
        ("[[0, 2, 0], [2, 2, 0], [1, 2, 0.5], [1, 2, 2]]", &["not convex at vertex"]),
        ("[[0, 2, 0], [1, 2, 0], [1, 2, 0], [0, 2, 1]]", &["not convex", "coincide"]),
        (
            "[[1, 2, 0], [0.309, 2, 0.951], [-0.809, 2, -0.588], [-0.809, 2, 0.588], [0.309, 2, -0.951]]",
            &["not convex"],
        ),
        ("[[0, 2, 0], [1, 2, nan], [0, 2, 1]]", &["`vertices`", "not a finite number"]),
    ];
    for (vertices, needles) in cases {
        expect_error(&with_polygon(vertices, ""), needles);
    }
    expect_error(
        &with_polygon("[[0, 2, 0], [1, 2, 0], [0, 2, 1]]", "position = [0, 0, 0]"),
        &["`position` does not apply"],
    );
    let point_with_vertices = MINIMAL.replace("[[lights]]", "[[lights]]\nvertices = [[0, 0, 0]]");
    expect_error(&point_with_vertices, &["`vertices` does not apply"]);
}

#[test]
fn a_scene_needs_a_mesh_and_a_light() {
    let no_lights = MINIMAL.split("[[lights]]").next().unwrap();
    expect_error(no_lights, &["`lights`", "no lights"]);
    let start = MINIMAL.find("[[meshes]]").unwrap();
    let end = MINIMAL.find("[[lights]]").unwrap();
    let no_meshes = format!("{}{}", &MINIMAL[..start], &MINIMAL[end..]);
    expect_error(&no_meshes, &["`meshes`", "no meshes"]);
}

#[test]
fn all_shipped_scenes_load() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut found = Vec::new();
    let mut folders = vec![root.clone()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "toml") {
                found.push(path);
            }
        }
    }
    found.sort();
    assert!(found.len() >= 6, "expected the shipped scenes under {}: {found:?}", root.display());
    for path in found {
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.triangle_count() > 0);
        for mesh in &scene.meshes {
            assert_eq!(mesh.positions.len(), mesh.normals.len());
            assert!(mesh.normals.iter().all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-5));
            assert!(mesh.indices.iter().all(|&i| (i as usize) < mesh.positions.len()));
        }
    }
}

/// The repository's `scenes/textures` folder, for scenes written to temporary folders.
fn shipped_texture(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/textures").join(name);
    path.display().to_string().replace('\\', "/")
}

#[test]
fn texture_problems_are_errors_naming_the_material_and_the_file() {
    let textured =
        |keys: &str| minimal_with("kd = [0.8, 0.8, 0.8]", &format!("kd = [0.8, 0.8, 0.8]\n{keys}"));
    let with_uv = |scene: String| {
        scene.replace("material = \"clay\"", "material = \"clay\"\nuv_projection = \"planar\"")
    };
    // A missing file names the key and the file.
    let message = expect_error(
        &with_uv(textured("kd_map = \"no_such.png\"")),
        &["[[materials]] #1", "kd_map", "no_such.png"],
    );
    assert!(message.contains("cannot read"), "{message}");
    // A file that is not a PNG.
    let dir = TempDir::new("garbage");
    dir.write("quad.obj", QUAD_OBJ);
    dir.write("garbage.png", "not a png");
    let path = dir.write("scene.toml", with_uv(textured("kd_map = \"garbage.png\"")));
    let message = Scene::load(&path).expect_err("garbage texture").to_string();
    assert!(message.contains("garbage.png") && message.contains("decode"), "{message}");
    // Maps and ranges come together and only on their own material type.
    let shiny = |keys: &str| {
        with_uv(minimal_with(
            "type = \"lambert\"\nkd = [0.8, 0.8, 0.8]",
            &format!("type = \"blinn_phong\"\nkd = [0.8, 0.8, 0.8]\nks = [0.2, 0.2, 0.2]\n{keys}"),
        ))
    };
    let map = shipped_texture("spots_shininess.png");
    expect_error(&shiny(&format!("shininess_map = \"{map}\"\nshininess = 8.0")), &["shininess_range"]);
    expect_error(&shiny("shininess_range = [2.0, 50.0]\nshininess = 8.0"), &["shininess_range", "shininess"]);
    expect_error(&shiny("shininess_range = [2.0, 50.0]"), &["shininess_range", "shininess_map"]);
    expect_error(
        &shiny(&format!("shininess_map = \"{map}\"\nshininess_range = [50.0, 2.0]")),
        &["shininess_range"],
    );
    expect_error(&shiny(&format!("roughness_map = \"{map}\"\nshininess = 8.0")), &["roughness_map"]);
    expect_error(&textured(&format!("shininess_map = \"{map}\"")), &["shininess_map", "lambert"]);
    // A parameter map must be a power of two (a 3×2 image).
    let dir = TempDir::new("npot");
    dir.write("quad.obj", QUAD_OBJ);
    image::GrayImage::from_pixel(3, 2, image::Luma([9])).save(dir.0.join("odd.png")).unwrap();
    let path = dir.write("scene.toml", shiny("shininess_map = \"odd.png\"\nshininess_range = [2.0, 50.0]"));
    let message = Scene::load(&path).expect_err("3×2 parameter map").to_string();
    assert!(message.contains("odd.png") && message.contains("power of two"), "{message}");
    // A textured material on a mesh without texture coordinates.
    let albedo = shipped_texture("spots_albedo.png");
    expect_error(&textured(&format!("kd_map = \"{albedo}\"")), &["texture coordinates", "quad.obj"]);
    // uv_scale needs uv_projection.
    expect_error(
        &minimal_with("material = \"clay\"", "material = \"clay\"\nuv_scale = [2, 2]"),
        &["uv_projection"],
    );
}

#[test]
fn textured_material_loads_with_its_maps() {
    let dir = TempDir::new("textured");
    let map = shipped_texture("spots_shininess.png");
    let scene = minimal_with(
        "type = \"lambert\"\nkd = [0.8, 0.8, 0.8]",
        &format!(
            "type = \"blinn_phong\"\nkd = [0.8, 0.8, 0.8]\nks = [0.2, 0.2, 0.2]\nshininess_map = \"{map}\"\nshininess_range = [4.0, 400.0]"
        ),
    )
    .replace("material = \"clay\"", "material = \"clay\"\nuv_projection = \"planar\"\nuv_scale = [3, 3]");
    let (_, result) = load_text(&dir, &scene);
    let scene = result.expect("textured scene loads");
    let map = scene.materials[0].maps.parameter.as_ref().expect("parameter map");
    assert_eq!(map.mapping, ParameterMapping::Exponential);
    assert_eq!(map.value(0.0), 4.0);
    assert!((map.value(1.0) - 400.0).abs() < 1e-2 && (map.value(0.5) - 40.0).abs() < 1e-2);
    // Planar uvs of the 2×2 quad, scaled by 3, span [0, 3].
    let uvs = &scene.meshes[0].uvs;
    assert_eq!(uvs.len(), scene.meshes[0].positions.len());
    let max = uvs.iter().fold(Vec2::ZERO, |a, b| a.max(*b));
    assert_eq!(max, Vec2::splat(3.0));
}

#[test]
fn cylindrical_uvs_have_no_triangle_across_the_seam() {
    let scene =
        Scene::load(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bunny_spots.toml"))).unwrap();
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.uvs.len(), mesh.positions.len());
    let mut seam_copies = 0;
    for t in mesh.indices.chunks_exact(3) {
        let us = [0, 1, 2].map(|k| mesh.uvs[t[k] as usize].x / 2.0);
        let span = us.iter().fold(f32::MIN, |a, &b| a.max(b)) - us.iter().fold(f32::MAX, |a, &b| a.min(b));
        // The shortest way around the axis: one turn less the largest gap between corners.
        let mut around = us.map(|u| u.rem_euclid(1.0));
        around.sort_by(f32::total_cmp);
        let gap = (around[1] - around[0]).max(around[2] - around[1]).max(around[0] + 1.0 - around[2]);
        assert!((span - (1.0 - gap)).abs() < 1e-4, "a triangle spans {span} turns, {} would do", 1.0 - gap);
        seam_copies += us.iter().filter(|&&u| u > 1.0).count();
    }
    assert!(seam_copies > 0, "the bunny's back crosses the seam, so some corners continue past u = 1");
    // The copies keep the surface connected for the adjacency (welded by position): the bunny
    // is closed, so no edge may be left without a neighbour (a patch naming itself across it).
    let patches = adjacency::adjacency_patches(mesh);
    for patch in patches.chunks_exact(adjacency::PATCH_SIZE) {
        for edge in 0..3 {
            assert_ne!(&patch[3 + 3 * edge..6 + 3 * edge], &patch[0..3], "an edge lost its neighbour");
        }
    }
}

#[test]
fn closed_meshes_default_to_one_sided_and_open_ones_to_two_sided() {
    let dir = TempDir::new("sides");
    let (_, quad) = load_text(&dir, MINIMAL);
    assert!(quad.expect("quad").meshes[0].two_sided, "an open quad shows both faces");
    // A tetrahedron: every edge shared by two triangles.
    dir.write("tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    let tetra = minimal_with("obj = \"quad.obj\"", "obj = \"tetra.obj\"");
    let (_, closed) = load_text(&dir, &tetra);
    assert!(!closed.expect("tetrahedron").meshes[0].two_sided, "a closed mesh hides its back faces");
    let forced = minimal_with("obj = \"quad.obj\"", "obj = \"tetra.obj\"\ntwo_sided = true");
    let (_, forced) = load_text(&dir, &forced);
    assert!(forced.expect("tetrahedron, two-sided").meshes[0].two_sided);
    let shipped = Scene::load(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bunny.toml"))).unwrap();
    assert!(!shipped.meshes[0].two_sided, "the bunny is closed");
}

/// A light's `shadow` table: defaults, the settings kept, the light it belongs to.
#[test]
fn shadow_tables_load_with_their_defaults() {
    let dir = TempDir::new("shadow");
    let plain = load_text(&dir, MINIMAL).1.unwrap();
    assert!(plain.shadow_casters.is_empty());
    let hard = load_text(&dir, &minimal_with("intensity = 1.0", "intensity = 1.0\nshadow = {}")).1.unwrap();
    let expected = ShadowCaster { light: 0, resolution: ShadowCaster::DEFAULT_RESOLUTION, filter: 1 };
    assert_eq!(hard.shadow_casters, [expected]);
    let text = format!(
        "{}\n[[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\ncolor = [1, 1, 1]\nintensity = 1\nshadow = {{ resolution = 256, filter = 5 }}\n",
        MINIMAL
    );
    let second = load_text(&dir, &text).1.unwrap();
    assert_eq!(second.shadow_casters, [ShadowCaster { light: 1, resolution: 256, filter: 5 }]);
}

#[test]
fn bad_shadow_tables_are_named() {
    let cases: &[(&str, &[&str])] = &[
        ("shadow = { filter = 2 }", &["[[lights]] #1 `shadow`", "`filter` = 2", "odd"]),
        ("shadow = { filter = 11 }", &["`filter` = 11"]),
        ("shadow = { resolution = 8 }", &["`resolution` = 8", "16..=4096"]),
        ("shadow = { resolution = 100000 }", &["`resolution` = 100000"]),
        ("shadow = { size = 3 }", &["unknown field `size`"]),
    ];
    for (table, needles) in cases {
        expect_error(&minimal_with("intensity = 1.0", &format!("intensity = 1.0\n{table}")), needles);
    }
    let point = "\n[[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\ncolor = [1, 1, 1]\nintensity = 1\nshadow = {}\n";
    let casters = ShadowCaster::MAX_LIGHTS + 1;
    let crowded = format!(
        "{}{}",
        minimal_with("intensity = 1.0", "intensity = 1.0\nshadow = {}"),
        point.repeat(casters - 1)
    );
    expect_error(&crowded, &["`lights`", &format!("{casters} lights cast shadows"), "at most 4"]);
    expect_error(
        &with_polygon("[[0, 2, 0], [1, 2, 0], [0, 2, 1]]", "shadow = {}"),
        &["[[lights]] #2 `shadow`", "polygonal lights cast no shadows"],
    );
}

const PATH: &str = "\n[[path]]\ntime = 0\neye = [0, 1, 3]\ntarget = [0, 0, 0]\n[[path]]\ntime = 2.5\neye = [3, 1, 0]\ntarget = [0, 0.5, 0]\n";

#[test]
fn a_camera_path_loads_through_its_keys() {
    let dir = TempDir::new("path");
    assert_eq!(load_text(&dir, MINIMAL).1.unwrap().camera_path, None);
    let scene = load_text(&dir, &format!("{MINIMAL}{PATH}")).1.unwrap();
    let path = scene.camera_path.expect("the path");
    assert_eq!(path.duration(), 2.5);
    let (eye, target) = path.eye_and_target((scene.camera.eye, scene.camera.target, scene.camera.up), 2.5);
    assert_eq!((eye, target), (Vec3::new(3.0, 1.0, 0.0), Vec3::new(0.0, 0.5, 0.0)));
}

#[test]
fn bad_camera_paths_are_named() {
    let one_key = PATH.split("[[path]]").take(2).collect::<Vec<_>>().join("[[path]]");
    expect_error(&format!("{MINIMAL}{one_key}"), &["[[path]] #1", "at least two keys"]);
    let backwards = PATH.replace("time = 2.5", "time = 0");
    expect_error(&format!("{MINIMAL}{backwards}"), &["[[path]] #2", "`time` = 0", "not after"]);
    let meets = PATH.replace("eye = [3, 1, 0]", "eye = [0, 0.5, 0]");
    expect_error(&format!("{MINIMAL}{meets}"), &["[[path]] #1", "the eye meets the target"]);
    let upwards = PATH
        .replace("eye = [3, 1, 0]", "eye = [0, 5, 0]")
        .replace("target = [0, 0.5, 0]", "target = [0, 0, 0]");
    expect_error(&format!("{MINIMAL}{upwards}"), &["[[path]] #1", "looks along `up`"]);
    expect_error(&format!("{MINIMAL}{}", PATH.replace("time = 0\n", "")), &["missing field `time`"]);
    expect_error(
        &format!("{MINIMAL}{}", PATH.replace("target = [0, 0, 0]", "target = [0, nan, 0]")),
        &["[[path]] #1", "`target`"],
    );
}
