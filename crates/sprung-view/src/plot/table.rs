//! Reading `diagnostics.csv` (README.md, "Usage"): a header,
//! then one row of numbers per recorded step. Empty cells are missing
//! values (volume and pressure of bodies without gas); anything else that
//! does not fit is refused with the file, the line and the column.

use std::path::{Path, PathBuf};

use super::PlotError;

/// The columns every diagnostics file starts with, in this order.
pub const REQUIRED_COLUMNS: [&str; 7] = [
    "step", "time", "kinetic", "spring", "gravity", "gas", "total",
];

/// Columns that hold names, not numbers: implicit Euler's preconditioner.
pub const TEXT_COLUMNS: [&str; 1] = ["solver_preconditioner"];

/// Column suffixes of a body `NAME` (`NAME.volume`, ...).
const BODY_SUFFIXES: [&str; 5] = ["volume", "pressure", "cx", "cy", "cz"];

/// Column suffixes of a probed point `pI` (`pI.x`, ...).
const POINT_SUFFIXES: [&str; 3] = ["x", "y", "z"];

/// A run's `diagnostics.csv`, held column by column.
#[derive(Debug, Clone, PartialEq)]
pub struct DiagnosticsTable {
    path: PathBuf,
    names: Vec<String>,
    columns: Vec<Vec<Option<f64>>>,
    /// The cells of the [`TEXT_COLUMNS`] present, by column index (their
    /// numeric cells are all `None`).
    texts: Vec<(usize, Vec<String>)>,
    time: Vec<f64>,
}

impl DiagnosticsTable {
    /// Read and check the file at `path`.
    pub fn read(path: &Path) -> Result<Self, PlotError> {
        Self::read_lines(path, false)
    }

    /// Read and check the table of a run that was killed before it
    /// finished (`diagnostics.csv.partial`): its rows up to the last whole
    /// line (the last may have been cut in the middle).
    pub fn read_unfinished(path: &Path) -> Result<Self, PlotError> {
        Self::read_lines(path, true)
    }

    /// Read the file at `path`, up to its last line break when
    /// `whole_lines_only`.
    fn read_lines(path: &Path, whole_lines_only: bool) -> Result<Self, PlotError> {
        let mut bytes = std::fs::read(path).map_err(|source| PlotError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        if whole_lines_only {
            let whole = bytes
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(0, |end| end + 1);
            bytes.truncate(whole);
        }
        let text = String::from_utf8(bytes).map_err(|e| {
            let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            PlotError::Malformed {
                path: path.to_path_buf(),
                line: 1 + good.iter().filter(|&&b| b == b'\n').count(),
                message: "not UTF-8 text".into(),
            }
        })?;
        Self::parse(&text, path)
    }

    /// Parse `text`, the content of the file `path` (named in errors).
    pub fn parse(text: &str, path: &Path) -> Result<Self, PlotError> {
        let fail = |line: usize, message: String| PlotError::Malformed {
            path: path.to_path_buf(),
            line,
            message,
        };
        let mut lines = text
            .split('\n')
            .map(|l| l.strip_suffix('\r').unwrap_or(l))
            .enumerate()
            .map(|(i, l)| (i + 1, l))
            .filter(|(_, l)| !l.trim().is_empty());
        let expected = REQUIRED_COLUMNS.join(",");
        let Some((header_line, header)) = lines.next() else {
            return Err(fail(
                1,
                format!("empty file: expected the header `{expected}`"),
            ));
        };
        let names: Vec<String> = header.split(',').map(|c| c.trim().to_string()).collect();
        check_header(&names, &expected).map_err(|m| fail(header_line, m))?;
        let mut columns = vec![Vec::new(); names.len()];
        let mut texts: Vec<(usize, Vec<String>)> = (0..names.len())
            .filter(|&i| TEXT_COLUMNS.contains(&names[i].as_str()))
            .map(|i| (i, Vec::new()))
            .collect();
        for (number, line) in lines {
            let cells: Vec<&str> = line.split(',').collect();
            if cells.len() != names.len() {
                return Err(fail(
                    number,
                    format!(
                        "{} values, expected {} (one per column of the header on line {header_line})",
                        cells.len(),
                        names.len()
                    ),
                ));
            }
            for (index, cell) in cells.iter().enumerate() {
                if let Some((_, text)) = texts.iter_mut().find(|(i, _)| *i == index) {
                    let word = cell.trim();
                    if !word.chars().all(|c| c.is_ascii_lowercase() || c == '_') {
                        let shown: String = word.chars().take(40).collect();
                        return Err(fail(
                            number,
                            format!(
                                "column {} (`{}`): `{shown}` is not a name",
                                index + 1,
                                names[index]
                            ),
                        ));
                    }
                    text.push(word.to_string());
                    columns[index].push(None);
                    continue;
                }
                let value = parse_cell(cell, index < 2).map_err(|m| {
                    fail(
                        number,
                        format!("column {} (`{}`): {m}", index + 1, names[index]),
                    )
                })?;
                columns[index].push(value);
            }
        }
        let time: Vec<f64> = columns[1].iter().map(|t| t.unwrap_or(f64::NAN)).collect();
        if time.is_empty() {
            return Err(fail(
                header_line,
                "a header but no rows: the run recorded nothing".into(),
            ));
        }
        Ok(DiagnosticsTable {
            path: path.to_path_buf(),
            names,
            columns,
            texts,
            time,
        })
    }

    /// The file this table was read from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The column names, in the file's order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Number of rows (recorded steps).
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// Whether there are no rows (never true for a table that was read).
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// The `time` column (s), one value per row, always present and finite.
    pub fn time(&self) -> &[f64] {
        &self.time
    }

    /// The column `name` (in its own unit), `None` where a cell is empty
    /// or not finite; `None` for a column the file does not have.
    pub fn column(&self, name: &str) -> Option<&[Option<f64>]> {
        let index = self.names.iter().position(|n| n == name)?;
        Some(&self.columns[index])
    }

    /// The cells of the text column `name` (`solver_preconditioner`), if it is
    /// one and present (empty strings for empty cells).
    pub fn text_column(&self, name: &str) -> Option<&[String]> {
        let index = self.names.iter().position(|n| n == name)?;
        self.texts
            .iter()
            .find(|(i, _)| *i == index)
            .map(|(_, cells)| &cells[..])
    }

    /// The names of the bodies (from the `NAME.volume`, ..., `NAME.cz`
    /// columns), in the file's order.
    pub fn bodies(&self) -> Vec<String> {
        self.prefixes(&BODY_SUFFIXES)
    }

    /// The probed points (`p3` for the columns `p3.x`, `p3.y`, `p3.z`), in
    /// the file's order.
    pub fn probes(&self) -> Vec<String> {
        self.prefixes(&POINT_SUFFIXES)
    }

    /// Whether every value of the column `name` is missing or zero.
    pub fn is_zero(&self, name: &str) -> bool {
        let nonzero = |v: &Option<f64>| matches!(v, Some(x) if *x != 0.0);
        !self.column(name).is_some_and(|c| c.iter().any(nonzero))
    }

    /// Whether the column `name` exists and has at least one value.
    pub fn has_values(&self, name: &str) -> bool {
        self.column(name)
            .is_some_and(|c| c.iter().any(Option::is_some))
    }

    /// The energy's terms, as the run's world listed them: the columns
    /// from `kinetic` up to `contacts` (or up to the first column of a body
    /// or probe, in tables from before that column), `total` left out.
    pub fn energy_terms(&self) -> Vec<String> {
        self.names
            .iter()
            .skip(2)
            .take_while(|name| *name != "contacts" && !name.contains('.'))
            .filter(|name| *name != "total")
            .cloned()
            .collect()
    }

    /// Whether `name` is a column of the energy (`total` included), in J.
    pub fn is_energy(&self, name: &str) -> bool {
        name == "total" || self.energy_terms().iter().any(|term| term == name)
    }

    fn prefixes(&self, suffixes: &[&str]) -> Vec<String> {
        let mut found: Vec<String> = Vec::new();
        for name in &self.names {
            if let Some((prefix, suffix)) = name.rsplit_once('.') {
                if suffixes.contains(&suffix) && !found.iter().any(|f| f == prefix) {
                    found.push(prefix.to_string());
                }
            }
        }
        found
    }
}

/// The header must start with [`REQUIRED_COLUMNS`] and name each column
/// once.
fn check_header(names: &[String], expected: &str) -> Result<(), String> {
    let starts_right = names.len() >= REQUIRED_COLUMNS.len()
        && names.iter().zip(REQUIRED_COLUMNS).all(|(n, r)| n == r);
    if !starts_right {
        let found: String = names.join(",").chars().take(80).collect();
        return Err(format!(
            "missing or wrong header: expected it to start with `{expected}`, found `{found}`"
        ));
    }
    for (index, name) in names.iter().enumerate() {
        if name.is_empty() {
            return Err(format!("column {} of the header has no name", index + 1));
        }
        if names[..index].contains(name) {
            return Err(format!(
                "column {} (`{name}`) is named twice in the header",
                index + 1
            ));
        }
    }
    Ok(())
}

/// A cell: empty is missing (refused where `required`), otherwise a number;
/// a non-finite number counts as missing.
fn parse_cell(cell: &str, required: bool) -> Result<Option<f64>, String> {
    let cell = cell.trim();
    if cell.is_empty() {
        return if required {
            Err("empty, but every row needs a value here".into())
        } else {
            Ok(None)
        };
    }
    let value: f64 = cell.parse().map_err(|_| {
        let shown: String = cell.chars().take(40).collect();
        format!("`{shown}` is not a number")
    })?;
    if value.is_finite() {
        Ok(Some(value))
    } else if required {
        Err(format!("`{cell}` is not a finite number"))
    } else {
        Ok(None)
    }
}
