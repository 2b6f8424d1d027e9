//! Typed parameter lists (`"float fov" [45]`) as the parser hands them to plugins.
//!
//! A `ParamSet` keeps every parameter with its declared type, its values and the place it was
//! written. Lookups are typed (a `float` lookup never returns a `color`) and mark the parameter
//! as consumed, so once a plugin has been built, [`ParamSet::unused`] lists what it ignored: a
//! misspelled or unsupported parameter is then reported with its file:line:column.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A place in a scene file: file path as written/resolved, 1-based line and column.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub struct Loc {
    pub file: Arc<str>,
    pub line: u32,
    pub col: u32,
}

impl fmt::Display for Loc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.col)
    }
}

/// The declared type of a parameter, as written before its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ParamType {
    Integer,
    Float,
    Point,
    Vector,
    Normal,
    Color,
    Bool,
    String,
    Texture,
    /// Legacy `spectrum` parameters of old exporters: either numbers (wavelength/value pairs or
    /// RGB) or a file name; kept as written.
    Spectrum,
}

impl ParamType {
    /// Parses the type keyword of a parameter declaration (`"float fov"` -> `Float`).
    /// `point3`/`normal3`/`vector3`/`rgb`/`bool`-aliases that LuxRender accepts map too.
    pub fn from_keyword(s: &str) -> Option<ParamType> {
        Some(match s {
            "integer" | "int" => ParamType::Integer,
            "float" => ParamType::Float,
            "point" | "point3" => ParamType::Point,
            "vector" | "vector3" => ParamType::Vector,
            "normal" | "normal3" => ParamType::Normal,
            "color" | "rgb" => ParamType::Color,
            "bool" => ParamType::Bool,
            "string" => ParamType::String,
            "texture" => ParamType::Texture,
            "spectrum" => ParamType::Spectrum,
            _ => return None,
        })
    }

    pub fn keyword(self) -> &'static str {
        match self {
            ParamType::Integer => "integer",
            ParamType::Float => "float",
            ParamType::Point => "point",
            ParamType::Vector => "vector",
            ParamType::Normal => "normal",
            ParamType::Color => "color",
            ParamType::Bool => "bool",
            ParamType::String => "string",
            ParamType::Texture => "texture",
            ParamType::Spectrum => "spectrum",
        }
    }
}

/// The values of one parameter. Numbers are stored compactly (f32/i32): real exports are
/// dominated by huge vertex and index arrays.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", content = "values", rename_all = "lowercase")]
pub enum ParamValue {
    Integer(Vec<i32>),
    Float(Vec<f32>),
    Point(Vec<[f32; 3]>),
    Vector(Vec<[f32; 3]>),
    Normal(Vec<[f32; 3]>),
    Color(Vec<[f32; 3]>),
    Bool(Vec<bool>),
    String(Vec<String>),
    /// Name of a texture (`"texture Kd" "wood"`).
    Texture(String),
    /// Legacy spectrum: numbers, or a file name.
    Spectrum(SpectrumValue),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SpectrumValue {
    Numbers(Vec<f32>),
    File(String),
}

impl ParamValue {
    pub fn param_type(&self) -> ParamType {
        match self {
            ParamValue::Integer(_) => ParamType::Integer,
            ParamValue::Float(_) => ParamType::Float,
            ParamValue::Point(_) => ParamType::Point,
            ParamValue::Vector(_) => ParamType::Vector,
            ParamValue::Normal(_) => ParamType::Normal,
            ParamValue::Color(_) => ParamType::Color,
            ParamValue::Bool(_) => ParamType::Bool,
            ParamValue::String(_) => ParamType::String,
            ParamValue::Texture(_) => ParamType::Texture,
            ParamValue::Spectrum(_) => ParamType::Spectrum,
        }
    }

    /// Number of values (triples count once).
    pub fn len(&self) -> usize {
        match self {
            ParamValue::Integer(v) => v.len(),
            ParamValue::Float(v) => v.len(),
            ParamValue::Point(v)
            | ParamValue::Vector(v)
            | ParamValue::Normal(v)
            | ParamValue::Color(v) => v.len(),
            ParamValue::Bool(v) => v.len(),
            ParamValue::String(v) => v.len(),
            ParamValue::Texture(_) => 1,
            ParamValue::Spectrum(SpectrumValue::Numbers(v)) => v.len(),
            ParamValue::Spectrum(SpectrumValue::File(_)) => 1,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One parameter: name, values, where it was written, and whether a plugin consumed it.
#[derive(Debug, Serialize, Deserialize)]
pub struct Param {
    pub name: String,
    pub value: ParamValue,
    pub loc: Loc,
    #[serde(skip)]
    used: AtomicBool,
}

impl Clone for Param {
    fn clone(&self) -> Self {
        Param {
            name: self.name.clone(),
            value: self.value.clone(),
            loc: self.loc.clone(),
            used: AtomicBool::new(self.used.load(Ordering::Relaxed)),
        }
    }
}

impl PartialEq for Param {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.value == other.value && self.loc == other.loc
    }
}

impl Param {
    pub fn new(name: impl Into<String>, value: ParamValue, loc: Loc) -> Param {
        Param {
            name: name.into(),
            value,
            loc,
            used: AtomicBool::new(false),
        }
    }

    pub fn is_used(&self) -> bool {
        self.used.load(Ordering::Relaxed)
    }

    /// Marks the parameter read. Only the first read writes: a light or texture that reads
    /// its parameters at render time (a moving area primitive) must not make every render
    /// thread write the same cache line.
    fn mark_used(&self) {
        if !self.used.load(Ordering::Relaxed) {
            self.used.store(true, Ordering::Relaxed);
        }
    }
}

/// The parameters of one statement. A later parameter of the same name replaces an earlier one
/// (as in LuxRender).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ParamSet {
    pub params: Vec<Param>,
}

macro_rules! typed_slice {
    ($fn:ident, $variant:ident, $t:ty) => {
        /// All values of the parameter of this name and type, marking it used.
        pub fn $fn(&self, name: &str) -> Option<&[$t]> {
            match self.lookup(name, ParamType::$variant)? {
                ParamValue::$variant(v) => Some(v.as_slice()),
                _ => None,
            }
        }
    };
}

impl ParamSet {
    pub fn new() -> ParamSet {
        ParamSet::default()
    }

    /// Adds a parameter, replacing one of the same name (any type).
    pub fn push(&mut self, param: Param) {
        self.params.retain(|p| p.name != param.name);
        self.params.push(param);
    }

    /// Adds a parameter built from parts (convenience for code and tests).
    pub fn add(&mut self, name: &str, value: ParamValue) {
        self.push(Param::new(name, value, Loc::default()));
    }

    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    pub fn len(&self) -> usize {
        self.params.len()
    }

    /// The parameter of this name and type, marked used when found.
    fn lookup(&self, name: &str, ty: ParamType) -> Option<&ParamValue> {
        let p = self
            .params
            .iter()
            .rev()
            .find(|p| p.name == name && p.value.param_type() == ty)?;
        p.mark_used();
        Some(&p.value)
    }

    /// The parameter of this name whatever its type, marked used when found.
    pub fn get(&self, name: &str) -> Option<&Param> {
        let p = self.params.iter().rev().find(|p| p.name == name)?;
        p.mark_used();
        Some(p)
    }

    /// Whether a parameter of this name exists (does not mark it used).
    pub fn contains(&self, name: &str) -> bool {
        self.params.iter().any(|p| p.name == name)
    }

    typed_slice!(ints, Integer, i32);
    typed_slice!(floats, Float, f32);
    typed_slice!(points, Point, [f32; 3]);
    typed_slice!(vectors, Vector, [f32; 3]);
    typed_slice!(normals, Normal, [f32; 3]);
    typed_slice!(colors, Color, [f32; 3]);
    typed_slice!(bools, Bool, bool);
    typed_slice!(strings, String, String);

    pub fn int(&self, name: &str) -> Option<i32> {
        self.ints(name)?.first().copied()
    }
    pub fn float(&self, name: &str) -> Option<f32> {
        self.floats(name)?.first().copied()
    }
    pub fn point(&self, name: &str) -> Option<[f32; 3]> {
        self.points(name)?.first().copied()
    }
    pub fn vector(&self, name: &str) -> Option<[f32; 3]> {
        self.vectors(name)?.first().copied()
    }
    pub fn normal(&self, name: &str) -> Option<[f32; 3]> {
        self.normals(name)?.first().copied()
    }
    pub fn color(&self, name: &str) -> Option<[f32; 3]> {
        self.colors(name)?.first().copied()
    }
    pub fn bool(&self, name: &str) -> Option<bool> {
        self.bools(name)?.first().copied()
    }
    pub fn string(&self, name: &str) -> Option<&str> {
        self.strings(name)?.first().map(String::as_str)
    }

    pub fn int_or(&self, name: &str, default: i32) -> i32 {
        self.int(name).unwrap_or(default)
    }
    pub fn float_or(&self, name: &str, default: f32) -> f32 {
        self.float(name).unwrap_or(default)
    }
    pub fn bool_or(&self, name: &str, default: bool) -> bool {
        self.bool(name).unwrap_or(default)
    }
    pub fn string_or<'a>(&'a self, name: &str, default: &'a str) -> &'a str {
        self.string(name).unwrap_or(default)
    }
    pub fn color_or(&self, name: &str, default: [f32; 3]) -> [f32; 3] {
        self.color(name).unwrap_or(default)
    }

    /// The texture name given by a `"texture NAME"` parameter.
    pub fn texture(&self, name: &str) -> Option<&str> {
        match self.lookup(name, ParamType::Texture)? {
            ParamValue::Texture(t) => Some(t.as_str()),
            _ => None,
        }
    }

    /// A legacy `spectrum` parameter.
    pub fn spectrum(&self, name: &str) -> Option<&SpectrumValue> {
        match self.lookup(name, ParamType::Spectrum)? {
            ParamValue::Spectrum(s) => Some(s),
            _ => None,
        }
    }

    /// Parameters no lookup has consumed: reported as warnings with their location.
    pub fn unused(&self) -> impl Iterator<Item = &Param> {
        self.params.iter().filter(|p| !p.is_used())
    }

    /// Forgets which parameters were consumed (before building the scene a second time).
    pub fn reset_used(&self) {
        for p in &self.params {
            p.used.store(false, Ordering::Relaxed);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_lookup_marks_used_and_respects_type() {
        let mut ps = ParamSet::new();
        ps.add("fov", ParamValue::Float(vec![45.0]));
        ps.add("Kd", ParamValue::Color(vec![[0.5, 0.5, 0.5]]));
        ps.add("typo", ParamValue::Float(vec![1.0]));
        assert_eq!(ps.color("fov"), None);
        assert_eq!(ps.float("fov"), Some(45.0));
        assert_eq!(ps.color("Kd"), Some([0.5, 0.5, 0.5]));
        let unused: Vec<_> = ps.unused().map(|p| p.name.as_str()).collect();
        assert_eq!(unused, vec!["typo"]);
    }

    #[test]
    fn later_parameter_replaces_earlier() {
        let mut ps = ParamSet::new();
        ps.add("a", ParamValue::Float(vec![1.0]));
        ps.add("a", ParamValue::Integer(vec![2]));
        assert_eq!(ps.len(), 1);
        assert_eq!(ps.int("a"), Some(2));
    }
}
