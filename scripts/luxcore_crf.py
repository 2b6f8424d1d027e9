"""LuxCore's camera response plugin on chosen radiances, for tests/camera_response_presets.rs.

    pip install pyluxcore numpy
    python3 scripts/luxcore_crf.py Advantix_100CD Agfapan_apx_100CD Ektachrome_64CD

Eight emitting squares side by side (radiances LEVELS, linear RGB) seen by an orthographic
camera, one 8x8-pixel square each, rendered by LuxCore with a linear tonemap of scale 1 and
then the CAMERA_RESPONSE_FUNC plugin with each named preset. Prints a line `plain ...` and then
one line per preset: its name and the mapped R G B at each square's centre, in LEVELS' order.
"""
import os
import sys

import pyluxcore

from luxcore_common import render_rgb

LEVELS = [(0.02, 0.02, 0.02), (0.1, 0.1, 0.1), (0.3, 0.3, 0.3), (0.6, 0.6, 0.6),
          (1.0, 1.0, 1.0), (0.5, 0.2, 0.05), (0.05, 0.3, 0.6), (2.0, 2.0, 2.0)]
SIDE = 8


def render(stages):
    scene = pyluxcore.Scene()
    props = pyluxcore.Properties()
    lines = ['scene.camera.type = "orthographic"', "scene.camera.lookat.orig = 0 0 1",
             "scene.camera.lookat.target = 0 0 0", "scene.camera.up = 0 1 0",
             "scene.camera.screenwindow = %g %g -0.5 0.5" % (-len(LEVELS) / 2, len(LEVELS) / 2)]
    for k, level in enumerate(LEVELS):
        lines += ['scene.materials.m%d.type = "matte"' % k, "scene.materials.m%d.kd = 0 0 0" % k,
                  "scene.materials.m%d.emission = %g %g %g" % ((k,) + level)]
    props.SetFromString("\n".join(lines))
    for k in range(len(LEVELS)):
        x0 = k - len(LEVELS) / 2
        scene.DefineMesh("q%d" % k, [(x0, -1, 0), (x0 + 1, -1, 0), (x0 + 1, 1, 0), (x0, 1, 0)],
                         [(0, 1, 2), (0, 2, 3)], None, None, None, None)
        props.Set(pyluxcore.Property("scene.objects.q%d.shape" % k, "q%d" % k))
        props.Set(pyluxcore.Property("scene.objects.q%d.material" % k, "m%d" % k))
    scene.Parse(props)
    width, height = SIDE * len(LEVELS), SIDE
    cfg = ['renderengine.type = "PATHCPU"', 'sampler.type = "SOBOL"',
           "film.width = %d" % width, "film.height = %d" % height, 'film.filter.type = "NONE"',
           "path.pathdepth.total = 1", "batch.haltspp = 4"]
    for i, stage in enumerate(stages):
        cfg += ["film.imagepipelines.0.%d.%s = %s" % (i, k, v) for k, v in stage.items()]
    props = pyluxcore.Properties()
    props.SetFromString("\n".join(cfg))
    img = render_rgb(props, scene, width, height, pyluxcore.FilmOutputType.RGB_IMAGEPIPELINE)
    return [img[SIDE // 2, SIDE * k + SIDE // 2] for k in range(len(LEVELS))]


def show(name, values):
    print(name + " " + " ".join("%.5f %.5f %.5f" % tuple(v) for v in values))


pyluxcore.Init(lambda s: None)
linear = {"type": '"TONEMAP_LINEAR"', "scale": 1}
show("plain", render([linear]))
for preset in sys.argv[1:]:
    show(preset, render([linear, {"type": '"CAMERA_RESPONSE_FUNC"', "name": '"%s"' % preset}]))
os._exit(0)
