//! The elastodynamic operator of both half-spaces (docs/spectral-model.md §2, independent formulation):
//! given the face displacements u^{±,n}, returns the history terms f^{±,n} so that
//! T^± = T^0 ∓ Z v^± + f^± (Z = μ/c_s in x, η μ/c_s in y).
//!
//! F^±_1 = ∓ μk (H11 ∗ Û^±_1) + i μk [(2−η) Û^±_2 + K12 ∗ Û^±_2]
//! F^±_2 = ∓ μk (H22 ∗ Û^±_2) − i μk [(2−η) Û^±_1 + K12 ∗ Û^±_1]
//! (k ≥ 0 from the real FFT; F(k=0) = 0; the i k terms dropped at Nyquist, §2 and §8.)

use std::sync::Arc;

use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use serde::{Deserialize, Serialize};

use crate::convolution::{self, ModeSums, Weights};
use crate::error::BuildError;
use crate::fast::{FastConvolution, FastState, FastStorage, MODES_PER_TASK, Packed, SoeFit};
use crate::history::{Entry, History, HistoryState};
use crate::kernels::Kernels;
use crate::modes::Modes;
use crate::profile::{Clock, Phase, StepWork, Work};
use crate::scene::Convolution;

/// Parameters of the half-space pair (identical materials); for two materials, one set per
/// half-space, each driving its own [`HalfSpaces`] (see [`Operator`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfSpaceParams {
    /// Shear modulus μ [Pa].
    pub shear_modulus: f64,
    /// Shear wave speed c_s [m/s].
    pub cs: f64,
    /// η = c_d/c_s [-].
    pub eta: f64,
    /// Number of grid points N [-] (even).
    pub grid_points: usize,
    /// Periodic length X [m].
    pub length: f64,
    /// CFL parameter β = c_s Δt/Δx [-].
    pub cs_dt_over_dx: f64,
    /// Kernel truncation tcut [-].
    pub kernel_cutoff: f64,
    /// Number of steps the run will take (caps the windows) [-].
    pub max_steps: usize,
    /// Convolution path.
    pub convolution: Convolution,
    /// Fast path: kernel-fit tolerance relative to max|K| [-].
    pub fast_tolerance: f64,
    /// Fast path: how the recursion states are stored between steps.
    pub fast_storage: FastStorage,
}

/// Displacement, velocity or traction fields of both faces on the grid (SoA).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FaceFields {
    /// Top face (y = 0⁺), x component.
    pub top_x: Vec<f64>,
    /// Top face, y component.
    pub top_y: Vec<f64>,
    /// Bottom face (y = 0⁻), x component.
    pub bottom_x: Vec<f64>,
    /// Bottom face, y component.
    pub bottom_y: Vec<f64>,
}

impl FaceFields {
    /// Zero fields on n points.
    pub fn zeros(n: usize) -> FaceFields {
        FaceFields {
            top_x: vec![0.0; n],
            top_y: vec![0.0; n],
            bottom_x: vec![0.0; n],
            bottom_y: vec![0.0; n],
        }
    }
}

/// i·z without a full complex multiplication.
#[inline(always)]
fn mul_i(z: Complex64) -> Complex64 {
    Complex64::new(-z.im, z.re)
}

enum Path {
    Direct {
        history: Box<History>,
        weights: Box<Weights>,
    },
    Fast(Box<FastConvolution>),
}

/// Cost figures of the convolution path.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct ConvolutionStats {
    /// Σ_j L_j: stored history steps over all modes [-].
    pub history_entries: u64,
    /// Bytes of history + weights streamed per step once the windows are full [B].
    pub bytes_per_step: u64,
    /// Fast path: exponential terms shared by the three kernels (0 for direct) [-].
    pub exp_terms: u64,
    /// Fast path: achieved max fit error relative to max|K| (0 for direct) [-].
    pub fit_error: f64,
}

/// The operator u^n → f^n with its history, FFT plans and buffers (allocated once).
pub struct HalfSpaces {
    p: HalfSpaceParams,
    modes: Modes,
    path: Path,
    fwd: Arc<dyn Fft<f64>>,
    inv: Arc<dyn Fft<f64>>,
    a: Vec<Complex64>,
    b: Vec<Complex64>,
    scratch: Vec<Complex64>,
    scratch_b: Vec<Complex64>,
    spectra: Vec<Entry>,
    sums: Vec<ModeSums>,
    stats: ConvolutionStats,
}

impl HalfSpaces {
    /// Builds kernels, windows, history and FFT plans.
    pub fn new(p: &HalfSpaceParams) -> Result<HalfSpaces, BuildError> {
        let n = p.grid_points;
        let modes = Modes::new(n, p.length, p.cs_dt_over_dx, p.kernel_cutoff, p.max_steps);
        let kernels = Kernels::new(p.eta, p.kernel_cutoff);
        let mut stats = ConvolutionStats {
            history_entries: modes.total as u64,
            ..Default::default()
        };
        let path = match p.convolution {
            Convolution::Direct => {
                let table = kernels.tabulate(modes.dt1, modes.max_sample() + 1);
                let weights = Weights::new(&modes, &table);
                let history = History::new(&modes);
                stats.bytes_per_step = (modes.total * std::mem::size_of::<Entry>() + weights.bytes()) as u64;
                Path::Direct {
                    history: Box::new(history),
                    weights: Box::new(weights),
                }
            }
            Convolution::Fast => {
                let fit = SoeFit::shared(&kernels, p.kernel_cutoff, p.fast_tolerance)?;
                stats.history_entries = 0;
                stats.exp_terms = fit.terms() as u64;
                stats.fit_error = fit.max_error;
                let fast = FastConvolution::new(&modes, &fit, p.fast_storage);
                stats.bytes_per_step = fast.bytes() as u64;
                Path::Fast(Box::new(fast))
            }
        };
        let mut planner = FftPlanner::new();
        let fwd = planner.plan_fft_forward(n);
        let inv = planner.plan_fft_inverse(n);
        let scratch_len = fwd.get_inplace_scratch_len().max(inv.get_inplace_scratch_len());
        Ok(HalfSpaces {
            p: *p,
            path,
            fwd,
            inv,
            a: vec![Complex64::default(); n],
            b: vec![Complex64::default(); n],
            scratch: vec![Complex64::default(); scratch_len],
            scratch_b: vec![Complex64::default(); scratch_len],
            spectra: vec![Entry::default(); n / 2 + 1],
            sums: vec![ModeSums::default(); n / 2 + 1],
            modes,
            stats,
        })
    }

    /// Cost figures of the chosen path.
    pub fn stats(&self) -> ConvolutionStats {
        self.stats
    }

    /// For benchmarks: treats every history window as full (of zeros), so one step streams the
    /// whole history as in the late part of a long run. No effect on the fast path.
    pub fn assume_full_history(&mut self) {
        if let Path::Direct { history, .. } = &mut self.path {
            history.assume_full();
        }
    }

    /// The evolving part, for a checkpoint: the convolution history of the chosen path (§4.1
    /// ring buffers or §4.3 recursion states). Everything else is the scene's (kernels, weights,
    /// FFT plans) or is written by a step before that step reads it (the FFT, spectra and sums
    /// buffers).
    pub(crate) fn saved(&self) -> HalfSpaceState<'_> {
        // `restore` names every field: one added there is one to think about here
        match &self.path {
            Path::Direct { history, .. } => HalfSpaceState::Direct(history.saved()),
            Path::Fast(fast) => HalfSpaceState::Fast(fast.saved()),
        }
    }

    /// Restores what [`HalfSpaces::saved`] wrote into this operator, built for the same scene.
    /// Every field is named: a new one is a compile error here until it is saved or said to be
    /// rebuilt.
    pub(crate) fn restore(&mut self, saved: &HalfSpaceState<'_>) -> Result<(), String> {
        let HalfSpaces {
            p: _,
            modes: _,
            path,
            fwd: _,
            inv: _,
            a: _,
            b: _,
            scratch: _,
            scratch_b: _,
            spectra: _,
            sums: _,
            stats: _,
        } = self;
        match (path, saved) {
            (Path::Direct { history, weights: _ }, HalfSpaceState::Direct(h)) => history.restore(h),
            (Path::Fast(fast), HalfSpaceState::Fast(s)) => fast.restore(s),
            _ => Err("its convolution path is not the scene's (spectral.convolution)".into()),
        }
    }

    /// Records u^n in the history and writes f^n (§4.2 steps 2–4). Call once per step, in order.
    pub fn step(&mut self, u: &FaceFields, f: &mut FaceFields) {
        self.step_timed(u, f, &mut Clock::default());
    }

    /// As [`step`](HalfSpaces::step), booking a lap to `clock` after each phase: forward FFT,
    /// convolution, inverse FFT. On the direct path the split of the transforms into spectra is
    /// booked with the forward FFT and the assembly of F^± with the inverse one; on the fast path
    /// both run in the recursion's tasks, each on its own modes (`split_recursion_assembly`),
    /// and are booked with the convolution.
    pub fn step_timed(&mut self, u: &FaceFields, f: &mut FaceFields, clock: &mut Clock) {
        self.transform(u);
        match &mut self.path {
            Path::Direct { history, weights } => {
                split_all(&mut self.spectra, &self.a, &self.b);
                clock.lap(Phase::ForwardFft);
                history.push(&self.spectra);
                convolution::convolve(history, weights, &mut self.sums);
                clock.lap(Phase::Convolution);
                self.assemble();
            }
            Path::Fast(fast) => {
                clock.lap(Phase::ForwardFft);
                let (mu, c) = (self.p.shear_modulus, 2.0 - self.p.eta);
                let modes = Spectra {
                    spectra: &mut self.spectra,
                    sums: &mut self.sums,
                    k: &self.modes.k,
                };
                split_recursion_assembly(fast, modes, &mut self.a, &mut self.b, mu, c);
                clock.lap(Phase::Convolution);
            }
        }
        self.inverse(f);
        clock.lap(Phase::InverseFft);
    }

    /// Work of one step by phase (the direct path's windows full), counted from the loops of
    /// [`step`](HalfSpaces::step) with N points and N/2 + 1 modes; each complex FFT of size N
    /// ≈ 5 N log2 N flops, its array read and written once:
    /// - forward: the four real fields read and packed into two complex arrays (32 N B each way);
    ///   two FFTs;
    /// - the split of both arrays into the spectra of the four fields (24 flops a mode, 64 B
    ///   written): of every mode with the forward FFT on the direct path, of the modes j ≥ 1
    ///   (mode 0 has no history term) with the convolution on the fast one (where it is booked);
    /// - convolution: the recursion's count (`fast.rs`: 120 flops per pole and mode, the states
    ///   read and written) or the direct sum's (`convolution.rs`: 32 flops per mode and lag);
    /// - the assembly: the sums, spectra and k read per mode and F^± assembled (49 flops a mode;
    ///   both halves of the two arrays written, 64 B): with the inverse FFT on the direct path,
    ///   with the convolution on the fast one; where the fast path runs the split, the recursion
    ///   and the assembly of a mode in one loop (AVX-512, `FastConvolution::fuses_modes`), the
    ///   spectra and sums of the modes 0 < j < N/2 are neither written nor read back;
    /// - inverse: two FFTs; both arrays read, scaled by 1/N and unpacked into f (4 N flops,
    ///   32 N B each way).
    pub fn work(&self) -> StepWork {
        let n = self.p.grid_points as f64;
        let modes = (self.p.grid_points / 2 + 1) as f64;
        let complex = std::mem::size_of::<Complex64>() as f64;
        let entry = std::mem::size_of::<Entry>() as f64;
        let ffts = Work {
            flops: 2.0 * fft_flops(self.p.grid_points),
            read: 2.0 * n * complex,
            written: 2.0 * n * complex,
        };
        // the four real fields ↔ the two packed complex arrays
        let pack = Work {
            flops: 0.0,
            read: 4.0 * n * 8.0,
            written: 2.0 * n * complex,
        };
        // the split of `m` modes (all on the direct path, those of j ≥ 1 on the fast one)
        let split = |m: f64| Work {
            flops: m * SPLIT_FLOPS_PER_MODE,
            read: 2.0 * n * complex,
            written: m * entry,
        };
        let unpack = Work {
            flops: 4.0 * n,
            read: pack.written,
            written: pack.read,
        };
        let assemble = Work {
            flops: (modes - 1.0) * ASSEMBLE_FLOPS_PER_MODE,
            read: modes * (std::mem::size_of::<ModeSums>() as f64 + entry + 8.0),
            written: 2.0 * n * complex,
        };
        let mut w = StepWork::default();
        match &self.path {
            Path::Direct { weights, .. } => {
                w.add(Phase::ForwardFft, pack + ffts + split(modes));
                w.add(Phase::Convolution, weights.work());
                w.add(Phase::InverseFft, assemble + ffts + unpack);
            }
            Path::Fast(fast) => {
                let mut convolution = split(modes - 1.0) + fast.work() + assemble;
                if fast.fuses_modes() {
                    // the modes 0 < j < N/2 keep their spectra and sums in registers: none
                    // written by the split or the recursion, none read by the recursion or the
                    // assembly
                    let (kept, sums) = (modes - 2.0, std::mem::size_of::<ModeSums>() as f64);
                    convolution.read -= kept * (2.0 * entry + sums);
                    convolution.written -= kept * (entry + sums);
                }
                w.add(Phase::ForwardFft, pack + ffts);
                w.add(Phase::Convolution, convolution);
                w.add(Phase::InverseFft, ffts + unpack);
            }
        }
        w
    }

    /// Two complex FFTs of the packed real fields, each face packed and transformed on its own
    /// rayon worker.
    fn transform(&mut self, u: &FaceFields) {
        let plan = &self.fwd;
        let (a, b) = (&mut self.a, &mut self.b);
        let (sa, sb) = (&mut self.scratch, &mut self.scratch_b);
        rayon::join(
            || {
                pack(a, &u.top_x, &u.top_y);
                plan.process_with_scratch(a, sa);
            },
            || {
                pack(b, &u.bottom_x, &u.bottom_y);
                plan.process_with_scratch(b, sb);
            },
        );
    }

    /// F^±(k_j) from the convolutions and the instantaneous (2−η) coupling, packed for the
    /// inverse: a[j] and b[j] for j = 0..=N/2, their conjugate halves a[N − j] and b[N − j] for
    /// 0 < j < N/2, modes in parallel.
    fn assemble(&mut self) {
        let n = self.p.grid_points;
        let half = n / 2;
        let (mu, c) = (self.p.shear_modulus, 2.0 - self.p.eta);
        let (sums, spectra, k) = (&self.sums[..], &self.spectra[..], &self.modes.k[..]);
        let (a_low, a_high) = self.a.split_at_mut(half + 1);
        let (b_low, b_high) = self.b.split_at_mut(half + 1);
        assemble_ends(a_low, b_low, mu * k[half], c, &sums[half], &spectra[half]);
        // j = 1..N/2: a[j] in a_low, a[N − j] in a_high read backwards
        // (chunks of modes, each a plain loop; a_high's chunks taken from its end)
        let chunk = par_modes(half);
        let a = a_low[1..half]
            .par_chunks_mut(chunk)
            .zip(a_high.par_rchunks_mut(chunk));
        let b = b_low[1..half]
            .par_chunks_mut(chunk)
            .zip(b_high.par_rchunks_mut(chunk));
        let inputs = sums[1..half]
            .par_chunks(chunk)
            .zip(spectra[1..half].par_chunks(chunk))
            .zip(k[1..half].par_chunks(chunk));
        a.zip(b)
            .zip(inputs)
            .for_each(|(((aj, an), (bj, bn)), ((s, e), k))| assemble_modes([aj, an, bj, bn], s, e, k, mu, c));
    }

    /// The two inverse FFTs, each face's on its own rayon worker, scaled by 1/N and unpacked
    /// into f there.
    fn inverse(&mut self, f: &mut FaceFields) {
        let plan = &self.inv;
        let scale = 1.0 / self.p.grid_points as f64;
        let (a, b) = (&mut self.a, &mut self.b);
        let (sa, sb) = (&mut self.scratch, &mut self.scratch_b);
        let FaceFields {
            top_x,
            top_y,
            bottom_x,
            bottom_y,
        } = f;
        rayon::join(
            || {
                plan.process_with_scratch(a, sa);
                unpack(a, scale, top_x, top_y);
            },
            || {
                plan.process_with_scratch(b, sb);
                unpack(b, scale, bottom_x, bottom_y);
            },
        );
    }
}

/// Modes per rayon task of the split and the assembly: as many tasks as the pool has threads, each
/// of at least [`MIN_PAR_MODES`]. Each phase is a few µs of work, so more tasks than threads only
/// add their hand-outs (docs/performance.md, "The spectral model"); the chunks change no value.
fn par_modes(modes: usize) -> usize {
    modes.div_ceil(rayon::current_num_threads()).max(MIN_PAR_MODES)
}

/// The fewest modes a task of the split or the assembly takes.
const MIN_PAR_MODES: usize = 256;

/// The spectra j = 0..=N/2 of the four fields from the two packed transforms, modes in
/// parallel: every value is computed as by a serial loop, whatever the thread count.
fn split_all(spectra: &mut [Entry], a: &[Complex64], b: &[Complex64]) {
    let half = a.len() / 2;
    let chunk = par_modes(half);
    spectra[0] = split(a[0], a[0], b[0], b[0]);
    // mode j pairs a[j] with a[N − j]: a[1..=N/2] against a[N/2..N] read backwards
    // (chunks of modes, each a plain loop: per mode, rayon called the closure out of line)
    spectra[1..]
        .par_chunks_mut(chunk)
        .zip(a[1..=half].par_chunks(chunk).zip(a[half..].par_rchunks(chunk)))
        .zip(b[1..=half].par_chunks(chunk).zip(b[half..].par_rchunks(chunk)))
        .for_each(|((e, (aj, an)), (bj, bn))| split_modes(e, [aj, an, bj, bn]));
}

/// [`split`] over consecutive modes j: `aj` and `bj` hold the transforms at j, `an` and `bn` at
/// N − j, in the arrays' order (so read backwards).
fn split_modes(e: &mut [Entry], [aj, an, bj, bn]: [&[Complex64]; 4]) {
    let a = aj.iter().zip(an.iter().rev());
    let b = bj.iter().zip(bn.iter().rev());
    for (e, ((&aj, &an), (&bj, &bn))) in e.iter_mut().zip(a.zip(b)) {
        *e = split(aj, an, bj, bn);
    }
}

/// Modes 0 and N/2 of the packed F^± (`a_low` and `b_low` hold modes 0..=N/2): zero at j = 0;
/// at Nyquist no coupling and no conjugate half, `muk` = μ k_{N/2}.
fn assemble_ends(
    a_low: &mut [Complex64],
    b_low: &mut [Complex64],
    muk: f64,
    c: f64,
    s: &ModeSums,
    e: &Entry,
) {
    let half = a_low.len() - 1;
    a_low[0] = Complex64::default();
    b_low[0] = Complex64::default();
    let [f1t, f2t, f1b, f2b] = forces(muk, 0.0, c, s, e);
    a_low[half] = f1t + mul_i(f2t);
    b_low[half] = f1b + mul_i(f2b);
}

/// F^± of consecutive modes 0 < j < N/2 packed for the inverse, at j (`aj`, `bj`) and their
/// conjugate halves at N − j (`an`, `bn`, in the arrays' order, so written backwards).
fn assemble_modes(
    [aj, an, bj, bn]: [&mut [Complex64]; 4],
    s: &[ModeSums],
    e: &[Entry],
    k: &[f64],
    mu: f64,
    c: f64,
) {
    let a = aj.iter_mut().zip(an.iter_mut().rev());
    let b = bj.iter_mut().zip(bn.iter_mut().rev());
    for (((aj, an), (bj, bn)), ((s, e), &kj)) in a.zip(b).zip(s.iter().zip(e).zip(k)) {
        let muk = mu * kj;
        let [f1t, f2t, f1b, f2b] = forces(muk, muk, c, s, e);
        *aj = f1t + mul_i(f2t);
        *bj = f1b + mul_i(f2b);
        // the conjugate half (the fields are real: F(−k) = F̄(k))
        *an = f1t.conj() + mul_i(f2t.conj());
        *bn = f1b.conj() + mul_i(f2b.conj());
    }
}

/// A half-space pair's per-mode buffers and wavenumbers, j = 0..=N/2.
struct Spectra<'a> {
    spectra: &'a mut [Entry],
    sums: &'a mut [ModeSums],
    /// k_j [1/m].
    k: &'a [f64],
}

/// The fast path's split, recursion and assembly in one pass over the modes: each rayon task
/// takes the recursion's [`MODES_PER_TASK`] modes, splits their spectra out of the packed
/// transforms `a` and `b`, pushes them into the recursion, and writes their F^± back into `a`
/// and `b` at the same places (mode j and its conjugate N − j are the task's alone). Each value
/// is computed by the operations of the separate passes ([`split_all`], `FastConvolution::step`,
/// [`HalfSpaces::assemble`]) in their order, so the bits are theirs; one parallel pass instead
/// of three saves two hand-outs of tasks a step, and each task's spectra and sums stay in its
/// core's cache. Where the CPU has AVX-512 ([`Block::fused`](crate::fast::Block::fused)), a task
/// does the three mode by mode in one loop and its spectra and sums stay in registers.
fn split_recursion_assembly(
    fast: &mut FastConvolution,
    m: Spectra<'_>,
    a: &mut [Complex64],
    b: &mut [Complex64],
    mu: f64,
    c: f64,
) {
    let half = a.len() / 2;
    let Spectra { spectra, sums, k } = m;
    let (a_low, a_high) = a.split_at_mut(half + 1);
    let (b_low, b_high) = b.split_at_mut(half + 1);
    // j = 1..N/2: a[j] in a_low, a[N − j] in a_high from its end, chunked as the recursion's blocks
    let chunk = MODES_PER_TASK;
    let low = a_low[1..half]
        .par_chunks_mut(chunk)
        .zip(b_low[1..half].par_chunks_mut(chunk));
    let high = a_high.par_rchunks_mut(chunk).zip(b_high.par_rchunks_mut(chunk));
    let per_mode = spectra[1..half]
        .par_chunks_mut(chunk)
        .zip(sums[1..half].par_chunks_mut(chunk))
        .zip(k[1..half].par_chunks(chunk));
    fast.blocks(1..half).zip(low.zip(high)).zip(per_mode).for_each(
        |((block, ((aj, bj), (an, bn))), ((e, s), k))| match block.fused() {
            Ok(block) => block.step(Packed {
                aj,
                an,
                bj,
                bn,
                k,
                mu,
                c,
            }),
            Err(block) => {
                split_modes(e, [aj, an, bj, bn]);
                block.step(e, s);
                assemble_modes([aj, an, bj, bn], s, e, k, mu, c);
            }
        },
    );
    // the Nyquist mode, its own conjugate; mode 0 has no history term and F(k = 0) = 0, so its
    // spectra and sums are not needed
    spectra[half] = split(a_low[half], a_low[half], b_low[half], b_low[half]);
    fast.block(half).step(&spectra[half..], &mut sums[half..]);
    assemble_ends(a_low, b_low, mu * k[half], c, &sums[half], &spectra[half]);
}

/// z[m] = x[m] + i y[m]: two real fields of a face packed into one complex array.
fn pack(z: &mut [Complex64], x: &[f64], y: &[f64]) {
    for ((z, &x), &y) in z.iter_mut().zip(x).zip(y) {
        *z = Complex64::new(x, y);
    }
}

/// x[m] = s Re z[m], y[m] = s Im z[m]: the inverse of [`pack`], scaled.
fn unpack(z: &[Complex64], scale: f64, x: &mut [f64], y: &mut [f64]) {
    for ((z, x), y) in z.iter().zip(x.iter_mut()).zip(y.iter_mut()) {
        *x = z.re * scale;
        *y = z.im * scale;
    }
}

/// The spectra of the four fields at mode j from the packed transforms A = FFT(u_x + i u_y)
/// of each face, at j (aj, bj) and at N − j (an, bn): Û_x = (A_j + Ā_{N−j})/2,
/// Û_y = −i (A_j − Ā_{N−j})/2.
#[inline(always)]
fn split(aj: Complex64, an: Complex64, bj: Complex64, bn: Complex64) -> Entry {
    let half_i = Complex64::new(0.0, -0.5);
    let (an, bn) = (an.conj(), bn.conj());
    Entry {
        top_x: 0.5 * (aj + an),
        top_y: half_i * (aj - an),
        bottom_x: 0.5 * (bj + bn),
        bottom_y: half_i * (bj - bn),
    }
}

/// F^±_1 and F^±_2 of one mode (§2, the module's formulas), μk and the coupling's factor given
/// (0 at Nyquist): (F^+_1, F^+_2, F^-_1, F^-_2).
#[inline(always)]
fn forces(muk: f64, couple: f64, c: f64, s: &ModeSums, e: &Entry) -> [Complex64; 4] {
    let f1t = -muk * s.h11_top + mul_i(couple * (c * e.top_y + s.k12_top_y));
    let f1b = muk * s.h11_bottom + mul_i(couple * (c * e.bottom_y + s.k12_bottom_y));
    let f2t = -muk * s.h22_top - mul_i(couple * (c * e.top_x + s.k12_top_x));
    let f2b = muk * s.h22_bottom - mul_i(couple * (c * e.bottom_x + s.k12_bottom_x));
    [f1t, f2t, f1b, f2b]
}

/// Flops of one complex FFT of size `n` [-]: 5 n log2 n, the count of a radix-2 transform
/// (rustfft's mixed radices do somewhat fewer; other sizes, somewhat more).
pub(crate) fn fft_flops(n: usize) -> f64 {
    let n = n as f64;
    5.0 * n * n.log2()
}

/// Flops per mode of the split of the two packed transforms into the four spectra
/// ([`HalfSpaces::step`], forward): per packed array a complex sum and a difference (2 adds
/// each), a halving (2 multiplies) and a product by −i/2 (a full complex product: 6).
const SPLIT_FLOPS_PER_MODE: f64 = 2.0 * (2.0 + 2.0 + 2.0 + 6.0);

/// Flops per mode j ≥ 1 of the assembly of F^± (§2): μ k_j (1 multiply); for each of the four
/// F (F^±_1, F^±_2) a real times a complex sum (2), the (2 − η) coupling, its sum with the
/// convolution and its product by μk (2 + 2 + 2) and the final sum (2); the two packed values
/// and their conjugate halves (4 complex adds, 8).
const ASSEMBLE_FLOPS_PER_MODE: f64 = 1.0 + 4.0 * (2.0 + 6.0 + 2.0) + 8.0;

/// The operator of a run (docs/spectral-model.md §2.1): one [`HalfSpaces`] for two identical
/// half-spaces, or one per half-space with its own material. Each half-space's relation involves
/// only its own face (T^± = T^0 ∓ Z^± v^± + f^±), so a split operator takes the top face's f^+
/// from the top material's operator and the bottom face's f^- from the bottom one's; the face
/// each does not own is computed and discarded, which doubles the convolution's cost.
pub enum Operator {
    /// Two identical half-spaces.
    Identical(Box<HalfSpaces>),
    /// Two materials: the top (y > 0) and bottom (y < 0) half-spaces' operators, and the buffer
    /// the bottom one writes to.
    Split {
        /// Operator of the top material (its f^+ is kept).
        top: Box<HalfSpaces>,
        /// Operator of the bottom material (its f^- is kept).
        bottom: Box<HalfSpaces>,
        /// The bottom operator's output (its top-face part is discarded).
        scratch: Box<FaceFields>,
    },
}

impl Operator {
    /// Records u^n and writes f^n of both faces (§4.2 steps 2–4).
    pub fn step(&mut self, u: &FaceFields, f: &mut FaceFields) {
        self.step_timed(u, f, &mut Clock::default());
    }

    /// As [`step`](Operator::step), booking its phases to `clock`. For two materials the top
    /// operator's phases are the laps; the bottom one, run beside it, is booked beside, and the
    /// wait for it and the copy of its face to [`Phase::SecondHalfSpace`].
    pub fn step_timed(&mut self, u: &FaceFields, f: &mut FaceFields, clock: &mut Clock) {
        match self {
            Operator::Identical(h) => h.step_timed(u, f, clock),
            Operator::Split { top, bottom, scratch } => {
                let (s, g) = (&mut **scratch, &mut *f);
                let mut other = Clock::default();
                rayon::join(
                    || top.step_timed(u, g, clock),
                    || {
                        other.start();
                        bottom.step_timed(u, s, &mut other)
                    },
                );
                f.bottom_x.copy_from_slice(&scratch.bottom_x);
                f.bottom_y.copy_from_slice(&scratch.bottom_y);
                clock.lap(Phase::SecondHalfSpace);
                clock.beside(&other);
            }
        }
    }

    /// Work of one step by phase ([`HalfSpaces::work`]): both operators' for two materials, the
    /// bottom one's in the phases of the top one's, and the copy of the bottom face.
    pub fn work(&self) -> StepWork {
        match self {
            Operator::Identical(h) => h.work(),
            Operator::Split { top, bottom, scratch } => {
                let (mut w, b) = (top.work(), bottom.work());
                for p in Phase::ALL {
                    w.add(p, b.of(p));
                }
                let face = 2.0 * scratch.bottom_x.len() as f64 * 8.0;
                w.add(
                    Phase::SecondHalfSpace,
                    Work {
                        flops: 0.0,
                        read: face,
                        written: face,
                    },
                );
                w
            }
        }
    }

    /// The evolving part, for a checkpoint: each half-space operator's history (the split
    /// operator's scratch is written by every step before it is read).
    pub(crate) fn saved(&self) -> OperatorState<'_> {
        match self {
            Operator::Identical(h) => OperatorState::Identical(h.saved()),
            Operator::Split {
                top,
                bottom,
                scratch: _,
            } => OperatorState::Split {
                top: top.saved(),
                bottom: bottom.saved(),
            },
        }
    }

    /// Restores what [`Operator::saved`] wrote into this operator, built for the same scene.
    pub(crate) fn restore(&mut self, saved: &OperatorState<'_>) -> Result<(), String> {
        match (self, saved) {
            (Operator::Identical(h), OperatorState::Identical(s)) => h.restore(s),
            (
                Operator::Split {
                    top,
                    bottom,
                    scratch: _,
                },
                OperatorState::Split { top: t, bottom: b },
            ) => {
                top.restore(t)?;
                bottom.restore(b)
            }
            _ => Err("one operator for both half-spaces against one per half-space ([material])".into()),
        }
    }

    /// Cost figures: both operators' together for a split one.
    pub fn stats(&self) -> ConvolutionStats {
        match self {
            Operator::Identical(h) => h.stats(),
            Operator::Split { top, bottom, .. } => {
                let (a, b) = (top.stats(), bottom.stats());
                ConvolutionStats {
                    history_entries: a.history_entries + b.history_entries,
                    bytes_per_step: a.bytes_per_step + b.bytes_per_step,
                    exp_terms: a.exp_terms + b.exp_terms,
                    fit_error: a.fit_error.max(b.fit_error),
                }
            }
        }
    }
}

/// The history of an [`crate::Operator`], in its shape.
#[derive(Debug, Serialize, Deserialize)]
pub(crate) enum OperatorState<'a> {
    /// Two identical half-spaces: one operator.
    Identical(HalfSpaceState<'a>),
    /// Two materials: the top and the bottom half-space's operators.
    Split {
        /// The top (y > 0) material's.
        top: HalfSpaceState<'a>,
        /// The bottom (y < 0) material's.
        bottom: HalfSpaceState<'a>,
    },
}

/// The history of one [`crate::HalfSpaces`] operator, by convolution path.
#[derive(Debug, Serialize, Deserialize)]
pub(crate) enum HalfSpaceState<'a> {
    /// Direct path (§4.1).
    Direct(HistoryState<'a>),
    /// Fast path (§4.3).
    Fast(FastState<'a>),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fast::Isa;

    /// A fast-path operator on `n` points (identical materials).
    fn fast_operator(n: usize) -> HalfSpaces {
        HalfSpaces::new(&HalfSpaceParams {
            shear_modulus: 30e9,
            cs: 3000.0,
            eta: 3f64.sqrt(),
            grid_points: n,
            length: 1.0,
            cs_dt_over_dx: 0.2,
            kernel_cutoff: 100.0,
            max_steps: 10,
            convolution: Convolution::Fast,
            fast_tolerance: 1e-5,
            fast_storage: FastStorage::F64,
        })
        .unwrap()
    }

    /// The split, the recursion and the assembly, each a pass of its own over the modes.
    fn step_in_separate_passes(h: &mut HalfSpaces, u: &FaceFields, f: &mut FaceFields) {
        h.transform(u);
        split_all(&mut h.spectra, &h.a, &h.b);
        let Path::Fast(fast) = &mut h.path else {
            panic!("the fast path")
        };
        fast.step(&h.spectra, &mut h.sums);
        h.assemble();
        h.inverse(f);
    }

    /// Face displacements that differ at every point and from step to step [m].
    fn displacements(n: usize, step: usize) -> FaceFields {
        let mut u = FaceFields::zeros(n);
        let s = 1.0 + step as f64;
        for m in 0..n {
            let x = m as f64;
            u.top_x[m] = 1e-5 * (0.37 * x * s).sin();
            u.top_y[m] = 1e-5 * (0.11 * x + s).cos();
            u.bottom_x[m] = -1e-5 * (0.23 * x * s).cos();
            u.bottom_y[m] = 1e-5 * (0.05 * x - s).sin();
        }
        u
    }

    /// The work per step counts no spectra and no sums for the modes 0 < j < N/2 where the
    /// AVX-512 pass keeps them in registers: 64 B of spectra written by the split and read by the
    /// recursion and the assembly, 128 B of sums written and read, a mode.
    #[test]
    fn the_work_of_the_avx512_pass_leaves_out_what_stays_in_registers() {
        let n = 1024;
        let work = |isa: Isa| {
            let mut h = fast_operator(n);
            let Path::Fast(fast) = &mut h.path else {
                panic!("the fast path")
            };
            fast.set_isa(isa);
            h.work().of(Phase::Convolution)
        };
        let apart = work(Isa::Portable);
        if !Isa::every_one_here().contains(&Isa::Avx512) {
            return; // nothing else to hold it to on this CPU
        }
        let fused = work(Isa::Avx512);
        let kept = (n / 2 - 1) as f64;
        assert_eq!(apart.read - fused.read, kept * (2.0 * 64.0 + 128.0));
        assert_eq!(apart.written - fused.written, kept * (64.0 + 128.0));
        assert_eq!(apart.flops, fused.flops);
    }

    /// The fast path's one pass over the modes gives f^n of the separate passes bit for bit, over
    /// steps (so through the recursion's states), on a grid whose modes 1..N/2 fill several
    /// tasks with a shorter last one (N = 1 024) and on one whose modes 1..N/2 − 1 fill their
    /// tasks exactly (N = 258), where the Nyquist mode is the only one left outside them: with
    /// each build of the recursion this CPU runs (the AVX-512 one does the split and the
    /// assembly in its registers) against the portable build's separate passes.
    #[test]
    fn the_fused_pass_over_the_modes_gives_the_bits_of_the_separate_passes() {
        for (n, isa) in [1024, 2 * (MODES_PER_TASK + 1)]
            .into_iter()
            .flat_map(|n| Isa::every_one_here().into_iter().map(move |isa| (n, isa)))
        {
            let (mut fused, mut apart) = (fast_operator(n), fast_operator(n));
            for (h, isa) in [(&mut fused, isa), (&mut apart, Isa::Portable)] {
                let Path::Fast(fast) = &mut h.path else {
                    panic!("the fast path")
                };
                fast.set_isa(isa);
            }
            let (mut f_fused, mut f_apart) = (FaceFields::zeros(n), FaceFields::zeros(n));
            for step in 0..3 {
                let u = displacements(n, step);
                fused.step(&u, &mut f_fused);
                step_in_separate_passes(&mut apart, &u, &mut f_apart);
                let bits = |f: &FaceFields| {
                    [&f.top_x, &f.top_y, &f.bottom_x, &f.bottom_y]
                        .map(|c| c.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
                };
                assert_eq!(bits(&f_fused), bits(&f_apart), "N = {n}, {isa:?}, step {step}");
                assert!(
                    f_fused.top_x.iter().any(|&x| x != 0.0),
                    "a history term at N = {n}"
                );
            }
        }
    }
}
