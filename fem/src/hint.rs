//! Hints to the processor: they change no value, only when memory is read.

/// Asks the cache for the lines that hold `v[i]`, one a 64 bytes of it from its start (nothing if
/// `i` is out of range): a hint, with no effect on any value.
#[inline(always)]
pub(crate) fn prefetch<T>(v: &[T], i: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(x) = v.get(i) {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let start = std::ptr::from_ref(x).cast::<i8>();
        for offset in (0..size_of::<T>().max(1)).step_by(64) {
            // SAFETY: SSE is part of every x86_64 CPU; a prefetch reads nothing, and the address
            // lies inside `v[i]`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(offset)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (v, i);
}
