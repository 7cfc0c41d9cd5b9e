//! Where a run's time steps go: the whole rayon pool, or one thread of it, whichever a timed
//! trial found faster per step.
//!
//! Every phase of a step hands arrays from one thread to the other: the face transforms run one
//! face a thread, the modes and the grid points are split in halves. When the pool's threads sit
//! on cores that share a last-level cache that costs little, and two threads take about 0.6 of
//! one thread's step. When they sit on cores that do not (two core complexes of an EPYC, where
//! a host may place a virtual machine's two CPUs), each hand-out crosses between the caches and
//! two threads can take longer than one: 200–212 µs a step against 167 µs on the centre crack
//! (docs/performance.md, "The spectral step when the two threads share no cache"). The run then
//! times chunks of steps both ways and keeps the faster, trying the other again now and then,
//! since the placement can change during a run.
//!
//! Each step's values do not depend on the number of threads that computed them (tests
//! `spectral_output_is_identical_between_runs_and_thread_counts` and
//! `steps_alternating_between_the_pool_and_one_thread_give_the_bits_of_the_pool`), so the
//! choice changes no output, only the time.

use std::time::Instant;

/// Where a chunk of steps runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    /// The whole rayon pool (the steps inside a `rayon::scope`, on a pool thread).
    Pool,
    /// A pool of one thread, built for the purpose.
    One,
}

/// Chunks run on the chosen mode before the other is tried again, after a choice that changed
/// the mode [-]; each trial that loses doubles it. A trial of the slower mode costs at most the
/// difference of one chunk (one thread takes about 1.8 times the two-thread step when the threads
/// share a cache), so a run of 200 chunks (a progress report's each) whose choice holds tries
/// twice more after its first choice (its 52nd and 149th chunks), about 1 % of its time.
const TRIAL_EVERY: usize = 48;

/// One thread is chosen only if its time per step is below this fraction of the pool's [-]: at
/// least 5 % faster, so that a tie, or the noise of two timed chunks, leaves the steps on the pool,
/// the default.
const MARGIN: f64 = 0.95;

/// The choice between the pool and one thread, and the timings it rests on.
pub(crate) struct Placement {
    /// The one-thread pool; `None` when the global pool has one thread already (or the pool
    /// could not be built: the steps then all run on the global pool).
    one: Option<rayon::ThreadPool>,
    /// Chunks started so far [-].
    chunks: usize,
    /// The mode chosen by the last trial.
    chosen: Mode,
    /// Seconds per step of each mode's last timed chunk ([`Mode::Pool`], [`Mode::One`]) [s].
    per_step: [Option<f64>; 2],
    /// Chunks run since the last trial [-].
    since_trial: usize,
    /// Chunks between two trials: [`TRIAL_EVERY`], doubled by each trial that loses [-].
    trial_every: usize,
    /// Steps run on one thread [-].
    one_thread_steps: u64,
    /// Whether the modes alternate chunk by chunk whatever the timings (tests).
    alternate: bool,
}

impl Placement {
    /// The choice for a run on the global rayon pool: with more than one thread, a one-thread
    /// pool is built (once, before the first step).
    pub(crate) fn new() -> Self {
        let one = (rayon::current_num_threads() > 1)
            .then(|| rayon::ThreadPoolBuilder::new().num_threads(1).build().ok())
            .flatten();
        Self::with_pool(one)
    }

    /// Chunks on the pool and on one thread in turn, whatever their times: for the tests that
    /// hold the two to the same bits.
    #[cfg(test)]
    pub(crate) fn alternating() -> Self {
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().ok();
        Self {
            alternate: true,
            ..Self::with_pool(one)
        }
    }

    fn with_pool(one: Option<rayon::ThreadPool>) -> Self {
        Self {
            one,
            chunks: 0,
            chosen: Mode::Pool,
            per_step: [None; 2],
            since_trial: 0,
            trial_every: TRIAL_EVERY,
            one_thread_steps: 0,
            alternate: false,
        }
    }

    /// Runs `body`, a chunk of `steps` time steps, where the choice says, and books its time.
    pub(crate) fn run<R: Send>(&mut self, steps: u64, body: impl FnOnce() -> R + Send) -> R {
        let mode = match &self.one {
            None => Mode::Pool,
            Some(_) => self.next(),
        };
        let start = Instant::now();
        let out = match (mode, &self.one) {
            (Mode::One, Some(pool)) => pool.install(body),
            _ => rayon::scope(|_| body()),
        };
        self.booked(mode, start.elapsed().as_secs_f64(), steps);
        out
    }

    /// Steps run on one thread so far [-].
    pub(crate) fn one_thread_steps(&self) -> u64 {
        self.one_thread_steps
    }

    /// The mode of the next chunk: the first chunk on the pool untimed (it fills the caches),
    /// the second on the pool and the third on one thread, both timed; then the faster, with the
    /// other tried again after [`TRIAL_EVERY`] chunks, twice that after each trial it loses.
    fn next(&self) -> Mode {
        if self.alternate {
            return if self.chunks.is_multiple_of(2) {
                Mode::Pool
            } else {
                Mode::One
            };
        }
        match self.chunks {
            0 | 1 => Mode::Pool,
            2 => Mode::One,
            _ if self.since_trial >= self.trial_every => other(self.chosen),
            _ => self.chosen,
        }
    }

    /// Books a chunk of `steps` steps that took `seconds` in `mode`, and chooses again after a
    /// timed chunk of the mode not chosen.
    fn booked(&mut self, mode: Mode, seconds: f64, steps: u64) {
        self.chunks += 1;
        if mode == Mode::One {
            self.one_thread_steps += steps;
        }
        if self.chunks == 1 || steps == 0 || self.alternate {
            return; // the untimed first chunk; or no choice to make
        }
        self.per_step[mode as usize] = Some(seconds / steps as f64);
        if mode == self.chosen {
            self.since_trial += 1;
            return;
        }
        // a trial, or the third chunk (the first on one thread): choose
        self.since_trial = 0;
        if let [Some(pool), Some(one)] = self.per_step {
            let faster = if one < MARGIN * pool {
                Mode::One
            } else {
                Mode::Pool
            };
            // a trial that loses makes the next one twice as far; the first choice is no trial
            self.trial_every = match faster == self.chosen && self.chunks > 3 {
                true => self.trial_every.saturating_mul(2),
                false => TRIAL_EVERY,
            };
            self.chosen = faster;
        }
    }
}

/// The mode that is not `m`.
fn other(m: Mode) -> Mode {
    match m {
        Mode::Pool => Mode::One,
        Mode::One => Mode::Pool,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A placement with a one-thread pool, whose chunks are booked by hand with `pool` and `one`
    /// seconds a step: the modes of its first `n` chunks.
    fn modes(n: usize, pool: f64, one: f64) -> Vec<Mode> {
        let mut p = Placement::with_pool(None);
        (0..n)
            .map(|_| {
                let m = p.next();
                p.booked(m, if m == Mode::Pool { pool } else { one } * 10.0, 10);
                m
            })
            .collect()
    }

    #[test]
    fn one_thread_is_kept_when_it_is_faster_and_the_pool_tried_again() {
        let m = modes(3 + TRIAL_EVERY + 2, 2e-4, 1.6e-4);
        assert_eq!(&m[..3], [Mode::Pool, Mode::Pool, Mode::One]);
        assert!(m[3..3 + TRIAL_EVERY].iter().all(|&m| m == Mode::One), "{m:?}");
        assert_eq!(m[3 + TRIAL_EVERY], Mode::Pool, "the trial of the pool");
        assert_eq!(m[4 + TRIAL_EVERY], Mode::One, "one thread is still faster");
    }

    #[test]
    fn the_pool_is_kept_when_one_thread_is_not_faster_by_the_margin() {
        // one thread 3 % faster: within the margin, the pool stays
        let m = modes(3 + TRIAL_EVERY + 2, 1e-4, 0.97e-4);
        assert!(
            m.iter()
                .enumerate()
                .all(|(i, &m)| (m == Mode::One) == (i == 2 || i == 3 + TRIAL_EVERY)),
            "{m:?}"
        );
    }

    #[test]
    fn a_trial_that_wins_takes_over() {
        let mut p = Placement::with_pool(None);
        let mut seen = Vec::new();
        for chunk in 0..3 + 2 * TRIAL_EVERY + 3 {
            let m = p.next();
            // the pool is faster until the placement changes, at chunk 10
            let (pool, one) = if chunk < 10 {
                (1e-4, 1.7e-4)
            } else {
                (2e-4, 1.6e-4)
            };
            p.booked(m, if m == Mode::Pool { pool } else { one }, 1);
            seen.push(m);
        }
        assert_eq!(seen[3 + TRIAL_EVERY], Mode::One, "the trial of one thread");
        assert!(
            seen[4 + TRIAL_EVERY..]
                .iter()
                .take(TRIAL_EVERY)
                .all(|&m| m == Mode::One),
            "{seen:?}"
        );
    }

    #[test]
    fn a_trial_that_loses_comes_twice_as_late() {
        let m = modes(3 + 3 * TRIAL_EVERY + 2, 1e-4, 1.7e-4);
        let trials: Vec<usize> = (3..m.len()).filter(|&i| m[i] == Mode::One).collect();
        assert_eq!(trials, [3 + TRIAL_EVERY, 4 + 3 * TRIAL_EVERY], "{m:?}");
    }

    #[test]
    fn steps_run_on_one_thread_where_the_choice_says() {
        let mut p = Placement::alternating();
        let threads: Vec<usize> = (0..4).map(|_| p.run(5, rayon::current_num_threads)).collect();
        let n = rayon::current_num_threads();
        assert_eq!(threads, [n, 1, n, 1]);
        assert_eq!(p.one_thread_steps(), 10);
    }

    #[test]
    fn steps_alternating_between_the_pool_and_one_thread_give_the_bits_of_the_pool() {
        let text = preflight::testing::scene_text(env!("CARGO_MANIFEST_DIR"), "tiny-spectral-andrews");
        let scene = crate::Scene::from_toml_str(&text).unwrap();
        let run = |placement: &mut Placement| {
            let never = std::sync::atomic::AtomicBool::new(false);
            let built = crate::solver::build(&scene).unwrap();
            let out =
                crate::run_placed(&scene, built, (&mut |_, _| {}, &never), (None, None), placement).unwrap();
            // Debug prints every f64 to the bit (a −0 too)
            let debug = format!("{:?}", (&out.tips, &out.contact, &out.fields, &out.stats));
            (debug, out.profile.one_thread_steps, out.stats.steps)
        };
        let (pool, none, steps) = run(&mut Placement::with_pool(None));
        let (mixed, one, _) = run(&mut Placement::alternating());
        assert_eq!(none, 0);
        // about half of the steps on one thread, in chunks alternating with the pool's
        assert!(
            one > steps / 3 && one < 2 * steps / 3,
            "{one} of {steps} on one thread"
        );
        assert!(pool == mixed, "the records differ");
    }
}
