//! Atomic file replacement: a save either fully happens or leaves the old file as it was.
//!
//! [`write_atomic`] writes the new content to a temporary file in the target's directory
//! (so the final rename never crosses file systems), flushes it to disk, and renames it
//! over the target. A reader therefore sees either the old file or the complete new one,
//! never a truncated mix, even if geosnap crashes or the disk fills up mid-write.
//!
//! [`write_all_atomic`] does the same for the several outputs of one command: all of them
//! are replaced, or (on an error) none. [`check_target`] tells, before any work, whether a
//! file could be written at a path.
//!
//! Temporary files are named `.{name}.{pid}.{n}.tmp` beside their target. Each write
//! removes those in its directory whose process is gone (killed mid-write, say): on Linux
//! a process is gone when `/proc/{pid}` is missing; on other systems they are left alone.

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
/// temporary file is removed and the old file is untouched. Stale temporary files of
/// killed writes in the same directory are removed first (see the module docs).
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
    let staged = Staged::new(path.as_ref(), bytes)?;
    if let Err(error) = fs::rename(&staged.temp, &staged.target) {
        staged.discard();
        return Err(error);
    }
    sync_dir(&staged.dir);
    Ok(())
}

/// Why [`write_all_atomic`] wrote nothing: the file concerned and the error.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {}", path.display())]
pub struct WriteAllError {
    /// The file that could not be written.
    pub path: PathBuf,
    /// The operating system's error.
    #[source]
    pub source: io::Error,
}

/// Replaces several files together: all of them, or none.
///
/// Every file is first written to its temporary file and synced (as [`write_atomic`]
/// does), and each existing target is kept under a temporary name; only then are the
/// new files renamed over their targets. If a rename fails, the targets already replaced
/// get their old content back (or are removed if they did not exist), so an error leaves
/// every target as it was. A crash in the middle of the renames can leave some targets
/// replaced; the kept copies are then stale temporary files, removed by a later write.
///
/// # Errors
///
/// A [`WriteAllError`] naming the first file that could not be written.
pub fn write_all_atomic(files: &[(&Path, &[u8])]) -> Result<(), WriteAllError> {
    let fail = |path: &Path| {
        let path = path.to_owned();
        move |source| WriteAllError { path, source }
    };
    let mut staged: Vec<Staged> = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        match Staged::new(path, bytes) {
            Ok(s) => staged.push(s),
            Err(error) => {
                staged.into_iter().for_each(Staged::discard);
                return Err(fail(path)(error));
            }
        }
    }
    // Keep the old files, so a failed rename can be undone.
    let mut kept: Vec<Option<PathBuf>> = Vec::with_capacity(staged.len());
    for s in &staged {
        match keep_old(s) {
            Ok(k) => kept.push(k),
            Err(error) => {
                kept.iter().flatten().for_each(|k| drop(fs::remove_file(k)));
                let path = s.target.clone();
                staged.into_iter().for_each(Staged::discard);
                return Err(fail(&path)(error));
            }
        }
    }
    for (done, s) in staged.iter().enumerate() {
        if let Err(error) = fs::rename(&s.temp, &s.target) {
            // Undo the renames already made, newest first, then drop the rest.
            for (undone, k) in staged.iter().zip(&kept).take(done).rev() {
                match k {
                    Some(old) => drop(fs::rename(old, &undone.target)),
                    None => drop(fs::remove_file(&undone.target)),
                }
            }
            for (rest, k) in staged.iter().zip(&kept).skip(done) {
                let _ = fs::remove_file(&rest.temp);
                if let Some(old) = k {
                    let _ = fs::remove_file(old);
                }
            }
            return Err(fail(&s.target)(error));
        }
    }
    for (s, k) in staged.iter().zip(&kept) {
        if let Some(old) = k {
            let _ = fs::remove_file(old);
        }
        sync_dir(&s.dir);
    }
    Ok(())
}

/// Checks, without changing anything visible, that a file could be written at `path`:
/// it names a file (not a directory), and its directory exists and lets us create files
/// (tried with a temporary file, removed at once).
///
/// # Errors
///
/// [`io::ErrorKind::NotFound`] with a message if the directory does not exist,
/// [`io::ErrorKind::InvalidInput`] if `path` is a directory or has no file name, and the
/// error of creating a file in the directory otherwise (permission denied, say).
pub fn check_target(path: &Path) -> io::Result<()> {
    let (dir, name) = split(path)?;
    match fs::metadata(&dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(io::Error::new(
                io::ErrorKind::NotFound,
                format!("{} is not a directory", dir.display()),
            ))
        }
        Err(error) if error.kind() == io::ErrorKind::NotFound => {
            return Err(io::Error::new(
                io::ErrorKind::NotFound,
                format!("the directory {} does not exist", dir.display()),
            ))
        }
        Err(error) => return Err(error),
    }
    if fs::metadata(path).is_ok_and(|m| m.is_dir()) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} is a directory", path.display()),
        ));
    }
    let (temp, file) = create_temp(&dir, &name)?;
    drop(file);
    fs::remove_file(temp)
}

/// A new file's content written to its temporary file, synced, not yet renamed.
struct Staged {
    target: PathBuf,
    dir: PathBuf,
    temp: PathBuf,
}

impl Staged {
    fn new(path: &Path, bytes: &[u8]) -> io::Result<Self> {
        let (dir, name) = split(path)?;
        let (temp, mut file) = create_temp(&dir, &name)?;
        let written = (|| {
            if let Ok(metadata) = fs::metadata(path) {
                // Best effort: a file we cannot chmod is still better saved than not.
                let _ = file.set_permissions(metadata.permissions());
            }
            file.write_all(bytes)?;
            file.sync_all()
        })();
        drop(file);
        let staged = Self {
            target: path.to_owned(),
            dir,
            temp,
        };
        match written {
            Ok(()) => Ok(staged),
            Err(error) => {
                staged.discard();
                Err(error)
            }
        }
    }

    /// Removes the temporary file.
    fn discard(self) {
        let _ = fs::remove_file(&self.temp);
    }
}

/// Keeps the current file at a staged target under a temporary name (a hard link, or a
/// copy where links are not possible); `None` if there is no file there.
fn keep_old(staged: &Staged) -> io::Result<Option<PathBuf>> {
    match fs::symlink_metadata(&staged.target) {
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(error) => return Err(error),
        Ok(_) => {}
    }
    let name = staged
        .target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let (kept, file) = create_temp(&staged.dir, &name)?;
    drop(file);
    fs::remove_file(&kept)?;
    if fs::hard_link(&staged.target, &kept).is_err() {
        fs::copy(&staged.target, &kept)?;
    }
    Ok(Some(kept))
}

/// The directory and file name of `path` (the directory `.` for a bare name).
fn split(path: &Path) -> io::Result<(PathBuf, String)> {
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
    Ok((dir.to_owned(), name.to_string_lossy().into_owned()))
}

/// Creates a new, empty temporary file in `dir` with a name no other file has, after
/// removing the stale ones there.
fn create_temp(dir: &Path, name: &str) -> io::Result<(PathBuf, File)> {
    remove_stale_temps(dir);
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

/// The process id in a temporary file name of ours, `.{name}.{pid}.{n}.tmp`.
fn temp_pid(file_name: &str) -> Option<u32> {
    let rest = file_name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (rest, n) = rest.rsplit_once('.')?;
    let (name, pid) = rest.rsplit_once('.')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if name.is_empty() || !digits(n) || !digits(pid) {
        return None;
    }
    pid.parse().ok()
}

/// Whether process `pid` is running: `Some` where the system can tell.
#[cfg(target_os = "linux")]
fn process_alive(pid: u32) -> Option<bool> {
    let proc = Path::new("/proc");
    // Without a mounted /proc nothing can be told.
    if !proc.join("self").exists() {
        return None;
    }
    Some(proc.join(pid.to_string()).exists())
}

/// Whether process `pid` is running: `Some` where the system can tell.
#[cfg(not(target_os = "linux"))]
fn process_alive(_pid: u32) -> Option<bool> {
    None
}

/// Removes the temporary files of ours in `dir` whose process is gone (best effort).
fn remove_stale_temps(dir: &Path) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let own = std::process::id();
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = temp_pid(&name.to_string_lossy()) else {
            continue;
        };
        if pid == own || process_alive(pid) != Some(false) {
            continue;
        }
        if entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = fs::remove_file(entry.path());
        }
    }
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

    use super::{check_target, temp_pid, write_all_atomic, write_atomic};

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

    #[test]
    fn temporary_names_are_recognised() {
        assert_eq!(temp_pid(".model.json.4242.7.tmp"), Some(4242));
        assert_eq!(temp_pid(".a.b.c.1.0.tmp"), Some(1));
        for other in [
            ".model.json.tmp",
            "model.json.1.2.tmp",
            "..1.2.tmp",
            ".x.1.a.tmp",
            ".x.1.2",
        ] {
            assert_eq!(temp_pid(other), None, "{other}");
        }
    }

    /// Issue 19, case 6: a write removes the temporary files of killed writes beside it,
    /// and keeps those of running processes.
    #[cfg(target_os = "linux")]
    #[test]
    fn stale_temporary_files_of_dead_processes_are_removed() {
        let dir = TempDir::new("stale");
        // No process has a pid past the kernel's maximum (2^22); pid 1 always runs.
        let dead = dir.0.join(".model.json.999999999.3.tmp");
        let live = dir.0.join(".model.json.1.0.tmp");
        let foreign = dir.0.join(".notes.txt.tmp");
        for path in [&dead, &live, &foreign] {
            fs::write(path, b"half a write").unwrap();
        }
        write_atomic(dir.0.join("other.json"), b"{}").unwrap();
        assert!(
            !dead.exists(),
            "the dead process's temporary file is removed"
        );
        assert!(live.exists(), "a running process's temporary file is kept");
        assert!(foreign.exists(), "files not of our naming are kept");
    }

    /// Issue 19, case 5: the outputs of one command are written together or not at all.
    #[test]
    fn several_files_are_written_all_or_none() {
        let dir = TempDir::new("all");
        let (a, b) = (dir.0.join("a.json"), dir.0.join("b.png"));
        fs::write(&a, b"old a").unwrap();
        write_all_atomic(&[(&a, b"new a"), (&b, b"new b")]).unwrap();
        assert_eq!(fs::read(&a).unwrap(), b"new a");
        assert_eq!(fs::read(&b).unwrap(), b"new b");
        assert_eq!(dir.entries(), vec!["a.json".to_owned(), "b.png".to_owned()]);

        // The second target cannot be replaced (a non-empty directory): the first keeps
        // its old content.
        let occupied = dir.0.join("c.glb");
        fs::create_dir(&occupied).unwrap();
        fs::write(occupied.join("keep"), b"x").unwrap();
        let error = write_all_atomic(&[(&a, b"newer a"), (&occupied, b"c")]).unwrap_err();
        assert_eq!(error.path, occupied);
        assert_eq!(fs::read(&a).unwrap(), b"new a", "rolled back");
        assert_eq!(
            dir.entries(),
            vec!["a.json".to_owned(), "b.png".to_owned(), "c.glb".to_owned()],
            "no temporary file left"
        );

        // A missing directory fails before anything is renamed.
        let nowhere = dir.0.join("no/such/x.png");
        let new_file = dir.0.join("d.json");
        assert!(write_all_atomic(&[(&new_file, b"d"), (&nowhere, b"x")]).is_err());
        assert!(!new_file.exists());
    }

    #[test]
    fn targets_are_checked_without_a_trace() {
        let dir = TempDir::new("check");
        check_target(&dir.0.join("fine.json")).unwrap();
        let missing = check_target(&dir.0.join("nodir/x.png")).unwrap_err();
        assert!(missing.to_string().contains("does not exist"), "{missing}");
        let error = check_target(&dir.0).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
        assert!(dir.entries().is_empty());
    }
}
