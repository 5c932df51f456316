//! A small measurement harness shared by the benchmarks (`mod support;` in each).
//!
//! Criterion reports means and confidence intervals; the performance targets are stated
//! as medians and 95th percentiles of individual calls, so this helper times every call
//! on its own with [`Instant`]: a warm-up, then up to `GEOSNAP_BENCH_SAMPLES` samples
//! (default [`DEFAULT_SAMPLES`]) within `GEOSNAP_BENCH_SECONDS` per case (default
//! [`DEFAULT_SECONDS`]). Calls shorter than [`MIN_SAMPLE`] are batched so that each
//! timed sample lasts at least that long, and the sample is divided by the batch size.
//!
//! `cargo bench` passes `--bench` to the binary. Without it (`cargo test --benches`,
//! `cargo test --all-targets`) the benchmark runs in *smoke mode*: every case a few times,
//! to check that it still works, not to measure it. The first argument that is not a flag
//! filters the cases by name where the benchmark supports it (`cargo bench --bench solve
//! -- HS77`); a filter ending in `$` matches the end of the name only (`-- 'N=20$'`
//! leaves out N=200).

#![allow(dead_code, reason = "each benchmark uses a part of the helper")]

use std::env;
use std::fmt::Write as _;
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Samples per case unless `GEOSNAP_BENCH_SAMPLES` says otherwise.
pub(crate) const DEFAULT_SAMPLES: usize = 1000;
/// The time budget per case (warm-up included) unless `GEOSNAP_BENCH_SECONDS` says
/// otherwise; a case stops early when it has used it up (after at least
/// [`MIN_SAMPLES`] samples).
pub(crate) const DEFAULT_SECONDS: f64 = 0.4;
/// The fewest samples of a case, whatever the budget.
pub(crate) const MIN_SAMPLES: usize = 10;
/// Calls shorter than this are timed in batches.
pub(crate) const MIN_SAMPLE: Duration = Duration::from_micros(1);
/// Samples per case in smoke mode.
pub(crate) const SMOKE_SAMPLES: usize = 3;

/// How the cases of a benchmark binary are run.
#[derive(Clone, Debug)]
pub(crate) struct Bench {
    smoke: bool,
    samples: usize,
    budget: Duration,
    filter: Option<String>,
}

fn env_parse<T: std::str::FromStr>(name: &str) -> Option<T> {
    let text = env::var(name).ok()?;
    let value = text.trim().parse().ok();
    if value.is_none() {
        eprintln!("ignoring {name}={text:?}: not a number");
    }
    value
}

impl Bench {
    /// Reads the mode from the arguments and the sample count and time budget from the
    /// environment.
    pub(crate) fn from_env() -> Self {
        let args: Vec<String> = env::args().skip(1).collect();
        let smoke = !args.iter().any(|a| a == "--bench");
        let filter = args.iter().find(|a| !a.starts_with('-')).cloned();
        let samples = env_parse("GEOSNAP_BENCH_SAMPLES")
            .unwrap_or(DEFAULT_SAMPLES)
            .max(1);
        let seconds: f64 = env_parse("GEOSNAP_BENCH_SECONDS").unwrap_or(DEFAULT_SECONDS);
        let budget = Duration::try_from_secs_f64(seconds.max(0.0))
            .unwrap_or(Duration::from_secs_f64(DEFAULT_SECONDS));
        if smoke {
            Self {
                smoke,
                samples: SMOKE_SAMPLES,
                budget: Duration::ZERO,
                filter,
            }
        } else {
            Self {
                smoke,
                samples,
                budget,
                filter,
            }
        }
    }

    /// Whether this is a smoke run (no `--bench` argument).
    pub(crate) fn is_smoke(&self) -> bool {
        self.smoke
    }

    /// Whether the case `name` passes the name filter.
    pub(crate) fn wants(&self, name: &str) -> bool {
        self.filter
            .as_ref()
            .is_none_or(|f| match f.strip_suffix('$') {
                Some(end) => name.ends_with(end),
                None => name.contains(f.as_str()),
            })
    }

    /// Prints what the run measures and how.
    pub(crate) fn print_intro(&self, title: &str) {
        println!("{title}");
        if self.smoke {
            println!(
                "SMOKE MODE (no --bench argument): {SMOKE_SAMPLES} calls per case, figures \
                 are not measurements; run `cargo bench` for them."
            );
        } else {
            println!(
                "Up to {} samples per case within {:.1} s (GEOSNAP_BENCH_SAMPLES, \
                 GEOSNAP_BENCH_SECONDS), after a warm-up; times are per call. Calls under \
                 {} µs are timed in batches ('batch' column) and each sample divided by the \
                 batch size.",
                self.samples,
                self.budget.as_secs_f64(),
                MIN_SAMPLE.as_micros()
            );
        }
        println!(
            "{} build: median, p95 (95th percentile) and min of the samples.",
            if cfg!(debug_assertions) {
                "DEBUG (figures meaningless)"
            } else {
                "Optimised"
            }
        );
    }

    fn warm_up_time(&self) -> Duration {
        (self.budget / 10).min(Duration::from_millis(100))
    }

    /// Times `f`, batching calls shorter than [`MIN_SAMPLE`].
    pub(crate) fn batched<R>(&self, mut f: impl FnMut() -> R) -> Stats {
        self.interleaved(1, |_| f())
            .pop()
            .expect("one variant gives one result")
    }

    /// Times `variants` variants of a call, `f(0)`, `f(1)`, …, taking their samples in
    /// turn so that all of them see the same machine load (which keeps their ratios
    /// honest on a busy machine); each variant gets the budget of one case. Calls
    /// shorter than [`MIN_SAMPLE`] are batched.
    pub(crate) fn interleaved<R>(
        &self,
        variants: usize,
        mut f: impl FnMut(usize) -> R,
    ) -> Vec<Stats> {
        // Warm-up, which also gives the time of one call of each variant.
        let warm_up = self.warm_up_time() * variants as u32;
        let start = Instant::now();
        let mut rounds = 0u32;
        let mut fastest = vec![Duration::MAX; variants];
        loop {
            for (v, fastest) in fastest.iter_mut().enumerate() {
                let t = Instant::now();
                black_box(f(v));
                *fastest = (*fastest).min(t.elapsed());
            }
            rounds += 1;
            if rounds >= 3 && start.elapsed() >= warm_up {
                break;
            }
        }
        let batches: Vec<usize> = fastest
            .iter()
            .map(|one| {
                if self.smoke {
                    1
                } else {
                    MIN_SAMPLE.as_nanos().div_ceil(one.as_nanos().max(1)) as usize
                }
            })
            .collect();
        let mut samples = vec![Vec::with_capacity(self.samples); variants];
        let budget = self.budget * variants as u32;
        let start = Instant::now();
        let mut taken = 0;
        while taken < self.samples
            && (taken < MIN_SAMPLES.min(self.samples) || start.elapsed() < budget)
        {
            for (v, (samples, &batch)) in samples.iter_mut().zip(&batches).enumerate() {
                let t = Instant::now();
                for _ in 0..batch {
                    black_box(f(v));
                }
                samples.push(t.elapsed().as_nanos() as f64 / batch as f64);
            }
            taken += 1;
        }
        samples
            .into_iter()
            .zip(batches)
            .map(|(s, batch)| Stats::new(s, batch))
            .collect()
    }

    /// Calls `f` with the sample number (0, 1, 2, …; the warm-up uses the same numbers
    /// first) and records the duration it returns: `f` prepares its input untimed and
    /// times the call proper with [`timed`]. For calls that last well over
    /// [`MIN_SAMPLE`].
    pub(crate) fn each(&self, mut f: impl FnMut(usize) -> Duration) -> Stats {
        self.each_interleaved(1, |_, i| f(i))
            .pop()
            .expect("one variant gives one result")
    }

    /// Like [`Bench::each`] for `variants` variants, `f(0, i)`, `f(1, i)`, …, whose
    /// samples are taken in turn so that all of them see the same machine load; each
    /// variant gets the budget of one case, and all get the same number of samples.
    pub(crate) fn each_interleaved(
        &self,
        variants: usize,
        mut f: impl FnMut(usize, usize) -> Duration,
    ) -> Vec<Stats> {
        let warm_up = self.warm_up_time() * variants as u32;
        let start = Instant::now();
        let mut round = 0;
        while round < 2 || (!self.smoke && start.elapsed() < warm_up) {
            for v in 0..variants {
                black_box(f(v, round));
            }
            round += 1;
        }
        let mut samples = vec![Vec::with_capacity(self.samples); variants];
        let budget = self.budget * variants as u32;
        let start = Instant::now();
        let mut taken = 0;
        while taken < self.samples
            && (taken < MIN_SAMPLES.min(self.samples) || start.elapsed() < budget)
        {
            for (v, samples) in samples.iter_mut().enumerate() {
                samples.push(f(v, taken).as_nanos() as f64);
            }
            taken += 1;
        }
        samples.into_iter().map(|s| Stats::new(s, 1)).collect()
    }
}

/// Runs `f` once and returns its result and how long it took.
pub(crate) fn timed<R>(f: impl FnOnce() -> R) -> (R, Duration) {
    let t = Instant::now();
    let r = black_box(f());
    let elapsed = t.elapsed();
    (r, elapsed)
}

/// The distribution of the per-call times of one case, in nanoseconds.
#[derive(Clone, Debug)]
pub(crate) struct Stats {
    /// The median.
    pub(crate) median: f64,
    /// The 95th percentile (nearest rank).
    pub(crate) p95: f64,
    /// The fastest sample.
    pub(crate) min: f64,
    /// The number of samples.
    pub(crate) samples: usize,
    /// Calls per sample.
    pub(crate) batch: usize,
}

impl Stats {
    /// The statistics of samples timed elsewhere (in nanoseconds, one call each).
    pub(crate) fn of(samples: Vec<f64>) -> Self {
        Self::new(samples, 1)
    }

    fn new(mut samples: Vec<f64>, batch: usize) -> Self {
        assert!(!samples.is_empty(), "a case needs at least one sample");
        samples.sort_by(f64::total_cmp);
        let n = samples.len();
        let median = if n % 2 == 1 {
            samples[n / 2]
        } else {
            0.5 * (samples[n / 2 - 1] + samples[n / 2])
        };
        let rank = (0.95 * n as f64).ceil() as usize;
        Self {
            median,
            p95: samples[rank.clamp(1, n) - 1],
            min: samples[0],
            samples: n,
            batch,
        }
    }
}

/// A duration in nanoseconds with three significant digits and a unit.
pub(crate) fn fmt_ns(ns: f64) -> String {
    let (value, unit) = if ns < 1e3 {
        (ns, "ns")
    } else if ns < 1e6 {
        (ns / 1e3, "µs")
    } else if ns < 1e9 {
        (ns / 1e6, "ms")
    } else {
        (ns / 1e9, "s")
    };
    let decimals = match value {
        v if v < 10.0 => 2,
        v if v < 100.0 => 1,
        _ => 0,
    };
    format!("{value:.decimals$} {unit}")
}

/// A table of cases: a title, a header, then one aligned line per case with the name,
/// median, p95, min, samples, batch, and the table's extra columns.
#[derive(Clone, Debug)]
pub(crate) struct Table {
    name_width: usize,
    extras: Vec<(String, usize)>,
}

impl Table {
    /// Prints the title and header of a table whose case names take `name_width`
    /// characters and whose extra columns are `(header, width)`.
    pub(crate) fn new(title: &str, name_width: usize, extras: &[(&str, usize)]) -> Self {
        let table = Self {
            name_width,
            extras: extras
                .iter()
                .map(|&(h, w)| (h.to_owned(), w.max(h.chars().count())))
                .collect(),
        };
        println!();
        println!("{title}");
        let mut header = format!(
            "{:<w$} {:>10} {:>10} {:>10} {:>7} {:>5}",
            "case",
            "median",
            "p95",
            "min",
            "samples",
            "batch",
            w = name_width
        );
        for (h, w) in &table.extras {
            let _ = write!(header, "  {h:>w$}");
        }
        println!("{header}");
        println!("{}", "-".repeat(header.chars().count()));
        table
    }

    /// Prints one case.
    pub(crate) fn row(&self, name: &str, stats: &Stats, extras: &[String]) {
        assert_eq!(
            extras.len(),
            self.extras.len(),
            "one value per extra column"
        );
        let mut line = format!(
            "{:<w$} {:>10} {:>10} {:>10} {:>7} {:>5}",
            name,
            fmt_ns(stats.median),
            fmt_ns(stats.p95),
            fmt_ns(stats.min),
            stats.samples,
            stats.batch,
            w = self.name_width
        );
        for (value, (_, w)) in extras.iter().zip(&self.extras) {
            let _ = write!(line, "  {value:>w$}");
        }
        println!("{line}");
    }
}

/// A small deterministic generator (`SplitMix64`) for reproducible benchmark data.
#[derive(Clone, Debug)]
pub(crate) struct Rng(u64);

impl Rng {
    /// A generator with this seed.
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    /// Uniform in `0..n`.
    pub(crate) fn index(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// Standard normal (Box–Muller).
    pub(crate) fn normal(&mut self) -> f64 {
        let u = self.uniform(f64::MIN_POSITIVE, 1.0);
        let v = self.uniform(0.0, 1.0);
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}
