//! ARCHITECTURE.md stays a true map: every file and folder of the engine
//! (`crates/sprung/src`) is named in its engine table, every row of that
//! table names something that exists, every `Stage` of `stage.rs` has its
//! section (files, types, threads, refusals) in the order the step runs
//! them, and the crate table lists the workspace's members with the
//! dependencies their `Cargo.toml`s declare. Each failure names what is
//! missing or stale. The checks are functions of a tree and a text, so the
//! unit tests below show each one failing on a temporary tree.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: cannot read it: {e}", path.display()))
}

/// Every file and folder under `src`, as paths relative to it with `/`
/// between parts, folders ending in `/`, sorted.
fn entries(src: &Path) -> Vec<String> {
    fn walk(dir: &Path, prefix: &str, out: &mut Vec<String>) {
        let mut children: Vec<_> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|entry| entry.expect("a directory entry").path())
            .collect();
        children.sort();
        for child in children {
            let name = child
                .file_name()
                .expect("a name")
                .to_string_lossy()
                .into_owned();
            if child.is_dir() {
                let folder = format!("{prefix}{name}/");
                out.push(folder.clone());
                walk(&child, &folder, out);
            } else {
                out.push(format!("{prefix}{name}"));
            }
        }
    }
    let mut out = Vec::new();
    walk(src, "", &mut out);
    out.sort();
    out
}

/// The lines of the section of `text` under the heading `heading` (a line
/// equal to it), up to the next heading of the same or a higher level.
fn section<'a>(text: &'a str, heading: &str) -> Vec<&'a str> {
    let level = heading.len() - heading.trim_start_matches('#').len();
    let mut lines = text.lines().skip_while(|line| *line != heading);
    if lines.next().is_none() {
        return Vec::new();
    }
    lines
        .take_while(|line| {
            let hashes = line.len() - line.trim_start_matches('#').len();
            !(hashes > 0 && hashes <= level && line[hashes..].starts_with(' '))
        })
        .collect()
}

/// The code spans (`` `...` ``) of `line`, without their backticks.
fn code_spans(line: &str) -> Vec<&str> {
    line.split('`').skip(1).step_by(2).collect()
}

/// The rows of the table in `lines`: their cells, trimmed, for each line
/// that starts with `|` and is not the header's rule.
fn table_rows(lines: &[&str]) -> Vec<Vec<String>> {
    lines
        .iter()
        .filter(|line| line.starts_with('|') && !line.starts_with("|---"))
        .map(|line| {
            line.trim_matches('|')
                .split(" | ")
                .map(|cell| cell.trim().to_string())
                .collect()
        })
        .collect()
}

/// The rows of the engine table: the path in the first cell's code span,
/// and the row's code spans.
fn engine_rows(architecture: &str) -> Vec<(String, BTreeSet<String>)> {
    let lines = section(architecture, "## The engine (`crates/sprung/src`)");
    table_rows(&lines)
        .into_iter()
        .filter_map(|cells| {
            let first = code_spans(&cells[0]).first()?.to_string();
            let named = cells
                .iter()
                .flat_map(|c| code_spans(c))
                .map(str::to_string)
                .collect();
            Some((first, named))
        })
        .collect()
}

/// What of `entries` the engine table leaves out: a top-level file needs
/// its own row, a folder its row (`name/`), and a file in a folder its name
/// in a code span of its folder's row.
fn unmapped(architecture: &str, entries: &[String]) -> Vec<String> {
    let rows = engine_rows(architecture);
    let row = |path: &str| {
        rows.iter()
            .find(|(first, _)| first == path)
            .map(|(_, named)| named)
    };
    entries
        .iter()
        .filter(|entry| match entry.rfind('/') {
            // A folder, or a file at the top: a row of its own.
            Some(slash) if slash + 1 < entry.len() => {
                let (folder, name) = entry.split_at(slash + 1);
                !row(folder).is_some_and(|named| named.contains(name))
            }
            _ => row(entry).is_none(),
        })
        .cloned()
        .collect()
}

/// The rows of the engine table that name nothing in `entries`.
fn stale(architecture: &str, entries: &[String]) -> Vec<String> {
    engine_rows(architecture)
        .into_iter()
        .map(|(first, _)| first)
        .filter(|first| !entries.contains(first))
        .collect()
}

/// The stages of `stage.rs`, in the order of its `name` match (the order
/// the step runs them): the variant and its name.
fn stages(stage_rs: &str) -> Vec<(String, String)> {
    stage_rs
        .lines()
        .filter_map(|line| {
            let (variant, name) = line.trim().strip_prefix("Stage::")?.split_once(" => \"")?;
            Some((variant.to_string(), name.strip_suffix("\",")?.to_string()))
        })
        .collect()
}

/// What is wrong with the stages' sections of `architecture`: a stage
/// without its `### name (`Stage::Variant`)` section, a section without
/// its four parts, or sections out of the step's order.
fn stage_faults(architecture: &str, stages: &[(String, String)]) -> Vec<String> {
    let mut faults = Vec::new();
    let mut last = 0;
    for (variant, name) in stages {
        let heading = format!("### {name} (`Stage::{variant}`)");
        let Some(at) = architecture.find(&format!("\n{heading}\n")) else {
            faults.push(format!("no section `{heading}`"));
            continue;
        };
        if at < last {
            faults.push(format!("`{heading}` is out of the step's order"));
        }
        last = at;
        let body = section(architecture, &heading).join("\n");
        for part in ["**Files**", "**Types**", "**Threads**", "**Refuses**"] {
            if !body.contains(part) {
                faults.push(format!("`{heading}` has no {part}"));
            }
        }
    }
    faults
}

/// The paths the stages' **Files** bullets name (a code span with a `/`
/// or ending in `.rs`, up to the next bullet) that are not in `entries`.
fn stale_files(architecture: &str, stages: &[(String, String)], entries: &[String]) -> Vec<String> {
    let mut gone = Vec::new();
    for (variant, name) in stages {
        let heading = format!("### {name} (`Stage::{variant}`)");
        let lines = section(architecture, &heading);
        let files = lines
            .iter()
            .skip_while(|line| !line.starts_with("- **Files**"))
            .enumerate()
            .take_while(|(k, line)| *k == 0 || !line.starts_with("- "))
            .flat_map(|(_, line)| code_spans(line));
        for path in files.filter(|p| p.contains('/') || p.ends_with(".rs")) {
            if !entries.iter().any(|entry| entry == path) {
                gone.push(format!("{heading}: `{path}`"));
            }
        }
    }
    gone
}

/// The workspace's members under `root` and each one's dependencies (its
/// `[dependencies]` and every target's), by name.
fn workspace(root: &Path) -> Vec<(String, BTreeSet<String>)> {
    let manifest: toml::Table = read(&root.join("Cargo.toml"))
        .parse()
        .expect("the workspace's Cargo.toml");
    let members = manifest["workspace"]["members"]
        .as_array()
        .expect("workspace.members");
    members
        .iter()
        .map(|member| {
            let member = member.as_str().expect("a member's path").to_string();
            let path = root.join(&member).join("Cargo.toml");
            let crate_manifest: toml::Table = read(&path).parse().expect("a member's Cargo.toml");
            let names = |table: Option<&toml::Value>| -> Vec<String> {
                table
                    .and_then(toml::Value::as_table)
                    .map(|t| t.keys().cloned().collect())
                    .unwrap_or_default()
            };
            let mut deps: BTreeSet<String> = names(crate_manifest.get("dependencies"))
                .into_iter()
                .collect();
            if let Some(targets) = crate_manifest.get("target").and_then(toml::Value::as_table) {
                for target in targets.values() {
                    deps.extend(names(target.get("dependencies")));
                }
            }
            (member, deps)
        })
        .collect()
}

/// The crate table's rows: the crate's path and the names of its
/// dependencies (the last cell, each name before any parenthesis).
fn crate_table(architecture: &str) -> Vec<(String, BTreeSet<String>)> {
    table_rows(&section(architecture, "## Crates"))
        .into_iter()
        .filter_map(|cells| {
            let path = code_spans(&cells[0]).first()?.to_string();
            let deps = cells
                .last()?
                .split(',')
                .map(|dep| dep.split('(').next().unwrap_or("").trim().to_string())
                .filter(|dep| !dep.is_empty())
                .collect();
            Some((path, deps))
        })
        .collect()
}

/// Where the crate table and the workspace differ.
fn crate_faults(
    table: &[(String, BTreeSet<String>)],
    members: &[(String, BTreeSet<String>)],
) -> Vec<String> {
    let mut faults = Vec::new();
    for (member, deps) in members {
        match table.iter().find(|(path, _)| path == member) {
            None => faults.push(format!("no row for the member `{member}`")),
            Some((_, listed)) if listed != deps => faults.push(format!(
                "`{member}`: the table lists {listed:?}, its Cargo.toml declares {deps:?}"
            )),
            Some(_) => {}
        }
    }
    for (path, _) in table {
        if !members.iter().any(|(member, _)| member == path) {
            faults.push(format!("the row `{path}` is not a workspace member"));
        }
    }
    faults
}

fn architecture() -> String {
    read(&root().join("ARCHITECTURE.md"))
}

#[test]
fn every_engine_file_and_folder_is_mapped_and_every_row_exists() {
    let (text, entries) = (architecture(), entries(&root().join("crates/sprung/src")));
    assert!(
        entries.len() > 100,
        "the engine's tree was read: {} entries",
        entries.len()
    );
    let left_out = unmapped(&text, &entries);
    assert!(
        left_out.is_empty(),
        "ARCHITECTURE.md's engine table leaves out {left_out:?}"
    );
    let gone = stale(&text, &entries);
    assert!(
        gone.is_empty(),
        "ARCHITECTURE.md's engine table names what is not there: {gone:?}"
    );
}

#[test]
fn every_stage_has_its_section_in_the_steps_order() {
    let stages = stages(&read(&root().join("crates/sprung/src/stage.rs")));
    assert_eq!(
        stages.len(),
        11,
        "the stages of stage.rs were read: {stages:?}"
    );
    let faults = stage_faults(&architecture(), &stages);
    assert!(faults.is_empty(), "ARCHITECTURE.md: {faults:?}");
    let entries = entries(&root().join("crates/sprung/src"));
    let gone = stale_files(&architecture(), &stages, &entries);
    assert!(
        gone.is_empty(),
        "ARCHITECTURE.md's stage sections name files that are not there: {gone:?}"
    );
}

#[test]
fn the_crate_table_matches_the_cargo_tomls() {
    let members = workspace(&root());
    assert!(
        members.len() >= 7,
        "the workspace's members were read: {members:?}"
    );
    let faults = crate_faults(&crate_table(&architecture()), &members);
    assert!(
        faults.is_empty(),
        "ARCHITECTURE.md's crate table: {faults:?}"
    );
}

/// A temporary tree: `src/lib.rs`, `src/a/mod.rs`, `src/a/new.rs`, and a
/// workspace of one member `m` depending on `x` and, on one target, `y`.
fn temporary_tree() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let write = |path: &str, text: &str| {
        let path = dir.path().join(path);
        std::fs::create_dir_all(path.parent().expect("a parent")).expect("its folder");
        std::fs::write(path, text).expect("written");
    };
    write("src/lib.rs", "");
    write("src/a/mod.rs", "");
    write("src/a/new.rs", "");
    write("Cargo.toml", "[workspace]\nmembers = [\"m\"]\n");
    write(
        "m/Cargo.toml",
        "[package]\nname = \"m\"\n[dependencies]\nx = \"1\"\n[target.'cfg(unix)'.dependencies]\ny = \"1\"\n",
    );
    dir
}

#[test]
fn the_map_check_fails_on_an_unmapped_file_and_a_stale_row() {
    let tree = temporary_tree();
    let entries = entries(&tree.path().join("src"));
    assert_eq!(entries, ["a/", "a/mod.rs", "a/new.rs", "lib.rs"]);
    let text = "## The engine (`crates/sprung/src`)\n\n| file | holds |\n|---|---|\n\
                | `lib.rs` | the root |\n| `a/` | `mod.rs`: a |\n| `gone.rs` | was here |\n\n## Next\n\n| `b/` | not the map |\n";
    assert_eq!(unmapped(text, &entries), ["a/new.rs"]);
    assert_eq!(stale(text, &entries), ["gone.rs"]);
    let mapped = text.replace("`mod.rs`: a", "`mod.rs`: a; `new.rs`: the new one");
    assert!(unmapped(&mapped, &entries).is_empty());
}

#[test]
fn the_stage_check_fails_on_a_missing_section_or_part() {
    let stages =
        stages("        Stage::Detect => \"detect\",\n        Stage::Guard => \"guard\",\n");
    assert_eq!(
        stages,
        [
            ("Detect".into(), "detect".into()),
            ("Guard".into(), "guard".into())
        ]
    );
    let whole = "\n### detect (`Stage::Detect`)\n\n- **Files**\n- **Types**\n- **Threads**\n- **Refuses**\n";
    let text =
        format!("{whole}\n### guard (`Stage::Guard`)\n\n- **Files**\n- **Types**\n- **Threads**\n");
    assert_eq!(
        stage_faults(&text, &stages),
        ["`### guard (`Stage::Guard`)` has no **Refuses**"]
    );
    assert_eq!(
        stage_faults(whole, &stages),
        ["no section `### guard (`Stage::Guard`)`"]
    );
    // A file a section names that the tree lacks, on the bullet's second
    // line; what the next bullet names is not a file.
    let text = "\n### detect (`Stage::Detect`)\n\n- **Files**: `a/`,\n  `a/gone.rs`, `lib.rs`.\n\
                - **Types**: `b/c.rs`\n";
    let entries = [
        "a/".to_string(),
        "a/mod.rs".to_string(),
        "lib.rs".to_string(),
    ];
    assert_eq!(
        stale_files(text, &stages[..1], &entries),
        ["### detect (`Stage::Detect`): `a/gone.rs`"]
    );
}

#[test]
fn the_crate_check_fails_on_a_dependency_left_out() {
    let tree = temporary_tree();
    let members = workspace(tree.path());
    let table = |deps: &str| {
        format!(
            "## Crates\n\n| crate | what | depends on |\n|---|---|---|\n| `m` | it | {deps} |\n"
        )
    };
    assert!(crate_faults(&crate_table(&table("x, y (unix)")), &members).is_empty());
    let faults = crate_faults(&crate_table(&table("x")), &members);
    assert_eq!(faults.len(), 1, "{faults:?}");
    assert!(faults[0].starts_with("`m`: the table lists"), "{faults:?}");
}
