//! Crack-tip and cohesive-zone-tip tracking along the interface row (docs/fem-model.md §8.1,
//! docs/solver-api.md), damage records, and arrival times per Gauss point.

use crate::mesh::interfaces::{FacetKind, InterfaceRow};
use crate::model::cohesive::facet_gauss;
use crate::model::state::{Model, State};
use crate::records::{ArrivalRecord, CrackRecord, CrackTipRecord, InterfaceRecord, TipRecord};

/// Interface coordinate of Gauss point q of facet c [m] (x on the built-in grids).
fn gauss_x(model: &Model, c: usize, q: usize) -> f64 {
    let row = model
        .interface
        .row
        .as_ref()
        .expect("invariant: facets exist only with an interface row");
    let [xa, xb] = row.facet_span(c);
    let (_, n1, n2) = facet_gauss()[q];
    n1 * xa + n2 * xb
}

/// Walks the Gauss points in `order` from the pre-crack tip `start`: the crack tip is the last of
/// the contiguous fully broken points, the cohesive-zone tip the last of the following damaged ones.
/// The walk stays on its chain: it stops where the next facet does not touch the previous one.
fn walk(model: &Model, state: &State, order: impl Iterator<Item = (usize, usize)>, start: f64) -> (f64, f64) {
    let (mut tip, mut cz, mut broken_run) = (start, start, true);
    let row = model.interface.row.as_ref().expect("invariant: interface row");
    let mut prev: Option<usize> = None;
    for (c, q) in order {
        let joined = |p: usize| p == c || row.continues(p, c) || row.continues(c, p);
        if row.kind[c] != FacetKind::Cohesive || !prev.is_none_or(joined) {
            break;
        }
        prev = Some(c);
        let f = &state.facets;
        let d = if f.inserted[c] { f.gauss[c][q].damage } else { 0.0 };
        if broken_run && d >= 1.0 {
            tip = gauss_x(model, c, q);
            cz = tip;
        } else if d > 0.0 {
            broken_run = false;
            cz = gauss_x(model, c, q);
        } else {
            break;
        }
    }
    (tip, cz)
}

/// Tip record at the current state; `None` without a pre-crack (no tips to speak of).
pub(crate) fn tips(model: &Model, state: &State) -> Option<TipRecord> {
    let t = state.t;
    let (xc, a) = model.observed.crack?;
    let row = model
        .interface
        .row
        .as_ref()
        .expect("invariant: a pre-crack lies on the interface row");
    let nf = row.num_facets();
    // the tips are those of the chain that holds the pre-crack (its first facet's chain)
    let chain_of = |c: usize| row.chain[row.facet_columns(c)[0]];
    let crack_chain = (0..nf)
        .find(|&c| row.kind[c] == FacetKind::PreCrack)
        .map(chain_of);
    let on_chain =
        |c: usize| crack_chain.is_none_or(|k| chain_of(c) == k) && row.kind[c] != FacetKind::PreCrack;
    let first_right = (0..nf).find(|&c| on_chain(c) && gauss_x(model, c, 0) > xc);
    let last_left = (0..nf).rev().find(|&c| on_chain(c) && gauss_x(model, c, 1) < xc);
    let right = first_right.map_or((xc + a, xc + a), |c0| {
        walk(model, state, (c0..nf).flat_map(|c| [(c, 0), (c, 1)]), xc + a)
    });
    let left = last_left.map_or((xc - a, xc - a), |c0| {
        walk(
            model,
            state,
            (0..=c0).rev().flat_map(|c| [(c, 1), (c, 0)]),
            xc - a,
        )
    });
    Some(TipRecord {
        t,
        tip_right: right.0,
        tip_left: left.0,
        cz_tip_right: right.1,
        cz_tip_left: left.1,
    })
}

/// The cracked extent of every chain: one record per chain, in chain order. Each Gauss point of
/// a cohesive facet stands for half the facet's length (the 2-point Gauss weights).
pub(crate) fn crack_records(model: &Model, state: &State, out: &mut Vec<CrackRecord>) {
    let Some(row) = &model.interface.row else { return };
    let first = out.len();
    out.extend((0..row.num_chains()).map(|k| CrackRecord {
        t: state.t,
        chain: k as u16,
        cohesive_length: 0.0,
        broken_length: 0.0,
        process_zone_length: 0.0,
        broken_from: f64::NAN,
        broken_to: f64::NAN,
    }));
    for c in 0..row.num_facets() {
        if row.kind[c] != FacetKind::Cohesive {
            continue;
        }
        let r = &mut out[first + row.chain[row.facet_columns(c)[0]] as usize];
        let half = 0.5 * row.length[c];
        r.cohesive_length += 2.0 * half;
        if !state.facets.inserted[c] {
            continue;
        }
        for q in 0..2 {
            let d = state.facets.gauss[c][q].damage;
            if d >= 1.0 {
                r.broken_length += half;
                let x = gauss_x(model, c, q);
                r.broken_from = r.broken_from.min(x);
                r.broken_to = r.broken_to.max(x);
            } else if d > 0.0 {
                r.process_zone_length += half;
            }
        }
    }
}

/// A point of a chain as the crack records see it: its coordinate [m], and whether it is broken
/// (a pre-crack facet's end, or a Gauss point with d = 1) or damaged (d > 0, broken included).
#[derive(Clone, Copy)]
struct ChainPoint {
    x: f64,
    broken: bool,
    damaged: bool,
}

/// The points of facets `facets` (one chain, in its order): a pre-crack facet by its two ends,
/// a cohesive facet by its two Gauss points, a plain facet by one undamaged point.
fn chain_points(model: &Model, state: &State, facets: std::ops::Range<usize>, out: &mut Vec<ChainPoint>) {
    let row = model.interface.row.as_ref().expect("invariant: interface row");
    out.clear();
    for c in facets {
        match row.kind[c] {
            FacetKind::PreCrack => out.extend(row.facet_span(c).map(|x| ChainPoint {
                x,
                broken: true,
                damaged: true,
            })),
            FacetKind::Cohesive => out.extend((0..2).map(|q| {
                let d = if state.facets.inserted[c] {
                    state.facets.gauss[c][q].damage
                } else {
                    0.0
                };
                ChainPoint {
                    x: gauss_x(model, c, q),
                    broken: d >= 1.0,
                    damaged: d > 0.0,
                }
            })),
            FacetKind::Plain => out.push(ChainPoint {
                x: gauss_x(model, c, 0),
                broken: false,
                damaged: false,
            }),
        }
    }
}

/// Every crack of every chain. A crack is a stretch of consecutive broken points (its ends are
/// its crack tips); its cohesive-zone tips are the ends of the run of consecutive damaged points
/// that holds it, so that two cracks joined by a damaged ligament share them. A damaged run with
/// no broken point is a process zone (NaN tips). These are the definitions of [`tips`], which
/// follows the pre-crack's crack only. A closed chain's run across its first node is one run.
pub(crate) fn crack_tip_records(model: &Model, state: &State, out: &mut Vec<CrackTipRecord>) {
    let Some(row) = &model.interface.row else { return };
    let nf = row.num_facets();
    let chain_of = |c: usize| row.chain[row.facet_columns(c)[0]];
    let mut points = Vec::new();
    let mut first = 0;
    while first < nf {
        let chain = chain_of(first);
        let end = (first..nf).find(|&c| chain_of(c) != chain).unwrap_or(nf);
        chain_points(model, state, first..end, &mut points);
        // a closed chain's last facet continues into its first: start after an undamaged point
        // (or, all damaged, after an unbroken one) so that no run or crack is cut at the chain's
        // first node
        if row.continues(end - 1, first) {
            let undamaged = points.iter().rposition(|p| !p.damaged);
            if let Some(i) = undamaged.or_else(|| points.iter().rposition(|p| !p.broken)) {
                points.rotate_left(i + 1);
            }
        }
        let mut crack = 0u16;
        let mut i = 0;
        while i < points.len() {
            if !points[i].damaged {
                i += 1;
                continue;
            }
            let j = (i..points.len())
                .find(|&j| !points[j].damaged)
                .unwrap_or(points.len());
            let run = &points[i..j];
            let (cz_start, cz_end) = (run[0].x, run[run.len() - 1].x);
            let mut record = |tip_start: f64, tip_end: f64| {
                out.push(CrackTipRecord {
                    t: state.t,
                    chain,
                    crack,
                    tip_start,
                    tip_end,
                    cz_start,
                    cz_end,
                });
                crack += 1;
            };
            // each stretch of consecutive broken points is a crack; without one, a process zone
            let mut k = 0;
            let mut cracks = 0;
            while k < run.len() {
                if !run[k].broken {
                    k += 1;
                    continue;
                }
                let l = (k..run.len()).find(|&l| !run[l].broken).unwrap_or(run.len());
                record(run[k].x, run[l - 1].x);
                cracks += 1;
                k = l;
            }
            if cracks == 0 {
                record(f64::NAN, f64::NAN);
            }
            i = j;
        }
        first = end;
    }
}

/// The chain of facet c for the records: `None` on a row of one chain (no `chain` column).
fn chain_label(row: &InterfaceRow, c: usize) -> Option<u16> {
    (row.num_chains() > 1).then(|| row.chain[row.facet_columns(c)[0]])
}

/// Damage per cohesive Gauss point.
pub(crate) fn interface_records(model: &Model, state: &State, out: &mut Vec<InterfaceRecord>) {
    let Some(row) = &model.interface.row else { return };
    for c in 0..row.num_facets() {
        if row.kind[c] != FacetKind::Cohesive {
            continue;
        }
        let inserted = state.facets.inserted[c];
        for q in 0..2 {
            let damage = if inserted {
                state.facets.gauss[c][q].damage
            } else {
                0.0
            };
            out.push(InterfaceRecord {
                t: state.t,
                x: gauss_x(model, c, q),
                damage,
                inserted,
                chain: chain_label(row, c),
            });
        }
    }
}

/// Insertion and failure times per cohesive Gauss point.
pub(crate) fn arrivals(model: &Model, state: &State) -> Vec<ArrivalRecord> {
    let Some(row) = &model.interface.row else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for c in 0..row.num_facets() {
        if row.kind[c] != FacetKind::Cohesive {
            continue;
        }
        for q in 0..2 {
            out.push(ArrivalRecord {
                x: gauss_x(model, c, q),
                insertion_time: state.facets.insert_time[c],
                failure_time: state.facets.fail_time[c][q],
                work_density: state.facets.work_density[c][q],
                chain: chain_label(row, c),
            });
        }
    }
    out
}
