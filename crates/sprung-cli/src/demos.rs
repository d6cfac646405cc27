//! `sprung demo`: the built-in scenes (`sprung_io::demos`, compiled into the
//! binary with their meshes, so that `sprung demo` works from any folder).

use std::path::{Path, PathBuf};

use sprung::IntegratorKind;
use sprung_io::demos::{self, Bundled, DEFAULT_DEMO, DEMOS};
use sprung_io::export::{FrameFormat, OutputFormat};
use sprung_io::parse_scene_overridden;

use crate::error::CliError;
use crate::run::run_scene;
use crate::RunOptions;

/// Print the demos, one a line.
pub fn list() {
    for demo in DEMOS {
        let default = if demo.name == DEFAULT_DEMO {
            " (default)"
        } else {
            ""
        };
        println!("{:<16} {}{default}", demo.name, demo.about);
    }
}

/// `path` with the integrator's name before its extension
/// (`o.state` → `o.rk4.state`, `o` → `o.rk4`): the state file of one of a
/// demo's runs with every integrator.
fn per_integrator(path: &Path, kind: IntegratorKind) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    let name = match path.extension() {
        Some(extension) => format!("{stem}.{}.{}", kind.name(), extension.to_string_lossy()),
        None => format!("{stem}.{}", kind.name()),
    };
    path.with_file_name(name)
}

/// Run the demo `name` (or the default one).
pub fn run(name: Option<&str>, options: &RunOptions) -> Result<(), CliError> {
    let name = name.unwrap_or(DEFAULT_DEMO);
    let demo = demos::find(name).ok_or_else(|| {
        let names: Vec<_> = DEMOS.iter().map(|d| d.name).collect();
        CliError::Input(format!(
            "no demo named \"{name}\" (demos: {})",
            names.join(", ")
        ))
    })?;
    if demo.every_integrator && options.integrator.is_some() {
        return Err(CliError::Input(format!(
            "the \"{}\" demo runs every integrator: --integrator does not apply (use `sprung run` on its scene for one)",
            demo.name
        )));
    }
    let out = options
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("demo").join(demo.name));
    let mut options = options.clone();
    options.format = options
        .format
        .or(Some(OutputFormat::Frames(FrameFormat::Vtu)));
    let kinds: Vec<Option<IntegratorKind>> = if demo.every_integrator {
        IntegratorKind::ALL.into_iter().map(Some).collect()
    } else {
        vec![options.integrator]
    };
    let (save_state, resume) = (options.save_state.clone(), options.resume.clone());
    for kind in kinds {
        let scene = parse_scene_overridden(demo.text, &demo.path(), &options.set, &Bundled)?;
        let folder = match (demo.every_integrator, kind) {
            (true, Some(kind)) => out.join(kind.name()),
            _ => out.clone(),
        };
        // One run per integrator: each saves (and resumes from) a state
        // of its own, named after it.
        if let (true, Some(kind)) = (demo.every_integrator, kind) {
            options.save_state = save_state.as_deref().map(|p| per_integrator(p, kind));
            options.resume = resume.as_deref().map(|p| per_integrator(p, kind));
        }
        options.integrator = kind;
        run_scene(scene, &folder, &options, None)?;
    }
    if !options.quiet {
        let frames = match options.format {
            Some(OutputFormat::Frames(FrameFormat::Vtu)) => "open frames/frames.pvd in ParaView",
            Some(OutputFormat::Frames(FrameFormat::Vtk)) => {
                "open frames/frames.vtk.series in ParaView"
            }
            Some(OutputFormat::Frames(FrameFormat::Obj)) => "frames/ for Blender",
            _ => "animation.glb for Blender",
        };
        println!(
            "demo \"{}\" ({}): results in {} (diagnostics.csv; {frames})",
            demo.name,
            demo.about,
            out.display()
        );
    }
    Ok(())
}
