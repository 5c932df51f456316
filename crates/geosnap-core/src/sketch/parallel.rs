//! A parallel map over the strokes of a sketch, for the passes that treat each stroke on
//! its own (the shape tests of classification, with their ellipse fits).
//!
//! The work is shared among at most [`std::thread::available_parallelism`] scoped
//! threads, which take blocks of items in turn, so that a few costly strokes do not hold
//! up one thread. The result is in item order and does not depend on the number of
//! threads. Without threads (one core, or a platform that cannot start them), the map
//! runs on the calling thread.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::thread;

/// Items taken at once by a thread.
const BLOCK: usize = 16;

/// `items.iter().map(f).collect()`, on several threads when there is enough work.
pub(crate) fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = thread::available_parallelism()
        .map_or(1, std::num::NonZero::get)
        .min(items.len().div_ceil(BLOCK));
    if threads <= 1 {
        return items.iter().map(f).collect();
    }
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done: Vec<(usize, Vec<R>)> = Vec::new();
        loop {
            let start = next.fetch_add(BLOCK, Ordering::Relaxed);
            let Some(block) = items.get(start..items.len().min(start + BLOCK)) else {
                break;
            };
            if block.is_empty() {
                break;
            }
            done.push((start, block.iter().map(&f).collect()));
        }
        done
    };
    let mut blocks: Vec<(usize, Vec<R>)> = thread::scope(|scope| {
        let helpers: Vec<_> = (1..threads)
            .filter_map(|i| {
                thread::Builder::new()
                    .name(format!("geosnap-strokes-{i}"))
                    .spawn_scoped(scope, work)
                    .ok()
            })
            .collect();
        // The calling thread works too; a helper that could not start leaves its share
        // to the others.
        let mut blocks = work();
        for helper in helpers {
            match helper.join() {
                Ok(done) => blocks.extend(done),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        blocks
    });
    blocks.sort_unstable_by_key(|&(start, _)| start);
    blocks.into_iter().flat_map(|(_, b)| b).collect()
}

#[cfg(test)]
mod tests {
    use super::map;

    #[test]
    fn keeps_the_order_of_the_items() {
        for n in [0, 1, 15, 16, 17, 1000] {
            let items: Vec<u64> = (0..n).collect();
            let squares = map(&items, |&x| x * x);
            assert_eq!(squares, items.iter().map(|x| x * x).collect::<Vec<_>>());
        }
    }
}
