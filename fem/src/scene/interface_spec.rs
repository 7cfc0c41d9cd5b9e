//! `[fem]` keys that shape the interface row: the sinusoidal path of paper Section 4
//! (`interface_sine`), stretches with their own cohesive law (`interface_zones`) and which faces
//! join the contact detection surface (`contact_surface`, paper eqs. (10) and (16)).

use super::checks::{check, cohesive_law, inconsistent, option};
use super::raw::{RawFem, RawFriction, RawSine, RawZone};
use crate::error::SceneError;
use crate::law::cohesive::LinearCohesive;

/// Where contact friction acts on crack faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactFriction {
    /// On every face in contact, partially damaged cohesive facets included, on top of their
    /// cohesive shear (paper §2.3, Figure 4d; default).
    AllFaces,
    /// Only on faces whose facets have fully failed (damage 1) or are pre-crack, as the spectral
    /// model applies friction only where the interface has broken (paper §3.2).
    FailedOnly,
}

/// A stretch of the interface row with its own cohesive law (paper Section 4's weak interface).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfaceZone {
    /// Reference x range [m]; a facet belongs to the zone when its midpoint lies inside.
    pub x_range: [f64; 2],
    /// Cohesive law of the zone's facets.
    pub law: LinearCohesive,
}

/// Which faces form the contact detection surface Γ_det.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactSurface {
    /// Pre-crack faces and both faces of every inserted cohesive element (paper eq. 10; default).
    All,
    /// Only both faces of the inserted elements of `interface_zones` (paper eq. 16: Γ_weak⁺ ∪ Γ_weak⁻).
    Zones,
}

/// The sinusoidal path y = A sin(π (|x − x_c| − from)/half_period) for from ≤ |x − x_c| ≤ to,
/// 0 elsewhere, sampled at the node columns (the mapped row is exact at every node).
pub(crate) fn sine_polyline(f: &RawFem, s: &RawSine, center_x: f64) -> Result<Vec<[f64; 2]>, SceneError> {
    check(
        "fem.interface_sine.amplitude",
        s.amplitude,
        true,
        "a finite length [m]",
    )?;
    check(
        "fem.interface_sine.half_period",
        s.half_period,
        s.half_period > 0.0,
        "> 0 m",
    )?;
    check("fem.interface_sine.from", s.from, s.from >= 0.0, ">= 0 m")?;
    check("fem.interface_sine.to", s.to, s.to > s.from, "> from [m]")?;
    // the sine is cut where the grid ends: a `to` beyond both ends is not the path asked for
    let reach = (f.x_range[0] - center_x)
        .abs()
        .max((f.x_range[1] - center_x).abs());
    check(
        "fem.interface_sine.to",
        s.to,
        s.to <= reach * (1.0 + 1e-12),
        &format!("<= {reach} m, the farthest |x − x_c| of fem.x_range"),
    )?;
    if f.interface_polyline.is_some() {
        return Err(inconsistent(
            "fem.interface_sine",
            "give fem.interface_polyline or fem.interface_sine, not both",
        ));
    }
    let h = f.element_size;
    let n = ((f.x_range[1] - f.x_range[0]) / h).round() as usize;
    let path: Vec<[f64; 2]> = (0..=n)
        .map(|i| {
            let x = f.x_range[0] + i as f64 * h;
            let r = (x - center_x).abs();
            let y = if (s.from..=s.to).contains(&r) {
                s.amplitude * (std::f64::consts::PI * (r - s.from) / s.half_period).sin()
            } else {
                0.0
            };
            [x, y]
        })
        .collect();
    // sampled at the node columns only: an element size that is a multiple of the half-period,
    // from a `from` on a node, puts every node on a zero of the sine and the row stays flat
    let largest = path.iter().map(|p| p[1].abs()).fold(0.0, f64::max);
    if s.amplitude != 0.0 && largest <= 1e-9 * s.amplitude.abs() {
        return Err(inconsistent(
            "fem.interface_sine.half_period",
            format!(
                "every node column falls on a zero of the sine (half_period = {} m, fem.element_size \
                 = {h} m): the interface row would be flat (h is a multiple of the half-period); give a \
                 half-period of several elements",
                s.half_period
            ),
        ));
    }
    Ok(path)
}

fn zone(f: &RawFem, k: usize, z: &RawZone) -> Result<InterfaceZone, SceneError> {
    let key = |name: &str| format!("fem.interface_zones[{k}].{name}");
    let [x0, x1] = z.x_range;
    check(
        key("x_range"),
        x1 - x0,
        x0 >= f.x_range[0] && x1 <= f.x_range[1] && x1 > x0,
        "x_range[0] < x_range[1], inside fem.x_range [m]",
    )?;
    Ok(InterfaceZone {
        x_range: z.x_range,
        law: cohesive_law(
            &format!("fem.interface_zones[{k}]"),
            [z.sigma_c, z.delta_c, z.beta, z.kappa],
        )?,
    })
}

/// Where contact friction acts (`friction.contact_friction`, a key of the shared problem: the
/// spectral model reads it too).
pub(crate) fn contact_friction(f: Option<&RawFriction>) -> Result<ContactFriction, SceneError> {
    option(
        "friction.contact_friction",
        f.and_then(|f| f.contact_friction.as_ref()),
        ContactFriction::AllFaces,
        &[
            ("all_faces", ContactFriction::AllFaces),
            ("failed_only", ContactFriction::FailedOnly),
        ],
        "\"all_faces\" or \"failed_only\"",
    )
}

/// Validated zones (non-overlapping) and the contact surface choice.
pub(crate) fn zones_and_surface(f: &RawFem) -> Result<(Vec<InterfaceZone>, ContactSurface), SceneError> {
    let zones = f
        .interface_zones
        .iter()
        .flatten()
        .enumerate()
        .map(|(k, z)| zone(f, k, z))
        .collect::<Result<Vec<_>, _>>()?;
    for (k, a) in zones.iter().enumerate() {
        for b in &zones[k + 1..] {
            if a.x_range[0] < b.x_range[1] && b.x_range[0] < a.x_range[1] {
                return Err(inconsistent(
                    "fem.interface_zones",
                    format!("zones overlap: {:?} and {:?} m", a.x_range, b.x_range),
                ));
            }
        }
    }
    let surface = option(
        "fem.contact_surface",
        f.contact_surface.as_ref(),
        ContactSurface::All,
        &[("all", ContactSurface::All), ("zones", ContactSurface::Zones)],
        "\"all\" or \"zones\" (needs fem.interface_zones or fem.mesh.laws)",
    )?;
    let curve_laws = f
        .mesh
        .as_ref()
        .and_then(|m| m.laws.as_ref())
        .is_some_and(|l| !l.is_empty());
    if surface == ContactSurface::Zones && zones.is_empty() && !curve_laws {
        return Err(SceneError::BadOption {
            field: "fem.contact_surface".to_string(),
            value: "zones".to_string(),
            allowed: "\"zones\" only with fem.interface_zones or fem.mesh.laws",
        });
    }
    Ok((zones, surface))
}

/// Whether x [m] lies in [x₀, x₁], ends included up to 1e-12 m: a facet midpoint that falls on
/// a range end (2.5a = 312.5 mm is mid-element at h = 1 mm) is inside whatever its round-off.
pub(crate) fn in_range(x: f64, [x0, x1]: [f64; 2]) -> bool {
    const EPS: f64 = 1e-12;
    x >= x0 - EPS && x <= x1 + EPS
}

/// Each zone of `fem.interface_zones` must hold the centre of a cohesive facet (`centres`, in
/// interface coordinates [m]): a zone beyond the interface or inside the pre-crack would change
/// nothing, which the user cannot have meant.
pub(crate) fn zones_hold_facets(zones: &[InterfaceZone], centres: &[f64]) -> Result<(), SceneError> {
    for (k, z) in zones.iter().enumerate() {
        if !centres.iter().any(|&x| in_range(x, z.x_range)) {
            let (lo, hi) = centres
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            return Err(inconsistent(
                format!("fem.interface_zones[{k}].x_range"),
                format!(
                    "[{}, {}] m holds no cohesive facet (their centres lie in [{lo}, {hi}] m, in \
                     interface coordinates, outside the pre-crack): the zone would change nothing",
                    z.x_range[0], z.x_range[1]
                ),
            ));
        }
    }
    Ok(())
}

/// Index of the zone containing x [m] (1-based: 0 is the `[interface]` law).
pub(crate) fn zone_of(zones: &[InterfaceZone], x: f64) -> usize {
    zones
        .iter()
        .position(|z| in_range(x, z.x_range))
        .map_or(0, |k| k + 1)
}

#[cfg(test)]
mod tests {
    use crate::scene::{ContactSurface, Scene};

    fn sinusoid() -> String {
        crate::test_scenes::scene_text("sinusoidal-interface")
    }

    #[test]
    fn sinusoid_scene_maps_the_row_and_declares_two_weak_zones() {
        let s = Scene::from_toml_str(&sinusoid()).unwrap();
        let (a, lambda) = (0.125, 0.0625);
        for x in [0.140, 0.2, 0.3, -0.2, -0.140] {
            let y: f64 = 0.5 * lambda * (std::f64::consts::PI * (f64::abs(x) - a) / lambda).sin();
            assert!((s.fem.interface_y(x) - y).abs() < 1e-12, "x = {x}");
        }
        assert_eq!(s.fem.interface_y(0.32), 0.0);
        assert_eq!(s.fem.interface_y(0.1), 0.0);
        assert_eq!(s.fem.interface_zones.len(), 2);
        assert_eq!(s.fem.interface_zones[1].law.sigma_c, 0.04e6);
        assert_eq!(s.fem.contact_surface, ContactSurface::All);
        let zones = sinusoid().replace("contact_surface = \"all\"", "contact_surface = \"zones\"");
        assert_eq!(
            Scene::from_toml_str(&zones).unwrap().fem.contact_surface,
            ContactSurface::Zones
        );
        // steepest slope π/2 at |x| = a: altitude 1 mm / √(1 + π²/4) = 0.537 mm there; rows
        // compressed near the crests make the minimum a little smaller (0.51 mm)
        let alt = 1e-3 / (1.0 + 0.25 * std::f64::consts::PI.powi(2)).sqrt();
        let h_min = s.fem.min_edge();
        assert!(h_min <= alt && h_min > 0.9 * alt, "{h_min}");
    }

    #[test]
    fn bad_zones_and_surfaces_are_refused() {
        let overlap = sinusoid().replace("x_range = [0.125, 0.3125]", "x_range = [-0.2, 0.3125]");
        let e = Scene::from_toml_str(&overlap).unwrap_err().to_string();
        assert!(e.contains("overlap"), "{e}");
        let outside = sinusoid().replace("x_range = [0.125, 0.3125]", "x_range = [0.125, 0.5]");
        let e = Scene::from_toml_str(&outside).unwrap_err().to_string();
        assert!(e.contains("fem.interface_zones[1].x_range"), "{e}");
        let weak = sinusoid().replace("sigma_c = 0.04e6 ", "sigma_c = -1.0 ");
        let e = Scene::from_toml_str(&weak).unwrap_err().to_string();
        assert!(e.contains("fem.interface_zones[0].sigma_c"), "{e}");
        let no_zones: String = sinusoid()
            .replace("contact_surface = \"all\"", "contact_surface = \"zones\"")
            .split("[[fem.interface_zones]]")
            .next()
            .unwrap()
            .to_string();
        let e = Scene::from_toml_str(&no_zones).unwrap_err().to_string();
        assert!(e.contains("fem.contact_surface"), "{e}");
        let both = sinusoid().replace(
            "x_range = [-0.375, 0.375]",
            "interface_polyline = [[0.0, 0.0], [0.1, 0.0]]\nx_range = [-0.375, 0.375]",
        );
        let e = Scene::from_toml_str(&both).unwrap_err().to_string();
        assert!(e.contains("not both"), "{e}");
    }
}
