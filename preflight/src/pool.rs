//! Rayon's workers kept awake while a run steps. A worker of rayon's pool that finds no work
//! sleeps after a few dozen looks, and the next parallel loop wakes it through the kernel: under
//! a hypervisor that wake is an interrupt sent to another virtual CPU, and a time step, with serial
//! phases between its parallel loops, paid it at nearly every loop (docs/performance.md, "The
//! pool kept awake"). [`Steps`] runs a run's steps on a pool of their own whose other workers keep
//! looking for work, yielding their cores to any other thread between looks, until the steps end.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// A rayon pool for a run's steps, of as many threads as the caller's pool (rayon's global pool,
/// or the pool the caller runs on), built once for the whole run: none on one thread, or if it
/// cannot be built. Its own pool, not the caller's: on a shared one, a worker waiting inside
/// another caller's parallel loop could take up a looker and hold that caller's work until these
/// steps end.
pub struct Steps {
    pool: Option<rayon::ThreadPool>,
}

impl Steps {
    /// The pool for a run started from here.
    pub fn new() -> Steps {
        let threads = rayon::current_num_threads();
        let pool = (threads > 1)
            .then(|| rayon::ThreadPoolBuilder::new().num_threads(threads).build().ok())
            .flatten();
        Steps { pool }
    }

    /// Runs `steps` on a thread of the pool while every other worker of it looks for work instead
    /// of sleeping, until `steps` returns or panics; without a pool, inside `rayon::scope` on the
    /// caller's pool. Which thread runs which piece of work changes no value: the models' results
    /// do not depend on it.
    pub fn run<R: Send>(&self, steps: impl FnOnce() -> R + Send) -> R {
        match &self.pool {
            Some(pool) => pool.install(|| with_lookers(steps).0),
            None => rayon::scope(|_| steps()),
        }
    }
}

impl Default for Steps {
    fn default() -> Steps {
        Steps::new()
    }
}

/// `steps` on this worker, every other worker of its pool a looker until they end: a job that
/// executes whatever work the pool has, and yields its core when there is none. Also gives how
/// many workers looked.
fn with_lookers<R: Send>(steps: impl FnOnce() -> R + Send) -> (R, usize) {
    let lookers = rayon::current_num_threads().saturating_sub(1);
    let (done, settled, looked) = (AtomicBool::new(false), AtomicUsize::new(0), AtomicUsize::new(0));
    let out = rayon::scope(|s| {
        let home = rayon::current_thread_index();
        for _ in 0..lookers {
            let (done, settled, looked) = (&done, &settled, &looked);
            s.spawn(move |_| {
                settled.fetch_add(1, Ordering::AcqRel);
                // on the thread that runs the steps (which the wait below keeps from happening):
                // nothing to keep awake
                if rayon::current_thread_index() == home {
                    return;
                }
                looked.fetch_add(1, Ordering::AcqRel);
                // the other lookers left to the other workers first
                while settled.load(Ordering::Acquire) < lookers {
                    std::thread::yield_now();
                }
                while !done.load(Ordering::Acquire) {
                    if rayon::yield_now() != Some(rayon::Yield::Executed) {
                        std::thread::yield_now();
                    }
                }
            });
        }
        // Every looker taken up by another worker before the steps give the pool work: a looker
        // taken up later by a worker waiting inside a step's loop would hold that loop's job
        // until the steps end, which wait for it. This thread only yields meanwhile: were it to
        // look for work, it would take up the lookers itself.
        while settled.load(Ordering::Acquire) < lookers {
            std::thread::yield_now();
        }
        // set when the steps end, even by a panic, so that the scope's wait for the lookers ends
        struct Done<'a>(&'a AtomicBool);
        impl Drop for Done<'_> {
            fn drop(&mut self) {
                self.0.store(true, Ordering::Release);
            }
        }
        let _done = Done(&done);
        steps()
    });
    (out, looked.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    /// `steps` on a pool of their own, built for them.
    fn awake<R: Send>(steps: impl FnOnce() -> R + Send) -> R {
        Steps::new().run(steps)
    }

    /// Steps whose parallel loops nest joins: their sum with the lookers beside them, on pools of
    /// one to four threads, from inside a pool and from outside, nested, and from two callers at
    /// once on the same pool; a panic in the steps reaches the caller instead of leaving the
    /// lookers running.
    #[test]
    fn the_steps_run_beside_the_lookers_and_a_panic_ends_them() {
        fn steps() -> u64 {
            (0..50u64)
                .map(|k| -> u64 { (0..2000u64).into_par_iter().map(|i| i * k).sum() })
                .sum()
        }
        let want: u64 = (0..50u64).sum::<u64>() * (0..2000u64).sum::<u64>();
        for threads in [1, 2, 3, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            assert_eq!(pool.install(|| awake(steps)), want, "{threads} threads");
            assert_eq!(
                pool.install(|| awake(|| awake(steps))),
                want,
                "{threads} threads, nested"
            );
            let (a, b) = pool.install(|| rayon::join(|| awake(steps), || awake(steps)));
            assert_eq!((a, b), (want, want), "{threads} threads, two callers at once");
            let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                pool.install(|| awake(|| panic!("in the steps")))
            }));
            assert!(caught.is_err(), "{threads} threads: the panic reaches the caller");
        }
        assert_eq!(awake(steps), want, "from outside any pool");
    }

    /// Every worker but the one that runs the steps looks for work while they run (were the
    /// steps' thread to take up the lookers itself, none would).
    #[test]
    fn every_other_worker_looks_while_the_steps_run() {
        for threads in [2, 3, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for _ in 0..20 {
                let (_, looked) = pool.install(|| with_lookers(|| ()));
                assert_eq!(looked, threads - 1, "{threads} threads");
            }
        }
    }
}
