//! CPU-feature dispatch: which vector width the per-body loops (the step's kernel, the state
//! hash's record writer) run with.
//!
//! The bottom layer: nothing here imports another module of the crate.

/// The vector instruction set the per-body loop runs with, chosen once per process.
///
/// The loop is compiled three times: for the baseline target (SSE2 on x86-64) and, behind
/// `#[target_feature]`, for AVX2 and AVX-512, used when the CPU has them. Every version executes
/// the same IEEE-754 operations in the same order (Rust never fuses a multiply and an add on its
/// own, and the code never calls `mul_add`), so only the width differs and the results are
/// bit-identical on every machine. `VOLLEY_SIMD=baseline|avx2|avx512` caps the choice, to compare
/// the versions (`tests/cli/simd.rs` does).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum SimdLevel {
    /// The target's baseline (SSE2 on x86-64, whatever the target has elsewhere).
    Baseline,
    /// 256-bit vectors, 4 f64 lanes.
    Avx2,
    /// 512-bit vectors, 8 f64 lanes.
    Avx512,
}

/// The [`SimdLevel`] in use: the widest the CPU supports, capped by `VOLLEY_SIMD`
/// ([`simd_level_for`] of its value, read once per process).
pub fn simd_level() -> SimdLevel {
    static LEVEL: std::sync::OnceLock<SimdLevel> = std::sync::OnceLock::new();
    *LEVEL.get_or_init(|| simd_level_for(std::env::var("VOLLEY_SIMD").ok().as_deref()))
}

/// The [`SimdLevel`] [`simd_level`] chooses when `VOLLEY_SIMD` is `cap` (`None`: unset): the
/// widest the CPU supports, at most `baseline` or `avx2` if the cap names one. The SIMD tests
/// ask it which loop a run under each cap takes, without starting a process per cap.
pub fn simd_level_for(cap: Option<&str>) -> SimdLevel {
    let cap = match cap {
        Some("baseline") => SimdLevel::Baseline,
        Some("avx2") => SimdLevel::Avx2,
        _ => SimdLevel::Avx512,
    };
    detected_level().min(cap)
}

#[cfg(target_arch = "x86_64")]
fn detected_level() -> SimdLevel {
    if std::arch::is_x86_feature_detected!("avx512f") {
        SimdLevel::Avx512
    } else if std::arch::is_x86_feature_detected!("avx2") {
        SimdLevel::Avx2
    } else {
        SimdLevel::Baseline
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn detected_level() -> SimdLevel {
    SimdLevel::Baseline
}
