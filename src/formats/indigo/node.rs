//! `Elem`: one XML element of an Indigo file with its location, and the typed accessors the
//! converters read it through.
//!
//! Every accessor marks what it reads as used; once the import is done,
//! [`Elem::report_unused`] gives one located warning per element nothing read, so an element
//! luxfarm cannot map never passes in silence. A single-valued child written twice is read
//! from its first occurrence, with a warning naming both places (Indigo keeps the first).

use super::ctx::{err, Ctx};
use crate::lxs::{Loc, LxsError, LxsErrorKind};
use std::cell::Cell;

/// An element: name, attributes, direct text (CDATA included), child elements.
#[derive(Debug)]
pub struct Elem {
    pub name: String,
    pub loc: Loc,
    attrs: Vec<(String, String)>,
    pub text: String,
    pub children: Vec<Elem>,
    used: Cell<bool>,
}

type Res<T> = Result<T, LxsError>;

impl Elem {
    pub fn new(
        name: String,
        loc: Loc,
        attrs: Vec<(String, String)>,
        text: String,
        children: Vec<Elem>,
    ) -> Elem {
        Elem {
            name,
            loc,
            attrs,
            text,
            children,
            used: Cell::new(false),
        }
    }

    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    pub fn mark_used(&self) {
        self.used.set(true);
    }

    pub fn is_used(&self) -> bool {
        self.used.get()
    }

    /// Marks this element and its whole subtree used (read as a unit elsewhere).
    pub fn mark_all_used(&self) {
        self.used.set(true);
        for c in &self.children {
            c.mark_all_used();
        }
    }

    /// Marks children of these names used without reading them (settings that have no
    /// meaning for luxfarm: GUI, threads, file saving).
    pub fn ignore(&self, names: &[&str]) {
        for c in &self.children {
            if names.contains(&c.name.as_str()) {
                c.mark_all_used();
            }
        }
    }

    /// The first child of this name (marked used); a second one is reported and ignored.
    pub fn child(&self, ctx: &Ctx, name: &str) -> Option<&Elem> {
        let mut it = self.children.iter().filter(|c| c.name == name);
        let first = it.next()?;
        first.mark_used();
        for dup in it {
            dup.mark_all_used();
            ctx.warn(
                &dup.loc,
                format!(
                    "duplicated <{name}> in <{}>: the first one (line {}) is used, this one is ignored",
                    self.name, first.loc.line
                ),
            );
        }
        Some(first)
    }

    /// Whether a child of this name exists (marks it used).
    pub fn has(&self, ctx: &Ctx, name: &str) -> bool {
        self.child(ctx, name).is_some()
    }

    /// All children of this name, in order (each marked used).
    pub fn all<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Elem> + 'a {
        self.children
            .iter()
            .filter(move |c| c.name == name)
            .inspect(|c| c.mark_used())
    }

    /// The first element child whatever its name (e.g. the type element of a material).
    pub fn first_child_except<'a>(&'a self, skip: &[&str]) -> Option<&'a Elem> {
        self.children
            .iter()
            .find(|c| !skip.contains(&c.name.as_str()))
    }

    /// The trimmed text.
    pub fn str(&self) -> &str {
        self.text.trim()
    }

    /// The text as numbers (whitespace or comma separated).
    pub fn nums(&self, ctx: &Ctx) -> Res<Vec<f64>> {
        parse_numbers(self.str(), &self.loc, ctx)
    }

    /// Exactly `n` numbers.
    pub fn n_nums(&self, ctx: &Ctx, n: usize) -> Res<Vec<f64>> {
        let v = self.nums(ctx)?;
        if v.len() != n {
            return Err(err(
                LxsErrorKind::WrongValueCount,
                &self.loc,
                format!("<{}> needs {n} numbers, got {}", self.name, v.len()),
            ));
        }
        Ok(v)
    }

    pub fn num(&self, ctx: &Ctx) -> Res<f64> {
        Ok(self.n_nums(ctx, 1)?[0])
    }

    pub fn vec3(&self, ctx: &Ctx) -> Res<[f64; 3]> {
        let v = self.n_nums(ctx, 3)?;
        Ok([v[0], v[1], v[2]])
    }

    pub fn int(&self, ctx: &Ctx) -> Res<i64> {
        let v = self.num(ctx)?;
        if v.fract() != 0.0 || v.abs() > 2f64.powi(53) {
            return Err(err(
                LxsErrorKind::InvalidNumber,
                &self.loc,
                format!("<{}> must be an integer, got {}", self.name, self.str()),
            ));
        }
        Ok(v as i64)
    }

    pub fn bool(&self, _ctx: &Ctx) -> Res<bool> {
        match self.str().to_ascii_lowercase().as_str() {
            "true" | "1" | "yes" => Ok(true),
            "false" | "0" | "no" => Ok(false),
            other => Err(err(
                LxsErrorKind::WrongValueType,
                &self.loc,
                format!("<{}> must be true or false, got \"{other}\"", self.name),
            )),
        }
    }

    pub fn child_num(&self, ctx: &Ctx, name: &str) -> Res<Option<f64>> {
        self.child(ctx, name).map(|c| c.num(ctx)).transpose()
    }

    pub fn child_num_or(&self, ctx: &Ctx, name: &str, default: f64) -> Res<f64> {
        Ok(self.child_num(ctx, name)?.unwrap_or(default))
    }

    pub fn child_int(&self, ctx: &Ctx, name: &str) -> Res<Option<i64>> {
        self.child(ctx, name).map(|c| c.int(ctx)).transpose()
    }

    pub fn child_vec3(&self, ctx: &Ctx, name: &str) -> Res<Option<[f64; 3]>> {
        self.child(ctx, name).map(|c| c.vec3(ctx)).transpose()
    }

    pub fn child_bool(&self, ctx: &Ctx, name: &str) -> Res<Option<bool>> {
        self.child(ctx, name).map(|c| c.bool(ctx)).transpose()
    }

    pub fn child_bool_or(&self, ctx: &Ctx, name: &str, default: bool) -> Res<bool> {
        Ok(self.child_bool(ctx, name)?.unwrap_or(default))
    }

    pub fn child_str(&self, ctx: &Ctx, name: &str) -> Option<&str> {
        self.child(ctx, name).map(Elem::str)
    }

    /// A required child.
    pub fn need(&self, ctx: &Ctx, name: &str) -> Res<&Elem> {
        self.child(ctx, name).ok_or_else(|| {
            err(
                LxsErrorKind::WrongValueCount,
                &self.loc,
                format!("<{}> needs a <{name}> element", self.name),
            )
        })
    }

    /// A number that must be positive and finite.
    pub fn positive(&self, ctx: &Ctx) -> Res<f64> {
        let v = self.num(ctx)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(err(
                LxsErrorKind::InvalidValue,
                &self.loc,
                format!("<{}> must be > 0, got {v}", self.name),
            ))
        }
    }

    /// One located warning per element (here or below) that nothing read.
    pub fn report_unused(&self, ctx: &Ctx) {
        for c in &self.children {
            if c.is_used() {
                c.report_unused(ctx);
            } else {
                c.mark_all_used();
                ctx.warn(
                    &c.loc,
                    format!(
                        "<{}> in <{}> is not supported by luxfarm: ignored",
                        c.name, self.name
                    ),
                );
            }
        }
    }
}

/// Numbers separated by whitespace or commas; each must be finite. The count is checked
/// against `ParseOptions::max_array_len` before the list is built.
pub fn parse_numbers(text: &str, loc: &Loc, ctx: &Ctx) -> Res<Vec<f64>> {
    let is_sep = |c: char| c.is_whitespace() || c == ',';
    let count = text.split(is_sep).filter(|s| !s.is_empty()).count();
    ctx.check_count(count as u64, "numbers", loc)?;
    let mut out = Vec::with_capacity(count);
    for tok in text.split(is_sep).filter(|s| !s.is_empty()) {
        let v: f64 = tok.parse().map_err(|_| {
            err(
                LxsErrorKind::InvalidNumber,
                loc,
                format!("\"{}\" is not a number", truncate(tok)),
            )
        })?;
        if !v.is_finite() {
            return Err(err(
                LxsErrorKind::InvalidNumber,
                loc,
                format!("\"{}\" is not a finite number", truncate(tok)),
            ));
        }
        out.push(v);
    }
    Ok(out)
}

fn truncate(s: &str) -> String {
    s.chars().take(40).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::ParseOptions;
    use std::path::Path;

    fn elem(name: &str, text: &str, children: Vec<Elem>, line: u32) -> Elem {
        Elem::new(
            name.into(),
            Loc {
                file: "t.igs".into(),
                line,
                col: 1,
            },
            vec![],
            text.into(),
            children,
        )
    }

    #[test]
    fn first_duplicate_wins_with_a_warning_and_unused_elements_are_reported() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let e = elem(
            "camera",
            "",
            vec![
                elem("pos", "0 0 1", vec![], 2),
                elem("pos", "5 5 5", vec![], 3),
                elem("warp_drive", "1", vec![], 4),
            ],
            1,
        );
        assert_eq!(e.child_vec3(&ctx, "pos").unwrap(), Some([0.0, 0.0, 1.0]));
        e.report_unused(&ctx);
        let w = ctx.take_warnings();
        assert_eq!(w.len(), 2, "{w:?}");
        assert_eq!(w[0].loc.line, 3);
        assert!(w[0].message.contains("duplicated <pos>"));
        assert_eq!(w[1].loc.line, 4);
        assert!(w[1].message.contains("warp_drive"));
    }

    #[test]
    fn numbers_are_checked() {
        let ctx = Ctx::new(
            Path::new("t.igs"),
            &ParseOptions {
                max_array_len: 4,
                ..ParseOptions::default()
            },
        );
        let l = Loc::default();
        assert_eq!(
            parse_numbers(" 1, 2\n3e1 ", &l, &ctx).unwrap(),
            vec![1.0, 2.0, 30.0]
        );
        assert_eq!(
            parse_numbers("1 x", &l, &ctx).unwrap_err().kind,
            LxsErrorKind::InvalidNumber
        );
        assert_eq!(
            parse_numbers("1 nan", &l, &ctx).unwrap_err().kind,
            LxsErrorKind::InvalidNumber
        );
        assert_eq!(
            parse_numbers("1 2 3 4 5", &l, &ctx).unwrap_err().kind,
            LxsErrorKind::ArrayTooLong
        );
        let b = elem("b", " TRUE ", vec![], 1);
        assert!(b.bool(&ctx).unwrap());
        assert!(elem("b", "maybe", vec![], 1).bool(&ctx).is_err());
        assert!(elem("i", "2.5", vec![], 1).int(&ctx).is_err());
    }
}
