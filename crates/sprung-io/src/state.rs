//! State files: a [`WorldState`] on disk, to stop a run and resume it
//! (`sprung run --save-state`, `--checkpoint-every`, `--resume`).
//!
//! The layout, all numbers little-endian:
//!
//! | bytes | what |
//! |---|---|
//! | 13 | the magic `SPRUNG STATE\n` |
//! | 4 | format version ([`STATE_VERSION`]) |
//! | 4 | fingerprint of the world's structure ([`fingerprint`]) |
//! | 2 + n | the integrator's name: its length, then UTF-8 |
//! | 4 | the number of entries |
//! | per entry | name (2-byte length, UTF-8), value count (8 bytes), values (f64) |
//! | 4 | CRC-32 of everything before it |
//!
//! Numbers are stored as their bits, so a resumed run goes on with exactly
//! the values the saved run had.

use std::io;
use std::path::{Path, PathBuf};

use sprung::{Real, World, WorldState};
use thiserror::Error;

use crate::export::AtomicFile;
use crate::input;

/// The first bytes of every state file.
const MAGIC: &[u8] = b"SPRUNG STATE\n";

/// The state file format this version writes and reads.
pub const STATE_VERSION: u32 = 1;

/// Why a state file cannot be used.
#[derive(Debug, Error)]
pub enum StateFileError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: io::Error,
    },
    /// The file does not start as a state file does.
    #[error("{path}: not a sprung state file")]
    NotAState {
        /// The file.
        path: PathBuf,
    },
    /// The file was written by another version of the format.
    #[error("{path}: state file format {found}, this sprung reads format {STATE_VERSION}")]
    Version {
        /// The file.
        path: PathBuf,
        /// The version in the file.
        found: u32,
    },
    /// The file is cut short or its checksum does not match: it was damaged.
    #[error("{path}: the state file is damaged ({what})")]
    Damaged {
        /// The file.
        path: PathBuf,
        /// What does not hold.
        what: &'static str,
    },
    /// The state belongs to a world of another structure.
    #[error("{path}: the state was saved from another scene (its particles, springs or bodies differ from this one's)")]
    Foreign {
        /// The file.
        path: PathBuf,
    },
    /// The state's entries do not fit this world.
    #[error("{path}: {source}")]
    Mismatch {
        /// The file.
        path: PathBuf,
        /// What does not fit.
        source: sprung::StateError,
    },
}

/// A checksum of what a state depends on and the scene builds: particle
/// masses and pins, springs (endpoints, stiffness, damping, rest lengths
/// other than the muscles'; for springs that may yield or break, their
/// break strain instead), and the bodies' names and particle ranges.
pub fn fingerprint(world: &World) -> u32 {
    let mut hash = crc32fast::Hasher::new();
    let particles = &world.particles;
    hash.update(&(particles.len() as u64).to_le_bytes());
    for (&m, &w) in particles.mass.iter().zip(&particles.inverse_mass) {
        hash.update(&m.to_le_bytes());
        hash.update(&[u8::from(w == 0.0)]);
    }
    let springs = &world.springs;
    let mut muscle = vec![false; springs.len()];
    world
        .muscles
        .list
        .iter()
        .for_each(|m| muscle[m.spring] = true);
    for (s, &muscle) in muscle.iter().enumerate() {
        let [a, b] = springs.endpoints(s);
        hash.update(&a.to_le_bytes());
        hash.update(&b.to_le_bytes());
        if world.limits.can_give(s) {
            // Its stiffness and damping (0 once broken) and its rest
            // length (moved by yielding) change as it runs: its break
            // strain and sidedness are the scene's.
            hash.update(&world.limits.break_strain(s).to_le_bytes());
            hash.update(&[u8::from(springs.one_sided[s])]);
            continue;
        }
        hash.update(&springs.stiffness[s].to_le_bytes());
        hash.update(&springs.damping[s].to_le_bytes());
        hash.update(&[u8::from(springs.one_sided[s])]);
        if !muscle {
            hash.update(&springs.rest_length[s].to_le_bytes());
        }
    }
    for body in &world.bodies {
        hash.update(body.name.as_bytes());
        hash.update(&(body.particles.start as u64).to_le_bytes());
        hash.update(&(body.particles.end as u64).to_le_bytes());
    }
    hash.finalize()
}

/// Write `state`, saved from `world`, to `path`, atomically: the file is
/// complete or not there (an older one stays until the new one is whole).
///
/// Stop a run, and go on with it later exactly as if it had not stopped:
///
/// ```
/// use sprung::{build, IntegratorKind, World};
/// use sprung_io::state::{read_state, restore, write_state, StateFileError};
///
/// let path = std::env::temp_dir().join(format!("sprung-doc-state-{}.state", std::process::id()));
/// let world = || {
///     let mut world = World::new(IntegratorKind::Verlet);
///     world.add_body("rope", build::rope(5, 1.0).unwrap().with_stiffness(200.0)).unwrap();
///     world
/// };
/// let mut first = world();
/// for _ in 0..100 {
///     first.step(1e-3).unwrap();
/// }
/// write_state(&path, &first, &first.save_state()).unwrap();
///
/// // Later: the same scene built afresh, the state put back.
/// let mut second = world();
/// let state = read_state(&path, &second).unwrap();
/// restore(&path, &mut second, &state).unwrap();
/// assert_eq!((second.steps(), second.time()), (first.steps(), first.time()));
/// for _ in 0..100 {
///     first.step(1e-3).unwrap();
///     second.step(1e-3).unwrap();
/// }
/// assert_eq!(first.particles.position, second.particles.position); // bit for bit
///
/// // A state is refused for a world of another structure.
/// let mut other = World::new(IntegratorKind::Verlet);
/// other.add_body("rope", build::rope(6, 1.0).unwrap()).unwrap();
/// let error = read_state(&path, &other).unwrap_err();
/// assert!(matches!(error, StateFileError::Foreign { .. }), "{error}");
/// std::fs::remove_file(&path).unwrap();
/// ```
pub fn write_state(path: &Path, world: &World, state: &WorldState) -> Result<(), StateFileError> {
    let mut bytes = Vec::new();
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&STATE_VERSION.to_le_bytes());
    bytes.extend_from_slice(&fingerprint(world).to_le_bytes());
    put_name(&mut bytes, &state.integrator);
    bytes.extend_from_slice(&(state.entries.len() as u32).to_le_bytes());
    for (name, values) in &state.entries {
        put_name(&mut bytes, name);
        bytes.extend_from_slice(&(values.len() as u64).to_le_bytes());
        for v in values {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    let checksum = crc32fast::hash(&bytes);
    bytes.extend_from_slice(&checksum.to_le_bytes());
    AtomicFile::write(path, &bytes).map_err(|source| StateFileError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Read the state file at `path` for `world` (built from the scene the
/// state was saved from): refused when it is not a state file, of another
/// format version, damaged, or from a world of another structure.
pub fn read_state(path: &Path, world: &World) -> Result<WorldState, StateFileError> {
    let bytes = input::read_input(path, input::DEFAULT_MAX_INPUT_BYTES).map_err(|source| {
        StateFileError::Io {
            path: path.to_path_buf(),
            source,
        }
    })?;
    decode_state(&bytes, world, path)
}

/// [`read_state`] of a state file's `bytes`; `path` names it in errors.
pub fn decode_state(
    bytes: &[u8],
    world: &World,
    path: &Path,
) -> Result<WorldState, StateFileError> {
    let damaged = |what| StateFileError::Damaged {
        path: path.to_path_buf(),
        what,
    };
    if !bytes.starts_with(MAGIC) {
        return Err(StateFileError::NotAState {
            path: path.to_path_buf(),
        });
    }
    let mut reader = Reader {
        bytes: &bytes[..bytes.len().saturating_sub(4)],
        at: MAGIC.len(),
    };
    let version = reader.u32().ok_or_else(|| damaged("cut short"))?;
    if version != STATE_VERSION {
        return Err(StateFileError::Version {
            path: path.to_path_buf(),
            found: version,
        });
    }
    let (body, checksum) = bytes.split_at(bytes.len() - 4);
    if crc32fast::hash(body).to_le_bytes() != checksum {
        return Err(damaged("its checksum does not match"));
    }
    if reader.u32() != Some(fingerprint(world)) {
        return Err(StateFileError::Foreign {
            path: path.to_path_buf(),
        });
    }
    let mut state = WorldState {
        integrator: reader.name().ok_or_else(|| damaged("a bad name"))?,
        entries: Vec::new(),
    };
    let count = reader.u32().ok_or_else(|| damaged("cut short"))?;
    for _ in 0..count {
        let name = reader.name().ok_or_else(|| damaged("a bad name"))?;
        let values = reader.values().ok_or_else(|| damaged("cut short"))?;
        state.entries.push((name, values));
    }
    if reader.at != reader.bytes.len() {
        return Err(damaged("bytes after its last entry"));
    }
    Ok(state)
}

/// Check that `state` fits `world` and put it back: see
/// [`World::restore_state`].
pub fn restore(path: &Path, world: &mut World, state: &WorldState) -> Result<(), StateFileError> {
    world
        .restore_state(state)
        .map_err(|source| StateFileError::Mismatch {
            path: path.to_path_buf(),
            source,
        })
}

fn put_name(bytes: &mut Vec<u8>, name: &str) {
    let name = &name.as_bytes()[..name.len().min(u16::MAX as usize)];
    bytes.extend_from_slice(&(name.len() as u16).to_le_bytes());
    bytes.extend_from_slice(name);
}

/// Reads the fields of a state file, `None` where the bytes run out.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, count: usize) -> Option<&[u8]> {
        let end = self.at.checked_add(count)?;
        let slice = self.bytes.get(self.at..end)?;
        self.at = end;
        Some(slice)
    }

    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }

    fn name(&mut self) -> Option<String> {
        let length = u16::from_le_bytes(self.take(2)?.try_into().ok()?);
        String::from_utf8(self.take(usize::from(length))?.to_vec()).ok()
    }

    fn values(&mut self) -> Option<Vec<Real>> {
        let count = u64::from_le_bytes(self.take(8)?.try_into().ok()?);
        // Checked against the bytes left before anything is allocated.
        let bytes = self.take(usize::try_from(count).ok()?.checked_mul(8)?)?;
        Some(
            bytes
                .chunks_exact(8)
                .map(|c| Real::from_le_bytes(c.try_into().unwrap_or_default()))
                .collect(),
        )
    }
}
