//! `sprung bench` runs its cases on 1 thread and on all, writes its table
//! as CSV, and shows that a step allocates nothing once its buffers are
//! sized. `--quick` takes small cases: this checks the bench, it does not
//! time anything (no test here is timed).

mod common;

use common::{sprung, text};

#[test]
fn quick_bench_writes_every_group_on_one_and_two_threads_and_steps_allocate_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("bench.csv");
    let output = sprung(
        &[
            "--threads",
            "2",
            "bench",
            "--quick",
            "--compare",
            "--csv",
            csv.to_str().expect("utf-8 path"),
        ],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let table = std::fs::read_to_string(&csv).expect("the CSV is written");
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|&h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    };
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.iter().all(|r| r.len() == header.len()), "ragged CSV");
    for group in ["cloth", "integrators", "gas", "stiff", "contact", "give"] {
        for threads in ["1", "2"] {
            assert!(
                rows.iter()
                    .any(|r| r[column("group")] == group && r[column("threads")] == threads),
                "no {group} case on {threads} threads"
            );
        }
    }
    for row in &rows {
        // Every integrator, every case: a step allocates nothing once the
        // warm-up steps sized the buffers (and the solvers factored).
        assert_eq!(
            row[column("bytes_allocated_per_step")],
            "0",
            "{} under {} allocates in its steps",
            row[column("case")],
            row[column("integrator")]
        );
        let ms: f64 = row[column("ms_per_step")].parse().expect("a number");
        assert!(ms > 0.0 && ms.is_finite());
        let peak: usize = row[column("peak_bytes")].parse().expect("a count");
        assert!(peak > 0, "the world's own arrays are on the heap");
    }
    // The textbook loop is timed on the cloths of --compare.
    assert!(rows
        .iter()
        .any(|r| r[column("group")] == "cloth" && !r[column("textbook_ms_per_step")].is_empty()));
}

#[test]
fn demos_report_a_real_time_factor_each() {
    let dir = tempfile::tempdir().expect("temp dir");
    let output = sprung(&["bench", "--demos", "--quick"], dir.path());
    assert!(output.status.success(), "{}", text(&output.stderr));
    let out = text(&output.stdout);
    let list = sprung(&["demo", "--list"], dir.path());
    for line in text(&list.stdout).lines() {
        let name = line.split_whitespace().next().expect("a demo name");
        assert!(
            out.lines()
                .any(|l| l.split_whitespace().next() == Some(name)),
            "no real-time factor for {name}:\n{out}"
        );
    }
}

#[test]
fn bench_refuses_impossible_options() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Malformed option values are usage errors (status 2), as for every
    // command; a file that cannot be written an input error (1).
    for args in [
        &["bench", "--steps", "0"][..],
        &["bench", "--sizes", "1"],
        &["bench", "--size", "1"],
        &["bench", "--seconds=-1"],
        &["bench", "--seconds", "nan"],
        &["bench", "--only", "nonsense"],
    ] {
        let output = sprung(args, dir.path());
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(output.stdout.is_empty(), "{args:?} timed something");
    }
    for args in [
        // Refused before the timing, not after it.
        &["bench", "--csv", "missing/table.csv"][..],
        &["bench", "--csv", "."],
        &["bench", "--csv", ""],
        &["bench", "--csv", "newdir/"],
    ] {
        let output = sprung(args, dir.path());
        assert!(!output.status.success(), "{args:?} was accepted");
        assert!(!text(&output.stderr).is_empty());
        assert!(output.stdout.is_empty(), "{args:?} timed something");
    }
}
