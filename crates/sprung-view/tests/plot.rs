//! Plots of diagnostics: the CSV reader (every malformed file refused with
//! its name, line and column, never a panic), the PNG files (sizes,
//! determinism, which files) and comparisons of runs.

use std::path::{Path, PathBuf};

use sprung_view::plot::{
    self, compare_png, energy_png, gas_png, probes_png, DiagnosticsTable, Dimension, PlotError,
    PlotOptions, Scale,
};

const HEADER: &str = "step,time,kinetic,spring,gravity,gas,total,contact,\
ball.volume,ball.pressure,ball.cx,ball.cy,ball.cz,\
rope.volume,rope.pressure,rope.cx,rope.cy,rope.cz,p3.x,p3.y,p3.z";

/// A 2D run with a gas body `ball`, an open body `rope` (no volume, no
/// pressure) and the probe `p3`, `rows` rows long.
fn sample(rows: usize) -> String {
    let mut text = format!("{HEADER}\n");
    for i in 0..rows {
        let t = i as f64 * 0.01;
        let (k, s, g) = ((3.0 * t).sin().powi(2), (3.0 * t).cos().powi(2), 5.0 - t);
        let gas = 0.5 * t;
        text.push_str(&format!(
            "{i},{t},{k},{s},{g},{gas},{},0,{},{},{},{},0,,,1.5,{},0,{},{},0\n",
            k + s + g + gas,
            0.78 + 0.01 * (7.0 * t).sin(),
            100.0 * t.min(0.5),
            -1.5 + 0.1 * t,
            1.0 - t * t,
            -0.2 * t,
            t.cos(),
            t.sin()
        ));
    }
    text
}

fn parse(text: &str) -> Result<DiagnosticsTable, PlotError> {
    DiagnosticsTable::parse(text, Path::new("runs/x/diagnostics.csv"))
}

/// Width and height from a PNG's header.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    assert_eq!(&bytes[12..16], b"IHDR");
    let word =
        |at: usize| u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    (word(16), word(20))
}

fn small() -> PlotOptions {
    PlotOptions {
        width: 320,
        height: 240,
        ..PlotOptions::default()
    }
}

fn run_dir(root: &Path, name: &str, text: &str) -> PathBuf {
    let dir = root.join(name);
    std::fs::create_dir_all(&dir).expect("make run folder");
    std::fs::write(dir.join("diagnostics.csv"), text).expect("write csv");
    dir
}

#[test]
fn reads_the_columns_of_the_contract() {
    let table = parse(&sample(5)).expect("parses");
    assert_eq!(table.len(), 5);
    assert_eq!(table.bodies(), ["ball", "rope"]);
    assert_eq!(table.probes(), ["p3"]);
    assert_eq!(table.time()[2], 0.02);
    assert_eq!(table.column("rope.volume").expect("column")[1], None);
    assert_eq!(table.column("ball.cz").expect("column")[1], Some(0.0));
    assert!(table.has_values("ball.pressure") && !table.has_values("rope.pressure"));
    assert!(table.is_zero("contact") && !table.is_zero("kinetic"));
    assert!(table.column("nothing").is_none());
    assert_eq!(Dimension::detect(&table), Dimension::Two);
    // Windows line ends, blank lines and a header with only the required
    // columns are fine.
    let short =
        "step,time,kinetic,spring,gravity,gas,total\r\n0,0,1,2,3,4,10\r\n\r\n1,0.5,1,2,3,4,10\r\n";
    assert_eq!(parse(short).expect("parses").len(), 2);
}

#[test]
fn malformed_files_are_refused_with_file_line_and_column() {
    let good = sample(3);
    let mut lines: Vec<&str> = good.lines().collect();
    let wrong_count = {
        lines[2] = "1,0.01,1,2";
        lines.join("\n")
    };
    let not_a_number = good.replacen("\n1,0.01,", "\n1,0.01,abc", 1);
    let no_time = good.replacen("\n2,0.02,", "\n2,,", 1);
    let no_header = good.lines().skip(1).collect::<Vec<_>>().join("\n");
    let twice = good.replacen("rope.cz", "rope.cy", 1);
    let infinite_time = good.replacen("\n2,0.02,", "\n2,inf,", 1);
    let cases: [(&str, &str, usize, &[&str]); 9] = [
        ("empty file", "", 1, &["empty file", "step,time,kinetic"]),
        ("blank file", "\n \n", 1, &["empty file"]),
        (
            "wrong column count",
            &wrong_count,
            3,
            &["4 values, expected 21"],
        ),
        (
            "non-numeric value",
            &not_a_number,
            3,
            &["column 3 (`kinetic`)", "`abc0", "not a number"],
        ),
        ("empty time", &no_time, 4, &["column 2 (`time`)", "empty"]),
        (
            "missing header",
            &no_header,
            1,
            &["header", "expected it to start with `step,time"],
        ),
        ("header only", HEADER, 1, &["no rows"]),
        ("duplicate column", &twice, 1, &["`rope.cy`", "twice"]),
        (
            "infinite time",
            &infinite_time,
            4,
            &["`time`", "not a finite number"],
        ),
    ];
    for (what, text, line, words) in cases {
        let error = parse(text).expect_err(what);
        let message = error.to_string();
        match &error {
            PlotError::Malformed { line: l, path, .. } => {
                assert_eq!(*l, line, "{what}: {message}");
                assert_eq!(path, Path::new("runs/x/diagnostics.csv"));
            }
            other => panic!("{what}: unexpected {other:?}"),
        }
        assert!(
            message.starts_with(&format!("runs/x/diagnostics.csv, line {line}")),
            "{what}: {message}"
        );
        for word in words {
            assert!(message.contains(word), "{what}: `{word}` not in: {message}");
        }
    }
}

#[test]
fn unreadable_files_and_folders_are_named() {
    let dir = tempfile::tempdir().expect("tempdir");
    let missing = dir.path().join("missing.csv");
    let message = DiagnosticsTable::read(&missing)
        .expect_err("missing")
        .to_string();
    assert!(
        message.contains("cannot read") && message.contains("missing.csv"),
        "{message}"
    );

    let binary = dir.path().join("binary.csv");
    std::fs::write(&binary, b"step,time\n0,\xff\xfe\n").expect("write");
    let message = DiagnosticsTable::read(&binary)
        .expect_err("not UTF-8")
        .to_string();
    assert!(
        message.contains("binary.csv, line 2: not UTF-8"),
        "{message}"
    );

    let empty_dir = dir.path().join("empty");
    std::fs::create_dir(&empty_dir).expect("mkdir");
    let error = plot::plot_run(&empty_dir, None, &small()).expect_err("no csv");
    assert!(
        matches!(error, PlotError::NoDiagnostics { .. }),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("has no diagnostics.csv"),
        "{error}"
    );
    let error = plot::plot_run(&dir.path().join("nowhere"), None, &small()).expect_err("no dir");
    assert!(error.to_string().contains("nowhere"), "{error}");
}

#[test]
fn mangled_files_give_errors_not_panics() {
    let good = sample(4);
    let replacements = ["", ",", "\n", "x", "-", ".", "e", "nan", ",,"];
    let mut parsed = 0;
    for (at, _) in good.char_indices() {
        for replacement in replacements {
            let mut text = good.clone();
            text.replace_range(at..at + 1, replacement);
            if let Ok(table) = parse(&text) {
                parsed += 1;
                // Draw a few of the survivors: odd values must not panic.
                if parsed % 40 == 0 {
                    energy_png(&table, "mangled", &small()).expect("energy");
                    gas_png(&table, "mangled", &small()).expect("gas");
                    probes_png(&table, "mangled", &small()).expect("probes");
                }
            }
        }
    }
    assert!(
        parsed > 100,
        "some mangled files are still well-formed ({parsed})"
    );
}

#[test]
fn a_run_gives_energy_gas_and_probe_plots_of_the_asked_size() {
    let root = tempfile::tempdir().expect("tempdir");
    let dir = run_dir(root.path(), "ball", &sample(120));
    let options = PlotOptions {
        width: 640,
        height: 400,
        ..PlotOptions::default()
    };
    let written = plot::plot_run(&dir, None, &options).expect("plots");
    let names: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    assert_eq!(written.len(), 3, "{names:?}");
    for name in ["energy.png", "gas.png", "probes.png"] {
        let file = dir.join("plots").join(name);
        assert!(written.contains(&file), "{name} not in {names:?}");
        assert_eq!(
            png_size(&std::fs::read(&file).expect("read")),
            (640, 400),
            "{name}"
        );
    }
    // The diagnostics file itself may be named instead of its folder.
    let other = root.path().join("elsewhere");
    plot::plot_run(
        &dir.join("diagnostics.csv"),
        Some(&other),
        &PlotOptions::default(),
    )
    .expect("plots");
    assert_eq!(
        png_size(&std::fs::read(other.join("energy.png")).expect("read")),
        (1000, 600)
    );
}

#[test]
fn the_same_csv_gives_the_same_bytes() {
    let table = parse(&sample(200)).expect("parses");
    let options = PlotOptions::default();
    let first = energy_png(&table, "run", &options).expect("draw");
    assert_eq!(first, energy_png(&table, "run", &options).expect("draw"));
    let gas = gas_png(&table, "run", &options).expect("draw");
    assert_eq!(gas, gas_png(&table, "run", &options).expect("draw"));
    assert!(gas.is_some());
}

#[test]
fn without_gas_or_probes_only_the_energy_is_plotted() {
    let root = tempfile::tempdir().expect("tempdir");
    let dir = run_dir(root.path(), "full", &sample(30));
    plot::plot_run(&dir, None, &small()).expect("plots");
    // The same folder re-run without gas and probes: stale plots go.
    let plain = "step,time,kinetic,spring,gravity,gas,total,contact,rope.volume,rope.pressure,rope.cx,rope.cy,rope.cz\n\
                 0,0,1,2,-3,0,0,0,,,0,0,0\n1,0.1,1.5,1.5,-3,0,0,0,,,0,-0.1,0\n";
    std::fs::write(dir.join("diagnostics.csv"), plain).expect("write");
    let written = plot::plot_run(&dir, None, &small()).expect("plots");
    assert_eq!(written, [dir.join("plots/energy.png")]);
    assert!(!dir.join("plots/gas.png").exists() && !dir.join("plots/probes.png").exists());
    let table = parse(plain).expect("parses");
    assert_eq!(gas_png(&table, "r", &small()).expect("draw"), None);
    assert_eq!(probes_png(&table, "r", &small()).expect("draw"), None);
}

#[test]
fn extreme_values_still_draw() {
    let head = "step,time,kinetic,spring,gravity,gas,total,contact,b.volume,b.pressure,b.cx,b.cy,b.cz,p0.x,p0.y,p0.z";
    let texts = [
        format!("{head}\n0,0,0,0,0,0,0,0,1,1,0,0,1,0,0,1\n"),
        format!("{head}\n0,0,1e300,-1e300,1e-300,0,1,0,1e308,-1e308,0,0,0,0,0,0\n1,1e-9,0,0,0,0,1,0,2e308,5,0,0,0,0,0,0\n"),
        format!("{head}\n0,5,1,1,1,1,4,0,,,0,0,0,,,\n1,5,1,1,1,1,4,0,,,0,0,0,,,\n"),
        format!("{head}\n0,0,NaN,inf,-inf,1,1,1,0,0,0,0,0,0,0,0\n1,1,1,1,1,1,1,1,0,0,0,0,0,0,0,0\n"),
    ];
    for text in &texts {
        let table = parse(text).expect("parses");
        for png in [
            Some(energy_png(&table, "x", &small()).expect("energy")),
            gas_png(&table, "x", &small()).expect("gas"),
            probes_png(&table, "x", &small()).expect("probes"),
        ]
        .into_iter()
        .flatten()
        {
            assert_eq!(png_size(&png), (320, 240));
        }
    }
}

#[test]
fn runs_are_compared_on_one_chart() {
    let root = tempfile::tempdir().expect("tempdir");
    let group = root.path().join("oscillator");
    let a = run_dir(&group, "euler", &sample(50));
    let b = run_dir(&group, "verlet", &sample(80));
    let runs = [a.clone(), b.clone()];
    assert_eq!(plot::compare_out_dir(&runs), group.join("plots"));
    // One run alone (or one holding another) is compared beside it, not
    // into its own plots.
    assert_eq!(plot::compare_out_dir(&runs[..1]), group.join("plots"));
    let inner = group.join("euler/again");
    assert_eq!(
        plot::compare_out_dir(&[a.clone(), inner]),
        group.join("plots")
    );
    // A run named from inside its folder or beside it: the folder above.
    assert_eq!(
        plot::compare_out_dir(&[PathBuf::from("run")]),
        PathBuf::from("run/../plots")
    );
    assert_eq!(
        plot::compare_out_dir(&[PathBuf::from(".")]),
        PathBuf::from("./../plots")
    );
    let file = plot::plot_compare(&runs, "total", None, &PlotOptions::default()).expect("compare");
    assert_eq!(file, group.join("plots/compare.png"));
    assert_eq!(png_size(&std::fs::read(&file).expect("read")), (1000, 600));
    for scale in [Scale::Linear, Scale::Log] {
        let options = PlotOptions { scale, ..small() };
        let file =
            plot::plot_compare(&runs, "ball.volume", None, &options).expect("compare volume");
        assert_eq!(file, group.join("plots/compare-ball.volume.png"));
    }
    let error = plot::plot_compare(&runs, "nothing", None, &small()).expect_err("no column");
    assert!(error.to_string().contains("no column `nothing`"), "{error}");
    let none: [(String, DiagnosticsTable); 0] = [];
    assert!(compare_png("none", &none, "total", &small()).is_err());
}

#[test]
fn every_allowed_shape_draws() {
    let table = parse(&sample(60)).expect("parses");
    for (width, height) in [(200, 200), (200, 1200), (2400, 200), (333, 777)] {
        let options = PlotOptions {
            width,
            height,
            ..PlotOptions::default()
        };
        for png in [
            energy_png(&table, "a run with a long name", &options).expect("energy"),
            gas_png(&table, "r", &options)
                .expect("gas")
                .expect("has gas"),
            probes_png(&table, "r", &options)
                .expect("probes")
                .expect("has probes"),
        ] {
            assert_eq!(png_size(&png), (width, height));
        }
    }
}

#[test]
fn sizes_out_of_range_are_refused() {
    let table = parse(&sample(3)).expect("parses");
    for (width, height) in [(0, 600), (1000, 10), (100_000, 600)] {
        let options = PlotOptions {
            width,
            height,
            ..PlotOptions::default()
        };
        let error = energy_png(&table, "x", &options).expect_err("size");
        assert!(error.to_string().contains("must be from"), "{error}");
    }
}

#[test]
fn a_killed_run_is_plotted_from_its_unfinished_table() {
    // A run killed before it finished leaves `diagnostics.csv.partial`,
    // its last row perhaps cut in the middle: the folder is plotted from
    // the whole rows, the cut one left out.
    let dir = tempfile::tempdir().expect("tempdir");
    let run = dir.path().join("killed");
    std::fs::create_dir(&run).expect("mkdir");
    let text = sample(30);
    let cut = text.len() - 7;
    std::fs::write(run.join("diagnostics.csv.partial"), &text[..cut]).expect("write");
    let table = plot::read_run(&run).expect("the whole rows");
    assert_eq!(table.len(), 29);
    let written = plot::plot_run(&run, None, &small()).expect("plots");
    assert!(written.iter().any(|f| f.ends_with("energy.png")));
    // A finished table is read as it is: a cut last row is an error there.
    std::fs::write(run.join("diagnostics.csv"), &text[..cut]).expect("write");
    assert!(plot::read_run(&run).is_err());
}
