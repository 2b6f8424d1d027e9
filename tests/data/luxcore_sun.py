"""Reference values for src/light/sun.rs's `sun_matches_luxcore_renders`: LuxCore (pip package
pyluxcore) renders a kd = 1 matte plane lit by its `sun` light (gain 1, direct light only) and
prints the plane's mean linear sRGB, its chromaticity (via the sRGB matrix) and Y / cos(theta),
i.e. the sun's irradiance at normal incidence divided by pi.

    python3 tests/data/luxcore_sun.py
"""
import os, sys, time
import numpy as np
import pyluxcore

CASES = [((0, 0, 1), 2), ((-0.419128, -0.881370, 0.217989), 2), ((0, 0, 1), 6),
         ((-0.305558, -0.652300, 0.693642), 2)]
SRGB_TO_XYZ = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722],
                        [0.0193, 0.1192, 0.9505]])


def render(sundir, turbidity, res=16, spp=16):
    scene = pyluxcore.Scene()
    lines = ['scene.camera.type = "perspective"', "scene.camera.lookat.orig = 0 0 5",
             "scene.camera.lookat.target = 0 0 0", "scene.camera.up = 0 1 0",
             "scene.camera.fieldofview = 20",
             'scene.materials.white.type = "matte"', "scene.materials.white.kd = 1 1 1",
             'scene.lights.sun.type = "sun"', "scene.lights.sun.dir = %g %g %g" % sundir,
             "scene.lights.sun.turbidity = %g" % turbidity, "scene.lights.sun.gain = 1 1 1"]
    props = pyluxcore.Properties()
    props.SetFromString("\n".join(lines))
    quad = [(-10., -10., 0.), (10., -10., 0.), (10., 10., 0.), (-10., 10., 0.)]
    scene.DefineMesh("plane", quad, [(0, 1, 2), (0, 2, 3)], None, None, None, None)
    props.Set(pyluxcore.Property("scene.objects.plane.shape", "plane"))
    props.Set(pyluxcore.Property("scene.objects.plane.material", "white"))
    scene.Parse(props)
    cfg = pyluxcore.Properties()
    cfg.SetFromString("\n".join([
        'renderengine.type = "PATHCPU"', 'sampler.type = "RANDOM"',
        "film.width = %d" % res, "film.height = %d" % res, 'film.filter.type = "NONE"',
        "path.pathdepth.total = 1", "batch.haltspp = %d" % spp,
        'film.outputs.0.type = "RGB"', 'film.outputs.0.filename = "luxcore_sun.exr"',
        'film.imagepipelines.0.0.type = "TONEMAP_LINEAR"', "film.imagepipelines.0.0.scale = 1"]))
    session = pyluxcore.RenderSession(pyluxcore.RenderConfig(cfg, scene))
    session.Start()
    while not session.HasDone():
        time.sleep(0.1)
        session.UpdateStats()
    session.Stop()
    buf = np.zeros(res * res * 3, dtype=np.float32)
    session.GetFilm().GetOutputFloat(pyluxcore.FilmOutputType.RGB, buf)
    rgb = buf.reshape(-1, 3).mean(axis=0)
    xyz = SRGB_TO_XYZ @ rgb
    return rgb, xyz[:2] / xyz.sum(), xyz[1]


pyluxcore.Init(lambda s: None)
for d, t in CASES:
    rgb, xy, y = render(d, t)
    print("sundir", d, "turbidity", t, "rgb", rgb, "xy %.4f %.4f" % tuple(xy),
          "Y/cos %.4g" % (y / d[2]))
sys.stdout.flush()
os._exit(0)  # pyluxcore's teardown can abort the interpreter
