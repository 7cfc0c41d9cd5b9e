//! Contact search, docs/fem-model.md §5.1: a uniform bucket grid of master segments rebuilt every step in
//! O(|Γ_det|) into preallocated flat arrays (counting sort), and the narrow phase with the
//! paper's exclusion rules and the smallest-|g| choice (docs/fem-model.md §10.8).

use nalgebra::Vector2;
use rayon::prelude::*;

use super::geometry::{Projection, SegmentFrame, project_on_frame};

/// A slave and a master face each other when their normals are within 60° of opposite,
/// n_i·n_e < −cos 60° (the paper's rule is n_i·n_e < 0, within 90°). The faces of one interface
/// start opposite (n_i·n_e = −1) and turn by the bulk's rotations only; the 90° margin of the
/// paper's rule lets a node beside a right-angled kink of a Gmsh interface pair with the other
/// leg's face, onto whose end it projects (ξ = −1) at a penetration of its whole distance to the
/// corner (at a junction's 90° corners too): the contact then pushes it out with a spurious force
/// (docs/fem-model.md §5.1).
const FACING_COS: f64 = 0.5;

/// Upper bound of grid cells per segment capacity: the cell size is enlarged until the grid fits.
const CELLS_PER_SEGMENT: usize = 4;

/// Uniform grid of square cells; each segment is registered in every cell overlapped by its
/// bounding box inflated by the search margin, so a slave only queries its own cell.
///
/// Storage is a counting sort into flat arrays (`cell_start`, `entries`) sized once from the
/// segment capacity: rebuilding never allocates.
#[derive(Debug, Clone)]
pub(crate) struct BucketGrid {
    /// Lower-left corner of cell (0, 0) [m].
    origin: Vector2<f64>,
    /// Cell edge length [m].
    cell_size: f64,
    /// 1 / cell edge length [1/m] (multiplications instead of divisions in the hot loops).
    inv_cell_size: f64,
    /// Number of cells along x and y [-].
    nx: usize,
    ny: usize,
    /// Start of each cell's entries in `entries`; length `max_cells + 1`.
    cell_start: Vec<u32>,
    /// Segment indices, grouped by cell.
    entries: Vec<u32>,
    /// Number of valid entries.
    num_entries: usize,
    /// Cell budget: `cell_start.len() − 1`.
    max_cells: usize,
    /// Cells overlapped by each segment's inflated box, (i0, j0, i1, j1), of the last rebuild.
    ranges: Vec<[u32; 4]>,
    /// Skin s [m] the last rebuild added to the margin ([`BucketGrid::update`]; 0 after
    /// [`BucketGrid::rebuild`]).
    skin: f64,
    /// Positions [m] of the nodes of Γ_det at the last rebuild by `update`, in the order of its
    /// node list (empty after `rebuild`: the next `update` rebuilds).
    anchor: Vec<Vector2<f64>>,
    /// Number of segments at the last rebuild.
    built_segments: usize,
    /// Margin [m] the boxes of the last rebuild were inflated by: m + 2 s.
    margin: f64,
    /// Start of each node's candidates in `listed`, in the order of the node list of the last
    /// rebuild by `update`; length nodes + 1 (empty after `rebuild`).
    list_start: Vec<u32>,
    /// Per node, the segments whose box at the rebuild, inflated by m + 2 s, held the node (a
    /// Verlet list: [`BucketGrid::update`]).
    listed: Vec<u32>,
    /// Steps the grid has been kept since its rebuild.
    kept: usize,
}

/// Skin of a kept grid, as a fraction of the search margin m [-]: the boxes grow by 2 s = 0.2 × m,
/// and the grid is kept until a node of Γ_det has moved 0.9 s (about 0.1 h at the default
/// d_max = h).
const SKIN: f64 = 0.1;

/// When the nodes get their lists [-]. Building them costs about one narrow phase and saves a
/// part of each later one, so a grid rebuilt because Γ_det grew (by a facet every few steps behind
/// a running crack) goes without them, one rebuilt because a node outran the skin gets them, and
/// one kept this many steps without them is rebuilt once more, with them.
const LIST_AFTER: usize = 32;

/// Candidates a node's list is given room for at construction [-]: on an interface a node's box of
/// half-width m + 2 s ≈ 1.2 h meets about three segments of each face; a list that outgrows this
/// grows once.
const LISTED_PER_NODE: usize = 12;

/// Bounding box of one segment, inflated by the search margin [m].
fn inflated_box(a: Vector2<f64>, b: Vector2<f64>, margin: f64) -> (Vector2<f64>, Vector2<f64>) {
    let m = Vector2::repeat(margin);
    (a.inf(&b) - m, a.sup(&b) + m)
}

impl BucketGrid {
    /// Grid with storage for `max_segments` segments (4 entries each: a segment's inflated box is
    /// never wider than a cell, so it overlaps at most 2 × 2 cells).
    pub(crate) fn with_capacity(max_segments: usize) -> Self {
        let max_cells = CELLS_PER_SEGMENT * max_segments.max(1);
        Self {
            origin: Vector2::zeros(),
            cell_size: 1.0,
            inv_cell_size: 1.0,
            nx: 0,
            ny: 0,
            cell_start: vec![0; max_cells + 1],
            entries: vec![0; 4 * max_segments.max(1)],
            num_entries: 0,
            max_cells,
            ranges: Vec::with_capacity(max_segments),
            skin: 0.0,
            anchor: Vec::with_capacity(2 * max_segments.max(1)),
            built_segments: usize::MAX,
            margin: 0.0,
            kept: 0,
            list_start: Vec::with_capacity(2 * max_segments.max(1) + 1),
            listed: Vec::with_capacity(LISTED_PER_NODE * 2 * max_segments.max(1)),
        }
    }

    /// The grid for `segments` at positions `x`, whose nodes are `nodes` (each once), and each
    /// node's list of candidates ([`BucketGrid::candidates_of`]): the grid and lists of an earlier step
    /// are kept while they still hold every candidate the narrow phase can accept, else they are
    /// rebuilt with a skin s = 0.1 × m (a Verlet skin): the boxes are inflated by m + 2 s, and a
    /// node's list holds the segments whose box holds the node. Returns whether they were rebuilt.
    ///
    /// Kept lists are exact: every node of Γ_det has moved by at most d (in each coordinate)
    /// since the rebuild, so a segment's box inflated by the current margin lies inside its box
    /// at the rebuild inflated by m + d + √2 ε_ext d (the ends move by d, the length by at most
    /// 2√2 d), that is within m + s while d (1 + 1.5 ε_ext) ≤ s; a slave inside the current box
    /// was, at the rebuild, within d of it, so inside the box inflated by m + 2 s, and its list
    /// holds the segment. The narrow phase then finds the same closest master as from a fresh
    /// grid: the candidates it rejects only add work. (Whether a slave counts as lost to the
    /// detection distance depends on which cells list a master deeper than d_max, outside the
    /// box: a kept grid may count such a slave where a fresh one would not. It never changes a
    /// force; a slave whose list gives no master therefore reads its cell, which reaches a cell
    /// width, about 3 h, around it.) They are rebuilt once d reaches 0.9 s (floating-point
    /// slack), when segments were added, or when a position is not finite.
    pub(crate) fn update(
        &mut self,
        segments: &[[u32; 2]],
        nodes: &[u32],
        x: &[Vector2<f64>],
        max_gap: f64,
        projection_tolerance: f64,
    ) -> bool {
        let comparable =
            self.nx > 0 && segments.len() == self.built_segments && nodes.len() == self.anchor.len();
        // lists when the nodes outran the skin or the grid lasted, not when Γ_det grew
        let mut outran = false;
        if comparable {
            // the largest move, exact in any order (a NaN counts as infinite)
            let moved = nodes
                .par_iter()
                .zip(self.anchor.par_iter())
                .with_min_len(1024)
                .map(|(&i, a)| {
                    let d = x[i as usize] - a;
                    let m = d.x.abs().max(d.y.abs());
                    if m.is_nan() { f64::INFINITY } else { m }
                })
                .reduce(|| 0.0, f64::max);
            if moved * (1.0 + 1.5 * projection_tolerance) <= 0.9 * self.skin {
                self.kept += 1;
                // a grid that lasts is rebuilt once more, with the lists
                if self.kept < LIST_AFTER || !self.list_start.is_empty() {
                    return false;
                }
            } else {
                outran = true;
            }
        }
        let lists = outran || self.kept >= LIST_AFTER;
        self.kept = 0;
        self.build(segments, x, max_gap, projection_tolerance, SKIN);
        self.anchor.clear(); // keeps the capacity
        self.anchor.extend(nodes.iter().map(|&i| x[i as usize]));
        self.built_segments = segments.len();
        if lists {
            self.list(segments, nodes, x);
        } else {
            self.list_start.clear();
            self.listed.clear();
        }
        true
    }

    /// Each node's candidates: the segments of its cell whose box, inflated by the margin of the
    /// rebuild, holds the node, in increasing index (the cell's order).
    fn list(&mut self, segments: &[[u32; 2]], nodes: &[u32], x: &[Vector2<f64>]) {
        let (mut start, mut listed) = (
            std::mem::take(&mut self.list_start),
            std::mem::take(&mut self.listed),
        );
        start.clear();
        listed.clear();
        start.push(0);
        for &i in nodes {
            let p = x[i as usize];
            for &e in self.candidates(p) {
                let [a, b] = segments[e as usize];
                if a == i || b == i {
                    continue; // attached to the node: never its master
                }
                let (lo, hi) = inflated_box(x[a as usize], x[b as usize], self.margin);
                if lo.x <= p.x && p.x <= hi.x && lo.y <= p.y && p.y <= hi.y {
                    listed.push(e);
                }
            }
            start.push(listed.len() as u32);
        }
        (self.list_start, self.listed) = (start, listed);
    }

    /// The candidates of the k-th node of the node list given to the last [`BucketGrid::update`],
    /// at `p`: its list, or without lists the segments of its cell. Whether they came from a list.
    #[inline]
    pub(crate) fn candidates_of(&self, k: usize, p: Vector2<f64>) -> (&[u32], bool) {
        match self.list_start.get(k + 1) {
            Some(&end) => (&self.listed[self.list_start[k] as usize..end as usize], true),
            None => (self.candidates(p), false),
        }
    }

    /// Rebuilds the grid for `segments` at positions `x`, without skin. `max_gap` is d_max [m];
    /// `projection_tolerance` is ε_ext [-]: the margin m = d_max + ε_ext L_max / 2 covers every
    /// node that can pass the narrow phase. Cell size c ≥ L_max + 2m (≥ L_max + d_max, §5.1).
    #[cfg(test)]
    pub(crate) fn rebuild(
        &mut self,
        segments: &[[u32; 2]],
        x: &[Vector2<f64>],
        max_gap: f64,
        projection_tolerance: f64,
    ) {
        self.build(segments, x, max_gap, projection_tolerance, 0.0);
        self.anchor.clear();
        self.kept = 0;
        self.list_start.clear();
        self.listed.clear();
        self.built_segments = usize::MAX;
    }

    /// The rebuild, with the margin m (1 + 2 `skin`) [m].
    fn build(
        &mut self,
        segments: &[[u32; 2]],
        x: &[Vector2<f64>],
        max_gap: f64,
        projection_tolerance: f64,
        skin: f64,
    ) {
        self.num_entries = 0;
        self.nx = 0;
        self.ny = 0;
        self.margin = 0.0;
        if segments.is_empty() {
            return;
        }
        if segments.len() * 4 > self.entries.len() {
            // Only when more segments were added than `DetectionSurface::with_capacity` promised:
            // grow (allocates once) rather than miss contacts.
            self.max_cells = CELLS_PER_SEGMENT * segments.len();
            self.entries.resize(4 * segments.len(), 0);
            self.cell_start.resize(self.max_cells + 1, 0);
        }
        // Bounds and longest segment: minima and maxima are exact in any order, so the
        // reduction runs in parallel (chunks of at least 1024 segments) and its result does not
        // depend on the threads.
        let empty = (Vector2::repeat(f64::MAX), Vector2::repeat(f64::MIN), 0.0_f64);
        let (mut lo, mut hi, l_max) = segments
            .par_iter()
            .with_min_len(1024)
            .fold(
                || empty,
                |(lo, hi, l_max), s| {
                    let (a, b) = (x[s[0] as usize], x[s[1] as usize]);
                    (lo.inf(&a.inf(&b)), hi.sup(&a.sup(&b)), l_max.max((b - a).norm()))
                },
            )
            .reduce(
                || empty,
                |(lo1, hi1, l1), (lo2, hi2, l2)| (lo1.inf(&lo2), hi1.sup(&hi2), l1.max(l2)),
            );
        let bare = max_gap + 0.5 * projection_tolerance * l_max;
        self.skin = skin * bare;
        let margin = bare + 2.0 * self.skin;
        self.margin = margin;
        let finite = lo.iter().chain(hi.iter()).all(|v| v.is_finite()) && margin.is_finite();
        if !finite {
            return;
        }
        lo -= Vector2::repeat(margin);
        hi += Vector2::repeat(margin);
        let extent = hi - lo;
        // Cell size: at least L_max + 2m, enlarged until the grid fits the preallocated budget.
        let budget = self.max_cells as f64;
        let mut c = (l_max + 2.0 * margin)
            .max((extent.x * extent.y / budget).sqrt())
            .max(extent.x.max(extent.y) / budget)
            .max(f64::MIN_POSITIVE);
        let cells = |c: f64| ((extent.x / c) as usize + 1, (extent.y / c) as usize + 1);
        while cells(c).0.saturating_mul(cells(c).1) > self.max_cells {
            c *= 1.5;
        }
        self.origin = lo;
        self.cell_size = c;
        self.inv_cell_size = 1.0 / c;
        (self.nx, self.ny) = cells(c);
        self.fill(segments, x, margin);
    }

    /// Counting sort of the segments into their cells: each segment's cell range (in parallel,
    /// one slot per segment), then count, prefix sum and scatter in segment order, so every cell
    /// lists its segments in increasing index whatever the threads.
    fn fill(&mut self, segments: &[[u32; 2]], x: &[Vector2<f64>], margin: f64) {
        let num_cells = self.nx * self.ny;
        let mut ranges = std::mem::take(&mut self.ranges);
        let grid = &*self;
        segments
            .par_iter()
            .with_min_len(1024)
            .map(|s| {
                let (lo, hi) = inflated_box(x[s[0] as usize], x[s[1] as usize], margin);
                [grid.ix(lo.x), grid.iy(lo.y), grid.ix(hi.x), grid.iy(hi.y)].map(|k| k as u32)
            })
            .collect_into_vec(&mut ranges);
        self.ranges = ranges;
        let nx = self.nx;
        let cells = |[i0, j0, i1, j1]: [u32; 4]| {
            (j0 as usize..=j1 as usize)
                .flat_map(move |j| (i0 as usize..=i1 as usize).map(move |i| j * nx + i))
        };
        let counts = &mut self.cell_start[..=num_cells];
        counts.fill(0);
        for &r in &self.ranges {
            for k in cells(r) {
                counts[k + 1] += 1;
            }
        }
        for k in 0..num_cells {
            counts[k + 1] += counts[k];
        }
        self.num_entries = counts[num_cells] as usize;
        // Scatter: `cell_start[k]` is used as the running cursor of cell k and restored after.
        for (index, &r) in self.ranges.iter().enumerate() {
            for k in cells(r) {
                self.entries[self.cell_start[k] as usize] = index as u32;
                self.cell_start[k] += 1;
            }
        }
        for k in (1..=num_cells).rev() {
            self.cell_start[k] = self.cell_start[k - 1];
        }
        self.cell_start[0] = 0;
    }

    // Truncation of a non-negative value is its floor (and avoids a libm call per query).
    fn ix(&self, x: f64) -> usize {
        (((x - self.origin.x) * self.inv_cell_size).max(0.0) as usize).min(self.nx - 1)
    }

    fn iy(&self, y: f64) -> usize {
        (((y - self.origin.y) * self.inv_cell_size).max(0.0) as usize).min(self.ny - 1)
    }

    /// Segments registered in the cell containing `p` (empty outside the grid).
    pub(crate) fn candidates(&self, p: Vector2<f64>) -> &[u32] {
        if self.nx == 0 {
            return &[];
        }
        let r = (p - self.origin) * self.inv_cell_size;
        let inside = r.x >= 0.0 && r.y >= 0.0 && r.x < self.nx as f64 && r.y < self.ny as f64;
        if !inside {
            return &[];
        }
        let k = r.y as usize * self.nx + r.x as usize;
        &self.entries[self.cell_start[k] as usize..self.cell_start[k + 1] as usize]
    }

    /// Number of (segment, cell) registrations of the last rebuild.
    #[cfg(test)]
    pub(crate) fn num_entries(&self) -> usize {
        self.num_entries
    }

    /// Capacities of the flat arrays, the cell ranges and the anchor positions (for the
    /// no-allocation tests).
    #[cfg(test)]
    pub(crate) fn capacities(&self) -> [usize; 6] {
        [
            self.cell_start.capacity(),
            self.entries.capacity(),
            self.ranges.capacity(),
            self.anchor.capacity(),
            self.list_start.capacity(),
            self.listed.capacity(),
        ]
    }
}

/// The most nodes a slave may be tied to: a junction of up to 8 sectors (docs/meshes.md).
pub(crate) const MAX_TIED: usize = 7;

/// No tie: every slot unused.
pub(crate) const UNTIED: [u32; MAX_TIED] = [u32::MAX; MAX_TIED];

/// What the narrow phase needs besides the grid, for one slave node.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Slave {
    /// Node id i.
    pub node: u32,
    /// The nodes i is tied to (docs/fem-model.md §3.1; several at a junction), `u32::MAX` in
    /// the unused slots.
    pub tied: [u32; MAX_TIED],
    /// Slave normal n_i (normalised sum of its segments' outward normals) [-].
    pub normal: Vector2<f64>,
}

/// Acceptance limits of the narrow phase.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Limits {
    /// d_max [m]: candidates with |g| > d_max are ignored.
    pub max_gap: f64,
    /// ε_ext [-]: accept −1 − ε_ext ≤ ξ ≤ 1 + ε_ext.
    pub projection_tolerance: f64,
}

/// Narrow phase for one slave, docs/fem-model.md §5.1: among the grid candidates, drop segments attached
/// to the node or to its tied twin; project; keep penetrating (g < 0) pairs with |g| ≤ d_max,
/// facing normals (n_i·n_e < −cos 60°, [`FACING_COS`]) and ξ within tolerance; return the one with the smallest |g|
/// (docs/fem-model.md §10.8; on ties the lowest segment index, for reproducibility).
///
/// `frames[e]` is segment e's frame at the current positions (`None`: degenerate, never a master).
#[cfg(test)]
pub(crate) fn closest_master(
    slave: &Slave,
    grid: &BucketGrid,
    segments: &[[u32; 2]],
    frames: &[Option<SegmentFrame>],
    x: &[Vector2<f64>],
    limits: &Limits,
) -> Option<(u32, Projection)> {
    let candidates = grid.candidates(x[slave.node as usize]);
    closest_master_or_depth(slave, candidates, segments, frames, x, limits).0
}

/// As [`closest_master`] among `candidates` (the slave's list, [`BucketGrid::candidates_of`], or its
/// cell's segments), and whether a facing candidate within the projection tolerance was rejected
/// only because its penetration exceeds d_max: a contact lost to the detection distance.
#[inline(always)]
pub(crate) fn closest_master_or_depth(
    slave: &Slave,
    candidates: &[u32],
    segments: &[[u32; 2]],
    frames: &[Option<SegmentFrame>],
    x: &[Vector2<f64>],
    limits: &Limits,
) -> (Option<(u32, Projection)>, bool) {
    let xi_max = 1.0 + limits.projection_tolerance;
    let x_i = x[slave.node as usize];
    let mut best: Option<(u32, Projection)> = None;
    let mut too_deep = false;
    let tied = slave.tied.iter().any(|&t| t != u32::MAX);
    for &e in candidates {
        // Every test before the depth check only rejects, so their order does not change the
        // result; the cheapest come first. Not facing rejects the slave's own face (about half
        // of the candidates on an interface) from the frame alone, before any node is read.
        let Some(frame) = &frames[e as usize] else {
            continue;
        };
        if slave.normal.dot(&frame.normal) >= -FACING_COS {
            continue;
        }
        let [j1, j2] = segments[e as usize];
        let attached = j1 == slave.node || j2 == slave.node;
        let twin = tied && (slave.tied.contains(&j1) || slave.tied.contains(&j2));
        if attached || twin {
            continue;
        }
        // separated; then too deep (counted)
        let gap = (x_i - x[j1 as usize]).dot(&frame.normal);
        if gap >= 0.0 {
            continue;
        }
        let p = project_on_frame(x_i, x[j1 as usize], frame);
        if -gap > limits.max_gap {
            too_deep |= p.xi.abs() <= xi_max;
            continue;
        }
        let better = match &best {
            None => true,
            Some((b, q)) => -p.gap < -q.gap || (-p.gap == -q.gap && e < *b),
        };
        if p.xi.abs() <= xi_max && better {
            best = Some((e, p));
        }
    }
    let lost = best.is_none() && too_deep;
    (best, lost)
}
