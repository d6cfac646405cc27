//! Reading VTK frames back, as `sprung run --format vtu|vtk` writes them
//! (and as ParaView and other tools write simple ones): legacy ASCII
//! `POLYDATA` and `UNSTRUCTURED_GRID` here, VTK XML `.vtu` in `vtu_read`;
//! points, cells sorted into the four polydata kinds, and point, cell and
//! field data (`SCALARS`, `VECTORS`, `NORMALS`, `FIELD` arrays).
//!
//! Nothing in the file is trusted: every count is checked against what
//! follows, every index against the points, and any problem is a
//! [`VtkReadError`] naming the file and line, never a panic. The format is
//! the one of *The VTK User's Guide*, "VTK File Formats" (legacy format).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use sprung::{Real, Vec3};

/// A legacy VTK frame read from text.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VtkFrame {
    /// The title line (the file's second line).
    pub title: String,
    /// The step number, when the title is sprung's `... step N time T s`.
    pub step: Option<u64>,
    /// The simulated time (s), when the title is sprung's `... time T s`.
    pub time: Option<Real>,
    /// Point positions (m).
    pub points: Vec<Vec3>,
    /// `VERTICES` cells (point indices).
    pub vertices: Vec<Vec<u32>>,
    /// `LINES` cells (point indices; sprung's springs have two each).
    pub lines: Vec<Vec<u32>>,
    /// `POLYGONS` cells (point indices; sprung's faces are triangles,
    /// counter-clockwise seen from outside).
    pub polygons: Vec<Vec<u32>>,
    /// `TRIANGLE_STRIPS` cells (point indices).
    pub strips: Vec<Vec<u32>>,
    /// Point data arrays by name, one tuple per point.
    pub point_data: BTreeMap<String, DataArray>,
    /// Cell data arrays by name, one tuple per cell, in the format's cell
    /// order: vertices, lines, polygons, strips (the cells of an
    /// unstructured grid are sorted into these, their data with them).
    pub cell_data: BTreeMap<String, DataArray>,
    /// Field data arrays by name (`TIME`: the simulated time, s).
    pub field_data: BTreeMap<String, DataArray>,
}

/// One data array: `values.len() == components × tuples`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DataArray {
    /// Components per tuple (1 for scalars, 3 for vectors).
    pub components: usize,
    /// The values, tuple after tuple (in the file's units).
    pub values: Vec<Real>,
}

impl VtkFrame {
    /// Total number of cells of all four kinds.
    pub fn cell_count(&self) -> usize {
        self.vertices.len() + self.lines.len() + self.polygons.len() + self.strips.len()
    }

    /// The values of the one-component cell array `name` for the `LINES`
    /// cells (one per line, in order), if the file has it.
    pub fn line_scalars(&self, name: &str) -> Option<&[Real]> {
        let array = self.cell_data.get(name).filter(|a| a.components == 1)?;
        let start = self.vertices.len();
        array.values.get(start..start + self.lines.len())
    }

    /// The values of the one-component point array `name`, if present.
    pub fn point_scalars(&self, name: &str) -> Option<&[Real]> {
        let array = self.point_data.get(name).filter(|a| a.components == 1)?;
        Some(&array.values)
    }
}

/// Why a VTK frame could not be read: the file, the line (1-based) and what
/// is wrong there.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}:{line}: {message}", file.display())]
pub struct VtkReadError {
    /// The file read.
    pub file: PathBuf,
    /// The line of the problem (1-based; the last line when the file ends
    /// early).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Read a VTK frame from `text`: VTK XML (`.vtu`, when the text starts
/// with `<`) or legacy ASCII polydata or unstructured grid; `file` names it
/// in errors. Binary legacy files, other datasets, cells that are not
/// points, lines or polygons, and malformed content are refused with the
/// file and line.
pub fn read_vtk_frame(text: &str, file: &Path) -> Result<VtkFrame, VtkReadError> {
    let mut frame = if text.trim_start().starts_with('<') {
        super::vtu_read::read_vtu(text, file)?
    } else {
        Reader::new(text, file).read()?
    };
    if frame.time.is_none() {
        frame.time = frame
            .field_data
            .get("TIME")
            .and_then(|a| a.values.first().copied());
    }
    Ok(frame)
}

/// Sort the cells of an unstructured grid (`cells` with their VTK `types`)
/// into `frame`'s vertices, lines, polygons and strips, and reorder its
/// cell data the same way; `line` places an error. Cell types other than
/// vertices, lines, triangles, polygons, quads and strips are refused.
pub(crate) fn sort_cells(
    frame: &mut VtkFrame,
    cells: Vec<Vec<u32>>,
    types: &[u8],
    file: &Path,
    line: usize,
) -> Result<(), VtkReadError> {
    let error = |message: String| VtkReadError {
        file: file.to_path_buf(),
        line,
        message,
    };
    if types.len() != cells.len() {
        return Err(error(format!(
            "{} cell types for {} cells",
            types.len(),
            cells.len()
        )));
    }
    // The group of each cell: 0 vertices, 1 lines, 2 polygons, 3 strips.
    let mut groups = Vec::with_capacity(cells.len());
    for &t in types {
        groups.push(match t {
            1 | 2 => 0,
            3 | 4 => 1,
            5 | 7 | 9 => 2,
            6 => 3,
            other => {
                return Err(error(format!(
                    "cell type {other} is not a point, line or polygon"
                )))
            }
        });
    }
    let mut order: Vec<usize> = (0..cells.len()).collect();
    order.sort_by_key(|&c| groups[c]);
    let mut cells: Vec<Option<Vec<u32>>> = cells.into_iter().map(Some).collect();
    for &c in &order {
        let cell = cells[c].take().unwrap_or_default();
        match groups[c] {
            0 => frame.vertices.push(cell),
            1 => frame.lines.push(cell),
            2 => frame.polygons.push(cell),
            _ => frame.strips.push(cell),
        }
    }
    for array in frame.cell_data.values_mut() {
        let k = array.components;
        if array.values.len() != k * order.len() {
            continue;
        }
        array.values = order
            .iter()
            .flat_map(|&c| array.values[c * k..(c + 1) * k].to_vec())
            .collect();
    }
    Ok(())
}

/// Which attribute section is open.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Section {
    None,
    Point(usize),
    Cell(usize),
}

struct Reader<'a> {
    file: &'a Path,
    lines: Vec<&'a str>,
    tokens: Vec<(&'a str, usize)>,
    next: usize,
}

impl<'a> Reader<'a> {
    fn new(text: &'a str, file: &'a Path) -> Self {
        let lines: Vec<&str> = text.lines().collect();
        let tokens = lines
            .iter()
            .enumerate()
            .skip(2)
            .flat_map(|(n, line)| line.split_whitespace().map(move |t| (t, n + 1)))
            .collect();
        Reader {
            file,
            lines,
            tokens,
            next: 0,
        }
    }

    fn error(&self, line: usize, message: impl Into<String>) -> VtkReadError {
        VtkReadError {
            file: self.file.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    /// The line of the token about to be read (or the last line).
    fn line(&self) -> usize {
        self.tokens
            .get(self.next)
            .map_or(self.lines.len().max(1), |t| t.1)
    }

    fn token(&mut self, what: &str) -> Result<(&'a str, usize), VtkReadError> {
        match self.tokens.get(self.next) {
            Some(&t) => {
                self.next += 1;
                Ok(t)
            }
            None => Err(self.error(
                self.line(),
                format!("the file ends where {what} was expected"),
            )),
        }
    }

    fn peek_is(&self, keyword: &str) -> bool {
        self.tokens
            .get(self.next)
            .is_some_and(|t| t.0.eq_ignore_ascii_case(keyword))
    }

    fn count(&mut self, what: &str) -> Result<usize, VtkReadError> {
        let (token, line) = self.token(what)?;
        token
            .parse()
            .map_err(|_| self.error(line, format!("{what}: \"{token}\" is not a count")))
    }

    fn number(&mut self, what: &str) -> Result<Real, VtkReadError> {
        let (token, line) = self.token(what)?;
        token
            .parse()
            .map_err(|_| self.error(line, format!("{what}: \"{token}\" is not a number")))
    }

    /// `n` numbers, without trusting `n` for the allocation.
    fn numbers(&mut self, n: usize, what: &str) -> Result<Vec<Real>, VtkReadError> {
        let available = self.tokens.len().saturating_sub(self.next);
        let mut values = Vec::with_capacity(n.min(available));
        for _ in 0..n {
            values.push(self.number(what)?);
        }
        Ok(values)
    }

    fn read(mut self) -> Result<VtkFrame, VtkReadError> {
        let header = self.lines.first().copied().unwrap_or_default();
        if !header.trim_start().starts_with("# vtk DataFile") {
            return Err(self.error(1, "not a legacy VTK file (no \"# vtk DataFile\" header)"));
        }
        let title = self.lines.get(1).copied().unwrap_or_default().trim();
        let mut frame = VtkFrame {
            title: title.to_string(),
            step: title_value(title, "step"),
            time: title_value(title, "time"),
            ..Default::default()
        };
        let (format, line) = self.token("ASCII")?;
        if !format.eq_ignore_ascii_case("ASCII") {
            return Err(self.error(
                line,
                format!("\"{format}\": only ASCII VTK files can be read"),
            ));
        }
        self.keyword("DATASET")?;
        let (dataset, line) = self.token("the dataset type")?;
        let grid = dataset.eq_ignore_ascii_case("UNSTRUCTURED_GRID");
        if !(grid || dataset.eq_ignore_ascii_case("POLYDATA")) {
            return Err(self.error(
                line,
                format!("DATASET {dataset}: only POLYDATA and UNSTRUCTURED_GRID can be read"),
            ));
        }
        let mut section = Section::None;
        // An unstructured grid's cells, sorted by type at the end.
        let mut grid_cells: Vec<Vec<u32>> = Vec::new();
        let mut grid_types: Vec<u8> = Vec::new();
        let mut types_line = 1;
        while self.next < self.tokens.len() {
            let (keyword, line) = self.token("a section")?;
            match keyword.to_ascii_uppercase().as_str() {
                "POINTS" => self.points(&mut frame, line)?,
                "CELLS" if grid => {
                    grid_cells = self.cells(&frame, "CELLS")?;
                    // Counted as vertices until sorted, for CELL_DATA's count.
                    frame.vertices = vec![Vec::new(); grid_cells.len()];
                }
                "CELL_TYPES" if grid => {
                    types_line = line;
                    let n = self.count("the number of cell types")?;
                    grid_types = self
                        .numbers(n, "a cell type")?
                        .into_iter()
                        .map(|t| {
                            if (0.0..=255.0).contains(&t) {
                                t as u8
                            } else {
                                0
                            }
                        })
                        .collect();
                }
                "FIELD" if section == Section::None => self.field(&mut frame, Section::None)?,
                "VERTICES" => frame.vertices = self.cells(&frame, "VERTICES")?,
                "LINES" => frame.lines = self.cells(&frame, "LINES")?,
                "POLYGONS" => frame.polygons = self.cells(&frame, "POLYGONS")?,
                "TRIANGLE_STRIPS" => frame.strips = self.cells(&frame, "TRIANGLE_STRIPS")?,
                "POINT_DATA" => section = Section::Point(self.attribute_count(&frame, line, true)?),
                "CELL_DATA" => section = Section::Cell(self.attribute_count(&frame, line, false)?),
                "SCALARS" | "VECTORS" | "NORMALS" | "FIELD" | "LOOKUP_TABLE" => {
                    self.attribute(&mut frame, section, keyword, line)?
                }
                _ => return Err(self.error(line, format!("unknown section \"{keyword}\""))),
            }
        }
        if grid {
            frame.vertices.clear();
            sort_cells(&mut frame, grid_cells, &grid_types, self.file, types_line)?;
        }
        Ok(frame)
    }

    fn keyword(&mut self, expected: &str) -> Result<(), VtkReadError> {
        let (token, line) = self.token(expected)?;
        if token.eq_ignore_ascii_case(expected) {
            Ok(())
        } else {
            Err(self.error(line, format!("expected {expected}, found \"{token}\"")))
        }
    }

    fn points(&mut self, frame: &mut VtkFrame, line: usize) -> Result<(), VtkReadError> {
        let n = self.count("the number of points")?;
        self.token("the point type")?;
        let coordinates = n
            .checked_mul(3)
            .ok_or_else(|| self.error(line, "too many points"))?;
        let start = self.line();
        let values = self.numbers(coordinates, "a point coordinate")?;
        if let Some(bad) = values.iter().position(|v| !v.is_finite()) {
            let line = self
                .tokens
                .get(self.next - coordinates + bad)
                .map_or(start, |t| t.1);
            return Err(self.error(line, "a point coordinate is not finite"));
        }
        frame.points = values
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        Ok(())
    }

    fn cells(&mut self, frame: &VtkFrame, kind: &str) -> Result<Vec<Vec<u32>>, VtkReadError> {
        let n = self.count(&format!("the number of {kind}"))?;
        let size = self.count(&format!("the size of {kind}"))?;
        let available = self.tokens.len().saturating_sub(self.next);
        let mut cells = Vec::with_capacity(n.min(available));
        let mut read = 0usize;
        for _ in 0..n {
            let k = self.count("the number of points of a cell")?;
            let mut cell = Vec::with_capacity(k.min(available));
            for _ in 0..k {
                let (token, line) = self.token("a point index")?;
                let index: u32 = token
                    .parse()
                    .map_err(|_| self.error(line, format!("\"{token}\" is not a point index")))?;
                if index as usize >= frame.points.len() {
                    return Err(self.error(
                        line,
                        format!(
                            "point index {index} out of range (the file has {} points)",
                            frame.points.len()
                        ),
                    ));
                }
                cell.push(index);
            }
            read = read.saturating_add(k + 1);
            cells.push(cell);
        }
        if read != size {
            let line = self.line();
            return Err(self.error(
                line,
                format!("{kind} says its cells hold {size} numbers, they hold {read}"),
            ));
        }
        Ok(cells)
    }

    fn attribute_count(
        &mut self,
        frame: &VtkFrame,
        line: usize,
        points: bool,
    ) -> Result<usize, VtkReadError> {
        let n = self.count("the number of values")?;
        let (expected, what) = if points {
            (frame.points.len(), "points")
        } else {
            (frame.cell_count(), "cells")
        };
        if n != expected {
            return Err(self.error(
                line,
                format!("data for {n} {what}, but the file has {expected}"),
            ));
        }
        Ok(n)
    }

    fn attribute(
        &mut self,
        frame: &mut VtkFrame,
        section: Section,
        keyword: &str,
        line: usize,
    ) -> Result<(), VtkReadError> {
        let tuples = match section {
            Section::Point(n) | Section::Cell(n) => n,
            Section::None => {
                return Err(self.error(line, format!("{keyword} before POINT_DATA or CELL_DATA")))
            }
        };
        let keyword = keyword.to_ascii_uppercase();
        if keyword == "LOOKUP_TABLE" {
            // A colour table: name, size, then RGBA per entry; not used.
            self.token("the table name")?;
            let size = self.count("the table size")?;
            let values = size
                .checked_mul(4)
                .ok_or_else(|| self.error(line, "table too large"))?;
            self.numbers(values, "a table colour")?;
            return Ok(());
        }
        if keyword == "FIELD" {
            return self.field(frame, section);
        }
        let (name, _) = self.token("the array name")?;
        self.token("the value type")?;
        let components = if keyword == "SCALARS" {
            let components = if self.peek_is("LOOKUP_TABLE") {
                1
            } else {
                self.count("the number of components")?
            };
            self.keyword("LOOKUP_TABLE")?;
            self.token("the lookup table name")?;
            components
        } else {
            3
        };
        self.store(frame, section, name, components, tuples, line)
    }

    fn field(&mut self, frame: &mut VtkFrame, section: Section) -> Result<(), VtkReadError> {
        self.token("the field name")?;
        let arrays = self.count("the number of arrays")?;
        for _ in 0..arrays {
            let (name, line) = self.token("the array name")?;
            let components = self.count("the number of components")?;
            let tuples = self.count("the number of tuples")?;
            self.token("the value type")?;
            self.store(frame, section, name, components, tuples, line)?;
        }
        Ok(())
    }

    fn store(
        &mut self,
        frame: &mut VtkFrame,
        section: Section,
        name: &str,
        components: usize,
        tuples: usize,
        line: usize,
    ) -> Result<(), VtkReadError> {
        let n = components
            .checked_mul(tuples)
            .ok_or_else(|| self.error(line, format!("{name}: array too large")))?;
        let values = self.numbers(n, &format!("a value of {name}"))?;
        let array = DataArray { components, values };
        let target = match section {
            Section::Cell(_) => &mut frame.cell_data,
            Section::Point(_) => &mut frame.point_data,
            Section::None => &mut frame.field_data,
        };
        target.insert(name.to_string(), array);
        Ok(())
    }
}

/// The value after `key` in a title like `sprung frame: step 40 time 0.04 s`.
pub(crate) fn title_value<T: std::str::FromStr>(title: &str, key: &str) -> Option<T> {
    let mut words = title.split_whitespace();
    words.find(|w| *w == key)?;
    words.next()?.parse().ok()
}
