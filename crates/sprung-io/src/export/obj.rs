//! Wavefront OBJ: one object per body, its particles as vertices, its
//! faces as `f` and, for bodies without faces, its springs as `l` lines.
//! Blender imports `frame_*.obj` as a sequence.

use std::fmt::Write;

use sprung::World;

/// The world's current state as an OBJ file.
pub(crate) fn render(world: &World) -> String {
    let mut out = String::new();
    // Writing to a String cannot fail; the results are ignored on purpose.
    let _ = writeln!(
        out,
        "# sprung frame: step {} time {} s",
        world.steps(),
        world.time()
    );
    for x in &world.particles.position {
        let _ = writeln!(out, "v {} {} {}", x.x, x.y, x.z);
    }
    let springs = &world.springs;
    for body in &world.bodies {
        let _ = writeln!(out, "o {}", body.name);
        if body.faces.is_empty() {
            for s in body.springs.clone() {
                let _ = writeln!(
                    out,
                    "l {} {}",
                    springs.first()[s] + 1,
                    springs.second()[s] + 1
                );
            }
        } else {
            for [a, b, c] in &body.faces {
                let _ = writeln!(out, "f {} {} {}", a + 1, b + 1, c + 1);
            }
        }
    }
    out
}
