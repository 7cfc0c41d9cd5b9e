//! How a model's run ended, in one form that both models' command lines and the comparison
//! harness read: it reached T, or it stopped before (unstable, stopped on request, an output not
//! written) with the records computed up to there.

/// How a run ended, as its output files say it (`status` in the FE model's `run.csv` and the
/// spectral model's `stats.csv`): a reader tells a partial run from a finished one by it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// It reached T.
    Finished,
    /// Stopped on request (Ctrl-C, SIGTERM) before T; also what a run's records say until the
    /// run ends, so that records of a run that never said how it ended never pass for whole.
    #[default]
    Interrupted,
    /// A non-finite or runaway value appeared.
    Unstable,
    /// An output written during the run (a field snapshot) failed.
    OutputFailed,
}

/// How a run that started ended. Every way but `Finished` keeps the records up to the last step
/// computed, so that the caller can write them and say where they went.
#[derive(Debug, Clone, PartialEq)]
pub enum RunEnded<O> {
    /// It reached T.
    Finished(O),
    /// A non-finite or runaway value appeared.
    Unstable {
        /// Step at which the guard fired [-].
        step: u64,
        /// Its time [s].
        time_s: f64,
        /// Where, in the model's words (node or grid point, position, value).
        location: String,
        /// The records up to there.
        partial: O,
    },
    /// Stopped on request (Ctrl-C, SIGTERM) before T.
    Interrupted {
        /// Last step computed [-].
        step: u64,
        /// Its time [s].
        time_s: f64,
        /// The records up to there.
        partial: O,
    },
    /// An output written while the run goes (the FE model's ParaView snapshots) could not be
    /// written: the run stopped at once.
    OutputFailed {
        /// Step of the output [-].
        step: u64,
        /// Its time [s].
        time_s: f64,
        /// What failed.
        message: String,
        /// The records up to there.
        partial: O,
    },
}

impl<O> RunEnded<O> {
    /// The status its files record.
    pub fn status(&self) -> Status {
        match self {
            RunEnded::Finished(_) => Status::Finished,
            RunEnded::Unstable { .. } => Status::Unstable,
            RunEnded::Interrupted { .. } => Status::Interrupted,
            RunEnded::OutputFailed { .. } => Status::OutputFailed,
        }
    }

    /// The records: complete when the run finished, up to where it stopped otherwise.
    pub fn output(&self) -> &O {
        match self {
            RunEnded::Finished(o) => o,
            RunEnded::Unstable { partial, .. }
            | RunEnded::Interrupted { partial, .. }
            | RunEnded::OutputFailed { partial, .. } => partial,
        }
    }

    /// The records, taken out ([`RunEnded::output`]).
    pub fn into_output(self) -> O {
        match self {
            RunEnded::Finished(o) => o,
            RunEnded::Unstable { partial, .. }
            | RunEnded::Interrupted { partial, .. }
            | RunEnded::OutputFailed { partial, .. } => partial,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::RunEnded;

    /// Every way a run ends hands back its records, whole or partial.
    #[test]
    fn every_ending_keeps_its_records() {
        let endings = [
            RunEnded::Finished(1),
            RunEnded::Unstable {
                step: 3,
                time_s: 1e-6,
                location: "node 4".into(),
                partial: 2,
            },
            RunEnded::Interrupted {
                step: 3,
                time_s: 1e-6,
                partial: 3,
            },
            RunEnded::OutputFailed {
                step: 3,
                time_s: 1e-6,
                message: "disk full".into(),
                partial: 4,
            },
        ];
        for (i, e) in endings.into_iter().enumerate() {
            assert_eq!(*e.output(), i + 1);
            assert_eq!(e.into_output(), i + 1);
        }
    }
}
