//! Files that appear complete or not at all, and that only ever replace a
//! regular file.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written under a temporary name (`NAME.partial` in the same
/// folder) and renamed to its final name by [`AtomicFile::commit`]. Dropped
/// without a commit, it removes the temporary file.
///
/// Only a regular file is ever replaced: where `NAME` (or `NAME.partial`)
/// is a symbolic link, a device, a FIFO or a folder, [`AtomicFile::create`]
/// refuses (the rename would put a new file in the node's place: onto
/// `/dev/null` run as root, the system's `/dev/null`).
#[derive(Debug)]
pub struct AtomicFile {
    writer: Option<BufWriter<File>>,
    temporary: PathBuf,
    path: PathBuf,
}

impl AtomicFile {
    /// Start writing `path`; refused where `path` or its temporary name
    /// is something other than a regular file ([`replaceable`]).
    pub fn create(path: &Path) -> io::Result<Self> {
        let temporary = partial_path(path);
        replaceable(path)?;
        replaceable(&temporary)?;
        let file = File::create(&temporary)?;
        Ok(AtomicFile {
            writer: Some(BufWriter::new(file)),
            temporary,
            path: path.to_path_buf(),
        })
    }

    /// Write `bytes` to `path` in one go, atomically.
    pub fn write(path: &Path, bytes: &[u8]) -> io::Result<()> {
        let mut file = AtomicFile::create(path)?;
        file.write_all(bytes)?;
        file.commit()
    }

    /// Flush and rename the file into place. The rename is atomic, so a
    /// reader (or a run that was killed) never sees a partial file; the data
    /// is not forced to disk (no fsync: thousands of frames would crawl).
    pub fn commit(mut self) -> io::Result<()> {
        if let Some(mut writer) = self.writer.take() {
            writer.flush()?;
        }
        fs::rename(&self.temporary, &self.path)
    }

    /// Write `bytes` through to the file (past this file's buffer, to the
    /// system): when it returns `Ok`, they are in the file, whatever fails
    /// later.
    pub fn write_through(&mut self, bytes: &[u8]) -> io::Result<()> {
        let writer = self.writer()?;
        writer.write_all(bytes)?;
        writer.flush()
    }

    /// Rename the file into place with only its first `len` bytes (those
    /// known to be written, [`AtomicFile::write_through`]): what a failed
    /// write left after them is cut off, and nothing buffered is written.
    pub fn commit_truncated(mut self, len: u64) -> io::Result<()> {
        if let Some(writer) = self.writer.take() {
            let (file, _unwritten) = writer.into_parts();
            file.set_len(len)?;
        }
        fs::rename(&self.temporary, &self.path)
    }

    fn writer(&mut self) -> io::Result<&mut BufWriter<File>> {
        self.writer
            .as_mut()
            .ok_or_else(|| io::Error::other("the file was already committed"))
    }
}

/// The temporary name `path` is written under until it is committed:
/// `NAME.partial` beside it.
pub fn partial_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    path.with_file_name(name)
}

/// Whether a new file may be put at `path`: nothing is there, or a
/// regular file (not followed through a link). Refused, with an error of
/// kind [`io::ErrorKind::InvalidInput`] whose message starts "not a
/// regular file", where a symbolic link, a device, a FIFO, a socket or a
/// folder is there.
pub fn replaceable(path: &Path) -> io::Result<()> {
    let kind = match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e),
        Ok(metadata) => metadata.file_type(),
    };
    let what = if kind.is_file() {
        return Ok(());
    } else if kind.is_symlink() {
        "a symbolic link"
    } else if kind.is_dir() {
        "a folder"
    } else {
        node_kind(&kind)
    };
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "not a regular file: {} is {what}, which an output never replaces (give the path of a regular file, or of none)",
            path.display()
        ),
    ))
}

/// "a device", "a FIFO", "a socket": what a node that is neither a file,
/// a folder nor a link is.
fn node_kind(kind: &fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_socket() {
            return "a socket";
        }
        if kind.is_block_device() || kind.is_char_device() {
            return "a device";
        }
    }
    let _ = kind;
    "not a regular file"
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.writer()?.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.writer()?.flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = fs::remove_file(&self.temporary);
        }
    }
}
