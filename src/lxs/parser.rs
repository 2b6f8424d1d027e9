//! The statement grammar: reads statements from a stack of lexers (one per open Include) and
//! calls the matching [`SceneBuilder`] method. The parser checks syntax, value counts and
//! types, and input limits; graphics-state rules belong to the builder.

use super::builder::SceneBuilder;
use super::description::Entity;
use super::error::{LxsError, LxsErrorKind, LxsResult};
use super::include::resolve;
use super::lexer::{parse_f32, parse_f64, Lexer, Peek};
use super::params::{Loc, ParamSet};
use super::suggest::nearest;
use super::values::{describe_peek, ValueReader};
use super::ParseOptions;
use std::cell::Cell;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

/// Every statement name of the .lxs language.
pub const STATEMENTS: &[&str] = &[
    "Accelerator",
    "AreaLightSource",
    "AttributeBegin",
    "AttributeEnd",
    "Camera",
    "ConcatTransform",
    "CoordinateSystem",
    "CoordSysTransform",
    "Exterior",
    "Film",
    "Identity",
    "Include",
    "Interior",
    "LightGroup",
    "LightSource",
    "LookAt",
    "MakeNamedMaterial",
    "MakeNamedVolume",
    "Material",
    "MotionBegin",
    "MotionEnd",
    "MotionInstance",
    "NamedMaterial",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "PixelFilter",
    "PortalInstance",
    "PortalShape",
    "Renderer",
    "ReverseOrientation",
    "Rotate",
    "Sampler",
    "Scale",
    "SearchPath",
    "Shape",
    "SurfaceIntegrator",
    "Texture",
    "Transform",
    "TransformBegin",
    "TransformEnd",
    "Translate",
    "Volume",
    "VolumeIntegrator",
    "WorldBegin",
    "WorldEnd",
];

/// One open file.
struct Frame<'a> {
    lex: Lexer<'a>,
    /// Directory of this file as shown in locations.
    dir: PathBuf,
    /// Canonical directory (symlinks resolved).
    canonical_dir: PathBuf,
    /// Canonical path of the file itself, for cycle detection (None for in-memory text).
    canonical: Option<PathBuf>,
}

/// Drives a builder from text.
pub struct Parser<'a> {
    frames: Vec<Frame<'a>>,
    values: ValueReader,
    opts: ParseOptions,
    budget: Rc<Cell<u64>>,
    /// Canonical root directory when includes are confined to it.
    root: Option<PathBuf>,
}

fn canonical_dir_of(path: &Path) -> PathBuf {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::canonicalize(&dir).unwrap_or(dir)
}

fn display_dir_of(path: &Path) -> PathBuf {
    path.parent().map(Path::to_path_buf).unwrap_or_default()
}

impl<'a> Parser<'a> {
    /// A parser over `reader`, whose text is named `name` (a path: Includes resolve against its
    /// directory). `canonical` is the canonical path of the file when it is one.
    pub fn new(
        reader: Box<dyn Read + 'a>,
        name: &str,
        canonical: Option<PathBuf>,
        opts: &ParseOptions,
    ) -> Parser<'a> {
        let budget = Rc::new(Cell::new(opts.max_total_bytes));
        let path = Path::new(name);
        let canonical_dir = canonical
            .as_deref()
            .map(canonical_dir_of)
            .unwrap_or_else(|| canonical_dir_of(path));
        let root = opts.confine_to_root.then(|| canonical_dir.clone());
        let lex = Lexer::new(reader, Arc::from(name), budget.clone());
        Parser {
            frames: vec![Frame {
                lex,
                dir: display_dir_of(path),
                canonical_dir,
                canonical,
            }],
            values: ValueReader::new(opts.max_array_len),
            opts: opts.clone(),
            budget,
            root,
        }
    }

    fn lex(&mut self) -> LxsResult<&mut Lexer<'a>> {
        match self.frames.last_mut() {
            Some(f) => Ok(&mut f.lex),
            None => Err(LxsError::new(
                LxsErrorKind::Syntax,
                Loc::default(),
                "no input",
            )),
        }
    }

    /// Parses everything, calling `b` for each statement.
    pub fn run(&mut self, b: &mut dyn SceneBuilder) -> LxsResult<()> {
        loop {
            let lex = self.lex()?;
            lex.skip_ws()?;
            let loc = lex.loc();
            match lex.peek()? {
                Peek::Eof => {
                    if self.frames.len() == 1 {
                        return b.end_of_input(&loc);
                    }
                    self.frames.pop();
                }
                Peek::Ident => {
                    let word = lex.ident()?;
                    self.statement(&word, &loc, b)?;
                    for d in self.values.warnings.drain(..) {
                        b.warning(d);
                    }
                }
                _ => {
                    let what = describe_peek(lex)?;
                    return Err(LxsError::new(
                        LxsErrorKind::Syntax,
                        loc,
                        format!("expected a statement, found {what}"),
                    ));
                }
            }
        }
    }

    fn params(&mut self) -> LxsResult<ParamSet> {
        let lex = match self.frames.last_mut() {
            Some(f) => &mut f.lex,
            None => return Ok(ParamSet::new()),
        };
        self.values.param_list(lex)
    }

    /// `Keyword "kind" params` as an entity.
    fn entity(&mut self, stmt: &str, loc: &Loc) -> LxsResult<Entity> {
        let kind = self.string_arg(stmt, "a quoted type name")?;
        let params = self.params()?;
        Ok(Entity {
            kind,
            params,
            loc: loc.clone(),
        })
    }

    /// A required quoted string argument.
    fn string_arg(&mut self, stmt: &str, what: &str) -> LxsResult<String> {
        let lex = self.lex()?;
        lex.skip_ws()?;
        match lex.peek()? {
            Peek::Str => lex.string(),
            p => {
                let kind = if matches!(p, Peek::Number | Peek::LBrack) {
                    LxsErrorKind::WrongValueType
                } else {
                    LxsErrorKind::WrongValueCount
                };
                let found = describe_peek(lex)?;
                Err(LxsError::new(
                    kind,
                    lex.loc(),
                    format!("{stmt} needs {what}, found {found}"),
                ))
            }
        }
    }

    /// Numbers given bare or in one bracketed array; exactly `n` of them unless `n` is None.
    fn numbers(&mut self, stmt: &str, n: Option<usize>, loc: &Loc) -> LxsResult<Vec<f64>> {
        let max = self.opts.max_array_len;
        let lex = self.lex()?;
        lex.skip_ws()?;
        let mut out = Vec::new();
        if lex.peek()? == Peek::LBrack {
            let open = lex.loc();
            lex.bump();
            loop {
                lex.skip_ws()?;
                match lex.peek()? {
                    Peek::RBrack => {
                        lex.bump();
                        break;
                    }
                    Peek::Number => out.push(lex.number(parse_f64)?),
                    Peek::Str => {
                        return Err(LxsError::new(
                            LxsErrorKind::WrongValueType,
                            lex.loc(),
                            format!("{stmt} takes numbers, found a string"),
                        ))
                    }
                    _ => {
                        let found = describe_peek(lex)?;
                        return Err(LxsError::new(
                            LxsErrorKind::UnterminatedArray,
                            open,
                            format!("unterminated array of {stmt}: found {found} before ']'"),
                        ));
                    }
                }
                if out.len() > max {
                    return Err(LxsError::new(
                        LxsErrorKind::ArrayTooLong,
                        loc.clone(),
                        format!("{stmt} has too many values"),
                    ));
                }
            }
        } else {
            while lex.peek()? == Peek::Number {
                out.push(lex.number(parse_f64)?);
                if out.len() > 64 {
                    break;
                }
                lex.skip_ws()?;
            }
            if lex.peek()? == Peek::Str && n.is_some() {
                return Err(LxsError::new(
                    LxsErrorKind::WrongValueType,
                    lex.loc(),
                    format!("{stmt} takes numbers, found a string"),
                ));
            }
        }
        if let Some(n) = n {
            if out.len() != n {
                return Err(LxsError::new(
                    LxsErrorKind::WrongValueCount,
                    loc.clone(),
                    format!("{stmt} needs {n} numbers, found {}", out.len()),
                ));
            }
        }
        Ok(out)
    }

    fn vec3(v: &[f64], i: usize) -> [f64; 3] {
        [v[i], v[i + 1], v[i + 2]]
    }

    fn matrix(v: &[f64]) -> [f64; 16] {
        let mut m = [0.0; 16];
        m.copy_from_slice(&v[..16]);
        m
    }

    /// Dispatches one statement.
    fn statement(&mut self, word: &str, loc: &Loc, b: &mut dyn SceneBuilder) -> LxsResult<()> {
        match word {
            "Accelerator" => b.accelerator(self.entity(word, loc)?),
            "AreaLightSource" => b.area_light_source(self.entity(word, loc)?),
            "AttributeBegin" => b.attribute_begin(loc),
            "AttributeEnd" => b.attribute_end(loc),
            "Camera" => b.camera(self.entity(word, loc)?),
            "ConcatTransform" => {
                let v = self.numbers(word, Some(16), loc)?;
                b.concat_transform(Self::matrix(&v), loc)
            }
            "CoordinateSystem" => {
                let n = self.string_arg(word, "a quoted name")?;
                b.coordinate_system(&n, loc)
            }
            "CoordSysTransform" => {
                let n = self.string_arg(word, "a quoted name")?;
                b.coord_sys_transform(&n, loc)
            }
            "Exterior" => {
                let n = self.string_arg(word, "a quoted volume name")?;
                b.exterior(&n, loc)
            }
            "Film" => b.film(self.entity(word, loc)?),
            "Identity" => b.identity(loc),
            "Include" => self.include(loc, b),
            "Interior" => {
                let n = self.string_arg(word, "a quoted volume name")?;
                b.interior(&n, loc)
            }
            "LightGroup" => {
                let n = self.string_arg(word, "a quoted group name")?;
                let p = self.params()?;
                b.light_group(&n, p, loc)
            }
            "LightSource" => b.light_source(self.entity(word, loc)?),
            "LookAt" => {
                let v = self.numbers(word, Some(9), loc)?;
                b.look_at(Self::vec3(&v, 0), Self::vec3(&v, 3), Self::vec3(&v, 6), loc)
            }
            "MakeNamedMaterial" => {
                let n = self.string_arg(word, "a quoted material name")?;
                let p = self.params()?;
                b.make_named_material(&n, p, loc)
            }
            "MakeNamedVolume" => {
                let n = self.string_arg(word, "a quoted volume name")?;
                let e = self.entity(word, loc)?;
                b.make_named_volume(&n, e)
            }
            "Material" => b.material(self.entity(word, loc)?),
            "MotionBegin" => {
                let v = self.numbers(word, None, loc)?;
                if v.is_empty() {
                    return Err(LxsError::new(
                        LxsErrorKind::WrongValueCount,
                        loc.clone(),
                        "MotionBegin needs an array of times",
                    ));
                }
                b.motion_begin(v.into_iter().map(|t| t as f32).collect(), loc)
            }
            "MotionEnd" => b.motion_end(loc),
            "MotionInstance" => self.motion_instance(loc, b),
            "NamedMaterial" => {
                let n = self.string_arg(word, "a quoted material name")?;
                b.named_material(&n, loc)
            }
            "ObjectBegin" => {
                let n = self.string_arg(word, "a quoted object name")?;
                b.object_begin(&n, loc)
            }
            "ObjectEnd" => b.object_end(loc),
            "ObjectInstance" => {
                let n = self.string_arg(word, "a quoted object name")?;
                b.object_instance(&n, loc)
            }
            "PixelFilter" => b.pixel_filter(self.entity(word, loc)?),
            "PortalInstance" => {
                let n = self.string_arg(word, "a quoted object name")?;
                b.portal_instance(&n, loc)
            }
            "PortalShape" => b.portal_shape(self.entity(word, loc)?),
            "Renderer" => b.renderer(self.entity(word, loc)?),
            "ReverseOrientation" => b.reverse_orientation(loc),
            "Rotate" => {
                let v = self.numbers(word, Some(4), loc)?;
                b.rotate(v[0], Self::vec3(&v, 1), loc)
            }
            "Sampler" => b.sampler(self.entity(word, loc)?),
            "Scale" => {
                let v = self.numbers(word, Some(3), loc)?;
                b.scale(Self::vec3(&v, 0), loc)
            }
            "SearchPath" => {
                let n = self.string_arg(word, "a quoted path")?;
                b.search_path(&n, loc)
            }
            "Shape" => b.shape(self.entity(word, loc)?),
            "SurfaceIntegrator" => b.surface_integrator(self.entity(word, loc)?),
            "Texture" => {
                let n = self.string_arg(word, "a quoted texture name")?;
                let ty = self.string_arg(word, "a value type (\"float\" or \"color\")")?;
                let e = self.entity(word, loc)?;
                b.texture(&n, &ty, e)
            }
            "Transform" => {
                let v = self.numbers(word, Some(16), loc)?;
                b.transform(Self::matrix(&v), loc)
            }
            "TransformBegin" => b.transform_begin(loc),
            "TransformEnd" => b.transform_end(loc),
            "Translate" => {
                let v = self.numbers(word, Some(3), loc)?;
                b.translate(Self::vec3(&v, 0), loc)
            }
            "Volume" => b.volume(self.entity(word, loc)?),
            "VolumeIntegrator" => b.volume_integrator(self.entity(word, loc)?),
            "WorldBegin" => b.world_begin(loc),
            "WorldEnd" => b.world_end(loc),
            _ => {
                let hint = nearest(word, STATEMENTS)
                    .map(|s| format!(" (did you mean '{s}'?)"))
                    .unwrap_or_default();
                Err(LxsError::new(
                    LxsErrorKind::UnknownStatement,
                    loc.clone(),
                    format!("unknown statement '{word}'{hint}"),
                ))
            }
        }
    }

    fn motion_instance(&mut self, loc: &Loc, b: &mut dyn SceneBuilder) -> LxsResult<()> {
        let name = self.string_arg("MotionInstance", "a quoted object name")?;
        let lex = self.lex()?;
        let mut times = [0.0f32; 2];
        for t in &mut times {
            lex.skip_ws()?;
            if lex.peek()? != Peek::Number {
                return Err(LxsError::new(
                    LxsErrorKind::WrongValueCount,
                    loc.clone(),
                    "MotionInstance needs a name, two times and a coordinate system name",
                ));
            }
            *t = lex.number(parse_f32)?;
        }
        let to = self.string_arg("MotionInstance", "a quoted coordinate system name")?;
        b.motion_instance(&name, times[0], times[1], &to, loc)
    }

    /// `Include "file"`: resolves and opens the file and pushes a lexer for it.
    fn include(&mut self, loc: &Loc, b: &mut dyn SceneBuilder) -> LxsResult<()> {
        let name = self.string_arg("Include", "a quoted file name")?;
        let Some(top) = self.frames.last() else {
            return Ok(());
        };
        if self.frames.len() > self.opts.max_include_depth {
            return Err(LxsError::new(
                LxsErrorKind::IncludeTooDeep,
                loc.clone(),
                format!(
                    "Include \"{name}\" nests deeper than {} levels (ParseOptions::max_include_depth)",
                    self.opts.max_include_depth
                ),
            ));
        }
        let r = resolve(
            &name,
            &top.dir,
            &top.canonical_dir,
            self.root.as_deref(),
            loc,
        )?;
        if self
            .frames
            .iter()
            .any(|f| f.canonical.as_deref() == Some(r.canonical.as_path()))
        {
            return Err(LxsError::new(
                LxsErrorKind::IncludeCycle,
                loc.clone(),
                format!(
                    "Include \"{name}\" forms a cycle: {} is already being read",
                    r.display.display()
                ),
            ));
        }
        let file = std::fs::File::open(&r.canonical).map_err(|e| {
            LxsError::new(
                LxsErrorKind::MissingInclude,
                loc.clone(),
                format!(
                    "Include \"{name}\": cannot open {}: {e}",
                    r.display.display()
                ),
            )
        })?;
        let shown = r.display.to_string_lossy().into_owned();
        b.include(&shown, loc)?;
        let lex = Lexer::new(
            Box::new(file),
            Arc::from(shown.as_str()),
            self.budget.clone(),
        );
        self.frames.push(Frame {
            lex,
            dir: display_dir_of(&r.display),
            canonical_dir: canonical_dir_of(&r.canonical),
            canonical: Some(r.canonical),
        });
        Ok(())
    }
}
