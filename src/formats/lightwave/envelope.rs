//! LightWave envelopes: a value as a function of time, read from `{ Envelope ... }` blocks and
//! evaluated at any time.
//!
//! ```text
//! { Envelope / nkeys / Key value time span p1..p6 ... / Behaviors pre post }
//!   --read()--> Envelope { keys, pre, post } --value(t)--> f64
//! ```
//!
//! Facts from the LWSC specification and the LightWave SDK's envelope sample (see the README's
//! LightWave section): the span type stored on a key governs the span that *ends* at that key:
//! TCB (Kochanek–Bartels), Hermite, 1-D Bézier (the same as Hermite), linear, stepped, 2-D
//! Bézier. For TCB/Hermite keys p1..p3 are tension, continuity and bias, p4 and p5 the incoming
//! and outgoing tangents; for 2-D Bézier keys p1, p2 are the incoming (time, value) offsets and
//! p3, p4 the outgoing ones. Before the first key and after the last the pre/post behaviour
//! extrapolates: reset (0), constant, repeat, oscillate, offset repeat, linear. Values are f64.

use super::text::{integer, number, Cursor, Line};
use crate::lxs::{Loc, LxsError, LxsErrorKind};

/// How the span ending at a key is interpolated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Span {
    Tcb,
    Hermite,
    Bezier1d,
    Linear,
    Stepped,
    Bezier2d,
}

impl Span {
    fn from_code(code: i64) -> Option<Span> {
        Some(match code {
            0 => Span::Tcb,
            1 => Span::Hermite,
            2 => Span::Bezier1d,
            3 => Span::Linear,
            4 => Span::Stepped,
            5 => Span::Bezier2d,
            _ => return None,
        })
    }
}

/// Extrapolation before the first key (pre) or after the last (post).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Behavior {
    Reset,
    Constant,
    Repeat,
    Oscillate,
    OffsetRepeat,
    Linear,
}

impl Behavior {
    fn from_code(code: i64) -> Option<Behavior> {
        Some(match code {
            0 => Behavior::Reset,
            1 => Behavior::Constant,
            2 => Behavior::Repeat,
            3 => Behavior::Oscillate,
            4 => Behavior::OffsetRepeat,
            5 => Behavior::Linear,
            _ => return None,
        })
    }
}

/// One key: value at a time (seconds), with the parameters of its span.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Key {
    pub value: f64,
    pub time: f64,
    pub span: Span,
    /// p1..p6 as written (see the module doc for their meaning per span type).
    pub p: [f64; 6],
}

impl Key {
    fn tension(&self) -> f64 {
        self.p[0]
    }
    fn continuity(&self) -> f64 {
        self.p[1]
    }
    fn bias(&self) -> f64 {
        self.p[2]
    }
    /// Hermite incoming tangent.
    fn tan_in(&self) -> f64 {
        self.p[3]
    }
    /// Hermite outgoing tangent.
    fn tan_out(&self) -> f64 {
        self.p[4]
    }
}

/// An envelope: keys in increasing time, and its behaviours.
#[derive(Clone, Debug, PartialEq)]
pub struct Envelope {
    pub keys: Vec<Key>,
    pub pre: Behavior,
    pub post: Behavior,
}

/// A parameter that is a constant or an envelope (`LightIntensity (envelope)`).
#[derive(Clone, Debug, PartialEq)]
pub enum Animated {
    Const(f64),
    Env(Envelope),
}

impl Animated {
    pub fn at(&self, time: f64) -> f64 {
        match self {
            Animated::Const(v) => *v,
            Animated::Env(e) => e.value(time),
        }
    }
}

impl Envelope {
    /// Reads the block that `open` (a `{ Envelope` line, consumed) begins, up to its `}`.
    /// Plug-in channel modifiers (`{ ChannelHandler ...`) are skipped and reported through
    /// `skipped` with their location.
    pub fn read(
        cur: &mut Cursor,
        open: &Line,
        skipped: &mut Vec<(Loc, String)>,
    ) -> Result<Envelope, LxsError> {
        let open_loc = cur.loc(open);
        let count_line = cur.expect_line(open, "the envelope's key count")?;
        let count_loc = cur.loc(&count_line);
        let declared = integer(
            count_line.tokens().first(),
            "Envelope key count",
            &count_loc,
        )?;
        if declared < 1 {
            return Err(LxsError::new(
                LxsErrorKind::InvalidValue,
                count_loc,
                format!("an envelope needs at least one key, not {declared}"),
            ));
        }
        let mut keys: Vec<Key> = Vec::new();
        let mut behaviors = None;
        loop {
            let l = cur.expect_line(open, "this Envelope is closed by `}`")?;
            let loc = cur.loc(&l);
            if l.closes_block() {
                break;
            }
            if l.opens_block() {
                let name = l.block_name().to_string();
                cur.skip_block(&l)?;
                skipped.push((loc, name));
                continue;
            }
            let t = l.tokens();
            match t.first().copied() {
                Some("Key") => keys.push(read_key(&t, &loc)?),
                Some("Behaviors") => {
                    let pre = behavior(t.get(1), &loc)?;
                    let post = behavior(t.get(2), &loc)?;
                    behaviors = Some((pre, post));
                }
                Some(other) => {
                    return Err(LxsError::new(
                        LxsErrorKind::Syntax,
                        loc,
                        format!("unexpected {other:?} inside an Envelope block"),
                    ))
                }
                None => {}
            }
        }
        if keys.len() as i64 != declared {
            return Err(LxsError::new(
                LxsErrorKind::WrongValueCount,
                count_loc,
                format!(
                    "the envelope declares {declared} keys but holds {}",
                    keys.len()
                ),
            ));
        }
        if keys.windows(2).any(|w| w[1].time < w[0].time) {
            return Err(LxsError::new(
                LxsErrorKind::InvalidValue,
                open_loc,
                "envelope keys are not in increasing time order",
            ));
        }
        let (pre, post) = behaviors.unwrap_or((Behavior::Constant, Behavior::Constant));
        Ok(Envelope { keys, pre, post })
    }

    /// The value at `time` (seconds).
    pub fn value(&self, time: f64) -> f64 {
        let (Some(first), Some(last)) = (self.keys.first(), self.keys.last()) else {
            return 0.0;
        };
        if self.keys.len() == 1 {
            return first.value;
        }
        let span = last.time - first.time;
        let mut t = time;
        let mut offset = 0.0;
        if time < first.time || time > last.time {
            let before = time < first.time;
            let behavior = if before { self.pre } else { self.post };
            match behavior {
                Behavior::Reset => return 0.0,
                Behavior::Constant => return if before { first.value } else { last.value },
                Behavior::Linear => return self.linear_extrapolation(time, before),
                Behavior::Repeat | Behavior::Oscillate | Behavior::OffsetRepeat => {
                    if span <= 0.0 {
                        return if before { first.value } else { last.value };
                    }
                    let cycles = ((time - first.time) / span).floor();
                    t = time - cycles * span;
                    match behavior {
                        Behavior::Oscillate if cycles.rem_euclid(2.0) == 1.0 => {
                            t = last.time - (t - first.time);
                        }
                        Behavior::OffsetRepeat => offset = cycles * (last.value - first.value),
                        _ => {}
                    }
                }
            }
        }
        self.interpolate(t) + offset
    }

    /// The value inside [first, last] key times.
    fn interpolate(&self, time: f64) -> f64 {
        let n = self.keys.len();
        // The span [k0, k1] holding `time`.
        let i1 = self
            .keys
            .iter()
            .position(|k| k.time >= time)
            .unwrap_or(n - 1)
            .max(1);
        let (k0, k1) = (&self.keys[i1 - 1], &self.keys[i1]);
        if time == k1.time {
            return k1.value;
        }
        if time <= k0.time {
            return k0.value;
        }
        let dt = k1.time - k0.time;
        if dt <= 0.0 {
            return k1.value;
        }
        let s = (time - k0.time) / dt;
        match k1.span {
            Span::Tcb | Span::Hermite | Span::Bezier1d => {
                let out = self.outgoing(i1 - 1);
                let inc = self.incoming(i1);
                let (h1, h2, h3, h4) = hermite_basis(s);
                h1 * k0.value + h2 * k1.value + h3 * out + h4 * inc
            }
            Span::Linear => k0.value + s * (k1.value - k0.value),
            Span::Stepped => k0.value,
            Span::Bezier2d => bezier2d(k0, k1, time),
        }
    }

    /// The outgoing tangent of key `i` towards key `i + 1` (value change over that span).
    fn outgoing(&self, i: usize) -> f64 {
        let k0 = &self.keys[i];
        let Some(k1) = self.keys.get(i + 1) else {
            return 0.0;
        };
        let prev = i.checked_sub(1).map(|p| &self.keys[p]);
        let d = k1.value - k0.value;
        // Share of the two spans around k0 that the outgoing span takes.
        let share = |p: &Key| ratio(k1.time - k0.time, k1.time - p.time);
        match k0.span {
            Span::Tcb => {
                let a = (1.0 - k0.tension()) * (1.0 + k0.continuity()) * (1.0 + k0.bias());
                let b = (1.0 - k0.tension()) * (1.0 - k0.continuity()) * (1.0 - k0.bias());
                match prev {
                    Some(p) => share(p) * (a * (k0.value - p.value) + b * d),
                    None => b * d,
                }
            }
            Span::Linear => match prev {
                Some(p) => share(p) * (k0.value - p.value + d),
                None => d,
            },
            Span::Hermite | Span::Bezier1d => match prev {
                Some(p) => k0.tan_out() * share(p),
                None => k0.tan_out(),
            },
            Span::Bezier2d => slope_times(k0.p[3], k0.p[2], k1.time - k0.time),
            Span::Stepped => 0.0,
        }
    }

    /// The incoming tangent of key `i` from key `i - 1`.
    fn incoming(&self, i: usize) -> f64 {
        let k1 = &self.keys[i];
        let Some(k0) = i.checked_sub(1).map(|p| &self.keys[p]) else {
            return 0.0;
        };
        let next = self.keys.get(i + 1);
        let d = k1.value - k0.value;
        let share = |n: &Key| ratio(k1.time - k0.time, n.time - k0.time);
        match k1.span {
            Span::Tcb => {
                let a = (1.0 - k1.tension()) * (1.0 - k1.continuity()) * (1.0 + k1.bias());
                let b = (1.0 - k1.tension()) * (1.0 + k1.continuity()) * (1.0 - k1.bias());
                match next {
                    Some(n) => share(n) * (b * (n.value - k1.value) + a * d),
                    None => a * d,
                }
            }
            Span::Linear => match next {
                Some(n) => share(n) * (n.value - k1.value + d),
                None => d,
            },
            Span::Hermite | Span::Bezier1d => match next {
                Some(n) => k1.tan_in() * share(n),
                None => k1.tan_in(),
            },
            Span::Bezier2d => slope_times(k1.p[1], k1.p[0], k1.time - k0.time),
            Span::Stepped => 0.0,
        }
    }

    /// Linear pre/post behaviour: the tangent at the nearest key, continued.
    fn linear_extrapolation(&self, time: f64, before: bool) -> f64 {
        let n = self.keys.len();
        if before {
            let (k0, k1) = (&self.keys[0], &self.keys[1]);
            let slope = ratio(self.outgoing(0), k1.time - k0.time);
            k0.value + slope * (time - k0.time)
        } else {
            let (k0, k1) = (&self.keys[n - 2], &self.keys[n - 1]);
            let slope = ratio(self.incoming(n - 1), k1.time - k0.time);
            k1.value + slope * (time - k1.time)
        }
    }
}

/// a / b, or 0 when b is 0 (coincident key times).
fn ratio(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        0.0
    } else {
        a / b
    }
}

/// A 2-D Bézier handle (`dt`, `dv`) as a Hermite tangent over a span of length `span`: the
/// handle's slope times the span (a vertical handle counts as a very steep slope).
fn slope_times(dv: f64, dt: f64, span: f64) -> f64 {
    if dt.abs() > 1e-5 {
        dv * span / dt
    } else {
        dv * span * 1e5
    }
}

/// Hermite basis functions at s in [0, 1].
fn hermite_basis(s: f64) -> (f64, f64, f64, f64) {
    let s2 = s * s;
    let s3 = s2 * s;
    (
        2.0 * s3 - 3.0 * s2 + 1.0,
        -2.0 * s3 + 3.0 * s2,
        s3 - 2.0 * s2 + s,
        s3 - s2,
    )
}

/// A cubic Bézier coordinate with control values a, b, c, d at parameter s.
fn bezier(a: f64, b: f64, c: f64, d: f64, s: f64) -> f64 {
    let r = 1.0 - s;
    r * r * r * a + 3.0 * r * r * s * b + 3.0 * r * s * s * c + s * s * s * d
}

/// The 2-D Bézier span from `k0` to `k1` at `time`: control points (t0, v0), k0's outgoing
/// handle, k1's incoming handle, (t1, v1); the curve parameter whose time coordinate is `time`
/// is found by bisection (the time coordinate is monotonic when the handles stay inside the
/// span, as LightWave keeps them).
fn bezier2d(k0: &Key, k1: &Key, time: f64) -> f64 {
    let dt = k1.time - k0.time;
    let (x1, y1) = if k0.span == Span::Bezier2d {
        (k0.time + k0.p[2], k0.value + k0.p[3])
    } else {
        (k0.time + dt / 3.0, k0.value + k0.tan_out() / 3.0)
    };
    let (x2, y2) = (k1.time + k1.p[0], k1.value + k1.p[1]);
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let mut s = 0.5;
    for _ in 0..60 {
        s = 0.5 * (lo + hi);
        let x = bezier(k0.time, x1, x2, k1.time, s);
        if x < time {
            lo = s;
        } else {
            hi = s;
        }
    }
    bezier(k0.value, y1, y2, k1.value, s)
}

fn read_key(t: &[&str], loc: &Loc) -> Result<Key, LxsError> {
    if t.len() < 4 {
        return Err(LxsError::new(
            LxsErrorKind::WrongValueCount,
            loc.clone(),
            "Key needs a value, a time and a span type",
        ));
    }
    let value = number(t.get(1), "Key value", loc)?;
    let time = number(t.get(2), "Key time", loc)?;
    let code = integer(t.get(3), "Key span type", loc)?;
    let span = Span::from_code(code).ok_or_else(|| {
        LxsError::new(
            LxsErrorKind::InvalidValue,
            loc.clone(),
            format!("unknown envelope span type {code} (0-5: TCB, Hermite, 1-D Bézier, linear, stepped, 2-D Bézier)"),
        )
    })?;
    let mut p = [0.0; 6];
    for (i, slot) in p.iter_mut().enumerate() {
        if let Some(tok) = t.get(4 + i) {
            *slot = number(Some(tok), "Key parameter", loc)?;
        }
    }
    Ok(Key {
        value,
        time,
        span,
        p,
    })
}

fn behavior(tok: Option<&&str>, loc: &Loc) -> Result<Behavior, LxsError> {
    let code = integer(tok, "Behaviors", loc)?;
    Behavior::from_code(code).ok_or_else(|| {
        LxsError::new(
            LxsErrorKind::InvalidValue,
            loc.clone(),
            format!("unknown envelope behaviour {code} (0-5: reset, constant, repeat, oscillate, offset repeat, linear)"),
        )
    })
}

#[cfg(test)]
mod tests;
