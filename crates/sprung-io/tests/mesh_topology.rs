//! Topology checks: volume by the divergence theorem, closedness,
//! orientation repair, and the edges and bending pairs a body is built from.

mod common;

use common::mesh_path;

use std::path::{Path, PathBuf};

use sprung_io::mesh::{
    bending_pairs, closed_surface, edge_report, load_mesh_file, select_object, signed_volume,
    unique_edges, MeshErrorKind, TriangleMesh,
};

fn load_one(name: &str) -> (TriangleMesh, PathBuf) {
    let path = mesh_path(name);
    let meshes = load_mesh_file(&path).unwrap_or_else(|e| panic!("{e}"));
    let mesh = select_object(meshes, None, &path).unwrap_or_else(|e| panic!("{e}"));
    (mesh, path)
}

fn mesh(name: &str, positions: &[[f64; 3]], triangles: &[[usize; 3]]) -> TriangleMesh {
    TriangleMesh {
        name: name.to_owned(),
        positions: positions.to_vec(),
        triangles: triangles.to_vec(),
    }
}

fn volume(m: &TriangleMesh) -> f64 {
    signed_volume(&m.positions, &m.triangles)
}

fn flipped(triangles: &[[usize; 3]]) -> Vec<[usize; 3]> {
    triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
}

/// The corner tetrahedron (0, e1, e2, e3), faces wound outward.
fn tetrahedron() -> TriangleMesh {
    mesh(
        "tetra",
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
}

/// The regular octahedron with vertices ±e_i: 0 = +x, 1 = -x, 2 = +y,
/// 3 = -y, 4 = +z, 5 = -z; faces wound outward.
fn octahedron() -> TriangleMesh {
    mesh(
        "octa",
        &[
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ],
        &[
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ],
    )
}

#[test]
fn tetrahedron_and_octahedron_volumes_are_exact() {
    // Corner tetrahedron: 1/6. Octahedron |x|+|y|+|z| ≤ 1: 4/3. Coordinates
    // are 0 and ±1, so the triple products are exact integers; the only
    // rounding is the final division by 6 (relative 1.1e-16).
    assert!((volume(&tetrahedron()) - 1.0 / 6.0).abs() < 1e-15);
    assert!((volume(&octahedron()) - 4.0 / 3.0).abs() < 1e-15);
}

#[test]
fn volume_of_a_closed_surface_does_not_depend_on_the_origin() {
    // The divergence theorem gives the enclosed volume wherever the origin
    // is. Shifts by integers keep every coordinate an exact small integer,
    // so the products are exact and the volumes agree to the last bit.
    let (cube, _) = load_one("cube.asc");
    let shifted: Vec<[f64; 3]> = cube
        .positions
        .iter()
        .map(|p| [p[0] + 1000.0, p[1] - 500.0, p[2] + 3.0])
        .collect();
    assert_eq!(signed_volume(&shifted, &cube.triangles), 8.0);
}

#[test]
fn a_mesh_with_every_triangle_flipped_comes_back_outward() {
    for name in ["cube.asc", "spot_low_resolution.obj", "sphere_low.off"] {
        let (original, path) = load_one(name);
        let inside_out = TriangleMesh {
            triangles: flipped(&original.triangles),
            ..original.clone()
        };
        // Swapping two corners negates every triple product exactly
        // (b×c = -(c×b) bit for bit), so the inside-out volume is exactly
        // the negated original.
        assert_eq!(volume(&inside_out), -volume(&original), "{name}");
        let repaired = closed_surface(&inside_out, &path).unwrap_or_else(|e| panic!("{e}"));
        // Flipping every triangle back restores the original winding, and
        // with it the original volume, exactly.
        assert_eq!(repaired.triangles, original.triangles, "{name}");
        assert!(volume(&repaired) > 0.0);
        assert_eq!(volume(&repaired), volume(&original), "{name}");
    }
}

#[test]
fn inconsistently_oriented_triangles_are_made_consistent() {
    for name in ["cube.asc", "sphere.obj", "icosahedron_ascii.stl"] {
        let (original, path) = load_one(name);
        // Flip every third triangle: the surface is no longer consistently
        // oriented, and its signed volume is no longer the enclosed volume.
        let mixed = TriangleMesh {
            triangles: original
                .triangles
                .iter()
                .enumerate()
                .map(|(t, &[a, b, c])| if t % 3 == 1 { [a, c, b] } else { [a, b, c] })
                .collect(),
            ..original.clone()
        };
        assert!(!edge_report(&mixed.triangles).misoriented.is_empty());
        // A connected closed orientable surface has exactly two consistent
        // orientations; the outward one is the file's (the meshes README).
        let repaired = closed_surface(&mixed, &path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(repaired.triangles, original.triangles, "{name}");
    }
}

#[test]
fn each_component_is_oriented_outward_on_its_own() {
    // Two unit-spaced cubes, the second inside out: both come back outward,
    // and the total is twice the cube's 8 (exact: integer coordinates).
    let (cube, path) = load_one("cube.asc");
    let mut positions = cube.positions.clone();
    positions.extend(cube.positions.iter().map(|p| [p[0] + 5.0, p[1], p[2]]));
    let mut triangles = cube.triangles.clone();
    triangles.extend(flipped(&cube.triangles).iter().map(|t| t.map(|v| v + 8)));
    let two = mesh("two cubes", &positions, &triangles);
    assert_eq!(volume(&two), 0.0);
    let repaired = closed_surface(&two, &path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(volume(&repaired), 16.0);
}

#[test]
fn an_open_surface_is_refused_with_its_first_boundary_edge() {
    let square = mesh(
        "square",
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        &[[0, 1, 2], [0, 2, 3]],
    );
    let err = closed_surface(&square, Path::new("sheet.obj")).expect_err("open");
    // Boundary edges in order of first appearance: 0-1 is the first edge of
    // triangle 0; the diagonal 0-2 is interior.
    assert_eq!(
        err.kind,
        MeshErrorKind::NotClosed {
            count: 4,
            first: [0, 1]
        }
    );
    assert_eq!(
        err.to_string(),
        "sheet.obj: object \"square\": not closed: 4 boundary edges, the first between \
         vertices 0 and 1; a gas body needs a closed surface (it can still be used as cloth)"
    );
}

#[test]
fn an_edge_of_four_triangles_is_refused() {
    // Two tetrahedra sharing the edge 0-1 (and nothing else): every other
    // edge has two triangles, the shared one has four.
    let t = tetrahedron();
    let mut positions = t.positions.clone();
    positions.extend([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
    let mut triangles = t.triangles.clone();
    // The second tetrahedron (0, 1, 4, 5) with 4 = -e2, 5 = -e3.
    triangles.extend([[0, 4, 1], [0, 1, 5], [0, 5, 4], [1, 4, 5]]);
    let two = mesh("bowtie", &positions, &triangles);
    let err = closed_surface(&two, Path::new("two.off")).expect_err("non-manifold");
    assert_eq!(
        err.kind,
        MeshErrorKind::NonManifold {
            count: 1,
            first: [0, 1],
            triangles: 4
        }
    );
    assert!(err
        .to_string()
        .starts_with("two.off: object \"bowtie\": not edge-manifold"));
}

#[test]
fn a_one_sided_surface_is_refused() {
    // The six-vertex projective plane (the hemi-icosahedron): closed, every
    // edge in exactly two triangles, χ = 6 - 15 + 10 = 1, and not orientable.
    let positions: Vec<[f64; 3]> = (0..6)
        .map(|k| {
            let a = f64::from(k);
            [a.cos(), a.sin(), 0.1 * a * a]
        })
        .collect();
    let triangles = [
        [0, 1, 2],
        [0, 2, 3],
        [0, 3, 4],
        [0, 4, 5],
        [0, 5, 1],
        [1, 2, 4],
        [2, 3, 5],
        [3, 4, 1],
        [4, 5, 2],
        [5, 1, 3],
    ];
    let report = edge_report(&triangles);
    assert!(report.is_closed());
    assert_eq!(report.edges.len(), 15);
    let rp2 = mesh("rp2", &positions, &triangles);
    let err = closed_surface(&rp2, Path::new("rp2.obj")).expect_err("one-sided");
    assert!(
        matches!(err.kind, MeshErrorKind::NotOrientable { .. }),
        "{err}"
    );
}

#[test]
fn degenerate_flat_and_broken_meshes_are_refused() {
    let t = tetrahedron();
    let file = Path::new("bad.asc");

    let mut degenerate = t.clone();
    degenerate.triangles[2] = [0, 3, 3];
    let err = closed_surface(&degenerate, file).expect_err("degenerate");
    assert_eq!(
        err.kind,
        MeshErrorKind::Degenerate {
            triangle: 2,
            vertex: 3
        }
    );
    assert_eq!(edge_report(&degenerate.triangles).degenerate, [2]);

    // Two triangles back to back: closed and consistently oriented, but flat.
    let pillow = mesh(
        "pillow",
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2], [0, 2, 1]],
    );
    let err = closed_surface(&pillow, file).expect_err("flat");
    assert!(
        matches!(err.kind, MeshErrorKind::FlatComponent { .. }),
        "{err}"
    );

    // Hand-built meshes can be wrong in ways files cannot: no panic either.
    let mut out_of_range = t.clone();
    out_of_range.triangles[1] = [0, 1, 9];
    let err = closed_surface(&out_of_range, file).expect_err("index");
    assert_eq!(
        err.to_string(),
        "bad.asc: object \"tetra\": face 1 vertex index 9 out of range (4 vertices)"
    );
    assert!(signed_volume(&out_of_range.positions, &out_of_range.triangles).is_nan());

    let mut not_finite = t.clone();
    not_finite.positions[3][2] = f64::NAN;
    assert!(closed_surface(&not_finite, file).is_err());

    let empty = mesh("empty", &t.positions, &[]);
    assert!(closed_surface(&empty, file).is_err());
}

#[test]
fn unique_edges_give_one_spring_per_edge() {
    // Closed triangle surfaces: E = 3T/2.
    assert_eq!(unique_edges(&tetrahedron().triangles).len(), 6);
    assert_eq!(unique_edges(&octahedron().triangles).len(), 12);
    let square = [[0, 1, 2], [0, 2, 3]];
    assert_eq!(
        unique_edges(&square),
        [[0, 1], [1, 2], [0, 2], [2, 3], [0, 3]]
    );
    // A degenerate triangle contributes its one proper edge.
    assert_eq!(unique_edges(&[[4, 4, 7]]), [[4, 7]]);
}

#[test]
fn bending_pairs_join_the_vertices_across_each_interior_edge() {
    // A square split along 0-2: one bending spring, the other diagonal.
    assert_eq!(bending_pairs(&[[0, 1, 2], [0, 2, 3]]), [[1, 3]]);
    // In a tetrahedron every opposite pair is already an edge.
    assert!(bending_pairs(&tetrahedron().triangles).is_empty());
    // Octahedron: across each of the 12 edges lie two antipodal vertices;
    // the 3 axes are the only bending pairs, each found from 4 edges.
    let mut pairs = bending_pairs(&octahedron().triangles);
    pairs.sort_unstable();
    assert_eq!(pairs, [[0, 1], [2, 3], [4, 5]]);
    // Cube of side 2 in 12 triangles: its 10 vertex pairs that are not
    // edges are the 6 unused face diagonals (squared length 8) and the 4
    // space diagonals (12). Across each used face diagonal lies the unused
    // one of the same face, so all 6 are bending pairs; every pair is one of
    // the 10, listed once.
    let (cube, _) = load_one("cube.asc");
    let pairs = bending_pairs(&cube.triangles);
    let edges = unique_edges(&cube.triangles);
    let length2 = |[a, b]: [usize; 2]| -> f64 {
        let (p, q) = (cube.positions[a], cube.positions[b]);
        (0..3).map(|k| (p[k] - q[k]).powi(2)).sum()
    };
    for i in 0..8 {
        for j in i + 1..8 {
            if length2([i, j]) == 8.0 && !edges.contains(&[i, j]) {
                assert!(pairs.contains(&[i, j]), "face diagonal {i}-{j} missing");
            }
        }
    }
    for &pair in &pairs {
        assert!(pair[0] < pair[1] && !edges.contains(&pair));
        assert!([8.0, 12.0].contains(&length2(pair)), "{pair:?}");
    }
    let mut unique = pairs.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), pairs.len());
    assert!((6..=10).contains(&pairs.len()));
}
