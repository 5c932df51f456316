//! The autosave: unsaved work is written to a file in the app's data folder on a timer
//! of its own (a thread), whether or not the window draws frames; it is removed when
//! the work is saved, discarded or closed cleanly, so finding it at start means the
//! last run did not end well, and the recovery prompt names the work and its time.
//!
//! The UI hands each new revision of unsaved work to the thread ([`Autosave::hand`]);
//! the thread writes the newest one once [`AUTOSAVE_EVERY`] has passed since the first
//! change it has not written. A small file beside it names the file the work came from.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime};

use anyhow::Context as _;

use crate::io::session::{session_bytes, Session};

/// How long unsaved work waits before it is written to the autosave file.
pub(crate) const AUTOSAVE_EVERY: Duration = Duration::from_secs(30);

/// The autosave's file name in the data folder.
const FILE: &str = "autosave.geosnap.json";
/// The file beside it that names the work's file.
const ABOUT: &str = "autosave.about.txt";

/// Unsaved work waiting for its turn.
struct Pending {
    session: Session,
    work: Option<PathBuf>,
    due: Instant,
}

#[derive(Default)]
struct Shared {
    pending: Option<Pending>,
    quit: bool,
    /// Bumped by every removal: a write taken before it is not done.
    epoch: u64,
}

/// What the thread and the UI share: the state with its signal, and the lock held
/// while the files are written or removed.
#[derive(Default)]
struct Channel {
    state: Mutex<Shared>,
    ready: Condvar,
    files: Mutex<()>,
}

/// The autosave file and the thread that writes it.
pub(crate) struct Autosave {
    path: Option<PathBuf>,
    every: Duration,
    /// The editor revision last handed to the thread (or written).
    handed: Option<u64>,
    shared: Arc<Channel>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for Autosave {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Autosave")
            .field("path", &self.path)
            .field("every", &self.every)
            .field("handed", &self.handed)
            .finish_non_exhaustive()
    }
}

/// An autosave left by a run that did not end well.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Recovery {
    /// The autosave file.
    pub(crate) path: PathBuf,
    /// The file the work came from, if it had one.
    pub(crate) work: Option<PathBuf>,
    /// When it was written.
    pub(crate) written: SystemTime,
}

impl Recovery {
    /// What the recovery prompt says: "Unsaved work on vase.svg from today 14:32
    /// (3 min ago)".
    pub(crate) fn describe(&self, now: SystemTime, zone: &jiff::tz::TimeZone) -> String {
        let name = self.work.as_deref().and_then(Path::file_name).map_or_else(
            || "an untitled drawing".to_owned(),
            |n| n.to_string_lossy().into_owned(),
        );
        format!(
            "Unsaved work on {name} from {}",
            when(self.written, now, zone)
        )
    }
}

/// A time in words for a designer: "today 14:32 (3 min ago)", "yesterday 09:05 (20 h
/// ago)", "2026-11-02 17:40 (22 days ago)", in the time zone `zone`.
pub(crate) fn when(time: SystemTime, now: SystemTime, zone: &jiff::tz::TimeZone) -> String {
    let ago = now.duration_since(time).unwrap_or_default().as_secs();
    let ago = match ago {
        0..60 => "just now".to_owned(),
        60..3600 => format!("{} min ago", ago / 60),
        3600..86_400 => format!("{} h ago", ago / 3600),
        _ => {
            let days = ago / 86_400;
            format!("{days} day{} ago", if days == 1 { "" } else { "s" })
        }
    };
    let local = |t: SystemTime| {
        jiff::Timestamp::try_from(t)
            .ok()
            .map(|t| t.to_zoned(zone.clone()))
    };
    let (Some(then), Some(today)) = (local(time), local(now)) else {
        return ago;
    };
    let day = if then.date() == today.date() {
        "today".to_owned()
    } else if today.date().yesterday().ok() == Some(then.date()) {
        "yesterday".to_owned()
    } else {
        then.date().to_string()
    };
    format!("{day} {} ({ago})", then.strftime("%H:%M"))
}

impl Autosave {
    /// The autosave in `dir` (the platform's data folder for geosnap when `None`),
    /// writing unsaved work `every` so often.
    pub(crate) fn new(dir: Option<PathBuf>, every: Duration) -> Self {
        let dir = dir.or_else(|| eframe::storage_dir("geosnap"));
        let path = dir.map(|d| d.join(FILE));
        let shared: Arc<Channel> = Arc::default();
        let thread = path.clone().and_then(|path| {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name("geosnap-autosave".into())
                .spawn(move || writer(&shared, &path))
                .ok()
        });
        Self {
            path,
            every,
            handed: None,
            shared,
            thread,
        }
    }

    /// Sets how long unsaved work waits before it is written.
    pub(crate) fn set_delay(&mut self, every: Duration) {
        self.every = every;
    }

    /// An autosave left by a run that did not exit cleanly: its file, the work's file
    /// and when it was written.
    pub(crate) fn pending(&self) -> Option<Recovery> {
        let path = self.path.clone().filter(|p| p.is_file())?;
        let written = std::fs::metadata(&path)
            .and_then(|m| m.modified())
            .unwrap_or_else(|_| SystemTime::now());
        let work = std::fs::read_to_string(about(&path))
            .ok()
            .map(|text| text.trim_end_matches('\n').to_owned())
            .filter(|text| !text.is_empty())
            .map(PathBuf::from);
        Some(Recovery {
            path,
            work,
            written,
        })
    }

    /// Looks at the work after a frame; whether a revision with unsaved changes is
    /// waiting to be handed over ([`Self::hand`]). When nothing is unsaved any more
    /// (saved, or undone back to the saved state) the autosave of this run is removed.
    pub(crate) fn wants(&mut self, revision: u64, dirty: bool) -> bool {
        if !dirty {
            if self.handed.is_some() {
                self.clear();
            }
            return false;
        }
        self.handed != Some(revision) && self.thread.is_some()
    }

    /// Hands `work` (at `revision`) to the thread: it is written once
    /// [`AUTOSAVE_EVERY`] (or the delay given) has passed since the first change not
    /// yet written.
    pub(crate) fn hand(&mut self, revision: u64, work: Work) {
        self.handed = Some(revision);
        let Work { session, origin } = work;
        let mut shared = lock(&self.shared.state);
        let due = shared
            .pending
            .as_ref()
            .map_or_else(|| Instant::now() + self.every, |p| p.due);
        shared.pending = Some(Pending {
            session,
            work: origin,
            due,
        });
        self.shared.ready.notify_one();
    }

    /// Writes `work` (at `revision`) now, on this thread.
    ///
    /// # Errors
    ///
    /// When there is no data folder, or the file cannot be written.
    pub(crate) fn write_now(&mut self, revision: u64, work: &Work) -> anyhow::Result<()> {
        let path = self
            .path
            .clone()
            .context("there is no data folder to autosave to")?;
        let _files = lock(&self.shared.files);
        lock(&self.shared.state).pending = None;
        write(
            &path,
            &session_bytes(&work.session)?,
            work.origin.as_deref(),
        )?;
        self.handed = Some(revision);
        Ok(())
    }

    /// A clean exit: removes this run's autosave, but not one left by an earlier run
    /// that the user has not recovered or discarded yet (it is offered again).
    pub(crate) fn exit(&mut self) {
        if self.handed.is_some() {
            self.clear();
        }
    }

    /// Removes the autosave and drops the work waiting to be written (the work was
    /// saved or discarded).
    pub(crate) fn clear(&mut self) {
        {
            let mut shared = lock(&self.shared.state);
            shared.pending = None;
            shared.epoch += 1;
        }
        // A write in progress ends first; one taken before the removal is not done.
        let _files = lock(&self.shared.files);
        if let Some(path) = &self.path {
            let _ = std::fs::remove_file(path);
            let _ = std::fs::remove_file(about(path));
        }
        self.handed = None;
    }
}

impl Drop for Autosave {
    fn drop(&mut self) {
        lock(&self.shared.state).quit = true;
        self.shared.ready.notify_one();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The work to autosave: the session and the file it came from.
pub(crate) struct Work {
    /// The strokes, image and model.
    pub(crate) session: Session,
    /// The file the work was opened from or saved to.
    pub(crate) origin: Option<PathBuf>,
}

fn about(path: &Path) -> PathBuf {
    path.with_file_name(ABOUT)
}

fn write(path: &Path, bytes: &[u8], work: Option<&Path>) -> anyhow::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let name = work.map(|w| w.display().to_string()).unwrap_or_default();
    crate::io::write_atomic(about(path), name.as_bytes())?;
    crate::io::write_atomic(path, bytes)?;
    Ok(())
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The thread: waits for work, then for its time, and writes it without holding the
/// state (the UI keeps handing work over meanwhile); a removal since it took the work
/// cancels the write.
fn writer(channel: &Channel, path: &Path) {
    let mut guard = lock(&channel.state);
    loop {
        if guard.quit {
            return;
        }
        let now = Instant::now();
        let wait = guard
            .pending
            .as_ref()
            .map(|p| p.due.saturating_duration_since(now));
        match wait {
            Some(Duration::ZERO) => {
                let epoch = guard.epoch;
                let Some(pending) = guard.pending.take() else {
                    continue;
                };
                drop(guard);
                let bytes = session_bytes(&pending.session);
                let files = lock(&channel.files);
                if lock(&channel.state).epoch == epoch {
                    let written = bytes
                        .map_err(anyhow::Error::from)
                        .and_then(|bytes| write(path, &bytes, pending.work.as_deref()));
                    if let Err(error) = written {
                        log::warn!("autosave to {} failed: {error:#}", path.display());
                    }
                }
                drop(files);
                guard = lock(&channel.state);
            }
            Some(wait) => {
                guard = channel
                    .ready
                    .wait_timeout(guard, wait)
                    .unwrap_or_else(PoisonError::into_inner)
                    .0;
            }
            None => {
                guard = channel
                    .ready
                    .wait(guard)
                    .unwrap_or_else(PoisonError::into_inner);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::time::{Duration, SystemTime};

    use jiff::tz::TimeZone;

    use super::{when, Autosave, Recovery, Work};
    use crate::io::session::Session;

    #[test]
    fn times_read_as_a_designer_says_them() {
        // 2026-11-24 14:32:00 UTC.
        let then = SystemTime::UNIX_EPOCH + Duration::from_mins(29_925_512);
        let utc = TimeZone::UTC;
        let later = |s: u64| then + Duration::from_secs(s);
        assert_eq!(when(then, later(20), &utc), "today 14:32 (just now)");
        assert_eq!(when(then, later(180), &utc), "today 14:32 (3 min ago)");
        assert_eq!(
            when(then, later(12 * 3600), &utc),
            "yesterday 14:32 (12 h ago)"
        );
        assert_eq!(
            when(then, later(3 * 86_400), &utc),
            "2026-11-24 14:32 (3 days ago)"
        );
        let recovery = Recovery {
            path: "autosave.geosnap.json".into(),
            work: Some("/drawings/vase.svg".into()),
            written: then,
        };
        assert_eq!(
            recovery.describe(later(180), &utc),
            "Unsaved work on vase.svg from today 14:32 (3 min ago)"
        );
    }

    #[test]
    fn the_thread_writes_after_its_delay_and_clear_removes_the_file() {
        let dir = std::env::temp_dir().join(format!("geosnap-autosave-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut autosave = Autosave::new(Some(dir.clone()), Duration::from_millis(100));
        let work = || Work {
            session: Session::default(),
            origin: Some("/drawings/vase.svg".into()),
        };
        assert!(autosave.wants(1, true), "new unsaved work is wanted");
        autosave.hand(1, work());
        assert!(!autosave.wants(1, true), "once");
        assert!(autosave.pending().is_none(), "not before its time");
        let start = std::time::Instant::now();
        while autosave.pending().is_none() {
            assert!(start.elapsed() < Duration::from_secs(20), "never written");
            std::thread::sleep(Duration::from_millis(20));
        }
        let pending = autosave.pending().expect("written");
        assert_eq!(pending.work, Some("/drawings/vase.svg".into()));
        assert!(!autosave.wants(2, false));
        assert!(
            autosave.pending().is_none(),
            "removed once nothing is unsaved"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
