//! Tests of OBJ files as scenes: MTL materials, what stands aside with a warning, and the
//! errors that name the file and line.

use super::*;
use crate::scene::tests::TempDir;
use crate::scene::MaterialKind;

/// A closed octahedron of radius 1 around (10, 0, 0) whose eight faces use five materials:
/// the two `shiny` faces give normals, the others do not; only the `painted` faces have
/// texture coordinates; `usemtl chrome` names no material of the library.
const OCTAHEDRON: &str = "\
mtllib materials.mtl
v 11 0 0
v 9 0 0
v 10 1 0
v 10 -1 0
v 10 0 1
v 10 0 -1
vn 0.577 0.577 0.577
vt 0 0
vt 1 0
vt 0 1
o top
usemtl matte
f 1 3 5
f 3 2 5
usemtl shiny
f 2//1 3//1 6//1
f 3//1 1//1 6//1
usemtl metal
f 1 5 4
usemtl painted
f 5/1 2/2 4/3
f 2/1 6/2 4/3
usemtl chrome
f 6 1 4
";

const MATERIALS: &str = "\
# four materials, one of them textured
newmtl matte
Kd 0.6 0.5 0.4
Ks 0 0 0

newmtl shiny
Kd 0.2 0.3 0.8
Ks 0.5 0.5 0.5
Ns 200

newmtl metal
Kd 0.9 0.6 0.2
Pr 0.3
Pm 1

newmtl painted
Kd 1.5 1 1
map_Kd textures\\missing.png
d 0.5
";

fn material_named<'a>(scene: &'a Scene, name: &str) -> &'a Material {
    scene.materials.iter().find(|m| m.name == name).unwrap_or_else(|| panic!("no material {name}"))
}

fn warned(scene: &Scene, needles: &[&str]) {
    assert!(
        scene.warnings.iter().any(|w| needles.iter().all(|n| w.contains(n))),
        "no warning with {needles:?} among {:#?}",
        scene.warnings
    );
}

#[test]
fn an_obj_with_its_materials_is_a_scene() {
    let dir = TempDir::new("octahedron");
    dir.write("materials.mtl", MATERIALS);
    let path = dir.write("octahedron.obj", OCTAHEDRON);
    let scene = Scene::load(&path).unwrap();

    assert_eq!(scene.materials.len(), 5, "{:#?}", scene.materials);
    assert_eq!(material_named(&scene, "matte").kind, MaterialKind::Lambert { kd: Vec3::new(0.6, 0.5, 0.4) });
    assert_eq!(
        material_named(&scene, "shiny").kind,
        MaterialKind::BlinnPhong { kd: Vec3::new(0.2, 0.3, 0.8), ks: Vec3::splat(0.5), shininess: 200.0 }
    );
    let MaterialKind::Ggx { albedo, f0, roughness } = material_named(&scene, "metal").kind else {
        panic!("metal is not GGX: {:?}", material_named(&scene, "metal"));
    };
    assert_eq!((albedo, f0, roughness), (Vec3::ZERO, Vec3::new(0.9, 0.6, 0.2), 0.3));
    // The texture is missing: Kd alone, clamped, with warnings that say so.
    let painted = material_named(&scene, "painted");
    assert_eq!(painted.kind, MaterialKind::Lambert { kd: Vec3::ONE });
    assert!(painted.maps.albedo.is_none());
    warned(&scene, &["materials.mtl", "\"painted\"", "map_Kd", "missing.png"]);
    warned(&scene, &["\"painted\"", "clamped", "Kd"]);
    warned(&scene, &["\"painted\"", "transparency"]);
    assert_eq!(material_named(&scene, "default").kind, DEFAULT_MATERIAL);
    warned(&scene, &["octahedron.obj", "usemtl chrome"]);

    // One mesh per material, faces kept: 8 triangles of a closed model, so one-sided.
    assert_eq!(scene.meshes.len(), 5);
    assert_eq!(scene.triangle_count(), 8);
    for (index, mesh) in scene.meshes.iter().enumerate() {
        assert_eq!(mesh.material, index);
        assert!(!mesh.two_sided, "{} is two-sided", mesh.name);
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        assert!(mesh.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
    }
    let shiny = &scene.meshes[scene.materials.iter().position(|m| m.name == "shiny").unwrap()];
    assert!(shiny.normals.iter().all(|n| n.abs_diff_eq(Vec3::splat(0.577).normalize(), 1e-5)));
    let matte = &scene.meshes[0];
    assert!(
        matte.normals.iter().any(|n| !n.abs_diff_eq(Vec3::splat(0.577).normalize(), 1e-2)),
        "faces without normals get computed ones"
    );
    let painted_mesh = &scene.meshes[scene.materials.iter().position(|m| m.name == "painted").unwrap()];
    assert_eq!(painted_mesh.uvs.len(), painted_mesh.positions.len());

    // The camera sees every vertex inside its vertical field of view, from in front (+Z).
    let camera = scene.camera;
    let view = (camera.target - camera.eye).normalize();
    assert!(view.z < 0.0);
    for p in scene.meshes.iter().flat_map(|m| &m.positions) {
        let angle = view.angle_between(*p - camera.eye).to_degrees();
        assert!(angle < 0.5 * camera.fov_y_degrees, "{p} is {angle}° off the view direction");
        let depth = (*p - camera.eye).dot(view);
        assert!(camera.near < depth && depth < camera.far);
    }
    // Key and fill give the model's centre a fixed irradiance, and a directional light.
    let centre = camera.target;
    let irradiances: Vec<f32> = scene
        .lights
        .iter()
        .filter_map(|l| match *l {
            Light::Point { position, intensity, .. } => Some(intensity / position.distance_squared(centre)),
            _ => None,
        })
        .collect();
    assert_eq!(irradiances.len(), 2);
    assert!((irradiances[0] - 0.8).abs() < 1e-3 && (irradiances[1] - 0.25).abs() < 1e-3, "{irradiances:?}");
    assert!(scene.lights.iter().any(|l| matches!(l, Light::Directional { .. })));
    // Each casts shadows, the key's hard.
    let shadowed: Vec<(usize, u32)> = scene.shadow_casters.iter().map(|c| (c.light, c.filter)).collect();
    assert_eq!(shadowed, [(0, 1), (1, 3), (2, 3)]);
}

#[test]
fn textures_in_png_and_jpeg_load_and_need_texture_coordinates() {
    let dir = TempDir::new("textures");
    let texture = image::RgbImage::from_fn(4, 4, |x, y| image::Rgb([(60 * x) as u8, (60 * y) as u8, 128]));
    texture.save(dir.0.join("albedo.png")).unwrap();
    texture.save(dir.0.join("albedo.jpg")).unwrap();
    dir.write(
        "t.mtl",
        "newmtl png\nKd 1 1 1\nmap_Kd albedo.png\nnewmtl jpeg\nKd 1 1 1\nmap_Kd -bm 1 albedo.jpg\n",
    );
    let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
               usemtl png\nf 1/1 2/2 3/3\nusemtl jpeg\nf 2 4 3\n";
    let scene = Scene::load(&dir.write("t.obj", obj)).unwrap();
    let png = material_named(&scene, "png");
    assert_eq!(png.maps.albedo.as_ref().map(|t| (t.width(), t.height())), Some((4, 4)));
    // The JPEG decodes, but its faces have no `vt`: drawn without it, with a warning.
    assert!(material_named(&scene, "jpeg").maps.albedo.is_none());
    warned(&scene, &["t.obj", "\"jpeg\"", "no texture coordinates"]);
    assert!(scene.meshes[0].two_sided, "an open model is two-sided");
}

#[test]
fn a_missing_library_leaves_the_default_material_with_a_warning() {
    let dir = TempDir::new("no-mtl");
    let path = dir.write("lonely.obj", OCTAHEDRON);
    let scene = Scene::load(&path).unwrap();
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].kind, DEFAULT_MATERIAL);
    assert_eq!(scene.triangle_count(), 8);
    warned(&scene, &["lonely.obj", "materials.mtl", "default material"]);

    let bare = dir.write("bare.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    warned(&Scene::load(&bare).unwrap(), &["bare.obj", "no material library"]);
}

#[test]
fn bad_models_and_libraries_are_errors_naming_file_and_line() {
    let dir = TempDir::new("bad");
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let load = |mtl: &str| {
        dir.write("m.mtl", mtl);
        Scene::load(&dir.write("m.obj", obj)).unwrap_err().to_string()
    };
    let message = load("newmtl a\nKd 0.5 abc 0.2\n");
    assert!(
        message.contains("m.mtl") && message.contains("line 2") && message.contains("`abc`"),
        "{message}"
    );
    let message = load("newmtl a\n\nNs nan\n");
    assert!(
        message.contains("m.mtl") && message.contains("line 3") && message.contains("not finite"),
        "{message}"
    );
    let message = load("newmtl a\nKd 0.5 0.5\n");
    assert!(message.contains("line 2") && message.contains("three numbers"), "{message}");

    let message = Scene::load(&dir.0.join("absent.obj")).unwrap_err().to_string();
    assert!(message.contains("absent.obj") && message.contains("cannot read"), "{message}");
    let nan = dir.write("nan.obj", "v 0 0 0\nv 1 NaN 0\nv 0 1 0\nf 1 2 3\n");
    let message = Scene::load(&nan).unwrap_err().to_string();
    assert!(message.contains("nan.obj: line 2") && message.contains("non-finite"), "{message}");
    let points = dir.write("points.obj", "v 0 0 0\nv 1 0 0\np 1 2\n");
    let message = Scene::load(&points).unwrap_err().to_string();
    assert!(message.contains("points.obj") && message.contains("no triangles"), "{message}");
    let point = dir.write("point.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n");
    let message = Scene::load(&point).unwrap_err().to_string();
    assert!(message.contains("point.obj") && message.contains("one point"), "{message}");
}

#[test]
fn a_model_far_from_zero_is_recentred_with_its_camera() {
    let dir = TempDir::new("far");
    let obj = "v 1000000 1000000 1000000\nv 1000001 1000000 1000000\nv 1000000 1000001 1000000\nf 1 2 3\n";
    let scene = Scene::load(&dir.write("far.obj", obj)).unwrap();
    assert!(scene.origin.length() > 1.0e6);
    let positions = &scene.meshes[0].positions;
    assert!(positions.iter().all(|p| p.length() < 1.0), "{positions:?}");
    assert!((positions[1] - positions[0]).abs_diff_eq(Vec3::X, 1e-6));
    assert!(scene.camera.target.length() < 1.0);
}
