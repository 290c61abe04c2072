//! Which vector instructions the intersectors use, chosen once when the process starts
//! using them: AVX2 with FMA where the processor has them, else the SSE2 every x86-64
//! has (other architectures get what the compiler targets).
//!
//! Every path computes the same products and sums in the same order, without fused
//! multiply-add, so the hits — and the images — are the same bit for bit whichever
//! path runs. `PRISM_SIMD=sse2` forces the baseline path (to compare, or to rule it
//! out); `PRISM_SIMD=avx2` on a processor without AVX2 falls back to SSE2. The path
//! model's lanes take AVX-512 too where the processor has it ([`avx512_wanted`]),
//! unless `PRISM_SIMD` names a level.

use std::sync::OnceLock;

/// The environment variable that overrides the detected level.
pub const SIMD_ENV: &str = "PRISM_SIMD";

/// A set of vector instructions the intersectors' kernels are compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimdLevel {
    /// The architecture's baseline: SSE2 on x86-64.
    Baseline,
    /// x86-64 with AVX2 and FMA: eight lanes, three-operand instructions.
    Avx2,
}

impl SimdLevel {
    /// Lower-case name, as [`SIMD_ENV`] takes it and benchmarks report it: `sse2` (the
    /// x86-64 baseline), `baseline` on other architectures, or `avx2`.
    pub fn name(self) -> &'static str {
        match self {
            SimdLevel::Baseline if cfg!(target_arch = "x86_64") => "sse2",
            SimdLevel::Baseline => "baseline",
            SimdLevel::Avx2 => "avx2",
        }
    }

    /// The best level this processor runs.
    pub fn best_supported() -> SimdLevel {
        if avx2_supported() {
            SimdLevel::Avx2
        } else {
            SimdLevel::Baseline
        }
    }

    /// `self` if the processor runs it, else the baseline.
    pub fn supported(self) -> SimdLevel {
        match self {
            SimdLevel::Avx2 if avx2_supported() => SimdLevel::Avx2,
            _ => SimdLevel::Baseline,
        }
    }

    /// The level in use: the best supported, unless [`SIMD_ENV`] says otherwise. Read
    /// once per process.
    pub fn current() -> SimdLevel {
        static LEVEL: OnceLock<SimdLevel> = OnceLock::new();
        *LEVEL.get_or_init(|| match std::env::var(SIMD_ENV).as_deref() {
            Ok("sse2" | "baseline") => SimdLevel::Baseline,
            Ok("avx2") => SimdLevel::Avx2.supported(),
            _ => SimdLevel::best_supported(),
        })
    }
}

/// Whether code that would gain from sixteen lanes (the path model's lanes) may use
/// AVX-512 (F, VL, DQ and BW): at the AVX2 level, unless [`SIMD_ENV`] asks for AVX2
/// itself, on a processor that has them. Read once per process.
pub fn avx512_wanted() -> bool {
    static WANTED: OnceLock<bool> = OnceLock::new();
    *WANTED.get_or_init(|| {
        SimdLevel::current() == SimdLevel::Avx2
            && std::env::var(SIMD_ENV).as_deref() != Ok("avx2")
            && avx512_supported()
    })
}

/// Whether the processor runs AVX-512 F, VL, DQ and BW.
pub fn avx512_supported() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
            && std::arch::is_x86_feature_detected!("avx512dq")
            && std::arch::is_x86_feature_detected!("avx512bw")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

fn avx2_supported() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_fall_back_to_what_the_processor_runs() {
        assert_eq!(SimdLevel::Baseline.supported(), SimdLevel::Baseline);
        let best = SimdLevel::best_supported();
        assert_eq!(SimdLevel::Avx2.supported(), best);
        assert!(matches!(
            SimdLevel::current(),
            SimdLevel::Baseline | SimdLevel::Avx2
        ));
        #[cfg(target_arch = "x86_64")]
        assert_eq!(SimdLevel::Baseline.name(), "sse2");
    }
}
