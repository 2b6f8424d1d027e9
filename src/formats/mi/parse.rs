//! Reading .mi files into a [`MiScene`]: the top-level statements of the root file and of
//! every `$include`d file, with mental ray's preprocessor (`$include`, `$ifdef`/`$ifndef`/
//! `$else`/`$endif`, `$define`/`$undef`) and the limits of [`ParseOptions`].
//!
//! ```text
//! file text --Cursor--> statement dispatch --options/camera/objects/instances/lights/shaders
//!     ::parse--> MiScene (named definitions, the render statement, files read, notes)
//! ```
//!
//! Includes: a `.mdl` file is an MDL module, not .mi text — never read, with a note (its
//! materials get the matte fallback of [`super::shaders`]); `$include <name>` names a file
//! on mental ray's own search path (its shader declarations, e.g. `base.mi`): not read,
//! with a note, since luxfarm maps the standard shaders itself; so is a quoted standard
//! declaration file (`base.mi`, `physics.mi`, ...) that is not beside the scene. Any other
//! include must exist, inside the scene's directory when `confine_to_root` is set, within
//! the include depth and the byte budget shared by all files. `declare ... end declare`
//! blocks (shader declarations) are skipped. A later definition of a name replaces the
//! earlier one (incremental changes).

use super::camera::{self, MiCamera};
use super::cursor::{Cursor, MiResult};
use super::instances::{self, MiInstGroup, MiInstance};
use super::lexer::Tok;
use super::lights::{self, MiLight};
use super::objects::{self, MiObject};
use super::options::{self, Options};
use super::shaders::{self, MiMaterial, MiShader};
use crate::lxs::include::resolve;
use crate::lxs::{Diagnostic, Loc, LxsError, LxsErrorKind, ParseOptions};
use std::collections::{HashMap, HashSet};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// `render "root instgroup" "camera instance" "options"`.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderStmt {
    pub root: (String, Loc),
    pub camera: (String, Loc),
    pub options: (String, Loc),
    pub loc: Loc,
}

/// Everything a .mi scene defines, by name.
#[derive(Debug, Default)]
pub struct MiScene {
    pub options: HashMap<String, Options>,
    pub cameras: HashMap<String, MiCamera>,
    pub objects: HashMap<String, MiObject>,
    pub instances: HashMap<String, MiInstance>,
    pub instgroups: HashMap<String, MiInstGroup>,
    pub lights: HashMap<String, MiLight>,
    pub shaders: HashMap<String, MiShader>,
    pub materials: HashMap<String, MiMaterial>,
    pub render: Option<RenderStmt>,
    /// Every file read, the root first.
    pub files: Vec<String>,
    pub warnings: Vec<Diagnostic>,
}

/// mental ray's standard shader declaration files.
const STANDARD_DECLARATIONS: &[&str] = &[
    "base.mi",
    "physics.mi",
    "contour.mi",
    "subsurface.mi",
    "architectural.mi",
    "production.mi",
    "paint.mi",
    "mayabase.mi",
    "builtin_bsdf.mi",
];

/// Shared state while reading the root file and its includes.
struct Reader<'o> {
    opts: &'o ParseOptions,
    budget: u64,
    /// Canonical paths of the files being read (include cycles).
    stack: Vec<Option<PathBuf>>,
    root: Option<PathBuf>,
    defines: HashSet<String>,
    scene: MiScene,
}

fn canonical_dir_of(path: &Path) -> PathBuf {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::canonicalize(&dir).unwrap_or(dir)
}

fn file_loc(name: &str) -> Loc {
    Loc {
        file: name.into(),
        line: 0,
        col: 0,
    }
}

/// Reads the file at `path` with everything it includes.
pub fn read_file(path: &Path, opts: &ParseOptions) -> MiResult<MiScene> {
    let name = path.to_string_lossy().into_owned();
    let canonical = std::fs::canonicalize(path).ok();
    let mut r = Reader::new(opts, canonical_dir_of(path));
    let text = r.read_bounded(path, &file_loc(&name))?;
    r.scene.files.push(name.clone());
    r.stack.push(canonical);
    r.file(&text, &name, path)?;
    Ok(r.scene)
}

/// Reads scene text named `name` (a path: includes resolve against its directory).
pub fn read_str(text: &str, name: &str, opts: &ParseOptions) -> MiResult<MiScene> {
    let path = Path::new(name);
    let mut r = Reader::new(opts, canonical_dir_of(path));
    if text.len() as u64 > r.budget {
        return Err(too_large(file_loc(name)));
    }
    r.budget -= text.len() as u64;
    r.scene.files.push(name.to_string());
    r.stack.push(None);
    r.file(text, name, path)?;
    Ok(r.scene)
}

fn too_large(loc: Loc) -> LxsError {
    LxsError::new(
        LxsErrorKind::InputTooLarge,
        loc,
        "input exceeds the total size limit (ParseOptions::max_total_bytes)",
    )
}

impl<'o> Reader<'o> {
    fn new(opts: &'o ParseOptions, root_dir: PathBuf) -> Reader<'o> {
        Reader {
            opts,
            budget: opts.max_total_bytes,
            stack: Vec::new(),
            root: opts.confine_to_root.then_some(root_dir),
            defines: HashSet::new(),
            scene: MiScene::default(),
        }
    }

    fn note(&mut self, loc: Loc, message: impl Into<String>) {
        self.scene.warnings.push(Diagnostic {
            loc,
            message: message.into(),
        });
    }

    /// Reads a whole file within the byte budget (as text; invalid UTF-8 is replaced).
    fn read_bounded(&mut self, path: &Path, loc: &Loc) -> MiResult<String> {
        let io = |e: std::io::Error| {
            LxsError::new(
                LxsErrorKind::Io,
                loc.clone(),
                format!("cannot read {}: {e}", path.display()),
            )
        };
        let file = std::fs::File::open(path).map_err(io)?;
        let mut bytes = Vec::new();
        file.take(self.budget.saturating_add(1))
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if bytes.len() as u64 > self.budget {
            return Err(too_large(loc.clone()));
        }
        self.budget -= bytes.len() as u64;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    fn max_len(&self) -> usize {
        self.opts.max_array_len.max(1)
    }

    /// Reads the statements of one file, named `name` in locations, found at `path`.
    fn file(&mut self, text: &str, name: &str, path: &Path) -> MiResult<()> {
        let mut c = Cursor::new(text, Arc::from(name));
        let mut conds: Vec<Loc> = Vec::new();
        loop {
            let at = c.loc()?;
            match c.next()? {
                Tok::Eof => {
                    if let Some(open) = conds.pop() {
                        return Err(LxsError::new(
                            LxsErrorKind::UnclosedBlock,
                            open,
                            "$ifdef/$ifndef without its $endif",
                        ));
                    }
                    return Ok(());
                }
                Tok::Directive(d) => self.directive(&mut c, d, at, path, &mut conds)?,
                Tok::Word(w) => self.statement(&mut c, w, at)?,
                other => {
                    return Err(LxsError::new(
                        LxsErrorKind::Syntax,
                        at,
                        format!("expected a statement, found {}", other.describe()),
                    ))
                }
            }
        }
    }

    fn directive(
        &mut self,
        c: &mut Cursor,
        d: &str,
        at: Loc,
        path: &Path,
        conds: &mut Vec<Loc>,
    ) -> MiResult<()> {
        match d {
            "include" => self.include(c, at, path),
            "define" | "undef" => {
                let name = define_name(c)?;
                if d == "define" {
                    c.skip_values()?;
                    self.defines.insert(name);
                } else {
                    self.defines.remove(&name);
                }
                Ok(())
            }
            "ifdef" | "ifndef" => {
                let name = define_name(c)?;
                let take = self.defines.contains(&name) == (d == "ifdef");
                if take || skip_branch(c, true)? {
                    conds.push(at);
                }
                Ok(())
            }
            "else" => {
                if conds.pop().is_none() {
                    return Err(LxsError::new(LxsErrorKind::UnmatchedEnd, at, "$else without $ifdef"));
                }
                // The taken branch ends here: skip the other one through its $endif.
                skip_branch(c, false)?;
                Ok(())
            }
            "endif" => match conds.pop() {
                Some(_) => Ok(()),
                None => Err(LxsError::new(LxsErrorKind::UnmatchedEnd, at, "$endif without $ifdef")),
            },
            other => Err(LxsError::new(
                LxsErrorKind::Unsupported,
                at,
                format!("preprocessor directive ${other} is not supported (include, ifdef, ifndef, else, endif, define, undef)"),
            )),
        }
    }

    fn include(&mut self, c: &mut Cursor, at: Loc, path: &Path) -> MiResult<()> {
        let (name, system) = match c.next()? {
            Tok::Str(s) => (s.into_owned(), false),
            Tok::Angle(s) => (s.to_string(), true),
            other => {
                return Err(LxsError::new(
                    LxsErrorKind::Syntax,
                    at,
                    format!(
                        "$include needs a \"file\" or <file>, found {}",
                        other.describe()
                    ),
                ))
            }
        };
        let base = Path::new(&name)
            .file_name()
            .and_then(|f| f.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        if base.ends_with(".mdl") {
            self.note(at, format!("$include \"{name}\": an MDL module, not read; its materials are rendered with luxfarm's fallback"));
            return Ok(());
        }
        if system {
            self.note(at, format!("$include <{name}>: mental ray's own declarations are not read; luxfarm maps the standard shaders itself"));
            return Ok(());
        }
        if self.stack.len() > self.opts.max_include_depth {
            return Err(LxsError::new(
                LxsErrorKind::IncludeTooDeep,
                at,
                format!(
                    "$include \"{name}\" nests deeper than {} levels (ParseOptions::max_include_depth)",
                    self.opts.max_include_depth
                ),
            ));
        }
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let resolved = match resolve(
            &name,
            &dir,
            &canonical_dir_of(path),
            self.root.as_deref(),
            &at,
        ) {
            Ok(r) => r,
            Err(e)
                if e.kind == LxsErrorKind::MissingInclude
                    && STANDARD_DECLARATIONS.contains(&base.as_str()) =>
            {
                self.note(at, format!("$include \"{name}\": mental ray's standard declarations, not found beside the scene and not needed"));
                return Ok(());
            }
            Err(e) => return Err(e),
        };
        if self
            .stack
            .iter()
            .any(|f| f.as_deref() == Some(resolved.canonical.as_path()))
        {
            return Err(LxsError::new(
                LxsErrorKind::IncludeCycle,
                at,
                format!(
                    "$include \"{name}\" forms a cycle: {} is already being read",
                    resolved.display.display()
                ),
            ));
        }
        let text = self.read_bounded(&resolved.canonical, &at)?;
        let shown = resolved.display.to_string_lossy().into_owned();
        if !self.scene.files.contains(&shown) {
            self.scene.files.push(shown.clone());
        }
        self.stack.push(Some(resolved.canonical));
        let result = self.file(&text, &shown, &resolved.display);
        self.stack.pop();
        result
    }

    fn statement(&mut self, c: &mut Cursor, w: &str, at: Loc) -> MiResult<()> {
        let max = self.max_len();
        let s = &mut self.scene;
        match w {
            "incremental" => {
                // `incremental shader/object/...`: the definition replaces the earlier one.
                let loc = c.loc()?;
                let next = c.word("a statement after 'incremental'")?;
                return self.statement(c, next, loc);
            }
            "options" => {
                let name = c.string("the options' name")?;
                let o = options::parse(c, name.clone(), at)?;
                s.options.insert(name, o);
            }
            "camera" => {
                let name = c.string("the camera's name")?;
                let cam = camera::parse(c, name.clone(), at, max)?;
                s.cameras.insert(name, cam);
            }
            "object" => {
                let name = c.string("the object's name")?;
                let o = objects::parse(c, name.clone(), at, max)?;
                s.objects.insert(name, o);
            }
            "instance" => {
                let name = c.string("the instance's name")?;
                let i = instances::parse_instance(c, name.clone(), at, max)?;
                s.instances.insert(name, i);
            }
            "instgroup" => {
                let name = c.string("the instgroup's name")?;
                let g = instances::parse_instgroup(c, name.clone(), at, max)?;
                s.instgroups.insert(name, g);
            }
            "light" => {
                let name = c.string("the light's name")?;
                let l = lights::parse(c, name.clone(), at, max)?;
                s.lights.insert(name, l);
            }
            "shader" => {
                let name = c.string("the shader's name")?;
                let sh = shaders::parse_shader(c, name.clone(), at, max)?;
                s.shaders.insert(name, sh);
            }
            "material" => {
                let name = c.string("the material's name")?;
                let m = shaders::parse_material(c, name.clone(), at, max)?;
                s.materials.insert(name, m);
            }
            "render" => {
                let root = (c.string("the root instgroup's name")?, c.last_loc());
                let camera = (c.string("the camera instance's name")?, c.last_loc());
                let options = (c.string("the options' name")?, c.last_loc());
                match &s.render {
                    None => {
                        s.render = Some(RenderStmt {
                            root,
                            camera,
                            options,
                            loc: at,
                        })
                    }
                    Some(_) => s.warnings.push(Diagnostic {
                        loc: at,
                        message: "a second render statement: luxfarm renders the first".into(),
                    }),
                }
            }
            "declare" | "registry" => skip_block(c, w, &at)?,
            "link" | "code" | "version" | "verbose" | "mdl" | "set" | "delete" => {
                c.skip_values()?;
            }
            "color" | "scalar" | "vector" | "data" | "lightprofile" | "userdata" => {
                c.skip_line()?;
                s.warnings.push(Diagnostic {
                    loc: at,
                    message: format!("'{w}' statements (textures, data) are not used by luxfarm"),
                });
            }
            other => {
                return Err(LxsError::new(
                    LxsErrorKind::UnknownStatement,
                    at,
                    format!("unknown statement '{other}'"),
                ))
            }
        }
        Ok(())
    }
}

/// The name after `$define`/`$ifdef`/...
fn define_name(c: &mut Cursor) -> MiResult<String> {
    match c.next()? {
        Tok::Word(w) => Ok(w.to_string()),
        Tok::Str(s) => Ok(s.into_owned()),
        _ => Err(LxsError::new(
            LxsErrorKind::Syntax,
            c.last_loc(),
            "a preprocessor directive needs a name",
        )),
    }
}

/// Skips a branch not taken. With `stop_at_else`, a same-level `$else` ends the skip and
/// its branch is taken (returns true); otherwise (and at `$endif`) returns false.
fn skip_branch(c: &mut Cursor, stop_at_else: bool) -> MiResult<bool> {
    let mut depth = 0usize;
    loop {
        let at = c.loc()?;
        match c.next()? {
            Tok::Directive("ifdef" | "ifndef") => depth += 1,
            Tok::Directive("else") if depth == 0 && stop_at_else => return Ok(true),
            Tok::Directive("endif") => {
                if depth == 0 {
                    return Ok(false);
                }
                depth -= 1;
            }
            Tok::Eof => {
                return Err(LxsError::new(
                    LxsErrorKind::UnclosedBlock,
                    at,
                    "$ifdef/$ifndef without its $endif",
                ))
            }
            _ => {}
        }
    }
}

/// Skips a `declare ... end declare` (or `registry`) block.
fn skip_block(c: &mut Cursor, kw: &str, at: &Loc) -> MiResult<()> {
    loop {
        match c.next()? {
            Tok::Word("end") if c.at_word(kw)? => {
                c.next()?;
                return Ok(());
            }
            Tok::Eof => {
                return Err(LxsError::new(
                    LxsErrorKind::UnclosedBlock,
                    at.clone(),
                    format!("'{kw}' without its 'end {kw}'"),
                ))
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> MiResult<MiScene> {
        read_str(text, "/nonexistent/t.mi", &ParseOptions::default())
    }

    #[test]
    fn preprocessor_branches() {
        let s = read(
            "$define A\n$ifdef A\nshader \"x\" \"one_color\" ()\n$else\nshader \"y\" \"one_color\" ()\n$endif\n\
             $ifndef A\nshader \"z\" \"one_color\" ()\n$else\n$ifdef B\n$endif\nshader \"w\" \"one_color\" ()\n$endif\n",
        )
        .unwrap();
        let mut names: Vec<&String> = s.shaders.keys().collect();
        names.sort();
        assert_eq!(names, vec!["w", "x"]);
        assert_eq!(
            read("$ifdef A\n").unwrap_err().kind,
            LxsErrorKind::UnclosedBlock
        );
        assert_eq!(read("$endif").unwrap_err().kind, LxsErrorKind::UnmatchedEnd);
    }

    #[test]
    fn standard_includes_and_declarations_are_noted_not_read() {
        let s = read(
            "$include \"export_multi.mdl\"\n$include <base.mi>\n$include \"base.mi\"\n\
             declare shader color \"x\" (color \"c\") version 1 end declare\nverbose on\n",
        )
        .unwrap();
        assert_eq!(s.warnings.len(), 3);
        assert_eq!(s.warnings[2].loc.line, 3);
        let e = read("$include \"missing.mi\"").unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::MissingInclude);
    }

    #[test]
    fn unknown_statements_and_budget() {
        let e = read("shader \"a\" \"one_color\" ()\nfrobnicate").unwrap_err();
        assert_eq!((e.kind, e.loc.line), (LxsErrorKind::UnknownStatement, 2));
        let opts = ParseOptions {
            max_total_bytes: 4,
            ..ParseOptions::default()
        };
        let e = read_str("verbose on", "t.mi", &opts).unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::InputTooLarge);
    }
}
