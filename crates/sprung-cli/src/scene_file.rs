//! The scene `sprung run` reads, from a file or from standard input (`-`),
//! with its `--set` overrides; and the copy of the effective scene it
//! keeps in the run's folder, `scene.toml` with the meshes it names in
//! `meshes/`, so that `sprung run OUT/scene.toml` repeats the run from the
//! folder alone.

use std::io::Read;
use std::path::{Path, PathBuf};

use sprung_io::export::AtomicFile;
use sprung_io::input::{max_input_bytes, read_input, DEFAULT_MAX_SCENE_BYTES};
use sprung_io::scene::{overridden_table, scene_text, scene_toml};
use sprung_io::toml::Value;
use sprung_io::{parse_scene_overridden, Disk, FileSource, Override, Scene, SceneError};

use crate::run::CliError;

/// The name of standard input in messages and as the scene's path.
const STDIN: &str = "<stdin>";

/// A scene's text and where it came from.
pub struct SceneInput {
    /// The text, UTF-8.
    text: String,
    /// Its name in messages: the file, or `<stdin>`.
    pub path: PathBuf,
    /// The folder its relative paths (meshes) start from.
    dir: PathBuf,
    /// Read from standard input.
    stdin: bool,
}

/// Files read from the disk, relative paths from `0`: the meshes of a
/// scene read from standard input.
struct BaseDir(PathBuf);

impl FileSource for BaseDir {
    fn read(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        Disk.read(&self.0.join(path))
    }
}

impl SceneInput {
    /// Read the scene file at `path`, or standard input for `-`, whose
    /// relative paths start from `base_dir` (default: the current folder).
    pub fn read(path: &Path, base_dir: Option<&Path>) -> Result<Self, CliError> {
        if path != Path::new("-") {
            if let Some(dir) = base_dir {
                return Err(CliError::Input(format!(
                    "--base-dir {}: applies to a scene read from standard input (`-`); a scene file's paths start from its own folder",
                    dir.display()
                )));
            }
            let bytes = read_input(path, DEFAULT_MAX_SCENE_BYTES).map_err(|e| {
                SceneError::new(path, None, format!("cannot read the scene file: {e}"))
            })?;
            return Ok(SceneInput {
                text: scene_text(&bytes, path)?.to_string(),
                path: path.to_path_buf(),
                dir: path.parent().unwrap_or(Path::new("")).to_path_buf(),
                stdin: false,
            });
        }
        let name = Path::new(STDIN);
        let unreadable = |e: std::io::Error| {
            SceneError::new(
                name,
                None,
                format!("cannot read the scene from standard input: {e}"),
            )
        };
        let limit = max_input_bytes(DEFAULT_MAX_SCENE_BYTES).map_err(unreadable)?;
        let mut bytes = Vec::new();
        std::io::stdin()
            .lock()
            .take(limit + 1)
            .read_to_end(&mut bytes)
            .map_err(unreadable)?;
        if bytes.len() as u64 > limit {
            return Err(unreadable(std::io::Error::other(format!(
                "more than the {limit} bytes a scene may have (set {} to raise the limit)",
                sprung_io::input::MAX_INPUT_VARIABLE
            )))
            .into());
        }
        Ok(SceneInput {
            text: scene_text(&bytes, name)?.to_string(),
            path: name.to_path_buf(),
            dir: base_dir.unwrap_or(Path::new("")).to_path_buf(),
            stdin: true,
        })
    }

    /// The default output folder: out/STEM, or out/stdin.
    pub fn default_out(&self) -> PathBuf {
        let stem = match self.stdin {
            true => "stdin".into(),
            false => self.path.file_stem().unwrap_or_default().to_string_lossy(),
        };
        Path::new("out").join(stem.as_ref())
    }

    /// Build the scene with `overrides` applied.
    pub fn load(&self, overrides: &[Override]) -> Result<Scene, CliError> {
        let scene = match self.stdin {
            true => {
                let files = BaseDir(self.dir.clone());
                parse_scene_overridden(&self.text, &self.path, overrides, &files)
            }
            false => parse_scene_overridden(&self.text, &self.path, overrides, &Disk),
        };
        Ok(scene?)
    }

    /// The copy of the effective scene (with `overrides`) for a run's
    /// folder: the text as given when nothing is overridden and it names
    /// no mesh, else the effective tables written out with each mesh path
    /// made `meshes/NAME`.
    pub fn copy(&self, overrides: &[Override]) -> Result<SceneCopy, CliError> {
        // A scene without the word `mesh` (nor an escape that could spell
        // it) names no mesh file.
        if overrides.is_empty() && !self.text.contains("mesh") && !self.text.contains('\\') {
            return Ok(SceneCopy {
                text: self.text.clone(),
                meshes: Vec::new(),
            });
        }
        let mut table = overridden_table(&self.text, &self.path, overrides)?;
        let mut meshes: Vec<(PathBuf, String)> = Vec::new();
        let bodies = table.get_mut("body").and_then(Value::as_array_mut);
        for body in bodies.into_iter().flatten() {
            let Some(Value::String(mesh)) = body.get_mut("mesh") else {
                continue;
            };
            let source = self.dir.join(&*mesh);
            let name = match meshes.iter().find(|(s, _)| *s == source) {
                Some((_, name)) => name.clone(),
                None => {
                    let name = free_name(&source, &meshes);
                    meshes.push((source, name.clone()));
                    name
                }
            };
            *mesh = format!("meshes/{name}");
        }
        Ok(SceneCopy {
            text: scene_toml(&table, &self.path)?,
            meshes,
        })
    }
}

/// A file name in `meshes/` for `source` that no other mesh has taken:
/// its own, or `STEM-2.EXT`, `STEM-3.EXT`, ...
fn free_name(source: &Path, taken: &[(PathBuf, String)]) -> String {
    let file = source.file_name().unwrap_or_default().to_string_lossy();
    let stem = source.file_stem().unwrap_or_default().to_string_lossy();
    let extension = source
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    (1..)
        .map(|n| match n {
            1 => file.to_string(),
            n => format!("{stem}-{n}{extension}"),
        })
        .find(|name| !taken.iter().any(|(_, t)| t == name))
        .unwrap_or_default()
}

/// The effective scene of a run, to be written into its folder.
pub struct SceneCopy {
    /// The text of `scene.toml`.
    text: String,
    /// Each mesh file and its name in `meshes/`.
    meshes: Vec<(PathBuf, String)>,
}

impl SceneCopy {
    /// The mesh files the scene reads (their paths on the disk).
    pub fn mesh_sources(&self) -> impl Iterator<Item = &Path> {
        self.meshes.iter().map(|(source, _)| source.as_path())
    }

    /// Write `out/meshes/NAME` for each mesh, then `out/scene.toml`, each
    /// atomically (a mesh of the scene that is already there, as when the
    /// run's own copy is run again into its folder, is read whole before
    /// it is replaced).
    pub fn write(&self, out: &Path) -> Result<(), CliError> {
        let failed = |path: &Path, e: std::io::Error| {
            CliError::Io(format!("cannot write {}: {e}", path.display()))
        };
        if !self.meshes.is_empty() {
            let folder = out.join("meshes");
            std::fs::create_dir_all(&folder).map_err(|e| failed(&folder, e))?;
            for (source, name) in &self.meshes {
                let bytes = Disk.read(source).map_err(|e| {
                    CliError::Io(format!(
                        "cannot copy the mesh {} into {}: {e}",
                        source.display(),
                        folder.display()
                    ))
                })?;
                let path = folder.join(name);
                AtomicFile::write(&path, &bytes).map_err(|e| failed(&path, e))?;
            }
        }
        let path = out.join("scene.toml");
        AtomicFile::write(&path, self.text.as_bytes()).map_err(|e| failed(&path, e))
    }
}
