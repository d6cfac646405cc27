//! Hints to the processor's caches.

/// Ask the processor to bring the cache line holding `value` into its
/// caches ahead of its use (an `_mm_prefetch` hint on x86-64, nothing
/// elsewhere). It reads nothing and never faults.
#[inline(always)]
pub(crate) fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: a prefetch is a hint that reads nothing and never
        // faults; the address is of a live value anyway.
        #[allow(unsafe_code)]
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(value).cast());
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}
