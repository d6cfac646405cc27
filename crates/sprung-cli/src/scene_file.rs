//! The scene `sprung run` reads, from a file or from standard input (`-`),
//! with its `--set` overrides; and the copy of the effective scene it
//! keeps in the run's folder, `scene.toml` with the meshes it names in
//! `meshes/`, so that `sprung run OUT/scene.toml` repeats the run from the
//! folder alone.

use std::path::{Path, PathBuf};

use sprung_io::export::AtomicFile;
use sprung_io::input::{read_scene_file, read_scene_stream};
use sprung_io::scene::{overridden_table, scene_toml};
use sprung_io::toml::Value;
use sprung_io::{parse_scene_overridden, Disk, FileSource, Override, Scene};

use crate::error::CliError;
use crate::outputs::resolved;

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
            let text = read_scene_file(path)?;
            return Ok(SceneInput {
                text,
                path: path.to_path_buf(),
                dir: path.parent().unwrap_or(Path::new("")).to_path_buf(),
                stdin: false,
            });
        }
        let name = Path::new(STDIN);
        let text = read_scene_stream(std::io::stdin().lock(), name)?;
        Ok(SceneInput {
            text,
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

    /// Refuse, before anything is written, a copy that would replace one
    /// of the files the run reads (`inputs`: the scene, its meshes, the
    /// state it resumes from) with other bytes: `sprung run DIR/scene.toml
    /// --out DIR` with `--set`, or of a scene with comments and meshes.
    /// The same bytes (a run's own copy run again into its folder) are
    /// left as they are.
    pub fn check(&self, out: &Path, inputs: &[&Path]) -> Result<(), CliError> {
        let inputs: Vec<PathBuf> = inputs.iter().map(|p| resolved(p)).collect();
        for (target, source) in self.targets(out) {
            let target_resolved = resolved(&target);
            let Some(input) = inputs.iter().find(|input| **input == target_resolved) else {
                continue;
            };
            let bytes = self.bytes(source)?;
            if Disk.read(&target).ok().as_deref() != Some(bytes.as_slice()) {
                return Err(CliError::Input(format!(
                    "--out {}: the run would write its copy of the scene over {}, which it reads, with other bytes ({}): give another --out (nothing was written)",
                    out.display(),
                    input.display(),
                    match source {
                        Some(_) => "another mesh",
                        None => "the effective scene: overrides applied, mesh paths pointed into meshes/, comments dropped",
                    },
                )));
            }
        }
        Ok(())
    }

    /// The files the copy writes in `out`, each with the mesh it copies
    /// (`None` for `scene.toml`).
    fn targets(&self, out: &Path) -> Vec<(PathBuf, Option<&Path>)> {
        let meshes = self
            .meshes
            .iter()
            .map(|(source, name)| (out.join("meshes").join(name), Some(source.as_path())));
        meshes
            .chain(std::iter::once((out.join("scene.toml"), None)))
            .collect()
    }

    /// The bytes of `source` (a mesh), or of `scene.toml` for `None`.
    fn bytes(&self, source: Option<&Path>) -> Result<Vec<u8>, CliError> {
        match source {
            None => Ok(self.text.as_bytes().to_vec()),
            Some(source) => Disk.read(source).map_err(|e| {
                CliError::Io(format!("cannot copy the mesh {}: {e}", source.display()))
            }),
        }
    }

    /// Write `out/meshes/NAME` for each mesh, then `out/scene.toml`, each
    /// atomically; a file that already holds the same bytes (as when the
    /// run's own copy is run again into its folder) is left as it is.
    pub fn write(&self, out: &Path) -> Result<(), CliError> {
        let failed = |path: &Path, e: std::io::Error| {
            CliError::Io(format!("cannot write {}: {e}", path.display()))
        };
        if !self.meshes.is_empty() {
            let folder = out.join("meshes");
            std::fs::create_dir_all(&folder).map_err(|e| failed(&folder, e))?;
        }
        for (path, source) in self.targets(out) {
            let bytes = self.bytes(source)?;
            if Disk.read(&path).ok().as_deref() == Some(bytes.as_slice()) {
                continue;
            }
            AtomicFile::write(&path, &bytes).map_err(|e| failed(&path, e))?;
        }
        Ok(())
    }
}
