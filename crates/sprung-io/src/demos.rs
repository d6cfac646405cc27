//! The demo scenes of `scenes/`, compiled in, with the mesh files they use,
//! so that `sprung demo` runs from any folder and the web viewer needs no
//! files beside its page. One list for the command line and the viewer.

use std::io;
use std::path::{Path, PathBuf};

use crate::scene::{parse_scene_with, FileSource, Scene, SceneError};

/// A built-in scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Demo {
    /// Short name: the file name in `scenes/` without `.toml`.
    pub name: &'static str,
    /// What it shows, in a line.
    pub about: &'static str,
    /// The scene file's text.
    pub text: &'static str,
    /// Meant to be run once per integrator, to compare them.
    pub every_integrator: bool,
}

impl Demo {
    /// The scene's path in the source tree (`scenes/NAME.toml`), used in
    /// error messages and to resolve its mesh files.
    pub fn path(&self) -> PathBuf {
        Path::new("scenes").join(format!("{}.toml", self.name))
    }

    /// Build the scene, its meshes read from [`Bundled`].
    pub fn load(&self) -> Result<Scene, SceneError> {
        parse_scene_with(self.text, &self.path(), &Bundled)
    }
}

/// The demo run when none is named.
pub const DEFAULT_DEMO: &str = "ball2d";

/// Every demo, the default first.
pub const DEMOS: &[Demo] = &[
    Demo {
        name: "ball2d",
        about: "the textbook 2D ball (a ring of 17) dropped on a floor, with and without gas",
        text: include_str!("../../../scenes/ball2d.toml"),
        every_integrator: false,
    },
    Demo {
        name: "ball3d",
        about: "a gas-filled icosphere dropped on a floor: it squashes and bounces",
        text: include_str!("../../../scenes/ball3d.toml"),
        every_integrator: false,
    },
    Demo {
        name: "pillow",
        about: "the textbook cube (cube.asc) inflating into a rounded pillow",
        text: include_str!("../../../scenes/pillow.toml"),
        every_integrator: false,
    },
    Demo {
        name: "horse",
        about: "the Cyberware horse mesh inflated and dropped on a floor",
        text: include_str!("../../../scenes/horse.toml"),
        every_integrator: false,
    },
    Demo {
        name: "balloon",
        about: "a balloon that starts to leak after 3 s, deflates and sags",
        text: include_str!("../../../scenes/balloon.toml"),
        every_integrator: false,
    },
    Demo {
        name: "flag",
        about: "a flag pinned along its pole fluttering in a steady wind",
        text: include_str!("../../../scenes/flag.toml"),
        every_integrator: false,
    },
    Demo {
        name: "billow",
        about: "two sheets pinned on four sides billowing in strong and weak wind",
        text: include_str!("../../../scenes/billow.toml"),
        every_integrator: false,
    },
    Demo {
        name: "drape",
        about: "a cloth dropped over a ball drapes around it",
        text: include_str!("../../../scenes/drape.toml"),
        every_integrator: false,
    },
    Demo {
        name: "poke",
        about: "a moving ball pushes into the inflated horse and pulls back out",
        text: include_str!("../../../scenes/poke.toml"),
        every_integrator: false,
    },
    Demo {
        name: "stiff_cloth",
        about: "a stiff cloth in a gusty wind at dt = 1/60 s with implicit Euler (explicit needs 130 times smaller steps)",
        text: include_str!("../../../scenes/stiff_cloth.toml"),
        every_integrator: false,
    },
    Demo {
        name: "firm_ball",
        about: "a firm gas ball (stiff springs) bouncing on a floor at dt = 1/60 s with implicit Euler",
        text: include_str!("../../../scenes/firm_ball.toml"),
        every_integrator: false,
    },
    Demo {
        name: "collide",
        about: "two gas balls thrown at each other: they squash and bounce apart",
        text: include_str!("../../../scenes/collide.toml"),
        every_integrator: false,
    },
    Demo {
        name: "stack",
        about: "three gas balls dropped into a tube settle, resting on each other",
        text: include_str!("../../../scenes/stack.toml"),
        every_integrator: false,
    },
    Demo {
        name: "pile2d",
        about: "a dozen 2D gas rings poured into a box pile up",
        text: include_str!("../../../scenes/pile2d.toml"),
        every_integrator: false,
    },
    Demo {
        name: "fold",
        about: "a cloth dropped upright folds over onto itself without passing through",
        text: include_str!("../../../scenes/fold.toml"),
        every_integrator: false,
    },
    Demo {
        name: "cover",
        about: "a cloth dropped over a gas ball resting on the floor",
        text: include_str!("../../../scenes/cover.toml"),
        every_integrator: false,
    },
    Demo {
        name: "bullet",
        about: "a gas ball fired into a pinned cloth at 100 m/s, and caught",
        text: include_str!("../../../scenes/bullet.toml"),
        every_integrator: false,
    },
    Demo {
        name: "twist",
        about: "a cloth tube twisted on itself: folds pressed on folds, none through",
        text: include_str!("../../../scenes/twist.toml"),
        every_integrator: false,
    },
    Demo {
        name: "tear",
        about: "a cloth joined to two heavy bars thrown apart: it stretches and tears",
        text: include_str!("../../../scenes/tear.toml"),
        every_integrator: false,
    },
    Demo {
        name: "burst",
        about: "a balloon pumped until its skin breaks: the gas escapes and it falls limp",
        text: include_str!("../../../scenes/burst.toml"),
        every_integrator: false,
    },
    Demo {
        name: "dent",
        about: "a soft can pressed by a ball: its springs yield and it stays dented",
        text: include_str!("../../../scenes/dent.toml"),
        every_integrator: false,
    },
    Demo {
        name: "tethered",
        about: "a gas ball tied by a join to a swinging rope",
        text: include_str!("../../../scenes/tethered.toml"),
        every_integrator: false,
    },
    Demo {
        name: "cloth",
        about: "a cloth hanging from two corners",
        text: include_str!("../../../scenes/cloth.toml"),
        every_integrator: false,
    },
    Demo {
        name: "rope",
        about: "a rope released horizontally, swinging down from its pinned end",
        text: include_str!("../../../scenes/rope.toml"),
        every_integrator: false,
    },
    Demo {
        name: "rope_one_sided",
        about: "a hanging rope of one-sided springs: every segment stretches by the same m g / k",
        text: include_str!("../../../scenes/rope_one_sided.toml"),
        every_integrator: false,
    },
    Demo {
        name: "jelly",
        about: "a 26-neighbour jelly cube dropped on a floor",
        text: include_str!("../../../scenes/jelly.toml"),
        every_integrator: false,
    },
    Demo {
        name: "chain",
        about: "a chain of five masses between two walls, one displaced",
        text: include_str!("../../../scenes/chain.toml"),
        every_integrator: false,
    },
    Demo {
        name: "lattice2d",
        about: "a 4×4 2D lattice falling onto a floor",
        text: include_str!("../../../scenes/lattice2d.toml"),
        every_integrator: false,
    },
    Demo {
        name: "pendulum",
        about: "rod pendulums at 10° and 120°: the large swing's period is 37 % longer (elliptic integral)",
        text: include_str!("../../../scenes/pendulum.toml"),
        every_integrator: false,
    },
    Demo {
        name: "double_pendulum",
        about: "chaos: two double pendulums of rods a millimetre apart part ways within seconds",
        text: include_str!("../../../scenes/double_pendulum.toml"),
        every_integrator: false,
    },
    Demo {
        name: "spring_pendulum",
        about: "a bob on a spring swings and bounces at once, tracing a Lissajous figure",
        text: include_str!("../../../scenes/spring_pendulum.toml"),
        every_integrator: false,
    },
    Demo {
        name: "orbit",
        about: "gravitation: a planet on an eccentric Kepler orbit and a collapsing cluster of twenty",
        text: include_str!("../../../scenes/orbit.toml"),
        every_integrator: false,
    },
    Demo {
        name: "walker",
        about: "a creature of springs and muscles walking along a floor with friction",
        text: include_str!("../../../scenes/walker.toml"),
        every_integrator: false,
    },
    Demo {
        name: "dice",
        about: "rigid lattice cubes thrown with spin onto a floor and onto a gas ball",
        text: include_str!("../../../scenes/dice.toml"),
        every_integrator: false,
    },
    Demo {
        name: "oscillator",
        about: "one mass on a spring, run with every integrator (compare their energy)",
        text: include_str!("../../../scenes/oscillator.toml"),
        every_integrator: true,
    },
];

/// The demo called `name`.
pub fn find(name: &str) -> Option<&'static Demo> {
    DEMOS.iter().find(|d| d.name == name)
}

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
    (
        "tube.obj",
        include_bytes!("../../../scenes/meshes/tube.obj"),
    ),
];

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
                        "{} is not one of the meshes built into sprung",
                        path.display()
                    ),
                )
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_demo_loads_from_bundled_files() {
        for demo in DEMOS {
            assert!(
                demo.load().is_ok(),
                "{}: {:?}",
                demo.name,
                demo.load().err()
            );
        }
        assert_eq!(DEMOS[0].name, DEFAULT_DEMO);
    }

    #[test]
    fn bundled_refuses_other_files() {
        assert!(Bundled.read(Path::new("scenes/meshes/none.obj")).is_err());
        assert!(Bundled.read(Path::new("elsewhere/horse.obj")).is_err());
        assert!(Bundled.read(Path::new("scenes/meshes/horse.obj")).is_ok());
    }
}
