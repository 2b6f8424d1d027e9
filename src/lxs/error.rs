//! Errors of the .lxs parser: every one names the file, line and column where it happened and
//! gives a one-line reason. Parsing stops at the first error.

use super::params::Loc;
use std::fmt;

/// What went wrong, so callers and tests can tell errors apart without matching on text.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum LxsErrorKind {
    /// A file could not be read (the root scene, or an I/O error while reading).
    Io,
    /// A character or token that cannot start anything here.
    Syntax,
    /// An identifier that is not a statement name.
    UnknownStatement,
    /// A quoted string without its closing quote on the same line.
    UnterminatedString,
    /// A `[` without its `]`.
    UnterminatedArray,
    /// A number that does not parse, or is out of range for its type.
    InvalidNumber,
    /// Too few or too many values for a statement or parameter.
    WrongValueCount,
    /// Values of the wrong type (a string where numbers belong, an unknown bool, ...).
    WrongValueType,
    /// A parameter declared with an unknown type keyword (`"flaot fov"`).
    UnknownParamType,
    /// A value that is well formed but meaningless (zero rotation axis, degenerate LookAt, ...).
    InvalidValue,
    /// An `Include` whose file does not exist or cannot be read.
    MissingInclude,
    /// An `Include` of a file that is already being read.
    IncludeCycle,
    /// Includes nested deeper than `ParseOptions::max_include_depth`.
    IncludeTooDeep,
    /// An `Include` that leaves the root scene's directory while `confine_to_root` is set.
    IncludeOutsideRoot,
    /// An array longer than `ParseOptions::max_array_len`.
    ArrayTooLong,
    /// More input than `ParseOptions::max_total_bytes`, or a single token too long.
    InputTooLarge,
    /// A statement where it is not allowed (Shape before WorldBegin, Camera after it, ...).
    WrongBlock,
    /// An end statement without its begin, or closing a different kind of block.
    UnmatchedEnd,
    /// A block still open at the end of the input (or at WorldEnd).
    UnclosedBlock,
    /// A reference to a named material, texture, object, volume or coordinate system that is
    /// not defined at that point.
    Undefined,
    /// Something LuxRender accepts that this parser does not represent.
    Unsupported,
}

/// A parse error: where, what kind, and a one-line reason.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct LxsError {
    pub loc: Loc,
    pub kind: LxsErrorKind,
    pub message: String,
}

impl LxsError {
    pub fn new(kind: LxsErrorKind, loc: Loc, message: impl Into<String>) -> LxsError {
        LxsError {
            loc,
            kind,
            message: message.into(),
        }
    }
}

impl fmt::Display for LxsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.loc, self.message)
    }
}

/// Shorthand for results of the parser.
pub type LxsResult<T> = Result<T, LxsError>;
