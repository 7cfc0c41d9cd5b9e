//! Independent runs at the same time. A run's time loop is memory-bound and its parallel parts
//! scale below the core count, so k runs side by side on n/k cores each often finish sooner than
//! the same runs one after the other on all n cores: on 2 cores the comparison's runs gain 1.5
//! (spectral) to 1.7 (FE) times from a second core and barely slow each other side by side
//! (docs/performance.md). Runs that gain well from a second core and slow each other side by side
//! (the FE runs on a mapped mesh) finish sooner one after the other, each on two cores, which
//! their jobs choose by default ([`Lanes::for_fe`]; measured both ways in docs/performance.md,
//! "The comparison and the other jobs"). `--concurrent-runs` overrides either default.
//! Each lane is an OS thread with its own rayon pool; the runs' results do not depend on the pool
//! size (both models are bit-identical on any number of threads), so running concurrently
//! changes wall time only.

use anyhow::{Context, Result};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// How many runs go at once and how many threads each gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lanes {
    /// Runs at the same time.
    pub lanes: usize,
    /// Threads of each run.
    pub threads: usize,
}

impl Lanes {
    /// `jobs` runs on `cores` threads: as many at once as asked (`requested`), else one per core,
    /// never more than there are runs; the cores are shared out evenly between them.
    pub fn new(jobs: usize, cores: usize, requested: Option<usize>) -> Lanes {
        let cores = cores.max(1);
        let lanes = requested.unwrap_or(cores).clamp(1, jobs.max(1));
        Lanes {
            lanes,
            threads: (cores / lanes).max(1),
        }
    }

    /// As [`Lanes::new`] for a job of FE runs only, `scenes`: unless asked otherwise, one run per
    /// two cores when every run finishes sooner on two cores than sharing them
    /// ([`fem::runs_best_on_two_cores`]: the mapped meshes), so on 2 cores one after the other;
    /// else one per core.
    pub fn for_fe<'s>(
        scenes: impl IntoIterator<Item = &'s fem::Scene>,
        cores: usize,
        requested: Option<usize>,
    ) -> Lanes {
        let (mut jobs, mut two_cores) = (0, true);
        for scene in scenes {
            jobs += 1;
            two_cores &= fem::runs_best_on_two_cores(scene);
        }
        let default = (two_cores && jobs > 0).then(|| (cores / 2).max(1));
        Lanes::new(jobs, cores, requested.or(default))
    }
}

impl std::fmt::Display for Lanes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.lanes {
            1 => write!(f, "one after the other on {} thread(s)", self.threads),
            n => write!(f, "{n} at a time on {} thread(s) each", self.threads),
        }
    }
}

/// One run to do.
pub type Task<'a, T> = Box<dyn FnOnce() -> Result<T> + Send + 'a>;

/// Runs `tasks` in `lanes`, taking them in the order given (put the longest first). Returns one
/// entry per task in the same order: its result, or `None` if it never started because an
/// earlier task had failed (the runs already going are left to finish and keep their output).
pub fn run_all<'a, T: Send>(tasks: Vec<Task<'a, T>>, lanes: Lanes) -> Result<Vec<Option<Result<T>>>> {
    let n = tasks.len();
    if lanes.lanes <= 1 {
        let mut out = Vec::with_capacity(n);
        let mut failed = false;
        for task in tasks {
            if failed {
                out.push(None);
                continue;
            }
            let r = task();
            failed = r.is_err();
            out.push(Some(r));
        }
        return Ok(out);
    }
    let queue: Vec<Mutex<Option<Task<'a, T>>>> = tasks.into_iter().map(|t| Mutex::new(Some(t))).collect();
    let results: Vec<Mutex<Option<Result<T>>>> = (0..n).map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let pools = (0..lanes.lanes)
        .map(|_| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(lanes.threads)
                .build()
                .context("starting a thread pool for concurrent runs")
        })
        .collect::<Result<Vec<_>>>()?;
    std::thread::scope(|s| {
        for pool in &pools {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    if k >= n || failed.load(Ordering::SeqCst) {
                        break;
                    }
                    let task = queue[k]
                        .lock()
                        .expect("invariant: no task panics while holding the queue")
                        .take()
                        .expect("invariant: every index is taken once");
                    let r = pool.install(task);
                    if r.is_err() {
                        failed.store(true, Ordering::SeqCst);
                    }
                    *results[k].lock().expect("invariant: one writer per slot") = Some(r);
                }
            });
        }
    });
    Ok(results
        .into_iter()
        .map(|m| m.into_inner().expect("invariant: no writer panicked"))
        .collect())
}

/// The results of [`run_all`], in task order, or one error naming every run that failed: runs
/// side by side stopped by one Ctrl-C or SIGTERM each say where their partial output went, and
/// every one of them is named, not the first only. A single failure is returned as it is.
pub fn all_ok<T>(results: Vec<Option<Result<T>>>) -> Result<Vec<T>> {
    let mut done = Vec::with_capacity(results.len());
    let mut failed = Vec::new();
    let mut skipped = false;
    for r in results {
        match r {
            Some(Ok(v)) => done.push(v),
            Some(Err(e)) => failed.push(e),
            None => skipped = true,
        }
    }
    match failed.len() {
        0 if skipped => Err(anyhow::anyhow!(
            "invariant: a run is skipped only after an earlier one failed"
        )),
        0 => Ok(done),
        1 => Err(failed.remove(0)),
        n => {
            let each: Vec<String> = failed.iter().map(|e| format!("{e:#}")).collect();
            Err(anyhow::anyhow!("{n} runs ended early:\n{}", each.join("\n")))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_share_the_cores_and_never_outnumber_the_runs() {
        assert_eq!(Lanes::new(4, 2, None), Lanes { lanes: 2, threads: 1 });
        assert_eq!(Lanes::new(4, 16, None), Lanes { lanes: 4, threads: 4 });
        assert_eq!(Lanes::new(1, 8, None), Lanes { lanes: 1, threads: 8 });
        assert_eq!(Lanes::new(4, 2, Some(1)), Lanes { lanes: 1, threads: 2 });
        assert_eq!(Lanes::new(4, 2, Some(9)), Lanes { lanes: 4, threads: 1 });
    }

    /// A job of runs on mapped meshes takes two cores a run; any other run keeps one per core.
    #[test]
    fn fe_runs_on_mapped_meshes_get_two_cores_each() {
        let scene = |name: &str| {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../scenes")
                .join(name);
            crate::study::Study::load(&path).unwrap().fem
        };
        let (sine, rough, flat) = (
            scene("sinusoidal-interface.toml"),
            scene("rough-interface.toml"),
            scene("center-crack.toml"),
        );
        let one = |threads| Lanes { lanes: 1, threads };
        assert_eq!(Lanes::for_fe([&sine, &sine], 2, None), one(2));
        assert_eq!(Lanes::for_fe([&rough, &rough], 2, None), one(2));
        assert_eq!(
            Lanes::for_fe([&sine, &rough], 8, None),
            Lanes { lanes: 2, threads: 4 }
        );
        assert_eq!(Lanes::for_fe([&sine, &sine, &sine], 1, None), one(1));
        // a structured run among them, or a request, keeps the cores shared as before
        assert_eq!(
            Lanes::for_fe([&sine, &flat], 2, None),
            Lanes { lanes: 2, threads: 1 }
        );
        assert_eq!(Lanes::for_fe([&flat; 3], 2, None), Lanes { lanes: 2, threads: 1 });
        assert_eq!(
            Lanes::for_fe([&sine, &sine], 2, Some(2)),
            Lanes { lanes: 2, threads: 1 }
        );
        assert_eq!(Lanes::for_fe([], 2, None), Lanes::new(0, 2, None));
    }

    #[test]
    fn results_come_back_in_task_order_and_a_failure_stops_the_queue() {
        for lanes in [1, 2, 3] {
            let lanes = Lanes { lanes, threads: 1 };
            let tasks: Vec<Task<usize>> = (0..7usize)
                .map(|k| {
                    Box::new(move || {
                        std::thread::sleep(std::time::Duration::from_millis((7 - k as u64) * 2));
                        Ok(k * k)
                    }) as Task<usize>
                })
                .collect();
            let got: Vec<usize> = run_all(tasks, lanes)
                .unwrap()
                .into_iter()
                .map(|r| r.unwrap().unwrap())
                .collect();
            assert_eq!(got, vec![0, 1, 4, 9, 16, 25, 36]);
            let mut tasks: Vec<Task<usize>> = vec![Box::new(|| Err(anyhow::anyhow!("unstable")))];
            tasks.extend((0..20usize).map(|k| {
                Box::new(move || {
                    std::thread::sleep(std::time::Duration::from_millis(20));
                    Ok(k)
                }) as Task<usize>
            }));
            let got = run_all(tasks, lanes).unwrap();
            assert!(got[0].as_ref().unwrap().is_err());
            assert!(got.iter().filter(|r| r.is_none()).count() >= 20 - (lanes.lanes - 1));
        }
    }

    /// Every failure is named, in task order.
    #[test]
    fn all_failures_are_named() {
        let results: Vec<Option<Result<u8>>> = vec![
            Some(Ok(1)),
            Some(Err(anyhow::anyhow!("FE μ = 0: stopped; output in a"))),
            Some(Err(anyhow::anyhow!("FE μ = 0.3: stopped; output in b"))),
            None,
        ];
        let e = all_ok(results).unwrap_err().to_string();
        assert!(
            e.starts_with("2 runs ended early") && e.contains("in a") && e.contains("in b"),
            "{e}"
        );
        assert_eq!(all_ok(vec![Some(Ok(1)), Some(Ok(2))]).unwrap(), vec![1, 2]);
    }
}
