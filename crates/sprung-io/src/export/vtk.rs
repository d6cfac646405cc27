//! Legacy VTK polydata (ASCII): particles as points, springs as lines,
//! faces as polygons, velocity and pinned flag as point data. ParaView
//! opens `frame_*.vtk` as one time series.

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
    if !springs.is_empty() {
        let _ = writeln!(out, "LINES {} {}", springs.len(), 3 * springs.len());
        for s in 0..springs.len() {
            let _ = writeln!(out, "2 {} {}", springs.first[s], springs.second[s]);
        }
    }
    if !faces.is_empty() {
        let _ = writeln!(out, "POLYGONS {} {}", faces.len(), 4 * faces.len());
        for [a, b, c] in faces {
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
    out
}
