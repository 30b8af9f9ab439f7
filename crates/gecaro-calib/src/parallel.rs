//! Work split over the cores with scoped standard-library threads: the
//! independent per-configuration kinematics and the row blocks of the tall
//! observation matrix. Every split is by contiguous parts whose results are
//! combined in part order, so results do not depend on the number of cores.

use std::sync::OnceLock;

/// The cores this process may use, asked once: the standard library reads
/// the cgroup quota files on every call, which costs more than evaluating
/// a hundred configurations.
pub fn available_threads() -> usize {
    static THREADS: OnceLock<usize> = OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get))
}

/// `work` applied to every part, in part order: the parts are dealt in
/// contiguous runs to at most [`available_threads`] threads, this one
/// included. A panic in a part is resumed here.
pub fn run_parts<T: Send, R: Send>(parts: Vec<T>, work: impl Fn(T) -> R + Sync) -> Vec<R> {
    let threads = available_threads().min(parts.len());
    if threads < 2 {
        return parts.into_iter().map(work).collect();
    }
    let per_thread = parts.len().div_ceil(threads);
    let mut parts = parts.into_iter();
    let mut runs: Vec<Vec<T>> = Vec::with_capacity(threads);
    loop {
        let run: Vec<T> = parts.by_ref().take(per_thread).collect();
        if run.is_empty() {
            break;
        }
        runs.push(run);
    }
    let work = &work;
    let run_all = move |run: Vec<T>| run.into_iter().map(work).collect::<Vec<R>>();
    std::thread::scope(|scope| {
        let mut runs = runs.into_iter();
        let first = runs.next().unwrap_or_default();
        let others: Vec<_> = runs.map(|run| scope.spawn(move || run_all(run))).collect();
        let mut results = run_all(first);
        for handle in others {
            results.extend(
                handle
                    .join()
                    .unwrap_or_else(|payload| std::panic::resume_unwind(payload)),
            );
        }
        results
    })
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

    #[test]
    #[should_panic(expected = "part 3")]
    fn a_panic_in_a_part_reaches_the_caller() {
        run_parts((0..4).collect(), |part: usize| {
            assert!(part != 3, "part 3");
        });
    }
}
