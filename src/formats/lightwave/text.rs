//! The LWSC text layer: a scene file as numbered lines of tokens, and a cursor over them.
//!
//! ```text
//! bytes --split at newlines (numbered from 1)--> Line { no, text }
//!       --tokens()--> words and "quoted strings" --Cursor--> the scene reader (scene.rs)
//! ```
//!
//! LightWave writes one keyword per line followed by its values, separated by spaces; strings
//! with spaces are quoted, but file names after `LoadObjectLayer` are written bare to the end
//! of the line ([`Line::rest_after`]). Multi-line blocks open with `{ Name` and close with a
//! line holding only `}`; plug-in data sits between `Plugin ...` and `EndPlugin`. The cursor
//! skips both kinds with their nesting bounded ([`MAX_NESTING`]), so hostile input cannot
//! recurse or loop without end.

use crate::lxs::{Loc, LxsError, LxsErrorKind};
use std::sync::Arc;

/// Deepest block nesting accepted (LightWave's own files nest a handful of levels).
pub const MAX_NESTING: usize = 64;

/// Most tokens on one line (a keyword and its values; envelope keys have 10).
pub const MAX_TOKENS: usize = 4096;

/// One line of the scene file, 1-based number.
#[derive(Clone, Copy, Debug)]
pub struct Line<'a> {
    pub no: u32,
    pub text: &'a str,
}

impl<'a> Line<'a> {
    /// The words of the line; a quoted string is one token without its quotes.
    pub fn tokens(&self) -> Vec<&'a str> {
        tokens(self.text)
    }

    /// The first word (the keyword), or "" for a blank line.
    pub fn keyword(&self) -> &'a str {
        self.text.split_whitespace().next().unwrap_or("")
    }

    /// The text after the first `n` words, trimmed, with surrounding quotes removed: the
    /// file name of `LoadObjectLayer 1 10000000 Objects/My Box.lwo`.
    pub fn rest_after(&self, n: usize) -> &'a str {
        let mut rest = self.text.trim_start();
        for _ in 0..n {
            let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
            rest = rest[end..].trim_start();
        }
        let rest = rest.trim_end();
        match rest.strip_prefix('"').and_then(|r| r.strip_suffix('"')) {
            Some(inner) => inner,
            None => rest,
        }
    }

    /// Whether the line opens a block (`{ Name ...`).
    pub fn opens_block(&self) -> bool {
        self.text.trim_start().starts_with('{')
    }

    /// The name of the block this line opens (`{ Envelope` gives "Envelope").
    pub fn block_name(&self) -> &'a str {
        self.text
            .trim_start()
            .strip_prefix('{')
            .and_then(|r| r.split_whitespace().next())
            .unwrap_or("")
    }

    /// Whether the line closes a block (`}` alone).
    pub fn closes_block(&self) -> bool {
        self.text.trim() == "}"
    }
}

/// Splits a line into words; `"a b"` is one token `a b`. An unterminated quote runs to the end
/// of the line.
pub fn tokens(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = text;
    while out.len() < MAX_TOKENS {
        rest = rest.trim_start();
        if rest.is_empty() {
            break;
        }
        if let Some(q) = rest.strip_prefix('"') {
            let end = q.find('"').unwrap_or(q.len());
            out.push(&q[..end]);
            rest = q.get(end + 1..).unwrap_or("");
        } else {
            let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
            out.push(&rest[..end]);
            rest = &rest[end..];
        }
    }
    out
}

/// The lines of a scene file and a position in them.
pub struct Cursor<'a> {
    file: Arc<str>,
    lines: Vec<Line<'a>>,
    pos: usize,
}

impl<'a> Cursor<'a> {
    /// Numbers the lines of `text` (CR LF and lone CR endings accepted), read from `file`.
    pub fn new(file: &str, text: &'a str) -> Cursor<'a> {
        let lines = text
            .split('\n')
            .enumerate()
            .map(|(i, l)| Line {
                no: u32::try_from(i + 1).unwrap_or(u32::MAX),
                text: l.strip_suffix('\r').unwrap_or(l),
            })
            .collect();
        Cursor {
            file: file.into(),
            lines,
            pos: 0,
        }
    }

    /// The location of a line (column 1).
    pub fn loc(&self, line: &Line) -> Loc {
        Loc {
            file: self.file.clone(),
            line: line.no,
            col: 1,
        }
    }

    /// The location just past the last line (for errors at the end of the input).
    pub fn end_loc(&self) -> Loc {
        Loc {
            file: self.file.clone(),
            line: self.lines.last().map_or(1, |l| l.no),
            col: 1,
        }
    }

    /// The next non-blank line, consumed.
    pub fn next_line(&mut self) -> Option<Line<'a>> {
        while let Some(l) = self.lines.get(self.pos).copied() {
            self.pos += 1;
            if !l.text.trim().is_empty() {
                return Some(l);
            }
        }
        None
    }

    /// The next non-blank line, which must exist (else an error located at `after`).
    pub fn expect_line(&mut self, after: &Line, what: &str) -> Result<Line<'a>, LxsError> {
        let loc = self.loc(after);
        self.next_line().ok_or_else(|| {
            LxsError::new(
                LxsErrorKind::UnclosedBlock,
                loc,
                format!("the file ends before {what}"),
            )
        })
    }

    /// Skips the rest of the block `open` began (its opening line already consumed), nested
    /// blocks included.
    pub fn skip_block(&mut self, open: &Line) -> Result<(), LxsError> {
        let mut depth = 1usize;
        while depth > 0 {
            let l = self.expect_line(open, "this block is closed by `}`")?;
            if l.closes_block() {
                depth -= 1;
            } else if l.opens_block() {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(LxsError::new(
                        LxsErrorKind::InputTooLarge,
                        self.loc(&l),
                        format!("blocks nested deeper than {MAX_NESTING}"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Skips plug-in data up to the `EndPlugin` matching `open` (a `Plugin ...` line, already
    /// consumed). Nested `Plugin`/`EndPlugin` pairs and braces inside are skipped with it.
    pub fn skip_plugin(&mut self, open: &Line) -> Result<(), LxsError> {
        let mut depth = 1usize;
        while depth > 0 {
            let l = self.expect_line(open, "this Plugin is closed by EndPlugin")?;
            match l.keyword() {
                "EndPlugin" => depth -= 1,
                "Plugin" => {
                    depth += 1;
                    if depth > MAX_NESTING {
                        return Err(LxsError::new(
                            LxsErrorKind::InputTooLarge,
                            self.loc(&l),
                            format!("Plugin blocks nested deeper than {MAX_NESTING}"),
                        ));
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// Parses a decimal number token, naming the keyword and line on failure.
pub fn number(tok: Option<&&str>, what: &str, loc: &Loc) -> Result<f64, LxsError> {
    let Some(t) = tok else {
        return Err(LxsError::new(
            LxsErrorKind::WrongValueCount,
            loc.clone(),
            format!("{what}: a value is missing"),
        ));
    };
    match t.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(LxsError::new(
            LxsErrorKind::InvalidNumber,
            loc.clone(),
            format!("{what}: {t:?} is not a finite number"),
        )),
    }
}

/// Parses an integer token (written as a decimal integer, or as a float with no fraction).
pub fn integer(tok: Option<&&str>, what: &str, loc: &Loc) -> Result<i64, LxsError> {
    let v = number(tok, what, loc)?;
    if v.fract() != 0.0 || v.abs() > 9.0e15 {
        return Err(LxsError::new(
            LxsErrorKind::InvalidNumber,
            loc.clone(),
            format!("{what}: {v} is not an integer"),
        ));
    }
    Ok(v as i64)
}

/// Parses an item id written as 8 hexadecimal digits (`10000000`).
pub fn hex_id(tok: Option<&&str>, what: &str, loc: &Loc) -> Result<u32, LxsError> {
    let t = tok.ok_or_else(|| {
        LxsError::new(
            LxsErrorKind::WrongValueCount,
            loc.clone(),
            format!("{what}: the item id is missing"),
        )
    })?;
    u32::from_str_radix(t, 16).map_err(|_| {
        LxsError::new(
            LxsErrorKind::InvalidNumber,
            loc.clone(),
            format!("{what}: {t:?} is not a hexadecimal item id"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_keep_quoted_strings_whole() {
        assert_eq!(
            tokens("LightName \"Key light\" 3"),
            vec!["LightName", "Key light", "3"]
        );
        assert_eq!(tokens("  a\tb  "), vec!["a", "b"]);
        assert_eq!(tokens("x \"open"), vec!["x", "open"]);
    }

    #[test]
    fn rest_after_keeps_spaces_in_file_names() {
        let l = Line {
            no: 1,
            text: "LoadObjectLayer 1 10000000 Objects/My Box.lwo  ",
        };
        assert_eq!(l.rest_after(3), "Objects/My Box.lwo");
        let q = Line {
            no: 1,
            text: "LoadObject \"a b.lwo\"",
        };
        assert_eq!(q.rest_after(1), "a b.lwo");
    }

    #[test]
    fn blocks_and_plugins_are_skipped_with_nesting() {
        let text = "{ Outer\n  { Inner\n    x\n  }\n}\nAfter\nPlugin A 1 x\n{ weird\nPlugin B\nEndPlugin\nEndPlugin\nLast\n";
        let mut c = Cursor::new("s.lws", text);
        let open = c.next_line().unwrap();
        assert_eq!(open.block_name(), "Outer");
        c.skip_block(&open).unwrap();
        assert_eq!(c.next_line().unwrap().keyword(), "After");
        let p = c.next_line().unwrap();
        c.skip_plugin(&p).unwrap();
        assert_eq!(c.next_line().unwrap().text, "Last");
    }

    #[test]
    fn unclosed_block_is_a_located_error() {
        let mut c = Cursor::new("s.lws", "{ Envelope\n  1\n");
        let open = c.next_line().unwrap();
        let e = c.skip_block(&open).unwrap_err();
        assert_eq!(e.loc.line, 1);
        assert!(e.to_string().contains("s.lws:1:1"), "{e}");
    }

    #[test]
    fn numbers_are_checked() {
        let loc = Loc::default();
        assert_eq!(number(Some(&"1.5"), "x", &loc).unwrap(), 1.5);
        assert!(number(Some(&"nan"), "x", &loc).is_err());
        assert!(number(None, "x", &loc).is_err());
        assert_eq!(integer(Some(&"3"), "x", &loc).unwrap(), 3);
        assert!(integer(Some(&"3.5"), "x", &loc).is_err());
        assert_eq!(hex_id(Some(&"2000000A"), "x", &loc).unwrap(), 0x2000_000A);
    }
}
