//! The bulk kernel on unstructured meshes of T3 and Q4 elements ([`crate::gmsh::UnstructuredMesh`]):
//! lumped masses, the smallest element length of the stable step, and the race-free, deterministic
//! rayon evaluation of the internal forces: the bulk of a scene on a Gmsh mesh (docs/meshes.md).
//!
//! Elements (plane strain, thickness 1 m, so forces are per metre of thickness):
//! - **T3**, the constant-strain triangle: f_e = A t Bᵀ D B u_e with t = 1 m and the constant
//!   B = 1/(2A) [[b₀, 0, b₁, 0, b₂, 0], [0, c₀, 0, c₁, 0, c₂], [c₀, b₀, c₁, b₁, c₂, b₂]],
//!   b_i = y_j − y_k, c_i = x_k − x_j for (i, j, k) cyclic (Zienkiewicz, Taylor & Zhu, *The Finite
//!   Element Method: Its Basis and Fundamentals*, 7th ed., §6.2). Lumped mass ρA/3 per node (the
//!   row sum of the consistent mass).
//! - **Q4**, the bilinear quadrangle with 2×2 Gauss points: f_e = Σ_q B_qᵀ D B_q u_e det J_q, the
//!   K_e u_e of `model::bulk::stiffness`, and `model::bulk::lumped_mass`, the structured grid's
//!   element (docs/fem-model.md §1).
//!
//! Storage: no element matrix is stored. The kernel keeps the node positions (16 B per node), the
//! D of each material (one unless `[fem.mesh.materials]` gives more), the connectivity (12 B per T3, 16 B per Q4) and, per node, one 2-byte slot per
//! adjacent element. Each evaluation recomputes the element forces f_e = Bᵀσ from the positions,
//! as explicit codes do (Belytschko, Liu & Moran, *Nonlinear Finite Elements for Continua and
//! Structures*, ch. 4: internal nodal forces f_e = ∫ Bᵀσ dΩ from ε = B u_e and σ = D ε): about
//! 60 flops per T3 and 250 per Q4, vectorised over 8 elements at a time, where streaming a K_e
//! (288 B per T3, 512 B per Q4) from memory made the old kernel bandwidth-bound. For the Q4 the
//! Jacobians come from the edge vectors of the element, as in [`crate::model::mapped`].
//!
//! The nodes are cut, at build time, into tiles of consecutive nodes. Each tile lists the
//! elements adjacent to its nodes (those on a tile's edge are listed by both neighbours and
//! computed twice), computes their forces into a buffer on the stack (256 KiB: it stays in the
//! core's L2), and every node then sums its elements' forces from that buffer through its slots,
//! in a fixed order (elements sorted by their material, then their lowest node, then mesh index).
//! Each material's elements run in batches of their own with that material's D, so the batch
//! code is the one-material code whatever the number of materials. Tiles run in
//! parallel and write disjoint node ranges, so the result is the same to the bit for any number of
//! threads, and the element passes use the same operations with or without AVX-512.

use crate::gmsh::{ElementKind, UnstructuredMesh};
use crate::model::bulk;
use nalgebra::Vector2;
use thiserror::Error;

/// Elements per vector batch (structure of arrays, one lane per element).
const L: usize = 8;

/// f64 values of a tile's element-force buffer (256 KiB on the stack; must fit `u16` offsets).
const SCRATCH: usize = 32 * 1024;

/// Nodes per tile at least (unless the buffer is full first): a tile's work must dwarf the cost
/// of a rayon task.
const MIN_TILE_NODES: usize = 256;

/// Tiles per mesh aimed at, so that 2 threads balance; the buffer may force more.
const TARGET_TILES: usize = 16;

/// A mesh the unstructured kernel cannot be built on.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum UnstructuredError {
    /// An element with a non-positive (or non-finite) Jacobian determinant at a quadrature point:
    /// inverted or degenerate. The mesh reader refuses such elements; this guards meshes built by
    /// hand.
    #[error("element {element} is inverted or degenerate (det J = {det_j} m²)")]
    InvertedElement {
        /// Element tag ([`crate::gmsh::BulkElement::tag`]).
        element: u64,
        /// The offending determinant (T3: twice the signed area) [m²].
        det_j: f64,
    },
    /// A density that is not finite and positive.
    #[error("density = {0} kg/m³ must be finite and positive")]
    BadDensity(f64),
    /// No material, more than 256, or an element material index out of range or missing.
    #[error("every element needs a material index into 1 to 256 materials")]
    BadMaterials,
    /// More nodes or element entries than the 32-bit indices of the kernel hold, or a node with
    /// more elements than one tile's buffer holds.
    #[error("the mesh is too large for the kernel's 32-bit indices")]
    TooLarge,
}

/// A range of consecutive nodes and the elements adjacent to them.
#[derive(Debug, Clone, Copy)]
struct Tile {
    /// First node and one past the last.
    nodes: [u32; 2],
    /// Range of the tile's Q4 in `UnstructuredBulk::tile_q4`.
    q4: [u32; 2],
    /// Range of the tile's T3 in `UnstructuredBulk::tile_t3`.
    t3: [u32; 2],
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
    /// Node positions (x, y) [m].
    pos: Vec<[f64; 2]>,
    /// Plane-strain Voigt matrix D [Pa] of each material (at most 256).
    d: Vec<[[f64; 3]; 3]>,
    /// Node indices of each Q4, sorted by material, then lowest node, then mesh index.
    q4: Vec<[u32; 4]>,
    /// Node indices of each T3, sorted as the Q4.
    t3: Vec<[u32; 3]>,
    /// The Q4 of material m are `q4[q4_bound[m]..q4_bound[m + 1]]` (one entry per material, + 1).
    q4_bound: Vec<u32>,
    /// The T3 of material m are `t3[t3_bound[m]..t3_bound[m + 1]]`.
    t3_bound: Vec<u32>,
    /// The tiles, covering the nodes in order.
    tiles: Vec<Tile>,
    /// Each tile's Q4 (indices into `q4`), ascending.
    tile_q4: Vec<u32>,
    /// Each tile's T3 (indices into `t3`), ascending.
    tile_t3: Vec<u32>,
    /// CSR offsets into `slots` per node (length: nodes + 1).
    adj_start: Vec<u32>,
    /// Per node and adjacent element (in the fixed summation order): the offset, in its tile's
    /// buffer, of the x component of that element's force on the node (y is `L` further).
    slots: Vec<u16>,
    /// Lumped nodal masses [kg/m].
    mass: Vec<f64>,
    /// Smallest element length of the stable step [m] (see [`UnstructuredBulk::min_length`]).
    h_min: f64,
    /// Smallest transit time h_e/c_d,e over the elements [s] (see
    /// [`UnstructuredBulk::min_transit_time`]).
    min_transit: f64,
    /// Tiles one rayon task runs in a row (sharing one zeroed buffer), about 1/8 of the tiles.
    tiles_per_task: usize,
    /// The CPU has AVX-512F (the element passes run in 512-bit registers).
    avx512: bool,
}

/// Buffer values of `nq` Q4 and `nt` T3 (whole batches of L, 2 components per node).
fn buffer_len(nq: usize, nt: usize) -> usize {
    nq.div_ceil(L) * L * 8 + nt.div_ceil(L) * L * 6
}

/// The most buffer values `nq` Q4 and `nt` T3 of `materials` materials take: each material's
/// elements start a batch of their own, so each material after the first may add a partial batch
/// of each kind.
fn padded_len(nq: usize, nt: usize, materials: usize) -> usize {
    buffer_len(nq, nt) + (materials - 1) * L * (8 + 6)
}

/// The material m whose range `bound[m]..bound[m + 1]` holds element `i`.
fn material_in(bound: &[u32], i: u32) -> usize {
    bound.partition_point(|&b| b <= i) - 1
}

impl UnstructuredBulk {
    /// Builds the kernel on `mesh` with the plane-strain Voigt matrix `d` [Pa]
    /// ([`crate::law::elastic::PlaneStrain::d_matrix`]) and the density `density` [kg/m³].
    pub fn new(mesh: &UnstructuredMesh, d: &[[f64; 3]; 3], density: f64) -> Result<Self, UnstructuredError> {
        Self::with_materials(mesh, &[BulkMaterial { d: *d, density }], &[])
    }

    /// Builds the kernel on `mesh` with several materials: element e (in the mesh's order) is of
    /// `materials[element_material[e]]`; an empty `element_material` puts every element in
    /// `materials[0]`. Masses, forces and the stable step then use each element's own material.
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
        let total: usize = mesh.elements.iter().map(|e| e.nodes.len()).sum();
        if nn >= u32::MAX as usize || total >= u32::MAX as usize {
            return Err(UnstructuredError::TooLarge);
        }
        let x = &mesh.positions;

        // validity and masses
        let mut mass = vec![0.0; nn];
        for (e, el) in mesh.elements.iter().enumerate() {
            let density = materials[material_of(e)].density;
            let inverted = |det_j: f64| UnstructuredError::InvertedElement {
                element: el.tag,
                det_j,
            };
            let m = match el.kind {
                ElementKind::T3 => {
                    let c = [x[el.nodes[0]], x[el.nodes[1]], x[el.nodes[2]]];
                    let two_a = (c[1] - c[0]).perp(&(c[2] - c[0]));
                    if two_a <= 0.0 || !two_a.is_finite() {
                        return Err(inverted(two_a));
                    }
                    vec![density * (0.5 * two_a) / 3.0; 3]
                }
                ElementKind::Q4 => {
                    let c = [x[el.nodes[0]], x[el.nodes[1]], x[el.nodes[2]], x[el.nodes[3]]];
                    let g = 1.0 / 3f64.sqrt();
                    for &(s, t) in &bulk::GAUSS_SIGNS {
                        let (_, det) = bulk::shape_gradients(&c, s * g, t * g);
                        if det <= 0.0 || !det.is_finite() {
                            return Err(inverted(det));
                        }
                    }
                    bulk::lumped_mass(&c, density).to_vec()
                }
            };
            for (&a, ma) in el.nodes.iter().zip(m) {
                mass[a] += ma;
            }
        }
        let h_min = min_element_length(mesh);
        let min_transit = (0..mesh.elements.len())
            .map(|e| element_length(mesh, e) / materials[material_of(e)].cd())
            .fold(f64::INFINITY, f64::min);

        // the kernel's element order: by material (each material's elements run in batches of
        // their own, with one D), then lowest node, then mesh index (elements that share nodes
        // end up close together, whatever order the mesh file has them in)
        let mut order: Vec<usize> = (0..mesh.elements.len()).collect();
        order.sort_by_key(|&e| (material_of(e), mesh.elements[e].nodes.iter().min().copied(), e));
        let mut q4 = Vec::new();
        let mut t3 = Vec::new();
        let nm = materials.len();
        let (mut q4_bound, mut t3_bound) = (vec![0u32; nm + 1], vec![0u32; nm + 1]);
        // node → (Q4?, index in q4 or t3, local node) in CSR form, in the kernel's element order
        let mut adj_start = vec![0u32; nn + 1];
        for &a in mesh.elements.iter().flat_map(|el| &el.nodes) {
            adj_start[a + 1] += 1;
        }
        for a in 0..nn {
            adj_start[a + 1] += adj_start[a];
        }
        let mut fill: Vec<u32> = adj_start[..nn].to_vec();
        let mut adj = vec![(false, 0u32, 0u8); total];
        for &e in &order {
            let el = &mesh.elements[e];
            let (is_q4, index) = match el.kind {
                ElementKind::Q4 => {
                    q4.push([0, 1, 2, 3].map(|k| el.nodes[k] as u32));
                    q4_bound[material_of(e) + 1] += 1;
                    (true, q4.len() - 1)
                }
                ElementKind::T3 => {
                    t3.push([0, 1, 2].map(|k| el.nodes[k] as u32));
                    t3_bound[material_of(e) + 1] += 1;
                    (false, t3.len() - 1)
                }
            };
            for (la, &a) in el.nodes.iter().enumerate() {
                adj[fill[a] as usize] = (is_q4, index as u32, la as u8);
                fill[a] += 1;
            }
        }
        for m in 0..nm {
            q4_bound[m + 1] += q4_bound[m];
            t3_bound[m + 1] += t3_bound[m];
        }
        let adj_of = |a: usize| &adj[adj_start[a] as usize..adj_start[a + 1] as usize];

        // tiles: consecutive nodes while their elements fit the buffer
        let max_nodes = nn.div_ceil(TARGET_TILES).max(MIN_TILE_NODES);
        let mut seen_q4 = vec![u32::MAX; q4.len()];
        let mut seen_t3 = vec![u32::MAX; t3.len()];
        let (mut tiles, mut tile_q4, mut tile_t3) = (Vec::new(), Vec::new(), Vec::new());
        let mut a = 0;
        while a < nn {
            let id = tiles.len() as u32;
            let (first, q_first, t_first) = (a, tile_q4.len(), tile_t3.len());
            while a < nn && a - first < max_nodes {
                let fresh = |is_q4: bool| {
                    adj_of(a)
                        .iter()
                        .filter(|&&(q, i, _)| {
                            q == is_q4
                                && if q {
                                    seen_q4[i as usize]
                                } else {
                                    seen_t3[i as usize]
                                } != id
                        })
                        .count()
                };
                let (nq, nt) = (
                    tile_q4.len() - q_first + fresh(true),
                    tile_t3.len() - t_first + fresh(false),
                );
                if padded_len(nq, nt, nm) > SCRATCH {
                    if a == first {
                        return Err(UnstructuredError::TooLarge);
                    }
                    break;
                }
                for &(is_q4, i, _) in adj_of(a) {
                    let (seen, list) = if is_q4 {
                        (&mut seen_q4[i as usize], &mut tile_q4)
                    } else {
                        (&mut seen_t3[i as usize], &mut tile_t3)
                    };
                    if *seen != id {
                        *seen = id;
                        list.push(i);
                    }
                }
                a += 1;
            }
            tile_q4[q_first..].sort_unstable();
            tile_t3[t_first..].sort_unstable();
            tiles.push(Tile {
                nodes: [first as u32, a as u32],
                q4: [q_first as u32, tile_q4.len() as u32],
                t3: [t_first as u32, tile_t3.len() as u32],
            });
        }

        // each node's slots in its tile's buffer (Q4 batches first, then T3 batches; in a batch
        // of L elements, node k's x components at 2kL + lane, its y components L further)
        let mut slot_q4 = vec![0usize; q4.len()];
        let mut slot_t3 = vec![0usize; t3.len()];
        let mut slots = Vec::with_capacity(total);
        for t in &tiles {
            let (lq, lt) = (
                &tile_q4[t.q4[0] as usize..t.q4[1] as usize],
                &tile_t3[t.t3[0] as usize..t.t3[1] as usize],
            );
            let t3_base = padded_slots(lq, &q4_bound, 8, 0, &mut slot_q4);
            padded_slots(lt, &t3_bound, 6, t3_base, &mut slot_t3);
            for a in t.nodes[0] as usize..t.nodes[1] as usize {
                for &(is_q4, i, la) in adj_of(a) {
                    let base = if is_q4 {
                        slot_q4[i as usize]
                    } else {
                        slot_t3[i as usize]
                    };
                    let slot = base + 2 * L * la as usize;
                    // the gather masks its indices instead of checking them: they must be in range
                    debug_assert!(slot + L < SCRATCH, "slot {slot} outside the tile buffer");
                    slots.push(slot as u16);
                }
            }
        }

        let tiles_per_task = (tiles.len() / 8).max(1);
        Ok(Self {
            pos: x.iter().map(|p| [p.x, p.y]).collect(),
            d: materials.iter().map(|m| m.d).collect(),
            q4,
            t3,
            q4_bound,
            t3_bound,
            tiles,
            tile_q4,
            tile_t3,
            adj_start,
            slots,
            mass,
            h_min,
            min_transit,
            tiles_per_task,
            avx512: avx512(),
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

    /// Bytes of the kernel's arrays (positions, connectivity, tiles and slots, masses).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(&self.pos[..])
            + size_of_val(&self.q4[..])
            + size_of_val(&self.t3[..])
            + size_of_val(&self.q4_bound[..])
            + size_of_val(&self.t3_bound[..])
            + size_of_val(&self.tiles[..])
            + size_of_val(&self.tile_q4[..])
            + size_of_val(&self.tile_t3[..])
            + size_of_val(&self.adj_start[..])
            + size_of_val(&self.slots[..])
            + size_of_val(&self.mass[..])
    }

    /// f = −f_int(u) [N/m] for displacements `u` [m] (overwrites `f`): every node gathers
    /// f_a = −Σ_e f_e[a] over its elements in a fixed order (see the module documentation).
    /// Parallel over tiles of nodes; each task writes only its own nodes and each node's sum has a
    /// fixed order, so the result is the same to the bit for any number of threads. Allocates
    /// nothing.
    pub fn internal_forces(&self, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
        assert_eq!(u.len(), self.num_nodes(), "one displacement per node");
        assert_eq!(f.len(), self.num_nodes(), "one force per node");
        self.run(&self.tiles, bytemuck::cast_slice(u), f);
    }

    /// The tiles `tiles`, whose nodes are those of `f`, split in halves across rayon tasks.
    fn run(&self, tiles: &[Tile], u: &[[f64; 2]], f: &mut [Vector2<f64>]) {
        match tiles {
            [] => {}
            _ if tiles.len() <= self.tiles_per_task => self.tiles(tiles, u, f),
            _ => {
                let mid = tiles.len() / 2;
                let split = (tiles[mid].nodes[0] - tiles[0].nodes[0]) as usize;
                let (lo, hi) = f.split_at_mut(split);
                rayon::join(
                    || self.run(&tiles[..mid], u, lo),
                    || self.run(&tiles[mid..], u, hi),
                );
            }
        }
    }

    /// Consecutive tiles, whose nodes are those of `f`, one after the other with one buffer.
    fn tiles(&self, tiles: &[Tile], u: &[[f64; 2]], f: &mut [Vector2<f64>]) {
        let mut buf = [0.0f64; SCRATCH];
        let first = tiles.first().map_or(0, |t| t.nodes[0]);
        for t in tiles {
            let nodes = (t.nodes[0] - first) as usize..(t.nodes[1] - first) as usize;
            self.tile(t, u, &mut f[nodes], &mut buf);
        }
    }

    /// One tile: its element forces into `buf`, then each node's sum.
    fn tile(&self, t: &Tile, u: &[[f64; 2]], f: &mut [Vector2<f64>], buf: &mut [f64; SCRATCH]) {
        let q = &self.tile_q4[t.q4[0] as usize..t.q4[1] as usize];
        let tr = &self.tile_t3[t.t3[0] as usize..t.t3[1] as usize];
        self.element_forces(q, tr, u, buf);
        let first = t.nodes[0] as usize;
        for (i, fa) in f.iter_mut().enumerate() {
            let a = first + i;
            let slots = &self.slots[self.adj_start[a] as usize..self.adj_start[a + 1] as usize];
            let (mut fx, mut fy) = (0.0, 0.0);
            for &s in slots {
                // (the masks keep the indices in range without a check: SCRATCH is a power of 2)
                fx += buf[s as usize % SCRATCH];
                fy += buf[(s as usize + L) % SCRATCH];
            }
            *fa = -Vector2::new(fx, fy);
        }
    }

    /// The forces f_e = K_e u_e of the Q4 `q` and the T3 `tr` into `buf` (layout: see
    /// `slots`), with AVX-512 if the CPU has it (same operations, same bits).
    fn element_forces(&self, q: &[u32], tr: &[u32], u: &[[f64; 2]], buf: &mut [f64; SCRATCH]) {
        #[cfg(target_arch = "x86_64")]
        if self.avx512 {
            // SAFETY: `avx512` is true only if the CPU reported AVX-512F at run time (`avx512()`).
            return unsafe { element_forces_avx512(self, q, tr, u, buf) };
        }
        element_forces(self, q, tr, u, buf)
    }
}

/// The buffer offsets (x component, lane) of the elements `list` of one kind (ascending; `bound`
/// its materials' ranges, `values` its buffer values per element: 8 for a Q4, 6 for a T3) from
/// `base` on, each material's run starting a batch of its own, into `slot`; returns the offset
/// after the last batch.
fn padded_slots(list: &[u32], bound: &[u32], values: usize, base: usize, slot: &mut [usize]) -> usize {
    let (mut run_base, mut run_first, mut run_material) = (base, 0, usize::MAX);
    for (p, &i) in list.iter().enumerate() {
        let m = material_in(bound, i);
        if m != run_material {
            run_base += (p - run_first).div_ceil(L) * L * values;
            (run_first, run_material) = (p, m);
        }
        let r = p - run_first;
        slot[i as usize] = run_base + (r / L) * values * L + r % L;
    }
    run_base + (list.len() - run_first).div_ceil(L) * L * values
}

/// Whether the element passes may use AVX-512F.
fn avx512() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx512f")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn element_forces_avx512(
    k: &UnstructuredBulk,
    q: &[u32],
    tr: &[u32],
    u: &[[f64; 2]],
    buf: &mut [f64; SCRATCH],
) {
    element_forces(k, q, tr, u, buf)
}

/// Corner values of a batch: `[a][l][k]` for corner a, lane l, and k = x, y [m], u_x, u_y [m]
/// (two 16-byte copies per corner; the element loops read them with strided vector loads).
type Batch<const N: usize> = [[[f64; 4]; L]; N];

/// Portable element passes: batches of L elements in structure-of-arrays form; every lane runs
/// the same scalar operations (no fused multiply-add: Rust never contracts), so the vector width
/// does not change a bit. The corner values of the next batch are gathered before the current
/// one is computed: vector loads of values just stored one lane at a time would stall on store
/// forwarding.
#[inline(always)]
fn element_forces(k: &UnstructuredBulk, q: &[u32], tr: &[u32], u: &[[f64; 2]], buf: &mut [f64; SCRATCH]) {
    // each material's elements (a run of the ascending list) in batches of their own, with its D
    // (with one material, one run: the whole list), Q4 first, then T3 (the layout of `slots`)
    let mut at = 0;
    let mut rest = q;
    for (m, d) in k.d.iter().enumerate() {
        let run;
        (run, rest) = rest.split_at(rest.partition_point(|&i| i < k.q4_bound[m + 1]));
        let len = buffer_len(run.len(), 0);
        batches::<4, Q4Pass>(&k.q4, &k.pos, d, u, run, &mut buf[at..at + len]);
        at += len;
    }
    let mut rest = tr;
    for (m, d) in k.d.iter().enumerate() {
        let run;
        (run, rest) = rest.split_at(rest.partition_point(|&i| i < k.t3_bound[m + 1]));
        let len = buffer_len(0, run.len());
        batches::<3, T3Pass>(&k.t3, &k.pos, d, u, run, &mut buf[at..at + len]);
        at += len;
    }
}

/// The force computation of one batch of an element kind with N corners. A trait rather than a
/// closure: closures are not inlined into the AVX-512 pass, which stops its vectorisation.
trait BatchPass<const N: usize> {
    /// Forces of the batch `w` into `out` (2NL values).
    fn forces(w: &Batch<N>, d: &[[f64; 3]; 3], out: &mut [f64]);
}

/// Q4 batches ([`q4_batch`]).
struct Q4Pass;
/// T3 batches ([`t3_batch`]).
struct T3Pass;

impl BatchPass<4> for Q4Pass {
    #[inline(always)]
    fn forces(w: &Batch<4>, d: &[[f64; 3]; 3], out: &mut [f64]) {
        q4_batch(w, d, out)
    }
}

impl BatchPass<3> for T3Pass {
    #[inline(always)]
    fn forces(w: &Batch<3>, d: &[[f64; 3]; 3], out: &mut [f64]) {
        t3_batch(w, d, out)
    }
}

/// One kind's element pass: the elements `list` in batches of L, each batch's forces (2N values
/// per lane) into the next 2NL values of `out`, the next batch's corners gathered first.
#[inline(always)]
fn batches<const N: usize, P: BatchPass<N>>(
    conn: &[[u32; N]],
    pos: &[[f64; 2]],
    d: &[[f64; 3]; 3],
    u: &[[f64; 2]],
    list: &[u32],
    out: &mut [f64],
) {
    let mut stage = [[[[0.0; 4]; L]; N]; 2];
    let (s0, s1) = stage.split_at_mut(1);
    let (mut cur, mut next) = (&mut s0[0], &mut s1[0]);
    let mut chunks = list.chunks(L);
    if let Some(c) = chunks.next() {
        gather(conn, pos, u, c, cur);
    }
    for out in out.chunks_exact_mut(2 * N * L) {
        if let Some(c) = chunks.next() {
            gather(conn, pos, u, c, next);
        }
        P::forces(cur, d, out);
        std::mem::swap(&mut cur, &mut next);
    }
}

/// The corner positions and displacements of the elements `chunk` (1 to L of them; the last
/// one fills the lanes left over).
#[inline(always)]
fn gather<const N: usize>(
    conn: &[[u32; N]],
    pos: &[[f64; 2]],
    u: &[[f64; 2]],
    chunk: &[u32],
    dst: &mut Batch<N>,
) {
    for l in 0..L {
        let nodes = conn[chunk[l.min(chunk.len() - 1)] as usize];
        for (a, &n) in nodes.iter().enumerate() {
            let (p, v) = (pos[n as usize], u[n as usize]);
            dst[a][l] = [p[0], p[1], v[0], v[1]];
        }
    }
}

/// K_e u_e of L constant-strain triangles (corner values `w`, see [`Batch`]) into
/// out[(2a + c)L + l] [N/m] for corner a, component c, lane l. ε = B u_e, σ = D ε,
/// f_a = A B_aᵀσ = ½ (b_a σ_xx + c_a σ_xy, c_a σ_yy + b_a σ_xy).
#[inline(always)]
fn t3_batch(w: &Batch<3>, d: &[[f64; 3]; 3], out: &mut [f64]) {
    let out: &mut [f64; 6 * L] = out.try_into().expect("a T3 batch is 6L values");
    for l in 0..L {
        let (x0, x1, x2) = (w[0][l][0], w[1][l][0], w[2][l][0]);
        let (y0, y1, y2) = (w[0][l][1], w[1][l][1], w[2][l][1]);
        let b = [y1 - y2, y2 - y0, y0 - y1];
        let c = [x2 - x1, x0 - x2, x1 - x0];
        let inv = 1.0 / ((x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0));
        let mut e = [0.0; 3];
        for a in 0..3 {
            let (ux, uy) = (w[a][l][2], w[a][l][3]);
            e[0] += b[a] * ux;
            e[1] += c[a] * uy;
            e[2] += c[a] * ux + b[a] * uy;
        }
        let e = [e[0] * inv, e[1] * inv, e[2] * inv];
        let s = [
            d[0][0] * e[0] + d[0][1] * e[1] + d[0][2] * e[2],
            d[1][0] * e[0] + d[1][1] * e[1] + d[1][2] * e[2],
            d[2][0] * e[0] + d[2][1] * e[1] + d[2][2] * e[2],
        ];
        for a in 0..3 {
            out[2 * a * L + l] = 0.5 * (b[a] * s[0] + c[a] * s[2]);
            out[(2 * a + 1) * L + l] = 0.5 * (c[a] * s[1] + b[a] * s[2]);
        }
    }
}

/// K_e u_e of L bilinear quadrangles, 2×2 Gauss (layout as [`t3_batch`]). With the edge
/// differences, 4 ∂v/∂ξ(η) = (v₁ − v₀)(1 − η) + (v₂ − v₃)(1 + η) and
/// 4 ∂v/∂η(ξ) = (v₃ − v₀)(1 − ξ) + (v₂ − v₁)(1 + ξ) for v = x and v = u give J and ∇_ξ u at each
/// Gauss point; ∇u = ∇_ξ u J⁻¹, σ = D ε, and det J B_aᵀσ = N_a,ξ P + N_a,η Q with
/// P = (y_η σ_xx − x_η σ_xy, y_η σ_xy − x_η σ_yy), Q = (x_ξ σ_xy − y_ξ σ_xx, x_ξ σ_yy − y_ξ σ_xy)
/// (the cofactors of J: no inverse in the force). With N_a,ξ = ¼ξ_a(1 + ηη_a),
/// N_a,η = ¼η_a(1 + ξξ_a) the Gauss sums collapse to f_a = ¼[ξ_a(ΣP + η_a ΣηP) + η_a(ΣQ + ξ_a ΣξQ)]
/// (the same structure as `model::mapped::element_forces`).
#[inline(always)]
fn q4_batch(w: &Batch<4>, d: &[[f64; 3]; 3], out: &mut [f64]) {
    let out: &mut [f64; 8 * L] = out.try_into().expect("a Q4 batch is 8L values");
    let g = 1.0 / 3f64.sqrt();
    // one element per lane, in a loop the optimiser vectorises (straight-line code, no calls)
    for l in 0..L {
        // [k] = x, y, u_x, u_y: 4 ∂/∂ξ at η = −g, +g and 4 ∂/∂η at ξ = −g, +g
        let dv = [
            q4_derivatives(w, 0, l, g),
            q4_derivatives(w, 1, l, g),
            q4_derivatives(w, 2, l, g),
            q4_derivatives(w, 3, l, g),
        ];
        // Gauss points (ξ, η) = g(−1, −1), g(1, −1), g(1, 1), g(−1, 1): (η index, ξ index) into
        // the derivative pairs; 1/det J at all four from one division (16 det J = 4h² for an
        // element of size h: the product of four stays within f64 for 1e-18 m < h < 1e18 m)
        let gp = [(0, 0), (0, 1), (1, 1), (1, 0)];
        let det = [
            q4_det(&dv, gp[0]),
            q4_det(&dv, gp[1]),
            q4_det(&dv, gp[2]),
            q4_det(&dv, gp[3]),
        ];
        let (d01, d23) = (det[0] * det[1], det[2] * det[3]);
        let r = 1.0 / (d01 * d23);
        let (r01, r23) = (d23 * r, d01 * r);
        let inv = [det[1] * r01, det[0] * r01, det[3] * r23, det[2] * r23];
        let (p0, q0) = gauss_point(&dv, gp[0], inv[0], d);
        let (p1, q1) = gauss_point(&dv, gp[1], inv[1], d);
        let (p2, q2) = gauss_point(&dv, gp[2], inv[2], d);
        let (p3, q3) = gauss_point(&dv, gp[3], inv[3], d);
        // P and Q are 4× the true ones (the derivatives are 4× too): f_a carries 1/16
        for c in 0..2 {
            let (p_sum, p_eta) = (
                (p0[c] + p1[c]) + (p2[c] + p3[c]),
                (p2[c] + p3[c]) - (p0[c] + p1[c]),
            );
            let (q_sum, q_xi) = (
                (q0[c] + q3[c]) + (q1[c] + q2[c]),
                (q1[c] + q2[c]) - (q0[c] + q3[c]),
            );
            let (pm, pp) = (p_sum - g * p_eta, p_sum + g * p_eta);
            let (qm, qp) = (q_sum - g * q_xi, q_sum + g * q_xi);
            out[c * L + l] = -0.0625 * (pm + qm);
            out[(2 + c) * L + l] = 0.0625 * (pm - qp);
            out[(4 + c) * L + l] = 0.0625 * (pp + qp);
            out[(6 + c) * L + l] = 0.0625 * (qm - pp);
        }
    }
}

/// 4 ∂v/∂ξ at η = −g, +g and 4 ∂v/∂η at ξ = −g, +g of corner value `k` (see [`Batch`]) in lane
/// `l`.
#[inline(always)]
fn q4_derivatives(w: &Batch<4>, k: usize, l: usize, g: f64) -> [[f64; 2]; 2] {
    let (v0, v1, v2, v3) = (w[0][l][k], w[1][l][k], w[2][l][k], w[3][l][k]);
    let (a, b, c, e) = (v1 - v0, v2 - v3, v3 - v0, v2 - v1);
    let (sx, dx, se, de) = (a + b, g * (b - a), c + e, g * (e - c));
    [[sx - dx, sx + dx], [se - de, se + de]]
}

/// 16 det J = 4x_ξ 4y_η − 4x_η 4y_ξ at Gauss point (η index, ξ index) of [`q4_batch`].
#[inline(always)]
fn q4_det(dv: &[[[f64; 2]; 2]; 4], (ie, ix): (usize, usize)) -> f64 {
    dv[0][0][ie] * dv[1][1][ix] - dv[0][1][ix] * dv[1][0][ie]
}

/// (4P, 4Q) of [`q4_batch`] at the Gauss point with η index `ie` and ξ index `ix` (0: −g, 1: +g),
/// from the derivatives `dv` of [`q4_derivatives`] and `inv` = 1/(16 det J) there.
#[inline(always)]
fn gauss_point(
    dv: &[[[f64; 2]; 2]; 4],
    (ie, ix): (usize, usize),
    inv: f64,
    d: &[[f64; 3]; 3],
) -> ([f64; 2], [f64; 2]) {
    let (xx, yx, uxx, uyx) = (dv[0][0][ie], dv[1][0][ie], dv[2][0][ie], dv[3][0][ie]);
    let (xe, ye, uxe, uye) = (dv[0][1][ix], dv[1][1][ix], dv[2][1][ix], dv[3][1][ix]);
    let e0 = (uxx * ye - uxe * yx) * inv;
    let e1 = (uye * xx - uyx * xe) * inv;
    let e2 = (uxe * xx - uxx * xe + uyx * ye - uye * yx) * inv;
    let s0 = d[0][0] * e0 + d[0][1] * e1 + d[0][2] * e2;
    let s1 = d[1][0] * e0 + d[1][1] * e1 + d[1][2] * e2;
    let s2 = d[2][0] * e0 + d[2][1] * e1 + d[2][2] * e2;
    (
        [ye * s0 - xe * s2, ye * s2 - xe * s1],
        [xx * s2 - yx * s0, xx * s1 - yx * s2],
    )
}

/// The smallest element length h_min [m] of `mesh` ([`UnstructuredBulk::min_length`]): per
/// element 2A/ℓ_max for a T3 and A/ℓ_max for a Q4 (ℓ_max its longest edge); ∞ for a mesh without
/// elements.
pub fn min_element_length(mesh: &UnstructuredMesh) -> f64 {
    (0..mesh.elements.len())
        .map(|e| element_length(mesh, e))
        .fold(f64::INFINITY, f64::min)
}

/// The length h_e [m] of element `e` of the stable step: 2A/ℓ_max for a T3, A/ℓ_max for a Q4.
pub fn element_length(mesh: &UnstructuredMesh, e: usize) -> f64 {
    let (x, el) = (&mesh.positions, &mesh.elements[e]);
    let c = |k: usize| x[el.nodes[k]];
    let n = el.nodes.len();
    let longest = (0..n).map(|k| (c((k + 1) % n) - c(k)).norm()).fold(0.0, f64::max);
    match el.kind {
        ElementKind::T3 => (c(1) - c(0)).perp(&(c(2) - c(0))) / longest,
        ElementKind::Q4 => 0.5 * ((c(2) - c(0)).perp(&(c(3) - c(1)))) / longest,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gmsh::BulkElement;
    use crate::law::elastic::PlaneStrain;
    use crate::mesh::structured::{Grid, GridSpec};
    use std::collections::BTreeMap;

    /// The reference the kernel is checked against: the constant-strain triangle K_e = A t Bᵀ D B (t = 1 m) [N/m per m], DOF order x₀, y₀, x₁, y₁,
    /// x₂, y₂; Err(2A) [m²] for a clockwise or degenerate triangle.
    fn cst_stiffness(c: &[Vector2<f64>; 3], d: &[[f64; 3]; 3]) -> Result<[[f64; 6]; 6], f64> {
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

    /// The AVX-512 element passes give the bits of the portable ones (the output must not depend
    /// on the CPU it runs on); on a CPU without AVX-512 both runs take the portable path.
    #[test]
    fn vector_paths_agree_bit_for_bit() {
        let mesh = distorted_mixed(30, 20, false);
        let mat = material();
        let mut bulk = UnstructuredBulk::new(&mesh, &mat.d_matrix(), mat.density).unwrap();
        let u = wobble(bulk.num_nodes());
        let dispatched = forces(&bulk, &u);
        bulk.avx512 = false;
        let portable = forces(&bulk, &u);
        assert_same_bits(&portable, &dispatched);
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
    /// bits on 1 and 2 threads and on both vector paths, and the smallest transit time against
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
        let mut bulk = UnstructuredBulk::with_materials(&mesh, &table, &index).unwrap();
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
        bulk.avx512 = false;
        assert_same_bits(&forces(&bulk, &u), &f);
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
