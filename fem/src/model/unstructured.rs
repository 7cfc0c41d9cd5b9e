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
//! reverse Cuthill–McKee, taken when more than 1 % of the mesh's edges join nodes over 1 024
//! apart and the new order halves that count (Gmsh numbers the nodes of the curves before those
//! of the surfaces); u and f then pass through buffers in that order. The nodes are cut, at build
//! time, into tiles of consecutive nodes (in the kernel's order). A tile runs its nodes in order: each node first sums its edges from nodes of earlier tiles (recomputed there, as the
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

/// An edge is far when its ends are more than this many nodes apart in the kernel's order: their
/// displacements are then more than 16 KiB apart, half the L1 data cache of common x86 cores, and
/// the read of the far end tends to miss it ([`kernel_order`]).
const FAR_EDGE: u32 = 1024;

/// Largest share of far edges for which the kernel keeps the mesh's node order ([`kernel_order`]).
const FAR_EDGE_SHARE: f64 = 0.01;

/// Nodes per rayon task of the copies into and out of the kernel's node order.
const COPY_CHUNK: usize = 4096;

/// Edges ahead of the node at hand whose blocks the kernel asks of the cache (4 KiB of blocks,
/// 32 nodes of a quadrangle mesh). The blocks stream at 96 to 128 bytes a node; once they outgrew
/// the last-level cache, the kernel ran at less than half its in-cache rate, and asking for them
/// ahead won back most of it (docs/performance.md, "Unstructured bulk kernel").
const BLOCKS_AHEAD: usize = 128;

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
        check_materials(mesh, materials, element_material)?;
        let single = element_material.is_empty();
        let material_of = |e: usize| if single { 0 } else { element_material[e] as usize };
        let nn = mesh.positions.len();
        if nn >= u32::MAX as usize {
            return Err(UnstructuredError::TooLarge);
        }
        let (mass, entries) = element_blocks(mesh, materials, &material_of)?;
        let h_min = min_element_length(mesh);
        let min_transit = (0..mesh.elements.len())
            .map(|e| element_length(mesh, e) / materials[material_of(e)].cd())
            .fold(f64::INFINITY, f64::min);
        let mut pairs = sum_edges(entries);
        if pairs.len() >= u32::MAX as usize {
            return Err(UnstructuredError::TooLarge);
        }
        let (order, rank) = kernel_order(nn, &mut pairs);
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
        let (tiles, in_start, in_edge) = tiles_and_incoming(nn, &edge_start, &other);
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

    /// The tiles `tiles`, whose nodes are those of `f`, split in halves across rayon tasks down
    /// to one tile a task. Beside the contact detection, which holds one thread for a while, the
    /// thread that comes free then takes a tile's worth of work, not half of the mesh's, and the
    /// two finish close together (docs/performance.md, "One tile a task").
    fn run(&self, tiles: &[[u32; 2]], u: &[[f64; 2]], f: &mut [[f64; 2]]) {
        match tiles {
            [] => {}
            [t] => self.tile(*t, u, f),
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
            // the blocks BLOCKS_AHEAD edges on, two cache lines: a Q4 node's four blocks
            crate::hint::prefetch(bl, edges.start + BLOCKS_AHEAD);
            crate::hint::prefetch(bl, edges.start + BLOCKS_AHEAD + 2);
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

/// Refuses a density that is not finite and positive, and a material table or element material
/// list that does not fit the mesh (none, more than 256, an index out of range or missing).
fn check_materials(
    mesh: &UnstructuredMesh,
    materials: &[BulkMaterial],
    element_material: &[u8],
) -> Result<(), UnstructuredError> {
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
    Ok(())
}

/// An edge block (a, b, K_ab) of the assembled stiffness [N/m²], a < b, K_ab row-major.
type EdgeBlock = (u32, u32, [f64; 4]);

/// Validity, lumped masses [kg/m] and the element stiffnesses' blocks (a, b, K_ab) for a < b, in
/// the mesh's element order, each element with its own material.
fn element_blocks(
    mesh: &UnstructuredMesh,
    materials: &[BulkMaterial],
    material_of: &dyn Fn(usize) -> usize,
) -> Result<(Vec<f64>, Vec<EdgeBlock>), UnstructuredError> {
    let x = &mesh.positions;
    let mut mass = vec![0.0; x.len()];
    let mut entries: Vec<EdgeBlock> = Vec::new();
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
    Ok((mass, entries))
}

/// The edges: blocks of the same pair summed in the mesh's element order (a stable sort).
fn sum_edges(mut entries: Vec<EdgeBlock>) -> Vec<EdgeBlock> {
    entries.sort_by_key(|&(a, b, _)| (a, b));
    let mut pairs: Vec<EdgeBlock> = Vec::new();
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
    pairs
}

/// The kernel's node order (order, rank), both empty for the mesh's own. What the order buys is
/// locality: an edge whose ends are close in the order reads u_b from a cache line read a moment
/// before. What it costs is the two copies into and out of that order at every evaluation, each a
/// gather through a permutation. So the mesh's own order is kept unless more than
/// [`FAR_EDGE_SHARE`] of its edges join nodes more than [`FAR_EDGE`] apart and reverse
/// Cuthill–McKee halves that count. Gmsh numbers the nodes of the curves first, then those of the
/// surfaces: on center-crack-tri's mesh 57 % of the edges are far, none after the reordering. A
/// grid numbered row by row has none, but the twins that splitting its interface appends at the
/// end (0.3 % of the edges of the centre crack's grid as a Gmsh mesh): there the copies would cost
/// more than those few edges (docs/performance.md, "Every mesh kind side by side"). With the new
/// order the edges are renumbered with a < b, the block transposed where the ends swap
/// (K_ba = K_abᵀ).
fn kernel_order(nn: usize, pairs: &mut [EdgeBlock]) -> (Vec<u32>, Vec<u32>) {
    let far = |pairs: &[EdgeBlock], rank: &dyn Fn(u32) -> u32| {
        pairs
            .iter()
            .filter(|&&(a, b, _)| rank(a).abs_diff(rank(b)) > FAR_EDGE)
            .count()
    };
    let far_in_mesh = far(pairs, &|n| n);
    if far_in_mesh as f64 <= FAR_EDGE_SHARE * pairs.len() as f64 {
        return (Vec::new(), Vec::new());
    }
    let cm = reverse_cuthill_mckee(nn, pairs);
    let mut rank = vec![0u32; nn];
    for (new, &old) in cm.iter().enumerate() {
        rank[old as usize] = new as u32;
    }
    if 2 * far(pairs, &|n| rank[n as usize]) >= far_in_mesh {
        return (Vec::new(), Vec::new());
    }
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
}

/// Tiles of consecutive nodes ([first, end) each), and each node's edges from earlier tiles as a
/// compressed list: `in_start` (per node, into `in_edge`) and `in_edge` ([edge, its first node]).
fn tiles_and_incoming(
    nn: usize,
    edge_start: &[u32],
    other: &[u32],
) -> (Vec<[u32; 2]>, Vec<u32>, Vec<[u32; 2]>) {
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
    (tiles, in_start, in_edge)
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
mod tests;
