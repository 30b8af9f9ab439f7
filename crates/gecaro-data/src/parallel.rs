//! Work split over the cores: the independent per-configuration kinematics
//! and the row blocks of the tall observation matrix. Every split is by
//! contiguous parts whose results are combined in part order, so results
//! do not depend on the number of cores, nor on which thread ran which part.
//!
//! The parts are taken in turn by whichever thread is free (this one
//! included, from the start), not dealt out in advance: a thread the
//! system starts late or runs slowly then takes fewer parts instead of
//! holding the others up. Callers cut about [`PARTS_PER_THREAD`] parts per
//! thread for that.
//!
//! The helpers are the process's worker threads (a `rayon-core` pool of
//! gecaro's own, one thread fewer than the cores, since the caller takes
//! parts too; started by the first split), not threads started for each
//! split. A thread
//! started for a split is placed by the system's fork balancing, which
//! often put it on the caller's own core, and on a virtual machine whose
//! idle core sleeps it began 0.6 ms late: at 5,000 configurations, where a
//! split lasts about a millisecond, two helpers in three came after the
//! caller had taken most parts. A worker woken for a split is placed on an
//! idle core and came within 30 µs in five splits of six
//! (docs/performance.md, "Workers kept"). One split at a time holds the
//! workers; a split that finds them held (a server's concurrent requests,
//! a split within a part) runs on threads started for it, as does every
//! split of a process forked after its workers started (Python's
//! `multiprocessing`): the child has none.

use std::sync::Mutex;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// About how many parts per thread a caller cuts its work into, so that
/// the threads finish together however unevenly they run.
pub const PARTS_PER_THREAD: usize = 8;

/// The cores this process may use, asked once: the standard library reads
/// the cgroup quota files on every call, which costs more than evaluating
/// a hundred configurations.
pub fn available_threads() -> usize {
    static THREADS: OnceLock<usize> = OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get))
}

/// The process's workers, started at the first call, and the process they
/// were started in (`None`: one core, or no thread could be started).
fn started() -> Option<&'static (rayon_core::ThreadPool, u32)> {
    static STARTED: OnceLock<Option<(rayon_core::ThreadPool, u32)>> = OnceLock::new();
    STARTED
        .get_or_init(|| {
            let helpers = available_threads().checked_sub(1).filter(|&n| n > 0)?;
            let pool = rayon_core::ThreadPoolBuilder::new()
                .num_threads(helpers)
                .thread_name(|index| format!("gecaro-worker-{index}"))
                .build()
                .ok()?;
            // Running: a new thread is often placed on its starter's core,
            // where it would start only when this thread first waits (at a
            // split's end, the split then without its help); waited for
            // here, 0.3 ms, it starts at once and is woken on the idle core
            // from then on.
            pool.install(|| ());
            Some((pool, std::process::id()))
        })
        .as_ref()
}

/// The workers, when this process started them (a forked child has none).
fn workers() -> Option<&'static rayon_core::ThreadPool> {
    started()
        .filter(|(_, process)| *process == std::process::id())
        .map(|(pool, _)| pool)
}

/// The workers held by one split at a time: a split that finds them held
/// (by another thread's, or by the split whose part it runs in) starts
/// threads of its own rather than wait for them.
struct Workers(&'static rayon_core::ThreadPool);

static WORKERS_HELD: AtomicBool = AtomicBool::new(false);

impl Workers {
    /// The workers, when started in this process and free; free again when
    /// dropped (a panic included).
    fn claim() -> Option<Self> {
        let pool = workers()?;
        WORKERS_HELD
            .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
            .is_ok()
            .then_some(Workers(pool))
    }
}

impl Drop for Workers {
    fn drop(&mut self) {
        WORKERS_HELD.store(false, Ordering::Release);
    }
}

/// `work` applied to every part, results in part order: at most
/// [`available_threads`] threads, this one included, each take the next
/// part not yet taken until none is left. A panic in a part is resumed here.
pub fn run_parts<T: Send, R: Send>(parts: Vec<T>, work: impl Fn(T) -> R + Sync) -> Vec<R> {
    run_parts_with(parts, || (), |(), part| work(part))
}

/// [`run_parts`] with buffers that each thread makes once, by `buffers`,
/// and hands to `work` for every part it takes: what a part needs for a
/// while and then drops is not allocated again and again.
pub fn run_parts_with<T: Send, R: Send, S>(
    parts: Vec<T>,
    buffers: impl Fn() -> S + Sync,
    work: impl Fn(&mut S, T) -> R + Sync,
) -> Vec<R> {
    let threads = available_threads().min(parts.len());
    if threads < 2 {
        let mut buffers = buffers();
        return parts
            .into_iter()
            .map(|part| work(&mut buffers, part))
            .collect();
    }
    let parts: Vec<Mutex<Option<T>>> = parts
        .into_iter()
        .map(|part| Mutex::new(Some(part)))
        .collect();
    let results: Vec<Mutex<Option<R>>> = parts.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let take_parts = || {
        let mut buffers = buffers();
        loop {
            let index = next.fetch_add(1, Ordering::Relaxed);
            let Some(slot) = parts.get(index) else {
                return;
            };
            // Each index is taken once: the slot holds its part.
            let part = slot
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .take();
            if let Some(part) = part {
                let result = work(&mut buffers, part);
                *results[index]
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(result);
            }
        }
    };
    if let Some(workers) = Workers::claim() {
        // A panic in a helper's part is resumed here once all have ended.
        workers.0.in_place_scope(|scope| {
            for _ in 1..threads {
                scope.spawn(|_| take_parts());
            }
            take_parts();
        });
    } else {
        // Another split has the workers (a server's requests, the tests'
        // threads, a split within a part), or this is a forked child, whose
        // parent's workers are not in it: threads of its own.
        std::thread::scope(|scope| {
            let helpers: Vec<_> = (1..threads).map(|_| scope.spawn(take_parts)).collect();
            take_parts();
            helpers.into_iter().for_each(joined);
        });
    }
    results
        .into_iter()
        .map(|slot| {
            slot.into_inner()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .expect("every part ran: a panic would have been resumed")
        })
        .collect()
}

/// `aside` on another core while `here` runs on this thread: both results.
/// `aside` goes to the process's workers when no split holds them (without
/// holding them: the splits `here` makes share them), to a thread started
/// for it otherwise — within a split's part, queued behind the workers'
/// own parts, it would keep the caller waiting while they take the rest.
/// A panic in either is resumed here.
pub fn beside<A: Send, B>(aside: impl FnOnce() -> A + Send, here: impl FnOnce() -> B) -> (A, B) {
    if available_threads() < 2 {
        return (aside(), here());
    }
    if let Some(pool) = workers().filter(|_| !WORKERS_HELD.load(Ordering::Acquire)) {
        let mut aside_result = None;
        let here_result = pool.in_place_scope(|scope| {
            scope.spawn(|_| aside_result = Some(aside()));
            here()
        });
        let aside_result = aside_result.expect("the scope ended after its job");
        (aside_result, here_result)
    } else {
        std::thread::scope(|scope| {
            let aside = scope.spawn(aside);
            let here_result = here();
            (joined(aside), here_result)
        })
    }
}

/// [`beside`] for small work: where the workers are held (within a
/// split's part, every core busy) `aside` runs first on this thread, then
/// `here`, instead of on a thread started for it (which costs about what
/// a tenth of a millisecond of work saves).
pub fn beside_if_free<A: Send, B>(
    aside: impl FnOnce() -> A + Send,
    here: impl FnOnce() -> B,
) -> (A, B) {
    if WORKERS_HELD.load(Ordering::Acquire) {
        let aside = aside();
        (aside, here())
    } else {
        beside(aside, here)
    }
}

/// A started thread's result, its panic resumed here.
fn joined<T>(thread: std::thread::ScopedJoinHandle<'_, T>) -> T {
    thread
        .join()
        .unwrap_or_else(|payload| std::panic::resume_unwind(payload))
}

/// Items from which a light pass over them (a sum, a range, a count, a
/// selection's pass: a few nanoseconds an item) is read in parts on all
/// cores: a thread's start costs about what such a pass over some ten
/// thousand items does, and a million configurations' residuals take a
/// fifth of a second on one core.
pub const PARALLEL_SCAN: usize = 1 << 16;

/// `0..len` cut into contiguous parts for a light pass (see
/// [`PARALLEL_SCAN`]): one below it, else about [`PARTS_PER_THREAD`] per
/// thread, for [`run_parts`] to take in turn. Never empty.
pub fn scan_parts(len: usize) -> Vec<std::ops::Range<usize>> {
    let parts = if len < PARALLEL_SCAN {
        1
    } else {
        available_threads() * PARTS_PER_THREAD
    };
    let at = |part: usize| len * part / parts;
    (0..parts).map(|part| at(part)..at(part + 1)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_come_back_in_order() {
        for count in [1, 2, 5, 16] {
            let parts: Vec<usize> = (0..count).collect();
            let expected: Vec<usize> = (0..count).map(|part| part * 10).collect();
            assert_eq!(run_parts(parts, |part| part * 10), expected);
        }
        assert_eq!(
            run_parts(Vec::<usize>::new(), |part| part),
            Vec::<usize>::new()
        );
    }

    /// A slow thread takes fewer parts and the results stay in part order.
    #[test]
    fn a_slow_part_does_not_reorder_the_results() {
        let parts: Vec<usize> = (0..40).collect();
        let results = run_parts(parts, |part| {
            if part == 0 {
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            part * 3
        });
        assert_eq!(results, (0..40).map(|part| part * 3).collect::<Vec<_>>());
    }

    /// Each thread makes its buffers once and keeps them for every part it
    /// takes: the buffers made are at most the threads, the parts each
    /// buffer saw add up to all of them, and the results stay in order.
    #[test]
    fn each_thread_makes_its_buffers_once() {
        let made = AtomicUsize::new(0);
        let parts: Vec<usize> = (0..200).collect();
        let results = run_parts_with(
            parts,
            || {
                made.fetch_add(1, Ordering::Relaxed);
                Vec::new()
            },
            |seen: &mut Vec<usize>, part| {
                seen.push(part);
                (part * 2, seen.len())
            },
        );
        let made = made.into_inner();
        assert!((1..=available_threads()).contains(&made), "{made} buffers");
        assert_eq!(
            results.iter().map(|(value, _)| *value).collect::<Vec<_>>(),
            (0..200).map(|part| part * 2).collect::<Vec<_>>()
        );
        // Each buffer's last count is the number of parts it saw.
        let most = results.iter().map(|(_, seen)| *seen).max().unwrap_or(0);
        assert!(most >= 200 / made, "a buffer saw at most {most} parts");
    }

    /// The parts of a light pass cover every item once, in order.
    #[test]
    fn scan_parts_cover_every_item() {
        for len in [0, 1, 100, PARALLEL_SCAN - 1, PARALLEL_SCAN, 1_000_003] {
            let parts = scan_parts(len);
            assert_eq!(parts.first().map(|part| part.start), Some(0));
            assert_eq!(parts.last().map(|part| part.end), Some(len));
            assert!(parts.windows(2).all(|pair| pair[0].end == pair[1].start));
            assert_eq!(
                parts.len() == 1,
                len < PARALLEL_SCAN || available_threads() * PARTS_PER_THREAD == 1
            );
        }
    }

    /// Splits from several threads at once, each with a split within every
    /// part, come back whole and in order: one holds the workers, the
    /// others run on threads of their own.
    #[test]
    fn concurrent_and_nested_splits_complete_in_order() {
        let expected = |k: usize| -> Vec<usize> {
            (0..50)
                .map(|part| (0..10).map(|x| x * part).sum::<usize>() + k)
                .collect()
        };
        std::thread::scope(|scope| {
            let runs: Vec<_> = (0..4)
                .map(|k| {
                    scope.spawn(move || {
                        run_parts((0..50).collect(), |part: usize| {
                            let inner = run_parts((0..10).collect(), |x: usize| x * part);
                            inner.iter().sum::<usize>() + k
                        })
                    })
                })
                .collect();
            for (k, run) in runs.into_iter().enumerate() {
                assert_eq!(run.join().expect("no panic"), expected(k));
            }
        });
    }

    /// Work beside each part of a split (a Monte Carlo run's identification
    /// in each part) leaves the caller taking its share of the parts: the
    /// workers the split holds are not waited for by the parts' work beside.
    #[test]
    fn work_beside_within_a_split_leaves_the_caller_its_share() {
        if available_threads() < 2 {
            return;
        }
        let caller = std::thread::current().id();
        let taken_here = run_parts((0..16).collect(), |_: usize| {
            let (_, here) = beside(
                || std::thread::sleep(std::time::Duration::from_millis(1)),
                || {
                    std::thread::sleep(std::time::Duration::from_millis(5));
                    std::thread::current().id() == caller
                },
            );
            here
        });
        let taken_here = taken_here.into_iter().filter(|here| *here).count();
        assert!(taken_here >= 3, "the caller took {taken_here} parts of 16");
    }

    /// Work beside a split's parts, and splits within it, from a split's
    /// part and from this thread: both results, whole.
    #[test]
    fn work_beside_comes_back_with_this_threads() {
        let (aside, here) = beside(
            || run_parts((0..20).collect(), |x: usize| x * 2),
            || run_parts((0..30).collect(), |x: usize| x + 1),
        );
        assert_eq!(aside, (0..20).map(|x| x * 2).collect::<Vec<_>>());
        assert_eq!(here, (1..=30).collect::<Vec<_>>());
        let nested = run_parts((0..8).collect(), |part: usize| {
            let (a, b) = beside(|| part * 3, || part + 1);
            a + b
        });
        assert_eq!(nested, (0..8).map(|p| 4 * p + 1).collect::<Vec<_>>());
    }

    /// Small work beside within a split's part runs on the part's thread
    /// (no thread started for it), and both results come back whole.
    #[test]
    fn small_work_beside_within_a_split_stays_on_its_thread() {
        let (aside, here) = beside_if_free(|| 2 + 2, || "here");
        assert_eq!((aside, here), (4, "here"));
        let same_thread = run_parts((0..16).collect(), |part: usize| {
            let (aside, here) = beside_if_free(
                || (std::thread::current().id(), part * 3),
                || (std::thread::current().id(), part + 1),
            );
            assert_eq!((aside.1, here.1), (part * 3, part + 1));
            aside.0 == here.0
        });
        // Another test's split ending may free the workers meanwhile.
        let same = same_thread.into_iter().filter(|same| *same).count();
        assert!(same >= 12, "{same} of 16 parts kept their work beside");
    }

    #[test]
    #[should_panic(expected = "aside")]
    fn a_panic_beside_reaches_the_caller() {
        beside(|| panic!("aside"), || 1);
    }

    #[test]
    #[should_panic(expected = "part 3")]
    fn a_panic_in_a_part_reaches_the_caller() {
        run_parts((0..4).collect(), |part: usize| {
            assert!(part != 3, "part 3");
        });
    }
}
