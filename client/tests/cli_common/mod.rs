//! Helpers of the tests that run the `luxfarm` binary on a scene of their own: the one
//! builder of their small scenes ([`SceneSpec`]: a camera, a Film statement, an area light
//! over matte quads), the tiny scene built with it (32×32, one area light over a matte floor),
//! and running the binary.

#![allow(dead_code)]

use std::process::{Command, Output, Stdio};

/// A small .lxs scene: a perspective camera, the Film statement the test gives, a box filter,
/// one random sample per pixel per pass, the path integrator, and in the world one area light
/// over matte surfaces (all triangle meshes).
pub struct SceneSpec<'a> {
    /// The `LookAt` numbers: eye, target, up.
    pub look_at: &'a str,
    pub fov: f32,
    /// The whole Film statement (it starts on the scene's third line).
    pub film: &'a str,
    pub maxdepth: u32,
    /// The light group of the lamp, if any.
    pub light_group: Option<&'a str>,
    /// The lamp's grey radiance `L`.
    pub lamp_l: f32,
    /// The lamp's trianglemesh parameters (indices and points).
    pub lamp: &'a str,
    /// The grey diffuse reflectance of the surfaces.
    pub kd: f32,
    /// The trianglemesh parameters of each matte surface.
    pub surfaces: &'a [&'a str],
}

/// The tiny scene's lamp: a 2×2 square at z = 3, facing down.
pub const TINY_LAMP: &str =
    r#""integer indices" [0 2 1 0 3 2] "point P" [-1 -1 3 1 -1 3 1 1 3 -1 1 3]"#;

/// The tiny scene's floor: 10×10 at z = 0, facing up.
pub const TINY_FLOOR: &str =
    r#""integer indices" [0 1 2 0 2 3] "point P" [-5 -5 0 5 -5 0 5 5 0 -5 5 0]"#;

impl<'a> SceneSpec<'a> {
    /// The tiny scene with the Film statement `film`: seen from (0, −4, 2), the lamp of
    /// radiance 20 over the floor (Kd 0.5), path depth 2.
    pub fn tiny(film: &'a str) -> SceneSpec<'a> {
        SceneSpec {
            look_at: "0 -4 2  0 0 0.5  0 0 1",
            fov: 40.0,
            film,
            maxdepth: 2,
            light_group: None,
            lamp_l: 20.0,
            lamp: TINY_LAMP,
            kd: 0.5,
            surfaces: &[TINY_FLOOR],
        }
    }

    /// The scene's statements.
    pub fn text(&self) -> String {
        let group = self
            .light_group
            .map(|g| format!("LightGroup \"{g}\"\n"))
            .unwrap_or_default();
        let surfaces: String = self
            .surfaces
            .iter()
            .map(|s| format!("Shape \"trianglemesh\" {s}\n"))
            .collect();
        let l = self.lamp_l;
        format!(
            r#"LookAt {}
Camera "perspective" "float fov" [{}]
{}
PixelFilter "box"
Sampler "random" "integer pixelsamples" [1]
SurfaceIntegrator "path" "integer maxdepth" [{}]
WorldBegin
AttributeBegin
{group}AreaLightSource "area" "color L" [{l} {l} {l}]
Shape "trianglemesh" {}
AttributeEnd
Material "matte" "color Kd" [{kd} {kd} {kd}]
{surfaces}WorldEnd
"#,
            self.look_at,
            self.fov,
            self.film.trim_end(),
            self.maxdepth,
            self.lamp,
            kd = self.kd,
        )
    }
}

/// The tiny scene, writing its outputs under `filename` (FLM only) and halting at `haltspp`.
pub fn tiny_scene(filename: &str, haltspp: u32) -> String {
    let film = format!(
        r#"Film "fleximage" "integer xresolution" [32] "integer yresolution" [32]
  "string filename" ["{filename}"] "bool write_png" ["false"] "bool write_exr" ["false"]
  "bool write_resume_flm" ["true"] "integer haltspp" [{haltspp}]"#
    );
    SceneSpec::tiny(&film).text()
}

/// Runs the `luxfarm` binary with `args` and no standard input.
pub fn luxfarm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_luxfarm"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run luxfarm")
}

/// The standard output of a run that must have succeeded (else a panic with its exit status
/// and standard error).
pub fn stdout_ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "exit {:?}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}
