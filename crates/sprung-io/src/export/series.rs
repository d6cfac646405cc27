//! The time-series file beside a run's frames, so that ParaView plays them
//! at their physical times: `frames.pvd` (a VTK collection) for `.vtu`
//! frames, `frames.vtk.series` (ParaView's JSON file series) for legacy
//! `.vtk` frames. Both name the bodies, in the order of their index in the
//! frames' `body` arrays.

use std::fmt::Write;
use std::io;
use std::path::{Path, PathBuf};

use sprung::World;

use super::{frame_path, AtomicFile, FrameFormat, Real};

/// The series file of `format` in `dir`, if the format has one.
pub fn series_path(dir: &Path, format: FrameFormat) -> Option<PathBuf> {
    match format {
        FrameFormat::Vtu => Some(dir.join("frames.pvd")),
        FrameFormat::Vtk => Some(dir.join("frames.vtk.series")),
        FrameFormat::Obj => None,
    }
}

/// Write the series file of `format` in `dir` for frames `0..times.len()`
/// at `times` (s), atomically; nothing for a format without one.
pub fn write_series(
    dir: &Path,
    format: FrameFormat,
    world: &World,
    times: &[f64],
) -> io::Result<()> {
    let Some(path) = series_path(dir, format) else {
        return Ok(());
    };
    let name = |index: usize| {
        frame_path(Path::new(""), index, format)
            .to_string_lossy()
            .into_owned()
    };
    let bodies: Vec<&str> = world.bodies.iter().map(|b| b.name.as_str()).collect();
    let mut out = String::new();
    // Writing to a String cannot fail; the results are ignored on purpose.
    if format == FrameFormat::Vtu {
        let _ = writeln!(out, "<?xml version=\"1.0\"?>");
        let _ = writeln!(
            out,
            "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">"
        );
        for (index, body) in bodies.iter().enumerate() {
            let _ = writeln!(out, "<!-- body {index}: {} -->", xml_comment(body));
        }
        let _ = writeln!(out, "<Collection>");
        for (index, &time) in times.iter().enumerate() {
            let _ = writeln!(
                out,
                "<DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>",
                Real(time),
                name(index)
            );
        }
        let _ = writeln!(out, "</Collection>\n</VTKFile>");
    } else {
        let _ = writeln!(out, "{{\n  \"file-series-version\": \"1.0\",");
        let names: Vec<String> = bodies.iter().map(|b| json_string(b)).collect();
        let _ = writeln!(out, "  \"bodies\": [{}],", names.join(", "));
        let _ = writeln!(out, "  \"files\": [");
        for (index, &time) in times.iter().enumerate() {
            let comma = if index + 1 < times.len() { "," } else { "" };
            let _ = writeln!(
                out,
                "    {{ \"name\": \"{}\", \"time\": {} }}{comma}",
                name(index),
                Real(time)
            );
        }
        let _ = writeln!(out, "  ]\n}}");
    }
    AtomicFile::write(&path, out.as_bytes())
}

/// `text` safe inside an XML comment (no `--`).
fn xml_comment(text: &str) -> String {
    text.replace("--", "- -")
}

/// `text` as a JSON string.
fn json_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
