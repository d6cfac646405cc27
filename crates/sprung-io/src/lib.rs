//! # sprung-io: scene files, mesh files and exports
//!
//! Everything of sprung that touches files: TOML scene files read into a
//! [`sprung::World`] ([`scene`]), mesh files from modelling tools
//! ([`mesh`]: 3D Studio ASCII, OBJ, OFF, STL) with their topology checks,
//! and the outputs of a run ([`export`]: `diagnostics.csv`, VTK and OBJ
//! frame sequences), each written completely or not at all; and state
//! files to resume a run ([`state`]).

pub mod crossings;
pub mod demos;
pub mod export;
pub mod input;
pub mod mesh;
pub mod scene;
pub mod state;

pub use scene::{
    apply_overrides, load_scene, load_scene_overridden, parse_scene, parse_scene_overridden,
    parse_scene_with, Device, Disk, FileSource, Override, OverrideError, Scene, SceneCamera,
    SceneError,
};
/// The TOML crate whose values [`Override`] holds and [`scene::overridden_table`]
/// returns.
pub use toml;
