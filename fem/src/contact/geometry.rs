//! Node-to-segment projection, paper eq. (5), docs/fem-model.md §5 "Segment geometry" and §5.1 step 2;
//! pure (nalgebra only).

use nalgebra::Vector2;

/// Linear shape functions of a 2-node segment, (N₁, N₂) = ((1 − ξ)/2, (1 + ξ)/2) [-].
pub(crate) fn shape(xi: f64) -> (f64, f64) {
    (0.5 * (1.0 - xi), 0.5 * (1.0 + xi))
}

/// Point of the segment (x_j1, x_j2) at natural coordinate ξ: x_ρ = N₁ x_j1 + N₂ x_j2 [m].
pub(crate) fn point_at(x_j1: Vector2<f64>, x_j2: Vector2<f64>, xi: f64) -> Vector2<f64> {
    let (n1, n2) = shape(xi);
    x_j1 * n1 + x_j2 * n2
}

/// Frame of a master segment (j1, j2) in the current configuration.
///
/// Sign convention: j1 → j2 follows the counter-clockwise order of the segment's owner element,
/// so n_e = (t_y, −t_x) points out of the owner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SegmentFrame {
    /// Unit tangent t_e = (x_j2 − x_j1)/L_e [-].
    pub tangent: Vector2<f64>,
    /// Outward unit normal n_e = (t_y, −t_x) [-].
    pub normal: Vector2<f64>,
    /// Current length L_e [m].
    pub length: f64,
}

/// Frame of the segment from `x_j1` to `x_j2`; `None` for a degenerate (zero or non-finite length)
/// segment, which can then be neither a master nor contribute to a nodal area.
pub(crate) fn segment_frame(x_j1: Vector2<f64>, x_j2: Vector2<f64>) -> Option<SegmentFrame> {
    let d = x_j2 - x_j1;
    let length = d.norm();
    if length.is_nan() || length <= 0.0 || length.is_infinite() {
        return None;
    }
    let tangent = d / length;
    Some(SegmentFrame {
        tangent,
        normal: Vector2::new(tangent.y, -tangent.x),
        length,
    })
}

/// Orthogonal projection of a slave node onto a master segment.
///
/// Sign convention (paper eq. 5, docs/fem-model.md §5): g = (x_i − ρ)·n_e with n_e the outward normal of
/// the master's (counter-clockwise) owner element, so **g < 0 ⇔ the node penetrates the owner**
/// and g ≥ 0 means separated. The penetration stored by the contact state is p = −g.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Projection {
    /// Natural coordinate of the projection, unclamped: ξ = 2 (x_i − x_j1)·t_e / L_e − 1 [-].
    pub xi: f64,
    /// ξ_c = clamp(ξ, −1, 1) [-], where forces are applied and x_ρ is evaluated.
    pub xi_clamped: f64,
    /// Signed gap g = (x_i − x_j1)·n_e [m]; g < 0 ⇔ penetration.
    pub gap: f64,
    /// Segment frame (t_e, n_e, L_e).
    pub frame: SegmentFrame,
}

/// Projects `x_i` onto the segment (`x_j1`, `x_j2`), docs/fem-model.md §5.1 step 2; `None` for a
/// degenerate segment. (The search calls [`project_on_frame`] with frames computed once per step.)
#[cfg(test)]
pub(crate) fn project(x_i: Vector2<f64>, x_j1: Vector2<f64>, x_j2: Vector2<f64>) -> Option<Projection> {
    Some(project_on_frame(x_i, x_j1, &segment_frame(x_j1, x_j2)?))
}

/// Same as [`project`] with the segment's frame already computed (the search computes each
/// frame once per step, not once per candidate).
pub(crate) fn project_on_frame(x_i: Vector2<f64>, x_j1: Vector2<f64>, frame: &SegmentFrame) -> Projection {
    let r = x_i - x_j1;
    let xi = 2.0 * r.dot(&frame.tangent) / frame.length - 1.0;
    Projection {
        xi,
        xi_clamped: xi.clamp(-1.0, 1.0),
        gap: r.dot(&frame.normal),
        frame: *frame,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y)
    }

    #[test]
    fn gap_is_negative_inside_the_counter_clockwise_owner() {
        // Owner = unit square above y = 0, CCW, bottom edge (0,0)→(1,0): a node at y < 0 is outside (g > 0),
        // a node at y > 0 is inside the owner (penetration, g < 0).
        assert!(project(v(0.5, 0.1), v(0.0, 0.0), v(1.0, 0.0)).unwrap().gap < 0.0);
    }

    #[test]
    fn projection_coordinates_normal_and_clamping() {
        let p = project(v(0.75, -0.2), v(0.0, 0.0), v(1.0, 0.0)).unwrap();
        assert!((p.xi - 0.5).abs() < 1e-15);
        assert!((p.gap - 0.2).abs() < 1e-15);
        assert_eq!(p.frame.normal, v(0.0, -1.0));
        assert_eq!(p.frame.length, 1.0);
        let beyond = project(v(1.5, 0.0), v(0.0, 0.0), v(1.0, 0.0)).unwrap();
        assert!((beyond.xi - 2.0).abs() < 1e-15);
        assert_eq!(beyond.xi_clamped, 1.0);
    }

    #[test]
    fn rotated_segment_and_projection_point() {
        // Segment along +y: outward normal (1, 0).
        let p = project(v(-0.1, 2.0), v(0.0, 1.0), v(0.0, 3.0)).unwrap();
        assert_eq!(p.frame.normal, v(1.0, 0.0));
        assert!((p.gap + 0.1).abs() < 1e-15);
        assert!(p.xi.abs() < 1e-15);
        let rho = point_at(v(0.0, 1.0), v(0.0, 3.0), p.xi_clamped);
        assert!((rho - v(0.0, 2.0)).norm() < 1e-15);
        let (n1, n2) = shape(0.2);
        assert!((n1 + n2 - 1.0).abs() < 1e-15 && (n1 - 0.4).abs() < 1e-15);
    }

    #[test]
    fn degenerate_segment_has_no_projection() {
        assert!(project(v(0.0, 1.0), v(1.0, 1.0), v(1.0, 1.0)).is_none());
        assert!(segment_frame(v(0.0, 0.0), v(f64::NAN, 0.0)).is_none());
    }
}
