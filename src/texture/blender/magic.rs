//! `blender_magic`: Blender's magic, nested sines and cosines of the point to `noisedepth`
//! (2) levels with `turbulence` (5; LuxRender 0.x's `turbulance` spelling is accepted),
//! giving a colour.

use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;

#[derive(Debug)]
pub struct Magic {
    pub depth: i32,
    pub turbulence: f32,
}

impl Magic {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let n = self.depth;
        let mut turb = self.turbulence / 5.0;
        let mut x = ((p[0] + p[1] + p[2]) * 5.0).sin();
        let mut y = ((-p[0] + p[1] - p[2]) * 5.0).cos();
        let mut z = -((-p[0] - p[1] + p[2]) * 5.0).cos();
        if n > 0 {
            x *= turb;
            y *= turb;
            z *= turb;
            y = -(x - y + z).cos() * turb;
            if n > 1 {
                x = (x - y - z).cos() * turb;
                if n > 2 {
                    z = (-x - y - z).sin() * turb;
                    if n > 3 {
                        x = -(-x + y - z).cos() * turb;
                        if n > 4 {
                            y = -(-x + y + z).sin() * turb;
                            if n > 5 {
                                y = -(-x + y + z).cos() * turb;
                                if n > 6 {
                                    x = (x + y + z).cos() * turb;
                                    if n > 7 {
                                        z = (x + y - z).sin() * turb;
                                        if n > 8 {
                                            x = -(-x - y + z).cos() * turb;
                                            if n > 9 {
                                                y = -(x - y + z).sin() * turb;
                                            }
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        if turb != 0.0 {
            turb *= 2.0;
            x /= turb;
            y /= turb;
            z /= turb;
        }
        let rgb = [0.5 - x, 0.5 - y, 0.5 - z];
        let tin = 0.3333 * (rgb[0] + rgb[1] + rgb[2]);
        TexResult {
            tin,
            rgb: Some(bc.rgb(rgb)),
        }
    }
}

pub fn build(p: &mut Params) -> Result<Magic, TextureError> {
    let turbulence = p.turbulence()?;
    Ok(Magic {
        depth: p.noise_depth(),
        turbulence,
    })
}
