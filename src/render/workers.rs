//! The threads a render runs on. Each reads denormal floats as zero and flushes
//! denormal results to zero (x86's DAZ and FTZ, Arm's FZ), as Embree asks of the
//! threads that call it and Cycles sets for its own.
//!
//! Why: the processor finishes an operation that meets or makes a denormal in a
//! microcode assist of a hundred cycles or more, and compiled code meets them where no
//! value of the program is denormal at all. A vector operation on two lanes of four
//! leaves its other two lanes as whatever earlier arithmetic left there, and two small
//! leftovers multiplied underflow. Building a sphere light's cone made such a denormal
//! at 41 % of the showcase's light samples, though every value it returns is
//! ordinary. Flushed, those cost nothing; and a value of the picture that small (below
//! 2^-126) is zero at any exposure.

use crate::error::{Error, Result};

/// x86's MXCSR bits: denormal results flushed to zero (FTZ), denormal operands read
/// as zero (DAZ).
#[cfg(target_arch = "x86_64")]
const FLUSH_TO_ZERO: u32 = 1 << 15;
#[cfg(target_arch = "x86_64")]
const DENORMALS_ARE_ZERO: u32 = 1 << 6;

/// Arm's FPCR bit that flushes denormal operands and results to zero (FZ).
#[cfg(target_arch = "aarch64")]
const FLUSH_ZERO: u64 = 1 << 24;

/// A pool of `threads` threads (one a core without a count) that flush denormals,
/// for the work of one render.
pub fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .start_handler(|_| flush_denormals())
        .build()
        .map_err(|e| Error::Settings(format!("cannot start threads: {e}")))
}

/// Denormal operands and results read and written as zero on this thread from now on.
pub fn flush_denormals() {
    #[cfg(target_arch = "x86_64")]
    {
        let mut csr = 0u32;
        // SAFETY: stmxcsr and ldmxcsr read and write the thread's own SSE control
        // word; the bits set change how denormals are read and written, nothing else.
        unsafe {
            std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack, preserves_flags));
            csr |= FLUSH_TO_ZERO | DENORMALS_ARE_ZERO;
            std::arch::asm!("ldmxcsr [{}]", in(reg) &csr, options(nostack, preserves_flags));
        }
    }
    #[cfg(target_arch = "aarch64")]
    {
        // SAFETY: as above, the thread's own floating-point control register.
        unsafe {
            let mut fpcr: u64;
            std::arch::asm!("mrs {}, fpcr", out(reg) fpcr, options(nomem, nostack, preserves_flags));
            fpcr |= FLUSH_ZERO;
            std::arch::asm!("msr fpcr, {}", in(reg) fpcr, options(nomem, nostack, preserves_flags));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The smallest normal float halved: a denormal a product makes from normal
    /// operands, and an operand that is itself denormal.
    #[test]
    fn a_pool_thread_flushes_what_the_calling_thread_keeps() {
        let tiny = std::hint::black_box(f32::MIN_POSITIVE);
        let half = std::hint::black_box(0.5f32);
        let denormal = std::hint::black_box(f32::MIN_POSITIVE / 4.0);
        let here = (tiny * half, denormal * 2.0);
        assert!(here.0 > 0.0 && here.0.is_subnormal());
        assert_eq!(here.1, f32::MIN_POSITIVE / 2.0);
        let pool = pool(Some(2)).unwrap();
        let there = pool.install(|| {
            let (tiny, half, denormal) = std::hint::black_box((tiny, half, denormal));
            (tiny * half, denormal * 2.0)
        });
        if cfg!(any(target_arch = "x86_64", target_arch = "aarch64")) {
            assert_eq!(there.0.to_bits(), 0, "the product is flushed");
            assert_eq!(there.1.to_bits(), 0, "the denormal operand reads as zero");
        }
        // The calling thread is left as it was.
        assert!((tiny * half).is_subnormal());
    }
}
