//! The FLM v0 header: resolution, buffer groups and configurations, and LuxRender's film
//! parameters by their `luxComponentParameters` ids; conversion to and from `FilmParams`.

use super::imaging::{ClampMethod, FalseMethod, FalseScale, Flavour, GroupParams, Kernel};
use super::{BufferType, FilmError, FilmParams};
use std::io::{Read, Write};

pub const FLM_MAGIC: u32 = 0xCEBC_D816;
pub const FLM_VERSION: i32 = 0;
/// Refuse headers with more light groups, buffer configurations or parameters than this.
pub const MAX_GROUPS: u32 = 1024;
pub const MAX_BUFFERS: u32 = 16;
pub const MAX_PARAMS: u32 = 1 << 16;
pub const MAX_STRING: u32 = 1 << 16;

/// LuxRender's parameter ids (`luxComponentParameters`) used in FLM headers.
pub mod id {
    pub const TONEMAPKERNEL: i32 = 0;
    pub const REINHARD_PRESCALE: i32 = 1;
    pub const REINHARD_POSTSCALE: i32 = 2;
    pub const REINHARD_BURN: i32 = 3;
    pub const LINEAR_SENSITIVITY: i32 = 4;
    pub const LINEAR_EXPOSURE: i32 = 5;
    pub const LINEAR_FSTOP: i32 = 6;
    pub const LINEAR_GAMMA: i32 = 7;
    pub const CONTRAST_YWA: i32 = 8;
    pub const X_WHITE: i32 = 9;
    pub const Y_WHITE: i32 = 10;
    pub const X_RED: i32 = 11;
    pub const Y_RED: i32 = 12;
    pub const X_GREEN: i32 = 13;
    pub const Y_GREEN: i32 = 14;
    pub const X_BLUE: i32 = 15;
    pub const Y_BLUE: i32 = 16;
    pub const GAMMA: i32 = 17;
    pub const UPDATEBLOOMLAYER: i32 = 18;
    pub const DELETEBLOOMLAYER: i32 = 19;
    pub const BLOOMRADIUS: i32 = 20;
    pub const BLOOMWEIGHT: i32 = 21;
    pub const VIGNETTING_ENABLED: i32 = 22;
    pub const VIGNETTING_SCALE: i32 = 23;
    pub const ABERRATION_ENABLED: i32 = 24;
    pub const ABERRATION_AMOUNT: i32 = 25;
    pub const UPDATEGLARELAYER: i32 = 26;
    pub const DELETEGLARELAYER: i32 = 27;
    pub const GLARE_AMOUNT: i32 = 28;
    pub const GLARE_RADIUS: i32 = 29;
    pub const GLARE_BLADES: i32 = 30;
    pub const HISTOGRAM_ENABLED: i32 = 31;
    pub const CHIU_ENABLED: i32 = 32;
    pub const GREYC_THREADS: i32 = 49;
    pub const LG_COUNT: i32 = 50;
    pub const LG_ENABLE: i32 = 51;
    pub const LG_NAME: i32 = 52;
    pub const LG_SCALE: i32 = 53;
    pub const LG_SCALE_RED: i32 = 54;
    pub const LG_SCALE_BLUE: i32 = 55;
    pub const LG_SCALE_GREEN: i32 = 56;
    pub const LG_TEMPERATURE: i32 = 57;
    pub const GLARE_THRESHOLD: i32 = 61;
    pub const CAMERA_RESPONSE_ENABLED: i32 = 62;
    pub const CAMERA_RESPONSE_FILE: i32 = 63;
    pub const LDR_CLAMP_METHOD: i32 = 64;
    /// The falsecolors kernel's method and colour scale (their ids as values).
    pub const FALSE_METHOD: i32 = 65;
    pub const FALSE_COLORSCALE: i32 = 66;
    /// The falsecolors kernel's luminance range: the Film's `false_max` and `false_min`
    /// (LuxRender's "MaxSat"/"MinSat"; its ids 67 and 68 are read-only image statistics).
    pub const FALSE_MAXSAT: i32 = 69;
    pub const FALSE_MINSAT: i32 = 70;
}

/// LuxRender's defaults of the noise filters (Chiu: ids 32-34, GREYCStoration: 35-49),
/// written as LuxRender writes them; luxfarm does not apply these filters.
const NOISE_DEFAULTS: [(i32, f32); 18] = [
    (32, 0.0),
    (33, 3.0),
    (34, 0.0),
    (35, 0.0),
    (36, 60.0),
    (37, 1.0),
    (38, 0.91),
    (39, 0.3),
    (40, 0.8),
    (41, 1.1),
    (42, 1.0),
    (43, 2.0),
    (44, 0.8),
    (45, 30.0),
    (46, 0.0),
    (47, 0.0),
    (48, 4.0),
    (49, 1.0),
];

/// A parameter value: FLM type 0 (float), 1 (string) or 2 (double).
#[derive(Clone, Debug, PartialEq)]
pub enum FlmValue {
    Float(f32),
    String(Vec<u8>),
    Double(f64),
}

impl FlmValue {
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            FlmValue::Float(v) => Some(f64::from(*v)),
            FlmValue::Double(v) => Some(*v),
            FlmValue::String(_) => None,
        }
    }

    pub fn as_string(&self) -> Option<String> {
        match self {
            FlmValue::String(s) => Some(String::from_utf8_lossy(s).into_owned()),
            _ => None,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct FlmParam {
    pub id: i32,
    pub index: u32,
    pub value: FlmValue,
}

/// The header of an FLM file.
#[derive(Clone, Debug, PartialEq)]
pub struct FlmHeader {
    pub width: u32,
    pub height: u32,
    pub groups: u32,
    pub buffer_types: Vec<BufferType>,
    pub params: Vec<FlmParam>,
}

fn corrupt(context: &'static str) -> impl Fn(std::io::Error) -> FilmError {
    move |source| FilmError::Corrupt { context, source }
}

pub(crate) fn read_u32(r: &mut impl Read, ctx: &'static str) -> Result<u32, FilmError> {
    let mut b = [0u8; 4];
    r.read_exact(&mut b).map_err(corrupt(ctx))?;
    Ok(u32::from_le_bytes(b))
}

pub(crate) fn read_f64(r: &mut impl Read, ctx: &'static str) -> Result<f64, FilmError> {
    let mut b = [0u8; 8];
    r.read_exact(&mut b).map_err(corrupt(ctx))?;
    Ok(f64::from_le_bytes(b))
}

impl FlmHeader {
    /// Reads and checks a header from the decompressed stream. Sizes are checked before
    /// anything is allocated for them.
    pub fn read(r: &mut impl Read) -> Result<FlmHeader, FilmError> {
        let magic = read_u32(r, "magic number")?;
        if magic != FLM_MAGIC {
            return Err(FilmError::BadMagic { found: magic });
        }
        let version = read_u32(r, "version")? as i32;
        if version != FLM_VERSION {
            return Err(FilmError::BadVersion { found: version });
        }
        let width = read_u32(r, "resolution")?;
        let height = read_u32(r, "resolution")?;
        super::check_size(width, height)?;
        let groups = read_u32(r, "buffer group count")?;
        let nbuf = read_u32(r, "buffer count")?;
        check_counts(width, height, groups, nbuf)?;
        let mut buffer_types = Vec::with_capacity(nbuf as usize);
        for i in 0..nbuf {
            let t = read_u32(r, "buffer type")? as i32;
            let ty = BufferType::from_id(t).ok_or_else(|| {
                FilmError::BadHeader(format!("buffer {i} has unknown type {t} (0-3)"))
            })?;
            buffer_types.push(ty);
        }
        let nparams = read_u32(r, "parameter count")?;
        if nparams > MAX_PARAMS {
            return Err(FilmError::BadHeader(format!("{nparams} parameters")));
        }
        let params = (0..nparams)
            .map(|_| read_param(r))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(FlmHeader {
            width,
            height,
            groups,
            buffer_types,
            params,
        })
    }

    /// Writes the header (uncompressed bytes; the caller compresses).
    pub fn write(&self, w: &mut impl Write) -> std::io::Result<()> {
        let mut b = Vec::with_capacity(64 + self.params.len() * 20);
        b.extend_from_slice(&FLM_MAGIC.to_le_bytes());
        b.extend_from_slice(&FLM_VERSION.to_le_bytes());
        for v in [
            self.width,
            self.height,
            self.groups,
            self.buffer_types.len() as u32,
        ] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        for t in &self.buffer_types {
            b.extend_from_slice(&t.id().to_le_bytes());
        }
        b.extend_from_slice(&(self.params.len() as u32).to_le_bytes());
        for p in &self.params {
            let (ty, size): (i32, u32) = match &p.value {
                FlmValue::Float(_) => (0, 4),
                FlmValue::String(s) => (1, s.len() as u32),
                FlmValue::Double(_) => (2, 8),
            };
            b.extend_from_slice(&ty.to_le_bytes());
            b.extend_from_slice(&size.to_le_bytes());
            b.extend_from_slice(&p.id.to_le_bytes());
            b.extend_from_slice(&p.index.to_le_bytes());
            match &p.value {
                FlmValue::Float(v) => b.extend_from_slice(&v.to_le_bytes()),
                FlmValue::String(s) => b.extend_from_slice(s),
                FlmValue::Double(v) => b.extend_from_slice(&v.to_le_bytes()),
            }
        }
        w.write_all(&b)
    }

    /// The numeric value of a parameter.
    pub fn value(&self, id: i32, index: u32) -> Option<f64> {
        self.params
            .iter()
            .rev()
            .find(|p| p.id == id && p.index == index)
            .and_then(|p| p.value.as_f64())
    }

    /// Light group names (`LG_NAME`), "lightgroup #i" when absent.
    pub fn group_names(&self) -> Vec<String> {
        (0..self.groups)
            .map(|i| {
                self.params
                    .iter()
                    .rev()
                    .find(|p| p.id == id::LG_NAME && p.index == i)
                    .and_then(|p| p.value.as_string())
                    .unwrap_or_else(|| format!("lightgroup #{}", i + 1))
            })
            .collect()
    }

    /// Bytes of pixel data that follow the header (sample counts included).
    pub fn data_len(&self) -> u64 {
        let px = u64::from(self.width) * u64::from(self.height);
        u64::from(self.groups) * (8 + self.buffer_types.len() as u64 * px * 20)
    }
}

fn check_counts(width: u32, height: u32, groups: u32, nbuf: u32) -> Result<(), FilmError> {
    if groups == 0 || groups > MAX_GROUPS {
        return Err(FilmError::BadHeader(format!(
            "{groups} buffer groups (1-{MAX_GROUPS})"
        )));
    }
    if nbuf == 0 || nbuf > MAX_BUFFERS {
        return Err(FilmError::BadHeader(format!(
            "{nbuf} buffers (1-{MAX_BUFFERS})"
        )));
    }
    let total = u64::from(width) * u64::from(height) * u64::from(groups) * u64::from(nbuf);
    if total > super::MAX_PIXELS {
        return Err(FilmError::BadHeader(format!(
            "{groups} groups x {nbuf} buffers x {width}x{height} pixels is more than 2^28 pixel buffers"
        )));
    }
    Ok(())
}

fn read_param(r: &mut impl Read) -> Result<FlmParam, FilmError> {
    let ty = read_u32(r, "parameter")? as i32;
    let size = read_u32(r, "parameter")?;
    let pid = read_u32(r, "parameter")? as i32;
    let index = read_u32(r, "parameter")?;
    let value = match (ty, size) {
        (0, 4) => {
            let mut b = [0u8; 4];
            r.read_exact(&mut b).map_err(corrupt("parameter value"))?;
            FlmValue::Float(f32::from_le_bytes(b))
        }
        (2, 8) => FlmValue::Double(read_f64(r, "parameter value")?),
        (1, n) if n <= MAX_STRING => {
            let mut s = vec![0u8; n as usize];
            r.read_exact(&mut s).map_err(corrupt("parameter value"))?;
            FlmValue::String(s)
        }
        (0 | 2, n) => {
            return Err(FilmError::BadHeader(format!(
                "parameter {pid}: type {ty} with size {n} (float 4, double 8)"
            )))
        }
        (1, n) => {
            return Err(FilmError::BadHeader(format!(
                "parameter {pid}: string of {n} bytes"
            )))
        }
        _ => {
            return Err(FilmError::BadHeader(format!(
                "parameter {pid}: unknown type {ty} (0 float, 1 string, 2 double)"
            )))
        }
    };
    Ok(FlmParam {
        id: pid,
        index,
        value,
    })
}

fn float(pid: i32, index: u32, v: f32) -> FlmParam {
    FlmParam {
        id: pid,
        index,
        value: FlmValue::Float(v),
    }
}

fn flag(b: bool) -> f32 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// Parameters luxfarm does not model but carries from a read FLM to a written one
/// (layer delete flags and the noise filter settings; the update flags are bloom's and glare's
/// enable switches).
const CARRIED: [i32; 21] = [
    19, 27, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 44, 45, 46, 47, 48, 49,
];

/// The parameters LuxRender writes, in its order, with the values of `p` and the light group
/// names: LuxRender 1.x's list, or 0.6/0.7's for a film of that flavour. The falsecolors
/// kernel's settings follow LuxRender 1.x's list (LuxRender itself does not write them but
/// takes them from a header by these ids), so that a film tonemaps the same after a round
/// trip through an FLM.
pub fn params_for(p: &FilmParams, groups: &[String]) -> Vec<FlmParam> {
    let legacy = p.tonemap.flavour == Flavour::Lux06;
    let mut v: Vec<FlmParam> = params_1x(p, groups)
        .into_iter()
        .filter(|q| !legacy || !matches!(q.id, 61..=70))
        .collect();
    for q in &mut v {
        if let Some(x) = p
            .flm_extra
            .iter()
            .find(|x| x.id == q.id && x.index == q.index)
        {
            q.value = x.value.clone();
        }
    }
    v
}

fn params_1x(p: &FilmParams, groups: &[String]) -> Vec<FlmParam> {
    let t = &p.tonemap;
    let e = &p.tonemap.effects;
    let cs = &t.colorspace;
    let mut v = vec![
        float(id::TONEMAPKERNEL, 0, t.kernel as i32 as f32),
        float(id::REINHARD_PRESCALE, 0, t.reinhard_prescale),
        float(id::REINHARD_POSTSCALE, 0, t.reinhard_postscale),
        float(id::REINHARD_BURN, 0, t.reinhard_burn),
        float(id::LINEAR_SENSITIVITY, 0, t.linear_sensitivity),
        float(id::LINEAR_EXPOSURE, 0, t.linear_exposure),
        float(id::LINEAR_FSTOP, 0, t.linear_fstop),
        float(id::LINEAR_GAMMA, 0, t.linear_gamma),
        float(id::CONTRAST_YWA, 0, t.contrast_ywa),
        float(id::LDR_CLAMP_METHOD, 0, t.clamp_method as i32 as f32),
        float(id::X_WHITE, 0, cs.white[0]),
        float(id::Y_WHITE, 0, cs.white[1]),
        float(id::X_RED, 0, cs.red[0]),
        float(id::Y_RED, 0, cs.red[1]),
        float(id::X_GREEN, 0, cs.green[0]),
        float(id::Y_GREEN, 0, cs.green[1]),
        float(id::X_BLUE, 0, cs.blue[0]),
        float(id::Y_BLUE, 0, cs.blue[1]),
        float(id::GAMMA, 0, t.gamma),
        float(
            id::CAMERA_RESPONSE_ENABLED,
            0,
            flag(!e.camera_response.is_empty()),
        ),
        FlmParam {
            id: id::CAMERA_RESPONSE_FILE,
            index: 0,
            value: FlmValue::String(e.camera_response.as_bytes().to_vec()),
        },
        // LuxRender computes a bloom (glare) layer when asked to update it and applies it
        // while it exists: an enabled effect is written as an update request.
        float(id::UPDATEBLOOMLAYER, 0, flag(e.bloom_enabled)),
        float(id::DELETEBLOOMLAYER, 0, 0.0),
        float(id::BLOOMRADIUS, 0, e.bloom_radius),
        float(id::BLOOMWEIGHT, 0, e.bloom_weight),
        float(id::VIGNETTING_ENABLED, 0, flag(e.vignetting_enabled)),
        float(id::VIGNETTING_SCALE, 0, e.vignetting_scale),
        float(id::ABERRATION_ENABLED, 0, flag(e.aberration_enabled)),
        float(id::ABERRATION_AMOUNT, 0, e.aberration_amount),
        float(id::UPDATEGLARELAYER, 0, flag(e.glare_enabled)),
        float(id::DELETEGLARELAYER, 0, 0.0),
        float(id::GLARE_AMOUNT, 0, e.glare_amount),
        float(id::GLARE_RADIUS, 0, e.glare_radius),
        float(id::GLARE_BLADES, 0, e.glare_blades as f32),
        float(id::GLARE_THRESHOLD, 0, e.glare_threshold),
    ];
    v.extend(NOISE_DEFAULTS.iter().map(|&(i, x)| float(i, 0, x)));
    v.extend(false_color_params(t));
    for (i, name) in groups.iter().enumerate() {
        let g = t.group(i);
        let i = i as u32;
        v.extend([
            float(id::LG_SCALE, i, g.scale),
            float(id::LG_ENABLE, i, flag(g.enabled)),
            float(id::LG_SCALE_RED, i, g.rgb_scale[0]),
            float(id::LG_SCALE_GREEN, i, g.rgb_scale[1]),
            float(id::LG_SCALE_BLUE, i, g.rgb_scale[2]),
            float(id::LG_TEMPERATURE, i, g.temperature),
            FlmParam {
                id: id::LG_NAME,
                index: i,
                value: FlmValue::String(name.as_bytes().to_vec()),
            },
        ]);
    }
    v
}

/// The falsecolors kernel's method, scale and range (ids 65, 66, 69, 70).
fn false_color_params(t: &super::imaging::TonemapParams) -> [FlmParam; 4] {
    let f = &t.false_colors;
    [
        float(id::FALSE_METHOD, 0, f.method as i32 as f32),
        float(id::FALSE_COLORSCALE, 0, f.scale as i32 as f32),
        float(id::FALSE_MAXSAT, 0, f.max),
        float(id::FALSE_MINSAT, 0, f.min),
    ]
}

impl FilmParams {
    /// Film parameters for a film read from an FLM without its scene: LuxRender's defaults
    /// at the FLM's resolution, then the header's parameters.
    pub fn from_flm(h: &FlmHeader) -> FilmParams {
        let mut p = FilmParams::with_resolution(h.width, h.height);
        p.apply_flm_params(h);
        p
    }

    /// Takes the imaging parameters an FLM header carries (tonemapper, colour space, gamma,
    /// clamp method, light groups), as LuxRender does when it loads a film.
    pub fn apply_flm_params(&mut self, h: &FlmHeader) {
        let t = &mut self.tonemap;
        let get = |pid: i32| h.value(pid, 0);
        let set = |dst: &mut f32, pid: i32| {
            if let Some(v) = get(pid) {
                *dst = v as f32;
            }
        };
        if let Some(k) = get(id::TONEMAPKERNEL) {
            t.kernel = Kernel::from_id(k);
        }
        match get(id::LDR_CLAMP_METHOD) {
            Some(c) => {
                t.clamp_method = ClampMethod::from_id(c);
                t.flavour = Flavour::Lux1;
            }
            // Written by LuxRender 0.6/0.7: its pipeline, and its default clamp ("lum").
            None if !h.params.is_empty() => {
                t.clamp_method = ClampMethod::Lum;
                t.flavour = Flavour::Lux06;
            }
            None => {}
        }
        set(&mut t.reinhard_prescale, id::REINHARD_PRESCALE);
        set(&mut t.reinhard_postscale, id::REINHARD_POSTSCALE);
        set(&mut t.reinhard_burn, id::REINHARD_BURN);
        set(&mut t.linear_sensitivity, id::LINEAR_SENSITIVITY);
        set(&mut t.linear_exposure, id::LINEAR_EXPOSURE);
        set(&mut t.linear_fstop, id::LINEAR_FSTOP);
        set(&mut t.linear_gamma, id::LINEAR_GAMMA);
        set(&mut t.contrast_ywa, id::CONTRAST_YWA);
        let fc = &mut t.false_colors;
        if let Some(m) = get(id::FALSE_METHOD) {
            fc.method = FalseMethod::from_id(m);
        }
        if let Some(c) = get(id::FALSE_COLORSCALE) {
            fc.scale = FalseScale::from_id(c);
        }
        set(&mut fc.max, id::FALSE_MAXSAT);
        set(&mut fc.min, id::FALSE_MINSAT);
        set(&mut t.gamma, id::GAMMA);
        let cs = &mut t.colorspace;
        set(&mut cs.white[0], id::X_WHITE);
        set(&mut cs.white[1], id::Y_WHITE);
        set(&mut cs.red[0], id::X_RED);
        set(&mut cs.red[1], id::Y_RED);
        set(&mut cs.green[0], id::X_GREEN);
        set(&mut cs.green[1], id::Y_GREEN);
        set(&mut cs.blue[0], id::X_BLUE);
        set(&mut cs.blue[1], id::Y_BLUE);
        t.groups = (0..h.groups).map(|i| group_params(h, i)).collect();
        self.apply_effect_params(h);
        self.flm_extra = h
            .params
            .iter()
            .filter(|p| CARRIED.contains(&p.id))
            .cloned()
            .collect();
    }

    fn apply_effect_params(&mut self, h: &FlmHeader) {
        let e = &mut self.tonemap.effects;
        let get = |pid: i32| h.value(pid, 0).map(|v| v as f32);
        e.bloom_enabled = get(id::UPDATEBLOOMLAYER).map_or(e.bloom_enabled, |v| v != 0.0);
        e.glare_enabled = get(id::UPDATEGLARELAYER).map_or(e.glare_enabled, |v| v != 0.0);
        let crf_on = get(id::CAMERA_RESPONSE_ENABLED).map(|v| v != 0.0);
        let crf = h
            .params
            .iter()
            .rev()
            .find(|p| p.id == id::CAMERA_RESPONSE_FILE && p.index == 0)
            .and_then(|p| p.value.as_string());
        match (crf_on, crf) {
            (Some(false), _) => e.camera_response.clear(),
            (_, Some(name)) => e.camera_response = name,
            _ => {}
        }
        e.bloom_radius = get(id::BLOOMRADIUS).unwrap_or(e.bloom_radius);
        e.bloom_weight = get(id::BLOOMWEIGHT).unwrap_or(e.bloom_weight);
        e.vignetting_enabled =
            get(id::VIGNETTING_ENABLED).map_or(e.vignetting_enabled, |v| v != 0.0);
        e.vignetting_scale = get(id::VIGNETTING_SCALE).unwrap_or(e.vignetting_scale);
        e.aberration_enabled =
            get(id::ABERRATION_ENABLED).map_or(e.aberration_enabled, |v| v != 0.0);
        e.aberration_amount = get(id::ABERRATION_AMOUNT).unwrap_or(e.aberration_amount);
        e.glare_amount = get(id::GLARE_AMOUNT).unwrap_or(e.glare_amount);
        e.glare_radius = get(id::GLARE_RADIUS).unwrap_or(e.glare_radius);
        e.glare_blades = get(id::GLARE_BLADES).map_or(e.glare_blades, |v| v.max(0.0) as u32);
        e.glare_threshold = get(id::GLARE_THRESHOLD).unwrap_or(e.glare_threshold);
    }
}

fn group_params(h: &FlmHeader, i: u32) -> GroupParams {
    let d = GroupParams::default();
    let get = |pid: i32, dv: f32| h.value(pid, i).map_or(dv, |v| v as f32);
    GroupParams {
        enabled: get(id::LG_ENABLE, 1.0) != 0.0,
        scale: get(id::LG_SCALE, d.scale),
        rgb_scale: [
            get(id::LG_SCALE_RED, 1.0),
            get(id::LG_SCALE_GREEN, 1.0),
            get(id::LG_SCALE_BLUE, 1.0),
        ],
        temperature: get(id::LG_TEMPERATURE, d.temperature),
    }
}
