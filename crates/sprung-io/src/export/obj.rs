//! Wavefront OBJ: one object per body, its particles as vertices with
//! smooth vertex normals (`vn`, the area-weighted mean of the faces around
//! each vertex) and its faces as `f v//vn` in smoothing group 1, so a frame
//! imported into Blender is shaded smooth as in the viewer; bodies without
//! faces have their springs as `l` lines. Blender imports `frame_*.obj` as
//! a sequence; for an animation, use the glTF frames.

use std::fmt::Write;

use sprung::surface::unit_vertex_normals;
use sprung::World;

use super::Real;

/// The world's current state as an OBJ file.
pub(crate) fn render(world: &World) -> String {
    let position = &world.particles.position;
    let faces = super::all_faces(world);
    let normals = unit_vertex_normals(&faces, position);
    let mut out = String::with_capacity(80 * position.len() + 32 * faces.len() + 64);
    // Writing to a String cannot fail; the results are ignored on purpose.
    let _ = writeln!(
        out,
        "# sprung frame: step {} time {} s",
        world.steps(),
        world.time()
    );
    for x in position {
        let _ = writeln!(out, "v {} {} {}", Real(x.x), Real(x.y), Real(x.z));
    }
    // One normal per vertex, unit length; +z for a vertex on no face (it
    // is in no `f` line).
    for n in &normals {
        let _ = writeln!(out, "vn {} {} {}", Real(n.x), Real(n.y), Real(n.z));
    }
    let springs = &world.springs;
    for body in &world.bodies {
        let _ = writeln!(out, "o {}", body.name);
        if body.faces.is_empty() {
            let _ = writeln!(out, "s off");
            for s in body.springs_in_scene_order() {
                let [a, b] = springs.endpoints(s);
                let _ = writeln!(out, "l {} {}", a + 1, b + 1);
            }
        } else {
            let _ = writeln!(out, "s 1");
            for face in &body.faces {
                let [a, b, c] = face.map(|i| i + 1);
                let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
            }
        }
    }
    out
}
