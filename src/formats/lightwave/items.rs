//! The LightWave scene as read from an LWSC file, before evaluation at a frame: global settings
//! and the items (objects, lights, cameras) with their motion and parameters.
//!
//! ```text
//! scene.rs (reads lines) --fills--> Scene { globals, objects, lights, cameras }
//!   --motion.rs evaluates at a time--> transforms --> camera.rs, lights.rs, the emitter
//! ```
//!
//! Item ids follow the LWSC convention: the high 4 bits give the type (1 object, 2 light,
//! 3 camera, 4 bone; bones are not imported) and the rest the item's number in file order (LWSC 4 and 5 write the id
//! after `LoadObjectLayer`/`AddLight`/`AddCamera`; LWSC 3 leaves it implicit).

use super::envelope::Animated;
use crate::lxs::Loc;
use glam::DVec3;

pub const TYPE_OBJECT: u32 = 1;
pub const TYPE_LIGHT: u32 = 2;
pub const TYPE_CAMERA: u32 = 3;

/// An item id from its type and ordinal.
pub fn item_id(kind: u32, ordinal: usize) -> u32 {
    (kind << 28) | (u32::try_from(ordinal).unwrap_or(0x0FFF_FFFF) & 0x0FFF_FFFF)
}

/// The type nibble of an item id.
pub fn id_type(id: u32) -> u32 {
    id >> 28
}

/// The nine motion channels: x, y, z position, heading, pitch, bank (radians), scale x, y, z.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    pub channels: [Option<Animated>; 9],
}

impl Motion {
    /// Channel `i` at `time`; channels the file does not give hold 0 (position, rotation) or
    /// 1 (scale).
    pub fn value(&self, i: usize, time: f64) -> f64 {
        match self.channels.get(i).and_then(Option::as_ref) {
            Some(a) => a.at(time),
            None if i >= 6 => 1.0,
            None => 0.0,
        }
    }

    pub fn position(&self, time: f64) -> DVec3 {
        DVec3::new(
            self.value(0, time),
            self.value(1, time),
            self.value(2, time),
        )
    }

    pub fn rotation(&self, time: f64) -> DVec3 {
        DVec3::new(
            self.value(3, time),
            self.value(4, time),
            self.value(5, time),
        )
    }

    pub fn scale(&self, time: f64) -> DVec3 {
        DVec3::new(
            self.value(6, time),
            self.value(7, time),
            self.value(8, time),
        )
    }
}

/// What every item has.
#[derive(Clone, Debug, PartialEq)]
pub struct ItemCommon {
    pub id: u32,
    pub name: String,
    /// The line that added the item.
    pub loc: Loc,
    pub motion: Motion,
    /// `ParentItem` id and where it was written.
    pub parent: Option<(u32, Loc)>,
    /// `TargetItem` id: the item turns its +Z towards the target.
    pub target: Option<(u32, Loc)>,
    /// `PivotPosition`; objects without one use their layer's pivot.
    pub pivot: Option<DVec3>,
}

impl ItemCommon {
    pub fn new(id: u32, name: String, loc: Loc) -> ItemCommon {
        ItemCommon {
            id,
            name,
            loc,
            motion: Motion::default(),
            parent: None,
            target: None,
            pivot: None,
        }
    }
}

/// Where an object's geometry comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectSource {
    /// A layer of an object file (`LoadObjectLayer n`, 1-based), or every layer (`LoadObject`).
    File { path: String, layer: Option<u32> },
    /// `AddNullObject`: a transform only.
    Null,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ObjectItem {
    pub common: ItemCommon,
    pub source: ObjectSource,
    /// `ObjectDissolve`: 0 opaque, 1 gone.
    pub dissolve: Animated,
    /// `UnseenByCamera`: as fully dissolved for rendering.
    pub unseen_by_camera: bool,
    /// `UnseenByRays`: not in reflections/refractions (approximated, see the emitter).
    pub unseen_by_rays: bool,
}

/// LightWave light types (`LightType`, or the LWSC 4+ `LightHandler` plug-in name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    Distant,
    Point,
    Spot,
    Linear,
    Area,
}

impl LightKind {
    pub fn from_code(code: i64) -> Option<LightKind> {
        Some(match code {
            0 => LightKind::Distant,
            1 => LightKind::Point,
            2 => LightKind::Spot,
            3 => LightKind::Linear,
            4 => LightKind::Area,
            _ => return None,
        })
    }

    pub fn from_handler(name: &str) -> Option<LightKind> {
        Some(match name {
            "DistantLight" => LightKind::Distant,
            "PointLight" => LightKind::Point,
            "SpotLight" => LightKind::Spot,
            "LinearLight" => LightKind::Linear,
            "AreaLight" => LightKind::Area,
            _ => return None,
        })
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct LightItem {
    pub common: ItemCommon,
    pub color: [Animated; 3],
    pub intensity: Animated,
    /// Type and the line that set it (distant when never set).
    pub kind: (LightKind, Option<Loc>),
    /// `LightFalloffType` (0 none, 1 linear, 2 inverse distance, 3 inverse square).
    pub falloff: (i64, Option<Loc>),
    /// `LightRange`: the falloff's range / nominal distance.
    pub range: Animated,
    /// `LightConeAngle`, `LightEdgeAngle` (degrees).
    pub cone_deg: Animated,
    pub edge_deg: Animated,
}

#[derive(Clone, Debug, PartialEq)]
pub struct CameraItem {
    pub common: ItemCommon,
    pub zoom: Animated,
    /// `FrameSize` (pixels), times `ResolutionMultiplier`.
    pub frame_size: Option<(u32, u32)>,
    pub multiplier: f64,
    pub pixel_aspect: f64,
    /// `MotionBlur` (0 off) and `BlurLength` (fraction of a frame).
    pub motion_blur: i64,
    pub blur_length: Animated,
    pub depth_of_field: bool,
    pub focal_distance: Animated,
    pub fstop: Animated,
    /// `ApertureHeight` (metres): the focal length is zoom × height / 2.
    pub aperture_height: f64,
    /// `LimitedRegion` (0 off) and `RegionLimits x0 x1 y0 y1` (fractions of the frame).
    pub limited_region: (i64, Option<Loc>),
    pub region: [f64; 4],
    pub use_global_resolution: bool,
    pub use_global_blur: bool,
    /// `Plugin CameraHandler n Name` (LWSC 4+): "Perspective" or another projection.
    pub handler: Option<(String, Loc)>,
}

/// Global settings of the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Globals {
    pub version: u32,
    pub first_frame: i64,
    pub last_frame: i64,
    pub frame_step: i64,
    pub current_frame: Option<i64>,
    pub fps: f64,
    pub ambient_color: [f64; 3],
    pub ambient_intensity: Animated,
    pub radiosity: bool,
    pub solid_backdrop: bool,
    pub backdrop_color: [f64; 3],
    /// Zenith, sky, ground, nadir colours of the gradient backdrop.
    pub gradient: [[f64; 3]; 4],
    pub current_camera: Option<(i64, Loc)>,
    pub global_frame_size: Option<(u32, u32)>,
    pub global_multiplier: f64,
    pub global_pixel_aspect: f64,
    pub global_motion_blur: i64,
    pub global_blur_length: Animated,
    pub ray_recursion_limit: i64,
    pub double_sided_area_lights: bool,
}

impl Default for Globals {
    fn default() -> Self {
        Globals {
            version: 3,
            first_frame: 1,
            last_frame: 60,
            frame_step: 1,
            current_frame: None,
            fps: 30.0,
            ambient_color: [1.0; 3],
            ambient_intensity: Animated::Const(0.25),
            radiosity: false,
            solid_backdrop: true,
            backdrop_color: [0.0; 3],
            gradient: [
                [0.0, 0.1569, 0.3137],
                [0.4706, 0.7059, 0.9412],
                [0.1961, 0.1569, 0.1176],
                [0.3922, 0.3137, 0.2353],
            ],
            current_camera: None,
            global_frame_size: None,
            global_multiplier: 1.0,
            global_pixel_aspect: 1.0,
            global_motion_blur: 0,
            global_blur_length: Animated::Const(0.5),
            ray_recursion_limit: 16,
            double_sided_area_lights: false,
        }
    }
}

/// A whole scene file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    pub file: String,
    pub globals: Globals,
    pub objects: Vec<ObjectItem>,
    pub lights: Vec<LightItem>,
    pub cameras: Vec<CameraItem>,
}

impl Scene {
    /// The common part of the item with this id.
    pub fn item(&self, id: u32) -> Option<&ItemCommon> {
        self.objects
            .iter()
            .map(|o| &o.common)
            .chain(self.lights.iter().map(|l| &l.common))
            .chain(self.cameras.iter().map(|c| &c.common))
            .find(|c| c.id == id)
    }

    /// Seconds of a frame number.
    pub fn frame_time(&self, frame: i64) -> f64 {
        frame as f64 / self.globals.fps
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_carry_type_and_number() {
        assert_eq!(item_id(TYPE_LIGHT, 0), 0x2000_0000);
        assert_eq!(item_id(TYPE_OBJECT, 10), 0x1000_000A);
        assert_eq!(id_type(0x3000_0001), TYPE_CAMERA);
    }

    #[test]
    fn missing_channels_hold_defaults() {
        let m = Motion::default();
        assert_eq!(m.position(1.0), DVec3::ZERO);
        assert_eq!(m.scale(1.0), DVec3::ONE);
    }
}
