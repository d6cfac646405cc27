//! Overrides of a scene's keys, `KEY=VALUE` as typed after `--set` on the
//! command line: `sim.dt=1e-4`, `sim.integrator=rk4`,
//! `body.ball.gas.nrt=800`, `collider.0.friction=0.5`.
//!
//! KEY is a dotted path into the scene's tables; where it passes through an
//! array of tables (`body`, `collider`) the next part picks one of them, by
//! its index from 0 or, failing that, by its `name`. VALUE is a TOML value,
//! or a bare word taken as a string. The scene's text is read as one TOML
//! table, the overrides set in it, and the table written out again as the
//! effective scene, which is built as any scene is.

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use toml::{Table, Value};

use super::read::parse_toml;
use super::{parse_scene_with, Disk, FileSource, Scene, SceneError};

/// The arrays of tables at the top of a scene, which a key picks an
/// element of (never created by an override: a missing one is empty).
const ARRAYS: [(&str, &str); 2] = [("body", "bodies"), ("collider", "colliders")];

/// The most dotted parts a key may have: the deepest key of a scene
/// (`body.NAME.gas.schedule.0.1`) has 6.
pub const MAX_KEY_PARTS: usize = 32;

/// The most bytes a key may have.
pub const MAX_KEY_BYTES: usize = 4096;

/// The most levels of arrays and inline tables a value may nest (an
/// override's value, and every value of a scene file): a scene's deepest
/// (a body's `particles`, a list of points) has 2.
pub const MAX_VALUE_DEPTH: usize = 32;

/// One override of a scene's key: `KEY=VALUE`.
///
/// ```
/// use std::path::Path;
/// use sprung_io::{parse_scene_overridden, Disk, Override};
///
/// let text = "[sim]\ndt = 1e-3\nsteps = 10\n\n[[body]]\nname = \"rope\"\nrope = { particles = 8, length = 1.0 }\n";
/// let overrides: Vec<Override> = ["sim.dt=2e-3", "body.rope.rope.particles=4", "sim.integrator=rk4"]
///     .iter()
///     .map(|s| s.parse().unwrap())
///     .collect();
/// let scene = parse_scene_overridden(text, Path::new("rope.toml"), &overrides, &Disk).unwrap();
/// assert_eq!((scene.dt, scene.world.particles.len()), (2e-3, 4));
/// assert_eq!(scene.world.integrator(), sprung::IntegratorKind::Rk4);
///
/// // An error of an override names its key.
/// let typo = [Override::new("body.rope.stifness", toml::Value::Float(10.0))];
/// let error = parse_scene_overridden(text, Path::new("rope.toml"), &typo, &Disk).unwrap_err();
/// assert!(error.message.starts_with("`--set body.rope.stifness`: unknown field `stifness`"), "{error}");
/// assert_eq!(error.key.as_deref(), Some("body.rope.stifness"));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Override {
    /// The dotted key: `sim.dt`, `body.NAME.stiffness`, `collider.0.friction`.
    pub key: String,
    /// The value to set there.
    pub value: Value,
}

/// A `KEY=VALUE` argument that is not an override: no `=`, an empty or
/// malformed key, or an empty value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OverrideError {
    /// The argument as given.
    pub argument: String,
    /// What is wrong with it.
    pub message: String,
}

impl fmt::Display for OverrideError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}`: {}", self.argument, self.message)
    }
}

impl std::error::Error for OverrideError {}

impl Override {
    /// Set `key` (dotted, as in `KEY=VALUE`) to `value`, already typed. The
    /// key is checked when the override is applied.
    pub fn new(key: impl Into<String>, value: Value) -> Self {
        Override {
            key: key.into(),
            value,
        }
    }

    /// Set the key in `scene`, a scene's tables: the tables on the way are
    /// made where missing, an array of tables is entered at the element
    /// the next part picks. The error names what is missing or in the way
    /// (not the override, which the caller names).
    pub fn apply(&self, scene: &mut Table) -> Result<(), String> {
        let parts = key_parts(&self.key)?;
        check_value_depth(&self.value)?;
        set_in_table(scene, &parts, 0, self.value.clone())
    }
}

impl FromStr for Override {
    type Err = OverrideError;

    /// `KEY=VALUE`: VALUE is a TOML value (`1e-4`, `true`, `[0, 1, 0]`,
    /// `"rk4"`, `{ nx = 4, ny = 4 }`), or a bare word of letters, digits,
    /// `_`, `-` and `.` taken as a string (`rk4`).
    fn from_str(argument: &str) -> Result<Self, OverrideError> {
        let refuse = |message: String| OverrideError {
            argument: argument.to_string(),
            message,
        };
        // The first `=` outside a quoted part of the key.
        let mut quoted = false;
        let equals = argument.find(|c| {
            quoted ^= c == '"';
            c == '=' && !quoted
        });
        let Some((key, value)) = equals.map(|at| (&argument[..at], &argument[at + 1..])) else {
            return Err(refuse(
                "expected KEY=VALUE (`sim.dt=1e-4`): there is no `=`".into(),
            ));
        };
        let key = key.trim();
        key_parts(key).map_err(refuse)?;
        let value = value.trim();
        if value.is_empty() {
            return Err(refuse(format!(
                "the value of `{key}` is empty: give a TOML value (`1e-4`, `true`, `\"rk4\"`, `[0, 1, 0]`)"
            )));
        }
        // Nesting is counted before the TOML reader, which recurses.
        check_text_depth(value).map_err(refuse)?;
        let value = match value.parse::<Value>() {
            Ok(value) => value,
            Err(_) if is_bare_word(value) => Value::String(value.to_string()),
            Err(e) => {
                return Err(refuse(format!(
                    "`{value}` is not a TOML value ({}): quote a string (`'\"{value}\"'`)",
                    e.message().trim()
                )))
            }
        };
        Ok(Override::new(key, value))
    }
}

/// Refuse `value` where it nests arrays and tables deeper than
/// [`MAX_VALUE_DEPTH`] (counted without recursion, so that no depth
/// overflows the stack).
pub fn check_value_depth(value: &Value) -> Result<(), String> {
    let mut stack = vec![(value, 0_usize)];
    while let Some((value, depth)) = stack.pop() {
        let children: Box<dyn Iterator<Item = &Value>> = match value {
            Value::Array(items) => Box::new(items.iter()),
            Value::Table(table) => Box::new(table.values()),
            _ => continue,
        };
        if depth >= MAX_VALUE_DEPTH {
            return Err(too_deep());
        }
        stack.extend(children.map(|child| (child, depth + 1)));
    }
    Ok(())
}

/// Refuse TOML `text` whose brackets and braces (outside strings) nest
/// deeper than [`MAX_VALUE_DEPTH`], before a reader that recurses sees it.
pub fn check_text_depth(text: &str) -> Result<(), String> {
    match too_deep_at(text) {
        Some(_) => Err(too_deep()),
        None => Ok(()),
    }
}

/// The byte of `text` (TOML) at which its brackets and braces, outside
/// strings and comments, first nest deeper than [`MAX_VALUE_DEPTH`], if
/// they do (a table header's brackets close before any value opens).
pub(super) fn too_deep_at(text: &str) -> Option<usize> {
    let (mut depth, mut quote, mut escaped) = (0_usize, None, false);
    let mut comment = false;
    for (at, c) in text.char_indices() {
        if comment {
            comment = c != '\n';
            continue;
        }
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if c == '\\' && q == '"' {
                    escaped = true;
                } else if c == q {
                    quote = None;
                }
            }
            None => match c {
                '"' | '\'' => quote = Some(c),
                '#' => comment = true,
                '[' | '{' => {
                    depth += 1;
                    if depth > MAX_VALUE_DEPTH {
                        return Some(at);
                    }
                }
                ']' | '}' => depth = depth.saturating_sub(1),
                _ => {}
            },
        }
    }
    None
}

/// The error of a value nested too deep.
fn too_deep() -> String {
    format!(
        "the value nests arrays or tables more than {MAX_VALUE_DEPTH} deep, the most a value may"
    )
}

impl fmt::Display for Override {
    /// `KEY=VALUE`, the value in TOML.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}={}", self.key, self.value)
    }
}

/// Letters, digits, `_`, `-` and `.`: a word taken as a string.
fn is_bare_word(value: &str) -> bool {
    value
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// The parts of a dotted key: bare (letters, digits, `_`, `-`) or in
/// double quotes (`body."my ball".mass`).
fn key_parts(key: &str) -> Result<Vec<String>, String> {
    if key.is_empty() {
        return Err("the key is empty: expected KEY=VALUE (`sim.dt=1e-4`)".into());
    }
    if key.len() > MAX_KEY_BYTES {
        return Err(format!(
            "the key is {} bytes long, more than the {MAX_KEY_BYTES} a key may have",
            key.len()
        ));
    }
    let mut parts = Vec::new();
    let mut rest = key;
    loop {
        let (part, after) = match rest.strip_prefix('"') {
            Some(quoted) => {
                let end = quoted
                    .find('"')
                    .ok_or_else(|| format!("`{key}`: a quote is not closed"))?;
                (&quoted[..end], &quoted[end + 1..])
            }
            None => {
                let end = rest.find('.').unwrap_or(rest.len());
                let part = &rest[..end];
                if part.is_empty() {
                    return Err(format!(
                        "`{key}` has an empty part: parts are joined by single dots (`sim.dt`)"
                    ));
                }
                if let Some(bad) = part
                    .chars()
                    .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-')))
                {
                    return Err(format!(
                        "`{key}`: `{bad}` in `{part}`; a part is letters, digits, `_` and `-`, or a name in double quotes (`body.\"my ball\".mass`)"
                    ));
                }
                (part, &rest[end..])
            }
        };
        parts.push(part.to_string());
        if parts.len() > MAX_KEY_PARTS {
            return Err(format!(
                "the key has more than the {MAX_KEY_PARTS} dotted parts a key may have"
            ));
        }
        if after.is_empty() {
            return Ok(parts);
        }
        rest = after
            .strip_prefix('.')
            .ok_or_else(|| format!("`{key}`: expected a `.` after `{part}`"))?;
        if rest.is_empty() {
            return Err(format!("`{key}` ends with a dot: the last part is missing"));
        }
    }
}

/// `parts[..n]` as a dotted key (parts that are not bare words quoted).
fn dotted(parts: &[String]) -> String {
    let quoted: Vec<String> = parts
        .iter()
        .map(|p| {
            if !p.is_empty()
                && p.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                p.clone()
            } else {
                format!("\"{p}\"")
            }
        })
        .collect();
    quoted.join(".")
}

/// Set `parts[at..]` in `table` to `value`.
fn set_in_table(
    table: &mut Table,
    parts: &[String],
    at: usize,
    value: Value,
) -> Result<(), String> {
    let name = &parts[at];
    if at + 1 == parts.len() {
        table.insert(name.clone(), value);
        return Ok(());
    }
    let entry = table.entry(name.clone()).or_insert_with(|| {
        // The top arrays are never made up: picking from a missing one
        // says there is none.
        match ARRAYS.iter().any(|(array, _)| at == 0 && array == name) {
            true => Value::Array(Vec::new()),
            false => Value::Table(Table::new()),
        }
    });
    set_in_value(entry, parts, at + 1, value)
}

/// Set `parts[at..]` inside `target`, the value at `parts[..at]`.
fn set_in_value(
    target: &mut Value,
    parts: &[String],
    at: usize,
    value: Value,
) -> Result<(), String> {
    match target {
        Value::Table(table) => set_in_table(table, parts, at, value),
        Value::Array(items) => {
            let index = pick(items, parts, at)?;
            if at + 1 == parts.len() {
                items[index] = value;
                Ok(())
            } else {
                set_in_value(&mut items[index], parts, at + 1, value)
            }
        }
        other => Err(format!(
            "`{}` is {} ({other}), not a table: there is no `{}` in it",
            dotted(&parts[..at]),
            a_type(other),
            parts[at]
        )),
    }
}

/// "a float", "an integer", ...
fn a_type(value: &Value) -> String {
    let name = value.type_str();
    let article = if name.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    };
    format!("{article} {name}")
}

/// The index in `items` (the array at `parts[..at]`) that `parts[at]`
/// picks: an index from 0, or the `name` of a table in it.
fn pick(items: &[Value], parts: &[String], at: usize) -> Result<usize, String> {
    let array = dotted(&parts[..at]);
    let part = &parts[at];
    let (one, many) = match ARRAYS.iter().find(|(name, _)| at == 1 && *name == array) {
        Some(&(one, many)) => (one.to_string(), many.to_string()),
        None => ("entry".to_string(), "entries".to_string()),
    };
    if let Ok(index) = part.parse::<usize>() {
        return match items.len() {
            _ if index < items.len() => Ok(index),
            0 => Err(format!(
                "there is no {one} {index}: the scene has no {many}"
            )),
            n => Err(format!(
                "there is no {one} {index}: `{array}` has {n} {}, numbered from 0 to {}",
                if n == 1 { &one } else { &many },
                n - 1
            )),
        };
    }
    let name_of = |item: &Value| item.get("name").and_then(Value::as_str).map(str::to_string);
    if let Some(index) = items
        .iter()
        .position(|item| name_of(item).as_deref() == Some(part.as_str()))
    {
        return Ok(index);
    }
    let names: Vec<String> = items
        .iter()
        .filter_map(name_of)
        .map(|n| format!("\"{n}\""))
        .collect();
    Err(match names.len() {
        0 if items.is_empty() => format!("there is no {one} named \"{part}\": the scene has no {many}"),
        0 => format!(
            "`{array}` is a list without names: pick an entry by its index from 0 to {} (`{array}.0`)",
            items.len() - 1
        ),
        _ => format!(
            "there is no {one} named \"{part}\": the {many} are {} (or pick one by its index from 0)",
            names.join(", ")
        ),
    })
}

/// The scene's `text` read as one TOML table, with `overrides` applied in
/// turn; `path` names the scene in errors. An error of an override names
/// its key ([`SceneError::key`]); text that is not TOML is refused at its
/// line, as [`parse_scene`](super::parse_scene) refuses it.
pub fn overridden_table(
    text: &str,
    path: &Path,
    overrides: &[Override],
) -> Result<Table, SceneError> {
    overridden(text, path, overrides).map_err(|(_, error)| error)
}

/// [`overridden_table`], its error marked `true` when it is the text's own
/// (not TOML), `false` when it is an override's.
fn overridden(
    text: &str,
    path: &Path,
    overrides: &[Override],
) -> Result<Table, (bool, SceneError)> {
    super::check_text(text, path).map_err(|e| (true, e))?;
    let mut table: Table = parse_toml(text, 0, text, path).map_err(|e| (true, e))?;
    for item in overrides {
        item.apply(&mut table)
            .map_err(|m| (false, blame(path, item, &m)))?;
    }
    Ok(table)
}

/// The scene's `text` with `overrides` applied, as TOML text: the
/// effective scene. Every number is written so that it reads back the
/// same to the bit; comments are not kept.
pub fn apply_overrides(
    text: &str,
    path: &Path,
    overrides: &[Override],
) -> Result<String, SceneError> {
    let table = overridden_table(text, path, overrides)?;
    scene_toml(&table, path)
}

/// The tables of a scene as TOML text.
pub fn scene_toml(table: &Table, path: &Path) -> Result<String, SceneError> {
    let mut text = toml::to_string(table).map_err(|e| {
        let message = format!("the overridden scene cannot be written as TOML: {e}");
        SceneError::new(path, None, message)
    })?;
    if !text.ends_with('\n') {
        text.push('\n');
    }
    Ok(text)
}

/// The error of `item`: `message` after the override's key.
fn blame(path: &Path, item: &Override, message: &str) -> SceneError {
    SceneError::new(path, None, format!("`--set {}`: {message}", item.key)).with_key(&item.key)
}

/// Build the scene `text` (at `path`, which anchors its relative paths)
/// with `overrides` applied, its files read from `files`.
///
/// With no overrides this is [`parse_scene_with`]. With some, an error of
/// the scene itself is reported as without them, at its line; an error
/// that only the overrides bring is reported as an error of the one
/// that brings it (the first whose addition makes the scene fail), naming
/// its key, without a line. The warnings of an overridden scene name no
/// line (they were found in the effective text, not the file).
pub fn parse_scene_overridden(
    text: &str,
    path: &Path,
    overrides: &[Override],
    files: &dyn FileSource,
) -> Result<Scene, SceneError> {
    if overrides.is_empty() {
        return parse_scene_with(text, path, files);
    }
    let effective = match overridden(text, path, overrides) {
        Ok(table) => scene_toml(&table, path)?,
        // Not TOML: the error exactly as the scene reader gives it.
        Err((true, error)) => {
            return Err(parse_scene_with(text, path, files).err().unwrap_or(error))
        }
        Err((false, error)) => return Err(error),
    };
    match parse_scene_with(&effective, path, files) {
        Ok(mut scene) => {
            let file = path.display().to_string();
            for warning in &mut scene.warnings {
                *warning = without_line(warning, &file);
            }
            Ok(scene)
        }
        Err(error) => {
            // The file's own error first, at its line.
            parse_scene_with(text, path, files)?;
            let culprit = culprit(text, path, overrides, files, &error);
            // "`dt`: invalid type ..." says `dt` once: after the override.
            let last = key_parts(&culprit.key).ok().and_then(|mut p| p.pop());
            let message = last
                .and_then(|last| error.message.strip_prefix(&format!("`{last}`: ")))
                .unwrap_or(&error.message);
            Err(blame(path, culprit, message))
        }
    }
}

/// The override to blame for `error` of the effective scene (the scene
/// alone builds): the one override whose last part is the error's key, or
/// else the first whose addition makes the scene fail.
fn culprit<'a>(
    text: &str,
    path: &Path,
    overrides: &'a [Override],
    files: &dyn FileSource,
    error: &SceneError,
) -> &'a Override {
    let last = overrides.len() - 1;
    let named: Vec<&Override> = overrides
        .iter()
        .filter(|o| {
            error.key.is_some()
                && key_parts(&o.key).ok().and_then(|p| p.last().cloned()) == error.key
        })
        .collect();
    if let [one] = named[..] {
        return one;
    }
    let fails = |count: usize| {
        apply_overrides(text, path, &overrides[..count])
            .map_or(true, |t| parse_scene_with(&t, path, files).is_err())
    };
    let first = (1..last + 1)
        .find(|&count| fails(count))
        .unwrap_or(last + 1);
    &overrides[first - 1]
}

/// `warning` (`FILE:LINE: message`) without its line.
fn without_line(warning: &str, file: &str) -> String {
    let Some(rest) = warning
        .strip_prefix(file)
        .and_then(|rest| rest.strip_prefix(':'))
    else {
        return warning.to_string();
    };
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    match rest[digits..].strip_prefix(": ") {
        Some(message) if digits > 0 => format!("{file}: {message}"),
        _ => warning.to_string(),
    }
}

/// Read and build the scene file at `path` with `overrides` applied (see
/// [`parse_scene_overridden`]); its files are read from the disk.
pub fn load_scene_overridden(path: &Path, overrides: &[Override]) -> Result<Scene, SceneError> {
    let text = crate::input::read_scene_file(path)?;
    parse_scene_overridden(&text, path, overrides, &Disk)
}
