//! Tests of an OBJ file's own MTL materials in a scene file (`materials = "mtl"`): one mesh per
//! material used, with the entry's transform; the statements the renderer does not model named
//! once each; what stands aside as a warning and what is an error; and the shipped chapel.

use crate::scene::tests::TempDir;
use crate::scene::{MaterialKind, Scene};

use glam::Vec3;
use std::path::Path;

/// A unit square in the XZ plane cut into four quads, each of its own material, one with
/// texture coordinates running from -2 to 6 (its texture repeats); `usemtl chrome` names no
/// material of the library, `unused` is never used.
const TILES: &str = "\
mtllib tiles.mtl
v 0 0 0
v 0.5 0 0
v 1 0 0
v 0 0 0.5
v 0.5 0 0.5
v 1 0 0.5
v 0 0 1
v 0.5 0 1
v 1 0 1
vt -2 -2
vt 6 -2
vt 6 6
vt -2 6
usemtl matte
f 1/1 4/2 5/3 2/4
usemtl shiny
f 2/1 5/2 6/3 3/4
usemtl metal
f 4/1 7/2 8/3 5/4
usemtl chrome
f 5/1 8/2 9/3 6/4
";

const LIBRARY: &str = "\
newmtl matte
Kd 0.6 0.5 0.4
map_Kd checker.png
map_Ka checker.png
map_Bump -bm 0.5 bumps.png
d 1
Tr 0
Ke 0 0 0

newmtl shiny
Kd 0.2 0.3 0.8
Ks 0.5 0.5 0.5
Ns 200
map_Bump bumps.png
d 0.5

newmtl metal
Kd 0.9 0.6 0.2
Pr 0.3
Pm 1
map_ka checker.png
Ke 0.5 0 0

newmtl unused
Kd 1 1 1
disp heights.png
";

/// A scene file around `meshes` (its `[[meshes]]` tables) with a camera, a light and a path.
fn scene_with(meshes: &str) -> String {
    format!(
        "[camera]\neye = [0.5, 3, 2]\ntarget = [0.5, 0, 0.5]\nfov_y_degrees = 50\n\
         [[materials]]\nname = \"clay\"\ntype = \"lambert\"\nkd = [0.8, 0.8, 0.8]\n\
         {meshes}\
         [[lights]]\ntype = \"point\"\nposition = [0.5, 2, 0.5]\ncolor = [1, 1, 1]\nintensity = 3\n\
         [[path]]\ntime = 0\neye = [0.5, 3, 2]\ntarget = [0.5, 0, 0.5]\n\
         [[path]]\ntime = 2\neye = [2, 3, 0.5]\ntarget = [0.5, 0, 0.5]\n"
    )
}

/// A folder with the tiles, their library and the checker texture, and a scene file in it.
fn folder_with(name: &str, library: &str, meshes: &str) -> (TempDir, std::path::PathBuf) {
    let dir = TempDir::new(name);
    dir.write("tiles.obj", TILES);
    dir.write("tiles.mtl", library);
    image::RgbImage::from_fn(4, 4, |x, y| image::Rgb([(60 * x) as u8, (60 * y) as u8, 128]))
        .save(dir.0.join("checker.png"))
        .unwrap();
    let scene = dir.write("scene.toml", scene_with(meshes));
    (dir, scene)
}

fn warnings_with(scene: &Scene, needle: &str) -> usize {
    scene.warnings.iter().filter(|w| w.contains(needle)).count()
}

#[test]
fn a_mesh_entry_takes_its_obj_files_own_materials() {
    let meshes = "[[meshes]]\nobj = \"tiles.obj\"\nmaterials = \"mtl\"\nname = \"hall\"\n\
                  scale = 2\ntranslate = [10, 1, 0]\n\
                  [[meshes]]\nobj = \"tiles.obj\"\nmaterial = \"clay\"\nname = \"plain\"\n";
    let (dir, path) = folder_with("own", LIBRARY, meshes);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));

    // One mesh per material used, in the library's order and the default last, then the
    // entry with a named material.
    let names: Vec<&str> = scene.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["hall/matte", "hall/shiny", "hall/metal", "hall/default", "plain"]);
    let kinds: Vec<MaterialKind> = scene.meshes.iter().map(|m| scene.materials[m.material].kind).collect();
    assert!(matches!(kinds[0], MaterialKind::Lambert { kd } if kd == Vec3::new(0.6, 0.5, 0.4)));
    assert!(matches!(kinds[1], MaterialKind::BlinnPhong { shininess, .. } if shininess == 200.0));
    assert!(matches!(kinds[2], MaterialKind::Ggx { roughness, .. } if roughness == 0.3));
    assert_eq!(kinds[3], crate::scene::obj_scene::DEFAULT_MATERIAL);
    assert_eq!(kinds[4], MaterialKind::Lambert { kd: Vec3::splat(0.8) });
    assert_eq!(scene.materials.len(), 5, "clay and the four of the entry");
    assert_eq!(scene.materials[scene.meshes[0].material].name, "hall/matte");
    for mesh in &scene.meshes[..4] {
        assert_eq!(mesh.source, dir.0.join("tiles.obj"));
        assert_eq!(mesh.indices.len(), 6, "{}: one quad", mesh.name);
        assert!(mesh.two_sided, "{}: an open model is two-sided", mesh.name);
    }

    // The entry's transform: scaled by 2 and moved by (10, 1, 0).
    let (lo, hi) =
        crate::scene::bounds_of(scene.meshes[..4].iter().flat_map(|m| m.positions.iter().copied()));
    assert!(
        lo.abs_diff_eq(Vec3::new(10.0, 1.0, 0.0), 1e-5) && hi.abs_diff_eq(Vec3::new(12.0, 1.0, 2.0), 1e-5)
    );
    // The texture is kept, with its texture coordinates as written (from -2 to 6: repeating).
    let matte = &scene.meshes[0];
    assert_eq!(scene.materials[matte.material].maps.albedo.as_ref().map(|t| t.width()), Some(4));
    let (uv_lo, uv_hi) = matte
        .uvs
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), uv| (lo.min(uv.x.min(uv.y)), hi.max(uv.x.max(uv.y))));
    assert_eq!((uv_lo, uv_hi), (-5.0, 6.0), "u from -2 to 6, v = 1 - (-2 .. 6)");

    // Camera, lights and path are the scene file's.
    assert_eq!(scene.camera.eye, Vec3::new(0.5, 3.0, 2.0));
    assert_eq!(scene.lights.len(), 1);
    assert!(scene.camera_path.is_some());
    assert_eq!(warnings_with(&scene, "`usemtl chrome`"), 1, "{:#?}", scene.warnings);
}

#[test]
fn unmodelled_statements_are_named_once_each() {
    let meshes = "[[meshes]]\nobj = \"tiles.obj\"\nmaterials = \"mtl\"\n";
    let (dir, path) = folder_with("unmodelled", LIBRARY, meshes);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let obj = Scene::load(&dir.0.join("tiles.obj")).unwrap_or_else(|e| panic!("{e}"));
    for scene in [&scene, &obj] {
        // `map_Bump` in two materials and `map_Ka` (once written `map_ka`) in two: one warning
        // each, naming both materials; `d` below 1 and a `Ke` that glows: one each.
        for (key, materials) in [
            ("`map_Bump` (bump map)", &["\"matte\"", "\"shiny\""][..]),
            ("`map_Ka` (ambient map)", &["\"matte\"", "\"metal\""]),
            ("`d` (transparency)", &["\"shiny\""]),
            ("`Ke` (emission)", &["\"metal\""]),
        ] {
            let found: Vec<&String> = scene.warnings.iter().filter(|w| w.contains(key)).collect();
            assert_eq!(found.len(), 1, "{key}: {:#?}", scene.warnings);
            assert!(found[0].contains("tiles.mtl") && found[0].contains("not modelled"), "{}", found[0]);
            assert!(materials.iter().all(|m| found[0].contains(m)), "{}", found[0]);
        }
        // Opaque `d 1` and `Tr 0` and a black `Ke` change nothing; an unused material's
        // statements are not named.
        assert_eq!(warnings_with(scene, "`Tr`"), 0, "{:#?}", scene.warnings);
        assert_eq!(warnings_with(scene, "disp"), 0, "{:#?}", scene.warnings);
        assert_eq!(warnings_with(scene, "not modelled"), 4, "{:#?}", scene.warnings);
    }
}

#[test]
fn what_cannot_be_used_is_a_warning_not_an_error() {
    // No library at all: the default material, with a warning.
    let meshes = "[[meshes]]\nobj = \"tiles.obj\"\nmaterials = \"mtl\"\n";
    let (dir, path) = folder_with("missing", LIBRARY, meshes);
    std::fs::remove_file(dir.0.join("tiles.mtl")).unwrap();
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.materials[scene.meshes[0].material].kind, crate::scene::obj_scene::DEFAULT_MATERIAL);
    assert_eq!(warnings_with(&scene, "cannot read its material library"), 1, "{:#?}", scene.warnings);

    // A missing texture: the material without it, with a warning naming it.
    dir.write("tiles.mtl", LIBRARY.replace("map_Kd checker.png", "map_Kd textures\\absent.png"));
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.materials.iter().all(|m| m.maps.albedo.is_none()));
    assert_eq!(warnings_with(&scene, "absent.png"), 1, "{:#?}", scene.warnings);

    // A named material that is textured is still an error without texture coordinates; a
    // scene file whose meshes name their materials has no warnings.
    let plain = dir.write("plain.toml", scene_with("[[meshes]]\nobj = \"tiles.obj\"\nmaterial = \"clay\"\n"));
    assert!(Scene::load(&plain).unwrap().warnings.is_empty());
}

/// The error of loading the scene file `text` written beside the tiles.
fn error_of(name: &str, library: &str, meshes: &str) -> String {
    let (_dir, path) = folder_with(name, library, meshes);
    Scene::load(&path).map(|_| ()).unwrap_err().to_string()
}

#[test]
fn bad_entries_and_libraries_are_errors_naming_the_file() {
    let both = "[[meshes]]\nobj = \"tiles.obj\"\nmaterial = \"clay\"\nmaterials = \"mtl\"\n";
    let message = error_of("both", LIBRARY, both);
    assert!(
        message.contains("scene.toml")
            && message.contains("[[meshes]] #1 (\"tiles.obj\")")
            && message.contains("`material` and `materials`"),
        "{message}"
    );
    let message = error_of("neither", LIBRARY, "[[meshes]]\nobj = \"tiles.obj\"\n");
    assert!(message.contains("scene.toml") && message.contains("missing `material`"), "{message}");
    let message = error_of("other", LIBRARY, "[[meshes]]\nobj = \"tiles.obj\"\nmaterials = \"obj\"\n");
    assert!(message.contains("scene.toml") && message.contains("`mtl`"), "{message}");
    let projected = "[[meshes]]\nobj = \"tiles.obj\"\nmaterials = \"mtl\"\nuv_projection = \"planar\"\n";
    let message = error_of("projected", LIBRARY, projected);
    assert!(message.contains("[[meshes]] #1") && message.contains("`uv_projection`"), "{message}");

    // A malformed number in the library: the library, its line, and the entry that uses it.
    let entry = "[[meshes]]\nobj = \"tiles.obj\"\nmaterials = \"mtl\"\n";
    let message = error_of("number", &LIBRARY.replace("Kd 0.2 0.3 0.8", "Kd 0.2 abc 0.8"), entry);
    assert!(
        message.contains("tiles.mtl: line 11")
            && message.contains("`abc`")
            && message.contains("[[meshes]] #1")
            && message.contains("scene.toml"),
        "{message}"
    );
    let message = error_of("absent", LIBRARY, &entry.replace("tiles.obj", "absent.obj"));
    assert!(message.contains("absent.obj") && message.contains("cannot read"), "{message}");
}

#[test]
fn the_shipped_chapel_is_seen_from_inside_with_its_own_materials() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/chapel.toml");
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.materials.len() >= 3);
    assert!(scene.triangle_count() < 5_000, "{} triangles", scene.triangle_count());
    let kinds = |f: fn(&MaterialKind) -> bool| scene.materials.iter().filter(|m| f(&m.kind)).count();
    assert!(kinds(|k| matches!(k, MaterialKind::Lambert { .. })) > 0);
    assert!(kinds(|k| matches!(k, MaterialKind::BlinnPhong { .. })) > 0);
    assert!(kinds(|k| matches!(k, MaterialKind::Ggx { .. })) > 0);
    // A textured mesh whose texture coordinates run well outside [0, 1].
    let repeating = scene.meshes.iter().any(|m| {
        scene.materials[m.material].maps.albedo.is_some()
            && m.uvs.iter().any(|uv| uv.min_element() < -1.0)
            && m.uvs.iter().any(|uv| uv.max_element() > 2.0)
    });
    assert!(repeating, "no textured mesh repeats its texture");
    // The eye, every path key's eye and the lights are inside the model's bounds.
    let (lo, hi) = scene.bounds();
    let inside = |p: Vec3| p.cmpgt(lo).all() && p.cmplt(hi).all();
    assert!(inside(scene.camera.eye));
    let path = scene.camera_path.as_ref().expect("a path");
    for k in 0..=8 {
        let time = path.duration() * k as f32 / 8.0;
        let (eye, _) = path.eye_and_target((scene.camera.eye, scene.camera.target, scene.camera.up), time);
        assert!(inside(eye), "{eye} at {time} s");
    }
    for light in &scene.lights {
        let crate::scene::Light::Point { position, .. } = light else { panic!("{light:?}") };
        assert!(inside(*position), "{position}");
    }
    // Its library's unmodelled statements are named, each once.
    for key in ["`map_Ka`", "`map_Bump`", "`d`"] {
        assert_eq!(warnings_with(&scene, key), 1, "{key}: {:#?}", scene.warnings);
    }
}
