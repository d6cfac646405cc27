//! `sprung run --profile`: where a run's steps spent their time, stage by
//! stage.

mod common;

use common::{sprung, text};
use std::path::Path;

#[test]
fn profile_names_every_stage_and_its_shares_add_up() {
    // The pile of a dozen gas rings from its start (2000 steps: they fall
    // and meet, so contacts are found, pushed and rubbed). Claims: the
    // table names every stage of the step in order, with the calls each
    // made (a step each for detect and guard; the forces once per step of
    // symplectic Euler), and the stages' times add up to the steps' wall
    // time within 5 % (the time outside the stages is the check of dt and
    // the settings before the first: well under 1 %).
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/pile2d.toml");
    let scene = scene.to_str().expect("a UTF-8 path");
    let out = sprung(
        &[
            "run",
            scene,
            "--out",
            "res",
            "--steps",
            "2000",
            "--profile",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    // The table, then the heap's peak on a line of its own.
    assert!(
        stdout
            .lines()
            .last()
            .is_some_and(|l| l.starts_with("heap peak: ")),
        "{stdout}"
    );
    let rows: Vec<Vec<&str>> = stdout
        .lines()
        .filter(|line| !line.starts_with("heap peak: "))
        .map(|line| line.split_whitespace().collect())
        .collect();
    let names: Vec<&str> = rows.iter().map(|row| row[0]).collect();
    assert_eq!(
        names,
        [
            "stage",
            "detect",
            "substeps",
            "muscles",
            "forces",
            "integrate",
            "collide",
            "friction",
            "constrain",
            "give",
            "ccd",
            "guard",
            "stages",
            "steps"
        ],
        "{stdout}"
    );
    let number = |row: &[&str], column: usize| -> f64 {
        row[column]
            .trim_end_matches('%')
            .parse()
            .unwrap_or_else(|_| panic!("a number in {row:?}"))
    };
    let stages = &rows[1..12];
    for row in stages {
        let calls = number(row, 3);
        assert_eq!(calls, 2000.0, "{row:?}: one call a step");
    }
    let staged: f64 = stages.iter().map(|row| number(row, 1)).sum();
    let shares: f64 = stages.iter().map(|row| number(row, 2)).sum();
    let wall = number(&rows[13], 1);
    assert!(wall > 0.0, "{stdout}");
    assert!(
        (staged / wall - 1.0).abs() <= 0.05,
        "stages {staged} s of {wall} s\n{stdout}"
    );
    // The shares, printed to 0.1 % each, add up the same way.
    assert!((shares - 100.0).abs() <= 5.0, "shares {shares} %\n{stdout}");
    assert!(
        number(&rows[4], 1) > 0.0 && number(&rows[1], 1) > 0.0,
        "{stdout}"
    );
}
