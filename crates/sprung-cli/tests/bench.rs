//! `sprung bench` runs its cases on 1 thread and on all, writes its table
//! as CSV, and shows that a step allocates nothing once its buffers are
//! sized. `--quick` takes small cases: this checks the bench, it does not
//! time anything (no test here is timed).

mod common;

use common::{sprung, text};

/// A CSV table the bench wrote, its rows all as long as its header.
struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    fn read(path: &std::path::Path) -> Table {
        let text = std::fs::read_to_string(path).expect("the CSV is written");
        let mut lines = text
            .lines()
            .map(|l| l.split(',').map(String::from).collect::<Vec<_>>());
        let header = lines.next().expect("a header");
        let rows: Vec<Vec<String>> = lines.collect();
        assert!(rows.iter().all(|r| r.len() == header.len()), "ragged CSV");
        Table { header, rows }
    }

    /// The index of the column `name`.
    fn column(&self, name: &str) -> usize {
        let header = &self.header;
        header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    }
}

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
    let table = Table::read(&csv);
    let (rows, column) = (&table.rows, |name: &str| table.column(name));
    for group in ["cloth", "integrators", "gas", "stiff", "contact", "give"] {
        for threads in ["1", "2"] {
            assert!(
                rows.iter()
                    .any(|r| r[column("group")] == group && r[column("threads")] == threads),
                "no {group} case on {threads} threads"
            );
        }
    }
    for row in rows {
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
fn goals_stand_beside_the_figures_before_them_and_their_targets() {
    // `--goals` prints issue 35's goals 1 to 4 and writes them as CSV:
    // each figure measured (finite, positive), its target, whether it is
    // met (the figure against the bound, as written; a ratio of rounds by
    // its lowest round), and a figure before
    // it where one exists: the Jacobi preconditioner's, measured in this
    // run, for implicit_euler; the record for the kernel.
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("goals.csv");
    let path = csv.to_str().expect("utf-8 path");
    let args = [
        "--threads",
        "2",
        "bench",
        "--goals",
        "--quick",
        "--csv",
        path,
    ];
    let output = sprung(&args, dir.path());
    assert!(output.status.success(), "{}", text(&output.stderr));
    let table = Table::read(&csv);
    let (rows, column) = (&table.rows, |name: &str| table.column(name));
    for goal in ["1", "2", "3", "4"] {
        assert!(
            rows.iter().any(|r| r[column("goal")] == goal),
            "no goal {goal}"
        );
    }
    for row in rows {
        let now: f64 = row[column("now")].parse().expect("a number");
        let target: f64 = row[column("target")].parse().expect("a number");
        assert!(now > 0.0 && now.is_finite(), "{row:?}");
        // A paired ratio (2 threads over 1, in rounds) is over its bound
        // only when its lowest round is.
        let lowest: f64 = row[column("lowest")].parse().unwrap_or(now);
        let met = match row[column("bound")].as_str() {
            "at_most" => lowest <= target,
            "at_least" => now >= target,
            other => panic!("bound {other}"),
        };
        assert_eq!(row[column("met")], met.to_string(), "{row:?}");
        assert_eq!(
            row[column("threads")],
            if row[column("figure")].contains("MuJoCo") {
                "1"
            } else {
                "2"
            }
        );
    }
    let met = rows.iter().filter(|r| r[column("met")] == "true").count();
    let summary = format!("goals met: {met} of {}", rows.len());
    assert!(
        text(&output.stdout).contains(&summary),
        "no {summary:?} printed"
    );
    let jacobi = rows
        .iter()
        .filter(|r| r[column("before_from")] == "this run; Jacobi pc.")
        .count();
    assert_eq!(
        jacobi, 4,
        "implicit_euler at 128² and the three sizes vs MuJoCo"
    );
    assert!(rows
        .iter()
        .any(|r| r[column("figure")].contains("spring updates")
            && r[column("before")].parse::<f64>() == Ok(9.2e8)));
    // --goals and --demos are two different runs.
    let both = sprung(&["bench", "--goals", "--demos", "--quick"], dir.path());
    assert_eq!(both.status.code(), Some(2));
}

/// `--device gpu`: each cloth (and the largest under RK4) timed on the GPU
/// and on the engine, with the adapter named (skipped where this machine
/// has no adapter and `SPRUNG_GPU_TESTS` is not `require`).
#[test]
fn the_gpu_bench_times_each_cloth_on_the_gpu_and_the_engine() {
    for (device, precision) in [("gpu", "f32"), ("gpu_f64", "f64")] {
        let dir = tempfile::tempdir().expect("temp dir");
        let csv = dir.path().join("gpu.csv");
        let out = sprung(
            &[
                "bench",
                "--device",
                device,
                "--quick",
                "--csv",
                csv.to_str().unwrap(),
            ],
            dir.path(),
        );
        let stderr = text(&out.stderr);
        if (stderr.contains("no GPU adapter found") || stderr.contains("has no SHADER_F64"))
            && std::env::var("SPRUNG_GPU_TESTS").as_deref() != Ok("require")
        {
            eprintln!("skipped: {stderr}");
            continue;
        }
        assert!(out.status.success(), "{device}: {stderr}");
        assert!(text(&out.stdout).contains(&format!(", in {precision}")));
        let table = Table::read(&csv);
        let names: Vec<(&str, &str)> = table
            .rows
            .iter()
            .map(|r| (r[0].as_str(), r[table.column("integrator")].as_str()))
            .collect();
        assert_eq!(
            names,
            [
                ("cloth 8²", "symplectic_euler"),
                ("cloth 16²", "symplectic_euler"),
                ("cloth 16²", "rk4")
            ]
        );
        for (row, particles) in table.rows.iter().zip([64.0, 256.0, 256.0]) {
            let number = |name: &str| row[table.column(name)].parse::<f64>().unwrap();
            assert_eq!(number("particles"), particles);
            for rate in [
                "gpu_spring_updates_per_second",
                "cpu_spring_updates_per_second",
            ] {
                assert!(
                    number(rate) > 0.0 && number(rate).is_finite(),
                    "{rate}: {row:?}"
                );
            }
            assert!(!row[table.column("gpu")].is_empty());
            assert_eq!(row[table.column("precision")], precision);
        }
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
