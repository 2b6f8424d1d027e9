"""LuxCore's render of the sky2 comparison scene of tests/render_sky2.rs: 32-pixel block means.

    pip install pyluxcore numpy
    python3 scripts/luxcore_sky2_render.py [--spp 256]

The scene (the same as SCENE in tests/render_sky2.rs): a camera 1 m above an infinite grey
(0.5) matte ground, looking level toward azimuth 135 degrees with a 90-degree field of view,
128x128 pixels, one-pixel box filter; a `sky2` light with the sun at 30 degrees elevation,
azimuth 0, turbidity 3, gain 1; no sun disc. Prints the luminance (0.2126 R + 0.7152 G +
0.0722 B of LuxCore's linear film) of each 32x32 block, row by row from the top.
"""
import argparse, math, os
import pyluxcore

from luxcore_common import luminance, render_rgb

ap = argparse.ArgumentParser()
ap.add_argument("--spp", type=int, default=256)
a = ap.parse_args()

RES, BLOCK = 128, 32
az = math.radians(135.0)
sun = (math.cos(math.radians(30)), 0.0, math.sin(math.radians(30)))
pyluxcore.Init(lambda s: None)
scene = pyluxcore.Scene()
props = pyluxcore.Properties()
props.SetFromString("\n".join([
    'scene.camera.type = "perspective"',
    "scene.camera.lookat.orig = 0 0 1",
    "scene.camera.lookat.target = %g %g 1" % (math.cos(az), math.sin(az)),
    "scene.camera.up = 0 0 1",
    "scene.camera.fieldofview = 90",
    'scene.lights.sky.type = "sky2"',
    "scene.lights.sky.dir = %g %g %g" % sun,
    "scene.lights.sky.turbidity = 3",
    "scene.lights.sky.gain = 1 1 1",
    'scene.materials.ground.type = "matte"',
    "scene.materials.ground.kd = 0.5 0.5 0.5",
]))
s = 1000.0
scene.DefineMesh("ground", [(-s, -s, 0.0), (s, -s, 0.0), (s, s, 0.0), (-s, s, 0.0)],
                 [(0, 1, 2), (0, 2, 3)], None, None, None, None)
props.Set(pyluxcore.Property("scene.objects.ground.shape", "ground"))
props.Set(pyluxcore.Property("scene.objects.ground.material", "ground"))
scene.Parse(props)
cfg = pyluxcore.Properties()
cfg.SetFromString("\n".join([
    'renderengine.type = "PATHCPU"', 'sampler.type = "RANDOM"',
    "film.width = %d" % RES, "film.height = %d" % RES, 'film.filter.type = "NONE"',
    "path.pathdepth.total = 2", "path.pathdepth.diffuse = 2",
    "batch.haltspp = %d" % a.spp,
    'film.imagepipelines.0.0.type = "TONEMAP_LINEAR"', "film.imagepipelines.0.0.scale = 1",
]))
y = luminance(render_rgb(cfg, scene, RES, RES))
# LuxCore's film rows start at the bottom of the image.
y = y[::-1]
n = RES // BLOCK
means = y.reshape(n, BLOCK, n, BLOCK).mean(axis=(1, 3))
for row in means:
    print(" ".join("%.1f" % v for v in row))
os._exit(0)
