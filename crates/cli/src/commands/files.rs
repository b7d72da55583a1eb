//! Output files written whole or not at all: each is written to a temporary file beside it
//! (same directory, so the final rename cannot cross file systems) and renamed over the target
//! only once complete. An interrupted run leaves the target as it was — absent, or the previous
//! complete file — never a partial one; the temporary file is removed when the write fails or
//! is abandoned (a process killed outright can leave it behind, hidden and named
//! `.<name>.partial-<pid>`).

use crate::error::CliError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written: [`Pending::writer`] takes the contents, [`Pending::commit`] puts it in
/// place; dropped without a commit, it removes its temporary file.
pub struct Pending {
    target: PathBuf,
    temporary: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl Pending {
    /// Start writing `target`.
    ///
    /// # Errors
    /// [`CliError::Io`] naming `target` when the temporary file cannot be created beside it.
    pub fn create(target: &Path) -> Result<Pending, CliError> {
        let name = target.file_name().map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
        let temporary = target.with_file_name(format!(".{name}.partial-{}", std::process::id()));
        let file = File::create(&temporary).map_err(|source| CliError::Io { path: target.to_path_buf(), source })?;
        Ok(Pending { target: target.to_path_buf(), temporary, writer: Some(BufWriter::new(file)) })
    }

    /// Where the contents go.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("a pending file has its writer until it is committed")
    }

    /// The error of a failed write, naming the target.
    pub fn error(&self, source: std::io::Error) -> CliError {
        CliError::Io { path: self.target.clone(), source }
    }

    /// Flush the contents to disk and rename the temporary file over the target.
    ///
    /// # Errors
    /// [`CliError::Io`] naming the target (the temporary file is then removed).
    pub fn commit(mut self) -> Result<(), CliError> {
        let writer = self.writer.take().expect("committed once");
        let file = writer.into_inner().map_err(|e| self.error(e.into_error()))?;
        file.sync_all().map_err(|e| self.error(e))?;
        drop(file);
        std::fs::rename(&self.temporary, &self.target).map_err(|e| self.error(e))
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        // Not committed (or the rename failed): the partial contents go.
        if self.writer.take().is_some() || self.temporary.exists() {
            let _ = std::fs::remove_file(&self.temporary);
        }
    }
}

/// Write `contents` to `path` whole or not at all.
///
/// # Errors
/// [`CliError::Io`] naming `path`.
pub fn write(path: &Path, contents: &[u8]) -> Result<(), CliError> {
    let mut file = Pending::create(path)?;
    file.writer().write_all(contents).map_err(|e| file.error(e))?;
    file.commit()
}
