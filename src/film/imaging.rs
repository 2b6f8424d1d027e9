//! The Film's imaging settings as plain data: tonemapping kernel and its parameters, colour
//! space, gamma, LDR clamping and light group scales, with LuxRender's defaults, names and ids.
//!
//! They live in the film layer, not in `tonemap`, because the film carries them without
//! interpreting them: the Film statement sets them ([`super::params`]) and FLM headers store
//! and restore them ([`super::flm_header`]). The `tonemap` module reads them to turn film
//! sums into RGB (and re-exports them under its own name), so the import runs one way:
//! tonemap -> film. The image effects' settings ([`Effects`]) live here too; their pixel
//! operations are in [`super::effects`].

/// Tonemapping kernel; the discriminant is LuxRender's id (FLM parameter 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    Reinhard = 0,
    Linear = 1,
    Contrast = 2,
    MaxWhite = 3,
    AutoLinear = 4,
    FalseColors = 5,
}

impl Kernel {
    pub fn from_name(s: &str) -> Option<Kernel> {
        Some(match s {
            "reinhard" => Kernel::Reinhard,
            "linear" => Kernel::Linear,
            "contrast" => Kernel::Contrast,
            "maxwhite" => Kernel::MaxWhite,
            "autolinear" => Kernel::AutoLinear,
            "falsecolors" => Kernel::FalseColors,
            _ => return None,
        })
    }

    /// From the FLM id (a float); LuxRender falls back to autolinear for unknown ids.
    pub fn from_id(id: f64) -> Kernel {
        match id.floor() as i64 {
            0 => Kernel::Reinhard,
            1 => Kernel::Linear,
            2 => Kernel::Contrast,
            3 => Kernel::MaxWhite,
            5 => Kernel::FalseColors,
            _ => Kernel::AutoLinear,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Kernel::Reinhard => "reinhard",
            Kernel::Linear => "linear",
            Kernel::Contrast => "contrast",
            Kernel::MaxWhite => "maxwhite",
            Kernel::AutoLinear => "autolinear",
            Kernel::FalseColors => "falsecolors",
        }
    }
}

/// How the `falsecolors` kernel spreads a luminance in [min, max] over its colour scale
/// (`false_method`); the discriminant is LuxRender's id (FLM parameter 65).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FalseMethod {
    /// The normalised luminance as it is.
    Linear = 0,
    /// `log10(1 + 9 v)`.
    Log = 1,
    /// The cube root of `log10(1 + 9 v)`.
    Log3 = 2,
}

impl FalseMethod {
    pub const ALL: [FalseMethod; 3] = [FalseMethod::Linear, FalseMethod::Log, FalseMethod::Log3];

    pub fn from_name(s: &str) -> Option<FalseMethod> {
        FalseMethod::ALL.into_iter().find(|m| m.name() == s)
    }

    /// From the FLM id (a float); LuxRender uses the linear method for unknown ids.
    pub fn from_id(id: f64) -> FalseMethod {
        FalseMethod::ALL
            .into_iter()
            .find(|&m| m as i64 == id.floor() as i64)
            .unwrap_or(FalseMethod::Linear)
    }

    pub fn name(self) -> &'static str {
        match self {
            FalseMethod::Linear => "linear",
            FalseMethod::Log => "log",
            FalseMethod::Log3 => "log3",
        }
    }
}

/// The `falsecolors` kernel's colour scale (`false_colorscale`); the discriminant is
/// LuxRender's id (FLM parameter 66).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FalseScale {
    /// Dark blue, blue, cyan, green, yellow, orange, red, dark red.
    Std = 0,
    /// Black, blue, green, red, yellow, white.
    Lmk = 1,
    /// Black to red.
    Red = 2,
    /// Black to white.
    White = 3,
    /// Black to a yellow-orange (green at 0.287 of red).
    Yellow = 4,
    /// Black, blue, cyan, green, yellow, red, white.
    Speos = 5,
}

impl FalseScale {
    pub const ALL: [FalseScale; 6] = [
        FalseScale::Std,
        FalseScale::Lmk,
        FalseScale::Red,
        FalseScale::White,
        FalseScale::Yellow,
        FalseScale::Speos,
    ];

    pub fn from_name(s: &str) -> Option<FalseScale> {
        FalseScale::ALL.into_iter().find(|c| c.name() == s)
    }

    /// From the FLM id (a float); LuxRender uses the std scale for unknown ids.
    pub fn from_id(id: f64) -> FalseScale {
        FalseScale::ALL
            .into_iter()
            .find(|&c| c as i64 == id.floor() as i64)
            .unwrap_or(FalseScale::Std)
    }

    pub fn name(self) -> &'static str {
        match self {
            FalseScale::Std => "std",
            FalseScale::Lmk => "lmk",
            FalseScale::Red => "red",
            FalseScale::White => "white",
            FalseScale::Yellow => "yellow",
            FalseScale::Speos => "speos",
        }
    }
}

/// The `falsecolors` kernel's settings: fleximage's `false_method`, `false_colorscale`,
/// `false_max` and `false_min` (LuxRender stores the last two as its "MaxSat"/"MinSat",
/// FLM parameters 69 and 70). `max` and `min` bound the film luminance Y (the Y of the
/// film's XYZ, in the units every kernel receives); LuxRender's defaults are 0 and 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FalseColors {
    pub method: FalseMethod,
    pub scale: FalseScale,
    pub max: f32,
    pub min: f32,
}

impl Default for FalseColors {
    fn default() -> Self {
        FalseColors {
            method: FalseMethod::Linear,
            scale: FalseScale::Std,
            max: 0.0,
            min: 0.0,
        }
    }
}

/// How LDR outputs bring colours above 1 into range (`ldr_clamp_method`); discriminant is
/// LuxRender's id.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClampMethod {
    Lum = 0,
    Hue = 1,
    Cut = 2,
    Darken = 3,
}

impl ClampMethod {
    pub fn from_name(s: &str) -> Option<ClampMethod> {
        Some(match s {
            "lum" => ClampMethod::Lum,
            "hue" => ClampMethod::Hue,
            "cut" => ClampMethod::Cut,
            "darken" => ClampMethod::Darken,
            _ => return None,
        })
    }

    pub fn from_id(id: f64) -> ClampMethod {
        match id.floor() as i64 {
            0 => ClampMethod::Lum,
            1 => ClampMethod::Hue,
            3 => ClampMethod::Darken,
            _ => ClampMethod::Cut,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            ClampMethod::Lum => "lum",
            ClampMethod::Hue => "hue",
            ClampMethod::Cut => "cut",
            ClampMethod::Darken => "darken",
        }
    }
}

/// Chromaticities (x, y) of the white point and the primaries. Default: SMPTE, as LuxRender.
#[derive(Clone, Debug, PartialEq)]
pub struct ColorSpaceParams {
    pub white: [f32; 2],
    pub red: [f32; 2],
    pub green: [f32; 2],
    pub blue: [f32; 2],
}

impl Default for ColorSpaceParams {
    fn default() -> Self {
        ColorSpaceParams {
            white: [0.314275, 0.329411],
            red: [0.63, 0.34],
            green: [0.31, 0.595],
            blue: [0.155, 0.07],
        }
    }
}

/// Per light group imaging settings (LuxRender's group scale, enable, RGB scale, temperature).
#[derive(Clone, Debug, PartialEq)]
pub struct GroupParams {
    pub enabled: bool,
    pub scale: f32,
    pub rgb_scale: [f32; 3],
    /// Colour temperature in kelvin; 0 disables it.
    pub temperature: f32,
}

impl Default for GroupParams {
    fn default() -> Self {
        GroupParams {
            enabled: true,
            scale: 1.0,
            rgb_scale: [1.0; 3],
            temperature: 0.0,
        }
    }
}

/// Which LuxRender generation's imaging pipeline to follow.
///
/// LuxRender 0.6 and 0.7 (FLM headers without the LDR clamp parameter, id 64) computed the
/// Reinhard adaptation luminance as the arithmetic mean of Y and applied the gamma before the
/// LDR clamp; LuxRender 1.x uses the log-average and clamps first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flavour {
    Lux1,
    Lux06,
}

/// Everything the imaging pipeline needs besides the film itself.
#[derive(Clone, Debug, PartialEq)]
pub struct TonemapParams {
    pub kernel: Kernel,
    pub reinhard_prescale: f32,
    pub reinhard_postscale: f32,
    pub reinhard_burn: f32,
    pub linear_sensitivity: f32,
    pub linear_exposure: f32,
    pub linear_fstop: f32,
    pub linear_gamma: f32,
    pub contrast_ywa: f32,
    /// The `falsecolors` kernel's method, colour scale and luminance range.
    pub false_colors: FalseColors,
    /// Output gamma (`gamma`, 2.2).
    pub gamma: f32,
    pub colorspace: ColorSpaceParams,
    pub clamp_method: ClampMethod,
    /// Per group settings by group index; groups beyond the list use the defaults.
    pub groups: Vec<GroupParams>,
    pub flavour: Flavour,
    /// Bloom, glare, vignetting, chromatic aberration and camera response.
    pub effects: Effects,
}

/// The Film's image effects (fleximage's `bloom_*`, `glare_*`, `vignetting_*`,
/// `abberation_*` and `cameraresponse`), with LuxRender's defaults; `tonemap` applies them in
/// LuxRender's order through [`super::effects`].
#[derive(Clone, Debug, PartialEq)]
pub struct Effects {
    pub bloom_enabled: bool,
    pub bloom_radius: f32,
    pub bloom_weight: f32,
    pub glare_enabled: bool,
    pub glare_amount: f32,
    pub glare_radius: f32,
    pub glare_blades: u32,
    pub glare_threshold: f32,
    pub vignetting_enabled: bool,
    pub vignetting_scale: f32,
    pub aberration_enabled: bool,
    pub aberration_amount: f32,
    /// `cameraresponse`: a built-in preset name or a CRF file (empty: none).
    pub camera_response: String,
    /// The loaded response curves (loaded with the scene's files: [`Effects::load_response`]).
    pub response: Option<std::sync::Arc<super::response::CameraResponse>>,
}

impl Default for Effects {
    fn default() -> Self {
        Effects {
            bloom_enabled: false,
            bloom_radius: 0.07,
            bloom_weight: 0.25,
            glare_enabled: false,
            glare_amount: 0.03,
            glare_radius: 0.03,
            glare_blades: 3,
            glare_threshold: 0.5,
            vignetting_enabled: false,
            vignetting_scale: 0.4,
            aberration_enabled: false,
            aberration_amount: 0.005,
            camera_response: String::new(),
            response: None,
        }
    }
}

impl Effects {
    /// Whether bloom changes the image.
    pub fn bloom_applies(&self) -> bool {
        self.bloom_enabled && self.bloom_radius > 0.0 && self.bloom_weight > 0.0
    }

    /// Whether glare changes the image.
    pub fn glare_applies(&self) -> bool {
        self.glare_enabled
            && self.glare_radius > 0.0
            && self.glare_amount > 0.0
            && self.glare_blades > 0
    }

    /// Whether vignetting changes the image.
    pub fn vignetting_applies(&self) -> bool {
        self.vignetting_enabled && self.vignetting_scale != 0.0
    }

    /// Resolves `cameraresponse`: a built-in preset, else a file through the scene's files
    /// (nothing when none is set; see [`super::response`]).
    pub fn load_response(&mut self, files: &crate::fileio::SceneFiles) -> Result<(), String> {
        let crf = super::response::CameraResponse::resolve(files, &self.camera_response)?;
        self.response = crf.map(std::sync::Arc::new);
        Ok(())
    }

    /// Whether chromatic aberration changes the image.
    pub fn aberration_applies(&self) -> bool {
        self.aberration_enabled && self.aberration_amount > 0.0
    }
}

impl Default for TonemapParams {
    /// LuxRender 1.x defaults of the fleximage film.
    fn default() -> Self {
        TonemapParams {
            kernel: Kernel::AutoLinear,
            reinhard_prescale: 1.0,
            reinhard_postscale: 1.0,
            reinhard_burn: 6.0,
            linear_sensitivity: 50.0,
            linear_exposure: 1.0,
            linear_fstop: 2.8,
            linear_gamma: 1.0,
            contrast_ywa: 1.0,
            false_colors: FalseColors::default(),
            gamma: 2.2,
            colorspace: ColorSpaceParams::default(),
            clamp_method: ClampMethod::Cut,
            groups: Vec::new(),
            flavour: Flavour::Lux1,
            effects: Effects::default(),
        }
    }
}

impl TonemapParams {
    /// The settings of a group (defaults when not given).
    pub fn group(&self, i: usize) -> GroupParams {
        self.groups.get(i).cloned().unwrap_or_default()
    }
}
