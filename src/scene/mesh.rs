//! OBJ loading for [`super::Scene`]: reads a Wavefront OBJ file through `tobj`, checks it,
//! applies the mesh transform and produces finite, unit-length vertex normals.
//!
//! The file is scanned once before `tobj` sees it, so that the problems a person is most likely
//! to make (a non-finite coordinate, a face index of 0 or past the end, a face with fewer than
//! three corners) are reported with the vertex number and line, and so that no input can reach
//! the index arithmetic inside `tobj` that would overflow.

use std::collections::HashMap;
use std::io::{BufRead, Read};
use std::path::Path;

use glam::{DVec3, Mat3, Vec2, Vec3};

/// The mesh transform from a `[[meshes]]` entry: scale, then rotation (Euler angles in degrees,
/// about X, then Y, then Z), then translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Transform {
    pub scale: Vec3,
    pub rotate_degrees: Vec3,
    /// In f64, so that a mesh placed far from the world origin keeps its precision.
    pub translate: DVec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform { scale: Vec3::ONE, rotate_degrees: Vec3::ZERO, translate: DVec3::ZERO }
    }
}

impl Transform {
    /// The rotation part, `Rz · Ry · Rx` (so X is applied first).
    fn rotation(&self) -> Mat3 {
        let r = self.rotate_degrees;
        Mat3::from_rotation_z(r.z.to_radians())
            * Mat3::from_rotation_y(r.y.to_radians())
            * Mat3::from_rotation_x(r.x.to_radians())
    }

    /// Whether the transform mirrors space (an odd number of negative scale factors).
    fn mirrors(&self) -> bool {
        self.scale.x * self.scale.y * self.scale.z < 0.0
    }
}

/// Where geometry with bounds `lo..=hi` (f64) is measured from: its centre where that lies
/// farther from zero than the bounds' diagonal, so that f32 coordinates relative to it keep the
/// precision of geometry near zero (a floating origin); zero otherwise, which keeps geometry
/// already around zero exactly as written.
pub(crate) fn recentring_origin(lo: DVec3, hi: DVec3) -> DVec3 {
    let centre = (lo + hi) * 0.5;
    if lo.cmple(hi).all() && centre.length() > (hi - lo).length() {
        centre
    } else {
        DVec3::ZERO
    }
}

/// An OBJ file's geometry with the mesh transform applied, before it is placed relative to
/// the scene's origin: positions in f32 relative to `anchor`, a world point in f64, so that a
/// mesh far from the world origin keeps its precision until the scene's origin is known.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TransformedMesh {
    local: Vec<Vec3>,
    anchor: DVec3,
    /// Per position: the file's normal, transformed, where it gives a non-zero one.
    given_normals: Vec<Option<Vec3>>,
    indices: Vec<u32>,
    uvs: Vec<Vec2>,
}

impl TransformedMesh {
    /// World-space bounds, f64.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let (lo, hi) = self
            .local
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        (self.anchor + lo.as_dvec3(), self.anchor + hi.as_dvec3())
    }

    /// Whether every vertex has texture coordinates.
    pub fn has_uvs(&self) -> bool {
        !self.uvs.is_empty()
    }

    /// The geometry with positions relative to `origin` (world, f64), in f32, and a unit normal
    /// per position: the file's where it gives one, else smooth normals of the placed positions.
    pub fn place(self, origin: DVec3) -> Result<LoadedMesh, ObjProblem> {
        let offset = self.anchor - origin;
        let mut positions = Vec::with_capacity(self.local.len());
        for (i, p) in self.local.iter().enumerate() {
            let placed = (p.as_dvec3() + offset).as_vec3();
            if !placed.is_finite() {
                return Err(ObjProblem::new(format!(
                    "vertex {} is too far from the scene's origin for f32 coordinates",
                    i + 1
                )));
            }
            positions.push(placed);
        }
        let computed = if self.given_normals.iter().any(Option::is_none) {
            smooth_normals(&positions, &self.indices)
        } else {
            Vec::new()
        };
        let normals = self
            .given_normals
            .into_iter()
            .enumerate()
            .map(|(i, n)| n.unwrap_or_else(|| computed[i]))
            .collect();
        Ok(LoadedMesh { positions, normals, indices: self.indices, uvs: self.uvs })
    }
}

/// Geometry of one OBJ file relative to the scene's origin, ready for [`super::Mesh`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LoadedMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
    /// One per position where every object of the file has texture coordinates, else empty.
    /// `v` is flipped (OBJ's origin is bottom-left, Vulkan's top-left).
    pub uvs: Vec<Vec2>,
}

/// Why an OBJ file could not be used; the caller adds the file's path.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ObjProblem {
    /// 1-based line of the OBJ file the problem is on, where one line is to blame.
    pub line: Option<usize>,
    pub message: String,
}

impl ObjProblem {
    pub(crate) fn new(message: impl Into<String>) -> Self {
        ObjProblem { line: None, message: message.into() }
    }

    pub(crate) fn at(line: usize, message: impl Into<String>) -> Self {
        ObjProblem { line: Some(line), message: message.into() }
    }
}

/// Reads, checks, triangulates and transforms the OBJ file at `path`.
pub(crate) fn load_obj(path: &Path, transform: &Transform) -> Result<TransformedMesh, ObjProblem> {
    let bytes =
        super::file::read_file(path).map_err(|e| ObjProblem::new(format!("cannot read file: {e}")))?;
    load_obj_bytes(&bytes, transform)
}

/// [`load_obj`] on the contents of a file. Material libraries are never opened.
pub(crate) fn load_obj_bytes(bytes: &[u8], transform: &Transform) -> Result<TransformedMesh, ObjProblem> {
    let (models, _materials) = parse_obj(bytes, &|_| Err(tobj::LoadError::OpenFileFailed))?;
    assemble(&models.iter().collect::<Vec<_>>(), transform)
}

/// An OBJ file's objects and the materials of its libraries (or why none could be read).
pub(crate) type ParsedObj = (Vec<tobj::Model>, Result<Vec<tobj::Material>, tobj::LoadError>);

/// The objects of an OBJ file as `tobj` reads them (one per object and material, triangulated,
/// one index per corner), after the pre-scan, and what `material_loader` made of the file's
/// `mtllib` lines.
pub(crate) fn parse_obj(
    bytes: &[u8],
    material_loader: &dyn Fn(&Path) -> tobj::MTLLoadResult,
) -> Result<ParsedObj, ObjProblem> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        ObjProblem::at(super::file::first_non_utf8_line(bytes, &e), "is not valid UTF-8 text")
    })?;
    prescan(text)?;

    // `..Default::default()` covers the fields that `tobj` has only with some of its features.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let mut reader = LineCountingReader::new(bytes);
    // The pre-scan keeps out the inputs known to make `tobj` panic; this is a second guard so
    // that no file can take the program down.
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        tobj::load_obj_buf(&mut reader, &options, material_loader)
    }));
    match result {
        Ok(Ok(parsed)) => Ok(parsed),
        Ok(Err(e)) => Err(describe_tobj_error(e, reader.current_line())),
        Err(_) => Err(ObjProblem::new("the OBJ parser failed on this file")),
    }
}

/// One mesh of `models` (objects of one file), with `transform` applied. Texture coordinates
/// are kept where every one of `models` has them.
pub(crate) fn assemble(
    models: &[&tobj::Model],
    transform: &Transform,
) -> Result<TransformedMesh, ObjProblem> {
    let mut positions = Vec::new();
    // Per vertex: the file's normal for it, where the file gives every vertex of its object one.
    let mut given_normals: Vec<Option<Vec3>> = Vec::new();
    let mut indices = Vec::new();
    let mut uvs = Vec::new();
    let mut all_have_uvs = true;
    for model in models {
        let m = &model.mesh;
        let base = positions.len();
        let count = m.positions.len() / 3;
        let has_normals = m.normals.len() == m.positions.len();
        let has_uvs = m.texcoords.len() == 2 * count;
        all_have_uvs &= has_uvs;
        for v in 0..count {
            positions.push(DVec3::from_slice(&m.positions[3 * v..3 * v + 3]));
            given_normals
                .push(has_normals.then(|| DVec3::from_slice(&m.normals[3 * v..3 * v + 3]).as_vec3()));
            if has_uvs {
                let uv = Vec2::new(m.texcoords[2 * v] as f32, 1.0 - m.texcoords[2 * v + 1] as f32);
                if !uv.is_finite() {
                    return Err(ObjProblem::new(format!(
                        "object \"{}\" has a texture coordinate that is not finite",
                        model.name
                    )));
                }
                uvs.push(uv);
            }
        }
        for &i in &m.indices {
            if i as usize >= count {
                return Err(ObjProblem::new(format!(
                    "object \"{}\" has a face referring to a vertex that does not exist",
                    model.name
                )));
            }
            let global = u32::try_from(base + i as usize)
                .map_err(|_| ObjProblem::new("has more than 2^32 vertices"))?;
            indices.push(global);
        }
    }
    // Triangulation always gives whole triangles; this keeps a short index list harmless anyway.
    indices.truncate(indices.len() / 3 * 3);
    if indices.is_empty() {
        return Err(ObjProblem::new("contains no triangles (no `f` lines with 3 or more vertices)"));
    }

    if !all_have_uvs {
        uvs.clear();
    }
    // Coordinates far from the file's zero are kept relative to its centre (f64) from here on.
    let (lo, hi) =
        positions.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let centre = recentring_origin(lo, hi);
    let relative = positions.iter().map(|p| (*p - centre).as_vec3()).collect();
    finish(relative, centre, indices, uvs, &given_normals, transform)
}

/// Applies `transform` to the positions (relative to the file's point `centre`) and the given
/// normals, and keeps triangles front-facing under a mirroring transform.
fn finish(
    relative: Vec<Vec3>,
    centre: DVec3,
    mut indices: Vec<u32>,
    uvs: Vec<Vec2>,
    given_normals: &[Option<Vec3>],
    transform: &Transform,
) -> Result<TransformedMesh, ObjProblem> {
    let rotation = transform.rotation();
    let mut local = Vec::with_capacity(relative.len());
    for (i, p) in relative.iter().enumerate() {
        let moved = rotation * (*p * transform.scale);
        if !moved.is_finite() {
            return Err(ObjProblem::new(format!(
                "vertex {} ({}) is not finite after the mesh transform",
                i + 1,
                fmt_vec(*p)
            )));
        }
        local.push(moved);
    }
    let anchor = transform.translate + rotation.as_dmat3() * (centre * transform.scale.as_dvec3());
    if !anchor.is_finite() {
        return Err(ObjProblem::new("is not finite after the mesh transform"));
    }
    if transform.mirrors() {
        for tri in indices.chunks_exact_mut(3) {
            tri.swap(1, 2);
        }
    }

    // Normals transform with the inverse transpose, R · S⁻¹ for M = R · S.
    let inverse_scale = transform.scale.recip();
    let mut normals: Vec<Option<Vec3>> = given_normals
        .iter()
        .map(|n| {
            n.and_then(|n| {
                let world = (rotation * (n * inverse_scale)).normalize_or_zero();
                (world != Vec3::ZERO && world.is_finite()).then_some(world)
            })
        })
        .collect();
    normals.resize(local.len(), None);
    Ok(TransformedMesh { local, anchor, given_normals: normals, indices, uvs })
}

/// Smooth, area-weighted vertex normals. Vertices at exactly the same position are welded first,
/// so seams in the source data (split vertices) do not show. A vertex whose weighted sum is about
/// zero (it touches only degenerate faces, or faces that cancel) takes the normal of its largest
/// adjacent non-degenerate face, or +Z where there is none. Every result is finite and unit
/// length. Degenerate triangles are kept: they add nothing to the sums.
pub(crate) fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    // Weld: one group per distinct position (-0.0 and 0.0 are the same position).
    let mut group_of_position: HashMap<[u32; 3], usize> = HashMap::with_capacity(positions.len());
    let group: Vec<usize> = positions
        .iter()
        .map(|p| {
            let key = [(p.x + 0.0).to_bits(), (p.y + 0.0).to_bits(), (p.z + 0.0).to_bits()];
            let next = group_of_position.len();
            *group_of_position.entry(key).or_insert(next)
        })
        .collect();
    let groups = group_of_position.len();

    // In f64, so that neither very large nor very small coordinates overflow or vanish.
    let mut sum = vec![DVec3::ZERO; groups];
    let mut weight = vec![0.0f64; groups];
    // The largest adjacent non-degenerate face: (twice its area, its unit normal).
    let mut largest: Vec<Option<(f64, DVec3)>> = vec![None; groups];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| positions.get(i as usize).map(|p| p.as_dvec3()));
        let (Some(a), Some(b), Some(c)) = (a, b, c) else {
            continue;
        };
        let cross = (b - a).cross(c - a);
        let area2 = cross.length();
        if !(area2 > 0.0 && area2.is_finite()) {
            continue;
        }
        let unit = cross / area2;
        for &i in tri {
            let g = group[i as usize];
            sum[g] += cross;
            weight[g] += area2;
            if largest[g].is_none_or(|(best, _)| area2 > best) {
                largest[g] = Some((area2, unit));
            }
        }
    }

    let group_normal: Vec<Vec3> = (0..groups)
        .map(|g| {
            let length = sum[g].length();
            let smooth = (length > 1e-6 * weight[g]).then(|| (sum[g] / length).as_vec3());
            let candidate = smooth.or_else(|| largest[g].map(|(_, n)| n.as_vec3()));
            candidate
                .map(Vec3::normalize_or_zero)
                .filter(|n| *n != Vec3::ZERO && n.is_finite())
                .unwrap_or(Vec3::Z)
        })
        .collect();
    group.iter().map(|&g| group_normal[g]).collect()
}

/// Checks what `tobj` leaves unchecked or reports without a line: non-finite coordinates, face
/// indices of 0 or outside the file, faces with fewer than three vertices.
fn prescan(text: &str) -> Result<(), ObjProblem> {
    let lines = || text.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l));
    let mut totals = [0usize; 3]; // v, vt, vn
    for line in lines() {
        match line.split_whitespace().next() {
            Some("v") => totals[0] += 1,
            Some("vt") => totals[1] += 1,
            Some("vn") => totals[2] += 1,
            _ => {}
        }
    }

    let mut seen = [0usize; 3];
    for (number, line) in lines().enumerate().map(|(i, l)| (i + 1, l)) {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                seen[0] += 1;
                check_vertex(seen[0], number, words)?;
            }
            Some("vt") => seen[1] += 1,
            Some("vn") => {
                seen[2] += 1;
                let values: Vec<f32> = words.take(3).filter_map(|w| w.parse().ok()).collect();
                if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
                    return Err(ObjProblem::at(
                        number,
                        format!("normal {} has a non-finite coordinate ({bad})", seen[2]),
                    ));
                }
            }
            Some("f") => check_face(number, words, &seen, &totals)?,
            _ => {}
        }
    }
    Ok(())
}

fn check_vertex<'a>(
    vertex: usize,
    line: usize,
    mut words: impl Iterator<Item = &'a str>,
) -> Result<(), ObjProblem> {
    let xyz: Vec<Option<f32>> = words.by_ref().take(3).map(|w| w.parse().ok()).collect();
    let rest: Vec<&str> = words.collect();
    if xyz.len() < 3 || xyz.iter().any(Option::is_none) {
        return Ok(()); // `tobj` reports this as a parse error, with the line.
    }
    let xyz = Vec3::new(xyz[0].unwrap_or(0.0), xyz[1].unwrap_or(0.0), xyz[2].unwrap_or(0.0));
    if let Some(bad) = xyz.to_array().into_iter().find(|v| !v.is_finite()) {
        return Err(ObjProblem::at(line, format!("vertex {vertex} has a non-finite coordinate ({bad})")));
    }
    // `v x y z w`: `tobj` divides by w.
    if let [w] = rest[..] {
        if let Ok(w) = w.parse::<f32>() {
            if !w.is_finite() || (w != 0.0 && !(xyz / w).is_finite()) {
                return Err(ObjProblem::at(
                    line,
                    format!("vertex {vertex} has a weight w = {w} that makes it non-finite"),
                ));
            }
        }
    }
    Ok(())
}

fn check_face<'a>(
    line: usize,
    words: impl Iterator<Item = &'a str>,
    seen: &[usize; 3],
    totals: &[usize; 3],
) -> Result<(), ObjProblem> {
    const WHAT: [(&str, &str); 3] =
        [("vertex", "vertices"), ("texture coordinate", "texture coordinates"), ("normal", "normals")];
    let corners: Vec<&str> = words.collect();
    if corners.len() < 3 {
        return Err(ObjProblem::at(
            line,
            format!("face has {} vertices; a polygon needs at least 3", corners.len()),
        ));
    }
    for corner in corners {
        let parts: Vec<&str> = corner.split('/').collect();
        if parts.len() > 3 || parts[0].is_empty() {
            return Err(ObjProblem::at(
                line,
                format!("face corner `{corner}` is not `v`, `v/vt`, `v//vn` or `v/vt/vn`"),
            ));
        }
        for (kind, part) in parts.iter().enumerate().filter(|(_, p)| !p.is_empty()) {
            let Ok(index) = part.parse::<i64>() else {
                return Err(ObjProblem::at(
                    line,
                    format!("face corner `{corner}` has an index that is not a valid integer"),
                ));
            };
            let (what, plural) = WHAT[kind];
            let valid = match index {
                0 => false,
                // Relative: counts back from the last one defined so far.
                i if i < 0 => i.unsigned_abs() <= seen[kind] as u64,
                // Absolute: `tobj` resolves them once the whole file is read.
                i => i as u64 <= totals[kind] as u64,
            };
            if !valid {
                return Err(ObjProblem::at(
                    line,
                    format!(
                        "face refers to {what} {index}, but the file defines {} {plural}{}",
                        if index < 0 { seen[kind] } else { totals[kind] },
                        if index < 0 { " before this line" } else { "" },
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn describe_tobj_error(error: tobj::LoadError, line: usize) -> ObjProblem {
    use tobj::LoadError as E;
    let at = |message: &str| ObjProblem::at(line, message.to_string());
    match error {
        E::ReadError => at("cannot read this line"),
        E::UnrecognizedCharacter => at("unrecognised character"),
        E::PositionParseError => at("malformed vertex (`v`) line: expected 3 numbers"),
        E::ScalingByZeroError => at("vertex has a weight w of 0"),
        E::ColorParseError => at("malformed vertex colour: expected 3 numbers after the position"),
        E::NormalParseError => at("malformed normal (`vn`) line: expected 3 numbers"),
        E::TexcoordParseError => at("malformed texture coordinate (`vt`) line: expected 2 numbers"),
        E::FaceParseError => at("malformed face (`f`) line"),
        E::InvalidObjectName => at("malformed object (`o`) or group (`g`) name"),
        E::InvalidPolygon => at("face has fewer than 3 vertices"),
        E::FaceVertexOutOfBounds => ObjProblem::new("a face refers to a vertex that does not exist"),
        E::FaceTexCoordOutOfBounds => {
            ObjProblem::new("a face refers to a texture coordinate that does not exist")
        }
        E::FaceNormalOutOfBounds => ObjProblem::new("a face refers to a normal that does not exist"),
        E::FaceColorOutOfBounds => {
            ObjProblem::new("vertex colours are given for some vertices but not for others")
        }
        other => ObjProblem::new(format!("cannot be parsed: {other}")),
    }
}

/// A reader over the file's bytes that counts the lines `tobj` has taken, to put a line number
/// on its parse errors.
struct LineCountingReader<'a> {
    rest: &'a [u8],
    newlines: usize,
    after_newline: bool,
}

impl<'a> LineCountingReader<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        LineCountingReader { rest: bytes, newlines: 0, after_newline: true }
    }

    /// The 1-based number of the line read last.
    fn current_line(&self) -> usize {
        if self.after_newline {
            self.newlines.max(1)
        } else {
            self.newlines + 1
        }
    }
}

impl Read for LineCountingReader<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.rest.len());
        buf[..n].copy_from_slice(&self.rest[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl BufRead for LineCountingReader<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        Ok(self.rest)
    }

    fn consume(&mut self, amount: usize) {
        let (taken, rest) = self.rest.split_at(amount.min(self.rest.len()));
        if let Some(&last) = taken.last() {
            self.newlines += taken.iter().filter(|&&b| b == b'\n').count();
            self.after_newline = last == b'\n';
        }
        self.rest = rest;
    }
}

fn fmt_vec(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// Computes texture coordinates from world-space positions (see [`super::UvProjection`]),
/// scaled by `scale`. A triangle whose corners' `u` spans more than half a turn is cut where
/// its corners are farthest apart around the axis: the corners before the cut get their own
/// vertices with `u + 1` (positions and normals are copied, so the adjacency, which welds by
/// position, still sees one surface), so every triangle takes its shortest way around.
pub(crate) fn project_uvs(
    mesh: &mut super::model::Mesh,
    projection: super::schema::UvProjection,
    scale: Vec2,
) {
    use super::schema::UvProjection as P;
    let (lo, hi) = super::model::bounds_of(mesh.positions.iter().copied());
    let centre = (lo + hi) * 0.5;
    let extent = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    let turn = |d: Vec3| (d.x.atan2(d.z) / std::f32::consts::TAU + 0.5).clamp(0.0, 1.0);
    let raw: Vec<Vec2> = mesh
        .positions
        .iter()
        .map(|&p| {
            let d = p - centre;
            match projection {
                P::Cylindrical => Vec2::new(turn(d), (hi.y - p.y) / extent.y),
                P::Spherical => {
                    let r = d.length();
                    let polar = if r > 0.0 { (d.y / r).clamp(-1.0, 1.0).acos() } else { 0.0 };
                    Vec2::new(turn(d), polar / std::f32::consts::PI)
                }
                P::Planar => {
                    let side = extent.x.max(extent.z);
                    Vec2::new((p.x - lo.x) / side, (p.z - lo.z) / side)
                }
            }
        })
        .collect();
    mesh.uvs = raw.clone();
    if projection != P::Planar {
        let mut copies: HashMap<u32, u32> = HashMap::new();
        for t in 0..mesh.indices.len() / 3 {
            let corners = [0, 1, 2].map(|k| mesh.indices[3 * t + k]);
            let us = corners.map(|i| raw[i as usize].x);
            let (lo, hi) = (us[0].min(us[1]).min(us[2]), us[0].max(us[1]).max(us[2]));
            if hi - lo <= 0.5 {
                continue;
            }
            // Cut the circle at the largest gap between the corners' u: the corners below the
            // cut continue past 1, which gives the triangle its shortest span.
            let mut sorted = us;
            sorted.sort_by(f32::total_cmp);
            let gaps = [sorted[1] - sorted[0], sorted[2] - sorted[1], sorted[0] + 1.0 - sorted[2]];
            let cut = if gaps[2] >= gaps[0].max(gaps[1]) {
                continue;
            } else if gaps[1] >= gaps[0] {
                sorted[2]
            } else {
                sorted[1]
            };
            for (k, &i) in corners.iter().enumerate() {
                if raw[i as usize].x < cut {
                    let copy = *copies.entry(i).or_insert_with(|| {
                        mesh.positions.push(mesh.positions[i as usize]);
                        mesh.normals.push(mesh.normals[i as usize]);
                        mesh.uvs.push(raw[i as usize] + Vec2::X);
                        (mesh.positions.len() - 1) as u32
                    });
                    mesh.indices[3 * t + k] = copy;
                }
            }
        }
    }
    for uv in &mut mesh.uvs {
        *uv *= scale;
    }
}

#[cfg(test)]
mod tests;
