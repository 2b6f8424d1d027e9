//! Reading an LWSC scene file (versions 3, 4 and 5) into [`Scene`].
//!
//! ```text
//! text --Cursor (numbered lines)--> header check (LWSC, version)
//!      --one keyword per line--> globals | the current item (object, light, camera, bone)
//!      --> Scene + located warnings
//! ```
//!
//! Statements about an item follow the line that adds it (`LoadObjectLayer`, `AddNullObject`,
//! `AddLight`, `AddCamera`, `AddBone`) until the next one. Motion channels (`Channel n` and its
//! `{ Envelope` block) belong to the item whose `...Motion` line precedes them. Values written
//! `(envelope)` are followed by their Envelope block. `Plugin ... EndPlugin` data and blocks
//! the importer does not use are skipped; unknown keywords, plug-ins and blocks get one
//! warning per kind. Versions 1 and 2 (LightWave 5 and before) store motion differently and
//! are refused with a clear error. The lines that add and describe items are read in
//! `scene_items.rs`.

use super::envelope::{Animated, Envelope};
use super::items::{Globals, LightKind, Scene};
use super::keywords;
use super::text::{integer, number, tokens, Cursor, Line};
use crate::lxs::{Diagnostic, Loc, LxsError, LxsErrorKind};
use std::collections::HashSet;

/// Which item the statements being read describe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Current {
    None,
    Object(usize),
    Light(usize),
    Camera(usize),
    Bone,
}

/// The scene and its warnings.
pub struct Parsed {
    pub scene: Scene,
    pub warnings: Vec<Diagnostic>,
}

/// Reads the scene text of `file`.
pub fn read(file: &str, text: &str) -> Result<Parsed, LxsError> {
    let mut r = Reader {
        cur: Cursor::new(file, text),
        scene: Scene {
            file: file.to_string(),
            ..Scene::default()
        },
        warnings: Vec::new(),
        warned: HashSet::new(),
        current: Current::None,
        motion: Current::None,
    };
    r.header()?;
    while let Some(line) = r.cur.next_line() {
        r.statement(&line)?;
    }
    Ok(Parsed {
        scene: r.scene,
        warnings: r.warnings,
    })
}

pub(super) struct Reader<'a> {
    pub(super) cur: Cursor<'a>,
    pub(super) scene: Scene,
    warnings: Vec<Diagnostic>,
    /// Kinds already warned about (one warning per kind).
    warned: HashSet<String>,
    pub(super) current: Current,
    /// The item `Channel` blocks belong to (set by `ObjectMotion` etc.).
    pub(super) motion: Current,
}

pub(super) fn err(kind: LxsErrorKind, loc: Loc, msg: impl Into<String>) -> LxsError {
    LxsError::new(kind, loc, msg)
}

impl<'a> Reader<'a> {
    pub(super) fn warn(&mut self, loc: Loc, message: impl Into<String>) {
        self.warnings.push(Diagnostic {
            loc,
            message: message.into(),
        });
    }

    pub(super) fn warn_once(&mut self, kind: &str, loc: Loc, message: impl Into<String>) {
        if self.warned.insert(kind.to_string()) {
            self.warn(loc, message);
        }
    }

    fn header(&mut self) -> Result<(), LxsError> {
        let start = self.cur.end_loc();
        let Some(magic) = self.cur.next_line() else {
            return Err(err(
                LxsErrorKind::Syntax,
                start,
                "empty file: not a LightWave scene",
            ));
        };
        let loc = self.cur.loc(&magic);
        if magic.text.trim() != "LWSC" {
            return Err(err(
                LxsErrorKind::Syntax,
                loc,
                "not a LightWave scene: the first line is not LWSC",
            ));
        }
        let vline = self.cur.expect_line(&magic, "the LWSC version")?;
        let vloc = self.cur.loc(&vline);
        let version = integer(vline.tokens().first(), "LWSC version", &vloc)?;
        match version {
            3..=5 => {}
            1 | 2 => {
                return Err(err(
                    LxsErrorKind::Unsupported,
                    vloc,
                    format!(
                        "LWSC version {version} (LightWave 5 and earlier) is not supported: \
                         open and save the scene in LightWave 6 or later (LWSC 3 to 5)"
                    ),
                ))
            }
            _ => {
                return Err(err(
                    LxsErrorKind::Unsupported,
                    vloc,
                    format!("unknown LWSC version {version} (versions 3 to 5 are read)"),
                ))
            }
        }
        self.scene.globals = Globals {
            version: version as u32,
            ..Globals::default()
        };
        Ok(())
    }

    /// A value that may be `(envelope)`, followed by its block.
    pub(super) fn animated(
        &mut self,
        line: &Line,
        tok: Option<&&str>,
        what: &str,
    ) -> Result<Animated, LxsError> {
        let loc = self.cur.loc(line);
        if tok.is_some_and(|t| *t == "(envelope)") {
            let open = self
                .cur
                .expect_line(line, &format!("the envelope of {what}"))?;
            if !(open.opens_block() && open.block_name() == "Envelope") {
                return Err(err(
                    LxsErrorKind::Syntax,
                    self.cur.loc(&open),
                    format!("{what} (envelope) must be followed by an {{ Envelope block"),
                ));
            }
            return Ok(Animated::Env(self.envelope(&open)?));
        }
        Ok(Animated::Const(number(tok, what, &loc)?))
    }

    pub(super) fn envelope(&mut self, open: &Line) -> Result<Envelope, LxsError> {
        let mut skipped = Vec::new();
        let e = Envelope::read(&mut self.cur, open, &mut skipped)?;
        for (loc, name) in skipped {
            self.warn_once(
                &format!("block {name}"),
                loc,
                format!("{name} (a plug-in channel modifier) skipped: the envelope's keys are used as they are"),
            );
        }
        Ok(e)
    }

    fn statement(&mut self, line: &Line) -> Result<(), LxsError> {
        let loc = self.cur.loc(line);
        if line.opens_block() {
            let name = line.block_name().to_string();
            self.cur.skip_block(line)?;
            if !keywords::IGNORED_BLOCKS.contains(&name.as_str()) {
                self.warn_once(
                    &format!("block {name}"),
                    loc,
                    format!("block {name} skipped"),
                );
            }
            return Ok(());
        }
        let t = line.tokens();
        let kw = t.first().copied().unwrap_or("");
        if self.item_statement(kw, &t, line)? || self.global_statement(kw, &t, line)? {
            return Ok(());
        }
        if kw == "Plugin" {
            return self.plugin(&t, line);
        }
        if let Some((_, what)) = keywords::UNSUPPORTED_WHEN_ON.iter().find(|(k, _)| *k == kw) {
            let on = t
                .get(1)
                .is_some_and(|v| v.parse::<f64>().ok().is_none_or(|x| x != 0.0));
            if on {
                self.warn_once(kw, loc, format!("{kw}: {what} is not rendered by luxfarm"));
            }
            return Ok(());
        }
        if let Some((_, what)) = keywords::UNSUPPORTED.iter().find(|(k, _)| *k == kw) {
            self.warn_once(
                what,
                loc,
                format!("{kw}: {what} are not rendered by luxfarm"),
            );
            return Ok(());
        }
        if keywords::is_ignored(kw) || (self.current == Current::Bone && kw.starts_with("Bone")) {
            return Ok(());
        }
        if ITEM_KEYWORDS.contains(&kw) {
            self.warn_once(
                kw,
                loc,
                format!("{kw} does not apply to the item it follows: skipped"),
            );
        } else {
            self.warn_once(kw, loc, format!("unknown keyword {kw} skipped"));
        }
        Ok(())
    }

    fn plugin(&mut self, t: &[&str], line: &Line) -> Result<(), LxsError> {
        let loc = self.cur.loc(line);
        let class = t.get(1).copied().unwrap_or("");
        let name = t.get(3).copied().unwrap_or("").to_string();
        match (class, self.current) {
            ("LightHandler", Current::Light(i)) => match LightKind::from_handler(&name) {
                Some(kind) => self.scene.lights[i].kind = (kind, Some(loc)),
                None => self.warn_once(
                    &format!("light handler {name}"),
                    loc,
                    format!("light type {name} is not supported: rendered as its LightType"),
                ),
            },
            ("CameraHandler", Current::Camera(i)) => {
                self.scene.cameras[i].handler = Some((name, loc));
            }
            _ => self.warn_once(
                &format!("plugin {class} {name}"),
                loc,
                format!("plug-in {name} ({class}) skipped"),
            ),
        }
        self.cur.skip_plugin(line)
    }

    /// Scene-wide statements. Returns whether `kw` was one.
    fn global_statement(&mut self, kw: &str, t: &[&str], line: &Line) -> Result<bool, LxsError> {
        let loc = self.cur.loc(line);
        let g = &mut self.scene.globals;
        match kw {
            "FirstFrame" => g.first_frame = integer(t.get(1), kw, &loc)?,
            "LastFrame" => g.last_frame = integer(t.get(1), kw, &loc)?,
            "FrameStep" => g.frame_step = integer(t.get(1), kw, &loc)?,
            "CurrentFrame" => g.current_frame = Some(integer(t.get(1), kw, &loc)?),
            "FramesPerSecond" => {
                let fps = number(t.get(1), kw, &loc)?;
                if fps <= 0.0 {
                    return Err(err(
                        LxsErrorKind::InvalidValue,
                        loc,
                        format!("FramesPerSecond {fps} must be positive"),
                    ));
                }
                g.fps = fps;
            }
            "AmbientColor" => g.ambient_color = color(t, kw, &loc)?,
            "AmbientIntensity" => {
                let a = self.animated(line, t.get(1), kw)?;
                self.scene.globals.ambient_intensity = a;
            }
            "EnableRadiosity" => g.radiosity = integer(t.get(1), kw, &loc)? != 0,
            "SolidBackdrop" => g.solid_backdrop = integer(t.get(1), kw, &loc)? != 0,
            "BackdropColor" => g.backdrop_color = color(t, kw, &loc)?,
            "ZenithColor" => g.gradient[0] = color(t, kw, &loc)?,
            "SkyColor" => g.gradient[1] = color(t, kw, &loc)?,
            "GroundColor" => g.gradient[2] = color(t, kw, &loc)?,
            "NadirColor" => g.gradient[3] = color(t, kw, &loc)?,
            "CurrentCamera" => g.current_camera = Some((integer(t.get(1), kw, &loc)?, loc)),
            "GlobalFrameSize" => g.global_frame_size = Some(size(t, kw, &loc)?),
            "GlobalMultiplier" => g.global_multiplier = number(t.get(1), kw, &loc)?,
            "GlobalPixelAspect" => g.global_pixel_aspect = number(t.get(1), kw, &loc)?,
            "GlobalMotionBlur" => g.global_motion_blur = integer(t.get(1), kw, &loc)?,
            "GlobalBlurLength" => {
                let a = self.animated(line, t.get(1), kw)?;
                self.scene.globals.global_blur_length = a;
            }
            "RayRecursionLimit" => g.ray_recursion_limit = integer(t.get(1), kw, &loc)?,
            "DoubleSidedAreaLights" => {
                g.double_sided_area_lights = integer(t.get(1), kw, &loc)? != 0
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// Keywords that belong to one kind of item (object, light, camera).
const ITEM_KEYWORDS: &[&str] = &[
    "ObjectDissolve",
    "UnseenByCamera",
    "UnseenByRays",
    "LightName",
    "LightColor",
    "LightIntensity",
    "LgtIntensity",
    "LightType",
    "LightFalloffType",
    "LightRange",
    "LightConeAngle",
    "LightEdgeAngle",
    "CameraName",
    "ZoomFactor",
    "FrameSize",
    "CustomSize",
    "ResolutionMultiplier",
    "PixelAspect",
    "MotionBlur",
    "BlurLength",
    "DepthOfField",
    "FocalDistance",
    "LensFStop",
    "ApertureHeight",
    "LimitedRegion",
    "RegionLimits",
    "UseGlobalResolution",
    "UseGlobalBlur",
    "MaskPosition",
];

/// `r g b` after the keyword.
fn color(t: &[&str], kw: &str, loc: &Loc) -> Result<[f64; 3], LxsError> {
    Ok([
        number(t.get(1), kw, loc)?,
        number(t.get(2), kw, loc)?,
        number(t.get(3), kw, loc)?,
    ])
}

/// `width height` after the keyword: positive and at most 65536 each.
pub(super) fn size(t: &[&str], kw: &str, loc: &Loc) -> Result<(u32, u32), LxsError> {
    let w = integer(t.get(1), kw, loc)?;
    let h = integer(t.get(2), kw, loc)?;
    let ok = |v: i64| (1..=65536).contains(&v);
    if !ok(w) || !ok(h) {
        return Err(err(
            LxsErrorKind::InvalidValue,
            loc.clone(),
            format!("{kw} {w} {h}: sizes must be 1 to 65536 pixels"),
        ));
    }
    Ok((w as u32, h as u32))
}

/// Whether `head` (the start of a file) looks like an LWSC scene.
pub fn looks_like_lwsc(head: &str) -> bool {
    head.lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .is_some_and(|l| tokens(l).first() == Some(&"LWSC"))
}

#[cfg(test)]
mod tests {
    use super::super::items::ObjectSource;
    use super::*;

    fn parse(text: &str) -> Result<Parsed, LxsError> {
        read("t.lws", text)
    }

    #[test]
    fn versions_one_and_two_are_refused_clearly() {
        for v in [1, 2] {
            let e = parse(&format!("LWSC\n{v}\n\nFirstFrame 1\n"))
                .err()
                .unwrap();
            assert_eq!(e.kind, LxsErrorKind::Unsupported);
            assert_eq!(e.loc.line, 2);
            assert!(e.message.contains("LightWave 6"), "{e}");
        }
        assert!(parse("LWSC\n9\n").is_err());
        assert!(parse("hello\n3\n").is_err());
        assert!(parse("").is_err());
    }

    #[test]
    fn items_ids_and_parents() {
        let text = "LWSC\n5\n\nLoadObjectLayer 2 10000000 Objects/My Box.lwo\nParentItem 10000001\n\
                    AddNullObject 10000001 Handle\nAddLight 20000000\nLightName Key\nLightType 2\n\
                    LightIntensity (envelope)\n{ Envelope\n  1\n  Key 0.5 0 0 0 0 0 0 0 0\n  Behaviors 1 1\n}\n\
                    AddCamera 30000000\nCameraName Cam\nZoomFactor 2\nFrameSize 320 240\n";
        let p = parse(text).unwrap();
        let s = &p.scene;
        assert_eq!(s.objects.len(), 2);
        assert_eq!(
            s.objects[0].source,
            ObjectSource::File {
                path: "Objects/My Box.lwo".into(),
                layer: Some(2)
            }
        );
        assert_eq!(s.objects[0].common.parent.as_ref().unwrap().0, 0x1000_0001);
        assert_eq!(s.objects[1].common.name, "Handle");
        assert_eq!(s.lights[0].common.name, "Key");
        assert_eq!(s.lights[0].kind.0, LightKind::Spot);
        assert_eq!(s.lights[0].intensity.at(3.0), 0.5);
        assert_eq!(s.cameras[0].frame_size, Some((320, 240)));
        assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    }

    #[test]
    fn version_3_numbers_items_in_order() {
        let p = parse(
            "LWSC\n3\nLoadObjectLayer 1 a.lwo\nLoadObjectLayer 1 b c.lwo\nAddLight\nAddCamera\n",
        )
        .unwrap();
        assert_eq!(p.scene.objects[1].common.id, 0x1000_0001);
        assert_eq!(
            p.scene.objects[1].source,
            ObjectSource::File {
                path: "b c.lwo".into(),
                layer: Some(1)
            }
        );
        assert_eq!(p.scene.lights[0].common.id, 0x2000_0000);
        assert_eq!(p.scene.cameras[0].common.id, 0x3000_0000);
    }

    #[test]
    fn channels_go_to_the_motion_owner() {
        let text = "LWSC\n3\nLoadObjectLayer 1 a.lwo\nObjectMotion\nNumChannels 9\nChannel 1\n{ Envelope\n  1\n  Key 2 0 0 0 0 0 0 0 0\n  Behaviors 1 1\n}\n";
        let p = parse(text).unwrap();
        assert_eq!(p.scene.objects[0].common.motion.value(1, 0.0), 2.0);
        let orphan = "LWSC\n3\nChannel 1\n{ Envelope\n  1\n  Key 2 0 0 0 0 0 0 0 0\n}\n";
        let e = parse(orphan).err().unwrap();
        assert_eq!(e.loc.line, 3);
    }

    #[test]
    fn unknown_keywords_plugins_and_blocks_warn_once_per_kind() {
        let text = "LWSC\n4\nFoo 1\nFoo 2\nBar\nPlugin MasterHandler 1 Thing\n{ x {\n}\nEndPlugin\n\
                    Plugin MasterHandler 2 Thing\nEndPlugin\n{ Weird\n  { Inner\n  }\n}\nFogType 1\nFogType 2\nShowObject 1\n";
        let p = parse(text).unwrap();
        let msgs: Vec<String> = p.warnings.iter().map(|w| w.to_string()).collect();
        assert_eq!(msgs.len(), 5, "{msgs:?}");
        assert!(
            msgs[0].starts_with("t.lws:3:1: unknown keyword Foo"),
            "{msgs:?}"
        );
        assert!(msgs[1].contains("Bar"));
        assert!(msgs[2].contains("Thing"));
        assert!(msgs[3].contains("Weird"));
        assert!(msgs[4].contains("fog"));
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse("LWSC\n3\nAddLight\nLightType 9\n").err().unwrap();
        assert_eq!(e.loc.line, 4);
        let e = parse("LWSC\n3\nFramesPerSecond 0\n").err().unwrap();
        assert_eq!(e.loc.line, 3);
        let p = parse("LWSC\n3\nLightIntensity 1\n").unwrap();
        assert!(p.warnings[0]
            .to_string()
            .starts_with("t.lws:3:1: LightIntensity does not apply"));
        let e = parse("LWSC\n3\nAddLight\nLightIntensity (envelope)\nLightType 1\n")
            .err()
            .unwrap();
        assert_eq!(e.loc.line, 5);
    }

    #[test]
    fn detects_lwsc() {
        assert!(looks_like_lwsc("\nLWSC\n5\n"));
        assert!(!looks_like_lwsc("LookAt 0 0 0"));
    }
}
