//! Frame ranges for animated scenes: `A-B[:step]` (or a single frame `N`), as `luxfarm submit
//! --frames` takes them. Frames may be negative (`-10--2`); the range is inclusive.
//!
//! ```text
//! "1-120:5" --FromStr--> FrameRange { first 1, last 120, step 5 } --frames()--> 1, 6, ..., 116
//! ```

use std::fmt;
use std::str::FromStr;

/// Most frames one `--frames` may submit (one job each).
pub const MAX_FRAMES: u64 = 100_000;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    pub first: i64,
    pub last: i64,
    pub step: i64,
}

impl FrameRange {
    /// The frames, first to last by step.
    pub fn frames(&self) -> impl Iterator<Item = i64> {
        let (first, last, step) = (self.first, self.last, self.step);
        (0..)
            .map(move |k: i64| first.saturating_add(k.saturating_mul(step)))
            .take_while(move |&f| f <= last)
    }

    pub fn len(&self) -> u64 {
        ((self.last as i128 - self.first as i128) / self.step as i128 + 1) as u64
    }
}

impl fmt::Display for FrameRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-{}:{}", self.first, self.last, self.step)
    }
}

impl FromStr for FrameRange {
    type Err = String;

    fn from_str(s: &str) -> Result<FrameRange, String> {
        let s = s.trim();
        let (range, step) = match s.split_once(':') {
            Some((r, st)) => (r, Some(st)),
            None => (s, None),
        };
        let step = match step {
            Some(st) => st
                .parse::<i64>()
                .ok()
                .filter(|&v| v >= 1)
                .ok_or_else(|| format!("step {st:?} must be a whole number of at least 1"))?,
            None => 1,
        };
        // The dash between the bounds follows a digit (a leading dash is a sign).
        let bytes = range.as_bytes();
        let split = (1..bytes.len()).find(|&i| bytes[i] == b'-' && bytes[i - 1].is_ascii_digit());
        let num = |t: &str| {
            t.parse::<i64>()
                .map_err(|_| format!("{t:?} is not a frame number (expected A-B[:step])"))
        };
        let (first, last) = match split {
            Some(i) => (num(&range[..i])?, num(&range[i + 1..])?),
            None => {
                let n = num(range)?;
                (n, n)
            }
        };
        if last < first {
            return Err(format!("the range {first}-{last} ends before it starts"));
        }
        let r = FrameRange { first, last, step };
        if r.len() > MAX_FRAMES {
            return Err(format!(
                "{} frames in {s:?}: at most {MAX_FRAMES} per submission",
                r.len()
            ));
        }
        Ok(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(s: &str) -> Vec<i64> {
        s.parse::<FrameRange>().unwrap().frames().collect()
    }

    #[test]
    fn parses_ranges_steps_and_single_frames() {
        assert_eq!(frames("1-5"), vec![1, 2, 3, 4, 5]);
        assert_eq!(frames("0-10:4"), vec![0, 4, 8]);
        assert_eq!(frames("12"), vec![12]);
        assert_eq!(frames("-3--1"), vec![-3, -2, -1]);
        assert_eq!(frames("-2-1:2"), vec![-2, 0]);
        assert_eq!("1-120".parse::<FrameRange>().unwrap().len(), 120);
    }

    #[test]
    fn refuses_bad_ranges() {
        for bad in ["", "a-b", "5-1", "1-5:0", "1-5:-1", "1-5:x", "0-1000000"] {
            assert!(bad.parse::<FrameRange>().is_err(), "{bad}");
        }
    }
}
