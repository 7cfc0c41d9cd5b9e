//! One sweep over memory for the bulk of an unsampled step: each layer's internal forces, and on
//! the layers nothing else needs at t_{n+1}, the corrector and the next step's predictor right
//! behind them (docs/fem-model.md §9 steps 4, 8 and the next step's 1). The step is memory-bound;
//! the separate passes move every node's u, f (written, then read back), v and m through memory
//! twice, this sweep once, and f of those layers never leaves the cache.
//!
//! Layers are taken in bands of [`BAND`], each band by one task, in order: when layer j's forces
//! are known, layer j − 1 can move on (its forces and those of both neighbours are computed from
//! its u_{n+1}); a band's last layer moves on once its own forces are known, since the band above
//! reads it from its halo copy, taken before the sweep. Deferred to the corrector pass after
//! contact and insertion, with their forces stored: the edge nodes of every layer (prescribed in
//! the paper's cases, whose reactions read their forces) and the layers of [`deferred_layers`].
//! Every node goes through exactly the operations of the separate passes, so the result is the
//! same to the bit, whatever the bands or the threads.

use crate::mesh::structured::Grid;
use crate::model::bulk::Stiffness;
use crate::model::layers::{BAND, SweepBuffers};
use crate::model::mapped::{self, MappedStiffness};
use crate::model::state::{BulkMesh, Model};
use crate::solver::node::{Span, advance_all};
use nalgebra::Vector2;
use rayon::prelude::*;

/// Forces of every layer into `f` (all of a deferred layer, the edge nodes of the others) and
/// the advance of the interior nodes of the other layers; returns the largest |v_{n+1}|² among
/// them (∞ if one is not finite). `None` when the mesh is neither a grid with shared stencils (one
/// K_e, or one a material row by row) nor a mapped grid (a Gmsh mesh, a mapped grid of two
/// materials): the caller then runs the separate passes.
pub(crate) fn forces_and_advance(
    model: &Model,
    u: &mut [Vector2<f64>],
    v: &mut [Vector2<f64>],
    f: &mut [Vector2<f64>],
    buffers: &mut SweepBuffers,
    dt: f64,
) -> Option<f64> {
    let (grid, kernel) = grid_and_kernel(model)?;
    let nx = grid.nx;
    let w = nx + 1;
    let row = 2 * w;
    let layers = grid.layer_side.len();
    {
        let u: &[f64] = bytemuck::cast_slice(u);
        for (b, halo) in buffers.halo.chunks_mut(2 * row).enumerate() {
            let (a, e) = (b * BAND, ((b + 1) * BAND).min(layers));
            if a > 0 {
                halo[..row].copy_from_slice(&u[(a - 1) * row..a * row]);
            }
            if e < layers {
                halo[row..].copy_from_slice(&u[e * row..(e + 1) * row]);
            }
        }
    }
    let ctx = Band {
        grid,
        kernel,
        deferred: &model.bulk.deferred,
        mass: &model.bulk.mass,
        dt,
        w,
        layers,
    };
    let vmax2 = u
        .par_chunks_mut(BAND * w)
        .zip(v.par_chunks_mut(BAND * w))
        .zip(f.par_chunks_mut(BAND * w))
        .zip(buffers.done.par_chunks_mut(BAND))
        .zip(
            buffers
                .halo
                .par_chunks(2 * row)
                .zip(buffers.ring.par_chunks_mut(2 * row))
                .zip(buffers.element_rows.par_chunks_mut(2 * mapped::row_len(nx))),
        )
        .enumerate()
        .map(|(b, ((((u, v), f), done), ((halo, ring), rows)))| {
            ctx.run(b * BAND, u, v, f, done, halo, Scratch { ring, rows })
        })
        .reduce(|| 0.0, f64::max);
    Some(vmax2)
}

/// Whether [`forces_and_advance`] sweeps this model's mesh (and so writes u and v in the bulk
/// phase), or leaves the separate passes to the caller.
pub(crate) fn applies(model: &Model) -> bool {
    grid_and_kernel(model).is_some()
}

/// The grid and the sweep's kernel on it, if the mesh has one (see [`forces_and_advance`]).
fn grid_and_kernel(model: &Model) -> Option<(&Grid, Kernel<'_>)> {
    let BulkMesh::Grid { grid, stiffness } = &model.bulk.mesh else {
        return None;
    };
    let kernel = match stiffness {
        Stiffness::Shared(_) | Stiffness::ByRow(_) => Kernel::Stencil(stiffness),
        Stiffness::Mapped(mapped) => Kernel::Mapped(mapped),
        Stiffness::PerElement(_) => return None,
    };
    (grid.nx >= 2).then_some((grid, kernel))
}

/// How a layer's forces are computed.
#[derive(Clone, Copy)]
enum Kernel<'a> {
    /// One shared K_e, or one a material with each element row of one: the 9-point stencil of
    /// every interior node, the layer's material's ([`Stiffness::stencil`]).
    Stencil(&'a Stiffness),
    /// Vertical-sided elements: each element row's forces on the fly (`model::mapped`), computed
    /// once and shared by its two layers.
    Mapped(&'a MappedStiffness),
}

/// A band's scratch: two rows of forces (x, y pairs) [N/m], and on a mapped mesh the element
/// forces of two element rows [N/m].
struct Scratch<'a> {
    ring: &'a mut [f64],
    rows: &'a mut [f64],
}

/// What every band task reads.
struct Band<'a> {
    grid: &'a Grid,
    kernel: Kernel<'a>,
    deferred: &'a [bool],
    mass: &'a [f64],
    dt: f64,
    w: usize,
    layers: usize,
}

impl Band<'_> {
    /// Layers a.. of one band: u, v, f of its nodes, its `done` flags, the halo rows (below a,
    /// above its last layer) and two rows of scratch forces.
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        a: usize,
        u: &mut [Vector2<f64>],
        v: &mut [Vector2<f64>],
        f: &mut [Vector2<f64>],
        done: &mut [bool],
        halo: &[f64],
        scratch: Scratch<'_>,
    ) -> f64 {
        let Scratch { ring, rows } = scratch;
        let (w, row) = (self.w, 2 * self.w);
        let e = a + done.len();
        let nx = w - 1;
        let mut vmax2 = 0.0f64;
        let stored = |j: usize| self.deferred[j];
        for j in a..e {
            done[j - a] = false;
            let (below, above) = self.grid.layer_element_rows(j);
            {
                let flat: &[f64] = bytemuck::cast_slice(u);
                let layer = |l: usize| -> &[f64] {
                    if l < a {
                        &halo[..row]
                    } else if l >= e {
                        &halo[row..]
                    } else {
                        &flat[(l - a) * row..(l - a + 1) * row]
                    }
                };
                let lo = below.map(|_| layer(j - 1));
                let hi = above.map(|_| layer(j + 1));
                debug_assert!(j + 1 < self.layers || hi.is_none());
                let forces = |out: &mut [f64], rows: &mut [f64]| match self.kernel {
                    Kernel::Stencil(k) => k
                        .stencil(below, above)
                        .expect("invariant: Kernel::Stencil holds a stiffness with stencils")
                        .layer(lo, layer(j), hi, out),
                    Kernel::Mapped(k) => {
                        // the element row above layer j is computed here and kept for layer
                        // j + 1; the one below was kept by layer j − 1 (computed again only at
                        // the band's first layer, from the halo)
                        let (even, odd) = rows.split_at_mut(mapped::row_len(nx));
                        let (mine, previous) = if j % 2 == 0 { (even, odd) } else { (odd, even) };
                        if let (Some(r), Some(lo)) = (below, lo)
                            && j == a
                        {
                            mapped::row_forces(k, r, lo, layer(j), previous);
                        }
                        if let (Some(r), Some(hi)) = (above, hi) {
                            mapped::row_forces(k, r, layer(j), hi, mine);
                        }
                        mapped::layer_from_rows(j, below.map(|_| &*previous), above.map(|_| &*mine), out);
                    }
                };
                if stored(j) {
                    let out: &mut [f64] = bytemuck::cast_slice_mut(&mut f[(j - a) * w..(j - a + 1) * w]);
                    forces(out, rows);
                } else {
                    let out = &mut ring[(j % 2) * row..(j % 2 + 1) * row];
                    forces(out, rows);
                    // the edge nodes are advanced after contact, from the stored forces
                    f[(j - a) * w] = Vector2::new(out[0], out[1]);
                    f[(j - a) * w + nx] = Vector2::new(out[2 * nx], out[2 * nx + 1]);
                }
            }
            // layer j − 1 now has its forces and both neighbours': it moves on.
            if j > a && !stored(j - 1) {
                self.advance(j - 1, a, u, v, ring, &mut vmax2);
                done[j - 1 - a] = true;
            }
        }
        // the band's last layer: its neighbour above is the next band's, which reads it from
        // its own halo copy
        if !stored(e - 1) {
            self.advance(e - 1, a, u, v, ring, &mut vmax2);
            done[e - 1 - a] = true;
        }
        vmax2
    }

    /// The corrector and the next predictor of the interior nodes of layer `j` of the band from
    /// layer `a`, from its forces in the scratch `ring`.
    fn advance(
        &self,
        j: usize,
        a: usize,
        u: &mut [Vector2<f64>],
        v: &mut [Vector2<f64>],
        ring: &[f64],
        vmax2: &mut f64,
    ) {
        let (w, row) = (self.w, 2 * self.w);
        let nx = w - 1;
        let fr = &ring[(j % 2) * row..(j % 2 + 1) * row];
        let base = (j - a) * w;
        let global = j * w;
        let nodes = Span {
            u: &mut u[base + 1..base + nx],
            v: &mut v[base + 1..base + nx],
            f: &fr[2..2 * nx],
            m: &self.mass[global + 1..global + nx],
        };
        advance_all(nodes, self.dt, vmax2);
    }
}
