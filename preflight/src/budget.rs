//! Memory and step budgets. A model estimates, from its validated scene and before allocating
//! anything, how many time steps its run takes and how many bytes it holds (state, history,
//! recorded output); a run beyond the budget is refused with the estimate and the key that
//! governs the largest part, unless its user raises the budget explicitly.

/// Memory a run may plan for unless told otherwise: 8 GiB [B].
pub const DEFAULT_MAX_BYTES: u64 = 8 << 30;
/// Time steps a run may plan for unless told otherwise [-].
pub const DEFAULT_MAX_STEPS: u64 = 100_000_000;

/// One part of a run's memory.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// What it holds, in words ("recorded interface rows").
    pub what: String,
    /// Estimated size [B].
    pub bytes: u64,
    /// The scene key that scales it, as its user would change it (`fem.output_interval`).
    pub key: &'static str,
}

/// What a run will cost, estimated before it allocates.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// Time steps from t = 0 to T [-].
    pub steps: u64,
    /// The keys that set the number of steps, as advice (`loading.duration, fem.element_size`).
    pub steps_keys: &'static str,
    /// Expected wall time on the 2-core machine the constants were measured on [s].
    pub seconds: f64,
    /// The parts of its memory.
    pub parts: Vec<Part>,
}

impl Estimate {
    /// Total estimated memory [B].
    pub fn bytes(&self) -> u64 {
        self.parts.iter().fold(0u64, |s, p| s.saturating_add(p.bytes))
    }

    /// "13087 steps, about 62.5 MiB of memory, about 17 s on 2 cores" — what a command prints
    /// before it starts.
    pub fn summary(&self) -> String {
        format!(
            "{} steps, about {} of memory, about {} on 2 cores",
            self.steps,
            human(self.bytes()),
            duration(self.seconds)
        )
    }

    fn largest(&self) -> Option<&Part> {
        self.parts.iter().max_by_key(|p| p.bytes)
    }
}

/// The most a run may cost. `Budget::default()` is 8 GiB and 10⁸ steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budget {
    /// Memory [B].
    pub max_bytes: u64,
    /// Time steps [-].
    pub max_steps: u64,
}

impl Default for Budget {
    fn default() -> Budget {
        Budget {
            max_bytes: DEFAULT_MAX_BYTES,
            max_steps: DEFAULT_MAX_STEPS,
        }
    }
}

impl Budget {
    /// A budget of `max_memory_gib` GiB and `max_steps` steps (command-line values).
    pub fn new(max_memory_gib: f64, max_steps: u64) -> Budget {
        Budget {
            max_bytes: (max_memory_gib * (1u64 << 30) as f64) as u64,
            max_steps,
        }
    }

    /// `Ok` if the estimate fits; otherwise what it costs, the key to change and the flag that
    /// allows more (`--max-memory GIB`, `--max-steps N`).
    pub fn check(&self, e: &Estimate) -> Result<(), String> {
        if e.steps > self.max_steps {
            return Err(format!(
                "the run needs {} time steps, above the budget of {}: change {} or allow more with \
                 --max-steps {}",
                e.steps, self.max_steps, e.steps_keys, e.steps
            ));
        }
        let bytes = e.bytes();
        if bytes > self.max_bytes {
            let parts: Vec<String> = e
                .parts
                .iter()
                .map(|p| format!("{} {}", p.what, human(p.bytes)))
                .collect();
            let key = e.largest().map_or("the resolution", |p| p.key);
            let gib = (bytes as f64 / (1u64 << 30) as f64).ceil();
            return Err(format!(
                "the run needs an estimated {} of memory ({}), above the budget of {}: change {key}, \
                 which scales the largest part, or allow more with --max-memory {gib}",
                human(bytes),
                parts.join(", "),
                human(self.max_bytes)
            ));
        }
        Ok(())
    }
}

/// Bytes in binary units, 3 significant figures ("1.25 GiB", "606 KiB", "8 GiB").
pub fn human(bytes: u64) -> String {
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut v = bytes as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        return format!("{bytes} B");
    }
    // three significant figures, trailing zeros dropped
    let digits = if v >= 100.0 {
        0
    } else if v >= 10.0 {
        1
    } else {
        2
    };
    let number = format!("{v:.digits$}");
    let number = if number.contains('.') {
        number.trim_end_matches('0').trim_end_matches('.')
    } else {
        &number
    };
    format!("{number} {}", UNITS[u])
}

/// Seconds in words, 2 significant figures ("17 s", "4.2 min", "3.1 h").
pub fn duration(seconds: f64) -> String {
    if !seconds.is_finite() {
        "forever".to_string()
    } else if seconds < 90.0 {
        format!("{seconds:.0} s")
    } else if seconds < 5400.0 {
        format!("{:.1} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}

/// `count × size` in bytes for counts computed in floating point, saturating instead of
/// overflowing (an absurd scene must give a huge estimate, not a wrapped small one).
pub fn bytes_of(count: f64, size: usize) -> u64 {
    let b = count.max(0.0) * size as f64;
    if b.is_finite() { b as u64 } else { u64::MAX }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn estimate(steps: u64, bytes: [u64; 2]) -> Estimate {
        Estimate {
            steps,
            steps_keys: "loading.duration",
            seconds: 1.0,
            parts: vec![
                Part {
                    what: "state".into(),
                    bytes: bytes[0],
                    key: "fem.element_size",
                },
                Part {
                    what: "recorded rows".into(),
                    bytes: bytes[1],
                    key: "fem.output_interval",
                },
            ],
        }
    }

    #[test]
    fn the_largest_part_names_the_key_to_change() {
        let b = Budget::default();
        assert!(b.check(&estimate(1000, [1 << 20, 1 << 30])).is_ok());
        let e = b.check(&estimate(1000, [1 << 20, 64 << 30])).unwrap_err();
        assert!(
            e.contains("fem.output_interval") && e.contains("--max-memory 65"),
            "{e}"
        );
        let e = b.check(&estimate(2_000_000_000, [1, 1])).unwrap_err();
        assert!(e.contains("loading.duration") && e.contains("--max-steps"), "{e}");
        assert!(
            Budget::new(100.0, u64::MAX)
                .check(&estimate(1000, [1 << 20, 64 << 30]))
                .is_ok()
        );
    }

    #[test]
    fn sizes_read_as_written() {
        assert_eq!(human(512), "512 B");
        assert_eq!(human(8 << 30), "8 GiB");
        assert_eq!(human(1536 << 20), "1.5 GiB");
        assert_eq!(human(620_521), "606 KiB");
        assert_eq!(human(84_634_000), "80.7 MiB");
        assert_eq!(bytes_of(f64::INFINITY, 8), u64::MAX);
        assert_eq!(bytes_of(1e30, 8), u64::MAX);
        assert_eq!(duration(17.2), "17 s");
        assert_eq!(duration(252.0), "4.2 min");
        assert_eq!(duration(11_160.0), "3.1 h");
    }
}
