//! Byte-level streaming lexer for .lxs text.
//!
//! The input is read in large chunks into one reusable buffer; tokens are scanned in place, so
//! numbers cost no allocation (the parser parses them straight from the buffer into its typed
//! vectors). Lines and columns (1-based, columns in bytes) are tracked for every token start.
//! The total number of bytes read across all files is charged to a shared budget.

use super::error::{LxsError, LxsErrorKind, LxsResult};
use super::params::Loc;
use std::cell::Cell;
use std::io::Read;
use std::rc::Rc;
use std::sync::Arc;

const CHUNK: usize = 1 << 20;
/// Longest single token (string or number) accepted: guards the buffer against runaway input.
const MAX_TOKEN: usize = 64 << 20;

/// What comes next in the input, as far as the parser needs to know to pick a rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Peek {
    Eof,
    Ident,
    Str,
    Number,
    LBrack,
    RBrack,
    Other(u8),
}

pub struct Lexer<'a> {
    reader: Box<dyn Read + 'a>,
    buf: Vec<u8>,
    pos: usize,
    end: usize,
    eof: bool,
    file: Arc<str>,
    line: u32,
    /// Absolute byte offset of `buf[0]` in the file.
    base: u64,
    /// Absolute byte offset of the start of the current line.
    line_start: u64,
    /// Remaining bytes all lexers together may still read.
    budget: Rc<Cell<u64>>,
}

pub fn is_number_start(b: u8) -> bool {
    b.is_ascii_digit() || b == b'-' || b == b'+' || b == b'.'
}

fn is_number_byte(b: u8) -> bool {
    b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.' | b'e' | b'E')
}

fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

fn is_ident_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// Bytes that may directly follow a number or identifier.
fn is_delimiter(b: u8) -> bool {
    matches!(
        b,
        b' ' | b'\t' | b'\r' | b'\n' | b'[' | b']' | b'"' | b'#' | 0x0b | 0x0c
    )
}

impl<'a> Lexer<'a> {
    pub fn new(reader: Box<dyn Read + 'a>, file: Arc<str>, budget: Rc<Cell<u64>>) -> Lexer<'a> {
        Lexer {
            reader,
            buf: vec![0; CHUNK],
            pos: 0,
            end: 0,
            eof: false,
            file,
            line: 1,
            base: 0,
            line_start: 0,
            budget,
        }
    }

    pub fn file(&self) -> &Arc<str> {
        &self.file
    }

    /// The location of the next byte.
    pub fn loc(&self) -> Loc {
        let abs = self.base + self.pos as u64;
        let col = abs.saturating_sub(self.line_start) + 1;
        Loc {
            file: self.file.clone(),
            line: self.line,
            col: u32::try_from(col).unwrap_or(u32::MAX),
        }
    }

    fn err(&self, kind: LxsErrorKind, msg: impl Into<String>) -> LxsError {
        LxsError::new(kind, self.loc(), msg)
    }

    /// Reads more input, keeping `buf[keep_from..end]`. Returns false at end of input.
    fn fill(&mut self, keep_from: usize) -> LxsResult<bool> {
        if self.eof {
            return Ok(false);
        }
        if keep_from > 0 {
            self.buf.copy_within(keep_from..self.end, 0);
            self.base += keep_from as u64;
            self.end -= keep_from;
            self.pos -= keep_from;
        }
        if self.end == self.buf.len() {
            if self.buf.len() >= MAX_TOKEN {
                return Err(self.err(LxsErrorKind::InputTooLarge, "token longer than 64 MiB"));
            }
            let n = self.buf.len() * 2;
            self.buf.resize(n, 0);
        }
        loop {
            match self.reader.read(&mut self.buf[self.end..]) {
                Ok(0) => {
                    self.eof = true;
                    return Ok(false);
                }
                Ok(n) => {
                    let left = self.budget.get();
                    if n as u64 > left {
                        self.budget.set(0);
                        return Err(self.err(
                            LxsErrorKind::InputTooLarge,
                            "input exceeds the total size limit (ParseOptions::max_total_bytes)",
                        ));
                    }
                    self.budget.set(left - n as u64);
                    self.end += n;
                    return Ok(true);
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => {
                    return Err(self.err(LxsErrorKind::Io, format!("read error: {e}")));
                }
            }
        }
    }

    /// The next byte without consuming it, reading more input when needed.
    fn peek_byte(&mut self) -> LxsResult<Option<u8>> {
        if self.pos >= self.end && !self.fill(self.pos)? {
            return Ok(None);
        }
        Ok(self.buf.get(self.pos).copied())
    }

    fn newline_at(&mut self, idx: usize) {
        self.line = self.line.saturating_add(1);
        self.line_start = self.base + idx as u64 + 1;
    }

    /// Skips whitespace and `#` comments.
    pub fn skip_ws(&mut self) -> LxsResult<()> {
        let mut in_comment = false;
        loop {
            while self.pos < self.end {
                let b = self.buf[self.pos];
                if b == b'\n' {
                    self.newline_at(self.pos);
                    in_comment = false;
                } else if in_comment {
                    // eat
                } else if b == b'#' {
                    in_comment = true;
                } else if !matches!(b, b' ' | b'\t' | b'\r' | 0x0b | 0x0c) {
                    return Ok(());
                }
                self.pos += 1;
            }
            if !self.fill(self.pos)? {
                return Ok(());
            }
        }
    }

    /// Classifies the next token (after whitespace has been skipped).
    pub fn peek(&mut self) -> LxsResult<Peek> {
        Ok(match self.peek_byte()? {
            None => Peek::Eof,
            Some(b'"') => Peek::Str,
            Some(b'[') => Peek::LBrack,
            Some(b']') => Peek::RBrack,
            Some(b) if is_number_start(b) => Peek::Number,
            Some(b) if is_ident_start(b) => Peek::Ident,
            Some(b) => Peek::Other(b),
        })
    }

    /// Consumes one byte (a bracket the caller has peeked).
    pub fn bump(&mut self) {
        if self.pos < self.end {
            self.pos += 1;
        }
    }

    /// Scans a run of bytes satisfying `pred` starting at the current position, reading more
    /// input when it reaches the end of the buffer. Returns the run's range in `buf`; the caller
    /// must consume it with `self.pos = range.end` after use.
    fn scan_run(&mut self, pred: fn(u8) -> bool) -> LxsResult<(usize, usize)> {
        let mut i = self.pos;
        loop {
            while i < self.end && pred(self.buf[i]) {
                i += 1;
            }
            if i < self.end {
                return Ok((self.pos, i));
            }
            let offset = i - self.pos;
            if !self.fill(self.pos)? {
                return Ok((self.pos, self.pos + offset));
            }
            i = self.pos + offset;
        }
    }

    /// Checks that the byte after a token ends it (whitespace, bracket, quote, comment, EOF).
    fn expect_delimiter(&mut self, what: &str, start: Loc) -> LxsResult<()> {
        match self.peek_byte()? {
            None => Ok(()),
            Some(b) if is_delimiter(b) => Ok(()),
            Some(b) => Err(LxsError::new(
                LxsErrorKind::Syntax,
                start,
                format!("{what} runs into unexpected character '{}'", char::from(b)),
            )),
        }
    }

    /// Reads an identifier (statement name).
    pub fn ident(&mut self) -> LxsResult<String> {
        let start = self.loc();
        let (s, e) = self.scan_run(is_ident_byte)?;
        let word = String::from_utf8_lossy(&self.buf[s..e]).into_owned();
        self.pos = e;
        self.expect_delimiter(&format!("'{word}'"), start)?;
        Ok(word)
    }

    /// Scans a number token and hands its bytes to `f`, which parses them. `f` gets the bytes
    /// and returns the value or a reason; errors carry the number's location.
    #[inline]
    pub fn number<T>(&mut self, f: impl FnOnce(&[u8]) -> Result<T, String>) -> LxsResult<T> {
        // Fast path: the whole number and its delimiter are in the buffer.
        let mut i = self.pos;
        while i < self.end && is_number_byte(self.buf[i]) {
            i += 1;
        }
        if i < self.end && is_delimiter(self.buf[i]) {
            let r = f(&self.buf[self.pos..i]);
            return match r {
                Ok(v) => {
                    self.pos = i;
                    Ok(v)
                }
                Err(m) => Err(self.err(LxsErrorKind::InvalidNumber, m)),
            };
        }
        let start = self.loc();
        let (s, e) = self.scan_run(is_number_byte)?;
        let v = f(&self.buf[s..e])
            .map_err(|m| LxsError::new(LxsErrorKind::InvalidNumber, start.clone(), m))?;
        self.pos = e;
        self.expect_delimiter("number", start)?;
        Ok(v)
    }

    /// Reads a run of numbers separated by whitespace, handing each parsed value to `sink`,
    /// and stops before the first byte that is neither (a bracket, quote, comment, letter) or
    /// at the end of input. This is the hot loop for big arrays: it scans the buffer in place
    /// and only leaves it to refill.
    #[inline]
    pub fn number_run<T>(
        &mut self,
        parse: fn(&[u8]) -> Result<T, String>,
        mut sink: impl FnMut(T),
    ) -> LxsResult<()> {
        loop {
            let end = self.end;
            let base = self.base;
            let mut i = self.pos;
            let mut line = self.line;
            let mut line_start = self.line_start;
            let mut stop = false;
            let mut failure: Option<(usize, LxsErrorKind, String)> = None;
            {
                let buf = &self.buf[..end];
                while i < end {
                    let b = buf[i];
                    if b == b' ' || b == b'\t' || b == b'\r' {
                        i += 1;
                    } else if b == b'\n' {
                        line = line.saturating_add(1);
                        line_start = base + i as u64 + 1;
                        i += 1;
                    } else if is_number_start(b) {
                        let mut j = i + 1;
                        while j < end && is_number_byte(buf[j]) {
                            j += 1;
                        }
                        if j == end && !self.eof {
                            break; // the number may continue in the next chunk
                        }
                        if j < end && !is_delimiter(buf[j]) {
                            let msg = format!(
                                "number runs into unexpected character '{}'",
                                char::from(buf[j]).escape_default()
                            );
                            failure = Some((i, LxsErrorKind::Syntax, msg));
                            break;
                        }
                        match parse(&buf[i..j]) {
                            Ok(v) => sink(v),
                            Err(m) => {
                                failure = Some((i, LxsErrorKind::InvalidNumber, m));
                                break;
                            }
                        }
                        i = j;
                    } else {
                        stop = true;
                        break;
                    }
                }
            }
            self.pos = i;
            self.line = line;
            self.line_start = line_start;
            if let Some((at, kind, msg)) = failure {
                self.pos = at;
                return Err(self.err(kind, msg));
            }
            if stop || !self.fill(self.pos)? {
                return Ok(());
            }
        }
    }

    /// Reads a quoted string (the current byte is the opening quote), decoding escapes. A
    /// newline or the end of input before the closing quote is an error at the opening quote.
    pub fn string(&mut self) -> LxsResult<String> {
        let start = self.loc();
        self.pos += 1;
        let mut out: Vec<u8> = Vec::new();
        loop {
            let Some(b) = self.peek_byte()? else {
                return Err(LxsError::new(
                    LxsErrorKind::UnterminatedString,
                    start,
                    "unterminated string: end of input before the closing quote",
                ));
            };
            self.pos += 1;
            match b {
                b'"' => break,
                b'\n' => {
                    return Err(LxsError::new(
                        LxsErrorKind::UnterminatedString,
                        start,
                        "unterminated string: end of line before the closing quote",
                    ))
                }
                b'\\' => self.escape(&mut out, &start)?,
                _ => out.push(b),
            }
            if out.len() > MAX_TOKEN {
                return Err(LxsError::new(
                    LxsErrorKind::InputTooLarge,
                    start,
                    "string longer than 64 MiB",
                ));
            }
        }
        self.expect_delimiter("string", start)?;
        Ok(match String::from_utf8(out) {
            Ok(s) => s,
            Err(e) => String::from_utf8_lossy(e.as_bytes()).into_owned(),
        })
    }

    /// Decodes the escape after a backslash inside a string.
    fn escape(&mut self, out: &mut Vec<u8>, start: &Loc) -> LxsResult<()> {
        let Some(c) = self.peek_byte()? else {
            return Err(LxsError::new(
                LxsErrorKind::UnterminatedString,
                start.clone(),
                "unterminated string: end of input after a backslash",
            ));
        };
        self.pos += 1;
        match c {
            b'n' => out.push(b'\n'),
            b't' => out.push(b'\t'),
            b'r' => out.push(b'\r'),
            b'b' => out.push(8),
            b'f' => out.push(12),
            b'\n' => self.newline_at(self.pos - 1),
            b'0'..=b'9' => {
                // Up to three decimal digits give a byte value (modulo 256), as LuxRender.
                let mut val = u32::from(c - b'0');
                for _ in 0..2 {
                    match self.peek_byte()? {
                        Some(d) if d.is_ascii_digit() => {
                            val = val * 10 + u32::from(d - b'0');
                            self.pos += 1;
                        }
                        _ => break,
                    }
                }
                out.push((val % 256) as u8);
            }
            other => out.push(other),
        }
        Ok(())
    }
}

/// Parses an f32 the way the parser needs: finite, and the whole token consumed.
#[inline]
pub fn parse_f32(bytes: &[u8]) -> Result<f32, String> {
    match fast_float2::parse::<f32, _>(bytes) {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!(
            "number '{}' is out of range for a 32-bit float",
            String::from_utf8_lossy(bytes)
        )),
        Err(_) => Err(format!(
            "invalid number '{}'",
            String::from_utf8_lossy(bytes)
        )),
    }
}

/// Parses an f64 (transform statements): finite, whole token.
pub fn parse_f64(bytes: &[u8]) -> Result<f64, String> {
    match fast_float2::parse::<f64, _>(bytes) {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!(
            "number '{}' is out of range",
            String::from_utf8_lossy(bytes)
        )),
        Err(_) => Err(format!(
            "invalid number '{}'",
            String::from_utf8_lossy(bytes)
        )),
    }
}

/// Parses an integer parameter value. Plain decimal integers take a fast path; a number with a
/// fraction or exponent is truncated toward zero as LuxRender does (the flag tells the caller,
/// which warns once). Values outside the i32 range are errors.
#[inline]
pub fn parse_i32(bytes: &[u8]) -> Result<(i32, bool), String> {
    let (neg, digits) = match bytes.first() {
        Some(b'-') => (true, &bytes[1..]),
        Some(b'+') => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    if !digits.is_empty() && digits.len() <= 10 && digits.iter().all(u8::is_ascii_digit) {
        let mut v: i64 = 0;
        for &d in digits {
            v = v * 10 + i64::from(d - b'0');
        }
        let v = if neg { -v } else { v };
        return i32::try_from(v).map(|v| (v, false)).map_err(|_| {
            format!(
                "integer '{}' is out of range",
                String::from_utf8_lossy(bytes)
            )
        });
    }
    let f = parse_f64(bytes)?;
    let t = f.trunc();
    if t < f64::from(i32::MIN) || t > f64::from(i32::MAX) {
        return Err(format!(
            "integer '{}' is out of range",
            String::from_utf8_lossy(bytes)
        ));
    }
    Ok((t as i32, t != f))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lexer(text: &'static str) -> Lexer<'static> {
        Lexer::new(
            Box::new(text.as_bytes()),
            Arc::from("t.lxs"),
            Rc::new(Cell::new(u64::MAX)),
        )
    }

    #[test]
    fn tracks_lines_and_columns_through_comments() {
        let mut l = lexer("# c\n  Shape \"a\\\"b\" 1.5");
        l.skip_ws().unwrap();
        assert_eq!((l.loc().line, l.loc().col), (2, 3));
        assert_eq!(l.ident().unwrap(), "Shape");
        l.skip_ws().unwrap();
        assert_eq!(l.peek().unwrap(), Peek::Str);
        assert_eq!(l.string().unwrap(), "a\"b");
        l.skip_ws().unwrap();
        assert_eq!(l.number(parse_f32).unwrap(), 1.5);
        l.skip_ws().unwrap();
        assert_eq!(l.peek().unwrap(), Peek::Eof);
    }

    #[test]
    fn integers_truncate_like_luxrender() {
        assert_eq!(parse_i32(b"42"), Ok((42, false)));
        assert_eq!(parse_i32(b"-7"), Ok((-7, false)));
        assert_eq!(parse_i32(b"2.0"), Ok((2, false)));
        assert_eq!(parse_i32(b"2.7"), Ok((2, true)));
        assert!(parse_i32(b"99999999999").is_err());
        assert!(parse_f32(b"1e60").is_err());
        assert!(parse_f32(b"1.2.3").is_err());
    }

    #[test]
    fn small_buffer_boundaries_do_not_split_tokens() {
        // A reader that yields one byte at a time exercises every refill path.
        struct OneByte(&'static [u8]);
        impl Read for OneByte {
            fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
                match self.0.split_first() {
                    Some((b, rest)) if !out.is_empty() => {
                        out[0] = *b;
                        self.0 = rest;
                        Ok(1)
                    }
                    _ => Ok(0),
                }
            }
        }
        let mut l = Lexer::new(
            Box::new(OneByte(b"Translate 12.25 \"xy\"\n  -3e2")),
            Arc::from("t"),
            Rc::new(Cell::new(u64::MAX)),
        );
        assert_eq!(l.ident().unwrap(), "Translate");
        l.skip_ws().unwrap();
        assert_eq!(l.number(parse_f32).unwrap(), 12.25);
        l.skip_ws().unwrap();
        assert_eq!(l.string().unwrap(), "xy");
        l.skip_ws().unwrap();
        let loc = l.loc();
        assert_eq!((loc.line, loc.col), (2, 3));
        assert_eq!(l.number(parse_f32).unwrap(), -300.0);

        let mut l = Lexer::new(
            Box::new(OneByte(b"10 2.5\n -3e1 7]x")),
            Arc::from("t"),
            Rc::new(Cell::new(u64::MAX)),
        );
        let mut got = Vec::new();
        l.number_run(parse_f32, |v| got.push(v)).unwrap();
        assert_eq!(got, vec![10.0, 2.5, -30.0, 7.0]);
        assert_eq!(l.peek().unwrap(), Peek::RBrack);
        assert_eq!((l.loc().line, l.loc().col), (2, 8));
        l.bump();
        let mut l2 = Lexer::new(
            Box::new(&b"1 2x"[..]),
            Arc::from("t"),
            Rc::new(Cell::new(u64::MAX)),
        );
        let e = l2.number_run(parse_f32, |_| {}).unwrap_err();
        assert_eq!((e.kind, e.loc.col), (LxsErrorKind::Syntax, 3));
    }
}
