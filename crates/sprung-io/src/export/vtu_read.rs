//! Reading VTK XML unstructured grids (`.vtu`) back into a [`VtkFrame`]:
//! sprung's own frames (binary arrays, zlib-compressed, `UInt64` or
//! `UInt32` block headers) and ASCII arrays as other tools write them.
//! Appended data and other compressors are refused with a clear error.
//!
//! As with the legacy reader nothing is trusted: sizes are checked against
//! the bytes there are, decompression stops at the sizes the header
//! declares (and at most [`MAX_ARRAY_BYTES`]), and every problem is a
//! [`VtkReadError`] with the file and line.

use std::io::Read;
use std::path::Path;

use base64::engine::general_purpose::STANDARD;
use base64::Engine;
use flate2::read::ZlibDecoder;
use sprung::{Real, Vec3};

use super::vtk_read::{sort_cells, title_value, DataArray, VtkFrame, VtkReadError};

/// The most bytes one array may decompress to (1 GiB).
pub const MAX_ARRAY_BYTES: u64 = 1 << 30;

/// One `<DataArray>`: its attributes, its text, and the line it starts on.
struct Element<'a> {
    attributes: &'a str,
    text: &'a str,
    line: usize,
}

impl Element<'_> {
    fn attribute(&self, name: &str) -> Option<&str> {
        attribute(self.attributes, name)
    }
}

/// The value of `name="..."` in a tag's attribute text.
fn attribute<'a>(attributes: &'a str, name: &str) -> Option<&'a str> {
    let mut rest = attributes;
    while let Some(at) = rest.find(name) {
        let after = &rest[at + name.len()..];
        let starts_word = at == 0 || rest.as_bytes()[at - 1].is_ascii_whitespace();
        if let (true, Some(value)) = (starts_word, after.trim_start().strip_prefix('=')) {
            let value = value.trim_start();
            let quote = value.chars().next()?;
            if quote == '"' || quote == '\'' {
                let end = value[1..].find(quote)?;
                return Some(&value[1..1 + end]);
            }
        }
        rest = after;
    }
    None
}

/// Read a `.vtu` frame from `text`; `file` names it in errors.
pub(crate) fn read_vtu(text: &str, file: &Path) -> Result<VtkFrame, VtkReadError> {
    let line_of = |offset: usize| text[..offset.min(text.len())].matches('\n').count() + 1;
    let error = |offset: usize, message: String| VtkReadError {
        file: file.to_path_buf(),
        line: line_of(offset),
        message,
    };
    let vtk_file = tag(text, "VTKFile").ok_or_else(|| error(0, "no <VTKFile> element".into()))?;
    if attribute(vtk_file.1, "type") != Some("UnstructuredGrid") {
        return Err(error(
            vtk_file.0,
            "only UnstructuredGrid VTK XML files can be read".into(),
        ));
    }
    if text.contains("<AppendedData") {
        return Err(error(
            vtk_file.0,
            "appended data cannot be read (write the arrays inline)".into(),
        ));
    }
    let little = attribute(vtk_file.1, "byte_order").is_none_or(|o| o == "LittleEndian");
    if !little {
        return Err(error(
            vtk_file.0,
            "only LittleEndian files can be read".into(),
        ));
    }
    let header64 = match attribute(vtk_file.1, "header_type").unwrap_or("UInt32") {
        "UInt64" => true,
        "UInt32" => false,
        other => {
            return Err(error(
                vtk_file.0,
                format!("header_type {other} is not UInt32 or UInt64"),
            ))
        }
    };
    let compressed = match attribute(vtk_file.1, "compressor") {
        None => false,
        Some("vtkZLibDataCompressor") => true,
        Some(other) => {
            return Err(error(
                vtk_file.0,
                format!("compressor {other} cannot be read (zlib only)"),
            ))
        }
    };
    let piece = tag(text, "Piece").ok_or_else(|| error(0, "no <Piece> element".into()))?;
    let count = |name: &str| -> Result<usize, VtkReadError> {
        attribute(piece.1, name)
            .and_then(|v| v.trim().parse().ok())
            .ok_or_else(|| error(piece.0, format!("<Piece> has no whole {name}")))
    };
    let (points, cells) = (count("NumberOfPoints")?, count("NumberOfCells")?);
    let decode = Decoder {
        header64,
        compressed,
    };
    let mut frame = VtkFrame {
        title: comment_title(text).unwrap_or_default(),
        ..VtkFrame::default()
    };
    frame.step = title_value(&frame.title, "step");
    frame.time = title_value(&frame.title, "time");
    let mut connectivity: Option<Vec<Real>> = None;
    let mut offsets: Option<Vec<Real>> = None;
    let mut types: Option<Vec<Real>> = None;
    let mut cells_line = 1;
    for (section, element) in elements(text) {
        let name = element.attribute("Name").unwrap_or_default().to_string();
        let components: usize = element
            .attribute("NumberOfComponents")
            .map_or(Some(1), |c| c.trim().parse().ok())
            .filter(|&c| c >= 1)
            .ok_or_else(|| {
                error_at(
                    file,
                    element.line,
                    format!("{name}: bad NumberOfComponents"),
                )
            })?;
        let values = decode
            .values(&element)
            .map_err(|m| error_at(file, element.line, format!("{name}: {m}")))?;
        let expect = |tuples: usize| -> Result<(), VtkReadError> {
            if tuples.checked_mul(components) == Some(values.len()) {
                Ok(())
            } else {
                Err(error_at(
                    file,
                    element.line,
                    format!(
                        "{name}: {} values where {tuples} tuples of {components} were declared",
                        values.len()
                    ),
                ))
            }
        };
        match section {
            "Points" => {
                expect(points)?;
                if components != 3 || values.iter().any(|v| !v.is_finite()) {
                    return Err(error_at(
                        file,
                        element.line,
                        "points must be three finite coordinates".into(),
                    ));
                }
                frame.points = values
                    .chunks_exact(3)
                    .map(|c| Vec3::new(c[0], c[1], c[2]))
                    .collect();
            }
            "Cells" => {
                cells_line = element.line;
                match name.as_str() {
                    "connectivity" => connectivity = Some(values),
                    "offsets" => {
                        expect(cells)?;
                        offsets = Some(values);
                    }
                    "types" => {
                        expect(cells)?;
                        types = Some(values);
                    }
                    _ => {}
                }
            }
            "PointData" => {
                expect(points)?;
                frame
                    .point_data
                    .insert(name, DataArray { components, values });
            }
            "CellData" => {
                expect(cells)?;
                frame
                    .cell_data
                    .insert(name, DataArray { components, values });
            }
            _ => {
                frame
                    .field_data
                    .insert(name, DataArray { components, values });
            }
        }
    }
    if frame.points.len() != points {
        return Err(error(
            piece.0,
            format!(
                "<Piece> declares {points} points, its <Points> has {}",
                frame.points.len()
            ),
        ));
    }
    let (Some(connectivity), Some(offsets), Some(types)) = (connectivity, offsets, types) else {
        return Err(error_at(
            file,
            cells_line,
            "<Cells> needs connectivity, offsets and types".into(),
        ));
    };
    let mut list = Vec::with_capacity(cells);
    let mut start = 0usize;
    for &end in &offsets {
        let end = index(end)
            .filter(|&e| e >= start && e <= connectivity.len())
            .ok_or_else(|| {
                error_at(
                    file,
                    cells_line,
                    format!("offset {end} is out of order or beyond the connectivity"),
                )
            })?;
        let cell = connectivity[start..end]
            .iter()
            .map(|&p| index(p).filter(|&p| p < points).map(|p| p as u32))
            .collect::<Option<Vec<u32>>>()
            .ok_or_else(|| {
                error_at(
                    file,
                    cells_line,
                    format!("a cell's point index is not one of the {points} points"),
                )
            })?;
        list.push(cell);
        start = end;
    }
    let types: Vec<u8> = types
        .iter()
        .map(|&t| index(t).map_or(0, |t| t.min(255) as u8))
        .collect();
    sort_cells(&mut frame, list, &types, file, cells_line)?;
    Ok(frame)
}

fn error_at(file: &Path, line: usize, message: String) -> VtkReadError {
    VtkReadError {
        file: file.to_path_buf(),
        line,
        message,
    }
}

/// `value` as an index, if it is a whole number that fits.
fn index(value: Real) -> Option<usize> {
    (value >= 0.0 && value.fract() == 0.0 && value < u32::MAX as Real).then_some(value as usize)
}

/// The title sprung writes in a comment, `sprung frame: step N time T s`.
fn comment_title(text: &str) -> Option<String> {
    let start = text.find("<!--")? + 4;
    let end = start + text[start..].find("-->")?;
    Some(text[start..end].trim().to_string())
}

/// The offset and attribute text of the first `<name ...>` tag.
fn tag<'a>(text: &'a str, name: &str) -> Option<(usize, &'a str)> {
    let mut from = 0;
    while let Some(at) = text[from..].find(&format!("<{name}")) {
        let start = from + at;
        let after = &text[start + 1 + name.len()..];
        if after.starts_with(|c: char| c.is_ascii_whitespace() || c == '>' || c == '/') {
            let end = after.find('>')?;
            return Some((start, after[..end].trim_end_matches('/')));
        }
        from = start + 1;
    }
    None
}

/// Every `<DataArray>` of `text` with the section it is in (`Points`,
/// `Cells`, `PointData`, `CellData`, `FieldData`).
fn elements(text: &str) -> Vec<(&'static str, Element<'_>)> {
    const SECTIONS: [&str; 5] = ["Points", "Cells", "PointData", "CellData", "FieldData"];
    let mut found = Vec::new();
    let mut section = "";
    let mut at = 0;
    while let Some(open) = text[at..].find('<') {
        let start = at + open;
        let Some(close) = text[start..].find('>') else {
            break;
        };
        let inside = &text[start + 1..start + close];
        at = start + close + 1;
        let name = inside
            .split(|c: char| c.is_ascii_whitespace() || c == '/')
            .next()
            .unwrap_or_default();
        if let Some(s) = SECTIONS.iter().find(|s| **s == name) {
            section = s;
        } else if name == "DataArray" {
            let self_closing = inside.ends_with('/');
            let end = if self_closing {
                at
            } else {
                text[at..]
                    .find("</DataArray>")
                    .map_or(text.len(), |e| at + e)
            };
            found.push((
                section,
                Element {
                    attributes: &inside["DataArray".len()..],
                    text: if self_closing { "" } else { &text[at..end] },
                    line: text[..start].matches('\n').count() + 1,
                },
            ));
            at = end;
        }
    }
    found
}

/// How the file's binary arrays are written.
struct Decoder {
    header64: bool,
    compressed: bool,
}

impl Decoder {
    /// The values of `element` as reals.
    fn values(&self, element: &Element) -> Result<Vec<Real>, String> {
        let kind = element.attribute("type").unwrap_or("Float64");
        match element.attribute("format").unwrap_or("ascii") {
            "ascii" => element
                .text
                .split_whitespace()
                .map(|t| {
                    t.parse::<Real>()
                        .map_err(|_| format!("\"{t}\" is not a number"))
                })
                .collect(),
            "binary" => {
                let bytes = self.bytes(element.text.trim())?;
                convert(&bytes, kind)
            }
            other => Err(format!(
                "format \"{other}\" cannot be read (ascii or binary)"
            )),
        }
    }

    fn header_size(&self) -> usize {
        if self.header64 {
            8
        } else {
            4
        }
    }

    fn read_header(&self, bytes: &[u8]) -> Vec<u64> {
        bytes
            .chunks_exact(self.header_size())
            .map(|c| {
                if self.header64 {
                    u64::from_le_bytes(c.try_into().unwrap_or_default())
                } else {
                    u64::from(u32::from_le_bytes(c.try_into().unwrap_or_default()))
                }
            })
            .collect()
    }

    /// The raw bytes of a binary array's base64 text.
    fn bytes(&self, text: &str) -> Result<Vec<u8>, String> {
        let base64 = |t: &str| STANDARD.decode(t).map_err(|e| format!("bad base64: {e}"));
        let encoded_len = |bytes: usize| bytes.div_ceil(3) * 4;
        let size = self.header_size();
        if !self.compressed {
            let all = base64(text)?;
            let length = self.read_header(all.get(..size).ok_or("cut short")?)[0];
            let data = &all[size..];
            return if length as usize == data.len() {
                Ok(data.to_vec())
            } else {
                Err(format!(
                    "the header says {length} bytes, there are {}",
                    data.len()
                ))
            };
        }
        // The header's numbers, exactly `count` of them.
        let header_of = |encoded: &str, count: usize| -> Result<Vec<u64>, String> {
            let bytes = base64(encoded)?;
            if bytes.len() != count * size {
                return Err("a block header of the wrong length".into());
            }
            Ok(self.read_header(&bytes))
        };
        let first = text.get(..encoded_len(3 * size)).ok_or("cut short")?;
        let start = header_of(first, 3)?;
        let blocks = usize::try_from(start[0]).map_err(|_| "too many blocks")?;
        let (block, last) = (start[1], start[2]);
        if last > block {
            return Err(format!("a last block of {last} bytes in blocks of {block}"));
        }
        let total = (blocks as u64)
            .saturating_mul(block)
            .min(MAX_ARRAY_BYTES + 1);
        if total > MAX_ARRAY_BYTES || blocks > text.len() {
            return Err(format!("{blocks} blocks of {block} bytes is too large"));
        }
        let header_text = text
            .get(..encoded_len((3 + blocks) * size))
            .ok_or("cut short")?;
        let header = header_of(header_text, 3 + blocks)?;
        let data = base64(&text[header_text.len()..])?;
        let mut out = Vec::new();
        let mut at = 0usize;
        for k in 0..blocks {
            let compressed = usize::try_from(header[3 + k]).map_err(|_| "block too large")?;
            let piece = data
                .get(at..at.saturating_add(compressed))
                .ok_or("a block runs past the data")?;
            at += compressed;
            let expected = if k + 1 == blocks && last != 0 {
                last
            } else {
                block
            };
            let before = out.len();
            ZlibDecoder::new(piece)
                .take(expected)
                .read_to_end(&mut out)
                .map_err(|e| format!("bad compressed data: {e}"))?;
            if (out.len() - before) as u64 != expected {
                return Err("a block decompresses to another size than declared".into());
            }
        }
        Ok(out)
    }
}

/// `bytes` as little-endian numbers of VTK type `kind`, as reals.
fn convert(bytes: &[u8], kind: &str) -> Result<Vec<Real>, String> {
    fn read<const N: usize>(
        bytes: &[u8],
        f: impl Fn([u8; N]) -> Real,
    ) -> Result<Vec<Real>, String> {
        if !bytes.len().is_multiple_of(N) {
            return Err(format!(
                "{} bytes is not a whole number of values",
                bytes.len()
            ));
        }
        Ok(bytes
            .chunks_exact(N)
            .map(|c| f(c.try_into().unwrap_or([0; N])))
            .collect())
    }
    match kind {
        "Float64" => read(bytes, f64::from_le_bytes),
        "Float32" => read(bytes, |b| Real::from(f32::from_le_bytes(b))),
        "Int64" => read(bytes, |b| i64::from_le_bytes(b) as Real),
        "UInt64" => read(bytes, |b| u64::from_le_bytes(b) as Real),
        "Int32" => read(bytes, |b| Real::from(i32::from_le_bytes(b))),
        "UInt32" => read(bytes, |b| Real::from(u32::from_le_bytes(b))),
        "Int16" => read(bytes, |b| Real::from(i16::from_le_bytes(b))),
        "UInt16" => read(bytes, |b| Real::from(u16::from_le_bytes(b))),
        "Int8" => read(bytes, |b: [u8; 1]| Real::from(b[0] as i8)),
        "UInt8" => read(bytes, |b: [u8; 1]| Real::from(b[0])),
        other => Err(format!("type {other} cannot be read")),
    }
}
