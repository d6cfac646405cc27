//! The documentation holds together: every relative link of README.md,
//! CHANGELOG.md, CONTRIBUTING.md, ARCHITECTURE.md and `docs/*.md` reaches
//! a file, and every `#anchor` a heading of it (GitHub's slugs), and the
//! README stays a front door: at most 250 lines, the demo and test commands
//! at its top (CI and users copy them). Each failure names the file, the
//! line and the link.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The documents whose links are checked, as paths from the root.
fn documents() -> Vec<PathBuf> {
    let mut documents: Vec<PathBuf> = [
        "README.md",
        "CHANGELOG.md",
        "CONTRIBUTING.md",
        "ARCHITECTURE.md",
    ]
    .into_iter()
    .map(PathBuf::from)
    .collect();
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .expect("docs/ exists")
        .map(|entry| entry.expect("a docs/ entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .map(|path| Path::new("docs").join(path.file_name().expect("a file name")))
        .collect();
    pages.sort();
    documents.extend(pages);
    documents
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(root().join(path))
        .unwrap_or_else(|e| panic!("{}: cannot read it: {e}", path.display()))
}

/// The lines of `text` outside fenced code blocks, with their numbers
/// (from 1).
fn prose_lines(text: &str) -> Vec<(usize, &str)> {
    let mut fence: Option<&str> = None;
    let mut lines = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        let marker = ["```", "~~~"]
            .into_iter()
            .find(|m| trimmed.starts_with(m) && line.len() - trimmed.len() <= 3);
        match (fence, marker) {
            (None, Some(m)) => fence = Some(m),
            (Some(open), Some(m)) if open == m && trimmed.trim_end() == m => fence = None,
            (None, None) => lines.push((index + 1, line)),
            _ => {}
        }
    }
    lines
}

/// `line` without its inline code spans (`` `...` ``), which hold no links.
fn without_code(line: &str) -> String {
    let mut out = String::new();
    let mut rest = line;
    while let Some(start) = rest.find('`') {
        out.push_str(&rest[..start]);
        let ticks = rest[start..].len() - rest[start..].trim_start_matches('`').len();
        let fence = &rest[start..start + ticks];
        match rest[start + ticks..].find(fence) {
            Some(end) => rest = &rest[start + ticks + end + ticks..],
            None => {
                out.push_str(&rest[start..]);
                rest = "";
            }
        }
    }
    out.push_str(rest);
    out
}

/// The link targets of `text` with their line numbers: inline links and
/// images, `[text](target)` and `![alt](target)`, and reference
/// definitions, `[label]: target`; none inside code.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for (number, line) in prose_lines(text) {
        let line = without_code(line);
        let mut rest = line.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let target = match after.strip_prefix('<') {
                Some(inside) => inside.split('>').next().unwrap_or(""),
                None => after
                    .split(|c: char| c == ')' || c.is_whitespace())
                    .next()
                    .unwrap_or(""),
            };
            found.push((number, target.to_string()));
            rest = after;
        }
        let trimmed = line.trim_start();
        if let Some(label_end) = trimmed.strip_prefix('[').and_then(|r| r.find("]: ")) {
            let target = trimmed[1 + label_end + 3..].split_whitespace().next();
            found.push((number, target.unwrap_or("").to_string()));
        }
    }
    found
}

/// GitHub's anchor for a heading's text: links reduced to their text,
/// lowercased, every character but letters, digits, spaces, `-` and `_`
/// dropped, spaces turned into `-`.
fn slug(heading: &str) -> String {
    let mut text = String::new();
    let mut rest = heading;
    // `[text](target)` reads as `text`.
    while let Some(open) = rest.find('[') {
        let Some(close) = rest[open..].find("](").map(|c| open + c) else {
            break;
        };
        let Some(end) = rest[close..].find(')').map(|e| close + e) else {
            break;
        };
        text.push_str(&rest[..open]);
        text.push_str(&rest[open + 1..close]);
        rest = &rest[end + 1..];
    }
    text.push_str(rest);
    text.trim()
        .chars()
        .flat_map(char::to_lowercase)
        .filter_map(|c| match c {
            ' ' => Some('-'),
            '-' | '_' => Some(c),
            c if c.is_alphanumeric() => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of a document's headings (`#` to `######`, outside code),
/// a repeated one numbered `-1`, `-2`, ... as GitHub does.
fn anchors(text: &str) -> Vec<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut anchors = Vec::new();
    for (_, line) in prose_lines(text) {
        let hashes = line.len() - line.trim_start_matches('#').len();
        if !(1..=6).contains(&hashes) || !line[hashes..].starts_with(' ') {
            continue;
        }
        let base = slug(line[hashes..].trim().trim_end_matches('#'));
        let count = seen.entry(base.clone()).or_insert(0);
        anchors.push(match *count {
            0 => base.clone(),
            n => format!("{base}-{n}"),
        });
        *count += 1;
    }
    anchors
}

/// What is wrong with the link `target` of the document `from` (a path
/// from the root), if anything.
fn broken(from: &Path, target: &str) -> Option<String> {
    if target.is_empty() {
        return Some("an empty target".into());
    }
    if ["http://", "https://", "mailto:"]
        .iter()
        .any(|scheme| target.starts_with(scheme))
    {
        return None;
    }
    let (file, anchor) = match target.split_once('#') {
        Some((file, anchor)) => (file, Some(anchor)),
        None => (target, None),
    };
    let path = if file.is_empty() {
        from.to_path_buf()
    } else {
        from.parent().unwrap_or(Path::new("")).join(file)
    };
    let on_disk = root().join(&path);
    if !on_disk.exists() {
        return Some(format!("{} does not exist", path.display()));
    }
    let anchor = anchor?;
    if on_disk.extension().is_none_or(|e| e != "md") {
        return Some(format!(
            "#{anchor} points into {}, which is not a markdown file",
            path.display()
        ));
    }
    let headings = anchors(&std::fs::read_to_string(&on_disk).ok()?);
    (!headings.iter().any(|h| h == anchor)).then(|| {
        format!(
            "{} has no heading #{anchor} (its anchors: {})",
            path.display(),
            headings.join(", ")
        )
    })
}

#[test]
fn every_relative_link_of_the_documentation_reaches_its_file_and_heading() {
    // Claim: no link of the front door, the changelog, the contributing
    // guide, the architecture map or a docs/ page leads nowhere.
    let mut problems = Vec::new();
    let mut checked = 0;
    for document in documents() {
        for (line, target) in links(&read(&document)) {
            checked += 1;
            if let Some(problem) = broken(&document, &target) {
                problems.push(format!(
                    "{}:{line}: link ({target}): {problem}",
                    document.display()
                ));
            }
        }
    }
    assert!(
        problems.is_empty(),
        "{} of {checked} links are broken:\n{}",
        problems.len(),
        problems.join("\n")
    );
    // The README links into the guides, so there is something to check.
    assert!(checked >= 20, "only {checked} links found");
}

#[test]
fn the_readme_is_a_front_door_of_at_most_250_lines() {
    let lines = read(Path::new("README.md")).lines().count();
    assert!(
        lines <= 250,
        "README.md has {lines} lines, at most 250: move the details to a page under docs/ and link to it"
    );
}

#[test]
fn the_readme_starts_with_the_demo_and_test_commands() {
    // CI and users copy these two lines from the top of the README.
    let readme = read(Path::new("README.md"));
    for command in [
        "cargo run --release -p sprung-cli -- demo",
        "scripts/test.sh",
    ] {
        let line = readme
            .lines()
            .take(30)
            .position(|line| line.starts_with(command));
        assert!(
            line.is_some(),
            "README.md: no line of its first 30 starts with `{command}`"
        );
    }
}

#[test]
fn slugs_follow_githubs_rules() {
    // The anchors GitHub gives the headings this repository has.
    for (heading, anchor) in [
        ("The step (`World::step`)", "the-step-worldstep"),
        ("Where to add …", "where-to-add-"),
        (
            "4. Pressure: the gas inside a soft body",
            "4-pressure-the-gas-inside-a-soft-body",
        ),
        ("Options of `run` and `demo`", "options-of-run-and-demo"),
        ("diagnostics.csv", "diagnosticscsv"),
        ("[Unreleased]", "unreleased"),
        ("A [link](x.md) and snake_case", "a-link-and-snake_case"),
    ] {
        assert_eq!(slug(heading), anchor, "{heading}");
    }
    assert_eq!(anchors("# A\n\n## A\n### A\n"), ["a", "a-1", "a-2"]);
}

#[test]
fn links_are_found_in_prose_and_not_in_code() {
    let text = "See [a](a.md#x) and ![b](img/b.png).\n\
                `[c](c.md)` is code.\n\
                ```\n[d](d.md)\n```\n\
                [![e](e.gif)](f.md)\n\
                [g]: g.md\n\
                ## A heading [h](h.md)\n";
    let found: Vec<(usize, String)> = links(text);
    let expected = [
        (1, "a.md#x"),
        (1, "img/b.png"),
        (6, "e.gif"),
        (6, "f.md"),
        (7, "g.md"),
        (8, "h.md"),
    ];
    assert_eq!(
        found,
        expected.map(|(line, target)| (line, target.to_string()))
    );
}
