//! `diagnostics.csv`: one row per recorded step with the energies, per-body
//! volume, pressure and centroid, and probed particle positions (README.md,
//! "Usage").

use std::fs::File;
use std::io::{self, BufRead, BufReader, Write};
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
        writeln!(file, "{}", header(world, probes))?;
        Ok(Diagnostics {
            file,
            probes: probes.to_vec(),
            rows: 0,
        })
    }

    /// Go on with the table of a run that stopped after `rows` rows: the
    /// header and the first `rows` rows of `path` (or of the
    /// `path.partial` a killed run left) are kept, later rows dropped, and
    /// new rows follow. Refused when the file has other columns or fewer
    /// rows. Returns `None` when there is neither file, and nothing is
    /// written then.
    pub fn resume(
        path: &Path,
        world: &World,
        probes: &[usize],
        rows: usize,
    ) -> io::Result<Option<Self>> {
        let partial = path.with_file_name(format!(
            "{}.partial",
            path.file_name().unwrap_or_default().to_string_lossy()
        ));
        // A killed run's rows are moved aside first: the new table is
        // written under the `.partial` name.
        let previous = partial.with_extension("previous");
        let source = if path.is_file() {
            path.to_path_buf()
        } else if partial.is_file() {
            std::fs::rename(&partial, &previous)?;
            previous.clone()
        } else {
            return Ok(None);
        };
        let mut lines = BufReader::new(File::open(&source)?).lines();
        let refuse = |what: String| {
            io::Error::new(
                io::ErrorKind::InvalidData,
                format!(
                    "{}: {what}, so the run cannot go on in it (use another --out)",
                    source.display()
                ),
            )
        };
        let header = header(world, probes);
        if lines.next().transpose()?.as_deref() != Some(header.as_str()) {
            return Err(refuse(
                "its columns are not this run's (another scene, or other --probe)".into(),
            ));
        }
        let mut diagnostics = Diagnostics::create(path, world, probes)?;
        for _ in 0..rows {
            let Some(line) = lines.next().transpose()? else {
                return Err(refuse(format!(
                    "it has only {} rows where the state was saved after {rows}",
                    diagnostics.rows
                )));
            };
            writeln!(diagnostics.file, "{line}")?;
            diagnostics.rows += 1;
        }
        drop(lines);
        if source == previous {
            std::fs::remove_file(&previous)?;
        }
        Ok(Some(diagnostics))
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

    /// Write the rows so far through to the (temporary) file, so that a
    /// run killed after a checkpoint keeps them in `diagnostics.csv.partial`.
    pub fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }

    /// Finish the file and move it into place.
    pub fn finish(self) -> io::Result<()> {
        self.file.commit()
    }
}

/// The header row: the fixed columns, five per body, three per probe.
fn header(world: &World, probes: &[usize]) -> String {
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
    header
}
