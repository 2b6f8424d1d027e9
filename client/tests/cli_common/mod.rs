//! Helpers of the tests that run the `luxfarm` binary on a scene of their own: the tiny scene
//! (32×32, one area light over a matte floor) and running the binary.

#![allow(dead_code)]

use std::process::{Command, Output, Stdio};

/// The tiny scene, writing its outputs under `filename` and halting at `haltspp`.
pub fn tiny_scene(filename: &str, haltspp: u32) -> String {
    format!(
        r#"LookAt 0 -4 2  0 0 0.5  0 0 1
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [32] "integer yresolution" [32]
  "string filename" ["{filename}"] "bool write_png" ["false"] "bool write_exr" ["false"]
  "bool write_resume_flm" ["true"] "integer haltspp" [{haltspp}]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [1]
SurfaceIntegrator "path" "integer maxdepth" [2]
WorldBegin
AttributeBegin
AreaLightSource "area" "color L" [20 20 20]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2] "point P" [-1 -1 3 1 -1 3 1 1 3 -1 1 3]
AttributeEnd
Material "matte" "color Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-5 -5 0 5 -5 0 5 5 0 -5 5 0]
WorldEnd
"#
    )
}

/// Runs the `luxfarm` binary with `args` and no standard input.
pub fn luxfarm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_luxfarm"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run luxfarm")
}
