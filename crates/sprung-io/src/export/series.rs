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
        let files: Vec<serde_json::Value> = times
            .iter()
            .enumerate()
            .map(|(index, &time)| serde_json::json!({ "name": name(index), "time": time }))
            .collect();
        let series = serde_json::json!({
            "file-series-version": "1.0",
            "bodies": bodies,
            "files": files,
        });
        out = serde_json::to_string_pretty(&series).map_err(io::Error::other)?;
        out.push('\n');
    }
    AtomicFile::write(&path, out.as_bytes())
}

/// `text` safe inside an XML comment (no `--`).
fn xml_comment(text: &str) -> String {
    text.replace("--", "- -")
}
