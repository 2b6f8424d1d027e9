"""Radiance of LuxCore's `sky2` light in chosen directions, for tests/render_sky2.rs.

    pip install pyluxcore numpy
    python3 scripts/luxcore_sky2.py

For each case (sun elevation in degrees, turbidity) and each view direction (elevation and
azimuth from the sun, degrees) it renders a 4x4 image through a 0.5-degree perspective camera
looking that way (nothing else in the scene but a tiny triangle far behind the camera, since
LuxCore wants geometry), and prints the mean linear RGB of the film, which is the sky's radiance
in that direction (LuxCore: 683 x the Hosek-Wilkie RGB tables x gain, gain 1, ground albedo 0).
"""
import math, os, sys
import pyluxcore

from luxcore_common import render_rgb

CASES = [(30.0, 3.0), (10.0, 6.0), (60.0, 2.0)]
VIEWS = [(90.0, 0.0), (45.0, 180.0), (20.0, 90.0), (5.0, 135.0), (35.0, 10.0)]


def unit(elev, azim):
    e, a = math.radians(elev), math.radians(azim)
    return (math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e))


def render(sun, turbidity, view):
    scene = pyluxcore.Scene()
    up = (0.0, 1.0, 0.0) if abs(view[2]) > 0.99 else (0.0, 0.0, 1.0)
    tri_at = [-100.0 * v for v in view]
    lines = [
        'scene.camera.type = "perspective"',
        "scene.camera.lookat.orig = 0 0 0",
        "scene.camera.lookat.target = %g %g %g" % view,
        "scene.camera.up = %g %g %g" % up,
        "scene.camera.fieldofview = 0.5",
        'scene.lights.sky.type = "sky2"',
        "scene.lights.sky.dir = %g %g %g" % sun,
        "scene.lights.sky.turbidity = %g" % turbidity,
        "scene.lights.sky.gain = 1 1 1",
        'scene.materials.m.type = "matte"',
        "scene.materials.m.kd = 0 0 0",
    ]
    props = pyluxcore.Properties()
    props.SetFromString("\n".join(lines))
    p = tri_at
    scene.DefineMesh("tri", [(p[0], p[1], p[2]), (p[0] + 0.01, p[1], p[2]), (p[0], p[1] + 0.01, p[2])],
                     [(0, 1, 2)], None, None, None, None)
    props.Set(pyluxcore.Property("scene.objects.tri.shape", "tri"))
    props.Set(pyluxcore.Property("scene.objects.tri.material", "m"))
    scene.Parse(props)
    cfg = pyluxcore.Properties()
    cfg.SetFromString("\n".join([
        'renderengine.type = "PATHCPU"', 'sampler.type = "RANDOM"', "film.width = 4",
        "film.height = 4", 'film.filter.type = "NONE"', "batch.haltspp = 4",
        "native.threads.count = 1",
        'film.imagepipelines.0.0.type = "TONEMAP_LINEAR"', "film.imagepipelines.0.0.scale = 1",
    ]))
    return render_rgb(cfg, scene, 4, 4).reshape(-1, 3).mean(axis=0)


def main():
    pyluxcore.Init(lambda s: None)
    for sun_elev, turb in CASES:
        sun = unit(sun_elev, 0.0)
        for elev, azim in VIEWS:
            rgb = render(sun, turb, unit(elev, azim))
            print("sun_elev=%g turbidity=%g view_elev=%g view_azim=%g rgb=%.6g %.6g %.6g"
                  % (sun_elev, turb, elev, azim, rgb[0], rgb[1], rgb[2]), flush=True)
    os._exit(0)


if __name__ == "__main__":
    main()
