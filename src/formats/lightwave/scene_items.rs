//! The LWSC lines about items: those that add an object, light, camera or bone, and those
//! that describe the item added last (parent, pivot, motion channels, the light's and the
//! camera's own keywords). `scene.rs` reads the file and hands each line here first; what is
//! not an item's line goes back to it as a global or an unknown keyword.

use super::envelope::Animated;
use super::items::{
    item_id, CameraItem, ItemCommon, LightItem, LightKind, ObjectItem, ObjectSource, TYPE_CAMERA,
    TYPE_LIGHT, TYPE_OBJECT,
};
use super::scene::{err, size, Current, Reader};
use super::text::{hex_id, integer, number, Line};
use crate::lxs::{Loc, LxsError, LxsErrorKind};
use glam::DVec3;

impl Reader<'_> {
    /// An item number for a new item: the hex id written after the keyword (LWSC 4+), else
    /// the ordinal. Returns the id and how many tokens it took.
    fn new_id(&self, kind: u32, ordinal: usize, t: &[&str], at: usize) -> (u32, usize) {
        if self.scene.globals.version >= 4 {
            if let Some(tok) = t.get(at) {
                if tok.len() == 8 {
                    if let Ok(id) = u32::from_str_radix(tok, 16) {
                        if id >> 28 == kind {
                            return (id, 1);
                        }
                    }
                }
            }
        }
        (item_id(kind, ordinal), 0)
    }

    fn add_object(&mut self, common: ItemCommon, source: ObjectSource) {
        self.scene.objects.push(ObjectItem {
            common,
            source,
            dissolve: Animated::Const(0.0),
            unseen_by_camera: false,
            unseen_by_rays: false,
        });
        self.current = Current::Object(self.scene.objects.len() - 1);
        self.motion = Current::None;
    }

    /// The common part of the current item, or an error naming the keyword.
    fn common(&mut self, kw: &str, loc: &Loc) -> Result<Option<&mut ItemCommon>, LxsError> {
        Ok(match self.current {
            Current::Object(i) => Some(&mut self.scene.objects[i].common),
            Current::Light(i) => Some(&mut self.scene.lights[i].common),
            Current::Camera(i) => Some(&mut self.scene.cameras[i].common),
            Current::Bone => None,
            Current::None => {
                return Err(err(
                    LxsErrorKind::WrongBlock,
                    loc.clone(),
                    format!("{kw} before any item (LoadObjectLayer, AddLight, AddCamera)"),
                ))
            }
        })
    }

    /// Statements that add items or describe the current one. Returns whether `kw` was one.
    pub(super) fn item_statement(
        &mut self,
        kw: &str,
        t: &[&str],
        line: &Line,
    ) -> Result<bool, LxsError> {
        let loc = self.cur.loc(line);
        match kw {
            "LoadObjectLayer" | "LoadObject" => {
                let ordinal = self.scene.objects.len();
                let (layer, at) = if kw == "LoadObjectLayer" {
                    let n = integer(t.get(1), "LoadObjectLayer layer", &loc)?;
                    let n = u32::try_from(n).ok().filter(|n| *n >= 1).ok_or_else(|| {
                        err(
                            LxsErrorKind::InvalidValue,
                            loc.clone(),
                            format!("LoadObjectLayer: layer {n} (layers count from 1)"),
                        )
                    })?;
                    (Some(n), 2)
                } else {
                    (None, 1)
                };
                let (id, used) = self.new_id(TYPE_OBJECT, ordinal, t, at);
                let path = line.rest_after(at + used).to_string();
                if path.is_empty() {
                    return Err(err(
                        LxsErrorKind::WrongValueCount,
                        loc,
                        format!("{kw}: the object file name is missing"),
                    ));
                }
                let name = path
                    .rsplit(['/', '\\', ':'])
                    .next()
                    .unwrap_or(&path)
                    .to_string();
                self.add_object(
                    ItemCommon::new(id, name, loc),
                    ObjectSource::File { path, layer },
                );
            }
            "AddNullObject" => {
                let ordinal = self.scene.objects.len();
                let (id, used) = self.new_id(TYPE_OBJECT, ordinal, t, 1);
                let name = line.rest_after(1 + used).to_string();
                self.add_object(ItemCommon::new(id, name, loc), ObjectSource::Null);
            }
            "AddLight" => {
                let (id, _) = self.new_id(TYPE_LIGHT, self.scene.lights.len(), t, 1);
                self.scene.lights.push(LightItem {
                    common: ItemCommon::new(
                        id,
                        format!("Light {}", self.scene.lights.len() + 1),
                        loc,
                    ),
                    color: [
                        Animated::Const(1.0),
                        Animated::Const(1.0),
                        Animated::Const(1.0),
                    ],
                    intensity: Animated::Const(1.0),
                    kind: (LightKind::Distant, None),
                    falloff: (0, None),
                    range: Animated::Const(1.0),
                    cone_deg: Animated::Const(30.0),
                    edge_deg: Animated::Const(5.0),
                });
                self.current = Current::Light(self.scene.lights.len() - 1);
                self.motion = Current::None;
            }
            "AddCamera" => {
                let (id, _) = self.new_id(TYPE_CAMERA, self.scene.cameras.len(), t, 1);
                self.scene.cameras.push(CameraItem {
                    common: ItemCommon::new(
                        id,
                        format!("Camera {}", self.scene.cameras.len() + 1),
                        loc,
                    ),
                    zoom: Animated::Const(3.2),
                    frame_size: None,
                    multiplier: 1.0,
                    pixel_aspect: 1.0,
                    motion_blur: 0,
                    blur_length: Animated::Const(0.5),
                    depth_of_field: false,
                    focal_distance: Animated::Const(1.0),
                    fstop: Animated::Const(4.0),
                    aperture_height: 0.015,
                    limited_region: (0, None),
                    region: [0.0, 1.0, 0.0, 1.0],
                    use_global_resolution: false,
                    use_global_blur: false,
                    handler: None,
                });
                self.current = Current::Camera(self.scene.cameras.len() - 1);
                self.motion = Current::None;
            }
            "AddBone" | "AddBones" => {
                self.warn_once(
                    "bones",
                    loc,
                    "bones are not supported: objects are rendered undeformed",
                );
                self.current = Current::Bone;
                self.motion = Current::None;
            }
            "ObjectMotion" | "LightMotion" | "CameraMotion" | "BoneMotion" => {
                let fits = matches!(
                    (kw, self.current),
                    ("ObjectMotion", Current::Object(_))
                        | ("LightMotion", Current::Light(_))
                        | ("CameraMotion", Current::Camera(_))
                        | ("BoneMotion", Current::Bone)
                );
                if !fits {
                    return Err(err(
                        LxsErrorKind::WrongBlock,
                        loc,
                        format!("{kw} does not follow an item of its kind"),
                    ));
                }
                self.motion = self.current;
            }
            "NumChannels" => {
                let n = integer(t.get(1), "NumChannels", &loc)?;
                if !(0..=9).contains(&n) {
                    self.warn(loc, format!("NumChannels {n}: only channels 0-8 (position, rotation, scale) are used"));
                }
            }
            "Channel" => self.channel(t, line)?,
            "ParentItem" => {
                let id = hex_id(t.get(1), "ParentItem", &loc)?;
                if let Some(c) = self.common(kw, &loc)? {
                    c.parent = Some((id, loc));
                }
            }
            "TargetItem" => {
                let id = hex_id(t.get(1), "TargetItem", &loc)?;
                if let Some(c) = self.common(kw, &loc)? {
                    c.target = Some((id, loc));
                }
            }
            "PivotPosition" | "PivotPoint" => {
                let p = DVec3::new(
                    number(t.get(1), kw, &loc)?,
                    number(t.get(2), kw, &loc)?,
                    number(t.get(3), kw, &loc)?,
                );
                if let Some(c) = self.common(kw, &loc)? {
                    c.pivot = Some(p);
                }
            }
            "PivotRotation" => {
                let any = (1..=3).any(|i| {
                    t.get(i)
                        .and_then(|v| v.parse::<f64>().ok())
                        .is_some_and(|v| v != 0.0)
                });
                if any {
                    self.warn_once(kw, loc, "PivotRotation is not supported: ignored");
                }
            }
            _ => return self.kind_statement(kw, t, line),
        }
        Ok(true)
    }

    /// `Channel n` and the envelope block after it.
    fn channel(&mut self, t: &[&str], line: &Line) -> Result<(), LxsError> {
        let loc = self.cur.loc(line);
        let n = integer(t.get(1), "Channel", &loc)?;
        let open = self.cur.expect_line(line, "the channel's envelope")?;
        if !(open.opens_block() && open.block_name() == "Envelope") {
            return Err(err(
                LxsErrorKind::Syntax,
                self.cur.loc(&open),
                "Channel must be followed by an { Envelope block",
            ));
        }
        let env = self.envelope(&open)?;
        let slot = usize::try_from(n).ok().filter(|&i| i < 9);
        let motion =
            match self.motion {
                Current::Object(i) => Some(&mut self.scene.objects[i].common.motion),
                Current::Light(i) => Some(&mut self.scene.lights[i].common.motion),
                Current::Camera(i) => Some(&mut self.scene.cameras[i].common.motion),
                Current::Bone => return Ok(()),
                Current::None => return Err(err(
                    LxsErrorKind::WrongBlock,
                    loc,
                    "Channel outside an item's motion (ObjectMotion, LightMotion, CameraMotion)",
                )),
            };
        match (slot, motion) {
            (Some(i), Some(m)) => m.channels[i] = Some(Animated::Env(env)),
            _ => self.warn_once(
                "channel",
                loc,
                format!("motion channel {n} skipped (0-8 are position, rotation, scale)"),
            ),
        }
        Ok(())
    }

    /// Object, light and camera keywords.
    fn kind_statement(&mut self, kw: &str, t: &[&str], line: &Line) -> Result<bool, LxsError> {
        let loc = self.cur.loc(line);
        match (kw, self.current) {
            ("ObjectDissolve", Current::Object(i)) => {
                let v = self.animated(line, t.get(1), kw)?;
                self.scene.objects[i].dissolve = v;
            }
            ("UnseenByCamera", Current::Object(i)) => {
                self.scene.objects[i].unseen_by_camera = integer(t.get(1), kw, &loc)? != 0;
            }
            ("UnseenByRays", Current::Object(i)) => {
                self.scene.objects[i].unseen_by_rays = integer(t.get(1), kw, &loc)? != 0;
            }
            ("LightName", Current::Light(i)) => {
                self.scene.lights[i].common.name = line.rest_after(1).to_string();
            }
            ("LightColor", Current::Light(i)) => {
                let r = self.animated(line, t.get(1), kw)?;
                let g = self.animated(line, t.get(2), kw)?;
                let b = self.animated(line, t.get(3), kw)?;
                self.scene.lights[i].color = [r, g, b];
            }
            ("LightIntensity" | "LgtIntensity", Current::Light(i)) => {
                self.scene.lights[i].intensity = self.animated(line, t.get(1), kw)?;
            }
            ("LightType", Current::Light(i)) => {
                let code = integer(t.get(1), kw, &loc)?;
                let kind = LightKind::from_code(code).ok_or_else(|| {
                    err(
                        LxsErrorKind::InvalidValue,
                        loc.clone(),
                        format!("LightType {code} (0-4: distant, point, spot, linear, area)"),
                    )
                })?;
                self.scene.lights[i].kind = (kind, Some(loc));
            }
            ("LightFalloffType", Current::Light(i)) => {
                let code = integer(t.get(1), kw, &loc)?;
                self.scene.lights[i].falloff = (code, Some(loc));
            }
            ("LightRange", Current::Light(i)) => {
                self.scene.lights[i].range = self.animated(line, t.get(1), kw)?;
            }
            ("LightConeAngle", Current::Light(i)) => {
                self.scene.lights[i].cone_deg = self.animated(line, t.get(1), kw)?;
            }
            ("LightEdgeAngle", Current::Light(i)) => {
                self.scene.lights[i].edge_deg = self.animated(line, t.get(1), kw)?;
            }
            _ => return self.camera_statement(kw, t, line),
        }
        Ok(true)
    }

    fn camera_statement(&mut self, kw: &str, t: &[&str], line: &Line) -> Result<bool, LxsError> {
        let loc = self.cur.loc(line);
        let Current::Camera(i) = self.current else {
            return Ok(false);
        };
        match kw {
            "CameraName" => self.scene.cameras[i].common.name = line.rest_after(1).to_string(),
            "ZoomFactor" => self.scene.cameras[i].zoom = self.animated(line, t.get(1), kw)?,
            "FrameSize" | "CustomSize" => {
                self.scene.cameras[i].frame_size = Some(size(t, kw, &loc)?);
            }
            "ResolutionMultiplier" => {
                self.scene.cameras[i].multiplier = number(t.get(1), kw, &loc)?
            }
            "PixelAspect" => self.scene.cameras[i].pixel_aspect = number(t.get(1), kw, &loc)?,
            "MotionBlur" => self.scene.cameras[i].motion_blur = integer(t.get(1), kw, &loc)?,
            "BlurLength" => {
                self.scene.cameras[i].blur_length = self.animated(line, t.get(1), kw)?
            }
            "DepthOfField" => {
                self.scene.cameras[i].depth_of_field = integer(t.get(1), kw, &loc)? != 0
            }
            "FocalDistance" => {
                self.scene.cameras[i].focal_distance = self.animated(line, t.get(1), kw)?
            }
            "LensFStop" => self.scene.cameras[i].fstop = self.animated(line, t.get(1), kw)?,
            "ApertureHeight" => self.scene.cameras[i].aperture_height = number(t.get(1), kw, &loc)?,
            "LimitedRegion" => {
                self.scene.cameras[i].limited_region = (integer(t.get(1), kw, &loc)?, Some(loc));
            }
            "RegionLimits" => {
                let mut r = [0.0; 4];
                for (k, v) in r.iter_mut().enumerate() {
                    *v = number(t.get(k + 1), kw, &loc)?;
                }
                self.scene.cameras[i].region = r;
            }
            "UseGlobalResolution" => {
                self.scene.cameras[i].use_global_resolution = integer(t.get(1), kw, &loc)? != 0;
            }
            "UseGlobalBlur" => {
                self.scene.cameras[i].use_global_blur = integer(t.get(1), kw, &loc)? != 0
            }
            "MaskPosition" => {
                let full = self.scene.cameras[i]
                    .frame_size
                    .map(|(w, h)| format!("0 0 {w} {h}"));
                let written = t.get(1..5).map(|v| v.join(" "));
                if written.is_some() && written != full {
                    self.warn_once(
                        kw,
                        loc,
                        "MaskPosition: the camera mask is not rendered (the whole frame is)",
                    );
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}
