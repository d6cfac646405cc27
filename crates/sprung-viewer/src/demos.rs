//! Where the viewer's scene comes from: one of the demos compiled into
//! `sprung_io::demos` (with their meshes, so the web page needs no files
//! beside it), a scene file on the disk, or a scene the web page handed
//! over (picked, dropped or fetched) with the mesh files beside it.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use sprung_io::demos::DEMOS;
use sprung_io::{parse_scene_with, Disk, FileSource, Scene};

/// A scene handed over by the web page: its file name, its text, and the
/// files that came with it (meshes), by name.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Upload {
    /// The scene file's name (for errors, and to place its meshes).
    pub name: String,
    /// The scene file's bytes (TOML, UTF-8 unless broken).
    pub text: Vec<u8>,
    /// Files that came with it: `(name, bytes)`.
    pub files: Vec<(String, Vec<u8>)>,
}

impl FileSource for Upload {
    /// A file that came with the scene, by its path or else by its name
    /// alone (a dropped `horse.obj` serves `meshes/horse.obj`). Nothing
    /// else: a mesh the scene names and that did not come with it is an
    /// error on the scene's line, as `sprung check` makes it (the meshes
    /// built into sprung serve the demos, which are opened by name).
    fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        let wanted = path.to_string_lossy();
        let name = path.file_name().map(|n| n.to_string_lossy());
        let found = self
            .files
            .iter()
            .find(|(file, _)| *file == wanted)
            .or_else(|| {
                self.files
                    .iter()
                    .find(|(file, _)| Some(file.as_str()) == name.as_deref())
            });
        match found {
            Some((_, bytes)) => Ok(bytes.clone()),
            None => Err(io::Error::new(
                io::ErrorKind::NotFound,
                format!(
                    "{} is not there: a scene opened by its address finds its meshes beside it; a picked or dropped one needs them picked or dropped together with {}",
                    path.display(),
                    self.name
                ),
            )),
        }
    }
}

/// The index of the demo called `name` in `sprung_io::demos::DEMOS`.
pub fn find(name: &str) -> Option<usize> {
    DEMOS.iter().position(|d| d.name == name)
}

/// Where a scene comes from: a demo, or a file on the disk (native only).
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// `DEMOS[index]`.
    Demo(usize),
    /// A scene file, read again at every reset.
    File(PathBuf),
    /// A scene the web page handed over.
    Upload(Arc<Upload>),
}

impl Source {
    /// The name shown in the picker and the title.
    pub fn label(&self) -> String {
        match self {
            Source::Demo(index) => DEMOS.get(*index).map_or("?", |d| d.name).to_string(),
            Source::File(path) => path.display().to_string(),
            Source::Upload(upload) => upload.name.clone(),
        }
    }

    /// The demo's index, for a demo.
    pub fn demo(&self) -> Option<usize> {
        match self {
            Source::Demo(index) => Some(*index),
            _ => None,
        }
    }

    /// The name without its folders (for narrow places).
    pub fn short_label(&self) -> String {
        match self {
            Source::Demo(_) | Source::Upload(_) => self.label(),
            Source::File(path) => path
                .file_name()
                .map_or_else(|| self.label(), |n| n.to_string_lossy().into_owned()),
        }
    }

    /// Read and build the scene; the error is the loader's message (file,
    /// line, key).
    pub fn load(&self) -> Result<Scene, String> {
        match self {
            Source::Demo(index) => {
                let demo = DEMOS
                    .get(*index)
                    .ok_or_else(|| format!("no demo number {index}"))?;
                demo.load().map_err(|e| e.to_string())
            }
            Source::File(path) => {
                let text = std::fs::read_to_string(path)
                    .map_err(|e| format!("{}: cannot read the scene file: {e}", path.display()))?;
                parse_scene_with(&text, path, &Disk).map_err(|e| e.to_string())
            }
            Source::Upload(upload) => {
                let path = Path::new(&upload.name);
                let text =
                    sprung_io::scene::scene_text(&upload.text, path).map_err(|e| e.to_string())?;
                parse_scene_with(text, path, upload.as_ref()).map_err(|e| e.to_string())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_demo_loads_from_bundled_files() {
        for (index, demo) in DEMOS.iter().enumerate() {
            let scene = Source::Demo(index).load();
            assert!(scene.is_ok(), "{}: {:?}", demo.name, scene.err());
        }
    }

    #[test]
    fn an_upload_finds_its_meshes_by_path_or_name_and_nowhere_else() {
        let cube = std::fs::read("../../scenes/meshes/cube.asc").expect("cube");
        let upload = Upload {
            name: "mine.toml".into(),
            text: b"[sim]\ndt = 1e-3\n\n[[body]]\nname = \"a\"\nmesh = \"shapes/box.asc\"\n"
                .to_vec(),
            files: vec![("box.asc".into(), cube)],
        };
        let scene = Source::Upload(Arc::new(upload.clone()))
            .load()
            .expect("loads");
        assert_eq!(scene.world.body("a").expect("a").particles.len(), 8);
        // A mesh of the same name as one built into sprung, not given:
        // an error on its line, as from the command line.
        let horse = Upload {
            text: b"[sim]\ndt = 1e-3\n\n[[body]]\nname = \"b\"\nmesh = \"meshes/horse.obj\"\n"
                .to_vec(),
            ..upload.clone()
        };
        let error = Source::Upload(Arc::new(horse))
            .load()
            .err()
            .unwrap_or_default();
        assert!(
            error.contains("mine.toml:6") && error.contains("meshes/horse.obj is not there"),
            "{error}"
        );
        let missing = Upload {
            files: Vec::new(),
            ..upload
        };
        let error = Source::Upload(Arc::new(missing.clone()))
            .load()
            .err()
            .unwrap_or_default();
        assert!(
            error.contains("mine.toml") && error.contains("shapes/box.asc"),
            "{error}"
        );
        let broken = Upload {
            text: b"[sim]\ndt = \xff\n".to_vec(),
            ..missing
        };
        let error = Source::Upload(Arc::new(broken))
            .load()
            .err()
            .unwrap_or_default();
        assert!(
            error.contains("mine.toml") && error.contains("line 2, byte 6"),
            "{error}"
        );
    }

    #[test]
    fn a_missing_file_is_an_error_naming_it() {
        let error = Source::File(PathBuf::from("no/such/scene.toml"))
            .load()
            .err()
            .unwrap_or_default();
        assert!(error.contains("no/such/scene.toml"), "{error}");
    }
}
