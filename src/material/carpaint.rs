//! `carpaint`: `name` picks one of LuxRender's measured presets (`ford f8`, `polaris silber`,
//! `opel titan`, `bmw339`, `2k acrylack` (also spelled `2k acrylic`), `white`, `blue`,
//! `blue matte`; unknown names fall back
//! to `ford f8` with a warning); without a name `Kd`, `Ks1`–`Ks3`, `R1`–`R3`, `M1`–`M3` are
//! read, defaulting to `ford f8`. `Ka` (0) and `d` (0) give the coating absorption. See
//! [`super::bxdf::carpaint`] for the model.

use super::bsdf::Lobes;
use super::bxdf::avg;
use super::bxdf::carpaint::{CarPaintLobes, PaintLayer};
use super::bxdf::schlick::SchlickDist;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, ColorTex, FloatTex};

/// (name, kd, ks1, ks2, ks3, [r1, r2, r3], [m1, m2, m3]) — LuxRender's car paint data.
type Preset = (
    &'static str,
    [f32; 3],
    [f32; 3],
    [f32; 3],
    [f32; 3],
    [f32; 3],
    [f32; 3],
);

#[rustfmt::skip]
const PRESETS: [Preset; 8] = [
    ("ford f8", [0.0012, 0.0015, 0.0018], [0.0049, 0.0076, 0.0120], [0.0100, 0.0130, 0.0180],
        [0.0070, 0.0065, 0.0077], [0.1500, 0.0870, 0.9000], [0.3200, 0.1100, 0.0130]),
    ("polaris silber", [0.0550, 0.0630, 0.0710], [0.0650, 0.0820, 0.0880], [0.1100, 0.1100, 0.1300],
        [0.0080, 0.0130, 0.0150], [1.0000, 0.9200, 0.9000], [0.3800, 0.1700, 0.0130]),
    ("opel titan", [0.0110, 0.0130, 0.0150], [0.0570, 0.0660, 0.0780], [0.1100, 0.1200, 0.1300],
        [0.0095, 0.0140, 0.0160], [0.8500, 0.8600, 0.9000], [0.3800, 0.1700, 0.0140]),
    ("bmw339", [0.0120, 0.0150, 0.0160], [0.0620, 0.0760, 0.0800], [0.1100, 0.1200, 0.1200],
        [0.0083, 0.0150, 0.0160], [0.9200, 0.8700, 0.9000], [0.3900, 0.1700, 0.0130]),
    ("2k acrylack", [0.4200, 0.3200, 0.1000], [0.0, 0.0, 0.0], [0.0280, 0.0260, 0.0060],
        [0.0170, 0.0075, 0.0041], [1.0000, 0.9000, 0.1700], [0.8800, 0.8000, 0.0150]),
    ("white", [0.6100, 0.6300, 0.5500], [2.6e-6, 0.00031, 3.1e-8], [0.0130, 0.0110, 0.0083],
        [0.0490, 0.0420, 0.0370], [0.0490, 0.4500, 0.1700], [1.0000, 0.1500, 0.0150]),
    ("blue", [0.0079, 0.0230, 0.1000], [0.0011, 0.0015, 0.0019], [0.0250, 0.0300, 0.0430],
        [0.0590, 0.0740, 0.0820], [1.0000, 0.0940, 0.1700], [0.1500, 0.0430, 0.0200]),
    ("blue matte", [0.0099, 0.0360, 0.1200], [0.0032, 0.0045, 0.0059], [0.1800, 0.2300, 0.2800],
        [0.0400, 0.0490, 0.0510], [1.0000, 0.0460, 0.1700], [0.1600, 0.0750, 0.0340]),
];

#[derive(Debug)]
pub struct CarPaint {
    pub kd: ColorTex,
    pub ka: ColorTex,
    pub depth: FloatTex,
    pub ks: [ColorTex; 3],
    pub r: [FloatTex; 3],
    pub m: [FloatTex; 3],
}

impl CarPaint {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<CarPaint, MaterialError> {
        let p = &e.params;
        let name = p.string_or("name", "").to_string();
        let ka = b.textures.color_param(p, "Ka", Rgb::BLACK)?;
        let depth = b.textures.float_param(p, "d", 0.0)?;
        let c = |a: [f32; 3]| ColorTex::constant(Rgb::from_array(a));
        if !name.is_empty() {
            // The scene-format page spells the acrylic paint "2k acrylic".
            let key = if name == "2k acrylic" {
                "2k acrylack"
            } else {
                name.as_str()
            };
            let preset = match PRESETS.iter().find(|x| x.0 == key) {
                Some(x) => x,
                None => {
                    b.warn(
                        &param_loc(p, "name", &e.loc),
                        format!("car paint \"{name}\" not found, using \"ford f8\""),
                    );
                    &PRESETS[0]
                }
            };
            let (_, kd, k1, k2, k3, r, m) = *preset;
            return Ok(CarPaint {
                kd: c(kd),
                ka,
                depth,
                ks: [c(k1), c(k2), c(k3)],
                r: r.map(FloatTex::constant),
                m: m.map(FloatTex::constant),
            });
        }
        let (_, kd, k1, k2, k3, r, m) = PRESETS[0];
        let t = &mut b.textures;
        Ok(CarPaint {
            kd: t.color_param(p, "Kd", Rgb::from_array(kd))?,
            ka,
            depth,
            ks: [
                t.color_param(p, "Ks1", Rgb::from_array(k1))?,
                t.color_param(p, "Ks2", Rgb::from_array(k2))?,
                t.color_param(p, "Ks3", Rgb::from_array(k3))?,
            ],
            r: [
                t.float_param(p, "R1", r[0])?,
                t.float_param(p, "R2", r[1])?,
                t.float_param(p, "R3", r[2])?,
            ],
            m: [
                t.float_param(p, "M1", m[0])?,
                t.float_param(p, "M2", m[1])?,
                t.float_param(p, "M3", m[2])?,
            ],
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let mut layers = [None; 3];
        for (i, slot) in layers.iter_mut().enumerate() {
            let ks = clamp(self.ks[i].eval(si));
            let m = self.m[i].eval(si);
            if avg(ks) > 0.0 && m > 0.0 {
                *slot = Some(PaintLayer {
                    ks,
                    r0: self.r[i].eval(si).clamp(0.0, 1.0),
                    dist: SchlickDist {
                        roughness: m * m,
                        anisotropy: 0.0,
                    },
                });
            }
        }
        Lobes::CarPaint(CarPaintLobes {
            kd: clamp(self.kd.eval(si)),
            ka: clamp(self.ka.eval(si)),
            depth: self.depth.eval(si).max(0.0),
            layers,
        })
    }
}
