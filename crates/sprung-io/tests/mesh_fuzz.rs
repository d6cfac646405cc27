//! The readers never panic: every real mesh file, damaged in thousands of
//! deterministic random ways, gives `Ok` or `Err`, and whatever is accepted
//! goes through the topology functions without a panic either.
//!
//! The damage imitates what happens to files: lines deleted, duplicated,
//! swapped or moved, bytes flipped or inserted, the file cut short, numbers
//! replaced by `nan`, huge, negative or malformed values. A tiny xorshift
//! generator with fixed seeds makes every run the same; a panic is reported
//! with the file, the case number and the mutations that caused it.

mod common;

use common::mesh_path;
use common::mutate::{mutate, XorShift};

use std::path::Path;

use sprung_io::mesh::{
    bending_pairs, closed_surface, edge_report, parse_mesh, select_object, signed_volume,
    unique_edges, MeshFormat,
};

/// Runs the readers and the topology functions on `bytes`; `Err` carries
/// the panic message if anything panicked.
fn exercise(bytes: &[u8], format: MeshFormat, path: &Path) -> Result<bool, String> {
    common::without_panic(|| {
        let Ok(meshes) = parse_mesh(bytes, format, path) else {
            return false;
        };
        for mesh in &meshes {
            let _ = closed_surface(mesh, path);
            let _ = signed_volume(&mesh.positions, &mesh.triangles);
            let _ = edge_report(&mesh.triangles);
            let _ = unique_edges(&mesh.triangles);
            let _ = bending_pairs(&mesh.triangles);
        }
        let first = meshes.first().map(|m| m.name.clone());
        let _ = select_object(meshes.clone(), first.as_deref(), path);
        let _ = select_object(meshes, None, path);
        true
    })
}

/// Damages `original` `cases` times (1 to 3 mutations each) and checks that
/// nothing panics. Returns how many damaged files were still accepted.
fn fuzz(name: &str, original: &[u8], format: MeshFormat, cases: usize, seed: u64) -> usize {
    let path = Path::new(name);
    assert_eq!(
        exercise(original, format, path),
        Ok(true),
        "{name}: the undamaged file must be accepted"
    );
    let mut rng = XorShift(seed);
    let mut accepted = 0;
    for case in 0..cases {
        let mut bytes = original.to_vec();
        let steps: Vec<String> = (0..1 + rng.below(3))
            .map(|_| mutate(&mut bytes, &mut rng))
            .collect();
        match exercise(&bytes, format, path) {
            Ok(true) => accepted += 1,
            Ok(false) => {}
            Err(message) => panic!("{name}: case {case} panicked ({message}) after: {steps:?}"),
        }
    }
    accepted
}

fn fuzz_file(name: &str, cases: usize, seed: u64) {
    let path = mesh_path(name);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let format = MeshFormat::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
    let accepted = fuzz(name, &bytes, format, cases, seed);
    // Some damage is harmless (a swapped comment line, a changed digit), most
    // is not: both outcomes must occur, or the mutations are not reaching
    // the parser.
    assert!(
        accepted > 0 && accepted < cases,
        "{name}: {accepted} of {cases} accepted"
    );
}

// Case counts: a few thousand for the small files. A case costs about
// 0.7 ms for the 40 kB files and 5 to 25 ms for the large OBJ files (the
// horse) in the dev profile on a loaded 2-core machine, so those get a few
// hundred at most, keeping this file within a few seconds.

#[test]
fn damaged_cube_asc_never_panics() {
    fuzz_file("cube.asc", 4000, 0x9E37_79B9_7F4A_7C15);
}

#[test]
fn damaged_uusalku_asc_never_panics() {
    fuzz_file("UUSALKU.ASC", 2000, 0xD1B5_4A32_D192_ED03);
}

#[test]
fn damaged_icosahedron_stl_never_panics() {
    fuzz_file("icosahedron_ascii.stl", 3000, 0x2545_F491_4F6C_DD1D);
}

#[test]
fn damaged_binary_stl_never_panics() {
    // The icosahedron's facets as binary STL, written here.
    let path = mesh_path("icosahedron_ascii.stl");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{e}"));
    let corners: Vec<f32> = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("vertex"))
        .flat_map(|l| l.split_whitespace().map(|w| w.parse::<f32>().unwrap()))
        .collect();
    let mut bytes = b"solid binary".to_vec();
    bytes.resize(80, 0);
    let triangles = corners.len() / 9;
    bytes.extend(u32::try_from(triangles).unwrap().to_le_bytes());
    for t in corners.chunks(9) {
        bytes.extend([0u8; 12]);
        for c in t {
            bytes.extend(c.to_le_bytes());
        }
        bytes.extend([0u8; 2]);
    }
    let accepted = fuzz(
        "binary.stl",
        &bytes,
        MeshFormat::Stl,
        3000,
        0x5851_F42D_4C95_7F2D,
    );
    assert!(accepted > 0 && accepted < 3000, "{accepted} accepted");
}

#[test]
fn damaged_sphere_low_off_never_panics() {
    fuzz_file("sphere_low.off", 1500, 0x1405_7B7E_F767_814F);
}

#[test]
fn damaged_sphere_obj_never_panics() {
    fuzz_file("sphere.obj", 1200, 0x6C07_8965_2F1B_3A5D);
}

#[test]
fn damaged_spot_obj_never_panics() {
    fuzz_file("spot_low_resolution.obj", 400, 0x94D0_49BB_1331_11EB);
}

#[test]
fn damaged_horse_obj_never_panics() {
    fuzz_file("horse.obj", 150, 0xBF58_476D_1CE4_E5B9);
}
