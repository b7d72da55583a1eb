//! Output files that never destroy what is at their path.
//!
//! - A regular file (or a path where nothing is yet) is written whole or not at all: to a
//!   temporary file beside it (same directory, so the final rename cannot cross file systems),
//!   renamed over the target only once complete. An interrupted run leaves the target as it was
//!   — absent, or the previous complete file — never a partial one; the temporary file is
//!   removed when the write fails or is abandoned (a process killed outright can leave it
//!   behind, hidden and named `.<name>.partial-<pid>`).
//! - A symbolic link is followed: the file it points to is written as above, and the link stays
//!   a link.
//! - Anything else — a named pipe, a device such as `/dev/stdout` or `/dev/full` — is opened
//!   and written directly, never replaced: a write it refuses (a full device) is an error.
//! - A directory is an error.

use crate::error::CliError;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// How deep a chain of symbolic links is followed (Linux's own limit is 40).
const MAX_LINKS: usize = 40;

/// A file being written: [`Pending::writer`] takes the contents, [`Pending::commit`] puts it in
/// place; dropped without a commit, it removes its temporary file.
pub struct Pending {
    /// The path as given, for messages.
    target: PathBuf,
    /// Where the links lead: the file that is written.
    resolved: PathBuf,
    /// The temporary file beside `resolved`; `None` when writing directly.
    temporary: Option<PathBuf>,
    writer: Option<BufWriter<File>>,
}

/// `path` with every symbolic link along its last component followed: the path of the file a
/// write through `path` reaches (which need not exist yet).
fn follow_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let next = std::fs::read_link(&current)?;
                current = match current.parent() {
                    Some(dir) if next.is_relative() => dir.join(next),
                    _ => next,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(std::io::Error::other(format!("more than {MAX_LINKS} symbolic links in a row")))
}

impl Pending {
    /// Start writing `target`.
    ///
    /// # Errors
    /// [`CliError::Io`] naming `target` when it is a directory, when its links cannot be
    /// followed, or when the file (or the temporary file beside it) cannot be opened.
    pub fn create(target: &Path) -> Result<Pending, CliError> {
        let io = |source| CliError::Io { path: target.to_path_buf(), source };
        let resolved = follow_links(target).map_err(io)?;
        let existing = std::fs::metadata(&resolved).ok();
        if existing.as_ref().is_some_and(std::fs::Metadata::is_dir) {
            return Err(io(std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a directory")));
        }
        if existing.as_ref().is_some_and(|m| !m.is_file()) {
            // A pipe, a device, a socket: written in place, never replaced.
            let file = OpenOptions::new().write(true).open(&resolved).map_err(io)?;
            return Ok(Pending {
                target: target.to_path_buf(),
                resolved,
                temporary: None,
                writer: Some(BufWriter::new(file)),
            });
        }
        let name = resolved.file_name().map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
        let temporary = resolved.with_file_name(format!(".{name}.partial-{}", std::process::id()));
        let file = File::create(&temporary).map_err(io)?;
        Ok(Pending {
            target: target.to_path_buf(),
            resolved,
            temporary: Some(temporary),
            writer: Some(BufWriter::new(file)),
        })
    }

    /// Where the contents go.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("a pending file has its writer until it is committed")
    }

    /// The error of a failed write, naming the target.
    pub fn error(&self, source: std::io::Error) -> CliError {
        CliError::Io { path: self.target.clone(), source }
    }

    /// Flush the contents and put them in place: a regular file is synced to disk and renamed
    /// over the target; a pipe or a device has had them written through.
    ///
    /// # Errors
    /// [`CliError::Io`] naming the target (a temporary file is then removed).
    pub fn commit(mut self) -> Result<(), CliError> {
        let writer = self.writer.take().expect("committed once");
        let file = writer.into_inner().map_err(|e| self.error(e.into_error()))?;
        let Some(temporary) = &self.temporary else {
            return Ok(());
        };
        file.sync_all().map_err(|e| self.error(e))?;
        drop(file);
        std::fs::rename(temporary, &self.resolved).map_err(|e| self.error(e))
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        // Not committed (or the rename failed): the partial contents go.
        if let Some(temporary) = &self.temporary
            && (self.writer.take().is_some() || temporary.exists())
        {
            let _ = std::fs::remove_file(temporary);
        }
    }
}

/// Write `contents` to `path` as [`Pending`] does.
///
/// # Errors
/// [`CliError::Io`] naming `path`.
pub fn write(path: &Path, contents: &[u8]) -> Result<(), CliError> {
    let mut file = Pending::create(path)?;
    file.writer().write_all(contents).map_err(|e| file.error(e))?;
    file.commit()
}
