//! Legacy VTK polydata (ASCII): particles as points, springs as lines,
//! faces as polygons, velocity and pinned flag as point data, and per cell
//! the spring's rest length and strain and whether it outlines a closed 2D
//! body. ParaView opens `frame_*.vtk` as one time series; `sprung render`
//! reads them back ([`super::read_vtk_frame`]).
//!
//! Cell data covers every cell, lines first then polygons (the legacy
//! format's order): `rest_length` (m) and `strain` (`(d - L0) / L0`, no
//! unit) are 0 for polygons; `outline` is 1 for a spring that is also a
//! segment of a closed 2D loop (a ring's perimeter), else 0. Rigid rods
//! follow the springs as lines (their length as `rest_length`), marked by
//! a `rod` array of 1s, written only when the world has rods.

use std::collections::BTreeSet;
use std::fmt::Write;

use sprung::World;

/// The world's current state as a legacy VTK file.
pub(crate) fn render(world: &World) -> String {
    let particles = &world.particles;
    let springs = &world.springs;
    let faces: Vec<[u32; 3]> = world
        .bodies
        .iter()
        .flat_map(|b| b.faces.iter().copied())
        .collect();
    let mut out = String::with_capacity(64 * (particles.len() + springs.len() + faces.len()) + 256);
    // Writing to a String cannot fail; the results are ignored on purpose.
    let _ = writeln!(out, "# vtk DataFile Version 3.0");
    let _ = writeln!(
        out,
        "sprung frame: step {} time {} s",
        world.steps(),
        world.time()
    );
    let _ = writeln!(out, "ASCII\nDATASET POLYDATA");
    let _ = writeln!(out, "POINTS {} double", particles.len());
    for x in &particles.position {
        let _ = writeln!(out, "{} {} {}", x.x, x.y, x.z);
    }
    let rods = &world.rods;
    let lines = springs.len() + rods.len();
    if lines > 0 {
        let _ = writeln!(out, "LINES {lines} {}", 3 * lines);
        for s in 0..springs.len() {
            let _ = writeln!(out, "2 {} {}", springs.first()[s], springs.second()[s]);
        }
        for r in 0..rods.len() {
            let _ = writeln!(out, "2 {} {}", rods.first[r], rods.second[r]);
        }
    }
    if !faces.is_empty() {
        let _ = writeln!(out, "POLYGONS {} {}", faces.len(), 4 * faces.len());
        for [a, b, c] in &faces {
            let _ = writeln!(out, "3 {a} {b} {c}");
        }
    }
    let _ = writeln!(out, "POINT_DATA {}", particles.len());
    let _ = writeln!(out, "VECTORS velocity double");
    for v in &particles.velocity {
        let _ = writeln!(out, "{} {} {}", v.x, v.y, v.z);
    }
    let _ = writeln!(out, "SCALARS pinned int 1\nLOOKUP_TABLE default");
    for i in 0..particles.len() {
        let _ = writeln!(out, "{}", u8::from(particles.is_pinned(i)));
    }
    write_cell_data(&mut out, world, faces.len());
    out
}

/// `CELL_DATA`: rest length, strain and outline flag of every spring (and
/// rod), 0 for every face; the `rod` flags when there are rods. Nothing
/// when there are no cells.
fn write_cell_data(out: &mut String, world: &World, faces: usize) {
    let springs = &world.springs;
    let rods = &world.rods;
    let cells = springs.len() + rods.len() + faces;
    if cells == 0 {
        return;
    }
    let position = &world.particles.position;
    let _ = writeln!(out, "CELL_DATA {cells}");
    let _ = writeln!(out, "SCALARS rest_length double 1\nLOOKUP_TABLE default");
    for length in springs.rest_length.iter().chain(&rods.length) {
        let _ = writeln!(out, "{length}");
    }
    for _ in 0..faces {
        let _ = writeln!(out, "0");
    }
    let _ = writeln!(out, "SCALARS strain double 1\nLOOKUP_TABLE default");
    for s in 0..springs.len() {
        let d =
            position[springs.first()[s] as usize].distance(position[springs.second()[s] as usize]);
        let _ = writeln!(
            out,
            "{}",
            (d - springs.rest_length[s]) / springs.rest_length[s]
        );
    }
    for r in 0..rods.len() {
        let d = position[rods.first[r] as usize].distance(position[rods.second[r] as usize]);
        let _ = writeln!(out, "{}", (d - rods.length[r]) / rods.length[r]);
    }
    for _ in 0..faces {
        let _ = writeln!(out, "0");
    }
    let outline = outline_springs(world);
    let _ = writeln!(out, "SCALARS outline int 1\nLOOKUP_TABLE default");
    for flag in outline {
        let _ = writeln!(out, "{}", u8::from(flag));
    }
    for _ in 0..rods.len() + faces {
        let _ = writeln!(out, "0");
    }
    if !rods.is_empty() {
        let _ = writeln!(out, "SCALARS rod int 1\nLOOKUP_TABLE default");
        for _ in 0..springs.len() {
            let _ = writeln!(out, "0");
        }
        for _ in 0..rods.len() {
            let _ = writeln!(out, "1");
        }
        for _ in 0..faces {
            let _ = writeln!(out, "0");
        }
    }
}

/// For every spring of the world: whether it joins the two ends of a
/// segment of a closed 2D body (either way round).
fn outline_springs(world: &World) -> Vec<bool> {
    let springs = &world.springs;
    let mut flags = vec![false; springs.len()];
    for body in world.bodies.iter().filter(|b| b.closed && b.is_planar()) {
        let segments: BTreeSet<(u32, u32)> = body
            .segments
            .iter()
            .map(|&[a, b]| (a.min(b), a.max(b)))
            .collect();
        for s in body.springs.clone() {
            let (a, b) = (springs.first()[s], springs.second()[s]);
            flags[s] = segments.contains(&(a.min(b), a.max(b)));
        }
    }
    flags
}
