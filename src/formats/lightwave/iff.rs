//! A bounds-checked reader of EA IFF 85 data as LightWave objects use it (big-endian numbers,
//! chunks with 4-byte lengths, sub-chunks with 2-byte lengths, even padding, null-terminated
//! strings padded to even length, LWO2 variable-length indices).
//!
//! ```text
//! file bytes --Reader::chunks()--> Chunk { id, offset, body: Reader } --typed reads--> values
//! ```
//!
//! Every read checks the bytes left first: a length or count in the file is never trusted
//! before it is compared with what remains, so a hostile file cannot make the reader allocate
//! beyond its own size or read out of bounds. Errors carry the absolute byte offset.

use std::fmt;

/// A malformed-data error at an absolute byte offset of the file.
#[derive(Clone, Debug, PartialEq)]
pub struct IffError {
    pub offset: usize,
    pub message: String,
}

impl fmt::Display for IffError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "at byte {}: {}", self.offset, self.message)
    }
}

pub type IffResult<T> = Result<T, IffError>;

/// A window of the file being read, with its absolute start offset.
#[derive(Clone, Debug)]
pub struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    base: usize,
}

/// A chunk or sub-chunk: its id, the absolute offset of its header, and its body.
#[derive(Clone, Debug)]
pub struct Chunk<'a> {
    pub id: [u8; 4],
    pub offset: usize,
    pub body: Reader<'a>,
}

impl Chunk<'_> {
    pub fn id_str(&self) -> String {
        id_string(self.id)
    }
}

/// A chunk id as text (non-printable bytes escaped).
pub fn id_string(id: [u8; 4]) -> String {
    id.iter()
        .map(|&b| {
            if b.is_ascii_graphic() || b == b' ' {
                char::from(b).to_string()
            } else {
                format!("\\x{b:02x}")
            }
        })
        .collect()
}

impl<'a> Reader<'a> {
    pub fn new(data: &'a [u8]) -> Reader<'a> {
        Reader {
            data,
            pos: 0,
            base: 0,
        }
    }

    /// The absolute offset of the next byte.
    pub fn offset(&self) -> usize {
        self.base + self.pos
    }

    pub fn remaining(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }

    pub fn is_empty(&self) -> bool {
        self.remaining() == 0
    }

    pub fn error(&self, message: impl Into<String>) -> IffError {
        IffError {
            offset: self.offset(),
            message: message.into(),
        }
    }

    fn take(&mut self, n: usize) -> IffResult<&'a [u8]> {
        if n > self.remaining() {
            return Err(self.error(format!("{n} bytes needed, {} left", self.remaining())));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    /// Skips `n` bytes (or fails when fewer remain).
    pub fn skip(&mut self, n: usize) -> IffResult<()> {
        self.take(n).map(|_| ())
    }

    /// The next `n` bytes as a reader of their own.
    pub fn sub(&mut self, n: usize) -> IffResult<Reader<'a>> {
        let base = self.offset();
        let data = self.take(n)?;
        Ok(Reader { data, pos: 0, base })
    }

    pub fn u1(&mut self) -> IffResult<u8> {
        Ok(self.take(1)?[0])
    }

    pub fn u2(&mut self) -> IffResult<u16> {
        let b = self.take(2)?;
        Ok(u16::from_be_bytes([b[0], b[1]]))
    }

    pub fn i2(&mut self) -> IffResult<i16> {
        Ok(self.u2()? as i16)
    }

    pub fn u4(&mut self) -> IffResult<u32> {
        let b = self.take(4)?;
        Ok(u32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    }

    pub fn id4(&mut self) -> IffResult<[u8; 4]> {
        let b = self.take(4)?;
        Ok([b[0], b[1], b[2], b[3]])
    }

    /// A big-endian f32; NaN and infinities (never meaningful in an object) become errors.
    pub fn f4(&mut self) -> IffResult<f32> {
        let at = self.offset();
        let v = f32::from_bits(self.u4()?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(IffError {
                offset: at,
                message: "a number is NaN or infinite".into(),
            })
        }
    }

    pub fn vec12(&mut self) -> IffResult<[f32; 3]> {
        Ok([self.f4()?, self.f4()?, self.f4()?])
    }

    /// An LWO2 variable-length index: 2 bytes, or 4 when the first byte is 0xFF (the low 24
    /// bits then hold the index).
    pub fn vx(&mut self) -> IffResult<u32> {
        if self.data.get(self.pos) == Some(&0xFF) {
            Ok(self.u4()? & 0x00FF_FFFF)
        } else {
            Ok(u32::from(self.u2()?))
        }
    }

    /// A null-terminated string padded to an even length (S0). Bytes are Latin-1 when not
    /// UTF-8.
    pub fn s0(&mut self) -> IffResult<String> {
        let rest = &self.data[self.pos.min(self.data.len())..];
        let Some(len) = rest.iter().position(|&b| b == 0) else {
            return Err(self.error("a string is not terminated"));
        };
        let bytes = &rest[..len];
        let s = match std::str::from_utf8(bytes) {
            Ok(s) => s.to_string(),
            Err(_) => bytes.iter().map(|&b| char::from(b)).collect(),
        };
        let total = len + 1 + (len + 1) % 2;
        self.pos += total.min(self.remaining());
        Ok(s)
    }

    /// The next chunk with a 4-byte length (top-level LWO chunks, CLIP), or None at the end.
    pub fn chunk(&mut self) -> IffResult<Option<Chunk<'a>>> {
        self.any_chunk(4)
    }

    /// The next sub-chunk with a 2-byte length (SURF, BLOK, CLIP contents), or None.
    pub fn subchunk(&mut self) -> IffResult<Option<Chunk<'a>>> {
        self.any_chunk(2)
    }

    fn any_chunk(&mut self, len_bytes: usize) -> IffResult<Option<Chunk<'a>>> {
        if self.remaining() == 0 {
            return Ok(None);
        }
        let offset = self.offset();
        if self.remaining() < 4 + len_bytes {
            return Err(self.error(format!(
                "{} stray bytes where a chunk header belongs",
                self.remaining()
            )));
        }
        let id = self.id4()?;
        let len = if len_bytes == 4 {
            self.u4()? as usize
        } else {
            usize::from(self.u2()?)
        };
        if len > self.remaining() {
            return Err(IffError {
                offset,
                message: format!(
                    "chunk {} claims {len} bytes but only {} are left",
                    id_string(id),
                    self.remaining()
                ),
            });
        }
        let body = self.sub(len)?;
        // Pad byte after odd lengths (may be missing at the very end).
        if len % 2 == 1 && self.remaining() > 0 {
            self.pos += 1;
        }
        Ok(Some(Chunk { id, offset, body }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_numbers_strings_and_indices() {
        let data = [
            0x00, 0x05, // u2
            0x3F, 0x80, 0x00, 0x00, // 1.0
            b'a', b'b', 0, 0, // "ab" padded
            b'x', 0, // "x"
            0x00, 0x07, // vx 2 bytes
            0xFF, 0x01, 0x00, 0x02, // vx 4 bytes
        ];
        let mut r = Reader::new(&data);
        assert_eq!(r.u2().unwrap(), 5);
        assert_eq!(r.f4().unwrap(), 1.0);
        assert_eq!(r.s0().unwrap(), "ab");
        assert_eq!(r.s0().unwrap(), "x");
        assert_eq!(r.vx().unwrap(), 7);
        assert_eq!(r.vx().unwrap(), 0x010002);
        assert!(r.is_empty());
        assert!(r.u1().is_err());
    }

    #[test]
    fn chunks_are_bounded_and_padded() {
        let data = [
            b'A', b'B', b'C', b'D', 0, 0, 0, 1, 9, 0, b'E', b'F', b'G', b'H', 0, 0, 0, 0,
        ];
        let mut r = Reader::new(&data);
        let c = r.chunk().unwrap().unwrap();
        assert_eq!(&c.id, b"ABCD");
        assert_eq!(c.body.remaining(), 1);
        let d = r.chunk().unwrap().unwrap();
        assert_eq!(d.offset, 10);
        assert!(r.chunk().unwrap().is_none());
        let bad = [b'A', b'B', b'C', b'D', 0xFF, 0xFF, 0xFF, 0xFF, 1];
        let e = Reader::new(&bad).chunk().unwrap_err();
        assert_eq!(e.offset, 0);
        assert!(e.message.contains("claims"), "{e}");
    }

    #[test]
    fn nan_and_unterminated_strings_are_errors() {
        let nan = 0x7FC0_0000u32.to_be_bytes();
        assert!(Reader::new(&nan).f4().is_err());
        assert!(Reader::new(b"abc").s0().is_err());
        assert_eq!(id_string(*b"A\x01BC"), "A\\x01BC");
    }
}
