//! The .mi tokenizer: words, quoted strings, numbers, punctuation, `$` directives and the
//! `<file>` of `$include <file>`, each with its 1-based line and column. `#` starts a comment
//! that runs to the end of the line (outside strings).
//!
//! ```text
//! &str --Lexer::next--> Token { Word | Str | Num | Punct | Directive | Angle | Eof, line, col }
//! ```
//!
//! The lexer borrows the file's text and allocates only for strings with escapes, so a mesh
//! of millions of numbers costs no allocation per token.

use crate::lxs::{Loc, LxsError, LxsErrorKind};
use std::borrow::Cow;
use std::sync::Arc;

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub enum Tok<'a> {
    /// A keyword or bare name (`object`, `end`, `on`, `v`, ...).
    Word(&'a str),
    /// A double-quoted string, escapes resolved.
    Str(Cow<'a, str>),
    /// A number, and whether it was written as an integer.
    Num(f64, bool),
    /// One of `( ) [ ] { } , = ;`.
    Punct(u8),
    /// `$name`: a preprocessor directive (`include`, `ifdef`, ...).
    Directive(&'a str),
    /// `<name>`: the system file of `$include <name>`.
    Angle(&'a str),
    Eof,
}

impl Tok<'_> {
    /// How the token is named in messages.
    pub fn describe(&self) -> String {
        match self {
            Tok::Word(w) => format!("'{w}'"),
            Tok::Str(s) => format!("string \"{s}\""),
            Tok::Num(n, _) => format!("number {n}"),
            Tok::Punct(c) => format!("'{}'", *c as char),
            Tok::Directive(d) => format!("'${d}'"),
            Tok::Angle(a) => format!("<{a}>"),
            Tok::Eof => "the end of the file".into(),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token<'a> {
    pub tok: Tok<'a>,
    pub line: u32,
    pub col: u32,
}

/// Splits a file's text into tokens.
pub struct Lexer<'a> {
    text: &'a str,
    pos: usize,
    line: u32,
    line_start: usize,
    file: Arc<str>,
}

impl<'a> Lexer<'a> {
    pub fn new(text: &'a str, file: Arc<str>) -> Lexer<'a> {
        Lexer {
            text,
            pos: 0,
            line: 1,
            line_start: 0,
            file,
        }
    }

    pub fn file(&self) -> &Arc<str> {
        &self.file
    }

    /// The location of byte `pos` on the current line.
    fn loc_at(&self, pos: usize) -> Loc {
        Loc {
            file: self.file.clone(),
            line: self.line,
            col: self.col_of(pos),
        }
    }

    fn col_of(&self, pos: usize) -> u32 {
        let start = self.line_start.min(pos);
        let chars = self.text.get(start..pos).map_or(0, |s| s.chars().count());
        u32::try_from(chars + 1).unwrap_or(u32::MAX)
    }

    fn err(&self, pos: usize, kind: LxsErrorKind, msg: impl Into<String>) -> LxsError {
        LxsError::new(kind, self.loc_at(pos), msg)
    }

    fn byte(&self, pos: usize) -> Option<u8> {
        self.text.as_bytes().get(pos).copied()
    }

    /// Skips blanks, newlines and comments.
    fn skip_space(&mut self) {
        while let Some(b) = self.byte(self.pos) {
            match b {
                b'\n' => {
                    self.pos += 1;
                    self.line = self.line.saturating_add(1);
                    self.line_start = self.pos;
                }
                b' ' | b'\t' | b'\r' | 0x0c => self.pos += 1,
                b'#' => {
                    while let Some(c) = self.byte(self.pos) {
                        if c == b'\n' {
                            break;
                        }
                        self.pos += 1;
                    }
                }
                _ => break,
            }
        }
    }

    /// The next token.
    pub fn next_token(&mut self) -> Result<Token<'a>, LxsError> {
        self.skip_space();
        let start = self.pos;
        let (line, col) = (self.line, self.col_of(start));
        let token = |tok| Token { tok, line, col };
        let Some(b) = self.byte(start) else {
            return Ok(token(Tok::Eof));
        };
        let tok = match b {
            b'"' => self.string(start)?,
            b'(' | b')' | b'[' | b']' | b'{' | b'}' | b',' | b'=' | b';' => {
                self.pos += 1;
                Tok::Punct(b)
            }
            b'$' => {
                self.pos += 1;
                let w = self.word_from(self.pos);
                if w.is_empty() {
                    return Err(self.err(
                        start,
                        LxsErrorKind::Syntax,
                        "'$' without a directive name",
                    ));
                }
                Tok::Directive(w)
            }
            b'<' => {
                let end = self.text[start..]
                    .find(['>', '\n'])
                    .map(|i| start + i)
                    .filter(|&e| self.byte(e) == Some(b'>'))
                    .ok_or_else(|| {
                        self.err(
                            start,
                            LxsErrorKind::Syntax,
                            "'<' without its '>' on the same line",
                        )
                    })?;
                self.pos = end + 1;
                Tok::Angle(&self.text[start + 1..end])
            }
            b'0'..=b'9' | b'.' | b'-' | b'+' => self.number(start)?,
            c if c.is_ascii_alphabetic() || c == b'_' => Tok::Word(self.word_from(start)),
            _ => {
                let ch = self.text[start..].chars().next().unwrap_or('?');
                return Err(self.err(
                    start,
                    LxsErrorKind::Syntax,
                    format!("unexpected character '{}'", ch.escape_default()),
                ));
            }
        };
        Ok(token(tok))
    }

    /// The identifier starting at `start` (letters, digits, `_`), consumed.
    fn word_from(&mut self, start: usize) -> &'a str {
        let mut end = start;
        while let Some(c) = self.byte(end) {
            if c.is_ascii_alphanumeric() || c == b'_' {
                end += 1;
            } else {
                break;
            }
        }
        self.pos = end;
        &self.text[start..end]
    }

    fn string(&mut self, start: usize) -> Result<Tok<'a>, LxsError> {
        let mut i = start + 1;
        let mut escaped = false;
        loop {
            match self.byte(i) {
                None | Some(b'\n') => {
                    return Err(self.err(
                        start,
                        LxsErrorKind::UnterminatedString,
                        "string without its closing quote on the same line",
                    ))
                }
                Some(b'\\') => {
                    escaped = true;
                    i += 2;
                }
                Some(b'"') => break,
                Some(_) => i += 1,
            }
        }
        let end = i.min(self.text.len());
        self.pos = end + 1;
        let raw = self.text.get(start + 1..end).unwrap_or("");
        if !escaped {
            return Ok(Tok::Str(Cow::Borrowed(raw)));
        }
        let mut out = String::with_capacity(raw.len());
        let mut chars = raw.chars();
        while let Some(c) = chars.next() {
            if c == '\\' {
                match chars.next() {
                    Some('n') => out.push('\n'),
                    Some('t') => out.push('\t'),
                    Some(other) => out.push(other),
                    None => {}
                }
            } else {
                out.push(c);
            }
        }
        Ok(Tok::Str(Cow::Owned(out)))
    }

    fn number(&mut self, start: usize) -> Result<Tok<'a>, LxsError> {
        let mut end = start;
        let mut integer = true;
        while let Some(c) = self.byte(end) {
            match c {
                b'0'..=b'9' => end += 1,
                b'+' | b'-' if end == start => end += 1,
                b'+' | b'-' if matches!(self.byte(end - 1), Some(b'e' | b'E')) => end += 1,
                b'.' | b'e' | b'E' => {
                    integer = false;
                    end += 1;
                }
                _ => break,
            }
        }
        self.pos = end;
        let text = &self.text[start..end];
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Tok::Num(v, integer)),
            _ => Err(self.err(
                start,
                LxsErrorKind::InvalidNumber,
                format!("'{text}' is not a finite number"),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(text: &str) -> Vec<Tok<'_>> {
        let mut l = Lexer::new(text, "t.mi".into());
        let mut out = Vec::new();
        loop {
            let t = l.next_token().unwrap();
            if t.tok == Tok::Eof {
                return out;
            }
            out.push(t.tok);
        }
    }

    #[test]
    fn tokens_of_a_statement() {
        let t = toks(
            "shader \"a#b\" \"one_color\" ( \"color\" 1 .5 -2e-1, ) # done\n$include <base.mi>",
        );
        assert_eq!(
            t,
            vec![
                Tok::Word("shader"),
                Tok::Str("a#b".into()),
                Tok::Str("one_color".into()),
                Tok::Punct(b'('),
                Tok::Str("color".into()),
                Tok::Num(1.0, true),
                Tok::Num(0.5, false),
                Tok::Num(-0.2, false),
                Tok::Punct(b','),
                Tok::Punct(b')'),
                Tok::Directive("include"),
                Tok::Angle("base.mi"),
            ]
        );
        assert_eq!(toks("\"a\\\"b\""), vec![Tok::Str("a\"b".into())]);
    }

    #[test]
    fn lines_and_columns() {
        let mut l = Lexer::new("# c\n  object\n\t\"x\"", "f.mi".into());
        let a = l.next_token().unwrap();
        assert_eq!((a.line, a.col), (2, 3));
        let b = l.next_token().unwrap();
        assert_eq!((b.line, b.col), (3, 2));
    }

    #[test]
    fn malformed_tokens_are_located() {
        for (text, col) in [
            ("  \"open", 3),
            (" 1.2.3", 2),
            ("x @", 3),
            ("$ x", 1),
            ("<a", 1),
        ] {
            let mut l = Lexer::new(text, "f.mi".into());
            let e = loop {
                match l.next_token() {
                    Err(e) => break e,
                    Ok(t) if t.tok == Tok::Eof => panic!("{text}: no error"),
                    Ok(_) => {}
                }
            };
            assert_eq!((e.loc.line, e.loc.col), (1, col), "{text}: {e}");
        }
    }
}
