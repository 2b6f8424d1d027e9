"""LuxCore's render of the participating-media comparison scene of tests/media_luxcore.rs: a
sphere of homogeneous absorbing and scattering medium behind a null boundary, over a grey
floor, lit by a square area light; 32-pixel block means of Y.

    pip install pyluxcore numpy
    python3 scripts/luxcore_media.py [--spp 1024]

The scene (the same as in the test):
* camera at (0, -5, 1.6) looking at (0, 0, 0.9), up +z, 40-degree field of view, 128x128
  pixels, one-pixel box filter;
* floor: the square |x|, |y| <= 5 at z = 0, grey (0.5) matte;
* sphere: centre (0, 0, 1), radius 0.8, a UV mesh of SEG x RINGS quads (the same triangles in
  both renderers), null material, interior medium homogeneous with absorption 0.4 and
  scattering 1.6 (per unit length, grey) and asymmetry g = 0.3;
* lamp: the square |x|, |y| <= 0.6 at z = 3.2, facing down, radiance 8 (grey), black matte;
* path tracing, 32 segments, no Russian roulette.

LuxCore's homogeneous volume scatters once unless `multiscattering` is set (LuxRender's
`multi` volume integrator, which the test uses, scatters any number of times): it is set.
LuxRender 1.x's light colours are illuminant spectra: the test divides luxfarm's figures by
the luminance of its white so that radiance 8 means the same in both. LuxCore's film, read
with GetOutputFloat and put top row first, lies one row below the scene's pixel centres (see
scripts/luxcore_photometric.py): the block means are taken over LuxCore's rows 1..127 against
luxfarm's 0..126, blocks of 32 rows, the last of 31. Prints the 16 block means of Y
(Y = 0.2126 R + 0.7152 G + 0.0722 B), rows from the top.
"""
import argparse
import math
import os

import numpy as np
import pyluxcore

from luxcore_common import block_means, luminance, render_rgb

RES, BLOCK = 128, 32
SEG, RINGS = 48, 24
CENTRE, RADIUS = (0.0, 0.0, 1.0), 0.8


def sphere_mesh():
    """The UV sphere: vertices ring by ring from the top pole, triangles wound outward."""
    pts = []
    for j in range(RINGS + 1):
        th = math.pi * j / RINGS
        for i in range(SEG):
            ph = 2 * math.pi * i / SEG
            pts.append((CENTRE[0] + RADIUS * math.sin(th) * math.cos(ph),
                        CENTRE[1] + RADIUS * math.sin(th) * math.sin(ph),
                        CENTRE[2] + RADIUS * math.cos(th)))
    tris = []
    for j in range(RINGS):
        for i in range(SEG):
            a, b = j * SEG + i, j * SEG + (i + 1) % SEG
            c, d = a + SEG, b + SEG
            if j > 0:
                tris.append((a, c, b))
            if j < RINGS - 1:
                tris.append((b, c, d))
    return pts, tris


def render(spp):
    scene = pyluxcore.Scene()
    props = pyluxcore.Properties()
    props.SetFromString("\n".join([
        'scene.camera.type = "perspective"',
        "scene.camera.lookat.orig = 0 -5 1.6",
        "scene.camera.lookat.target = 0 0 0.9",
        "scene.camera.up = 0 0 1",
        "scene.camera.fieldofview = 40",
        'scene.volumes.fog.type = "homogeneous"',
        "scene.volumes.fog.absorption = 0.4 0.4 0.4",
        "scene.volumes.fog.scattering = 1.6 1.6 1.6",
        "scene.volumes.fog.asymmetry = 0.3 0.3 0.3",
        "scene.volumes.fog.multiscattering = 1",
        'scene.materials.floor.type = "matte"',
        "scene.materials.floor.kd = 0.5 0.5 0.5",
        'scene.materials.boundary.type = "null"',
        'scene.materials.boundary.volume.interior = "fog"',
        'scene.materials.lamp.type = "matte"',
        "scene.materials.lamp.kd = 0 0 0",
        "scene.materials.lamp.emission = 8 8 8",
    ]))
    f, l = 5.0, 0.6
    scene.DefineMesh("floor", [(-f, -f, 0.0), (f, -f, 0.0), (f, f, 0.0), (-f, f, 0.0)],
                     [(0, 1, 2), (0, 2, 3)], None, None, None, None)
    scene.DefineMesh("lamp", [(-l, -l, 3.2), (l, -l, 3.2), (l, l, 3.2), (-l, l, 3.2)],
                     [(0, 2, 1), (0, 3, 2)], None, None, None, None)
    pts, tris = sphere_mesh()
    scene.DefineMesh("ball", pts, tris, None, None, None, None)
    for name, mat in (("floor", "floor"), ("lamp", "lamp"), ("ball", "boundary")):
        props.Set(pyluxcore.Property("scene.objects.%s.shape" % name, name))
        props.Set(pyluxcore.Property("scene.objects.%s.material" % name, mat))
    scene.Parse(props)
    cfg = pyluxcore.Properties()
    cfg.SetFromString("\n".join([
        'renderengine.type = "PATHCPU"', 'sampler.type = "SOBOL"',
        "sampler.sobol.adaptive.strength = 0",
        "film.width = %d" % RES, "film.height = %d" % RES, 'film.filter.type = "NONE"',
        "path.pathdepth.total = 32", "path.pathdepth.diffuse = 32",
        "path.pathdepth.glossy = 32", "path.pathdepth.specular = 32",
        "path.russianroulette.depth = 1000",
        "batch.haltspp = %d" % spp,
        'film.imagepipelines.0.0.type = "TONEMAP_LINEAR"', "film.imagepipelines.0.0.scale = 1",
    ]))
    img = render_rgb(cfg, scene, RES, RES)[::-1]
    return luminance(img)


ap = argparse.ArgumentParser()
ap.add_argument("--spp", type=int, default=1024)
ap.add_argument("--save", help="also write LuxCore's Y image here (.npy)")
a = ap.parse_args()
pyluxcore.Init(lambda s: None)
y = render(a.spp)
if a.save:
    np.save(a.save, y)
print("media " + " ".join("%.5g" % v for v in block_means(y, RES, BLOCK)))
os._exit(0)
