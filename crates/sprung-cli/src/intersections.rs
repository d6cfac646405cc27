//! `sprung check --intersections RUN_DIR`: count, frame by frame, the
//! particles that passed through a surface since the frame before and the
//! edges through triangles, from the run's frames alone
//! ([`sprung_io::crossings`]).

use std::path::Path;

use sprung_io::crossings::{count, Crossings, Surfaces};
use sprung_io::export::read_vtk_frame;
use sprung_view::render::frame_files;

use crate::error::CliError;

/// Print the crossings of every frame of the run in `dir` that has any,
/// and the totals. Exit status 1 when a surface passed through another
/// body's; crossings within one body (a fold through itself, which only
/// `self_collision` prevents) are counted but do not fail the check.
pub fn run(dir: &Path) -> Result<(), CliError> {
    let files = frame_files(dir).map_err(|e| CliError::Input(e.to_string()))?;
    let mut before: Option<Surfaces> = None;
    let mut total = Crossings::default();
    let mut failing = 0;
    println!("frame step time_s points_between edges_between points_within edges_within");
    for (k, file) in files.iter().enumerate() {
        let text = std::fs::read_to_string(file)
            .map_err(|e| CliError::Input(format!("{}: {e}", file.display())))?;
        let frame = read_vtk_frame(&text, file).map_err(|e| CliError::Input(e.to_string()))?;
        let now = Surfaces::of_frame(&frame);
        let found = count(before.as_ref(), &now);
        if found != Crossings::default() {
            println!(
                "{k} {} {} {} {} {} {}",
                frame.step.map_or("-".into(), |s| s.to_string()),
                frame.time.map_or("-".into(), |t| t.to_string()),
                found.points_between,
                found.edges_between,
                found.points_within,
                found.edges_within
            );
        }
        failing += usize::from(found.between() > 0);
        total += found;
        before = Some(now);
    }
    println!(
        "total {} frames: {} {} {} {}",
        files.len(),
        total.points_between,
        total.edges_between,
        total.points_within,
        total.edges_within
    );
    if failing > 0 {
        return Err(CliError::Input(format!(
            "{}: surfaces of different bodies passed through each other in {failing} of {} frames",
            dir.display(),
            files.len()
        )));
    }
    Ok(())
}
