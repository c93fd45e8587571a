use super::*;

fn load(text: &str) -> Result<LoadedMesh, ObjProblem> {
    placed(text.as_bytes(), &Transform::default())
}

/// Loaded and placed at the world origin.
fn placed(bytes: &[u8], transform: &Transform) -> Result<LoadedMesh, ObjProblem> {
    load_obj_bytes(bytes, transform)?.place(DVec3::ZERO)
}

fn assert_unit(n: Vec3) {
    assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-6, "not unit: {n}");
}

#[test]
fn flat_quad_normals_are_exactly_z_and_unit() {
    let mesh = load("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    assert_eq!(mesh.indices.len(), 6, "the quad is split into two triangles");
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    for n in &mesh.normals {
        assert_eq!(*n, Vec3::Z);
    }
    // The same quad wound the other way faces -Z.
    let mesh = load("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 4 3 2 1\n").unwrap();
    for n in &mesh.normals {
        assert_eq!(*n, -Vec3::Z);
    }
}

#[test]
fn welded_cube_corner_normals_are_averaged() {
    // Three unit faces of a cube meeting at the origin, each with its own copy of the corner
    // (as in a file with per-face vertices), all facing outward (-X, -Y, -Z).
    let obj = "\
v 0 0 0\nv 0 1 0\nv 0 1 1\nv 0 0 1\n\
v 0 0 0\nv 0 0 1\nv 1 0 1\nv 1 0 0\n\
v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
f 1 4 3 2\nf 5 8 7 6\nf 9 12 11 10\n";
    let mesh = load(obj).unwrap();
    let expected = Vec3::splat(-1.0).normalize();
    let corners: Vec<usize> =
        (0..mesh.positions.len()).filter(|&i| mesh.positions[i] == Vec3::ZERO).collect();
    assert_eq!(corners.len(), 3, "each face keeps its own corner vertex");
    for i in corners {
        assert!((mesh.normals[i] - expected).length() < 1e-6, "{}", mesh.normals[i]);
        assert_unit(mesh.normals[i]);
    }
}

#[test]
fn degenerate_triangles_get_finite_unit_normals() {
    // Triangle 1 is fine; triangle 2 is a sliver on a line, sharing a vertex with it;
    // triangle 3 is a point, alone.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 3 0 0\nv 5 5 5\nf 1 2 3\nf 2 4 5\nf 6 6 6\n";
    let mesh = load(obj).unwrap();
    assert_eq!(mesh.indices.len(), 9, "degenerate triangles are kept");
    for n in &mesh.normals {
        assert_unit(*n);
    }
    let at = |p: Vec3| mesh.positions.iter().position(|q| *q == p).unwrap();
    assert_eq!(mesh.normals[at(Vec3::new(3.0, 0.0, 0.0))], Vec3::Z, "no good face: +Z");
    assert_eq!(mesh.normals[at(Vec3::new(5.0, 5.0, 5.0))], Vec3::Z, "isolated: +Z");
    assert_eq!(mesh.normals[at(Vec3::new(1.0, 0.0, 0.0))], Vec3::Z, "from the good face");

    // Two faces that cancel exactly (a two-sided sheet) take one face's normal.
    let mesh = load("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n").unwrap();
    for n in &mesh.normals {
        assert_unit(*n);
        assert_eq!(n.z.abs(), 1.0);
    }
}

#[test]
fn given_normals_use_the_inverse_transpose() {
    // A 45° slope in XY: its normal (-1, 1, 0)/√2. Stretching X by 2 makes the slope
    // shallower, so the normal tilts towards +Y: (-1/2, 1, 0) normalised.
    let obj = "v 0 0 0\nv 1 1 0\nv 0 1 1\nvn -1 1 0\nf 1//1 2//1 3//1\n";
    let t = Transform { scale: Vec3::new(2.0, 1.0, 1.0), ..Default::default() };
    let mesh = placed(obj.as_bytes(), &t).unwrap();
    let expected = Vec3::new(-0.5, 1.0, 0.0).normalize();
    for n in &mesh.normals {
        assert!((*n - expected).length() < 1e-6, "{n}");
    }
    assert_eq!(mesh.positions[1], Vec3::new(2.0, 1.0, 0.0));
}

#[test]
fn transform_order_is_scale_rotate_translate() {
    let t = Transform {
        scale: Vec3::splat(2.0),
        rotate_degrees: Vec3::new(0.0, 0.0, 90.0),
        translate: DVec3::new(10.0, 0.0, 0.0),
    };
    let mesh = placed(b"v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n", &t).unwrap();
    // (1,0,0) → scaled (2,0,0) → rotated 90° about Z (0,2,0) → translated (10,2,0).
    assert!((mesh.positions[0] - Vec3::new(10.0, 2.0, 0.0)).length() < 1e-5);
    // X then Y: (1,0,0) → Rx keeps it → Ry(90°) sends it to (0,0,-1).
    let t = Transform { rotate_degrees: Vec3::new(90.0, 90.0, 0.0), ..Default::default() };
    let mesh = placed(b"v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n", &t).unwrap();
    assert!((mesh.positions[0] - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
    // (0,1,0) → Rx(90°) → (0,0,1) → Ry(90°) → (1,0,0).
    assert!((mesh.positions[1] - Vec3::new(1.0, 0.0, 0.0)).length() < 1e-6);
}

#[test]
fn mirroring_keeps_computed_normals_outward() {
    let quad = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    let t = Transform { scale: Vec3::new(-1.0, 1.0, 1.0), ..Default::default() };
    let mesh = placed(quad, &t).unwrap();
    for n in &mesh.normals {
        assert_eq!(*n, Vec3::Z);
    }
    // And the winding seen from +Z is still counter-clockwise.
    let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[mesh.indices[k] as usize]);
    assert!((b - a).cross(c - a).z > 0.0);
}

#[test]
fn coordinates_far_from_zero_keep_their_precision() {
    // f32 spacing at 10⁶ is 0.0625: read and transformed in f32, these millimetre offsets
    // would vanish. Kept relative to the file's centre (f64) and placed at the scene's
    // origin, they survive to within f32 rounding near zero.
    let obj = b"v 1000000.001 1000000 1000000\nv 1000000 1000000.002 1000000\nv 1000000 1000000 1000000.003\nf 1 2 3\n";
    let t = Transform { translate: DVec3::new(-2.0e6, 0.0, 0.0), ..Default::default() };
    let transformed = load_obj_bytes(obj, &t).unwrap();
    let (lo, hi) = transformed.bounds();
    assert!((lo - DVec3::new(-1.0e6, 1.0e6, 1.0e6)).length() < 1e-6, "{lo}");
    assert!((hi - lo - DVec3::new(0.001, 0.002, 0.003)).length() < 1e-9, "{hi} - {lo}");
    let origin = recentring_origin(lo, hi);
    assert_eq!(origin, (lo + hi) * 0.5);
    let mesh = transformed.place(origin).unwrap();
    let p = &mesh.positions;
    assert!((p[1] - p[0] - Vec3::new(-0.001, 0.002, 0.0)).length() < 1e-8, "{:?}", p);
    assert!((p[2] - p[0] - Vec3::new(-0.001, 0.0, 0.003)).length() < 1e-8, "{:?}", p);
    // The smooth normals come from the placed positions: the triangle's own, (1/2, 1/3, 1/6)·k.
    let expected = Vec3::new(6.0, 3.0, 2.0).normalize();
    assert!(mesh.normals.iter().all(|n| (*n - expected).length() < 1e-5), "{:?}", mesh.normals);
    // Geometry around zero is never moved.
    assert_eq!(recentring_origin(DVec3::new(-1.0, 0.5, -1.0), DVec3::new(1.0, 2.0, 1.0)), DVec3::ZERO);
}

#[test]
fn bad_files_are_errors_with_lines_not_panics() {
    let cases: &[(&str, &str, Option<usize>)] = &[
        ("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", "vertex 3 has a non-finite coordinate (NaN)", Some(3)),
        ("v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n", "vertex 2 has a non-finite coordinate (inf)", Some(2)),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "vertex 0", Some(4)),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "vertex 4", Some(4)),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "vertex -4", Some(4)),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//0 3//1\n", "normal 0", Some(5)),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//99999999999999999 2 3\n", "normal", Some(4)),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "at least 3", Some(4)),
        ("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", "malformed vertex", Some(2)),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "not a valid integer", Some(4)),
        ("v 0 0 0\nv 1 0 0 0\nv 0 1 0\nf 1 2 3\n", "weight", Some(2)),
        ("v 0 0 0\n", "no triangles", None),
        ("", "no triangles", None),
        ("# only points\nv 0 0 0\np 1\nl 1 1\n", "no triangles", None),
    ];
    for (obj, expected, line) in cases {
        let problem = load(obj).expect_err(obj);
        assert!(problem.message.contains(expected), "{obj:?}: {problem:?}");
        assert_eq!(problem.line, *line, "{obj:?}: {problem:?}");
    }
    let problem = load_obj_bytes(b"v 0 0 0\n\xff\xfe\n", &Transform::default()).unwrap_err();
    assert_eq!(problem.line, Some(2));
}

#[test]
fn objects_are_concatenated_and_normals_kept_or_filled() {
    let obj = "\
o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nf 1//1 2//1 3//1\n\
o b\nv 0 0 5\nv 1 0 5\nv 0 1 5\nf 4 5 6\n";
    let mesh = load(obj).unwrap();
    assert_eq!(mesh.indices.len(), 6);
    assert_eq!(mesh.positions.len(), 6);
    let z0: Vec<Vec3> = (0..6).filter(|&i| mesh.positions[i].z == 0.0).map(|i| mesh.normals[i]).collect();
    let z5: Vec<Vec3> = (0..6).filter(|&i| mesh.positions[i].z == 5.0).map(|i| mesh.normals[i]).collect();
    assert!(z0.iter().all(|n| *n == -Vec3::Z), "the file's normals are used: {z0:?}");
    assert!(z5.iter().all(|n| *n == Vec3::Z), "missing normals are computed: {z5:?}");
    for &i in &mesh.indices {
        assert!((i as usize) < mesh.positions.len());
    }
}

#[test]
fn line_counting_reader_counts() {
    let mut r = LineCountingReader::new(b"a\nb\nc");
    let mut s = String::new();
    r.read_line(&mut s).unwrap();
    assert_eq!(r.current_line(), 1);
    r.read_line(&mut s).unwrap();
    assert_eq!(r.current_line(), 2);
    r.read_line(&mut s).unwrap();
    assert_eq!(r.current_line(), 3);
}
