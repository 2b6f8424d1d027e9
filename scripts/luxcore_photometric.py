"""LuxCore's renders of the two photometric comparison scenes of tests/photometric_luxcore.rs
(an IES point light and a projection light over a grey floor): 32-pixel block means of Y.

    pip install pyluxcore numpy OpenEXR
    python3 scripts/luxcore_photometric.py [--spp 256]

Both scenes: a camera 3 m above an infinite grey (0.5) matte floor looking straight down
(up +y, 90-degree field of view), 128x128 pixels, one-pixel box filter, direct light only.

* ies: a `mappoint` light at (0.3, 0.2, 1) with the IES profile IES below (type C, a full turn
  of horizontal angles, brighter toward +x than -x), `flipz`, power 100 and efficacy 10.
* projection: a `projection` light at (0.2, 0.1, 1.5) looking straight down, fov 60, with the
  64x32 grey slide of `slide()` (four quadrants 1, 2, 3, 4, each ramped from 0.5 to 1 across
  the slide).

Where LuxCore 2.11 and LuxRender 1.x differ by construction, the LuxCore scene carries the
difference, so that both describe the same light (facts from both sources):

* mappoint divides its profile by 4 pi times `SampleableSphericalFunction::Average()`, which
  is already the profile's integral over the sphere; LuxRender 1.x's point light divides by
  that integral once. LuxCore's figures are multiplied by 4 pi.
* LuxRender 1.x's projection light emits slide / (A cos^3 theta) toward a direction at angle
  theta from its axis (A = 4 tan^2(fov/2) / aspect), so a facing wall receives the slide
  evenly; LuxCore's emits the slide as it is. The LuxCore slide is the same slide divided by
  A cos^3 theta at each texel centre.
* LuxCore frames its projector with CoordinateSystem(axis), a quarter turn about the axis from
  the light's own x and y, which LuxRender 1.x uses: the light is turned back by a rotation
  about z.

LuxCore's film, read with GetOutputFloat and put top row first, lies one row below the
scene's pixel centres (measured: a plain point light matches the closed form to 0.15 % rms per
pixel only when each LuxCore row is compared with the row above it). The block means are
taken over LuxCore's rows 1..127 against luxfarm's 0..126: blocks of 32 rows, the last of 31.
Prints, per scene, a line with its name and then the 16 block means (Y = 0.2126 R + 0.7152 G
+ 0.0722 B), rows from the top.
"""
import argparse
import math
import os
import tempfile

import numpy as np
import OpenEXR
import Imath
import pyluxcore

from luxcore_common import block_means, luminance, render_rgb

RES, BLOCK = 128, 32
IES = """IESNA:LM-63-2002
[TEST] asymmetric downlight
TILT=NONE
1 1000 1 5 5 1 2 0.1 0.1 0
1.0 1.0 20
0 30 60 90 180
0 90 180 270 360
900 700 300 50 0
600 500 250 40 0
300 250 120 20 0
600 500 250 40 0
900 700 300 50 0
"""
FOV = 60.0


def slide():
    """The projected slide: 64x32, row 0 at the top."""
    w, h = 64, 32
    j, i = np.mgrid[0:h, 0:w]
    quadrant = np.where(j < h // 2, np.where(i < w // 2, 1.0, 2.0),
                        np.where(i < w // 2, 3.0, 4.0))
    return quadrant * (0.5 + 0.5 * i / (w - 1))


def luxcore_slide(img):
    """The slide with LuxRender 1.x's 1 / (A cos^3 theta) folded in at each texel centre."""
    h, w = img.shape
    t = math.tan(math.radians(FOV) / 2)
    a = w / h
    x0, x1, y0, y1 = (-a, a, -1.0, 1.0) if a > 1 else (-1.0, 1.0, -1 / a, 1 / a)
    j, i = np.mgrid[0:h, 0:w]
    sx = x0 + (i + 0.5) / w * (x1 - x0)
    sy = y1 - (j + 0.5) / h * (y1 - y0)
    cos = 1 / np.sqrt(1 + t * t * (sx * sx + sy * sy))
    return img / (4 * t * t / a * cos ** 3)


def write_exr(path, img):
    h, w = img.shape
    hdr = OpenEXR.Header(w, h)
    hdr["channels"] = {c: Imath.Channel(Imath.PixelType(Imath.PixelType.FLOAT)) for c in "RGB"}
    out = OpenEXR.OutputFile(path, hdr)
    out.writePixels({c: img.astype(np.float32).tobytes() for c in "RGB"})
    out.close()


def render(light_lines, spp):
    scene = pyluxcore.Scene()
    props = pyluxcore.Properties()
    props.SetFromString("\n".join([
        'scene.camera.type = "perspective"',
        "scene.camera.lookat.orig = 0 0 3",
        "scene.camera.lookat.target = 0 0 0",
        "scene.camera.up = 0 1 0",
        "scene.camera.fieldofview = 90",
        'scene.materials.floor.type = "matte"',
        "scene.materials.floor.kd = 0.5 0.5 0.5",
    ] + light_lines))
    s = 100.0
    scene.DefineMesh("floor", [(-s, -s, 0.0), (s, -s, 0.0), (s, s, 0.0), (-s, s, 0.0)],
                     [(0, 1, 2), (0, 2, 3)], None, None, None, None)
    props.Set(pyluxcore.Property("scene.objects.floor.shape", "floor"))
    props.Set(pyluxcore.Property("scene.objects.floor.material", "floor"))
    scene.Parse(props)
    cfg = pyluxcore.Properties()
    cfg.SetFromString("\n".join([
        'renderengine.type = "PATHCPU"', 'sampler.type = "RANDOM"',
        "film.width = %d" % RES, "film.height = %d" % RES, 'film.filter.type = "NONE"',
        "path.pathdepth.total = 1", "path.pathdepth.diffuse = 1",
        "batch.haltspp = %d" % spp,
        'film.imagepipelines.0.0.type = "TONEMAP_LINEAR"', "film.imagepipelines.0.0.scale = 1",
    ]))
    img = render_rgb(cfg, scene, RES, RES)[::-1]
    return luminance(img)


ap = argparse.ArgumentParser()
ap.add_argument("--spp", type=int, default=256)
a = ap.parse_args()
pyluxcore.Init(lambda s: None)
with tempfile.TemporaryDirectory() as d:
    ies = os.path.join(d, "lamp.ies")
    with open(ies, "w") as f:
        f.write(IES)
    y = render([
        'scene.lights.l.type = "mappoint"',
        'scene.lights.l.iesfile = "%s"' % ies,
        "scene.lights.l.flipz = 1",
        "scene.lights.l.position = 0.3 0.2 1",
        "scene.lights.l.power = 100",
        "scene.lights.l.efficency = 10",
    ], a.spp)
    print("ies " + " ".join("%.5g" % (4 * math.pi * v) for v in block_means(y, RES, BLOCK)))
    slide_path = os.path.join(d, "slide.exr")
    write_exr(slide_path, luxcore_slide(slide()))
    y = render([
        'scene.lights.l.type = "projection"',
        'scene.lights.l.mapfile = "%s"' % slide_path,
        "scene.lights.l.gamma = 1",
        "scene.lights.l.fov = %g" % FOV,
        "scene.lights.l.position = 0 0 0",
        "scene.lights.l.target = 0 0 -1",
        # A quarter turn about z (column-major), then the projector's place.
        "scene.lights.l.transformation = 0 1 0 0 -1 0 0 0 0 0 1 0 0.2 0.1 1.5 1",
    ], a.spp)
    print("projection " + " ".join("%.5g" % v for v in block_means(y, RES, BLOCK)))
os._exit(0)
