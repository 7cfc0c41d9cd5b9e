//! Where the wall time of a run goes, and the work a step does (docs/spectral-model.md §4.2): one
//! clock lap per phase of the step — forward FFTs, history convolution, assembly and inverse
//! FFTs, interface law, records, displacement update — and the bytes and flops of each phase as
//! the model states them ([`StepWork`]), so that a run can print its roofline.
//!
//! A lap costs one `Instant::now()` (measured at the start of every run, [`Profile::lap_cost_s`];
//! tens of ns against a step of about a millisecond at paper resolution), so the clock stays on
//! in every run. It allocates nothing: the times are fixed arrays, one slot per [`Phase`].
//!
//! Timings never enter the run's records or files (they differ between runs); the `spectral`
//! binary prints them.

use std::time::Instant;

/// The phases of a step, in their order (docs/spectral-model.md §4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Packing of the four face fields into two complex arrays, the two forward FFTs and the
    /// split into the spectra Û of the four fields (§4.2 step 2).
    ForwardFft,
    /// History convolution per mode (§4.2 steps 2–3): the sum-of-exponentials recursion (§4.3),
    /// or the ring-buffer push and the direct sum (§4.1).
    Convolution,
    /// Assembly of F^± (§2), the two inverse FFTs and the unpacking into f^± (§4.2 step 4).
    InverseFft,
    /// Two materials (§2.1): the wait for the bottom half-space's operator, which runs beside
    /// the top one's, and the copy of its face.
    SecondHalfSpace,
    /// Interface law per grid point: cohesion, contact, friction, velocities and tractions
    /// (§5, §4.2 step 5).
    Law,
    /// Records of the step: tips every step, contact means and field snapshots at their
    /// intervals (§6, §4.2 step 6).
    Records,
    /// u^{n+1} = u^n + Δt v^n (§4.2 step 7).
    Update,
}

/// Number of phases.
const PHASES: usize = 7;

impl Phase {
    /// Every phase, in step order.
    pub const ALL: [Phase; PHASES] = [
        Phase::ForwardFft,
        Phase::Convolution,
        Phase::InverseFft,
        Phase::SecondHalfSpace,
        Phase::Law,
        Phase::Records,
        Phase::Update,
    ];

    /// Short name, as printed.
    pub fn name(self) -> &'static str {
        match self {
            Phase::ForwardFft => "forward FFT",
            Phase::Convolution => "convolution",
            Phase::InverseFft => "inverse FFT",
            Phase::SecondHalfSpace => "second half-space",
            Phase::Law => "interface law",
            Phase::Records => "records",
            Phase::Update => "displacements",
        }
    }
}

/// Wall time per phase over a run, the part of it that is measured (laps) and the work that ran
/// beside it (the bottom operator of two materials). Plain numbers: no allocation, `Copy`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Profile {
    /// Wall time booked to each phase, in the order of [`Phase::ALL`] [s].
    pub seconds: [f64; PHASES],
    /// Laps booked to each phase [-].
    pub laps: [u64; PHASES],
    /// Time of work done beside the laps (inside another phase's wall time, on another thread or
    /// waited for), per phase [s].
    pub beside: [f64; PHASES],
    /// Cost of one lap (one `Instant::now()` and the booking), measured when the run started [s].
    pub lap_cost_s: f64,
    /// Steps run on one thread of a larger pool: the chunks that timed one thread against the
    /// pool, and those run there because such a trial found it faster (docs/performance.md, "The
    /// spectral step when the two threads share no cache") [-].
    pub one_thread_steps: u64,
}

/// The wall time of one phase over a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseTime {
    /// The phase.
    pub phase: Phase,
    /// Wall time [s].
    pub seconds: f64,
    /// Work that ran beside the laps (the bottom half-space's operator of two materials, run
    /// beside the top one's): inside another phase's time, not part of the total.
    pub beside: bool,
}

impl Profile {
    /// Seconds per phase that ran (a phase never lapped, such as the second half-space of
    /// identical materials, is left out), then the work done beside them.
    pub fn phases(&self) -> Vec<PhaseTime> {
        let laps = Phase::ALL
            .iter()
            .filter(|&&p| self.laps[p as usize] > 0)
            .map(|&p| PhaseTime {
                phase: p,
                seconds: self.seconds[p as usize],
                beside: false,
            });
        let beside = Phase::ALL
            .iter()
            .filter(|&&p| self.beside[p as usize] > 0.0)
            .map(|&p| PhaseTime {
                phase: p,
                seconds: self.beside[p as usize],
                beside: true,
            });
        laps.chain(beside).collect()
    }

    /// Wall time of the laps, all phases [s].
    pub fn total(&self) -> f64 {
        self.seconds.iter().sum()
    }

    /// Laps taken, all phases [-].
    pub fn total_laps(&self) -> u64 {
        self.laps.iter().sum()
    }

    /// Time the clock itself cost over the run: laps × the measured cost of one [s].
    pub fn clock_cost(&self) -> f64 {
        self.total_laps() as f64 * self.lap_cost_s
    }
}

/// The running clock: a [`Profile`] and the end of the last lap.
#[derive(Debug, Clone, Copy)]
pub struct Clock {
    profile: Profile,
    last: Instant,
}

impl Default for Clock {
    fn default() -> Self {
        Clock {
            profile: Profile::default(),
            last: Instant::now(),
        }
    }
}

impl Clock {
    /// A clock started now, whose lap cost is measured (10 000 laps into a scratch clock, about
    /// 0.5 ms at 50 ns a lap).
    pub fn calibrated() -> Clock {
        const LAPS: u32 = 10_000;
        let mut scratch = Clock::default();
        let start = Instant::now();
        for _ in 0..LAPS {
            scratch.lap(Phase::Update);
        }
        let mut c = Clock::default();
        c.profile.lap_cost_s = start.elapsed().as_secs_f64() / f64::from(LAPS);
        c
    }

    /// Starts a lap now (the time since the last lap is not booked).
    #[inline]
    pub fn start(&mut self) {
        self.last = Instant::now();
    }

    /// Books the time since the last lap to `phase` and starts the next lap.
    #[inline]
    pub fn lap(&mut self, phase: Phase) {
        let now = Instant::now();
        self.profile.seconds[phase as usize] += (now - self.last).as_secs_f64();
        self.profile.laps[phase as usize] += 1;
        self.last = now;
    }

    /// Books the laps of `other`, a clock that ran beside this one's current lap, as work beside
    /// (printed apart, not added to the total).
    #[inline]
    pub fn beside(&mut self, other: &Clock) {
        for (b, s) in self.profile.beside.iter_mut().zip(other.profile.seconds) {
            *b += s;
        }
    }

    /// What the clock has booked so far.
    pub fn profile(&self) -> Profile {
        self.profile
    }
}

/// The profile as an aligned text table, in the `fem` command's form
/// (`preflight::profile::table`): phase, seconds, share of the total, µs per step and ns per
/// grid-point step, over `steps` steps of `points` grid points.
pub fn table(profile: &Profile, steps: u64, points: u64) -> String {
    let rows: Vec<preflight::profile::Row<'_>> = profile
        .phases()
        .iter()
        .map(|p| preflight::profile::Row {
            phase: p.phase.name(),
            seconds: p.seconds,
            beside: p.beside,
        })
        .collect();
    preflight::profile::table(&rows, steps, points, "ns/point-step")
}

/// Work of one phase of a step: floating-point operations and the bytes its loops read and
/// write, each array counted once per pass (what a cache line brings beyond the values used,
/// FFT scratch and passes inside the cache, and prefetch are not counted).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Work {
    /// Floating-point operations (a fused multiply-add counts 2) [-].
    pub flops: f64,
    /// Bytes read [B].
    pub read: f64,
    /// Bytes written [B].
    pub written: f64,
}

impl Work {
    /// Bytes moved, read and written [B].
    pub fn bytes(&self) -> f64 {
        self.read + self.written
    }

    /// Arithmetic intensity, flops per byte moved [flop/B].
    pub fn intensity(&self) -> f64 {
        if self.bytes() > 0.0 {
            self.flops / self.bytes()
        } else {
            0.0
        }
    }
}

impl std::ops::Add for Work {
    type Output = Work;
    fn add(self, o: Work) -> Work {
        Work {
            flops: self.flops + o.flops,
            read: self.read + o.read,
            written: self.written + o.written,
        }
    }
}

impl std::ops::Mul<f64> for Work {
    type Output = Work;
    fn mul(self, k: f64) -> Work {
        Work {
            flops: self.flops * k,
            read: self.read * k,
            written: self.written * k,
        }
    }
}

/// The work of one step, per phase (the convolution with full windows on the direct path):
/// what docs/performance.md needs for the model's roofline.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepWork {
    /// Work of each phase, in the order of [`Phase::ALL`] (none for the records, which the
    /// model does not count: a walk from the centre to the tips every step, a pass over the
    /// grid at each sample).
    pub phases: [Work; PHASES],
}

impl StepWork {
    /// The work of `phase`.
    pub fn of(&self, phase: Phase) -> Work {
        self.phases[phase as usize]
    }

    /// Adds `w` to `phase`.
    pub fn add(&mut self, phase: Phase, w: Work) {
        self.phases[phase as usize] = self.phases[phase as usize] + w;
    }

    /// The whole step.
    pub fn total(&self) -> Work {
        self.phases.iter().fold(Work::default(), |a, &b| a + b)
    }
}

/// The work per step as an aligned text table: per phase, kB moved, kflop, flop/B, and with a
/// measured `profile` over `steps` steps the rates it achieved (GB/s and GFLOP/s).
pub fn work_table(work: &StepWork, profile: &Profile, steps: u64) -> String {
    let line = |name: &str, w: Work, s: f64| {
        let t = if steps > 0 { s / steps as f64 } else { 0.0 };
        let rate = |x: f64| if t > 0.0 { x / t / 1e9 } else { f64::NAN };
        format!(
            "{:<18} {:>9.1} {:>9.1} {:>9.1} {:>7.2} {:>8.1} {:>8.2}\n",
            name,
            w.read / 1e3,
            w.written / 1e3,
            w.flops / 1e3,
            w.intensity(),
            rate(w.bytes()),
            rate(w.flops)
        )
    };
    let mut out = format!(
        "{:<18} {:>9} {:>9} {:>9} {:>7} {:>8} {:>8}\n",
        "phase", "kB read", "kB wrote", "kflop", "flop/B", "GB/s", "GFLOP/s"
    );
    for p in Phase::ALL {
        let w = work.of(p);
        if w == Work::default() {
            if profile.laps[p as usize] > 0 {
                out += &format!("{:<18} {:>9}\n", p.name(), "not counted");
            }
            continue;
        }
        out += &line(p.name(), w, profile.seconds[p as usize]);
    }
    out += &line("total", work.total(), profile.total());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn laps_go_to_their_phase_and_the_table_sums_them() {
        let mut c = Clock::calibrated();
        // tens of ns a lap; the bound allows a preemption of up to 0.5 s during the calibration,
        // and fails if the whole loop (at least 0.1 ms: 10 ns a lap or more) were booked as one lap
        assert!(
            c.profile().lap_cost_s > 0.0 && c.profile().lap_cost_s < 5e-5,
            "a lap costs {} s",
            c.profile().lap_cost_s
        );
        c.start();
        std::thread::sleep(std::time::Duration::from_millis(5));
        c.lap(Phase::Convolution);
        c.lap(Phase::Law);
        let mut other = Clock::default();
        std::thread::sleep(std::time::Duration::from_millis(2));
        other.lap(Phase::Convolution);
        c.beside(&other);
        let p = c.profile();
        let conv = p.seconds[Phase::Convolution as usize];
        let law = p.seconds[Phase::Law as usize];
        assert!(conv >= 0.005 && law < conv, "{conv} {law}");
        assert_eq!(p.total_laps(), 2);
        assert_eq!(
            p.phases().len(),
            3,
            "two phases lapped, one beside: {:?}",
            p.phases()
        );
        let t = table(&p, 10, 100);
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines.len(), 5, "{t}");
        assert!(lines[1].starts_with("convolution") && lines[2].starts_with("interface law"));
        assert!(lines[3].starts_with("total") && lines[4].starts_with("convolution, beside"));
        // The total is the laps' time alone. A sleep may run long on a loaded machine, so the
        // printed total is checked against the laps (to the table's 1 ms precision), not against
        // a fixed time: the 2 ms or more beside them would show as a difference of 2 ms or more.
        assert_eq!(p.total(), conv + law);
        let beside = p.beside[Phase::Convolution as usize];
        assert!(beside >= 0.002, "{beside}");
        let total: f64 = lines[3].split_whitespace().nth(1).unwrap().parse().unwrap();
        assert!(
            (total - p.total()).abs() <= 0.0005 + 1e-12,
            "time beside the laps is not in the total: {t}"
        );
    }

    #[test]
    fn work_adds_up_by_phase() {
        let mut w = StepWork::default();
        let a = Work {
            flops: 10.0,
            read: 3.0,
            written: 2.0,
        };
        w.add(Phase::Law, a);
        w.add(Phase::Law, a * 2.0);
        w.add(Phase::Update, a);
        assert_eq!(w.of(Phase::Law).flops, 30.0);
        assert_eq!(w.total().bytes(), 20.0);
        assert_eq!(w.total().intensity(), 2.0);
        let t = work_table(&w, &Profile::default(), 0);
        assert_eq!(t.lines().count(), 4, "header, law, displacements, total: {t}");
    }
}
