//! Instruction-set levels: the x86-64 microarchitecture level this code was compiled for
//! ([`BUILD`]) and the highest one the running CPU supports ([`cpu_level`]).
//!
//! The levels are the x86-64 psABI's: `x86-64` (SSE2), `x86-64-v2` (adds SSE3, SSSE3,
//! SSE4.1/4.2, POPCNT, CMPXCHG16B, LAHF/SAHF), `x86-64-v3` (adds AVX, AVX2, BMI1/2, F16C, FMA,
//! LZCNT, MOVBE) and `x86-64-v4` (adds AVX-512 F/BW/CD/DQ/VL). LAHF/SAHF (every v2 CPU has
//! them) is not tested. A production install carries
//! the render core built for several levels; the `luxfarm` binary starts the best one the CPU
//! runs (the client's `isa` module), so every farm node runs the same install at its CPU's
//! speed. Benchmarks print [`BUILD`] beside their numbers. On other architectures the level is
//! the architecture's name and no dispatch happens.
//!
//! Nothing here imports the rest of the crate.

/// An x86-64 microarchitecture level, lowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    V1,
    V2,
    V3,
    V4,
}

impl Level {
    /// Every level, lowest first.
    pub const ALL: [Level; 4] = [Level::V1, Level::V2, Level::V3, Level::V4];

    /// The psABI's name, as `-Ctarget-cpu` takes it and as the production build names its
    /// binaries (`luxfarm-x86-64-v3`).
    pub fn name(self) -> &'static str {
        match self {
            Level::V1 => "x86-64",
            Level::V2 => "x86-64-v2",
            Level::V3 => "x86-64-v3",
            Level::V4 => "x86-64-v4",
        }
    }

    /// The highest level whose features are all present, given whether v2's, v2's and v3's,
    /// and all of v4's are (each test includes the ones below it).
    const fn highest(v2: bool, v3: bool, v4: bool) -> Level {
        if v4 {
            Level::V4
        } else if v3 {
            Level::V3
        } else if v2 {
            Level::V2
        } else {
            Level::V1
        }
    }

    /// The level named `name` (as [`Level::name`] gives it).
    pub fn from_name(name: &str) -> Option<Level> {
        Level::ALL.into_iter().find(|l| l.name() == name)
    }
}

/// The level this code was compiled for (`None` off x86-64).
pub const BUILD: Option<Level> = build_level();

const fn build_level() -> Option<Level> {
    if !cfg!(target_arch = "x86_64") {
        return None;
    }
    let v2 = cfg!(all(
        target_feature = "sse3",
        target_feature = "ssse3",
        target_feature = "sse4.1",
        target_feature = "sse4.2",
        target_feature = "popcnt"
    ));
    let v3 = v2
        && cfg!(all(
            target_feature = "avx",
            target_feature = "avx2",
            target_feature = "bmi1",
            target_feature = "bmi2",
            target_feature = "f16c",
            target_feature = "fma",
            target_feature = "lzcnt",
            target_feature = "movbe"
        ));
    let v4 = v3
        && cfg!(all(
            target_feature = "avx512f",
            target_feature = "avx512bw",
            target_feature = "avx512cd",
            target_feature = "avx512dq",
            target_feature = "avx512vl"
        ));
    Some(Level::highest(v2, v3, v4))
}

/// The name of the level this code was compiled for, or the architecture's name off x86-64.
pub fn build_name() -> &'static str {
    BUILD.map_or(std::env::consts::ARCH, Level::name)
}

/// The highest level the running CPU (and operating system: AVX state saving) supports;
/// `None` off x86-64.
pub fn cpu_level() -> Option<Level> {
    detect::cpu_level()
}

#[cfg(target_arch = "x86_64")]
mod detect {
    use super::Level;

    pub fn cpu_level() -> Option<Level> {
        let v2 = is_x86_feature_detected!("sse3")
            && is_x86_feature_detected!("ssse3")
            && is_x86_feature_detected!("sse4.1")
            && is_x86_feature_detected!("sse4.2")
            && is_x86_feature_detected!("popcnt")
            && is_x86_feature_detected!("cmpxchg16b");
        let v3 = v2
            && is_x86_feature_detected!("avx")
            && is_x86_feature_detected!("avx2")
            && is_x86_feature_detected!("bmi1")
            && is_x86_feature_detected!("bmi2")
            && is_x86_feature_detected!("f16c")
            && is_x86_feature_detected!("fma")
            && is_x86_feature_detected!("lzcnt")
            && is_x86_feature_detected!("movbe");
        let v4 = v3
            && is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512bw")
            && is_x86_feature_detected!("avx512cd")
            && is_x86_feature_detected!("avx512dq")
            && is_x86_feature_detected!("avx512vl");
        Some(Level::highest(v2, v3, v4))
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod detect {
    pub fn cpu_level() -> Option<super::Level> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_in_order() {
        for l in Level::ALL {
            assert_eq!(Level::from_name(l.name()), Some(l));
        }
        assert!(Level::ALL.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(Level::from_name("x86-64-v5"), None);
    }

    /// The running code's own instructions work here, so the CPU is at least at its level.
    #[test]
    fn the_cpu_runs_the_build_level() {
        assert_eq!(BUILD.is_some(), cfg!(target_arch = "x86_64"));
        assert!(cpu_level() >= BUILD);
        if cfg!(target_arch = "x86_64") {
            assert!(cpu_level().is_some());
        }
    }
}
