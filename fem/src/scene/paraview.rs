//! `[fem.paraview]`: field snapshots for ParaView (docs/outputs.md, "ParaView fields"). Nothing is
//! computed or written unless the table is declared.

use super::checks::{check, inconsistent};
use super::raw::RawFem;
use crate::error::SceneError;

/// Most files one run may write into `fields/` and beside it (the snapshots' `.vtu` files and
/// `fields.pvd`): a typo in `interval` must not flood a disk with tens of thousands of files.
pub const MAX_FIELD_FILES: u64 = 10_000;

/// Validated `[fem.paraview]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParaviewSpec {
    /// Simulated time between two snapshots [s], rounded to a whole number of time steps.
    pub interval: f64,
}

impl ParaviewSpec {
    /// Steps between two snapshots: `interval` / Δt rounded, at least 1 (Δt [s]).
    pub fn every(&self, dt: f64) -> u64 {
        ((self.interval / dt).round() as u64).max(1)
    }

    /// Snapshots of a run of `steps` steps of Δt [s]: t = 0, every [`Self::every`] steps, and the
    /// last step when it is not one of those.
    pub fn count(&self, dt: f64, steps: u64) -> u64 {
        let every = self.every(dt);
        steps / every + 1 + u64::from(!steps.is_multiple_of(every))
    }
}

/// Validates `[fem.paraview]` against the duration T [s] (`None`: not declared).
pub(crate) fn paraview(f: &RawFem, duration: f64) -> Result<Option<ParaviewSpec>, SceneError> {
    let Some(p) = f.paraview else { return Ok(None) };
    let Some(interval) = p.interval else {
        return Err(inconsistent(
            "fem.paraview.interval",
            "missing: give the simulated time between two snapshots [s]",
        ));
    };
    check(
        "fem.paraview.interval",
        interval,
        interval > 0.0 && interval <= duration,
        "(0, loading.duration] s",
    )?;
    Ok(Some(ParaviewSpec { interval }))
}

/// Refuses an interval that would write more than [`MAX_FIELD_FILES`] files: `pieces` files per
/// snapshot (the bulk, and the crack when there is an interface row) plus `fields.pvd`, over a run
/// of T [s] in steps of Δt [s].
pub(crate) fn file_count(spec: &ParaviewSpec, duration: f64, dt: f64, pieces: u64) -> Result<(), SceneError> {
    let steps = (duration / dt).ceil() as u64;
    let files = spec.count(dt, steps).saturating_mul(pieces).saturating_add(1);
    if files <= MAX_FIELD_FILES {
        return Ok(());
    }
    // `every` steps give ceil(steps/every) + 1 snapshots at most: the fewest steps between two
    // snapshots that keep within the limit, as an interval
    let most = (MAX_FIELD_FILES - 1) / pieces;
    let smallest = round_up(steps.div_ceil(most - 1) as f64 * dt);
    Err(SceneError::OutOfRange {
        field: "fem.paraview.interval".to_string(),
        value: spec.interval,
        allowed: format!(
            ">= {smallest:.2e} s: it would write {files} files ({pieces} per snapshot + fields.pvd), \
             more than {MAX_FIELD_FILES}"
        ),
    })
}

/// `x` > 0 rounded up to three significant digits (a value to quote that is still allowed).
fn round_up(x: f64) -> f64 {
    let scale = 10f64.powf(x.log10().floor() - 2.0);
    (x / scale).ceil() * scale
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn center_crack() -> String {
        crate::test_scenes::scene_text("center-crack")
    }

    fn with_paraview(interval: &str) -> String {
        format!("{}\n[fem.paraview]\ninterval = {interval}\n", center_crack())
    }

    #[test]
    fn off_by_absence_and_on_when_declared() {
        assert_eq!(Scene::from_toml_str(&center_crack()).unwrap().fem.paraview, None);
        let s = Scene::from_toml_str(&with_paraview("1e-3")).unwrap();
        assert_eq!(s.fem.paraview, Some(ParaviewSpec { interval: 1e-3 }));
    }

    #[test]
    fn the_schedule_counts_the_first_and_the_last_state() {
        let p = ParaviewSpec { interval: 1e-3 };
        assert_eq!(p.every(1e-4), 10);
        // steps 0, 10, ..., 100: 11 snapshots; 105 steps adds the last one
        assert_eq!(p.count(1e-4, 100), 11);
        assert_eq!(p.count(1e-4, 105), 12);
        // an interval below Δt snapshots every step
        assert_eq!(ParaviewSpec { interval: 1e-9 }.every(1e-4), 1);
    }

    #[test]
    fn bad_intervals_are_refused_with_the_key_and_its_line() {
        let good = with_paraview("1e-3");
        let line = good.lines().position(|l| l.starts_with("interval")).unwrap() + 1;
        for (bad, why) in [
            ("-1e-3", "(0, loading.duration]"),
            ("0.5", "(0, loading.duration]"),
            // T = 0.02 s in steps of about 1.3 µs: a snapshot every 2 steps, 2 files each
            ("2e-6", "more than 10000"),
        ] {
            let e = Scene::from_toml_str(&with_paraview(bad)).unwrap_err().to_string();
            let expect = format!(
                "line {line}: fem.paraview.interval = {}",
                crate::error::number(bad.parse::<f64>().unwrap())
            );
            assert!(e.contains(&expect) && e.contains(why), "{bad}: {e}");
        }
        // a misspelt key: reported as unknown, on its line, and the key it meant as missing
        let typo = good.replace("\ninterval =", "\nintervall =");
        let e = Scene::from_toml_str(&typo).unwrap_err().to_string();
        assert!(
            e.contains(&format!("line {line}: unknown key fem.paraview.intervall"))
                && e.contains("fem.paraview.interval: missing"),
            "{e}"
        );
    }

    #[test]
    fn the_file_limit_allows_the_interval_it_names() {
        let e = Scene::from_toml_str(&with_paraview("2e-6"))
            .unwrap_err()
            .to_string();
        let smallest = e.split(">= ").nth(1).and_then(|r| r.split(' ').next()).unwrap();
        let s = Scene::from_toml_str(&with_paraview(smallest)).unwrap();
        let p = s.fem.paraview.unwrap();
        let steps = (s.duration() / s.time_step()).ceil() as u64;
        // 2 files per snapshot (bulk and crack) + fields.pvd; one step fewer between snapshots
        // would be too many: the suggestion is the smallest allowed interval, to whole steps
        let dt = s.time_step();
        let files = |p: ParaviewSpec| 2 * p.count(dt, steps) + 1;
        assert!(files(p) <= MAX_FIELD_FILES, "{} files", files(p));
        let closer = ParaviewSpec {
            interval: (p.every(dt) - 1) as f64 * dt,
        };
        assert!(files(closer) > MAX_FIELD_FILES, "{} files", files(closer));
    }
}
