//! Legacy VTK (ASCII) frames: the [`Frame`] as an `UNSTRUCTURED_GRID`,
//! which ParaView, VTK, pyvista and meshio all read; `sprung render` reads
//! them back ([`super::read_vtk_frame`]). The title line keeps the step and
//! time (`sprung frame: step N time T s`), and `TIME` field data the time.

use std::fmt::Write;

use sprung::World;

use super::frame::Frame;
use super::Real;

/// The world's current state as a legacy VTK file.
pub(crate) fn render(world: &World) -> String {
    let frame = Frame::of(world);
    let particles = &world.particles;
    let cells = frame.cells();
    let mut out = String::with_capacity(64 * (particles.len() + cells) + 256);
    // Writing to a String cannot fail; the results are ignored on purpose.
    let _ = writeln!(out, "# vtk DataFile Version 4.2");
    let _ = writeln!(
        out,
        "sprung frame: step {} time {} s",
        world.steps(),
        world.time()
    );
    let _ = writeln!(out, "ASCII\nDATASET UNSTRUCTURED_GRID");
    let _ = writeln!(
        out,
        "FIELD FieldData 1\nTIME 1 1 double\n{}",
        Real(world.time())
    );
    let _ = writeln!(out, "POINTS {} double", particles.len());
    for x in &particles.position {
        let _ = writeln!(out, "{} {} {}", Real(x.x), Real(x.y), Real(x.z));
    }
    let _ = writeln!(out, "CELLS {cells} {}", cells + frame.connectivity.len());
    let mut start = 0;
    for &end in &frame.offsets {
        let nodes = &frame.connectivity[start..end as usize];
        let _ = write!(out, "{}", nodes.len());
        for n in nodes {
            let _ = write!(out, " {n}");
        }
        out.push('\n');
        start = end as usize;
    }
    let _ = writeln!(out, "CELL_TYPES {cells}");
    for t in &frame.types {
        let _ = writeln!(out, "{t}");
    }
    let _ = writeln!(out, "POINT_DATA {}", particles.len());
    let _ = writeln!(out, "VECTORS velocity double");
    for v in &particles.velocity {
        let _ = writeln!(out, "{} {} {}", Real(v.x), Real(v.y), Real(v.z));
    }
    scalars(&mut out, "pinned", "int", frame.pinned.iter());
    scalars(&mut out, "body", "int", frame.point_body.iter());
    if cells > 0 {
        let _ = writeln!(out, "CELL_DATA {cells}");
        scalars(&mut out, "kind", "int", frame.kind.iter());
        scalars(&mut out, "body", "int", frame.cell_body.iter());
        scalars(
            &mut out,
            "rest_length",
            "double",
            frame.rest_length.iter().map(|&x| Real(x)),
        );
        scalars(
            &mut out,
            "strain",
            "double",
            frame.strain.iter().map(|&x| Real(x)),
        );
    }
    out
}

/// A `SCALARS` array of one component.
fn scalars<T: std::fmt::Display>(
    out: &mut String,
    name: &str,
    kind: &str,
    values: impl Iterator<Item = T>,
) {
    let _ = writeln!(out, "SCALARS {name} {kind} 1\nLOOKUP_TABLE default");
    for v in values {
        let _ = writeln!(out, "{v}");
    }
}
