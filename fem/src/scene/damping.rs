//! The `[fem]` damping keys (paper §2, §3.1; docs/fem-model.md §6): which interface nodes have
//! their velocity scaled after every step, and by how much. The paper scales the velocities of
//! nodes in contact or on a cohesive element by 0.99 every step; that rate doubles each time the
//! step halves, so a rate can also be given as a decay time, the same in every mesh.

use super::checks::{check, inconsistent, option};
use super::raw::RawFem;
use crate::error::SceneError;

/// Which nodes are damped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DampingSet {
    /// No node (the default: measured stable in both validation cases, and the paper's rule
    /// removes 12–21 % of the centre crack's fracture energy; docs/results.md).
    None,
    /// Contact slaves only.
    ContactOnly,
    /// Nodes of cohesive elements for `window` seconds after their insertion.
    Inserted {
        /// How long after an insertion its nodes are damped [s].
        window: f64,
    },
    /// Contact slaves and nodes of cohesive elements for `window` seconds after insertion.
    ContactAndInserted {
        /// How long after an insertion its nodes are damped [s].
        window: f64,
    },
    /// Contact slaves and every node of any inserted cohesive element, for ever (paper §3.1).
    AllCohesive,
}

/// How strongly the damped nodes' velocities are scaled every step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DampingRate {
    /// v ← c v every step, whatever the step (paper: c = 0.99) [-].
    PerStep(f64),
    /// v ← exp(−Δt/τ) v every step: a decay time τ [s], independent of the mesh.
    DecayTime(f64),
}

/// The damping of a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damping {
    /// Which nodes.
    pub set: DampingSet,
    /// How strongly.
    pub rate: DampingRate,
}

impl Damping {
    /// Velocity factor c of one step Δt [s] [-].
    pub fn factor(&self, dt: f64) -> f64 {
        match (self.set, self.rate) {
            (DampingSet::None, _) => 1.0,
            (_, DampingRate::PerStep(c)) => c,
            (_, DampingRate::DecayTime(tau)) => (-dt / tau).exp(),
        }
    }

    /// The choice in words, as the run record states it.
    pub fn describe(&self) -> String {
        let set = match self.set {
            DampingSet::None => return "none".to_string(),
            DampingSet::ContactOnly => "contact_only".to_string(),
            DampingSet::Inserted { window } => format!("inserted for {window:e} s"),
            DampingSet::ContactAndInserted { window } => format!("contact_and_inserted for {window:e} s"),
            DampingSet::AllCohesive => "all_cohesive".to_string(),
        };
        match self.rate {
            DampingRate::PerStep(c) => format!("{set}, velocity x {c} per step"),
            DampingRate::DecayTime(tau) => format!("{set}, decay time {tau:e} s"),
        }
    }
}

/// Validates the damping keys.
pub(crate) fn damping(f: &RawFem) -> Result<Damping, SceneError> {
    #[derive(Clone, Copy)]
    enum Name {
        None,
        ContactOnly,
        Inserted,
        ContactAndInserted,
        AllCohesive,
    }
    let name = option(
        "fem.damping",
        f.damping.as_ref(),
        Name::None,
        &[
            ("none", Name::None),
            ("contact_only", Name::ContactOnly),
            ("inserted", Name::Inserted),
            ("contact_and_inserted", Name::ContactAndInserted),
            ("all_cohesive", Name::AllCohesive),
        ],
        "\"none\", \"contact_only\", \"inserted\", \"contact_and_inserted\" or \"all_cohesive\"",
    )?;
    let windowed = matches!(name, Name::Inserted | Name::ContactAndInserted);
    let window = match (f.damping_window, windowed) {
        (Some(w), true) => check("fem.damping_window", w, w > 0.0, "> 0 s")?,
        (None, true) => {
            return Err(inconsistent(
                "fem.damping",
                "\"inserted\" or \"contact_and_inserted\" needs fem.damping_window [s]",
            ));
        }
        (Some(_), false) => {
            return Err(inconsistent(
                "fem.damping_window",
                "applies only to fem.damping = \"inserted\" or \"contact_and_inserted\"",
            ));
        }
        (None, false) => 0.0,
    };
    if matches!(name, Name::None)
        && let Some(key) = [
            ("fem.damping_factor", f.damping_factor),
            ("fem.damping_time", f.damping_time),
        ]
        .into_iter()
        .find_map(|(k, v)| v.map(|_| k))
    {
        return Err(inconsistent(
            key,
            "applies only with fem.damping (\"contact_only\", \"inserted\", …); without it nothing is damped",
        ));
    }
    let rate = match (f.damping_factor, f.damping_time) {
        (Some(_), Some(_)) => {
            return Err(inconsistent(
                "fem.damping_time",
                "give fem.damping_factor [-] or fem.damping_time [s], not both",
            ));
        }
        (_, Some(tau)) => DampingRate::DecayTime(check("fem.damping_time", tau, tau > 0.0, "> 0 s")?),
        (c, None) => {
            let c = c.unwrap_or(0.99);
            DampingRate::PerStep(check("fem.damping_factor", c, c > 0.0 && c <= 1.0, "(0, 1]")?)
        }
    };
    let set = match name {
        Name::None => DampingSet::None,
        Name::ContactOnly => DampingSet::ContactOnly,
        Name::Inserted => DampingSet::Inserted { window },
        Name::ContactAndInserted => DampingSet::ContactAndInserted { window },
        Name::AllCohesive => DampingSet::AllCohesive,
    };
    Ok(Damping { set, rate })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    /// The centre-crack scene with its `damping = ...` line replaced by `keys`.
    fn with(keys: &str) -> Result<Scene, SceneError> {
        let scene = crate::test_scenes::scene_text("center-crack");
        let text: Vec<&str> = scene
            .lines()
            .map(|l| if l.starts_with("damping = ") { keys } else { l })
            .collect::<Vec<_>>();
        Scene::from_toml_str(&text.join("\n"))
    }

    #[test]
    fn a_decay_time_is_the_same_damping_at_every_step() {
        let s = with("damping = \"inserted\"\ndamping_window = 2e-5\ndamping_time = 1.5e-4").unwrap();
        let d = s.fem.damping;
        assert_eq!(d.set, DampingSet::Inserted { window: 2e-5 });
        // two half steps damp exactly as much as one full step
        let (dt, c) = (1e-6, d.factor(1e-6));
        assert!(
            (d.factor(0.5 * dt).powi(2) - c).abs() < 1e-15 && (c - (-dt / 1.5e-4f64).exp()).abs() < 1e-15
        );
        assert_eq!(with("damping = \"none\"").unwrap().fem.damping.factor(1e-6), 1.0);
        assert_eq!(
            with("").unwrap().fem.damping.factor(1e-6),
            1.0,
            "no damping by default"
        );
        let paper = with("damping = \"all_cohesive\"").unwrap().fem.damping;
        assert_eq!(
            (paper.set, paper.factor(1e-6)),
            (DampingSet::AllCohesive, 0.99),
            "the paper's rule"
        );
    }

    #[test]
    fn inconsistent_damping_keys_are_refused() {
        for (keys, key) in [
            ("damping = \"inserted\"", "fem.damping_window"),
            (
                "damping = \"contact_only\"\ndamping_window = 1e-5",
                "fem.damping_window",
            ),
            (
                "damping = \"all_cohesive\"\ndamping_factor = 0.9\ndamping_time = 1e-4",
                "fem.damping_time",
            ),
            // a rate without damping would damp nothing
            ("damping_factor = 0.9", "fem.damping_factor"),
            ("damping = \"none\"\ndamping_time = 1e-4", "fem.damping_time"),
            ("damping_time = -1.0", "fem.damping_time"),
            ("damping = \"sometimes\"", "fem.damping"),
        ] {
            let e = with(keys).unwrap_err().to_string();
            assert!(e.contains(key), "{keys}: {e}");
        }
    }
}
