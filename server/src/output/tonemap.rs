//! Tonemapping chosen per request: the `kernel` and kernel parameters of image outputs
//! (preview.png, image.png) given as query parameters with LuxRender's film parameter names,
//! validated, folded into a stable ETag component, and applied over the scene's own settings
//! without touching the job.
//!
//! Missing parameters keep the scene's values when the requested kernel is the scene's; when
//! another kernel is requested its parameters start from LuxRender's defaults. The output
//! `gamma` always defaults to the scene's.

use crate::error::{Result, ServerError};
use luxfarm::tonemap::{Kernel, TonemapParams};

/// One tonemapping query parameter: its name, the kernel it belongs to (None: every kernel),
/// the accepted range and its field of [`TonemapParams`].
pub struct ParamSpec {
    pub name: &'static str,
    pub kernel: Option<Kernel>,
    /// Lower bound, excluded when `min_open`.
    pub min: f64,
    pub min_open: bool,
    pub max: f64,
    read: fn(&TonemapParams) -> f32,
    write: fn(&mut TonemapParams, f32),
}

/// Strictly positive, bounded so that f32 arithmetic stays finite.
const POSITIVE: (f64, bool, f64) = (0.0, true, 1e6);

/// A [`ParamSpec`] for the field of [`TonemapParams`] named like the query parameter.
macro_rules! param {
    ($field:ident, $kernel:expr, $range:expr) => {
        ParamSpec {
            name: stringify!($field),
            kernel: $kernel,
            min: $range.0,
            min_open: $range.1,
            max: $range.2,
            read: |p| p.$field,
            write: |p, v| p.$field = v,
        }
    };
}

/// The tonemapping parameters, in query and ETag order.
pub const PARAMS: [ParamSpec; 9] = [
    param!(reinhard_prescale, Some(Kernel::Reinhard), POSITIVE),
    param!(
        reinhard_postscale,
        Some(Kernel::Reinhard),
        (0.0, false, 1e6)
    ),
    param!(reinhard_burn, Some(Kernel::Reinhard), POSITIVE),
    param!(linear_sensitivity, Some(Kernel::Linear), POSITIVE),
    param!(linear_exposure, Some(Kernel::Linear), POSITIVE),
    param!(linear_fstop, Some(Kernel::Linear), (0.0, true, 1e3)),
    param!(linear_gamma, Some(Kernel::Linear), (0.0, true, 10.0)),
    param!(contrast_ywa, Some(Kernel::Contrast), POSITIVE),
    param!(gamma, None, (0.0, true, 10.0)),
];

impl ParamSpec {
    /// The parameter's value in `p`.
    pub fn get(&self, p: &TonemapParams) -> f32 {
        (self.read)(p)
    }

    fn set(&self, p: &mut TonemapParams, v: f32) {
        (self.write)(p, v)
    }

    /// Parses and range-checks a query value; errors name the parameter.
    fn parse(&self, text: &str) -> Result<f32> {
        let v: f64 = text.trim().parse().map_err(|_| {
            ServerError::BadRequest(format!("parameter {}: not a number: {text:?}", self.name))
        })?;
        let above_min = if self.min_open {
            v > self.min
        } else {
            v >= self.min
        };
        if !v.is_finite() || !above_min || v > self.max {
            let low = if self.min_open { ">" } else { ">=" };
            return Err(ServerError::BadRequest(format!(
                "parameter {}: {text} is out of range (must be {low} {} and <= {})",
                self.name, self.min, self.max
            )));
        }
        Ok(v as f32)
    }
}

/// A validated tonemapping request: an optional kernel and the parameters given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TonemapOverride {
    pub kernel: Option<Kernel>,
    /// (index into [`PARAMS`], value), in [`PARAMS`] order.
    values: Vec<(usize, f32)>,
}

impl TonemapOverride {
    /// Validates a kernel name and `(parameter name, text)` pairs (absent ones as None).
    pub fn parse<'a>(
        kernel: Option<&str>,
        params: impl IntoIterator<Item = (&'a str, Option<&'a str>)>,
    ) -> Result<TonemapOverride> {
        let kernel = match kernel.map(str::trim).filter(|k| !k.is_empty()) {
            None => None,
            // falsecolors needs its luminance range (false_min, false_max), which only the
            // scene's Film gives: a scene in false colours is previewed in them by default.
            Some(k) => Some(
                Kernel::from_name(k)
                    .filter(|&k| k != Kernel::FalseColors)
                    .ok_or_else(|| {
                        ServerError::BadRequest(format!(
                            "parameter kernel: unknown kernel {k:?} (reinhard, linear, \
                             contrast, maxwhite or autolinear; falsecolors only from the \
                             scene's Film)"
                        ))
                    })?,
            ),
        };
        let mut values = Vec::new();
        for (name, text) in params {
            let Some(text) = text.filter(|t| !t.trim().is_empty()) else {
                continue;
            };
            let i = PARAMS
                .iter()
                .position(|s| s.name == name)
                .ok_or_else(|| ServerError::BadRequest(format!("unknown parameter {name:?}")))?;
            let spec = &PARAMS[i];
            if let (Some(k), Some(own)) = (kernel, spec.kernel) {
                if k != own {
                    return Err(ServerError::BadRequest(format!(
                        "parameter {name}: belongs to the {} kernel, not {}",
                        own.name(),
                        k.name()
                    )));
                }
            }
            values.push((i, spec.parse(text)?));
        }
        values.sort_by_key(|&(i, _)| i);
        values.dedup_by_key(|&mut (i, _)| i);
        Ok(TonemapOverride { kernel, values })
    }

    /// True when nothing is overridden (the scene's tonemapping).
    pub fn is_empty(&self) -> bool {
        self.kernel.is_none() && self.values.is_empty()
    }

    /// A short stable tag of the request for the ETag: "scene" when empty, else a hash of
    /// the kernel and the exact values.
    pub fn tag(&self) -> String {
        if self.is_empty() {
            return "scene".into();
        }
        let mut canon = self.kernel.map(Kernel::name).unwrap_or("-").to_string();
        for &(i, v) in &self.values {
            canon.push_str(&format!(";{}={:08x}", PARAMS[i].name, v.to_bits()));
        }
        format!("{:016x}", fnv1a(canon.as_bytes()))
    }

    /// The tonemapping to use over the scene's settings `scene`.
    pub fn apply(&self, scene: &TonemapParams) -> TonemapParams {
        let mut p = scene.clone();
        if let Some(k) = self.kernel.filter(|&k| k != scene.kernel) {
            p.kernel = k;
            let defaults = TonemapParams::default();
            for s in PARAMS.iter().filter(|s| s.kernel == Some(k)) {
                s.set(&mut p, s.get(&defaults));
            }
        }
        for &(i, v) in &self.values {
            PARAMS[i].set(&mut p, v);
        }
        p
    }
}

/// FNV-1a, 64 bits: stable across builds (ETags survive a master restart unchanged).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Kernel and parameter values of a tonemapping, as the API shows them.
#[derive(Clone, Debug, PartialEq, serde::Serialize, utoipa::ToSchema)]
pub struct TonemapSettings {
    /// reinhard, linear, contrast, maxwhite or autolinear
    pub kernel: String,
    pub reinhard_prescale: f32,
    pub reinhard_postscale: f32,
    pub reinhard_burn: f32,
    pub linear_sensitivity: f32,
    pub linear_exposure: f32,
    pub linear_fstop: f32,
    pub linear_gamma: f32,
    pub contrast_ywa: f32,
    /// Output gamma.
    pub gamma: f32,
}

impl From<&TonemapParams> for TonemapSettings {
    fn from(p: &TonemapParams) -> TonemapSettings {
        TonemapSettings {
            kernel: p.kernel.name().into(),
            reinhard_prescale: p.reinhard_prescale,
            reinhard_postscale: p.reinhard_postscale,
            reinhard_burn: p.reinhard_burn,
            linear_sensitivity: p.linear_sensitivity,
            linear_exposure: p.linear_exposure,
            linear_fstop: p.linear_fstop,
            linear_gamma: p.linear_gamma,
            contrast_ywa: p.contrast_ywa,
            gamma: p.gamma,
        }
    }
}

/// A job's tonemapping: the scene's settings and LuxRender's defaults (the starting values of
/// a kernel other than the scene's).
#[derive(Clone, Debug, serde::Serialize, utoipa::ToSchema)]
pub struct TonemapView {
    pub scene: TonemapSettings,
    pub defaults: TonemapSettings,
}

impl TonemapView {
    pub fn new(scene: &TonemapParams) -> TonemapView {
        TonemapView {
            scene: scene.into(),
            defaults: TonemapSettings {
                gamma: scene.gamma,
                ..(&TonemapParams::default()).into()
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(
        kernel: Option<&str>,
        pairs: &[(&'static str, &'static str)],
    ) -> Result<TonemapOverride> {
        TonemapOverride::parse(kernel, pairs.iter().map(|&(n, v)| (n, Some(v))))
    }

    fn detail(r: Result<TonemapOverride>) -> String {
        match r {
            Err(ServerError::BadRequest(d)) => d,
            other => panic!("expected a bad request, got {other:?}"),
        }
    }

    #[test]
    fn missing_parameters_keep_the_scene_values_for_the_scene_kernel() {
        let scene = TonemapParams {
            kernel: Kernel::Linear,
            linear_exposure: 0.25,
            linear_fstop: 4.0,
            gamma: 1.8,
            ..TonemapParams::default()
        };
        let p = parse(Some("linear"), &[("linear_fstop", "8")])
            .unwrap()
            .apply(&scene);
        assert_eq!(p.kernel, Kernel::Linear);
        assert_eq!(p.linear_exposure, 0.25);
        assert_eq!(p.linear_fstop, 8.0);
        assert_eq!(p.gamma, 1.8);
    }

    #[test]
    fn another_kernel_starts_from_luxrender_defaults() {
        let scene = TonemapParams {
            kernel: Kernel::AutoLinear,
            linear_exposure: 0.25,
            reinhard_burn: 2.0,
            gamma: 1.8,
            ..TonemapParams::default()
        };
        let p = parse(Some("linear"), &[]).unwrap().apply(&scene);
        assert_eq!(p.kernel, Kernel::Linear);
        assert_eq!(p.linear_exposure, 1.0);
        assert_eq!(p.linear_sensitivity, 50.0);
        assert_eq!(p.linear_fstop, 2.8);
        assert_eq!(p.gamma, 1.8, "the output gamma stays the scene's");
        assert_eq!(p.reinhard_burn, 2.0, "other kernels' values are untouched");
        let p = parse(None, &[]).unwrap().apply(&scene);
        assert_eq!(p, scene);
    }

    #[test]
    fn bad_values_name_the_parameter() {
        assert!(detail(parse(Some("filmic"), &[])).contains("kernel"));
        assert!(detail(parse(Some("falsecolors"), &[])).contains("scene's Film"));
        for (name, value) in [
            ("linear_exposure", "NaN"),
            ("linear_exposure", "inf"),
            ("linear_exposure", "0"),
            ("linear_fstop", "-2"),
            ("gamma", "11"),
            ("reinhard_burn", "abc"),
        ] {
            let d = detail(parse(None, &[(name, value)]));
            assert!(d.contains(name), "{name}={value}: {d}");
        }
        assert!(parse(None, &[("reinhard_postscale", "0")]).is_ok());
        assert!(detail(parse(None, &[("exposure", "1")])).contains("exposure"));
        let d = detail(parse(Some("reinhard"), &[("linear_exposure", "1")]));
        assert!(
            d.contains("linear_exposure") && d.contains("linear kernel"),
            "{d}"
        );
        assert!(parse(Some("reinhard"), &[("gamma", "2")]).is_ok());
    }

    #[test]
    fn tag_changes_with_every_setting_and_only_then() {
        let a = parse(Some("linear"), &[("linear_exposure", "2")]).unwrap();
        let b = parse(Some("linear"), &[("linear_exposure", "2.0")]).unwrap();
        let c = parse(Some("linear"), &[("linear_exposure", "3")]).unwrap();
        let d = parse(Some("linear"), &[("linear_exposure", "2"), ("gamma", "2")]).unwrap();
        let e = parse(None, &[("linear_exposure", "2")]).unwrap();
        assert_eq!(a.tag(), b.tag());
        for other in [&c, &d, &e] {
            assert_ne!(a.tag(), other.tag(), "{other:?}");
        }
        assert_eq!(parse(None, &[]).unwrap().tag(), "scene");
    }

    #[test]
    fn every_param_reads_and_writes_its_own_field() {
        let mut p = TonemapParams::default();
        for (i, s) in PARAMS.iter().enumerate() {
            s.set(&mut p, 100.0 + i as f32);
        }
        for (i, s) in PARAMS.iter().enumerate() {
            assert_eq!(s.get(&p), 100.0 + i as f32, "{}", s.name);
        }
    }
}
