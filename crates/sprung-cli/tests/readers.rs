//! Frames that a reader which is not ours takes as they are: meshio (the
//! usual Python reader of meshes), installed from PyPI into a virtual
//! environment under `target/` when Python is there, reads every `.vtu` and
//! legacy `.vtk` frame of a short run of two gas balls. Its point counts,
//! each point's body, and each body's centroid agree with the run and with
//! `diagnostics.csv` (1e-12 m), and the series file beside the frames
//! lists every frame at the `time` of its row.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{sprung, text};

/// The Python of a virtual environment with meshio 5.3.5, made on first
/// use; `None` when this machine has no `python3`.
fn meshio_python() -> Option<PathBuf> {
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/meshio-venv");
    let python = venv.join("bin/python");
    let has_meshio = |python: &Path| {
        Command::new(python)
            .args(["-c", "import meshio"])
            .status()
            .is_ok_and(|s| s.success())
    };
    if python.exists() && has_meshio(&python) {
        return Some(python);
    }
    let system = std::env::var("SPRUNG_PYTHON").unwrap_or_else(|_| "python3".into());
    if Command::new(&system).arg("--version").output().is_err() {
        eprintln!("no {system} on this machine: the meshio check is not run");
        return None;
    }
    let made = Command::new(&system)
        .args(["-m", "venv"])
        .arg(&venv)
        .status()
        .expect("venv runs");
    assert!(made.success(), "python3 -m venv {} failed", venv.display());
    let installed = Command::new(&python)
        .args(["-m", "pip", "install", "--quiet", "meshio==5.3.5"])
        .status()
        .expect("pip runs");
    assert!(installed.success(), "pip install meshio failed");
    assert!(has_meshio(&python));
    Some(python)
}

/// Reads the series file of `frames` and every frame it lists with meshio;
/// prints per frame: its time as listed, its point count, the set of body
/// ids, and each body's mean point position (17 significant digits).
const READ_FRAMES: &str = r#"
import json, re, sys
import meshio, numpy
frames, kind = sys.argv[1], sys.argv[2]
if kind == "vtu":
    text = open(frames + "/frames.pvd").read()
    listed = [(float(t), f) for t, f in re.findall(r'timestep="([^"]+)" part="0" file="([^"]+)"', text)]
else:
    listed = [(f["time"], f["name"]) for f in json.load(open(frames + "/frames.vtk.series"))["files"]]
for time, name in listed:
    mesh = meshio.read(frames + "/" + name)
    body = numpy.asarray(mesh.point_data["body"]).astype(int).ravel()
    ids = sorted(set(body.tolist()))
    centroids = [mesh.points[body == b].mean(axis=0) for b in ids]
    print(repr(time), len(mesh.points), ",".join(map(str, ids)), " ".join(
        repr(float(c)) for centroid in centroids for c in centroid))
"#;

#[test]
fn meshio_reads_every_frame_as_the_run_wrote_it() {
    let Some(python) = meshio_python() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/collide.toml");
    for format in ["vtu", "vtk"] {
        let output = sprung(
            &[
                "run",
                scene.to_str().expect("utf-8 path"),
                "--steps",
                "400",
                "--every",
                "40",
                "--format",
                format,
                "--quiet",
                "--out",
                format,
            ],
            d,
        );
        assert!(output.status.success(), "{}", text(&output.stderr));
        let frames = d.join(format).join("frames");
        let output = Command::new(&python)
            .args(["-c", READ_FRAMES])
            .arg(&frames)
            .arg(format)
            .output()
            .expect("python runs");
        assert!(output.status.success(), "meshio: {}", text(&output.stderr));
        let read = text(&output.stdout);
        let csv = std::fs::read_to_string(d.join(format).join("diagnostics.csv")).expect("csv");
        let mut rows = csv.lines();
        let header: Vec<&str> = rows.next().expect("header").split(',').collect();
        let column = |name: &str| header.iter().position(|h| *h == name).expect(name);
        let rows: Vec<Vec<f64>> = rows
            .map(|r| {
                r.split(',')
                    .map(|v| v.parse().unwrap_or(f64::NAN))
                    .collect()
            })
            .collect();
        let frames_read: Vec<&str> = read.lines().collect();
        assert_eq!(frames_read.len(), rows.len(), "{format}: one frame per row");
        assert_eq!(rows.len(), 11);
        for (line, row) in frames_read.iter().zip(&rows) {
            let fields: Vec<&str> = line.split_whitespace().collect();
            let time: f64 = fields[0].parse().expect("time");
            assert_eq!(
                time,
                row[column("time")],
                "{format}: the series file's time"
            );
            // Two balls of 162 particles each (icospheres of 2 subdivisions).
            assert_eq!(fields[1], "324", "{format}: points");
            assert_eq!(fields[2], "0,1", "{format}: both bodies' ids");
            // The balls' particles have equal masses, so the mean point is
            // the centre of mass diagnostics.csv gives; both are sums of
            // the same 162 numbers in another order: 1e-12 m is thousands
            // of times their rounding.
            let centroid: Vec<f64> = fields[3..]
                .iter()
                .map(|v| v.parse().expect("centroid"))
                .collect();
            for (b, name) in ["left", "right"].iter().enumerate() {
                for (k, axis) in ["cx", "cy", "cz"].iter().enumerate() {
                    let expected = row[column(&format!("{name}.{axis}"))];
                    let got = centroid[3 * b + k];
                    assert!(
                        (got - expected).abs() <= 1e-12,
                        "{format}: {name}.{axis} {got} against {expected}"
                    );
                }
            }
        }
    }
}
