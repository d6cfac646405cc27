//! `sprung demo`: the built-in scenes of `scenes/`, compiled into the
//! binary so that `sprung demo` works from any folder.

use std::path::{Path, PathBuf};

use sprung::IntegratorKind;
use sprung_io::export::FrameFormat;
use sprung_io::parse_scene;

use crate::run::{run_scene, CliError};
use crate::RunOptions;

/// A built-in demo.
struct Demo {
    name: &'static str,
    about: &'static str,
    scene: &'static str,
    /// Run once per integrator, into one subfolder each.
    every_integrator: bool,
}

macro_rules! scene {
    ($file:literal) => {
        include_str!(concat!("../../../scenes/", $file))
    };
}

/// The demo run when no name is given.
const DEFAULT_DEMO: &str = "ball2d";

const DEMOS: &[Demo] = &[
    Demo {
        name: "ball2d",
        about: "the textbook 2D ball (a ring of 17) dropped on a floor, with and without gas",
        scene: scene!("ball2d.toml"),
        every_integrator: false,
    },
    Demo {
        name: "ball3d",
        about: "a gas-filled icosphere dropped on a floor: it squashes and bounces",
        scene: scene!("ball3d.toml"),
        every_integrator: false,
    },
    Demo {
        name: "pillow",
        about: "the textbook cube (cube.asc) inflating into a rounded pillow",
        scene: scene!("pillow.toml"),
        every_integrator: false,
    },
    Demo {
        name: "horse",
        about: "the Cyberware horse mesh inflated and dropped on a floor",
        scene: scene!("horse.toml"),
        every_integrator: false,
    },
    Demo {
        name: "balloon",
        about: "a balloon that starts to leak after 3 s, deflates and sags",
        scene: scene!("balloon.toml"),
        every_integrator: false,
    },
    Demo {
        name: "flag",
        about: "a flag pinned along its pole fluttering in a steady wind",
        scene: scene!("flag.toml"),
        every_integrator: false,
    },
    Demo {
        name: "billow",
        about: "two sheets pinned on four sides billowing in strong and weak wind",
        scene: scene!("billow.toml"),
        every_integrator: false,
    },
    Demo {
        name: "drape",
        about: "a cloth dropped over a ball drapes around it",
        scene: scene!("drape.toml"),
        every_integrator: false,
    },
    Demo {
        name: "poke",
        about: "a moving ball pushes into the inflated horse and pulls back out",
        scene: scene!("poke.toml"),
        every_integrator: false,
    },
    Demo {
        name: "cloth",
        about: "a cloth hanging from two corners",
        scene: scene!("cloth.toml"),
        every_integrator: false,
    },
    Demo {
        name: "rope",
        about: "a rope released horizontally, swinging down from its pinned end",
        scene: scene!("rope.toml"),
        every_integrator: false,
    },
    Demo {
        name: "rope_one_sided",
        about: "a hanging rope of one-sided springs: every segment stretches by the same m g / k",
        scene: scene!("rope_one_sided.toml"),
        every_integrator: false,
    },
    Demo {
        name: "jelly",
        about: "a 26-neighbour jelly cube dropped on a floor",
        scene: scene!("jelly.toml"),
        every_integrator: false,
    },
    Demo {
        name: "chain",
        about: "a chain of five masses between two walls, one displaced",
        scene: scene!("chain.toml"),
        every_integrator: false,
    },
    Demo {
        name: "lattice2d",
        about: "a 4×4 2D lattice falling onto a floor",
        scene: scene!("lattice2d.toml"),
        every_integrator: false,
    },
    Demo {
        name: "oscillator",
        about: "one mass on a spring, run with every integrator (compare their energy)",
        scene: scene!("oscillator.toml"),
        every_integrator: true,
    },
];

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

/// Run the demo `name` (or the default one).
pub fn run(name: Option<&str>, options: &RunOptions) -> Result<(), CliError> {
    let name = name.unwrap_or(DEFAULT_DEMO);
    let demo = DEMOS.iter().find(|d| d.name == name).ok_or_else(|| {
        let names: Vec<_> = DEMOS.iter().map(|d| d.name).collect();
        CliError::Input(format!(
            "no demo named \"{name}\" (demos: {})",
            names.join(", ")
        ))
    })?;
    let path = scenes_dir().join(format!("{}.toml", demo.name));
    let out = options
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("demo").join(demo.name));
    let mut options = options.clone();
    options.format = options.format.or(Some(FrameFormat::Vtk));
    let kinds: Vec<Option<IntegratorKind>> = if demo.every_integrator {
        IntegratorKind::ALL.into_iter().map(Some).collect()
    } else {
        vec![options.integrator]
    };
    for kind in kinds {
        let scene = parse_scene(demo.scene, &path)?;
        let folder = match (demo.every_integrator, kind) {
            (true, Some(kind)) => out.join(kind.name()),
            _ => out.clone(),
        };
        options.integrator = kind;
        run_scene(scene, &folder, &options)?;
    }
    if !options.quiet {
        println!(
            "demo \"{}\" ({}): results in {} (diagnostics.csv; frames/ opens in ParaView)",
            demo.name,
            demo.about,
            out.display()
        );
    }
    Ok(())
}

/// Where the demo scenes live in the source tree (relative paths inside
/// them, such as mesh files, are resolved from there).
fn scenes_dir() -> PathBuf {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = crate_dir.ancestors().nth(2).unwrap_or(crate_dir);
    root.join("scenes")
}
