//! Wavefront OBJ (`.obj`), read with the `tobj` crate.
//!
//! Only geometry is read: `v` positions and `f` faces (`f a b c`,
//! `f a/t b/t c/t`, `f a//n b//n c//n`, `f a/t/n ...`, negative indices
//! counting back from the last vertex). Polygons are split into a fan of
//! triangles around their first corner (`tobj`'s triangulation), which is
//! exact for convex planar polygons. Each `o` or `g` line starts a new
//! object; faces before the first one form an object named after the file
//! stem. Objects without faces are dropped. A vertex's optional `w` divides
//! its coordinates, as the format says. Texture coordinates, normals,
//! materials, lines (`l`) and points (`p`) are ignored. Each object gets its
//! own vertex list (the vertices its faces use, in the file's order), so two
//! objects never share a vertex, and an object of every vertex of the file
//! numbers them as the file does (less one).
//!
//! `tobj` reports neither the line nor the object of a problem, and a few of
//! its index computations can overflow on absurd input, so the text is first
//! checked line by line here: malformed `v`/`vt`/`vn`/`f` lines, coordinates
//! that are not finite numbers and face indices out of range are reported
//! with their line. Only the lines `tobj` needs (`v`, `vt`, `vn`, `f`, `o`,
//! `g`) are then handed to it, trimmed, without comments (a `#` starts one
//! anywhere on a line).

use std::path::Path;

use super::error::{MeshError, MeshErrorKind};
use super::text::{coordinate, lines, require_content, shown, stem_name, syntax};
use super::TriangleMesh;

/// Reads every object of an OBJ file as a triangle mesh.
///
/// Positions are in the file's units. `file` is used in error messages; its
/// stem names faces that precede any `o`/`g` line.
///
/// A tetrahedron from OBJ text, checked closed and turned outward (one of
/// its faces is wound inward), then made a gas body of the engine:
///
/// ```
/// use std::path::Path;
/// use sprung::{build, Gas, Vec3};
/// use sprung_io::mesh::{closed_surface, parse_obj, signed_volume};
///
/// let text = "\
/// o tet
/// v 0 0 0
/// v 1 0 0
/// v 0 1 0
/// v 0 0 1
/// f 1 3 2
/// f 1 2 4
/// f 1 4 3
/// f 2 4 3  # wound inward
/// ";
/// let file = Path::new("tet.obj");
/// let meshes = parse_obj(text, file).unwrap();
/// assert_eq!(meshes.len(), 1);
/// assert_eq!(meshes[0].name, "tet");
/// assert_eq!((meshes[0].positions.len(), meshes[0].triangles.len()), (4, 4));
///
/// let mesh = closed_surface(&meshes[0], file).unwrap();
/// assert!((signed_volume(&mesh.positions, &mesh.triangles) - 1.0 / 6.0).abs() < 1e-12);
///
/// let position = mesh.positions.iter().map(|&p| Vec3::from_array(p)).collect();
/// let mut body = build::surface(position, mesh.triangles, Default::default()).unwrap();
/// body.gas = Some(Gas::new(1.0, 0.0));
/// assert!(body.is_closed());
///
/// // A face naming a vertex the file lacks is refused at its line.
/// let error = parse_obj("v 0 0 0\nv 1 0 0\nf 1 2 7\n", file).unwrap_err();
/// assert_eq!(error.line, Some(3));
/// assert!(error.to_string().starts_with("tet.obj:3: "), "{error}");
/// ```
pub fn parse_obj(text: &str, file: &Path) -> Result<Vec<TriangleMesh>, MeshError> {
    require_content(text, file)?;
    let (geometry, faces) =
        prescan(text).map_err(|(kind, line)| MeshError::new(file, kind).at_line(line))?;

    // `tobj` gains fields under its optional features: keep the update syntax
    // so the code compiles whichever features are on.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _materials) = tobj::load_obj_buf(&mut geometry.as_bytes(), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| MeshError::new(file, MeshErrorKind::Obj(e.to_string())))?;

    let mut meshes = Vec::new();
    let mut object_faces = faces.iter();
    for model in models {
        let mesh = model.mesh;
        let triangles: Vec<[usize; 3]> = mesh
            .indices
            .chunks_exact(3)
            .filter_map(|t| match *t {
                [a, b, c] => Some([a as usize, b as usize, c as usize]),
                _ => None,
            })
            .collect();
        if triangles.is_empty() {
            continue;
        }
        let positions: Vec<[f64; 3]> = mesh
            .positions
            .chunks_exact(3)
            .filter_map(|p| match *p {
                [x, y, z] => Some([x, y, z]),
                _ => None,
            })
            .collect();
        let name = if model.name == "unnamed_object" {
            stem_name(file)
        } else {
            model.name
        };
        if let Some(bad) = positions.iter().flatten().find(|c| !c.is_finite()) {
            return Err(MeshError::new(
                file,
                MeshErrorKind::NonFinite {
                    value: bad.to_string(),
                },
            )
            .in_object(&name));
        }
        let mut mesh = TriangleMesh {
            name,
            positions,
            triangles,
        };
        if let Some(faces) = object_faces.next() {
            in_file_order(&mut mesh, faces);
        }
        meshes.push(mesh);
    }
    if meshes.is_empty() {
        return Err(MeshError::new(file, MeshErrorKind::NoMesh));
    }
    Ok(meshes)
}

/// An object's faces, each its vertices in the file's numbering (0-based).
type ObjectFaces = Vec<Vec<i64>>;

/// Element counts of the whole file, or seen so far.
#[derive(Default, Clone, Copy)]
struct Counts {
    v: usize,
    vt: usize,
    vn: usize,
}

/// Checks the lines `tobj` will read and returns them, trimmed, one per
/// line; an error comes with its 1-based line.
fn prescan(text: &str) -> Result<(String, Vec<ObjectFaces>), (MeshErrorKind, usize)> {
    // A `#` starts a comment to the end of its line, after a statement too
    // (`f 1 2 3 # top`), as exporters write them.
    let uncommented = |raw: &str| raw.split('#').next().unwrap_or("").to_owned();
    let mut total = Counts::default();
    for (_, raw) in lines(text) {
        let raw = uncommented(raw);
        match raw.split_whitespace().next() {
            Some("v") => total.v += 1,
            Some("vt") => total.vt += 1,
            Some("vn") => total.vn += 1,
            _ => {}
        }
    }
    let mut seen = Counts::default();
    let mut faces = 0usize;
    let mut geometry = String::with_capacity(text.len());
    // Per object (a new one at each `o` or `g` line), its faces' vertices
    // in the file's numbering (0-based).
    let mut objects: Vec<ObjectFaces> = vec![Vec::new()];
    for (line, raw) in lines(text) {
        let raw = uncommented(raw);
        let mut words = raw.split_whitespace();
        let keyword = words.next();
        let checked = match keyword {
            Some("v") => {
                seen.v += 1;
                vertex(words)
            }
            Some("vt") => {
                seen.vt += 1;
                numbers(words, 2, "a texture coordinate line (`vt u v`)")
            }
            Some("vn") => {
                seen.vn += 1;
                numbers(words, 3, "a normal line (`vn x y z`)")
            }
            Some("f") => {
                faces += 1;
                face(words, faces - 1, seen, total).map(|vertices| {
                    if let Some(object) = objects.last_mut() {
                        object.push(vertices);
                    }
                })
            }
            Some("o" | "g") => {
                objects.push(Vec::new());
                Ok(())
            }
            _ => continue,
        };
        checked.map_err(|kind| (kind, line))?;
        geometry.push_str(raw.trim());
        geometry.push('\n');
    }
    objects.retain(|faces| !faces.is_empty());
    Ok((geometry, objects))
}

/// Renumber `mesh`'s vertices (numbered by `tobj` in order of first use by
/// its faces) in the file's order, given its faces in the file's numbering:
/// a mesh of every vertex of the file then has them as the file lists
/// them, and `pinned`, `--probe` and the messages use the file's numbers
/// (less one). Left as it is if the faces do not give back `tobj`'s
/// triangles (a reading this does not foresee).
fn in_file_order(mesh: &mut TriangleMesh, faces: &[Vec<i64>]) {
    // The file's vertex of each of tobj's, in order of first use.
    let mut first_used: Vec<i64> = Vec::with_capacity(mesh.positions.len());
    let mut local = std::collections::HashMap::new();
    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    for face in faces {
        let mut corner = |v: i64| {
            *local.entry(v).or_insert_with(|| {
                first_used.push(v);
                first_used.len() - 1
            })
        };
        let first = corner(face[0]);
        let mut last = corner(face[1]);
        for &v in &face[2..] {
            let next = corner(v);
            triangles.push([first, last, next]);
            last = next;
        }
    }
    if triangles != mesh.triangles || first_used.len() != mesh.positions.len() {
        return;
    }
    let mut order: Vec<usize> = (0..first_used.len()).collect();
    order.sort_by_key(|&k| first_used[k]);
    let mut renumbered = vec![0; order.len()];
    for (new, &old) in order.iter().enumerate() {
        renumbered[old] = new;
    }
    mesh.positions = order.iter().map(|&old| mesh.positions[old]).collect();
    for triangle in &mut mesh.triangles {
        *triangle = triangle.map(|old| renumbered[old]);
    }
}

/// `v x y z [w]` or `v x y z r g b`.
fn vertex(words: std::str::SplitWhitespace<'_>) -> Result<(), MeshErrorKind> {
    let words: Vec<&str> = words.collect();
    let (xyz, extra) = words.split_at(words.len().min(3));
    let [x, y, z] = *xyz else {
        return Err(syntax(format!(
            "a vertex needs 3 coordinates, found {}",
            words.len()
        )));
    };
    let p = [coordinate(x)?, coordinate(y)?, coordinate(z)?];
    match *extra {
        [] => Ok(()),
        [w] => {
            let w_value = coordinate(w)?;
            if w_value == 0.0 {
                return Err(syntax("vertex weight w is 0"));
            }
            if p.iter().any(|c| !(c / w_value).is_finite()) {
                return Err(syntax(format!(
                    "dividing the vertex by its weight w = {} overflows",
                    shown(w)
                )));
            }
            Ok(())
        }
        [r, g, b] => {
            for c in [r, g, b] {
                c.parse::<f64>()
                    .map_err(|_| syntax(format!("expected a colour value, found {}", shown(c))))?;
            }
            Ok(())
        }
        _ => Err(syntax(format!(
            "a vertex has 3, 4 (x y z w) or 6 (x y z r g b) values, found {}",
            words.len()
        ))),
    }
}

/// At least `n` numbers (texture coordinates, normals: any value is kept as
/// it is, since only positions are used).
fn numbers(
    mut words: std::str::SplitWhitespace<'_>,
    n: usize,
    what: &str,
) -> Result<(), MeshErrorKind> {
    for _ in 0..n {
        let word = words
            .next()
            .ok_or_else(|| syntax(format!("{what} needs {n} numbers")))?;
        word.parse::<f64>()
            .map_err(|_| syntax(format!("{what}: expected a number, found {}", shown(word))))?;
    }
    Ok(())
}

/// `f` line number `face`: at least 3 corners `v`, `v/t`, `v//n` or `v/t/n`,
/// each index in range.
fn face(
    words: std::str::SplitWhitespace<'_>,
    face: usize,
    seen: Counts,
    total: Counts,
) -> Result<Vec<i64>, MeshErrorKind> {
    let mut corners = 0;
    // The corners' vertices (0-based), to refuse one listed twice.
    let mut vertices: Vec<i64> = Vec::new();
    for word in words {
        corners += 1;
        let mut parts = word.split('/');
        let v = parts.next().unwrap_or("");
        let t = parts.next().unwrap_or("");
        let n = parts.next().unwrap_or("");
        if parts.next().is_some() {
            return Err(syntax(format!(
                "face {face}: corner {} has more than 3 indices",
                shown(word)
            )));
        }
        if v.is_empty() {
            return Err(syntax(format!(
                "face {face}: corner {} has no vertex index",
                shown(word)
            )));
        }
        index(v, face, seen.v, total.v, "vertex", "vertices")?;
        // In range (checked just above): 1-based, or back from the last.
        let value: i64 = v.parse().unwrap_or(0);
        let vertex = if value > 0 {
            value - 1
        } else {
            seen.v as i64 + value
        };
        if vertices.contains(&vertex) {
            return Err(syntax(format!(
                "face {face}: vertex {} is listed twice (as {}); a face needs distinct vertices",
                vertex + 1,
                shown(word)
            )));
        }
        vertices.push(vertex);
        if !t.is_empty() {
            index(
                t,
                face,
                seen.vt,
                total.vt,
                "texture coordinate",
                "texture coordinates",
            )?;
        }
        if !n.is_empty() {
            index(n, face, seen.vn, total.vn, "normal", "normals")?;
        }
    }
    if corners < 3 {
        return Err(syntax(format!(
            "face {face} has {corners} corners; a face needs at least 3"
        )));
    }
    Ok(vertices)
}

/// One OBJ index: 1-based, or negative counting back from the last element
/// seen so far (`seen`); positive indices may point up to `total`.
fn index(
    word: &str,
    face: usize,
    seen: usize,
    total: usize,
    what: &str,
    plural: &str,
) -> Result<(), MeshErrorKind> {
    let value: i64 = word.parse().map_err(|_| {
        syntax(format!(
            "face {face}: expected a {what} index, found {}",
            shown(word)
        ))
    })?;
    let (in_range, available) = if value > 0 {
        (usize::try_from(value).is_ok_and(|v| v <= total), total)
    } else if value < 0 {
        (
            usize::try_from(value.unsigned_abs()).is_ok_and(|back| back <= seen),
            seen,
        )
    } else {
        return Err(syntax(format!(
            "face {face}: {what} index 0 (OBJ indices start at 1)"
        )));
    };
    if in_range {
        Ok(())
    } else if what == "vertex" {
        Err(MeshErrorKind::IndexOutOfRange {
            face,
            index: value,
            vertices: available,
        })
    } else {
        Err(syntax(format!(
            "face {face}: {what} index {value} out of range ({available} {plural})"
        )))
    }
}
