//! Reading a scene's TOML text: the `[[body]]` sections one at a time,
//! their long arrays in bulk, and a parse error placed at its line with
//! its key named.

use std::path::Path;

use super::bulk::BulkArrays;
use super::error::{key_before, line_of};
use super::tables::{BodySection, BodyTable};
use super::SceneError;
use toml::Spanned;

/// The body table of the `[[body]]` section `section` of `text`, its long
/// arrays read in bulk, its span in the whole text.
pub(super) fn body_section(
    text: &str,
    section: std::ops::Range<usize>,
    path: &Path,
) -> Result<Vec<Spanned<BodyTable>>, SceneError> {
    let part = &text[section.clone()];
    let (bulk, blanked) = BulkArrays::read(part);
    let chunk: BodySection = parse_toml(
        blanked.as_deref().unwrap_or(part),
        section.start,
        text,
        path,
    )?;
    // One `[[body]]` header per section: one table.
    let mut bulk = Some(bulk);
    Ok(chunk
        .body
        .into_iter()
        .map(|table| {
            let span = table.span();
            let mut body = table.into_inner();
            if let Some(bulk) = bulk.take() {
                bulk.fill(&mut body);
            }
            Spanned::new(section.start + span.start..section.start + span.end, body)
        })
        .collect())
}

/// Parse `part` of a scene's `text` (which starts at byte `offset` of it)
/// into `T`, its error placed at its line of the whole text.
pub(super) fn parse_toml<T: serde::de::DeserializeOwned>(
    part: &str,
    offset: usize,
    text: &str,
    path: &Path,
) -> Result<T, SceneError> {
    toml::from_str(part).map_err(|e| {
        let start = e.span().map(|s| offset + s.start);
        let line = start.map(|s| line_of(text, s));
        let message = e.message().trim();
        // A table header: `[[contact]]` for the one `[contact]` table, or
        // a table given twice.
        let header = start
            .and_then(|s| text.get(..s.min(text.len())))
            .map(|before| {
                let from = before.rfind('\n').map_or(0, |i| i + 1);
                let end = text[from..].find('\n').map_or(text.len(), |i| from + i);
                text[from..end].trim()
            })
            .filter(|line| line.starts_with('['));
        let name = header.map(|h| {
            h.trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
        });
        let (message, key) = match (header, name) {
            (Some(h), Some(name)) if h.starts_with("[[") && message.starts_with("invalid type") => {
                (
                    format!(
                    "`[[{name}]]`: `{name}` is one table, written `[{name}]`, not a list of them"
                ),
                    Some(name),
                )
            }
            (Some(_), Some(name)) if message.starts_with("duplicate key") => (
                format!("`[{name}]` is given twice: write its keys in one table"),
                Some(name),
            ),
            _ if message.starts_with("duplicate key") => {
                let key = start.and_then(|s| key_at(text, s));
                let message = key.map_or(message.to_string(), |key| {
                    format!("`{key}` is given twice in its table")
                });
                (message, key)
            }
            // The key is the one the message names as unknown or missing,
            // else the one the value belongs to.
            _ => match start.and_then(|s| key_before(text, s)) {
                Some(key) if !message.contains(&format!("`{key}`")) => (
                    format!("`{key}`: {message}"),
                    field_named(message).or(Some(key)),
                ),
                key => (message.to_string(), field_named(message).or(key)),
            },
        };
        let error = SceneError::new(path, line, message);
        match key {
            Some(key) => error.with_key(key),
            None => error,
        }
    })
}

/// The field a serde message names: `timestep` in "unknown field
/// `timestep`, expected one of ...", `dt` in "missing field `dt`".
fn field_named(message: &str) -> Option<&str> {
    let rest = ["unknown field `", "missing field `"]
        .iter()
        .find_map(|start| message.strip_prefix(start))?;
    rest.split('`').next().filter(|key| !key.is_empty())
}

/// The key assigned on the line of byte `offset` of `text` (`dt` in
/// `dt = 1e-3`), if the line is an assignment.
fn key_at(text: &str, offset: usize) -> Option<&str> {
    let from = text
        .get(..offset.min(text.len()))?
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let line = &text[from..];
    let key = line[..line.find('=')?].trim();
    (!key.is_empty() && !key.contains('\n')).then_some(key)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::sections::Sections;
    use crate::scene::tables::SceneFile;

    /// The file read whole by the TOML parser, bodies and all.
    fn whole(text: &str) -> Option<String> {
        toml::from_str::<SceneFile>(text)
            .ok()
            .map(|f| format!("{f:?}"))
    }

    /// The file read as `parse_scene` reads it: the rest, then each body
    /// section with its long arrays in bulk.
    fn sectioned(text: &str) -> Option<String> {
        let sections = Sections::find(text);
        let mut file: SceneFile = toml::from_str(&sections.without_bodies(text)).ok()?;
        let path = Path::new("t.toml");
        for section in &sections.bodies {
            file.body
                .get_or_insert_with(Vec::new)
                .extend(body_section(text, section.clone(), path).ok()?);
        }
        Some(format!("{file:?}"))
    }

    /// A tiny deterministic generator for the damage.
    fn next(state: &mut u64) -> usize {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 16) as usize
    }

    /// Reading a scene a body at a time means what reading it whole means:
    /// the same tables with the same spans, or an error in both, for every
    /// demo scene, tricky forms of headers and arrays, and thousands of
    /// damaged variants of them.
    #[test]
    fn sections_read_what_the_whole_file_says() {
        let tricky = [
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nparticles = [[0, 0, 0], [1.5, 0, 0], # é\n [0, 1e0, -0.0]]\nsprings = [[0, 1], [1, 2],]\nfaces = [[0, 1, 2]]\nmasses = [1, 2.5, 3]\npinned = [0]\n[body.gas]\nnrt = 1.0\n[[body]]\nname = \"b\"\nrope = { particles = 3, length = 1.0 }\n",
            "[[ body ]]\nname = \"a\"\nparticles = [[0, 0, 0]]\n[sim]\ndt = 1e-3\n[body.gas]\nnrt = 1.0\n",
            "[[\"body\"]]\nname = \"a\"\nparticles = [[0, 0, 0]]\nparticles = [[1, 0, 0]]\n[sim]\ndt = 1e-3\n",
            "[sim]\ndt = 1e-3\nbody = [{ name = \"a\", particles = [[0, 0, 0]] }]\n[[body]]\nname = \"b\"\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nparticles = [[0x10, 1_0, 0]]\nsprings = [[0, +1]]\nrods = [[0, 1, 2]]\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nparticles = [\n  [0, 0, 0],\n  [1, 0, 0]\n] # end\nvelocities = [[1, 2, 3], [4, 5, 6]] mass = 1\n",
            "[body]\nname = \"a\"\n[[body]]\nname = \"b\"\n[sim]\ndt = 1\n",
            "[sim]\ndt = 1e-3\nbody = []\n[[body]]\nname = \"b\"\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nparticles = [[0, 0, 0],\r[1, 0, 0]]\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nmasses = [1, # \u{7f}\n 2]\nparticles = [[0, 0, 0], [1, 0, 0]]\n",
            "[sim]\ndt = 1e-3\n[[\"bod\\u0079\"]]\nname = \"a\"\n[[body]]\nname = \"b\"\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nnote = '''\n[[body]]\nname = \"fake\"\n'''\n",
        ];
        let mut texts: Vec<String> = tricky.iter().map(|t| t.to_string()).collect();
        texts.extend(crate::demos::DEMOS.iter().map(|d| d.text.to_string()));
        let mut agreed_ok = 0;
        for text in &texts {
            assert_eq!(whole(text), sectioned(text), "{text}");
            agreed_ok += usize::from(whole(text).is_some());
            let mut state = 0x9e37_79b9_7f4a_7c15_u64 ^ text.len() as u64;
            for _ in 0..500 {
                let mut damaged = text.clone().into_bytes();
                for _ in 0..=next(&mut state) % 3 {
                    let at = next(&mut state) % damaged.len().max(1);
                    let pieces: &[&[u8]] = &[
                        b"[",
                        b"]",
                        b"[[body]]\n",
                        b"[body.gas]\n",
                        b",",
                        b"\n",
                        b"#",
                        b"\"",
                        b"=",
                        b"0",
                        b"-",
                        b".",
                        b"e",
                        b"{",
                        b"}",
                        b" ",
                    ];
                    match next(&mut state) % 3 {
                        0 if at < damaged.len() => {
                            damaged.remove(at);
                        }
                        _ => {
                            let piece = pieces[next(&mut state) % pieces.len()];
                            damaged.splice(at..at, piece.iter().copied());
                        }
                    }
                }
                let Ok(damaged) = String::from_utf8(damaged) else {
                    continue;
                };
                assert_eq!(whole(&damaged), sectioned(&damaged), "{damaged}");
                agreed_ok += usize::from(whole(&damaged).is_some());
            }
        }
        // Many damaged files still parse: the comparison saw real tables.
        assert!(agreed_ok > texts.len(), "{agreed_ok}");
    }
}
