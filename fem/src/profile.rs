//! Where the wall time of a run goes: one clock lap per phase of the step (docs/fem-model.md §9)
//! and of the loop around it. A lap costs one `Instant::now()` (tens of ns) against a step of
//! about a millisecond at paper resolution, so the clock stays on in every run.
//!
//! Timings never enter the run's records or files (they differ between runs); the `fem` binary
//! prints them.

use serde::Serialize;
use std::time::Instant;

/// The phases of a run, in the order of the step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Ramp values, interface displacements saved, predictor, prescribed values.
    Predictor,
    /// Bulk internal forces (element kernel).
    Bulk,
    /// Strain energy at the sampled steps.
    StrainEnergy,
    /// Cohesive tractions of the inserted elements, paper eqs. (2)–(3).
    Cohesive,
    /// Contact detection and resolution (node-to-segment, friction).
    Contact,
    /// External forces, boundary reactions and work, tied pairs.
    Boundary,
    /// Corrector, stability guard, prescribed values restored.
    Corrector,
    /// Extrinsic insertion check.
    Insertion,
    /// Velocity scaling on the damped set.
    Damping,
    /// Records of the sampled steps (tips, tractions, energies, probes).
    Diagnostics,
}

impl Phase {
    /// Every phase, in step order.
    pub const ALL: [Phase; 10] = [
        Phase::Predictor,
        Phase::Bulk,
        Phase::StrainEnergy,
        Phase::Cohesive,
        Phase::Contact,
        Phase::Boundary,
        Phase::Corrector,
        Phase::Insertion,
        Phase::Damping,
        Phase::Diagnostics,
    ];

    /// Short name, as printed.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Predictor => "predictor",
            Phase::Bulk => "bulk forces",
            Phase::StrainEnergy => "strain energy",
            Phase::Cohesive => "cohesive law",
            Phase::Contact => "contact",
            Phase::Boundary => "boundary and ties",
            Phase::Corrector => "corrector",
            Phase::Insertion => "insertion",
            Phase::Damping => "damping",
            Phase::Diagnostics => "diagnostics",
        }
    }
}

/// Wall time per phase, accumulated lap by lap.
#[derive(Debug, Clone)]
pub struct Clock {
    seconds: [f64; Phase::ALL.len()],
    /// Time of work done beside another phase (on other threads), per phase [s].
    beside: [f64; Phase::ALL.len()],
    last: Instant,
}

impl Default for Clock {
    fn default() -> Self {
        Clock {
            seconds: [0.0; Phase::ALL.len()],
            beside: [0.0; Phase::ALL.len()],
            last: Instant::now(),
        }
    }
}

impl Clock {
    /// Starts a lap now (the time since the last lap is not booked).
    #[inline]
    pub(crate) fn start(&mut self) {
        self.last = Instant::now();
    }

    /// Books the time since the last lap to `phase` and starts the next lap.
    #[inline]
    pub(crate) fn lap(&mut self, phase: Phase) {
        let now = Instant::now();
        self.seconds[phase as usize] += (now - self.last).as_secs_f64();
        self.last = now;
    }

    /// Books `seconds` of work of `phase` that ran beside the current lap (inside it, on other
    /// threads): printed apart, not added to the total.
    #[inline]
    pub(crate) fn overlapped(&mut self, phase: Phase, seconds: f64) {
        self.beside[phase as usize] += seconds;
    }

    /// Seconds per phase so far, then the work done beside other phases.
    pub fn phases(&self) -> Vec<PhaseTime> {
        let laps = Phase::ALL.iter().map(|&p| PhaseTime {
            phase: p.name(),
            seconds: self.seconds[p as usize],
            beside: false,
        });
        let beside = Phase::ALL
            .iter()
            .filter(|&&p| self.beside[p as usize] > 0.0)
            .map(|&p| PhaseTime {
                phase: p.name(),
                seconds: self.beside[p as usize],
                beside: true,
            });
        laps.chain(beside).collect()
    }
}

/// The wall time of one phase over a run.
#[derive(Debug, Clone, Serialize)]
pub struct PhaseTime {
    /// Phase name.
    pub phase: &'static str,
    /// Wall time [s].
    pub seconds: f64,
    /// Work that ran beside the laps (e.g. contact detection on another thread while the bulk
    /// sweep ran): inside another phase's time, not part of the total.
    pub beside: bool,
}

/// The profile as an aligned text table: phase, seconds, share of the total, µs per step and ns
/// per element-step (`preflight::profile::table`).
pub fn table(phases: &[PhaseTime], steps: u64, elements: usize) -> String {
    let rows: Vec<preflight::profile::Row<'_>> = phases
        .iter()
        .map(|p| preflight::profile::Row {
            phase: p.phase,
            seconds: p.seconds,
            beside: p.beside,
        })
        .collect();
    preflight::profile::table(&rows, steps, elements as u64, "ns/elem-step")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn laps_go_to_their_phase_and_the_table_sums_them() {
        let mut c = Clock::default();
        c.start();
        std::thread::sleep(std::time::Duration::from_millis(5));
        c.lap(Phase::Bulk);
        c.lap(Phase::Contact);
        c.overlapped(Phase::Contact, 0.5);
        let p = c.phases();
        let bulk = p.iter().find(|x| x.phase == "bulk forces").unwrap().seconds;
        let contact = p.iter().find(|x| x.phase == "contact").unwrap().seconds;
        assert!(bulk >= 0.005 && contact < bulk, "{bulk} {contact}");
        let t = table(&p, 10, 100);
        assert!(
            t.lines().nth(Phase::ALL.len() + 1).unwrap().starts_with("total"),
            "{t}"
        );
        assert!(t.lines().last().unwrap().starts_with("contact, beside"), "{t}");
        assert_eq!(t.lines().count(), Phase::ALL.len() + 3);
        let total: f64 = t
            .lines()
            .nth(Phase::ALL.len() + 1)
            .unwrap()
            .split_whitespace()
            .nth(1)
            .unwrap()
            .parse()
            .unwrap();
        // against the laps, to the table's 1 ms, not against a fixed time (a sleep runs long on
        // a loaded machine): the 0.5 s beside them would show as a difference of 0.5 s
        assert!(
            (total - (bulk + contact)).abs() <= 0.0005 + 1e-12,
            "time beside the laps is not in the total: {t}"
        );
    }
}
