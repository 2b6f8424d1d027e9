"""LuxCore's side of the image-effect comparison of tests/imaging_luxcore.rs: bloom, chromatic
aberration and vignetting on one small scene.

    pip install pyluxcore numpy
    python3 scripts/luxcore_effects.py

The scene (the same as SCENE in the test): a camera 3 m above the z = 0 plane looking straight
down (up +y, 90-degree field of view), 128x128 pixels, one-pixel box filter, 64 samples per
pixel, emitters only: a 0.2 m square of radiance 50 at (-1, 1), a 0.6 m square of 5 at
(1, -0.5), a 1.5 m square of 1 at (-1.75, -1.75), and behind them a 6 m square of 0.3 filling
the view. Every figure is a difference image divided by the plain image's mean, so the
renderers' radiometric scales cancel; Y = 0.2126 R + 0.7152 G + 0.0722 B.

* bloom (radius 0.3, weight 0.5): (bloomed - plain) / mean(plain), in 8-pixel blocks of the
  48x48 window around the small bright square (LuxCore rows 20..67, luxfarm rows 19..66:
  LuxCore's film lies one row below the scene's pixel centres, see
  scripts/luxcore_photometric.py), rows from the top.
* aberration (amount 0.5): LuxCore returns the mean of the plain and the aberrated image
  (LuxRender 1.x returns the aberrated image), so 2 (out - plain) / mean(plain), in 16-pixel
  blocks of LuxCore's rows 1..112.
* vignetting (scale 0.4): the factor out / plain at chosen pixels (column, row from the top).
  LuxCore measures a pixel's offset from the centre in [-1, 1] where LuxRender 1.x uses
  [-0.5, 0.5]: LuxCore's factor at offset r is LuxRender's at 2r.
* aberration_formula, vignetting_formula: LuxRender 1.x's aberration and vignetting (the
  formulas luxfarm implements) applied to LuxCore's own plain image with LuxCore's two changes
  (the half-and-half mix, the doubled offsets), against LuxCore's output: the largest
  per-pixel difference over the image's peak.
"""
import os

import numpy as np
import pyluxcore

from luxcore_common import render_rgb

RES = 128
QUADS = [  # (x0, y0, x1, y1, z, radiance)
    (-1.1, 0.9, -0.9, 1.1, 0.0, 50.0),
    (0.7, -0.8, 1.3, -0.2, 0.0, 5.0),
    (-2.5, -2.5, -1.0, -1.0, 0.0, 1.0),
    (-3.0, -3.0, 3.0, 3.0, -0.01, 0.3),
]


def render(stages):
    scene = pyluxcore.Scene()
    props = pyluxcore.Properties()
    lines = ['scene.camera.type = "perspective"', "scene.camera.lookat.orig = 0 0 3",
             "scene.camera.lookat.target = 0 0 0", "scene.camera.up = 0 1 0",
             "scene.camera.fieldofview = 90"]
    for k, q in enumerate(QUADS):
        lines += ['scene.materials.m%d.type = "matte"' % k, "scene.materials.m%d.kd = 0 0 0" % k,
                  "scene.materials.m%d.emission = %g %g %g" % (k, q[5], q[5], q[5])]
    props.SetFromString("\n".join(lines))
    for k, (x0, y0, x1, y1, z, _) in enumerate(QUADS):
        scene.DefineMesh("q%d" % k, [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)],
                         [(0, 1, 2), (0, 2, 3)], None, None, None, None)
        props.Set(pyluxcore.Property("scene.objects.q%d.shape" % k, "q%d" % k))
        props.Set(pyluxcore.Property("scene.objects.q%d.material" % k, "m%d" % k))
    scene.Parse(props)
    cfg = ['renderengine.type = "PATHCPU"', 'sampler.type = "SOBOL"',
           "film.width = %d" % RES, "film.height = %d" % RES, 'film.filter.type = "NONE"',
           "path.pathdepth.total = 1", "batch.haltspp = 64"]
    for i, stage in enumerate(stages):
        cfg += ["film.imagepipelines.0.%d.%s = %s" % (i, k, v) for k, v in stage.items()]
    props = pyluxcore.Properties()
    props.SetFromString("\n".join(cfg))
    return render_rgb(props, scene, RES, RES, pyluxcore.FilmOutputType.RGB_IMAGEPIPELINE)


def top_first_y(img):
    img = img[::-1]
    return img[..., 0] * 0.2126 + img[..., 1] * 0.7152 + img[..., 2] * 0.0722


def bilinear(img, x, y):
    h, w, _ = img.shape
    x1 = np.clip(np.floor(x).astype(int), 0, w - 1)
    y1 = np.clip(np.floor(y).astype(int), 0, h - 1)
    x2, y2 = np.clip(x1 + 1, 0, w - 1), np.clip(y1 + 1, 0, h - 1)
    tx, ty = np.clip(x - x1, 0, 1)[..., None], np.clip(y - y1, 0, 1)[..., None]
    return ((1 - tx) * (1 - ty) * img[y1, x1] + tx * (1 - ty) * img[y1, x2]
            + (1 - tx) * ty * img[y2, x1] + tx * ty * img[y2, x2])


def luxrender_aberration(img, amount):
    """LuxRender 1.x's aberrated image, in the image's own rows (LuxCore's: bottom first)."""
    h, w, _ = img.shape
    y, x = np.mgrid[0:h, 0:w]
    dx, dy = x / w - 0.5, y / h - 0.5
    r = np.sqrt(dx * dx + dy * dy)
    at = lambda s: bilinear(img, (0.5 + dx * (1 + s * r * amount)) * w,
                            (0.5 + dy * (1 + s * r * amount)) * h)
    rb, g = at(1.0), at(-1.0)
    return np.stack([rb[..., 0], g[..., 1], rb[..., 2]], -1)


def luxrender_vignetting(h, w, scale, offset_scale):
    y, x = np.mgrid[0:h, 0:w]
    dx, dy = (x / w - 0.5) * offset_scale, (y / h - 0.5) * offset_scale
    t = 1 - 1.42 * np.sqrt(dx * dx + dy * dy)
    return ((1 - t) * (1 - scale) + t)[..., None]


def blocks(img, size):
    h, w = img.shape
    return img.reshape(h // size, size, w // size, size).mean(axis=(1, 3))


def show(name, values):
    print(name + " " + " ".join("%.4f" % v for v in np.ravel(values)))


pyluxcore.Init(lambda s: None)
linear = {"type": '"TONEMAP_LINEAR"', "scale": 1}
plain_rgb = render([linear])
plain = top_first_y(plain_rgb)
mean = plain.mean()
bloom = top_first_y(render([{"type": '"BLOOM"', "radius": 0.3, "weight": 0.5}, linear]))
show("bloom", blocks(((bloom - plain) / mean)[20:68, 19:67], 8))
aberration_rgb = render([linear, {"type": '"COLOR_ABERRATION"', "amount": 0.5}])
aberration = top_first_y(aberration_rgb)
show("aberration", blocks((2 * (aberration - plain) / mean)[1:113], 16))
vignetting_rgb = render([linear, {"type": '"VIGNETTING"', "scale": 0.4}])
vignetting = top_first_y(vignetting_rgb)
pixels = [(64, 64), (0, 64), (32, 96), (100, 100), (1, 127)]
show("vignetting", [vignetting[y, x] / plain[y, x] for x, y in pixels])
# LuxRender 1.x's formulas (which luxfarm implements) applied to LuxCore's own plain image,
# with LuxCore's two changes, against LuxCore's output: the largest difference over the peak.
want = 0.5 * (plain_rgb + luxrender_aberration(plain_rgb, 0.5))
print("aberration_formula %.5f" % (np.abs(aberration_rgb - want).max() / aberration_rgb.max()))
want = plain_rgb * luxrender_vignetting(RES, RES, 0.4, 2.0)
print("vignetting_formula %.5f" % (np.abs(vignetting_rgb - want).max() / vignetting_rgb.max()))
os._exit(0)
