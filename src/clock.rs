//! The real clock for solves, outside the core (which only sees the
//! [`Clock`] trait).

use std::time::{Duration, Instant};

use crate::core::solve::Clock;

/// Monotonic time since [`MonotonicClock::start`].
///
/// # Examples
///
/// ```
/// use geosnap::clock::MonotonicClock;
/// use geosnap::core::solve::Clock;
///
/// let clock = MonotonicClock::start();
/// assert!(clock.elapsed() < std::time::Duration::from_secs(60));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct MonotonicClock(Instant);

impl MonotonicClock {
    /// A clock that starts now.
    pub fn start() -> Self {
        Self(Instant::now())
    }
}

impl Clock for MonotonicClock {
    fn elapsed(&self) -> Duration {
        self.0.elapsed()
    }
}
