//! `--time-limit`: a budget for a whole command, enforced at safe points.
//!
//! A [`Deadline`] raises a [`CancelFlag`] from a watchdog thread when the budget is
//! spent. The global solves of the command carry that flag, so a long solve stops at
//! its next evaluation; the command itself checks [`Deadline::check`] between steps
//! (between files for `check`) and once more before writing, so nothing is written once
//! the budget is spent.

use std::fmt;
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::core::solve::CancelFlag;

/// The exit status of a command whose `--time-limit` was spent (nothing written).
pub const EXIT_TIME_LIMIT: u8 = 3;

/// The exit statuses, as `--help` shows them after each command's options.
pub const EXIT_HELP: &str = "Exit status: 0 on success; 1 on any error (the message names the \
file; nothing is written, except by `run --strict`, which fails after writing); 2 for a wrong \
command line; 3 when `--time-limit` is spent (nothing is written; see docs/formats.md §7).";

/// The longest `--time-limit` taken: a week, far beyond any real command, and small
/// enough for every clock.
const MAX_SECONDS: f64 = 7.0 * 24.0 * 3600.0;

/// Parses `--time-limit SECONDS`: a positive number of seconds, fractions allowed.
pub(super) fn parse_seconds(text: &str) -> Result<Duration, String> {
    let seconds: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number of seconds"))?;
    if !(seconds > 0.0 && seconds <= MAX_SECONDS) {
        return Err(format!(
            "the time limit must be more than 0 and at most {MAX_SECONDS} seconds (a week), \
             not {text}"
        ));
    }
    Ok(Duration::from_secs_f64(seconds))
}

/// A spent `--time-limit`: what was done and that nothing was written. Its message reads
/// "time limit of 5 s reached after 212 of 300 steps: nothing written".
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TimeLimitReached {
    /// The budget given.
    pub limit: Duration,
    /// What was done when it was spent ("after 212 of 300 steps").
    pub progress: String,
}

impl fmt::Display for TimeLimitReached {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "time limit of {} s reached {}: nothing written",
            seconds(self.limit),
            self.progress
        )
    }
}

impl std::error::Error for TimeLimitReached {}

/// Seconds in words: `5`, `0.5`, `1.25`.
fn seconds(duration: Duration) -> String {
    let text = format!("{:.6}", duration.as_secs_f64());
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// The budget of one command: none, or a time from now after which its flag is raised.
pub(super) struct Deadline {
    limit: Option<Duration>,
    start: Instant,
    flag: CancelFlag,
    /// Dropping the sender wakes the watchdog, which then ends without raising the flag.
    watchdog: Option<(mpsc::Sender<()>, JoinHandle<()>)>,
}

impl Deadline {
    /// A deadline `limit` from now (none without a limit).
    pub(super) fn new(limit: Option<Duration>) -> Self {
        let start = Instant::now();
        let flag = CancelFlag::new();
        let watchdog = limit.and_then(|limit| {
            let (stop, stopped) = mpsc::channel::<()>();
            let raise = flag.clone();
            std::thread::Builder::new()
                .name("geosnap-time-limit".to_owned())
                .spawn(move || {
                    if let Err(mpsc::RecvTimeoutError::Timeout) = stopped.recv_timeout(limit) {
                        raise.cancel();
                    }
                })
                .ok()
                .map(|handle| (stop, handle))
        });
        Self {
            limit,
            start,
            flag,
            watchdog,
        }
    }

    /// The flag the command's solves carry: raised when the budget is spent.
    pub(super) fn flag(&self) -> &CancelFlag {
        &self.flag
    }

    /// Whether the budget is spent.
    pub(super) fn expired(&self) -> bool {
        self.flag.is_cancelled()
            || self
                .limit
                .is_some_and(|limit| self.start.elapsed() >= limit)
    }

    /// Fails with [`TimeLimitReached`] when the budget is spent; `progress` says what was
    /// done ("after 3 of 10 files").
    pub(super) fn check(&self, progress: impl FnOnce() -> String) -> anyhow::Result<()> {
        match self.limit {
            Some(limit) if self.expired() => Err(TimeLimitReached {
                limit,
                progress: progress(),
            }
            .into()),
            _ => Ok(()),
        }
    }
}

impl Drop for Deadline {
    fn drop(&mut self) {
        if let Some((stop, handle)) = self.watchdog.take() {
            drop(stop);
            let _ = handle.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::{parse_seconds, seconds, Deadline, TimeLimitReached};

    #[test]
    fn seconds_are_positive_and_bounded() {
        assert_eq!(parse_seconds("5"), Ok(Duration::from_secs(5)));
        assert_eq!(parse_seconds("0.25"), Ok(Duration::from_millis(250)));
        for bad in ["0", "-1", "NaN", "inf", "1e300", "five", ""] {
            assert!(parse_seconds(bad).is_err(), "{bad} must be refused");
        }
        assert_eq!(seconds(Duration::from_secs(5)), "5");
        assert_eq!(seconds(Duration::from_millis(1250)), "1.25");
    }

    #[test]
    fn a_deadline_raises_its_flag_once_spent() {
        let none = Deadline::new(None);
        assert!(
            !none.expired() && none.check(String::new).is_ok(),
            "no limit"
        );
        let short = Deadline::new(Some(Duration::from_millis(20)));
        std::thread::sleep(Duration::from_millis(200));
        assert!(short.flag().is_cancelled(), "the watchdog raised the flag");
        let error = short
            .check(|| "after 2 of 3 steps".to_owned())
            .expect_err("spent");
        let reached = error.downcast_ref::<TimeLimitReached>().expect("typed");
        assert_eq!(
            reached.to_string(),
            "time limit of 0.02 s reached after 2 of 3 steps: nothing written"
        );
        // A long deadline dropped early ends its watchdog at once.
        let started = std::time::Instant::now();
        drop(Deadline::new(Some(Duration::from_mins(10))));
        assert!(
            started.elapsed() < Duration::from_secs(5),
            "no wait on drop"
        );
    }
}
