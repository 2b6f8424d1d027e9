//! Helpers the benchmarks share: where the shared material is (scenes, references, the
//! LuxCore script), timing the best of several runs, the machine's load, and resolutions
//! given as `WIDTHxHEIGHT`.

use std::path::PathBuf;
use std::time::Instant;

/// The shared material: `../shared` beside the repository when it holds `scenes/`, else
/// `/work/shared`.
pub fn shared_dir() -> PathBuf {
    let beside = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared"));
    if beside.join("scenes").is_dir() {
        beside
    } else {
        PathBuf::from("/work/shared")
    }
}

/// Runs `f` `runs` times (at least once): the fastest time in seconds and the last result.
pub fn best<T>(runs: u32, mut f: impl FnMut() -> T) -> (f64, T) {
    let time = |f: &mut dyn FnMut() -> T| {
        let t = Instant::now();
        let r = f();
        (t.elapsed().as_secs_f64(), r)
    };
    let (mut fastest, mut last) = time(&mut f);
    for _ in 1..runs {
        let (s, r) = time(&mut f);
        fastest = fastest.min(s);
        last = r;
    }
    (fastest, last)
}

/// The machine as a benchmark reports it: cores, the build (a `scripts/build-production`
/// binary, which farm nodes run, or another) and the instruction-set level its render core was
/// built for (a production install runs its CPU's best: `luxfarm::isa`), and the load.
pub fn machine() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let build = match option_env!("LUXFARM_BUILD_ID") {
        Some(id) => format!("production build {id}"),
        None => "not a production build (farm nodes run scripts/build-production's)".into(),
    };
    format!(
        "{cores} cores, {build}, render core built for {}, load average {}",
        luxfarm::isa::build_name(),
        loadavg()
    )
}

/// The 1, 5 and 15 minute load averages ("?" where /proc is missing).
pub fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

/// Parses `WxH` (or `WXH`) into a film size the render core accepts.
pub fn parse_res(s: &str) -> anyhow::Result<(u32, u32)> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| anyhow::anyhow!("resolution {s:?} is not WIDTHxHEIGHT"))?;
    let (w, h) = (w.trim().parse()?, h.trim().parse()?);
    luxfarm::film::check_size(w, h)?;
    Ok((w, h))
}

/// The number after `name=` in a `key=value` statistics line (the renderer scripts' output).
pub fn stat(text: &str, name: &str) -> Option<f64> {
    text.split_whitespace()
        .find_map(|w| w.strip_prefix(name)?.strip_prefix('='))
        .and_then(|v| v.parse::<f64>().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolutions() {
        assert_eq!(parse_res("1920x1080").unwrap(), (1920, 1080));
        assert_eq!(parse_res(" 64 X 48").unwrap(), (64, 48));
        assert!(parse_res("1920").is_err());
        assert!(parse_res("0x10").is_err());
        assert!(parse_res("ax10").is_err());
    }

    #[test]
    fn best_keeps_the_last_result() {
        let mut n = 0;
        let (secs, last) = best(3, || {
            n += 1;
            n
        });
        assert_eq!(last, 3);
        assert!(secs >= 0.0);
    }
}
