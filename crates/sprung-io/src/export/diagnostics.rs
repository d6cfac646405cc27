//! `diagnostics.csv`: one row per recorded step with the energies, per-body
//! volume, pressure and centroid, and probed particle positions (README.md,
//! "Usage").

use std::fs::File;
use std::io::{self, BufRead, BufReader};
use std::path::Path;

use sprung::World;

use super::AtomicFile;

/// The diagnostics table of a run, written row by row and committed at the
/// end (a run that blew up commits the rows it recorded before, all finite).
///
/// A rope's table, with its free end probed:
///
/// ```
/// use sprung::{build, IntegratorKind, World};
/// use sprung_io::export::Diagnostics;
///
/// let dir = std::env::temp_dir().join(format!("sprung-doc-diagnostics-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let mut world = World::new(IntegratorKind::Verlet);
/// world.add_body("rope", build::rope(4, 1.0).unwrap().with_stiffness(100.0)).unwrap();
///
/// let path = dir.join("diagnostics.csv");
/// let mut table = Diagnostics::create(&path, &world, &[3]).unwrap();
/// for _ in 0..10 {
///     table.record(&world).unwrap();
///     world.step(1e-3).unwrap();
/// }
/// assert_eq!(table.rows(), 10);
/// assert!(!path.exists()); // written under `diagnostics.csv.partial` until finished
/// table.finish().unwrap();
///
/// let text = std::fs::read_to_string(&path).unwrap();
/// let mut lines = text.lines();
/// let header: Vec<&str> = lines.next().unwrap().split(',').collect();
/// assert_eq!(header[..5], ["step", "time", "kinetic", "spring", "gravity"]);
/// assert!(header.contains(&"rope.cy"));
/// assert_eq!(header[header.len() - 3..], ["p3.x", "p3.y", "p3.z"]);
/// let last: Vec<&str> = lines.last().unwrap().split(',').collect();
/// assert_eq!(last[0], "9"); // the step
/// assert!((last[1].parse::<f64>().unwrap() - 9e-3).abs() < 1e-15); // the time (s)
/// std::fs::remove_dir_all(&dir).unwrap();
/// ```
#[derive(Debug)]
pub struct Diagnostics {
    file: Sink,
    probes: Vec<usize>,
    /// The potential terms of the energy, as the header lists them.
    energy_names: Vec<&'static str>,
    rows: usize,
    /// The `time` of every row (s), for the frames' series file.
    times: Vec<f64>,
}

impl Diagnostics {
    /// Start `path` with the header for `world`'s bodies and the `probes`
    /// (particle indices, which the caller has checked).
    pub fn create(path: &Path, world: &World, probes: &[usize]) -> io::Result<Self> {
        Self::start(
            Sink::File(RowFile::new(AtomicFile::create(path)?)),
            world,
            probes,
        )
    }

    /// The same table kept in memory, for a program that reads the rows
    /// back ([`Diagnostics::text`]) instead of a file: the same bytes a
    /// file of the same run holds.
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, World};
    /// use sprung_io::export::Diagnostics;
    ///
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// world.add_body("rope", build::rope(4, 1.0).unwrap()).unwrap();
    /// let mut table = Diagnostics::in_memory(&world, &[]);
    /// table.record(&world).unwrap();
    /// assert!(table.text().starts_with("step,time,kinetic,spring,gravity,gas,total,"));
    /// assert_eq!(table.text().lines().count(), 2); // the header and a row
    /// ```
    pub fn in_memory(world: &World, probes: &[usize]) -> Self {
        Self::start(Sink::Memory(Vec::new()), world, probes).expect("writing to memory cannot fail")
    }

    fn start(mut file: Sink, world: &World, probes: &[usize]) -> io::Result<Self> {
        file.line(&header(world, probes))?;
        Ok(Diagnostics {
            file,
            probes: probes.to_vec(),
            energy_names: world.energy_names(),
            rows: 0,
            times: Vec::new(),
        })
    }

    /// The table so far as text (header and rows) when it is kept in
    /// memory ([`Diagnostics::in_memory`]); empty for a file.
    pub fn text(&self) -> &str {
        match &self.file {
            Sink::Memory(bytes) => std::str::from_utf8(bytes).unwrap_or_default(),
            Sink::File(_) => "",
        }
    }

    /// Go on with the table of a run that stopped after `rows` rows: the
    /// header and the first `rows` rows of the newest table there is (the
    /// `path.partial` a killed run left, else `path`) are kept, later rows
    /// dropped, and new rows follow. Refused when that table has other
    /// columns or fewer rows, and it is then left as it was. Returns `None`
    /// when there is no table, and nothing is written then.
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
        // The new table is written under the `.partial` name: a killed
        // run's rows are moved aside first (where a resume killed while
        // copying may also have left them).
        let previous = partial.with_extension("previous");
        if partial.is_file() {
            std::fs::rename(&partial, &previous)?;
        }
        let source = if previous.is_file() {
            previous.clone()
        } else if path.is_file() {
            path.to_path_buf()
        } else {
            return Ok(None);
        };
        let copied = Self::copy_rows(&source, path, world, probes, rows);
        if source == previous {
            match &copied {
                // The rows are safely in the new table before the old goes.
                Ok(_) => std::fs::remove_file(&previous)?,
                Err(_) => std::fs::rename(&previous, &partial)?,
            }
        }
        copied.map(Some)
    }

    /// A new table at `path` with the header and the first `rows` rows of
    /// `source`, written through to the disk.
    fn copy_rows(
        source: &Path,
        path: &Path,
        world: &World,
        probes: &[usize],
        rows: usize,
    ) -> io::Result<Self> {
        let mut lines = BufReader::new(File::open(source)?).lines();
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
                "its columns are not this run's (another scene, other --probe, or a table \
                 written by an earlier sprung, before the solver_preconditioner and \
                 solver_refactorings columns)"
                    .into(),
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
            diagnostics.file.line(&line)?;
            diagnostics.rows += 1;
            let time = line.split(',').nth(1).and_then(|t| t.parse().ok());
            diagnostics.times.push(time.unwrap_or(f64::NAN));
        }
        diagnostics.flush()?;
        Ok(diagnostics)
    }

    /// Append a row for the world's current state: `contacts` counts the
    /// pairs of bodies touching (closer than the contact thickness). Volume (area in 2D) is
    /// left empty for bodies that are not closed, pressure for bodies
    /// without a gas; the solver's iterations and residual (of the step
    /// that led to this state) for the explicit integrators and the
    /// starting row; the substeps and the last substep's length (s) where a
    /// step was split (`rk45`, `substeps`); the impulses and impact zones
    /// of the CCD behind the contacts in the step that led here
    /// (`ccd_impulses`, `ccd_zones`); implicit Euler's preconditioner and
    /// factorisations in that step (`solver_preconditioner`,
    /// `solver_refactorings`); where springs can break or yield,
    /// the springs and joins broken so far (`broken`).
    pub fn record(&mut self, world: &World) -> io::Result<()> {
        let mut bad: Option<NotFiniteValue> = None;
        let mut number = |quantity: &dyn Fn() -> String, value: f64| {
            if !value.is_finite() && bad.is_none() {
                bad = Some(NotFiniteValue {
                    quantity: quantity(),
                    value,
                });
            }
            Real(value).to_string()
        };
        let optional = |value: Option<f64>| value.map(|v| Real(v).to_string()).unwrap_or_default();
        let report = world.last_step_report();
        let mut row = format!(
            "{},{}",
            world.steps(),
            number(&|| "time".into(), world.time())
        );
        for (name, energy) in energy_columns(world, &self.energy_names) {
            row.push_str(&format!(",{}", number(&|| name.to_string(), energy)));
        }
        let ccd = world.last_ccd_report();
        row.push_str(&format!(
            ",{},{},{},{},{},{},{},{},{}",
            world.active_contacts(),
            report.iterations.map(|i| i.to_string()).unwrap_or_default(),
            optional(report.residual),
            report.substeps.map(|n| n.to_string()).unwrap_or_default(),
            optional(report.step_size),
            ccd.impulses,
            ccd.zones,
            report.preconditioner.map(|p| p.name()).unwrap_or_default(),
            report
                .refactorings
                .map(|n| n.to_string())
                .unwrap_or_default(),
        ));
        if world.limits.enabled() {
            row.push_str(&format!(",{}", world.limits.broken_count()));
        }
        for (index, body) in world.bodies.iter().enumerate() {
            let c = world.centroid(index).unwrap_or_default();
            let column = |what: &str| format!("{}.{what}", body.name);
            let mut maybe = |what: &str, value: Option<f64>| {
                value
                    .map(|v| number(&|| column(what), v))
                    .unwrap_or_default()
            };
            let (volume, pressure) = (
                maybe("volume", world.volume(index)),
                maybe("pressure", world.pressure(index)),
            );
            let (x, y, z) = (
                number(&|| column("cx"), c.x),
                number(&|| column("cy"), c.y),
                number(&|| column("cz"), c.z),
            );
            row.push_str(&format!(",{volume},{pressure},{x},{y},{z}"));
        }
        for &p in &self.probes {
            let x = world.particles.position[p];
            let probe = |axis: &str| format!("p{p}.{axis}");
            row.push_str(&format!(
                ",{},{},{}",
                number(&|| probe("x"), x.x),
                number(&|| probe("y"), x.y),
                number(&|| probe("z"), x.z)
            ));
        }
        // Finite in, finite out: a row with a non-finite number is not
        // written; the error says which.
        if let Some(bad) = bad {
            return Err(io::Error::new(io::ErrorKind::InvalidData, bad));
        }
        self.file.line(&row)?;
        self.rows += 1;
        self.times.push(world.time());
        Ok(())
    }

    /// The simulated time (s) of every row so far, kept rows of a resumed
    /// run included.
    pub fn times(&self) -> &[f64] {
        &self.times
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

    /// Finish the file and move it into place (nothing to do in memory).
    pub fn finish(self) -> io::Result<()> {
        match self.file {
            Sink::File(file) => file.finish(),
            Sink::Memory(_) => Ok(()),
        }
    }

    /// Finish the file after a failure (a write of a row, a frame or a
    /// checkpoint that failed): the rows that reach the file are moved into
    /// place, whole, and a row cut short by the failure is cut off.
    /// Returns the rows kept (of a resumed run's too), at most
    /// [`Diagnostics::rows`].
    pub fn keep(self) -> io::Result<usize> {
        match self.file {
            // The header is a line too: rows kept are the lines after it.
            Sink::File(file) => Ok(file.keep()?.saturating_sub(1)),
            Sink::Memory(_) => Ok(self.rows),
        }
    }
}

/// Where the table's rows go: a file (complete or not at all) or memory.
#[derive(Debug)]
enum Sink {
    File(RowFile),
    Memory(Vec<u8>),
}

impl Sink {
    /// Append `line` (the header or a row, without its newline).
    fn line(&mut self, line: &str) -> io::Result<()> {
        match self {
            Sink::File(file) => file.line(line),
            Sink::Memory(bytes) => {
                bytes.extend_from_slice(line.as_bytes());
                bytes.push(b'\n');
                Ok(())
            }
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match self {
            Sink::File(file) => file.flush(),
            Sink::Memory(_) => Ok(()),
        }
    }
}

/// Lines gathered before they are written through (bytes): the 8 KiB a
/// buffered file writes at a time.
const PENDING_BYTES: usize = 8 << 10;

/// A table's temporary file, written a few lines at a time, that knows
/// how many of its bytes are in the file: a failure leaves whole lines.
#[derive(Debug)]
struct RowFile {
    file: AtomicFile,
    /// Lines not yet written, each ending in a newline.
    pending: Vec<u8>,
    /// Where each pending line ends in `pending`.
    ends: Vec<usize>,
    /// Bytes in the file, all of them whole lines, and those lines.
    written: u64,
    lines: usize,
    /// A write failed: nothing more is written (what it left past
    /// `written` is cut off by [`RowFile::keep`]).
    failed: bool,
}

impl RowFile {
    fn new(file: AtomicFile) -> Self {
        RowFile {
            file,
            pending: Vec::new(),
            ends: Vec::new(),
            written: 0,
            lines: 0,
            failed: false,
        }
    }

    fn line(&mut self, line: &str) -> io::Result<()> {
        self.pending.extend_from_slice(line.as_bytes());
        self.pending.push(b'\n');
        self.ends.push(self.pending.len());
        if self.pending.len() >= PENDING_BYTES {
            self.flush()?;
        }
        Ok(())
    }

    fn flush(&mut self) -> io::Result<()> {
        if self.pending.is_empty() {
            return Ok(());
        }
        if self.failed {
            return Err(io::Error::other("an earlier write to this table failed"));
        }
        if let Err(e) = self.file.write_through(&self.pending) {
            self.failed = true;
            return Err(e);
        }
        self.written += self.pending.len() as u64;
        self.lines += self.ends.len();
        self.pending.clear();
        self.ends.clear();
        Ok(())
    }

    fn finish(mut self) -> io::Result<()> {
        self.flush()?;
        self.file.commit()
    }

    /// Write the pending lines one at a time up to the first that fails,
    /// then move the file into place with the whole lines written; returns
    /// how many lines it holds.
    fn keep(mut self) -> io::Result<usize> {
        let mut from = 0;
        for &end in &self.ends {
            if self.failed || self.file.write_through(&self.pending[from..end]).is_err() {
                self.failed = true;
                break;
            }
            self.written += (end - from) as u64;
            self.lines += 1;
            from = end;
        }
        self.file.commit_truncated(self.written)?;
        Ok(self.lines)
    }
}

/// The energy columns of `world` (J) as `diagnostics.csv` has them, in
/// its order: `kinetic`, the potential terms `names` (the world's
/// [`World::energy_names`] when the table started) with `total` after the
/// first three. A term the world no longer has (a force taken out of the
/// list mid-run) is zero.
///
/// ```
/// use sprung::{build, IntegratorKind, World};
/// use sprung_io::export::energy_columns;
///
/// let mut world = World::new(IntegratorKind::Verlet);
/// world.add_body("rope", build::rope(4, 1.0).unwrap()).unwrap();
/// let columns = energy_columns(&world, &world.energy_names());
/// let names: Vec<&str> = columns.iter().map(|c| c.0).collect();
/// assert_eq!(names[..5], ["kinetic", "spring", "gravity", "gas", "total"]);
/// let total = columns.iter().find(|c| c.0 == "total").unwrap().1;
/// assert_eq!(total, world.energies().total());
/// ```
pub fn energy_columns(world: &World, names: &[&'static str]) -> Vec<(&'static str, f64)> {
    let e = world.energies();
    let mut columns = vec![("kinetic", e.kinetic)];
    for (k, &name) in names.iter().enumerate() {
        if k == TERMS_BEFORE_TOTAL {
            columns.push(("total", e.total()));
        }
        columns.push((name, e.get(name).unwrap_or(0.0)));
    }
    columns
}

/// A number as `diagnostics.csv` writes it: the shortest digits that read
/// back to the same `f64`, in plain notation from 1e-5 to below 1e16 (and
/// 0), in scientific notation (`2.1782575743145572e-15`) outside, where
/// plain notation would run to dozens of zeros.
#[derive(Debug, Clone, Copy)]
pub struct Real(pub f64);

impl std::fmt::Display for Real {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let magnitude = self.0.abs();
        if magnitude == 0.0 || (1e-5..1e16).contains(&magnitude) || !magnitude.is_finite() {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// A number a row would have held that is not finite: the row is not
/// written. [`Diagnostics::record`] returns it inside an
/// [`io::ErrorKind::InvalidData`] error (`get_ref` and `downcast_ref` find
/// it), so that a run can stop as a blow-up.
#[derive(Debug, Clone, PartialEq)]
pub struct NotFiniteValue {
    /// Its column's name (`time`, `spring`, `ball.pressure`, ...).
    pub quantity: String,
    /// The value: infinite or NaN.
    pub value: f64,
}

impl std::fmt::Display for NotFiniteValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} = {}, not a finite number", self.quantity, self.value)
    }
}

impl std::error::Error for NotFiniteValue {}

/// How many potential terms come before the `total` column: the
/// textbook's three (spring, gravity, gas), as the first tables had them;
/// the later terms (contact, gravitation, and those of a user's forces)
/// follow it.
const TERMS_BEFORE_TOTAL: usize = 3;

/// The header row: `step`, `time`, the energy's terms (kinetic, then the
/// world's potential terms with `total` after the first three), the step's
/// contacts and solver columns, five per body, three per probe.
fn header(world: &World, probes: &[usize]) -> String {
    let mut header = String::from("step,time,kinetic");
    for (k, name) in world.energy_names().iter().enumerate() {
        if k == TERMS_BEFORE_TOTAL {
            header.push_str(",total");
        }
        header.push_str(&format!(",{name}"));
    }
    header.push_str(
        ",contacts,solver_iterations,solver_residual,substeps,step_size,ccd_impulses,ccd_zones,\
         solver_preconditioner,solver_refactorings",
    );
    if world.limits.enabled() {
        header.push_str(",broken");
    }
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

#[cfg(test)]
mod tests {
    use super::Real;

    #[test]
    fn numbers_are_short_and_read_back_exactly() {
        assert_eq!(
            Real(-2.1782575743145572e-15).to_string(),
            "-2.1782575743145572e-15"
        );
        assert_eq!(Real(0.5).to_string(), "0.5");
        assert_eq!(Real(0.1 + 0.2).to_string(), "0.30000000000000004");
        assert_eq!(Real(20.0).to_string(), "20");
        assert_eq!(Real(1e-5).to_string(), "0.00001");
        assert_eq!(Real(9.99e-6).to_string(), "9.99e-6");
        assert_eq!(Real(1e20).to_string(), "1e20");
        assert_eq!(Real(0.0).to_string(), "0");
        assert_eq!(Real(-0.0).to_string(), "-0");
        // Every bit pattern of finite numbers (a scattering of them) reads
        // back to the same bits.
        let mut bits = 0x9E37_79B9_7F4A_7C15_u64;
        for _ in 0..100_000 {
            bits ^= bits << 13;
            bits ^= bits >> 7;
            bits ^= bits << 17;
            let x = f64::from_bits(bits);
            if x.is_finite() {
                let text = Real(x).to_string();
                let back: f64 = text.parse().expect("a number");
                assert_eq!(back.to_bits(), x.to_bits(), "{x:e} written as {text}");
                assert!(text.len() <= 24, "{text}");
            }
        }
    }
}
