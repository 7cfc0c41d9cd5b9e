//! Fast history convolution (docs/spectral-model.md §4.3): with the kernels fitted as
//! K(T) ≈ Σ_p c^K_p e^{λ_p T} ([`SoeFit`]), the §4.1 quadrature of mode j becomes, exactly,
//!
//! W^K_{j,l} = ½[K(lΔT_j) + K((l+1)ΔT_j)]ΔT_j = Σ_p g^K_{j,p} z_{j,p}^l,
//! z_{j,p} = e^{λ_p ΔT_j},  g^K_{j,p} = c^K_p ΔT_j (1 + z_{j,p})/2,
//! C^K_j(n) = Σ_l W^K_{j,l} Û^{n−l} = Σ_p g^K_{j,p} s_{j,p}(n),  s_{j,p}(n) = Û^n + z_{j,p} s_{j,p}(n−1),
//!
//! so work and memory per step are O(N r), independent of the history length.
//!
//! # Deviation
//! The direct path truncates every kernel at T = tcut (cRacklet rule, §3.4); the recursion cannot,
//! so the fitted kernel continues beyond tcut with its own exponential decay (the exact kernel
//! decays like T^{−3/2} there, |K| ≤ 9e−3 at T = 100). Both paths use the same kernels on [0, tcut]
//! to the fit tolerance.

use std::borrow::Cow;
use std::ops::Range;

use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use serde::{Deserialize, Serialize};

use crate::convolution::ModeSums;
use crate::history::{Entry, fill};
use crate::modes::Modes;
use crate::profile::Work;
pub use crate::scene::FastStorage;
pub use crate::soe::SoeFit;

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;

/// Per-mode recursion coefficients and states, one contiguous block per mode.
///
/// A kernel is real, so a conjugate pair (z, z̄) with amplitudes (c, c̄) acting on Û = A + iB (A, B
/// real sequences) gives C = 2Re(c s_z[A]) + i 2Re(c s_z[B]), s_z[A] = Σ_l z^l A^{n−l}: one state per
/// pair and real part, and the outputs need only real parts.
pub struct FastConvolution {
    r: usize,
    /// z_{j,p} at [j r + p].
    z: Vec<Complex64>,
    /// w_p (g^H11, g^H22, g^K12)_{j,p} at [j r + p].
    g: Vec<[Complex64; 3]>,
    /// States at [j r + p]: real parts then imaginary parts of s_z for the eight real sequences in
    /// the order of [`Lanes`], stored as `[spectral] fast_storage` says.
    s: States,
    isa: Isa,
}

/// Every state of the recursion, in the storage the scene chose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) enum States {
    /// [`FastStorage::F64`].
    F64(Vec<State>),
    /// [`FastStorage::F32`].
    F32(Vec<State32>),
}

impl States {
    fn len(&self) -> usize {
        match self {
            States::F64(s) => s.len(),
            States::F32(s) => s.len(),
        }
    }

    fn storage(&self) -> FastStorage {
        match self {
            States::F64(_) => FastStorage::F64,
            States::F32(_) => FastStorage::F32,
        }
    }

    /// The states of the poles `at`.
    fn slice_mut(&mut self, at: Range<usize>) -> StatesMut<'_> {
        match self {
            States::F64(s) => StatesMut::F64(&mut s[at]),
            States::F32(s) => StatesMut::F32(&mut s[at]),
        }
    }
}

/// Bytes of one state in `storage` [B].
fn state_bytes(storage: FastStorage) -> usize {
    match storage {
        FastStorage::F64 => std::mem::size_of::<State>(),
        FastStorage::F32 => std::mem::size_of::<State32>(),
    }
}

/// Bytes the recursion holds per mode and pole, its states in `storage`: z (16), g (48) and the
/// state (128 in f64, 64 in f32) [B].
pub(crate) fn bytes_per_pole(storage: FastStorage) -> usize {
    std::mem::size_of::<Complex64>() + std::mem::size_of::<[Complex64; 3]>() + state_bytes(storage)
}

/// The states of a block of modes, in either storage.
pub(crate) enum StatesMut<'a> {
    /// [`FastStorage::F64`].
    F64(&'a mut [State]),
    /// [`FastStorage::F32`].
    F32(&'a mut [State32]),
}

/// The eight real input sequences of a mode, x fields first: (top x re, top x im, bottom x re,
/// bottom x im, top y re, top y im, bottom y re, bottom y im).
type Lanes = [f64; 8];

/// Recursion state s_{j,p}(n) of one pole: real parts and imaginary parts over the eight lanes
/// [m·(kernel units)], the whole memory of the fast path (§4.3).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[repr(C, align(64))]
pub(crate) struct State {
    re: Lanes,
    im: Lanes,
}

/// [`State`] rounded to single precision ([`FastStorage::F32`]): the same lanes in half the
/// bytes, one cache line a pole.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[repr(C, align(64))]
pub(crate) struct State32 {
    re: [f32; 8],
    im: [f32; 8],
}

/// A stored recursion state: read as double-precision lanes, written back rounded to the
/// storage's precision (to nearest, ties to even, as Rust's `as f32` and the vector conversions
/// with the default rounding mode).
pub(crate) trait Stored: Copy + Default + Send + Sync + 'static {
    /// Whether the lanes are single precision, laid out as `[f32; 8]` real parts then `[f32; 8]`
    /// imaginary parts (else `[f64; 8]` each): the vector builds load and store by it.
    const SINGLE: bool;
    /// The real and imaginary parts, exactly.
    fn lanes(&self) -> (Lanes, Lanes);
    /// Keeps `re` and `im`, rounded to the storage's precision.
    fn keep(&mut self, re: &Lanes, im: &Lanes);
}

impl Stored for State {
    const SINGLE: bool = false;
    #[inline(always)]
    fn lanes(&self) -> (Lanes, Lanes) {
        (self.re, self.im)
    }
    #[inline(always)]
    fn keep(&mut self, re: &Lanes, im: &Lanes) {
        self.re = *re;
        self.im = *im;
    }
}

impl Stored for State32 {
    const SINGLE: bool = true;
    #[inline(always)]
    fn lanes(&self) -> (Lanes, Lanes) {
        (self.re.map(f64::from), self.im.map(f64::from))
    }
    #[inline(always)]
    fn keep(&mut self, re: &Lanes, im: &Lanes) {
        self.re = re.map(|x| x as f32);
        self.im = im.map(|x| x as f32);
    }
}

/// Flops of one pole of one mode in [`mode_kernel`]: the state update s ← z s + u on the 8 lanes
/// (real part 2 multiplies and 2 adds, imaginary part 2 multiplies and 1 add: 7 a lane) and the
/// two accumulations H += Re(g_H s), K += Re(g_K12 s) (2 multiplies and 2 adds each: 8 a lane),
/// 15 × 8 = 120.
pub(crate) const FLOPS_PER_POLE: f64 = 120.0;

/// One mode: s ← z s + u for every pole, then H = Σ Re(g_H s) (H11 on x lanes, H22 on y lanes) and
/// K = Σ Re(g_K12 s). Written as vertical operations on 8-lane arrays so it vectorises. The sums
/// take the new state as computed, before it is stored: in double precision it is the stored
/// value; in single precision the sums do not see its rounding, which only the next step reads.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane-indexed vertical ops over four arrays: clearer than a 4-way zip
fn mode_kernel<S: Stored>(z: &[Complex64], g: &[[Complex64; 3]], s: &mut [S], u: &Lanes) -> (Lanes, Lanes) {
    let mut h = [0.0f64; 8];
    let mut k = [0.0f64; 8];
    for ((zp, gp), sp) in z.iter().zip(g).zip(s.iter_mut()) {
        let (zr, zi) = (zp.re, zp.im);
        let (re, im) = sp.lanes();
        let (mut new_re, mut new_im) = ([0.0f64; 8], [0.0f64; 8]);
        for q in 0..8 {
            new_re[q] = zr * re[q] - zi * im[q] + u[q];
            new_im[q] = zr * im[q] + zi * re[q];
        }
        sp.keep(&new_re, &new_im);
        for q in 0..8 {
            let gh = if q < 4 { gp[0] } else { gp[1] };
            h[q] += gh.re * new_re[q] - gh.im * new_im[q];
            k[q] += gp[2].re * new_re[q] - gp[2].im * new_im[q];
        }
    }
    (h, k)
}

/// The instruction set [`mode_kernel`] is compiled for, chosen at run time. Rust never contracts
/// a multiply and an add into an FMA, so every choice computes the same bits; the wider one does
/// a pole's eight lanes in one AVX-512 register instead of two AVX2 ones.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Isa {
    /// x86-64 with AVX-512F.
    Avx512,
    /// x86-64 with AVX2 and FMA.
    Avx2,
    /// Whatever the build targets.
    Portable,
}

impl Isa {
    /// Every build this CPU runs, the portable one first.
    #[cfg(test)]
    pub(crate) fn every_one_here() -> Vec<Isa> {
        [Isa::Portable, Isa::Avx2, Isa::Avx512]
            .into_iter()
            .filter(|isa| isa.runs_here())
            .collect()
    }

    /// Whether this CPU runs the build: AVX-512F, or AVX2 with FMA, reported at run time.
    fn runs_here(self) -> bool {
        match self {
            Isa::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => {
                std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// Whether this build splits, recurses and assembles a mode in one loop ([`Block::fused`]).
    fn fuses_modes(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        if self == Isa::Avx512 {
            return true;
        }
        false
    }

    /// The widest the CPU reports.
    fn detect() -> Isa {
        [Isa::Avx512, Isa::Avx2]
            .into_iter()
            .find(|isa| isa.runs_here())
            .unwrap_or(Isa::Portable)
    }
}

/// The modes of one rayon task: for each, its eight input lanes from Û, [`mode_kernel`] over its
/// `r` poles, and its eight sums. Inlined whole into the portable and AVX-512 builds, so the
/// kernel's results go to the sums in registers (a call returned them through memory, read back
/// in narrower pieces: a store-forwarding stall a mode); the AVX2 build is written in intrinsics
/// ([`avx2::modes`]).
#[inline(always)]
fn modes_kernel<S: Stored>(
    r: usize,
    z: &[Complex64],
    g: &[[Complex64; 3]],
    s: &mut [S],
    spectra: &[Entry],
    out: &mut [ModeSums],
) {
    let coefficients = z.chunks(r).zip(g.chunks(r));
    for (((o, e), s), (z, g)) in out.iter_mut().zip(spectra).zip(s.chunks_mut(r)).zip(coefficients) {
        let u = [
            e.top_x.re,
            e.top_x.im,
            e.bottom_x.re,
            e.bottom_x.im,
            e.top_y.re,
            e.top_y.im,
            e.bottom_y.re,
            e.bottom_y.im,
        ];
        let (h, k) = mode_kernel(z, g, s, &u);
        let c = |a: &Lanes, lane: usize| Complex64::new(a[lane], a[lane + 1]);
        *o = ModeSums {
            h11_top: c(&h, 0),
            h11_bottom: c(&h, 2),
            h22_top: c(&h, 4),
            h22_bottom: c(&h, 6),
            k12_top_x: c(&k, 0),
            k12_bottom_x: c(&k, 2),
            k12_top_y: c(&k, 4),
            k12_bottom_y: c(&k, 6),
        };
    }
}

/// The arguments of [`modes_kernel`] for one task: `r` poles a mode, then the modes' z, g,
/// states, spectra and sums.
type Task<'a, S> = (
    usize,
    &'a [Complex64],
    &'a [[Complex64; 3]],
    &'a mut [S],
    &'a [Entry],
    &'a mut [ModeSums],
);

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
fn modes_avx512<S: Stored>((r, z, g, s, e, o): Task<'_, S>) {
    modes_kernel(r, z, g, s, e, o)
}

fn dispatch_in<S: Stored>(isa: Isa, task: Task<'_, S>) {
    match isa {
        // SAFETY: `Isa::detect` returned these only if the CPU reported the features at run time.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { modes_avx512(task) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { avx2::modes(task) },
        _ => {
            let (r, z, g, s, e, o) = task;
            modes_kernel(r, z, g, s, e, o)
        }
    }
}

/// [`modes_kernel`] on `isa`'s build, for the states' storage.
fn dispatch(
    isa: Isa,
    r: usize,
    z: &[Complex64],
    g: &[[Complex64; 3]],
    s: StatesMut<'_>,
    e: &[Entry],
    o: &mut [ModeSums],
) {
    match s {
        StatesMut::F64(s) => dispatch_in(isa, (r, z, g, s, e, o)),
        StatesMut::F32(s) => dispatch_in(isa, (r, z, g, s, e, o)),
    }
}

impl FastConvolution {
    /// Coefficients for every mode j ≥ 1 (mode 0 has no history term), the states stored as
    /// `storage` says.
    pub fn new(modes: &Modes, fit: &SoeFit, storage: FastStorage) -> FastConvolution {
        let r = fit.poles.len();
        let nm = modes.k.len();
        let mut z = vec![Complex64::default(); nm * r];
        let mut g = vec![[Complex64::default(); 3]; nm * r];
        for j in 1..nm {
            let dtj = j as f64 * modes.dt1;
            for p in 0..r {
                let zz = (fit.poles[p] * dtj).exp();
                let f = 0.5 * dtj * (1.0 + zz) * fit.weight[p];
                z[j * r + p] = zz;
                g[j * r + p] = [fit.amps[0][p] * f, fit.amps[1][p] * f, fit.amps[2][p] * f];
            }
        }
        let s = match storage {
            FastStorage::F64 => States::F64(vec![State::default(); nm * r]),
            FastStorage::F32 => States::F32(vec![State32::default(); nm * r]),
        };
        FastConvolution {
            r,
            z,
            g,
            s,
            isa: Isa::detect(),
        }
    }

    /// Whether [`Block::fused`] gives its blocks to the one-loop pass (AVX-512F), in which each
    /// mode's spectra and sums stay in registers.
    pub(crate) fn fuses_modes(&self) -> bool {
        self.isa.fuses_modes()
    }

    /// Runs the recursion on `isa`'s build, one this CPU has ([`Isa::every_one_here`]).
    #[cfg(test)]
    pub(crate) fn set_isa(&mut self, isa: Isa) {
        self.isa = isa;
    }

    /// Bytes of coefficients and states touched per step [B].
    pub fn bytes(&self) -> usize {
        self.s.len() * bytes_per_pole(self.s.storage())
    }

    /// Work of the recursion over one step (docs/spectral-model.md §4.3): per mode
    /// j ≥ 1, its spectra Û read and its eight sums written; per pole of the mode, z and the
    /// three g read, the state read and written back, and [`FLOPS_PER_POLE`] flops. Mode 0's
    /// coefficients and states, which [`bytes`](FastConvolution::bytes) counts, are not touched.
    pub fn work(&self) -> Work {
        let modes = (self.s.len() / self.r.max(1)).saturating_sub(1) as f64;
        let poles = modes * self.r as f64;
        let storage = self.s.storage();
        let state = state_bytes(storage) as f64;
        Work {
            flops: poles * FLOPS_PER_POLE,
            read: modes * std::mem::size_of::<Entry>() as f64 + poles * bytes_per_pole(storage) as f64,
            written: modes * std::mem::size_of::<ModeSums>() as f64 + poles * state,
        }
    }

    /// The evolving part, for a checkpoint: the recursion states (poles, weights and `r` are the
    /// fit's).
    pub(crate) fn saved(&self) -> FastState<'_> {
        // `restore` names every field: one added there is one to think about here
        FastState {
            states: Cow::Borrowed(&self.s),
        }
    }

    /// Restores what [`FastConvolution::saved`] wrote into these states (built for the same
    /// scene).
    pub(crate) fn restore(&mut self, saved: &FastState<'_>) -> Result<(), String> {
        let FastConvolution {
            r: _,
            z: _,
            g: _,
            s,
            isa: _,
        } = self;
        let FastState { states } = saved;
        match (s, states.as_ref()) {
            (States::F64(s), States::F64(saved)) => fill(s, saved, "sum-of-exponentials states"),
            (States::F32(s), States::F32(saved)) => fill(s, saved, "sum-of-exponentials states"),
            (s, saved) => Err(format!(
                "its sum-of-exponentials states are stored as {}, the scene's spectral.fast_storage \
                 says {}",
                saved.storage().name(),
                s.storage().name()
            )),
        }
    }

    /// Pushes Û^n of every mode and writes the eight convolutions per mode into `out`: the
    /// recursion alone, as a pass of its own (the operator runs it inside its fused pass over the
    /// modes, `elastodynamics::split_recursion_assembly`).
    #[cfg(test)]
    pub(crate) fn step(&mut self, spectra: &[Entry], out: &mut [ModeSums]) {
        out[0] = ModeSums::default();
        let modes = out.len();
        self.blocks(1..modes)
            .zip(out[1..].par_chunks_mut(MODES_PER_TASK))
            .zip(spectra[1..].par_chunks(MODES_PER_TASK))
            .for_each(|((block, o), e)| block.step(e, o));
    }

    /// The modes `modes` in blocks of [`MODES_PER_TASK`] (the last one shorter), one rayon task
    /// each: a caller zips its own per-mode arrays, chunked alike, and does its work on a block's
    /// modes in the same task as their recursion.
    pub(crate) fn blocks(&mut self, modes: Range<usize>) -> impl IndexedParallelIterator<Item = Block<'_>> {
        use rayon::iter::Either;
        let (r, isa) = (self.r, self.isa);
        let (poles, at) = (r * MODES_PER_TASK, modes.start * r..modes.end * r);
        let states = match &mut self.s {
            States::F64(s) => Either::Left(s[at.clone()].par_chunks_mut(poles).map(StatesMut::F64)),
            States::F32(s) => Either::Right(s[at.clone()].par_chunks_mut(poles).map(StatesMut::F32)),
        };
        states
            .zip(
                self.z[at.clone()]
                    .par_chunks(poles)
                    .zip(self.g[at].par_chunks(poles)),
            )
            .map(move |(s, (z, g))| Block { r, isa, z, g, s })
    }

    /// Mode `j` alone, as a block.
    pub(crate) fn block(&mut self, j: usize) -> Block<'_> {
        let at = j * self.r..(j + 1) * self.r;
        Block {
            r: self.r,
            isa: self.isa,
            z: &self.z[at.clone()],
            g: &self.g[at.clone()],
            s: self.s.slice_mut(at),
        }
    }
}

/// Consecutive modes' coefficients and recursion states, from [`FastConvolution::blocks`] or
/// [`FastConvolution::block`].
pub(crate) struct Block<'a> {
    r: usize,
    isa: Isa,
    z: &'a [Complex64],
    g: &'a [[Complex64; 3]],
    s: StatesMut<'a>,
}

impl<'a> Block<'a> {
    /// Pushes Û^n of the block's modes (`spectra`, one a mode) and writes their eight
    /// convolutions into `out`.
    pub(crate) fn step(self, spectra: &[Entry], out: &mut [ModeSums]) {
        dispatch(self.isa, self.r, self.z, self.g, self.s, spectra, out);
    }

    /// The block as the one-loop pass over its modes takes it, if the CPU has AVX-512F; else
    /// the block back, for the split, [`step`](Block::step) and the assembly as passes of their
    /// own.
    pub(crate) fn fused(self) -> Result<FusedBlock<'a>, Block<'a>> {
        if self.isa.fuses_modes() {
            Ok(FusedBlock(self))
        } else {
            Err(self)
        }
    }
}

/// A block whose modes are split, pushed through the recursion and assembled in one loop, each
/// mode's spectra and sums in AVX-512 registers ([`avx512::modes`]); from [`Block::fused`].
pub(crate) struct FusedBlock<'a>(Block<'a>);

impl FusedBlock<'_> {
    /// Reads the block's modes from the packed transforms in `p`, pushes their Û^n and writes
    /// their F^± back in place: the bits of the split, [`Block::step`] and the assembly.
    pub(crate) fn step(self, p: Packed<'_>) {
        let Block { r, z, g, s, .. } = self.0;
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `Block::fused` made a FusedBlock only where `Isa::detect` found AVX-512F.
        unsafe {
            match s {
                StatesMut::F64(s) => avx512::modes(r, z, g, s, p),
                StatesMut::F32(s) => avx512::modes(r, z, g, s, p),
            }
        }
        // off x86-64 `Block::fused` never makes one
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (r, z, g, s, p);
    }
}

/// A block's modes in the two packed transforms (A = FFT(u^+_x + i u^+_y), B the same for the
/// bottom face), with what their F^± take: mode m (counted from the block's first) at `aj[m]`
/// and `bj[m]`, its conjugate N − j at `an` and `bn` read backwards. The transforms are read and
/// F^± written back to the same places.
pub(crate) struct Packed<'a> {
    /// A at the block's modes j.
    pub aj: &'a mut [Complex64],
    /// A at N − j, in the array's order (the block's last mode first).
    pub an: &'a mut [Complex64],
    /// B at j.
    pub bj: &'a mut [Complex64],
    /// B at N − j, in the array's order.
    pub bn: &'a mut [Complex64],
    /// k_j [1/m].
    pub k: &'a [f64],
    /// Shear modulus μ [Pa].
    pub mu: f64,
    /// 2 − η [-].
    pub c: f64,
}

/// Modes per rayon task of the recursion (each mode's result depends on that mode alone).
pub(crate) const MODES_PER_TASK: usize = 128;

/// The fast path's recursion states (§4.3; `crate::fast::FastConvolution`).
#[derive(Debug, Serialize, Deserialize)]
pub(crate) struct FastState<'a> {
    /// s_{j,p}(n) at [j r + p], mode 0 included (unused, zero), in the run's storage.
    pub states: Cow<'a, States>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// N = 8 (modes j = 0..=4, four with a history) and a fit of two poles: the work of a step
    /// counted by hand.
    #[test]
    fn work_of_a_step_is_counted_per_mode_and_pole() {
        let modes = Modes::new(8, 1.0, 0.2, 100.0, 10);
        let one = vec![Complex64::new(1.0, 0.0); 2];
        let fit = SoeFit {
            poles: vec![Complex64::new(-1.0, 0.5), Complex64::new(-2.0, 0.0)],
            weight: vec![2.0, 1.0],
            amps: [one.clone(), one.clone(), one],
            max_error: 0.0,
        };
        let fast = FastConvolution::new(&modes, &fit, FastStorage::F64);
        // state: 8 lanes × (re, im) × 8 B = 128 B; z 16 B; g 3 × 16 B
        assert_eq!(std::mem::size_of::<State>(), 128);
        assert_eq!(fast.bytes(), 5 * 2 * (16 + 48 + 128), "mode 0 included");
        let w = fast.work();
        // 4 modes × 2 poles × (8 lanes × (4 + 3) state update + 8 lanes × (4 + 4) sums)
        assert_eq!(w.flops, (4 * 2 * (8 * 7 + 8 * 8)) as f64);
        assert_eq!(w.flops, 960.0);
        // per mode Û read (4 complex, 64 B); per pole z, g and the state read
        assert_eq!(w.read, (4 * 64 + 4 * 2 * (16 + 48 + 128)) as f64);
        // per mode the 8 complex sums (128 B); per pole the state written back
        assert_eq!(w.written, (4 * 128 + 4 * 2 * 128) as f64);
        assert_eq!(w.bytes(), 3328.0);
        // in single precision: 8 lanes × (re, im) × 4 B = 64 B a state, the same flops
        let single = FastConvolution::new(&modes, &fit, FastStorage::F32);
        assert_eq!(std::mem::size_of::<State32>(), 64);
        assert_eq!(single.bytes(), 5 * 2 * (16 + 48 + 64));
        let w = single.work();
        assert_eq!(w.flops, 960.0);
        assert_eq!(w.read, (4 * 64 + 4 * 2 * (16 + 48 + 64)) as f64);
        assert_eq!(w.written, (4 * 128 + 4 * 2 * 64) as f64);
    }

    /// 600 points (301 modes: three tasks of 128, the last one short) and a fit of three poles.
    fn three_poles() -> (Modes, SoeFit) {
        let modes = Modes::new(600, 1.0, 0.2, 100.0, 10);
        let amps = |a: f64| {
            vec![
                Complex64::new(a, 0.3),
                Complex64::new(-0.7, a),
                Complex64::new(0.2, 0.0),
            ]
        };
        let fit = SoeFit {
            poles: vec![
                Complex64::new(-0.9, 0.41),
                Complex64::new(-2.3, 1.7),
                Complex64::new(-0.05, 0.0),
            ],
            weight: vec![2.0, 2.0, 1.0],
            amps: [amps(1.1), amps(-0.6), amps(0.35)],
            max_error: 0.0,
        };
        (modes, fit)
    }

    /// Spectra of step `n` that differ per mode, lane and step.
    fn spectra_of_step(nm: usize, n: usize) -> Vec<Entry> {
        let v = |j: usize, q: f64| {
            Complex64::new(
                (0.37 * j as f64 + q + 0.11 * n as f64).sin(),
                (q * j as f64).cos() / 3.0,
            )
        };
        (0..nm)
            .map(|j| Entry {
                top_x: v(j, 0.1),
                top_y: v(j, 0.2),
                bottom_x: v(j, 0.3),
                bottom_y: v(j, 0.4),
            })
            .collect()
    }

    /// The sixteen values of each mode's sums, in the order of [`ModeSums`].
    fn values(out: &[ModeSums]) -> Vec<f64> {
        out.iter()
            .flat_map(|o| {
                [
                    o.h11_top,
                    o.h11_bottom,
                    o.h22_top,
                    o.h22_bottom,
                    o.k12_top_x,
                    o.k12_bottom_x,
                    o.k12_top_y,
                    o.k12_bottom_y,
                ]
            })
            .flat_map(|c| [c.re, c.im])
            .collect()
    }

    /// Every instruction-set build the CPU has gives the portable build's bits, in both storages:
    /// 301 modes, three poles, 25 steps of spectra that differ per mode, lane and step. A build
    /// whose sums differ by one rounding fails it (one sum of the AVX-512 build scaled by
    /// 1 + 1e-15 did).
    #[test]
    fn every_instruction_set_gives_the_bits_of_the_portable_build() {
        let (modes, fit) = three_poles();
        let run = |isa: Isa, storage: FastStorage| {
            let mut fast = FastConvolution::new(&modes, &fit, storage);
            fast.isa = isa;
            let nm = modes.k.len();
            let mut out = vec![ModeSums::default(); nm];
            let mut bits = Vec::new();
            for n in 0..25 {
                fast.step(&spectra_of_step(nm, n), &mut out);
                bits.extend(values(&out).iter().map(|x| x.to_bits()));
            }
            bits
        };
        for storage in [FastStorage::F64, FastStorage::F32] {
            let portable = run(Isa::Portable, storage);
            assert!(portable.iter().any(|&b| f64::from_bits(b) != 0.0));
            for isa in Isa::every_one_here().into_iter().skip(1) {
                assert!(
                    run(isa, storage) == portable,
                    "{isa:?} differs from the portable build, states in {storage:?}"
                );
            }
        }
    }

    /// In single precision the states are kept rounded and the sums take them unrounded: from
    /// zero states, the first step's sums are those of double precision to the bit and its
    /// states those of double precision rounded to f32; the next step reads the rounded states,
    /// so its sums differ, within the rounding of a state (2⁻²⁴ relative) times the sums' terms.
    /// Fails if the sums take the rounded state (the first step then differs), or if the states
    /// are kept in double precision (the second step then agrees), on every build here.
    #[test]
    fn single_precision_storage_rounds_what_it_keeps_not_what_it_sums() {
        let (modes, fit) = three_poles();
        let nm = modes.k.len();
        for isa in Isa::every_one_here() {
            let mut double = FastConvolution::new(&modes, &fit, FastStorage::F64);
            let mut single = FastConvolution::new(&modes, &fit, FastStorage::F32);
            (double.isa, single.isa) = (isa, isa);
            let (mut od, mut os) = (vec![ModeSums::default(); nm], vec![ModeSums::default(); nm]);
            let first = spectra_of_step(nm, 0);
            double.step(&first, &mut od);
            single.step(&first, &mut os);
            let (vd, vs) = (values(&od), values(&os));
            assert!(
                vd.iter().zip(&vs).all(|(a, b)| a.to_bits() == b.to_bits()),
                "{isa:?}: the first step's sums differ"
            );
            let (States::F64(sd), States::F32(ss)) = (&double.s, &single.s) else {
                panic!("storage not as asked");
            };
            let mut inexact = 0;
            for (d, s) in sd.iter().zip(ss) {
                for q in 0..8 {
                    assert_eq!(s.re[q].to_bits(), (d.re[q] as f32).to_bits(), "{isa:?}");
                    assert_eq!(s.im[q].to_bits(), (d.im[q] as f32).to_bits(), "{isa:?}");
                    inexact += usize::from(f64::from(s.re[q]) != d.re[q]);
                }
            }
            assert!(
                inexact > 1000,
                "{isa:?}: the test needs states that f32 rounds ({inexact})"
            );
            let second = spectra_of_step(nm, 1);
            double.step(&second, &mut od);
            single.step(&second, &mut os);
            let (vd, vs) = (values(&od), values(&os));
            let scale = vd.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let worst = vd.iter().zip(&vs).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            // each sum adds 3 poles × 2 products of a state and a g of magnitude ≤ about 1:
            // a few 2⁻²⁴ ≈ 6e-8 of the largest sum, and not zero
            assert!(worst > 0.0, "{isa:?}: the second step read unrounded states");
            assert!(
                worst <= 1e-6 * scale,
                "{isa:?}: {worst:e} against sums up to {scale:e}"
            );
        }
    }
}
