//! Where the viewer's scene comes from: one of the demos compiled into
//! `sprung_io::demos` (with their meshes, so the web page needs no files
//! beside it), or a scene file on the disk.

use std::path::PathBuf;

use sprung_io::demos::DEMOS;
use sprung_io::{parse_scene_with, Disk, Scene};

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
                demo.load().map_err(|e| e.to_string())
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
    fn a_missing_file_is_an_error_naming_it() {
        let error = Source::File(PathBuf::from("no/such/scene.toml"))
            .load()
            .err()
            .unwrap_or_default();
        assert!(error.contains("no/such/scene.toml"), "{error}");
    }
}
