//! `diagnostics.csv`: one row per recorded step with the energies, per-body
//! volume, pressure and centroid, and probed particle positions (DESIGN.md
//! "The command line").

use std::io::{self, Write};
use std::path::Path;

use sprung::World;

use super::AtomicFile;

/// The diagnostics table of a run, written row by row and committed at the
/// end (a run that blew up commits the rows it recorded before, all finite).
#[derive(Debug)]
pub struct Diagnostics {
    file: AtomicFile,
    probes: Vec<usize>,
    rows: usize,
}

impl Diagnostics {
    /// Start `path` with the header for `world`'s bodies and the `probes`
    /// (particle indices, which the caller has checked).
    pub fn create(path: &Path, world: &World, probes: &[usize]) -> io::Result<Self> {
        let mut file = AtomicFile::create(path)?;
        let mut header = String::from(
            "step,time,kinetic,spring,gravity,gas,total,contact,gravitation,contacts,solver_iterations,solver_residual,substeps,step_size",
        );
        for body in &world.bodies {
            for column in ["volume", "pressure", "cx", "cy", "cz"] {
                header.push_str(&format!(",{}.{column}", body.name));
            }
        }
        for p in probes {
            header.push_str(&format!(",p{p}.x,p{p}.y,p{p}.z"));
        }
        writeln!(file, "{header}")?;
        Ok(Diagnostics {
            file,
            probes: probes.to_vec(),
            rows: 0,
        })
    }

    /// Append a row for the world's current state: `contacts` counts the
    /// pairs of bodies touching (closer than the contact thickness). Volume (area in 2D) is
    /// left empty for bodies that are not closed, pressure for bodies
    /// without a gas; the solver's iterations and residual (of the step
    /// that led to this state) for the explicit integrators and the
    /// starting row; the substeps and the last substep's length (s) where a
    /// step was split (`rk45`, `substeps`).
    pub fn record(&mut self, world: &World) -> io::Result<()> {
        let e = world.energies();
        let optional = |value: Option<f64>| value.map(|v| v.to_string()).unwrap_or_default();
        let report = world.last_step_report();
        let mut row = format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            world.steps(),
            world.time(),
            e.kinetic,
            e.spring,
            e.gravity,
            e.gas,
            e.total(),
            e.contact,
            e.gravitation,
            world.active_contacts(),
            optional(report.iterations.map(f64::from)),
            optional(report.residual),
            optional(report.substeps.map(f64::from)),
            optional(report.step_size),
        );
        for index in 0..world.bodies.len() {
            let c = world.centroid(index).unwrap_or_default();
            let (volume, pressure) = (
                optional(world.volume(index)),
                optional(world.pressure(index)),
            );
            row.push_str(&format!(",{volume},{pressure},{},{},{}", c.x, c.y, c.z));
        }
        for &p in &self.probes {
            let x = world.particles.position[p];
            row.push_str(&format!(",{},{},{}", x.x, x.y, x.z));
        }
        writeln!(self.file, "{row}")?;
        self.rows += 1;
        Ok(())
    }

    /// Number of rows recorded.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Finish the file and move it into place.
    pub fn finish(self) -> io::Result<()> {
        self.file.commit()
    }
}
