//! The bulk kernel on unstructured meshes of T3 and Q4 elements ([`crate::mesh::gmsh::UnstructuredMesh`]):
//! lumped masses, the smallest element length of the stable step, and the race-free, deterministic
//! rayon evaluation of the internal forces: the bulk of a scene on a Gmsh mesh (docs/meshes.md).
//!
//! Elements (plane strain, thickness 1 m, so forces are per metre of thickness):
//! - **T3**, the constant-strain triangle: K_e = A t Bᵀ D B with t = 1 m and the constant
//!   B = 1/(2A) [[b₀, 0, b₁, 0, b₂, 0], [0, c₀, 0, c₁, 0, c₂], [c₀, b₀, c₁, b₁, c₂, b₂]],
//!   b_i = y_j − y_k, c_i = x_k − x_j for (i, j, k) cyclic (Zienkiewicz, Taylor & Zhu, *The Finite
//!   Element Method: Its Basis and Fundamentals*, 7th ed., §6.2). Lumped mass ρA/3 per node (the
//!   row sum of the consistent mass).
//! - **Q4**, the bilinear quadrangle with 2×2 Gauss points: K_e = Σ_q B_qᵀ D B_q det J_q
//!   (`model::bulk::stiffness`) and `model::bulk::lumped_mass`, the structured grid's element
//!   (docs/fem-model.md §1).
//!
//! Storage: the material is linear and the strains small, so the assembled stiffness K is
//! constant. The kernel stores it by **edges**: one 2×2 block K_ab per pair of nodes a < b that
//! share an element (the edges of a T3, the edges and diagonals of a Q4), summed over those
//! elements with each element's own D, in a fixed order. A rigid translation produces no force,
//! so each block row of K sums to zero and K_aa = −Σ_b K_ab; hence
//! (K u)_a = Σ_b K_ab (u_b − u_a), and one edge serves both ends: with d = u_b − u_a,
//! f_a −= K_ab d and f_b += K_abᵀ d (K_ba = K_abᵀ by symmetry). This is the edge-based
//! formulation of explicit unstructured solvers (Löhner, *Applied Computational Fluid Dynamics
//! Techniques*, 2nd ed., §4.9): about 18 flops and 36 bytes per edge, 3 edges per node on a
//! triangle mesh and 4 on a quadrangle mesh, against a stored K_e (288 B per T3, 512 B per Q4) or
//! the element forces recomputed from the node positions (≈ 60 flops per T3, 250 per Q4, with
//! their gathers and scatters). A rigid translation gives exactly zero force.
//!
//! The kernel numbers the nodes in its own order when the mesh's numbering is far from local:
//! reverse Cuthill–McKee, kept if it brings the two ends of an edge at least four times closer on
//! average (Gmsh numbers the nodes of the curves before those of the surfaces); u and f then pass
//! through buffers in that order. The nodes are cut, at build time, into tiles of consecutive
//! nodes (in the kernel's order). A tile runs its nodes in order: each node first sums its edges from nodes of earlier tiles (recomputed there, as the
//! other tile computes them too), then runs its own edges (b > a), adding to a and, if b is in the
//! tile, to b. Every node's force is therefore summed in a fixed order set by the mesh and the
//! tiles, not by the threads; tiles run in parallel and write disjoint node ranges, so the result
//! is the same to the bit for any number of threads.

use crate::error::UnstructuredError;
use crate::mesh::gmsh::{ElementKind, UnstructuredMesh};
use crate::mesh::lengths::{element_length, min_element_length};
use crate::model::bulk;
use nalgebra::Vector2;

/// Nodes per tile at least: a tile's work must dwarf the cost of a rayon task.
const MIN_TILE_NODES: usize = 256;

/// Tiles per mesh aimed at, so that 2 threads balance.
const TARGET_TILES: usize = 16;

/// Nodes per rayon task of the copies into and out of the kernel's node order.
const COPY_CHUNK: usize = 4096;

/// The kernel's u and f buffers (in its node order), behind a lock so that an evaluation through
/// `&self` may fill them; a clone gets buffers of its own.
#[derive(Debug)]
struct Work(std::sync::Mutex<Buffers>);

/// u [m] and f [N/m] per node, in the kernel's node order.
type Buffers = (Vec<[f64; 2]>, Vec<[f64; 2]>);

impl Work {
    fn new(nn: usize) -> Self {
        Self(std::sync::Mutex::new((vec![[0.0; 2]; nn], vec![[0.0; 2]; nn])))
    }
}

impl Clone for Work {
    fn clone(&self) -> Self {
        Self::new(self.0.lock().unwrap_or_else(|e| e.into_inner()).0.len())
    }
}

/// A node order of reverse Cuthill–McKee (Cuthill & McKee, 1969; George & Liu, *Computer
/// Solution of Large Sparse Positive Definite Systems*, 1981, §4.3) over the graph of the node
/// pairs `pairs`: breadth first from a node of least degree in each connected part, each node's
/// unvisited neighbours by increasing degree (then index), the whole order reversed. Returns, for
/// each new index, the old one.
fn reverse_cuthill_mckee(nn: usize, pairs: &[(u32, u32, [f64; 4])]) -> Vec<u32> {
    let mut start = vec![0usize; nn + 1];
    for &(a, b, _) in pairs {
        start[a as usize + 1] += 1;
        start[b as usize + 1] += 1;
    }
    for n in 0..nn {
        start[n + 1] += start[n];
    }
    let mut fill = start.clone();
    let mut adj = vec![0u32; start[nn]];
    for &(a, b, _) in pairs {
        adj[fill[a as usize]] = b;
        fill[a as usize] += 1;
        adj[fill[b as usize]] = a;
        fill[b as usize] += 1;
    }
    let degree = |n: u32| start[n as usize + 1] - start[n as usize];
    for n in 0..nn {
        adj[start[n]..start[n + 1]].sort_unstable_by_key(|&m| (degree(m), m));
    }
    let mut roots: Vec<u32> = (0..nn as u32).collect();
    roots.sort_by_key(|&n| (degree(n), n));
    let mut seen = vec![false; nn];
    let mut order = Vec::with_capacity(nn);
    for &root in &roots {
        if seen[root as usize] {
            continue;
        }
        seen[root as usize] = true;
        let mut head = order.len();
        order.push(root);
        while head < order.len() {
            let n = order[head] as usize;
            head += 1;
            for &m in &adj[start[n]..start[n + 1]] {
                if !seen[m as usize] {
                    seen[m as usize] = true;
                    order.push(m);
                }
            }
        }
    }
    order.reverse();
    order
}

/// The elastic constants of one material of the kernel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BulkMaterial {
    /// Plane-strain Voigt matrix D [Pa] ([`crate::law::elastic::PlaneStrain::d_matrix`]).
    pub d: [[f64; 3]; 3],
    /// Density ρ [kg/m³].
    pub density: f64,
}

impl BulkMaterial {
    /// Dilatational (P-wave) speed c_d = √(D₀₀/ρ) [m/s], D₀₀ = λ + 2G.
    pub fn cd(&self) -> f64 {
        (self.d[0][0] / self.density).sqrt()
    }
}

/// The bulk of an unstructured T3/Q4 mesh, ready for force evaluations.
#[derive(Debug, Clone)]
pub struct UnstructuredBulk {
    /// The kernel's node order, if not the mesh's: `order[i]` is the mesh's index of the kernel's
    /// node i (reverse Cuthill–McKee). The edges, tiles and cross-tile lists below are in the
    /// kernel's order; `mass` is in the mesh's.
    order: Vec<u32>,
    /// The inverse of `order`: `rank[n]` is the kernel's index of the mesh's node n.
    rank: Vec<u32>,
    /// u and f in the kernel's order during an evaluation (empty without `order`).
    work: Work,
    /// Per node a, its edges (a, b) with b > a: `edge_start[a]..edge_start[a + 1]` into `other`
    /// and `blocks` (length: nodes + 1).
    edge_start: Vec<u32>,
    /// The higher node b of each edge, ascending per node.
    other: Vec<u32>,
    /// K_ab of each edge [N/m per m of thickness]: the 2×2 block of the assembled stiffness at row
    /// a, column b, as [xx, xy, yx, yy].
    blocks: Vec<[f64; 4]>,
    /// The tiles: node ranges [first, end), covering the nodes in order.
    tiles: Vec<[u32; 2]>,
    /// Per node b, its edges from nodes of earlier tiles: `in_start[b]..in_start[b + 1]` into
    /// `in_edge` (length: nodes + 1).
    in_start: Vec<u32>,
    /// Those edges as (edge index, lower node a), by ascending a.
    in_edge: Vec<[u32; 2]>,
    /// Lumped nodal masses [kg/m].
    mass: Vec<f64>,
    /// Smallest element length of the stable step [m] (see [`UnstructuredBulk::min_length`]).
    h_min: f64,
    /// Smallest transit time h_e/c_d,e over the elements [s] (see
    /// [`UnstructuredBulk::min_transit_time`]).
    min_transit: f64,
    /// Tiles one rayon task runs in a row, about 1/8 of the tiles.
    tiles_per_task: usize,
}

impl UnstructuredBulk {
    /// Builds the kernel on `mesh` with the plane-strain Voigt matrix `d` [Pa]
    /// ([`crate::law::elastic::PlaneStrain::d_matrix`]) and the density `density` [kg/m³].
    pub fn new(mesh: &UnstructuredMesh, d: &[[f64; 3]; 3], density: f64) -> Result<Self, UnstructuredError> {
        Self::with_materials(mesh, &[BulkMaterial { d: *d, density }], &[])
    }

    /// Builds the kernel on `mesh` with several materials: element e (in the mesh's order) is of
    /// `materials[element_material[e]]`; an empty `element_material` puts every element in
    /// `materials[0]`. Masses, stiffness and the stable step then use each element's own material.
    pub fn with_materials(
        mesh: &UnstructuredMesh,
        materials: &[BulkMaterial],
        element_material: &[u8],
    ) -> Result<Self, UnstructuredError> {
        if let Some(m) = materials
            .iter()
            .find(|m| !(m.density.is_finite() && m.density > 0.0))
        {
            return Err(UnstructuredError::BadDensity(m.density));
        }
        let single = element_material.is_empty();
        let material_of = |e: usize| if single { 0 } else { element_material[e] as usize };
        if materials.is_empty()
            || materials.len() > 256
            || !(single || element_material.len() == mesh.elements.len())
            || (0..mesh.elements.len()).any(|e| material_of(e) >= materials.len())
        {
            return Err(UnstructuredError::BadMaterials);
        }
        let nn = mesh.positions.len();
        if nn >= u32::MAX as usize {
            return Err(UnstructuredError::TooLarge);
        }
        let x = &mesh.positions;

        // validity, masses and the element stiffnesses' blocks (a, b, K_ab) for a < b, in the
        // mesh's element order
        let mut mass = vec![0.0; nn];
        let mut entries: Vec<(u32, u32, [f64; 4])> = Vec::new();
        for (e, el) in mesh.elements.iter().enumerate() {
            let material = &materials[material_of(e)];
            let inverted = |det_j: f64| UnstructuredError::InvertedElement {
                element: el.tag,
                det_j,
            };
            match el.kind {
                ElementKind::T3 => {
                    let c = [x[el.nodes[0]], x[el.nodes[1]], x[el.nodes[2]]];
                    let k = cst_stiffness(&c, &material.d).map_err(inverted)?;
                    let two_a = (c[1] - c[0]).perp(&(c[2] - c[0]));
                    let m = [material.density * (0.5 * two_a) / 3.0; 3];
                    add_element(&el.nodes, &m, &k, &mut mass, &mut entries);
                }
                ElementKind::Q4 => {
                    let c = [x[el.nodes[0]], x[el.nodes[1]], x[el.nodes[2]], x[el.nodes[3]]];
                    let k = bulk::stiffness(&c, &material.d).map_err(inverted)?;
                    let m = bulk::lumped_mass(&c, material.density);
                    add_element(&el.nodes, &m, &k, &mut mass, &mut entries);
                }
            }
        }
        let h_min = min_element_length(mesh);
        let min_transit = (0..mesh.elements.len())
            .map(|e| element_length(mesh, e) / materials[material_of(e)].cd())
            .fold(f64::INFINITY, f64::min);

        // the edges: blocks of the same pair summed in the mesh's element order (a stable sort)
        entries.sort_by_key(|&(a, b, _)| (a, b));
        let mut pairs: Vec<(u32, u32, [f64; 4])> = Vec::new();
        for &(a, b, k) in &entries {
            match pairs.last_mut() {
                Some((pa, pb, sum)) if (*pa, *pb) == (a, b) => {
                    for (s, v) in sum.iter_mut().zip(k) {
                        *s += v;
                    }
                }
                _ => pairs.push((a, b, k)),
            }
        }
        drop(entries);
        if pairs.len() >= u32::MAX as usize {
            return Err(UnstructuredError::TooLarge);
        }

        // the kernel's node order: the mesh's, unless reverse Cuthill–McKee brings the two ends of
        // an edge at least four times as close on average (Gmsh numbers the nodes of the curves
        // first, then those of the surfaces, so an interface node's neighbours are far from it:
        // 0.068 on center-crack-tri's mesh; a grid numbered row by row: 0.42 with triangles, 0.58
        // with quadrangles, where the copies into the kernel's order would cost more); edges
        // renumbered with a < b, the block transposed where the ends swap (K_ba = K_abᵀ)
        let spread = |rank: &dyn Fn(u32) -> u32| {
            pairs
                .iter()
                .map(|&(a, b, _)| rank(a).abs_diff(rank(b)) as f64)
                .sum::<f64>()
        };
        let cm = reverse_cuthill_mckee(nn, &pairs);
        let mut rank = vec![0u32; nn];
        for (new, &old) in cm.iter().enumerate() {
            rank[old as usize] = new as u32;
        }
        let (order, rank) = if spread(&|n| rank[n as usize]) < 0.25 * spread(&|n| n) {
            for (a, b, k) in pairs.iter_mut() {
                let (ra, rb) = (rank[*a as usize], rank[*b as usize]);
                if ra < rb {
                    (*a, *b) = (ra, rb);
                } else {
                    (*a, *b, *k) = (rb, ra, [k[0], k[2], k[1], k[3]]);
                }
            }
            pairs.sort_unstable_by_key(|&(a, b, _)| (a, b));
            (cm, rank)
        } else {
            (Vec::new(), Vec::new())
        };
        let mut edge_start = vec![0u32; nn + 1];
        for &(a, _, _) in &pairs {
            edge_start[a as usize + 1] += 1;
        }
        for a in 0..nn {
            edge_start[a + 1] += edge_start[a];
        }
        let other: Vec<u32> = pairs.iter().map(|p| p.1).collect();
        let blocks: Vec<[f64; 4]> = pairs.iter().map(|p| p.2).collect();
        drop(pairs);

        // tiles of consecutive nodes, and each node's edges from earlier tiles
        let per_tile = nn.div_ceil(TARGET_TILES).max(MIN_TILE_NODES);
        let tiles: Vec<[u32; 2]> = (0..nn)
            .step_by(per_tile)
            .map(|first| [first as u32, (first + per_tile).min(nn) as u32])
            .collect();
        let tile_of = |n: usize| n / per_tile;
        let mut incoming: Vec<(u32, u32, u32)> = Vec::new(); // (b, a, edge)
        for a in 0..nn {
            let edges = edge_start[a] as usize..edge_start[a + 1] as usize;
            for (k, &b) in edges.clone().zip(&other[edges]) {
                if tile_of(b as usize) != tile_of(a) {
                    incoming.push((b, a as u32, k as u32));
                }
            }
        }
        incoming.sort_unstable();
        let mut in_start = vec![0u32; nn + 1];
        for &(b, _, _) in &incoming {
            in_start[b as usize + 1] += 1;
        }
        for b in 0..nn {
            in_start[b + 1] += in_start[b];
        }
        let in_edge = incoming.iter().map(|&(_, a, k)| [k, a]).collect();

        let tiles_per_task = (tiles.len() / 8).max(1);
        Ok(Self {
            work: Work::new(if order.is_empty() { 0 } else { nn }),
            order,
            rank,
            edge_start,
            other,
            blocks,
            tiles,
            in_start,
            in_edge,
            mass,
            h_min,
            min_transit,
            tiles_per_task,
        })
    }

    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.mass.len()
    }

    /// Lumped nodal masses [kg/m] (T3: ρA/3 per node; Q4: the row sums of
    /// `model::bulk::lumped_mass`).
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }

    /// Smallest element length h_min [m] of the stable step Δt = α h_min/c_d · f(β_p)
    /// (docs/fem-model.md §2, [`crate::law::elastic::stable_time_step`]). Per element:
    /// - T3: its smallest altitude, 2A/ℓ_max with ℓ_max its longest edge (the characteristic
    ///   length of explicit codes for triangles);
    /// - Q4: A/ℓ_max. On a rectangle h × h that is h, and on the vertical-sided elements of a
    ///   mapped grid (width h, height v, top edge of slope s) it is v/√(1 + s²): the structured
    ///   model's rule ([`crate::scene::FemSpec::min_edge`]) on the meshes it covers.
    pub fn min_length(&self) -> f64 {
        self.h_min
    }

    /// Stable time step Δt = α h_min/c_d [s] without a penalty (β_p = 0), with c_d [m/s] the
    /// plane-strain dilatational speed ([`crate::law::elastic::PlaneStrain::wave_speeds`]).
    pub fn stable_time_step(&self, alpha: f64, cd: f64) -> f64 {
        crate::law::elastic::stable_time_step(alpha, self.h_min, cd, 0.0)
    }

    /// The smallest transit time min_e h_e/c_d,e [s] over the elements, each with its own length
    /// h_e ([`UnstructuredBulk::min_length`]'s rule) and its own material's P-wave speed: the
    /// stable step without a penalty is α times it.
    pub fn min_transit_time(&self) -> f64 {
        self.min_transit
    }

    /// Bytes of the kernel's arrays (edges and their blocks, tiles, cross-tile lists, masses).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(&self.order[..])
            + size_of_val(&self.rank[..])
            + 2 * self.order.len() * std::mem::size_of::<[f64; 2]>()
            + size_of_val(&self.edge_start[..])
            + size_of_val(&self.other[..])
            + size_of_val(&self.blocks[..])
            + size_of_val(&self.tiles[..])
            + size_of_val(&self.in_start[..])
            + size_of_val(&self.in_edge[..])
            + size_of_val(&self.mass[..])
    }

    /// f = −f_int(u) = −K u [N/m] for displacements `u` [m] (overwrites `f`), in a fixed order of
    /// summation per node (see the module documentation). Parallel over tiles of nodes; each task
    /// writes only its own nodes, so the result is the same to the bit for any number of threads.
    /// Allocates nothing (in the kernel's own node order, u and f pass through buffers kept with
    /// it).
    pub fn internal_forces(&self, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
        use rayon::prelude::*;
        assert_eq!(u.len(), self.num_nodes(), "one displacement per node");
        assert_eq!(f.len(), self.num_nodes(), "one force per node");
        let u: &[[f64; 2]] = bytemuck::cast_slice(u);
        if self.order.is_empty() {
            return self.run(&self.tiles, u, bytemuck::cast_slice_mut(f));
        }
        // (a poisoned lock only means that an evaluation panicked: both buffers are overwritten)
        let mut work = self.work.0.lock().unwrap_or_else(|e| e.into_inner());
        let (uk, fk) = &mut *work;
        uk.par_chunks_mut(COPY_CHUNK)
            .zip(self.order.par_chunks(COPY_CHUNK))
            .for_each(|(dst, from)| {
                for (d, &n) in dst.iter_mut().zip(from) {
                    *d = u[n as usize];
                }
            });
        self.run(&self.tiles, uk, fk);
        let fk = &*fk;
        f.par_chunks_mut(COPY_CHUNK)
            .zip(self.rank.par_chunks(COPY_CHUNK))
            .for_each(|(dst, from)| {
                for (d, &k) in dst.iter_mut().zip(from) {
                    *d = Vector2::from(fk[k as usize]);
                }
            });
    }

    /// The tiles `tiles`, whose nodes are those of `f`, split in halves across rayon tasks.
    fn run(&self, tiles: &[[u32; 2]], u: &[[f64; 2]], f: &mut [[f64; 2]]) {
        match tiles {
            [] => {}
            _ if tiles.len() <= self.tiles_per_task => {
                let first = tiles[0][0];
                for t in tiles {
                    let nodes = (t[0] - first) as usize..(t[1] - first) as usize;
                    self.tile(*t, u, &mut f[nodes]);
                }
            }
            _ => {
                let mid = tiles.len() / 2;
                let split = (tiles[mid][0] - tiles[0][0]) as usize;
                let (lo, hi) = f.split_at_mut(split);
                rayon::join(
                    || self.run(&tiles[..mid], u, lo),
                    || self.run(&tiles[mid..], u, hi),
                );
            }
        }
    }

    /// One tile, nodes [first, end) (those of `f`): the edges from earlier tiles, then its own.
    fn tile(&self, [first, end]: [u32; 2], u: &[[f64; 2]], f: &mut [[f64; 2]]) {
        let (first, end) = (first as usize, end as usize);
        let bl = &self.blocks;
        for (i, fb) in f.iter_mut().enumerate() {
            let b = first + i;
            let ub = u[b];
            let mut acc = [0.0; 2];
            for &[k, a] in &self.in_edge[self.in_start[b] as usize..self.in_start[b + 1] as usize] {
                let (kb, ua) = (bl[k as usize], u[a as usize]);
                let d = [ub[0] - ua[0], ub[1] - ua[1]];
                acc[0] += kb[0] * d[0] + kb[2] * d[1];
                acc[1] += kb[1] * d[0] + kb[3] * d[1];
            }
            *fb = acc;
        }
        for a in first..end {
            let ua = u[a];
            let mut acc = f[a - first];
            let edges = self.edge_start[a] as usize..self.edge_start[a + 1] as usize;
            for (&b, kb) in self.other[edges.clone()].iter().zip(&bl[edges]) {
                let b = b as usize;
                let ub = u[b];
                let d = [ub[0] - ua[0], ub[1] - ua[1]];
                acc[0] -= kb[0] * d[0] + kb[1] * d[1];
                acc[1] -= kb[2] * d[0] + kb[3] * d[1];
                if b < end {
                    let fb = &mut f[b - first];
                    fb[0] += kb[0] * d[0] + kb[2] * d[1];
                    fb[1] += kb[1] * d[0] + kb[3] * d[1];
                }
            }
            f[a - first] = acc;
        }
    }
}

/// Adds an element with nodes `nodes`, lumped masses `m` [kg/m] and stiffness `k` (DOF order
/// x₀, y₀, x₁, y₁, …) [N/m per m]: its masses to `mass`, and its block K_ab for every pair of its
/// nodes a < b to `entries` as (a, b, [xx, xy, yx, yy]).
fn add_element<const N: usize, const D: usize>(
    nodes: &[usize],
    m: &[f64; N],
    k: &[[f64; D]; D],
    mass: &mut [f64],
    entries: &mut Vec<(u32, u32, [f64; 4])>,
) {
    for (&a, ma) in nodes.iter().zip(m) {
        mass[a] += ma;
    }
    for (i, &a) in nodes.iter().enumerate() {
        for (j, &b) in nodes.iter().enumerate() {
            if a < b {
                let (r, c) = (2 * i, 2 * j);
                entries.push((
                    a as u32,
                    b as u32,
                    [k[r][c], k[r][c + 1], k[r + 1][c], k[r + 1][c + 1]],
                ));
            }
        }
    }
}

/// The constant-strain triangle's K_e = A t Bᵀ D B (t = 1 m) [N/m per m] with corners `c` [m] and
/// the Voigt matrix `d` [Pa], DOF order x₀, y₀, x₁, y₁, x₂, y₂; Err(2A) [m²] for a clockwise or
/// degenerate triangle.
pub(crate) fn cst_stiffness(c: &[Vector2<f64>; 3], d: &[[f64; 3]; 3]) -> Result<[[f64; 6]; 6], f64> {
    let two_a = (c[1] - c[0]).perp(&(c[2] - c[0]));
    if two_a <= 0.0 || !two_a.is_finite() {
        return Err(two_a);
    }
    let mut b = [[0.0; 6]; 3];
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        // ∂N_i/∂x = b_i/(2A), ∂N_i/∂y = c_i/(2A)
        let (bi, ci) = ((c[j].y - c[k].y) / two_a, (c[k].x - c[j].x) / two_a);
        b[0][2 * i] = bi;
        b[1][2 * i + 1] = ci;
        b[2][2 * i] = ci;
        b[2][2 * i + 1] = bi;
    }
    let area = 0.5 * two_a;
    let mut k = [[0.0; 6]; 6];
    for (i, ki) in k.iter_mut().enumerate() {
        for (j, kij) in ki.iter_mut().enumerate() {
            let mut sum = 0.0;
            for p in 0..3 {
                for q in 0..3 {
                    sum += b[p][i] * d[p][q] * b[q][j];
                }
            }
            *kij = area * sum;
        }
    }
    Ok(k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::elastic::PlaneStrain;
    use crate::mesh::gmsh::BulkElement;
    use crate::mesh::structured::{Grid, GridSpec};
    use std::collections::BTreeMap;

    /// The old formulation, as reference: f_a = −Σ_e K_e[a-rows] u_e in mesh element order, with
    /// K_e from `cst_stiffness` and `bulk::stiffness`.
    fn reference_forces(mesh: &UnstructuredMesh, d: &[[f64; 3]; 3], u: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
        reference_forces_of(mesh, &|_| *d, u)
    }

    /// As [`reference_forces`], element e with the Voigt matrix `d_of(e)`.
    fn reference_forces_of(
        mesh: &UnstructuredMesh,
        d_of: &dyn Fn(usize) -> [[f64; 3]; 3],
        u: &[Vector2<f64>],
    ) -> Vec<Vector2<f64>> {
        let mut f = vec![Vector2::zeros(); u.len()];
        for (e, el) in mesh.elements.iter().enumerate() {
            let d = &d_of(e);
            let c: Vec<Vector2<f64>> = el.nodes.iter().map(|&a| mesh.positions[a]).collect();
            let k: Vec<Vec<f64>> = match el.kind {
                ElementKind::T3 => cst_stiffness(&[c[0], c[1], c[2]], d)
                    .unwrap()
                    .iter()
                    .map(|r| r.to_vec())
                    .collect(),
                ElementKind::Q4 => bulk::stiffness(&[c[0], c[1], c[2], c[3]], d)
                    .unwrap()
                    .iter()
                    .map(|r| r.to_vec())
                    .collect(),
            };
            for (i, &a) in el.nodes.iter().enumerate() {
                for (j, &b) in el.nodes.iter().enumerate() {
                    for r in 0..2 {
                        f[a][r] -= k[2 * i + r][2 * j] * u[b].x + k[2 * i + r][2 * j + 1] * u[b].y;
                    }
                }
            }
        }
        f
    }

    /// The paper's material (E = 70 MPa, ν = 0.35, ρ = 1230 kg/m³).
    fn material() -> PlaneStrain {
        PlaneStrain::new(70e6, 0.35, 1230.0)
    }

    fn committed(name: &str) -> UnstructuredMesh {
        let path = format!("{}/../meshes/{name}", env!("CARGO_MANIFEST_DIR"));
        UnstructuredMesh::read(std::path::Path::new(&path)).unwrap()
    }

    /// A mesh with the given nodes and elements and nothing else.
    fn mesh_of(positions: Vec<Vector2<f64>>, elements: Vec<(ElementKind, Vec<usize>)>) -> UnstructuredMesh {
        UnstructuredMesh {
            node_tags: (1..=positions.len() as u64).collect(),
            positions,
            elements: elements
                .into_iter()
                .enumerate()
                .map(|(e, (kind, nodes))| BulkElement {
                    tag: e as u64 + 1,
                    kind,
                    nodes,
                })
                .collect(),
            lines: Vec::new(),
            groups: BTreeMap::new(),
            reoriented: 0,
            warnings: Vec::new(),
        }
    }

    /// Nodes on the outer boundary of the committed rectangles: the `bottom`, `top`, `left` and
    /// `right` groups.
    fn boundary_nodes(mesh: &UnstructuredMesh) -> Vec<bool> {
        let mut on = vec![false; mesh.positions.len()];
        for g in ["bottom", "top", "left", "right"] {
            for &a in &mesh.group(g).unwrap().nodes {
                on[a] = true;
            }
        }
        on
    }

    fn longest_edge(mesh: &UnstructuredMesh) -> f64 {
        mesh.elements
            .iter()
            .flat_map(|el| {
                let n = el.nodes.len();
                (0..n).map(move |k| (el.nodes[k], el.nodes[(k + 1) % n]))
            })
            .map(|(a, b)| (mesh.positions[a] - mesh.positions[b]).norm())
            .fold(0.0, f64::max)
    }

    fn forces(bulk: &UnstructuredBulk, u: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
        let mut f = vec![Vector2::zeros(); u.len()];
        bulk.internal_forces(u, &mut f);
        f
    }

    /// Patch test: u = A x + b is a state of constant stress σ = D ε(A), so every interior node
    /// is in equilibrium and the boundary forces balance. Scale: the force a single element
    /// carries, |σ| × ℓ_max [N/m]. Round-off: each nodal force sums ≲ 50 products of size
    /// |K| |u| ≈ |D| (|A| L + |b|) with L = 2 m the domain, i.e. ≈ 100 × (L/ℓ_max) × 1e-16 of the
    /// scale ≈ 1e-13 on these meshes (ℓ_max ≈ 0.1 m); 1e-10 leaves three orders of margin.
    #[test]
    fn linear_field_passes_the_patch_test_on_committed_meshes() {
        let mat = material();
        let d = mat.d_matrix();
        let a = [[1.3e-3, -0.4e-3], [0.7e-3, -2.1e-3]];
        let b = Vector2::new(2e-4, -3e-4);
        let eps = [a[0][0], a[1][1], a[0][1] + a[1][0]];
        let sigma = [0, 1, 2].map(|p| (0..3).map(|q| d[p][q] * eps[q]).sum::<f64>());
        let sigma_norm = sigma.iter().map(|s| s * s).sum::<f64>().sqrt();
        for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh", "arc.msh"] {
            let mesh = committed(name);
            let bulk = UnstructuredBulk::new(&mesh, &d, mat.density).unwrap();
            let u: Vec<Vector2<f64>> = mesh
                .positions
                .iter()
                .map(|x| Vector2::new(a[0][0] * x.x + a[0][1] * x.y, a[1][0] * x.x + a[1][1] * x.y) + b)
                .collect();
            let f = forces(&bulk, &u);
            let scale = sigma_norm * longest_edge(&mesh);
            let on_boundary = boundary_nodes(&mesh);
            let mut interior = 0;
            for (n, fa) in f.iter().enumerate() {
                if !on_boundary[n] {
                    interior += 1;
                    assert!(
                        fa.norm() <= 1e-10 * scale,
                        "{name}: node {n} f = {fa}, scale {scale}"
                    );
                }
            }
            assert!(interior > 10, "{name}: {interior} interior nodes");
            // the boundary tractions balance; they also carry σ: the right edge (x = 2 m, height
            // 1 m) takes −(σ_xx, σ_xy) × 1 m in f = −f_int
            let total: Vector2<f64> = f.iter().sum();
            let magnitude: f64 = f.iter().map(|fa| fa.norm()).sum();
            assert!(total.norm() <= 1e-10 * magnitude, "{name}: Σf = {total}");
            let right: Vector2<f64> = mesh.group("right").unwrap().nodes.iter().map(|&n| f[n]).sum();
            let expect = -Vector2::new(sigma[0], sigma[2]);
            assert!(
                (right - expect).norm() <= 1e-10 * sigma_norm,
                "{name}: {right} vs {expect}"
            );
        }
    }

    /// A small rotation θ (−y, x) plus a translation is a rigid motion of the linear kernel:
    /// zero force, against the scale |D| θ ℓ_max of a stretch of the same size (the same
    /// round-off budget as the patch test). The masses add up to ρ × area of the rectangle
    /// [0, 2] × [0, 1] m: both lumpings integrate the element's area exactly, so only the
    /// round-off of some hundred additions remains, far below 1e-12.
    #[test]
    fn rigid_motion_has_no_force_and_masses_sum_to_rho_area() {
        let mat = material();
        let d = mat.d_matrix();
        let theta = 1e-4;
        for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh", "arc.msh"] {
            let mesh = committed(name);
            let bulk = UnstructuredBulk::new(&mesh, &d, mat.density).unwrap();
            let u: Vec<Vector2<f64>> = mesh
                .positions
                .iter()
                .map(|x| theta * Vector2::new(-x.y, x.x) + Vector2::new(3e-5, -1e-5))
                .collect();
            let f = forces(&bulk, &u);
            let scale = d[0][0] * theta * longest_edge(&mesh);
            for (n, fa) in f.iter().enumerate() {
                assert!(fa.norm() <= 1e-10 * scale, "{name}: node {n} f = {fa}");
            }
            let total: f64 = bulk.masses().iter().sum();
            let expect = mat.density * 2.0;
            assert!(
                (total - expect).abs() <= 1e-12 * expect,
                "{name}: {total} vs {expect}"
            );
            assert!(bulk.masses().iter().all(|&m| m > 0.0));
        }
    }

    /// A structured rectangle with a twinned row, written as an unstructured Q4 mesh, gives the
    /// forces of the structured driver (the shared-K_e stencil and the per-element gather). The
    /// two sum the same products in a different order (the stencil sums a node row's blocks of
    /// the two element rows first), so they agree to round-off, 1e-12 of the largest force.
    #[test]
    fn q4_grid_matches_the_structured_driver() {
        let d = material().d_matrix();
        for (nx, ny, twinned) in [(7, 4, Some(2)), (12, 6, None)] {
            let grid = Grid::new(&GridSpec {
                x_range: [-0.3, 0.4],
                y_range: [-0.2, 0.2],
                nx,
                ny,
                twinned_row: twinned,
                upper_shift: 0.0,
                row_map: None,
            });
            let mesh = mesh_of(
                grid.x0.clone(),
                (0..grid.num_elements())
                    .map(|e| {
                        (
                            ElementKind::Q4,
                            grid.element_nodes(e).map(|a| a as usize).to_vec(),
                        )
                    })
                    .collect(),
            );
            let bulk = UnstructuredBulk::new(&mesh, &d, 1230.0).unwrap();
            let u: Vec<Vector2<f64>> = (0..grid.num_nodes())
                .map(|n| Vector2::new((n as f64 * 0.37).sin(), (n as f64 * 0.11).cos()) * 1e-3)
                .collect();
            let f = forces(&bulk, &u);
            let k = bulk::stiffness(&grid.element_coords(0), &d).unwrap();
            for stiffness in [
                bulk::Stiffness::shared(k),
                bulk::Stiffness::PerElement(
                    (0..grid.num_elements())
                        .map(|e| bulk::stiffness(&grid.element_coords(e), &d).unwrap())
                        .collect(),
                ),
            ] {
                let mut g = vec![Vector2::zeros(); u.len()];
                bulk::internal_forces(&grid, &stiffness, &u, &mut g);
                let scale = g.iter().map(|v| v.norm()).fold(0.0, f64::max);
                for (n, (a, b)) in f.iter().zip(&g).enumerate() {
                    assert!((a - b).norm() <= 1e-12 * scale, "{nx}×{ny} node {n}: {a} vs {b}");
                }
            }
            // masses: the structured grid's ρ h_x h_y / 4 per element corner
            let (hx, hy) = (0.7 / nx as f64, 0.4 / ny as f64);
            let corner = 1230.0 * hx * hy / 4.0;
            for (n, &m) in bulk.masses().iter().enumerate() {
                let count = (m / corner).round();
                assert!((m - count * corner).abs() <= 1e-12 * m, "node {n}: {m}");
            }
            assert!((bulk.min_length() - hx.min(hy)).abs() <= 1e-12 * hx);
        }
    }

    /// A distorted nx × ny grid on [0, 0.01 nx] × [0, 0.01 ny] m, no two elements alike: every
    /// third square split into two T3, the others Q4. `scramble` renumbers the nodes by a
    /// multiplicative permutation (neighbours far apart in the numbering).
    fn distorted_mixed(nx: usize, ny: usize, scramble: bool) -> UnstructuredMesh {
        let nn = (nx + 1) * (ny + 1);
        let perm = |n: usize| if scramble { (n * 7919) % nn } else { n };
        let mut positions = vec![Vector2::zeros(); nn];
        for j in 0..=ny {
            for i in 0..=nx {
                let (x, y) = (i as f64 * 0.01, j as f64 * 0.01);
                positions[perm(j * (nx + 1) + i)] =
                    Vector2::new(x + 0.002 * (7.0 * y).sin(), y + 0.002 * (5.0 * x).cos());
            }
        }
        let node = |i: usize, j: usize| perm(j * (nx + 1) + i);
        let mut elements = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let q = [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)];
                if (i + j) % 3 == 0 {
                    elements.push((ElementKind::T3, vec![q[0], q[1], q[2]]));
                    elements.push((ElementKind::T3, vec![q[0], q[2], q[3]]));
                } else {
                    elements.push((ElementKind::Q4, q.to_vec()));
                }
            }
        }
        mesh_of(positions, elements)
    }

    /// A displacement field without symmetry [m].
    fn wobble(n: usize) -> Vec<Vector2<f64>> {
        (0..n)
            .map(|n| Vector2::new((n as f64 * 0.37).sin(), (n as f64 * 0.11).cos()) * 1e-3)
            .collect()
    }

    /// The forces are the same to the bit on 1 and 2 threads (each node's sum has a fixed order),
    /// on a mixed mesh large enough to be split into several tiles.
    #[test]
    fn forces_do_not_depend_on_the_thread_count() {
        let mesh = distorted_mixed(60, 40, false);
        let mat = material();
        let bulk = UnstructuredBulk::new(&mesh, &mat.d_matrix(), mat.density).unwrap();
        assert!(bulk.tiles.len() > 2, "{} tiles", bulk.tiles.len());
        let u = wobble(bulk.num_nodes());
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| forces(&bulk, &u))
        };
        let (one, two) = (run(1), run(2));
        assert!(one.iter().any(|f| f.norm() > 0.0));
        assert_same_bits(&one, &two);
    }

    /// Every component of `a` has the bits of the same component of `b`.
    fn assert_same_bits(a: &[Vector2<f64>], b: &[Vector2<f64>]) {
        for (n, (a, b)) in a.iter().zip(b).enumerate() {
            assert_eq!(
                (a.x.to_bits(), a.y.to_bits()),
                (b.x.to_bits(), b.y.to_bits()),
                "node {n}"
            );
        }
    }

    /// The element forces computed from the positions (ε = B u_e, σ = D ε, Bᵀσ) are those of the
    /// stored-K_e formulation to round-off: 1e-12 of the largest force. The two sum the same
    /// terms in another order, each force being ≲ 50 products of size |K| |u|; the distorted
    /// elements make every K_e different, and the scrambled numbering gives tiles with elements
    /// far apart.
    #[test]
    fn forces_match_the_stiffness_matrices() {
        let mat = material();
        let d = mat.d_matrix();
        for scramble in [false, true] {
            let mesh = distorted_mixed(60, 40, scramble);
            let bulk = UnstructuredBulk::new(&mesh, &d, mat.density).unwrap();
            // a grid numbered row by row keeps its order; scrambled, the kernel takes its own
            assert_eq!(bulk.order.is_empty(), !scramble);
            let u = wobble(bulk.num_nodes());
            let f = forces(&bulk, &u);
            let g = reference_forces(&mesh, &d, &u);
            let scale = g.iter().map(|v| v.norm()).fold(0.0, f64::max);
            for (n, (a, b)) in f.iter().zip(&g).enumerate() {
                assert!(
                    (a - b).norm() <= 1e-12 * scale,
                    "scramble {scramble}, node {n}: {a} vs {b}"
                );
            }
        }
    }

    /// The CST against a hand value: the right triangle (0,0), (1,0), (0,1) has B with rows
    /// (−1, 0, 1, 0, 0, 0), (0, −1, 0, 0, 0, 1), (−1, −1, 0, 1, 1, 0) and A = ½, so
    /// K₀₀ = ½ (D₀₀ + D₂₂) and K₀₁ = ½ (D₀₁ + D₂₂); its smallest altitude is 1/√2. A clockwise
    /// triangle is refused with its tag.
    #[test]
    fn cst_hand_values_length_and_inversion() {
        let d = material().d_matrix();
        let c = [
            Vector2::new(0.0, 0.0),
            Vector2::new(1.0, 0.0),
            Vector2::new(0.0, 1.0),
        ];
        let k = cst_stiffness(&c, &d).unwrap();
        assert!((k[0][0] - 0.5 * (d[0][0] + d[2][2])).abs() <= 1e-12 * d[0][0]);
        assert!((k[0][1] - 0.5 * (d[0][1] + d[2][2])).abs() <= 1e-12 * d[0][0]);
        let mesh = mesh_of(c.to_vec(), vec![(ElementKind::T3, vec![0, 1, 2])]);
        let bulk = UnstructuredBulk::new(&mesh, &d, 1230.0).unwrap();
        assert!((bulk.min_length() - 0.5f64.sqrt()).abs() < 1e-15);
        let bad = mesh_of(c.to_vec(), vec![(ElementKind::T3, vec![0, 2, 1])]);
        assert!(matches!(
            UnstructuredBulk::new(&bad, &d, 1230.0),
            Err(UnstructuredError::InvertedElement { element: 1, .. })
        ));
        assert!(UnstructuredBulk::new(&mesh, &d, 0.0).is_err());
    }

    /// Two materials, (E, ν, ρ) and (8E, 0.25, 2ρ), on the elements of a distorted mixed mesh in a
    /// scattered pattern: forces against Σ K_e u_e with each element's own D (round-off, 1e-12
    /// of the largest force, as the one-material test), masses against ρ_e A_e summed, the same
    /// bits on 1 and 2 threads, and the smallest transit time against
    /// min_e h_e/c_d,e.
    #[test]
    fn two_materials_use_each_elements_own() {
        let mesh = distorted_mixed(60, 40, true);
        let (m0, m1) = (material(), PlaneStrain::new(560e6, 0.25, 2460.0));
        let table = [m0, m1].map(|m| BulkMaterial {
            d: m.d_matrix(),
            density: m.density,
        });
        let index: Vec<u8> = (0..mesh.elements.len())
            .map(|e| ((e * 7) % 3 == 0) as u8)
            .collect();
        let bulk = UnstructuredBulk::with_materials(&mesh, &table, &index).unwrap();
        let u = wobble(bulk.num_nodes());
        let f = forces(&bulk, &u);
        let g = reference_forces_of(&mesh, &|e| table[index[e] as usize].d, &u);
        let scale = g.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for (n, (a, b)) in f.iter().zip(&g).enumerate() {
            assert!((a - b).norm() <= 1e-12 * scale, "node {n}: {a} vs {b}");
        }
        let one_d = reference_forces(&mesh, &table[0].d, &u);
        assert!(f.iter().zip(&one_d).any(|(a, b)| (a - b).norm() > 1e-3 * scale));
        // masses: ρ_e A_e over the elements
        let area = |e: usize| {
            let c: Vec<Vector2<f64>> = mesh.elements[e]
                .nodes
                .iter()
                .map(|&a| mesh.positions[a])
                .collect();
            0.5 * (0..c.len())
                .map(|k| c[k].perp(&c[(k + 1) % c.len()]))
                .sum::<f64>()
        };
        let total: f64 = (0..mesh.elements.len())
            .map(|e| table[index[e] as usize].density * area(e))
            .sum();
        let summed: f64 = bulk.masses().iter().sum();
        assert!((summed - total).abs() <= 1e-12 * total, "{summed} vs {total}");
        let transit = (0..mesh.elements.len())
            .map(|e| element_length(&mesh, e) / table[index[e] as usize].cd())
            .fold(f64::INFINITY, f64::min);
        assert_eq!(bulk.min_transit_time(), transit);
        assert!(transit < bulk.min_length() / m0.wave_speeds().cd);
        let run = |threads: usize, bulk: &UnstructuredBulk| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| forces(bulk, &u))
        };
        assert_same_bits(&run(1, &bulk), &run(2, &bulk));
    }

    /// A table of one material repeated splits the elements into two runs of batches, which must
    /// give the forces of the one-material kernel: to round-off (1e-12 of the largest force, as
    /// the other kernel tests), since a node sums its elements in another order (by material
    /// first).
    #[test]
    fn a_table_of_one_material_gives_the_single_material_forces() {
        let mesh = distorted_mixed(30, 20, false);
        let m = material();
        let one = BulkMaterial {
            d: m.d_matrix(),
            density: m.density,
        };
        let single = UnstructuredBulk::new(&mesh, &one.d, one.density).unwrap();
        let index: Vec<u8> = (0..mesh.elements.len()).map(|e| (e % 2) as u8).collect();
        let table = UnstructuredBulk::with_materials(&mesh, &[one, one], &index).unwrap();
        let u = wobble(single.num_nodes());
        let (a, b) = (forces(&table, &u), forces(&single, &u));
        let scale = b.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for (n, (a, b)) in a.iter().zip(&b).enumerate() {
            assert!((a - b).norm() <= 1e-12 * scale, "node {n}: {a} vs {b}");
        }
        assert_eq!(table.masses(), single.masses());
        assert!(matches!(
            UnstructuredBulk::with_materials(&mesh, &[one], &index),
            Err(UnstructuredError::BadMaterials)
        ));
    }

    /// The static patch across two materials (`meshes/bimaterial.msh`, "soft" for x < 1 m,
    /// "stiff" beyond): under a uniform σ_xx = p with u_y = 0 (rollers on top and bottom), the
    /// exact field is u_x = p x/M₁ for x ≤ 1 m and p/M₁ + p (x − 1)/M₂ beyond (M = λ + 2G, each
    /// part's own compliance). Bilinear elements hold it exactly, so every node off the two ends
    /// is in equilibrium in x (and off the rollers in y) to round-off: 1e-10 of the end forces.
    /// The end forces sum to p times the bar's height, on the right end as on the left.
    #[test]
    fn a_uniform_stress_crosses_two_materials_exactly() {
        let mesh = committed("bimaterial.msh");
        let (soft, stiff) = (material(), PlaneStrain::new(560e6, 0.35, 2460.0));
        let table = [soft, stiff].map(|m| BulkMaterial {
            d: m.d_matrix(),
            density: m.density,
        });
        let mut index = vec![0u8; mesh.elements.len()];
        for &e in &mesh.groups["stiff"].elements {
            index[e] = 1;
        }
        let bulk = UnstructuredBulk::with_materials(&mesh, &table, &index).unwrap();
        let p = 1e5;
        let (m1, m2) = (table[0].d[0][0], table[1].d[0][0]);
        let u: Vec<Vector2<f64>> = mesh
            .positions
            .iter()
            .map(|x| {
                let ux = if x.x <= 1.0 {
                    p * x.x / m1
                } else {
                    p / m1 + p * (x.x - 1.0) / m2
                };
                Vector2::new(ux, 0.0)
            })
            .collect();
        let f = forces(&bulk, &u);
        let tol = 1e-10 * p * 0.06;
        let (mut left, mut right) = (0.0, 0.0);
        for (n, (x, fa)) in mesh.positions.iter().zip(&f).enumerate() {
            let end = x.x.abs() < 1e-9 || (x.x - 2.5).abs() < 1e-9;
            let roller = x.y.abs() < 1e-9 || (x.y - 0.06).abs() < 1e-9;
            if x.x.abs() < 1e-9 {
                left += fa.x;
            } else if (x.x - 2.5).abs() < 1e-9 {
                right += fa.x;
            }
            assert!(end || fa.x.abs() <= tol, "node {n} at {x}: f_x = {}", fa.x);
            assert!(roller || fa.y.abs() <= tol, "node {n} at {x}: f_y = {}", fa.y);
        }
        // f = −f_int: the left end's nodes need +p h to be held, the right end's −p h
        assert!((left - p * 0.06).abs() <= tol, "{left}");
        assert!((right + p * 0.06).abs() <= tol, "{right}");
    }
}
