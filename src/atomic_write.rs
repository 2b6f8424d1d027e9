//! Atomic file writes, the one home of the rule every writer of the project follows (FLM
//! films, PNG/TGA/EXR images, the master's checkpoints): the content goes to a temporary
//! file beside the target, is flushed and synced, and is then renamed over the target. A
//! reader sees the old file or the new one, never a half-written one; on any error the
//! temporary file is removed and the target is left as it was.
//!
//! This module imports nothing else of the crate, so every layer (film, image encoding,
//! outputs, the master) can use it without an import running back. Callers keep their own
//! error types: [`write_atomic`] returns the caller's error, built from a [`FileError`] for
//! the failures of the file itself.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// An I/O failure on a named file (the temporary file or the target).
#[derive(Debug, thiserror::Error)]
#[error("I/O error on {path}: {source}")]
pub struct FileError {
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

impl FileError {
    fn at(path: &Path) -> impl FnOnce(std::io::Error) -> FileError + '_ {
        move |source| FileError {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Writes `path` atomically: `write` fills a buffered temporary file beside it, which is then
/// synced and renamed over `path`. The caller's error type carries both its own failures and
/// the file's ([`FileError`]).
pub fn write_atomic<E: From<FileError>>(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
) -> Result<(), E> {
    let tmp = temp_path(path);
    let result = (|| {
        let f = File::create(&tmp).map_err(FileError::at(&tmp))?;
        let mut w = BufWriter::with_capacity(1 << 16, f);
        write(&mut w)?;
        let f = w
            .into_inner()
            .map_err(|e| FileError::at(&tmp)(e.into_error()))?;
        f.sync_all().map_err(FileError::at(&tmp))?;
        std::fs::rename(&tmp, path).map_err(FileError::at(path))?;
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes bytes held in memory to `path` atomically.
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    write_atomic(path, |w| w.write_all(bytes).map_err(FileError::at(path)))
}

/// The temporary name beside `path`: its file name, the process id and `.tmp` (two
/// processes writing the same target never share a temporary file).
fn temp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".{}.tmp", std::process::id()));
    path.with_file_name(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug)]
    enum TestError {
        File,
        Writer,
    }

    impl From<FileError> for TestError {
        fn from(_: FileError) -> TestError {
            TestError::File
        }
    }

    #[test]
    fn writes_replaces_and_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.bin");
        write_bytes_atomic(&p, b"first").unwrap();
        write_bytes_atomic(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "{names:?}");
    }

    #[test]
    fn a_failing_writer_keeps_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.bin");
        write_bytes_atomic(&p, b"old").unwrap();
        let r = write_atomic(&p, |w| {
            w.write_all(b"partial").map_err(|_| TestError::Writer)?;
            Err(TestError::Writer)
        });
        assert!(matches!(r, Err(TestError::Writer)));
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_missing_directory_is_a_file_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no/such/dir/a.bin");
        let e = write_bytes_atomic(&p, b"x").unwrap_err();
        assert!(e.to_string().contains("a.bin"), "{e}");
        let r: Result<(), TestError> = write_atomic(&p, |_| Ok(()));
        assert!(matches!(r, Err(TestError::File)));
    }
}
