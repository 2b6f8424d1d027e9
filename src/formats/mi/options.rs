//! `options "name" ... end options`: the render settings, and what of them a path tracer can
//! use.
//!
//! ```text
//! options block --parse--> Options --pixel_filter / integrator / haltspp--> Entities
//! ```
//!
//! What maps (mental ray's manual for the meaning, luxfarm's plugins for the target):
//! - `filter box|triangle|gauss|mitchell|lanczos [xsize [ysize]]` → PixelFilter box,
//!   triangle, gaussian, mitchell, sinc. mental ray gives the filter's full width in pixels
//!   (defaults 1, 2, 3, 4, 4); LuxRender's `xwidth`/`ywidth` are half-widths, so they are
//!   halved.
//! - `trace depth reflect refract [sum]` (reflection/refraction bounces) and, with `"gi" on`,
//!   `"gi depth"` (diffuse bounces) → the path integrator's `maxdepth` = 1 + the larger of
//!   the trace sum (reflect + refract when no sum is given) and the gi depth: a path tracer
//!   counts every bounce alike, and its camera hit is a vertex of its own.
//! - `"samples max" N` (unified sampling's upper bound per pixel) → the Film's `haltspp` N;
//!   the classic `samples min max` → 4^max (mental ray takes 2^max × 2^max per pixel).
//!
//! Everything else (sampling contrast and quality, shadow modes, photon and final gather
//! settings, colour clipping, ...) has no meaning for luxfarm's path tracer: each ignored
//! item is listed in one located note.

use super::cursor::{Cursor, MiResult};
use super::lexer::Tok;
use crate::lxs::{Diagnostic, Entity, Loc, Param, ParamSet, ParamValue};

#[derive(Clone, Debug, Default)]
pub struct Options {
    pub name: String,
    pub loc: Loc,
    /// Filter type with its x and y sizes (full widths, pixels), where written.
    pub filter: Option<(String, Option<f64>, Option<f64>, Loc)>,
    /// Reflection, refraction and sum trace depths.
    pub trace_depth: Option<([Option<f64>; 3], Loc)>,
    pub gi: bool,
    pub gi_depth: Option<(f64, Loc)>,
    pub samples_max: Option<(f64, Loc)>,
    pub classic_samples: Option<(f64, f64, Loc)>,
    /// Items luxfarm does not use, by name.
    pub ignored: Vec<String>,
}

/// Reads the block after `options "name"` up to and including `end options`.
pub fn parse(c: &mut Cursor, name: String, loc: Loc) -> MiResult<Options> {
    let mut o = Options {
        name,
        loc,
        ..Options::default()
    };
    loop {
        let at = c.loc()?;
        match c.peek()?.clone() {
            Tok::Word("end") => {
                c.next()?;
                c.expect_word("options")?;
                return Ok(o);
            }
            Tok::Str(key) => {
                let key = key.into_owned();
                c.next()?;
                let values = line_values(c)?;
                string_option(&mut o, &key, &values, at);
            }
            Tok::Word("filter") => {
                c.next()?;
                c.eat_word("clip")?;
                let kind = c.word("a filter type")?.to_string();
                let x = opt_number(c)?;
                let y = opt_number(c)?;
                o.filter = Some((kind, x, y, at));
            }
            Tok::Word("trace") => {
                c.next()?;
                if c.eat_word("depth")? {
                    let d = [opt_number(c)?, opt_number(c)?, opt_number(c)?];
                    o.trace_depth = Some((d, at));
                } else {
                    c.flag()?;
                    o.ignored.push("trace".into());
                }
            }
            Tok::Word("samples") => {
                c.next()?;
                let lo = opt_number(c)?;
                let hi = opt_number(c)?;
                if let (Some(lo), Some(hi)) = (lo, hi) {
                    o.classic_samples = Some((lo, hi, at));
                }
            }
            Tok::Word(w) => {
                let mut name = w.to_string();
                c.next()?;
                // The rest of the line names and sets the item (`object space`, ...).
                let line = c.last_loc().line;
                while !c.at_eof()? && c.peek_line()? == line {
                    if let Tok::Word(w) = c.next()? {
                        name.push(' ');
                        name.push_str(w);
                    }
                }
                o.ignored.push(name);
            }
            Tok::Eof => return Err(c.unexpected("'end options'")),
            _ => return Err(c.unexpected("an option or 'end options'")),
        }
    }
}

/// A number if one comes next.
fn opt_number(c: &mut Cursor) -> MiResult<Option<f64>> {
    Ok(if c.at_number()? {
        Some(c.number("a number")?)
    } else {
        None
    })
}

/// The values written on the same line as the item just read.
fn line_values<'a>(c: &mut Cursor<'a>) -> MiResult<Vec<Tok<'a>>> {
    let line = c.last_loc().line;
    let mut out = Vec::new();
    while !c.at_eof()? && c.peek_line()? == line {
        out.push(c.next()?);
    }
    Ok(out)
}

fn first_number(v: &[Tok]) -> Option<f64> {
    v.iter().find_map(|t| match t {
        Tok::Num(x, _) => Some(*x),
        _ => None,
    })
}

fn is_on(v: &[Tok]) -> bool {
    matches!(v.first(), Some(Tok::Word("on" | "true")))
        || matches!(v.first(), Some(Tok::Num(x, _)) if *x != 0.0)
}

/// A `"string key" value` option (mental ray 3.x's newer options).
fn string_option(o: &mut Options, key: &str, values: &[Tok], at: Loc) {
    match key {
        "samples max" => match first_number(values) {
            Some(v) => o.samples_max = Some((v, at)),
            None => o.ignored.push(key.into()),
        },
        "gi" => o.gi = is_on(values),
        "gi depth" => match first_number(values) {
            Some(v) => o.gi_depth = Some((v, at)),
            None => o.ignored.push(key.into()),
        },
        _ => o.ignored.push(key.into()),
    }
}

fn param(name: &str, value: ParamValue, loc: &Loc) -> Param {
    Param::new(name, value, loc.clone())
}

/// The PixelFilter for the options' `filter` (`None`: luxfarm's default).
pub fn pixel_filter(o: &Options, warnings: &mut Vec<Diagnostic>) -> Option<Entity> {
    let (kind, x, y, loc) = o.filter.as_ref()?;
    let (lux, default) = match kind.as_str() {
        "box" => ("box", 1.0),
        "triangle" => ("triangle", 2.0),
        "gauss" => ("gaussian", 3.0),
        "mitchell" => ("mitchell", 4.0),
        "lanczos" => ("sinc", 4.0),
        other => {
            warnings.push(Diagnostic {
                loc: loc.clone(),
                message: format!(
                    "filter \"{other}\" is unknown (box, triangle, gauss, mitchell, lanczos): \
                     luxfarm's default filter is used"
                ),
            });
            return None;
        }
    };
    let xs = x.unwrap_or(default);
    let ys = y.unwrap_or(xs);
    let mut params = ParamSet::new();
    params.push(param(
        "xwidth",
        ParamValue::Float(vec![(xs / 2.0) as f32]),
        loc,
    ));
    params.push(param(
        "ywidth",
        ParamValue::Float(vec![(ys / 2.0) as f32]),
        loc,
    ));
    Some(Entity {
        kind: lux.into(),
        params,
        loc: loc.clone(),
    })
}

/// The path integrator with the depth the options allow (see the module docs).
pub fn integrator(o: &Options) -> Entity {
    let mut params = ParamSet::new();
    let mut loc = o.loc.clone();
    let trace = o.trace_depth.as_ref().map(|(d, l)| {
        loc = l.clone();
        match d {
            [_, _, Some(sum)] => *sum,
            [r, f, None] => r.unwrap_or(0.0) + f.unwrap_or(0.0),
        }
    });
    let gi = o.gi_depth.as_ref().filter(|_| o.gi).map(|(d, l)| {
        loc = l.clone();
        *d
    });
    let depth = match (trace, gi) {
        (Some(t), Some(g)) => Some(t.max(g)),
        (t, g) => t.or(g),
    };
    if let Some(d) = depth {
        let d = d.clamp(0.0, 1000.0) as i32 + 1;
        params.push(param("maxdepth", ParamValue::Integer(vec![d]), &loc));
    }
    Entity {
        kind: "path".into(),
        params,
        loc: o.loc.clone(),
    }
}

/// Samples per pixel the options ask for, with where (see the module docs).
pub fn haltspp(o: &Options) -> Option<(i32, Loc)> {
    if let Some((n, loc)) = &o.samples_max {
        return Some((n.ceil().clamp(1.0, 1e6) as i32, loc.clone()));
    }
    let (_, hi, loc) = o.classic_samples.as_ref()?;
    let n = 4f64.powf(hi.clamp(0.0, 10.0));
    Some((n as i32, loc.clone()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(text: &str) -> Options {
        let mut c = Cursor::new(text, "t.mi".into());
        parse(&mut c, "opt".into(), Loc::default()).unwrap()
    }

    #[test]
    fn the_sample_options_map() {
        let o = options(
            "\"unified sampling\" on\n \"samples max\" 100.0\n \"gi\" on\n \"gi depth\" 3\n\
             filter gauss 2.0 2.0\n trace depth 2 4 5\n object space\n shadow segments\n end options",
        );
        let mut w = Vec::new();
        let f = pixel_filter(&o, &mut w).unwrap();
        assert_eq!(f.kind, "gaussian");
        assert_eq!(f.params.float("xwidth"), Some(1.0));
        assert_eq!(integrator(&o).params.int("maxdepth"), Some(6));
        assert_eq!(haltspp(&o).unwrap().0, 100);
        assert_eq!(
            o.ignored,
            vec!["unified sampling", "object space", "shadow segments"]
        );
    }

    #[test]
    fn depth_without_gi_and_classic_samples() {
        let o = options("trace depth 3 2\n samples -1 2\n \"gi depth\" 9\nend options");
        assert_eq!(integrator(&o).params.int("maxdepth"), Some(6));
        assert_eq!(haltspp(&o).unwrap().0, 16);
        let o = options("end options");
        assert_eq!(integrator(&o).params.int("maxdepth"), None);
        assert!(haltspp(&o).is_none());
    }

    #[test]
    fn an_unclosed_block_is_located() {
        let mut c = Cursor::new("filter box 1 1\n", "t.mi".into());
        let e = parse(&mut c, "o".into(), Loc::default()).unwrap_err();
        assert_eq!(e.loc.line, 2);
    }
}
