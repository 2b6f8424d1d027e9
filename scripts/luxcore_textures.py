"""Render one textured surface with LuxCore (pip package pyluxcore), for `luxfarm bench
luxcore-textures`, which renders the same surface with luxfarm and compares them per pixel.

    python3 scripts/luxcore_textures.py --type fbm --prop octaves=8 --prop roughness=0.5 \
        --out fbm.exr
    python3 scripts/luxcore_textures.py --json case.json      # or --json - (standard input)

The scene is built in LuxCore's own scene language (not its .lxs importer): one mesh (by
default a 2x2 quad in the z = 0 plane, uvs 0..1, facing +z), a perspective camera, the textures,
one material and the lights. With `--type`/`--prop` the texture `tex` is the emission of a black
matte quad seen straight on (no light, no noise beyond pixel coverage); a JSON case gives
everything itself:

    {"res": 96, "spp": 16, "maxdepth": 4, "out": "x.exr",
     "camera": {"orig": [0, 0, 2], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40},
     "mesh": {"points": [[x, y, z], ...], "tris": [[0, 1, 2], ...],
              "uvs": [[u, v], ...], "cols": [[r, g, b], ...], "alphas": [a, ...]},
     "textures": [["name", {"type": "fbm", "octaves": 8, "mapping.type": "..."}], ...],
     "material": {"type": "matte", "kd": [0, 0, 0], "emission": "name"},
     "lights": [["name", {"type": "distant", "direction": [0, 0, -1]}], ...]}

Property values are numbers, lists of numbers or strings (texture names and keywords); keys
are the property names below `scene.textures.NAME.`, `scene.materials.surface.` and
`scene.lights.NAME.`. The film is written as a linear RGB EXR with a one-pixel box filter
(LuxCore's filter NONE) and the random sampler; the script prints one line
`luxcore_textures spp=N res=R elapsed=S mean=M out=PATH` (M: the mean over pixels and channels).
"""
import argparse
import json
import os
import sys
import time

import pyluxcore

DEFAULT_CAMERA = {"orig": [0.0, 0.0, 2.0], "target": [0.0, 0.0, 0.0], "up": [0.0, 1.0, 0.0],
                  "fov": 40.0}
DEFAULT_MESH = {
    "points": [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
    "tris": [[0, 1, 2], [0, 2, 3]],
    "uvs": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
}


def parse_value(text):
    """A `--prop` value: numbers (one or several, space separated) or a string."""
    parts = text.split()
    try:
        nums = [float(p) for p in parts]
    except ValueError:
        return text
    if len(nums) == 1:
        return nums[0]
    return nums


def case_from_args(a):
    """The JSON case of `--type`/`--prop`: texture `tex` as the emission of a black quad."""
    tex = {"type": a.type}
    for p in a.prop:
        key, sep, val = p.partition("=")
        if not sep:
            sys.exit("--prop wants KEY=VALUE, got %r" % p)
        tex[key.strip()] = parse_value(val.strip())
    return {"textures": [["tex", tex]],
            "material": {"type": "matte", "kd": [0.0, 0.0, 0.0], "emission": "tex",
                         "emission.power": 0.0, "emission.efficency": 0.0}}


def prop(name, value):
    """A pyluxcore property: strings stay strings, numbers become floats, lists of numbers
    become lists of floats (ints are written as floats, which LuxCore reads as either)."""
    if isinstance(value, str):
        return pyluxcore.Property(name, value)
    if isinstance(value, bool):
        return pyluxcore.Property(name, value)
    if isinstance(value, (int, float)):
        return pyluxcore.Property(name, float(value))
    if isinstance(value, list) and all(isinstance(v, (int, float)) for v in value):
        return pyluxcore.Property(name, [float(v) for v in value])
    sys.exit("property %s: unsupported value %r" % (name, value))


def film_mean(film):
    """Mean over pixels and channels of the film's RGB output (read through pyluxcore: the
    OpenEXR module cannot be loaded beside pyluxcore's own EXR library)."""
    import numpy as np
    buf = np.zeros(film.GetWidth() * film.GetHeight() * 3, dtype=np.float32)
    film.GetOutputFloat(pyluxcore.FilmOutputType.RGB, buf)
    return float(buf.astype(np.float64).mean())


def build_scene(case):
    scene = pyluxcore.Scene()
    cam = dict(DEFAULT_CAMERA, **case.get("camera", {}))
    props = pyluxcore.Properties()
    props.Set(pyluxcore.Property("scene.camera.type", "perspective"))
    props.Set(prop("scene.camera.lookat.orig", cam["orig"]))
    props.Set(prop("scene.camera.lookat.target", cam["target"]))
    props.Set(prop("scene.camera.up", cam["up"]))
    props.Set(prop("scene.camera.fieldofview", cam["fov"]))
    for name, tex in case.get("textures", []):
        for key, val in tex.items():
            props.Set(prop("scene.textures.%s.%s" % (name, key), val))
    for key, val in case.get("material", {"type": "matte"}).items():
        props.Set(prop("scene.materials.surface.%s" % key, val))
    for name, light in case.get("lights", []):
        for key, val in light.items():
            props.Set(prop("scene.lights.%s.%s" % (name, key), val))
    mesh = case.get("mesh", DEFAULT_MESH)
    pts = [tuple(map(float, p)) for p in mesh["points"]]
    tris = [tuple(map(int, t)) for t in mesh["tris"]]
    uvs = [tuple(map(float, t)) for t in mesh["uvs"]] if mesh.get("uvs") else None
    cols = [tuple(map(float, c)) for c in mesh["cols"]] if mesh.get("cols") else None
    # pyluxcore 2.11 takes an alpha per vertex as a one-element tuple.
    alphas = [(float(x),) for x in mesh["alphas"]] if mesh.get("alphas") else None
    scene.DefineMesh("surface", pts, tris, None, uvs, cols, alphas)
    props.Set(pyluxcore.Property("scene.objects.surface.shape", "surface"))
    props.Set(pyluxcore.Property("scene.objects.surface.material", "surface"))
    scene.Parse(props)
    return scene


def render(case, out, threads):
    res, spp, depth = int(case.get("res", 96)), int(case.get("spp", 16)), int(case.get("maxdepth", 4))
    scene = build_scene(case)
    cfg = pyluxcore.Properties()
    lines = [
        'renderengine.type = "PATHCPU"', 'sampler.type = "RANDOM"',
        "film.width = %d" % res, "film.height = %d" % res, 'film.filter.type = "NONE"',
        "path.pathdepth.total = %d" % depth, "path.pathdepth.diffuse = %d" % depth,
        "path.pathdepth.glossy = %d" % depth, "path.pathdepth.specular = %d" % depth,
        "path.russianroulette.depth = 1000", "batch.haltspp = %d" % spp,
        'film.outputs.0.type = "RGB"', 'film.outputs.0.filename = "%s"' % out,
        'film.imagepipelines.0.0.type = "TONEMAP_LINEAR"', "film.imagepipelines.0.0.scale = 1"]
    if threads > 0:
        lines.append("native.threads.count = %d" % threads)
    cfg.SetFromString("\n".join(lines))
    session = pyluxcore.RenderSession(pyluxcore.RenderConfig(cfg, scene))
    t0 = time.time()
    session.Start()
    while not session.HasDone():
        time.sleep(0.05)
        session.UpdateStats()
    elapsed = time.time() - t0
    session.Stop()
    stats = session.GetStats()
    film = session.GetFilm()
    film.Save()
    return stats.Get("stats.renderengine.pass").GetInt(), res, elapsed, film_mean(film)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", help="the case as JSON: a file, or - for standard input")
    ap.add_argument("--type", help="a texture class (with --prop), shown as emission")
    ap.add_argument("--prop", action="append", default=[], help="KEY=VALUE of the texture")
    ap.add_argument("--res", type=int, help="image width and height (default 96)")
    ap.add_argument("--spp", type=int, help="samples per pixel (default 16)")
    ap.add_argument("--threads", type=int, default=0, help="0 = all cores")
    ap.add_argument("--out", help="the EXR to write (default luxcore_textures.exr)")
    a = ap.parse_args()
    if a.json:
        text = sys.stdin.read() if a.json == "-" else open(a.json).read()
        case = json.loads(text)
    elif a.type:
        case = case_from_args(a)
    else:
        ap.error("give --json or --type")
    if a.res:
        case["res"] = a.res
    if a.spp:
        case["spp"] = a.spp
    out = os.path.abspath(a.out or case.get("out") or "luxcore_textures.exr")
    pyluxcore.Init(lambda s: None)
    spp, res, elapsed, mean = render(case, out, a.threads)
    print("luxcore_textures spp=%d res=%d elapsed=%.3f mean=%.6g out=%s" % (
        spp, res, elapsed, mean, out), flush=True)
    os._exit(0)  # pyluxcore's teardown can abort the interpreter; the film is saved


if __name__ == "__main__":
    main()
