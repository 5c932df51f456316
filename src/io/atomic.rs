//! Atomic file replacement: a save either fully happens or leaves the old file as it was.
//!
//! [`write_atomic`] writes the new content to a temporary file in the target's directory
//! (so the final rename never crosses file systems), flushes it to disk, and renames it
//! over the target. A reader therefore sees either the old file or the complete new one,
//! never a truncated mix, even if geosnap crashes or the disk fills up mid-write.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// How many temporary names to try before giving up (they only collide with leftovers).
const NAME_ATTEMPTS: u32 = 64;

/// Distinguishes temporary files of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Replaces the file at `path` with `bytes`, atomically.
///
/// The bytes go to a hidden temporary file next to `path` (`.{name}.{pid}.{n}.tmp`),
/// which is flushed with `fsync`, given the permissions of the file it replaces (if
/// any), and renamed over `path`; on Unix the directory is then synced too (best effort)
/// so the rename itself survives a power loss. If anything fails before the rename, the
/// temporary file is removed and the old file is untouched.
///
/// If `path` is a symbolic link, the link itself is replaced by a regular file.
///
/// # Errors
///
/// Any I/O error from creating, writing, syncing or renaming the temporary file, for
/// example [`io::ErrorKind::NotFound`] if the directory does not exist. A `path` without
/// a file name (such as `/` or `..`) gives [`io::ErrorKind::InvalidInput`].
///
/// # Examples
///
/// ```
/// let path = std::env::temp_dir().join(format!("geosnap-doc-{}.txt", std::process::id()));
/// geosnap::io::write_atomic(&path, b"first")?;
/// geosnap::io::write_atomic(&path, b"second")?;
/// assert_eq!(std::fs::read(&path)?, b"second");
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), std::io::Error>(())
/// ```
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> io::Result<()> {
    let path = path.as_ref();
    let Some(name) = path.file_name() else {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("not a file path: {}", path.display()),
        ));
    };
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };

    let (temp_path, mut temp) = create_temp(dir, &name.to_string_lossy())?;
    let written = (|| {
        if let Ok(metadata) = fs::metadata(path) {
            // Best effort: a file we cannot chmod is still better saved than not.
            let _ = temp.set_permissions(metadata.permissions());
        }
        temp.write_all(bytes)?;
        temp.sync_all()?;
        drop(temp);
        fs::rename(&temp_path, path)
    })();
    if let Err(error) = written {
        let _ = fs::remove_file(&temp_path);
        return Err(error);
    }
    sync_dir(dir);
    Ok(())
}

/// Creates a new, empty temporary file in `dir` with a name no other file has.
fn create_temp(dir: &Path, name: &str) -> io::Result<(PathBuf, File)> {
    let pid = std::process::id();
    let mut last_error = None;
    for _ in 0..NAME_ATTEMPTS {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let temp_path = dir.join(format!(".{name}.{pid}.{n}.tmp"));
        match OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp_path)
        {
            Ok(file) => return Ok((temp_path, file)),
            Err(error) if error.kind() == io::ErrorKind::AlreadyExists => {
                last_error = Some(error);
            }
            Err(error) => return Err(error),
        }
    }
    Err(last_error.unwrap_or_else(|| io::Error::other("no free temporary file name")))
}

/// Flushes the directory entry of the rename to disk where the platform supports it.
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(handle) = File::open(dir) {
        // Best effort: some file systems refuse to sync directories, and the new content
        // is already in place.
        let _ = handle.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

#[cfg(test)]
mod tests {
    use std::fs;
    use std::io;
    use std::path::{Path, PathBuf};

    use super::write_atomic;

    /// A fresh, empty directory under the system temporary directory, removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir =
                std::env::temp_dir().join(format!("geosnap-atomic-{name}-{}", std::process::id()));
            let _ = fs::remove_dir_all(&dir);
            fs::create_dir_all(&dir).unwrap();
            Self(dir)
        }

        fn entries(&self) -> Vec<String> {
            let mut names: Vec<String> = fs::read_dir(&self.0)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            names.sort();
            names
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    #[test]
    fn creates_a_new_file_and_leaves_no_temporary_file() {
        let dir = TempDir::new("create");
        let path = dir.0.join("sketch.json");
        write_atomic(&path, b"hello").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"hello");
        assert_eq!(dir.entries(), vec!["sketch.json".to_owned()]);
    }

    #[test]
    fn replaces_an_existing_file() {
        let dir = TempDir::new("replace");
        let path = dir.0.join("sketch.json");
        fs::write(&path, b"a much longer old content").unwrap();
        write_atomic(&path, b"new").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"new");
        write_atomic(&path, b"").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"");
        assert_eq!(dir.entries(), vec!["sketch.json".to_owned()]);
    }

    #[test]
    fn a_failed_rename_leaves_the_target_untouched() {
        // The target is a non-empty directory: the temporary file is written, but
        // the rename over the target fails.
        let dir = TempDir::new("fail");
        let target = dir.0.join("occupied");
        fs::create_dir(&target).unwrap();
        fs::write(target.join("keep.txt"), b"precious").unwrap();
        assert!(write_atomic(&target, b"new").is_err());
        assert!(target.is_dir(), "the directory is still there");
        assert_eq!(fs::read(target.join("keep.txt")).unwrap(), b"precious");
        assert_eq!(
            dir.entries(),
            vec!["occupied".to_owned()],
            "the temporary file is removed"
        );
    }

    #[test]
    fn a_missing_directory_is_an_error() {
        let dir = TempDir::new("missing");
        let path = dir.0.join("no/such/dir/sketch.json");
        let error = write_atomic(&path, b"x").unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::NotFound);
        assert!(dir.entries().is_empty());
    }

    #[test]
    fn a_path_without_file_name_is_invalid_input() {
        for path in [Path::new("/"), Path::new("..")] {
            let error = write_atomic(path, b"x").unwrap_err();
            assert_eq!(error.kind(), io::ErrorKind::InvalidInput, "{path:?}");
        }
    }

    #[test]
    fn a_relative_path_in_the_current_directory_works() {
        // `Path::parent` of a bare file name is empty; the temporary file must still
        // land next to the target. Use an absolute directory but a relative-looking
        // name through `join` to avoid changing the process's current directory.
        let dir = TempDir::new("relative");
        let path = dir.0.join("./plain.json");
        write_atomic(&path, b"{}").unwrap();
        assert_eq!(fs::read(dir.0.join("plain.json")).unwrap(), b"{}");
    }

    #[cfg(unix)]
    #[test]
    fn keeps_the_permissions_of_the_replaced_file() {
        use std::os::unix::fs::PermissionsExt;

        let dir = TempDir::new("perms");
        let path = dir.0.join("script.sh");
        fs::write(&path, b"old").unwrap();
        fs::set_permissions(&path, fs::Permissions::from_mode(0o751)).unwrap();
        write_atomic(&path, b"new").unwrap();
        let mode = fs::metadata(&path).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o751);
    }

    #[test]
    fn concurrent_writers_never_leave_a_partial_file() {
        let dir = TempDir::new("concurrent");
        let path = dir.0.join("shared.bin");
        let contents: Vec<Vec<u8>> = (0..8u8).map(|i| vec![i; 64 * 1024]).collect();
        std::thread::scope(|scope| {
            for content in &contents {
                let path = &path;
                std::thread::Builder::new()
                    .name("atomic-writer".into())
                    .spawn_scoped(scope, move || write_atomic(path, content).unwrap())
                    .unwrap();
            }
        });
        let result = fs::read(&path).unwrap();
        assert!(contents.contains(&result), "the file is one complete write");
        assert_eq!(dir.entries(), vec!["shared.bin".to_owned()]);
    }
}
