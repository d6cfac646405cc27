//! The demo scenes of `scenes/`, compiled into the viewer (so that the web
//! page needs no files beside it), and the meshes they use, served to the
//! scene loader through a [`FileSource`].

use std::io;
use std::path::{Path, PathBuf};

use sprung_io::{parse_scene_with, Disk, FileSource, Scene};

/// A built-in scene.
#[derive(Debug, Clone, Copy)]
pub struct Demo {
    /// Short name (the file name without `.toml`).
    pub name: &'static str,
    /// The scene file's text.
    pub text: &'static str,
}

macro_rules! demo {
    ($name:literal) => {
        Demo {
            name: $name,
            text: include_str!(concat!("../../../scenes/", $name, ".toml")),
        }
    };
}

/// Every demo, in the order of the scene picker.
pub const DEMOS: &[Demo] = &[
    demo!("ball2d"),
    demo!("ball3d"),
    demo!("flag"),
    demo!("billow"),
    demo!("cloth"),
    demo!("pillow"),
    demo!("balloon"),
    demo!("horse"),
    demo!("jelly"),
    demo!("rope"),
    demo!("rope_one_sided"),
    demo!("chain"),
    demo!("lattice2d"),
    demo!("oscillator"),
];

/// The meshes the demos refer to, by file name (under `scenes/meshes/`).
const MESHES: &[(&str, &[u8])] = &[
    (
        "cube.asc",
        include_bytes!("../../../scenes/meshes/cube.asc"),
    ),
    (
        "horse.obj",
        include_bytes!("../../../scenes/meshes/horse.obj"),
    ),
];

/// The index of the demo called `name`.
pub fn find(name: &str) -> Option<usize> {
    DEMOS.iter().position(|d| d.name == name)
}

/// Mesh files compiled into the program: `meshes/NAME` of a demo scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct Bundled;

impl FileSource for Bundled {
    fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        let in_meshes = path
            .parent()
            .and_then(Path::file_name)
            .is_some_and(|folder| folder == "meshes");
        let name = path.file_name().and_then(|n| n.to_str());
        MESHES
            .iter()
            .find(|(file, _)| in_meshes && Some(*file) == name)
            .map(|(_, bytes)| bytes.to_vec())
            .ok_or_else(|| {
                io::Error::new(
                    io::ErrorKind::NotFound,
                    format!(
                        "{} is not one of the meshes built into the viewer",
                        path.display()
                    ),
                )
            })
    }
}

/// Where a scene comes from: a demo, or a file on the disk (native only).
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// `DEMOS[index]`.
    Demo(usize),
    /// A scene file, read again at every reset.
    File(PathBuf),
}

impl Source {
    /// The name shown in the picker and the title.
    pub fn label(&self) -> String {
        match self {
            Source::Demo(index) => DEMOS.get(*index).map_or("?", |d| d.name).to_string(),
            Source::File(path) => path.display().to_string(),
        }
    }

    /// The name without its folders (for narrow places).
    pub fn short_label(&self) -> String {
        match self {
            Source::Demo(_) => self.label(),
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
                let path = Path::new("scenes").join(format!("{}.toml", demo.name));
                parse_scene_with(demo.text, &path, &Bundled).map_err(|e| e.to_string())
            }
            Source::File(path) => {
                let text = std::fs::read_to_string(path)
                    .map_err(|e| format!("{}: cannot read the scene file: {e}", path.display()))?;
                parse_scene_with(&text, path, &Disk).map_err(|e| e.to_string())
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
    fn bundled_refuses_other_files() {
        assert!(Bundled.read(Path::new("scenes/meshes/none.obj")).is_err());
        assert!(Bundled.read(Path::new("elsewhere/horse.obj")).is_err());
        assert!(Bundled.read(Path::new("scenes/meshes/horse.obj")).is_ok());
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
