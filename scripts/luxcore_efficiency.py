"""LuxCore's side of `luxfarm bench efficiency`: the Cornell benchmark scene, or its caustic
variant, rendered by one LuxCore engine and sampler for a fixed wall time (or spp).

    pip install pyluxcore numpy
    python3 scripts/luxcore_efficiency.py --shared ../shared --engine BIDIRCPU \
        --sampler RANDOM --halttime 30 --out bidir.exr [--lamp-half 0.05 --lamp-scale 25]

The scene is built from ../shared/bench/cornell_scene.py in LuxCore's own scene language, as
../shared/bench/luxcore_cornell.py builds it. `--lamp-half H` replaces the ceiling lamp by a
square of half-side H at the same place and multiplies its radiance by `--lamp-scale` (the
caustic variant: a small bright lamp whose light reaches the floor through the glass sphere);
`--lamp-cover C` puts a closed glass slab of half-side C under it (faces at z 1.95 and 1.975),
so that its light reaches the room through glass (the caustic-covered variant).
Depth is in path segments for both the eye and the light path (`path.maxdepth`,
`light.maxdepth`), Russian roulette off, a one-pixel box filter (LuxCore's NONE).

LuxCore's RANDOM and SOBOL samplers are adaptive by default on PATHCPU (more samples where
its noise estimate is high; at 8 s on the caustic variant, 120 to 1773 samples in a pixel
of 218 on average). Without `--adaptive` their adaptive strength is set to 0, so every pixel
gets the same number of samples, as with luxfarm's samplers without `noiseaware`; with it,
LuxCore's default is kept.

Prints one line: 'luxcore engine=E sampler=S spp=N res=R elapsed=T samples_per_s=X' and
writes the linear RGB film as EXR.
"""
import argparse, os, sys, time

ap = argparse.ArgumentParser()
ap.add_argument("--shared", required=True)
ap.add_argument("--engine", default="PATHCPU", choices=["PATHCPU", "BIDIRCPU"])
ap.add_argument("--sampler", default="RANDOM", choices=["RANDOM", "SOBOL", "METROPOLIS"])
ap.add_argument("--spp", type=int, default=0, help="halt at this spp (0: no spp halt)")
ap.add_argument("--halttime", type=float, default=0, help="halt after this many seconds")
ap.add_argument("--res", type=int, default=256)
ap.add_argument("--maxdepth", type=int, default=8)
ap.add_argument("--threads", type=int, default=0, help="0 = all cores")
ap.add_argument("--seed", type=int, default=1)
ap.add_argument("--lamp-half", type=float, default=0, help="0: the benchmark's own lamp")
ap.add_argument("--lamp-scale", type=float, default=1)
ap.add_argument("--lamp-cover", type=float, default=0,
                help="half-side of a glass slab under the lamp (0: none); faces at z 1.95 and 1.975")
ap.add_argument("--adaptive", action="store_true",
                help="keep LuxCore's adaptive sampling (default: off, uniform per pixel)")
ap.add_argument("--out", required=True)
a = ap.parse_args()
if a.spp <= 0 and a.halttime <= 0:
    sys.exit("give --spp or --halttime")

sys.path.insert(0, os.path.join(a.shared, "bench"))
import cornell_scene as cs  # noqa: E402
import pyluxcore  # noqa: E402

if a.lamp_half > 0:
    name, mat, P, I = cs.LAMP
    z = P[0][2]
    h = a.lamp_half
    cs.LAMP = (name, mat, [(-h, -h, z), (h, -h, z), (h, h, z), (-h, h, z)], I)
    cs.LIGHT_L = tuple(c * a.lamp_scale for c in cs.LIGHT_L)

pyluxcore.Init(lambda s: None)
scene = pyluxcore.Scene()
c = cs.CAMERA
lines = ['scene.camera.type = "perspective"',
         "scene.camera.lookat.orig = %g %g %g" % c["orig"],
         "scene.camera.lookat.target = %g %g %g" % c["target"],
         "scene.camera.up = %g %g %g" % c["up"],
         "scene.camera.fieldofview = %g" % c["fov"]]
for name, (kind, p) in cs.MATERIALS.items():
    lines.append('scene.materials.%s.type = "%s"' % (name, kind))
    if kind == "matte":
        lines.append("scene.materials.%s.kd = %g %g %g" % ((name,) + p["Kd"]))
    else:
        lines += ["scene.materials.%s.kr = %g %g %g" % ((name,) + p["Kr"]),
                  "scene.materials.%s.kt = %g %g %g" % ((name,) + p["Kt"]),
                  "scene.materials.%s.interiorior = %g" % (name, p["index"])]
lines += ['scene.materials.lamp.type = "matte"', "scene.materials.lamp.kd = 0.75 0.75 0.75",
          "scene.materials.lamp.emission = %g %g %g" % cs.LIGHT_L,
          "scene.materials.lamp.emission.power = 0", "scene.materials.lamp.emission.efficency = 0"]
props = pyluxcore.Properties()
props.SetFromString("\n".join(lines))
objs = [(n, m, P, I, None) for n, m, P, I in cs.QUADS]
objs.append((cs.LAMP[0], "lamp", cs.LAMP[2], cs.LAMP[3], None))
if a.lamp_cover > 0:
    c, (z0, z1) = a.lamp_cover, (1.95, 1.975)
    P = [(-c, -c, z0), (c, -c, z0), (c, c, z0), (-c, c, z0),
         (-c, -c, z1), (c, -c, z1), (c, c, z1), (-c, c, z1)]
    I = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
         (3, 7, 6), (3, 6, 2), (0, 4, 7), (0, 7, 3), (1, 2, 6), (1, 6, 5)]
    objs.append(("cover", "glass", P, I, None))
for n, m, center, r in cs.SPHERES:
    P, I, N = cs.sphere_mesh(center, r)
    objs.append((n, m, P, I, N))
for n, m, P, I, N in objs:
    scene.DefineMesh(n, [tuple(map(float, p)) for p in P], [tuple(t) for t in I],
                     [tuple(x) for x in N] if N else None, None, None, None)
    props.Set(pyluxcore.Property("scene.objects.%s.shape" % n, n))
    props.Set(pyluxcore.Property("scene.objects.%s.material" % n, m))
scene.Parse(props)

d = a.maxdepth
lines = [
    'renderengine.type = "%s"' % a.engine, 'sampler.type = "%s"' % a.sampler,
    "renderengine.seed = %d" % a.seed,
    "film.width = %d" % a.res, "film.height = %d" % a.res, 'film.filter.type = "NONE"',
    "path.maxdepth = %d" % d, "light.maxdepth = %d" % d,
    "path.pathdepth.total = %d" % d, "path.pathdepth.diffuse = %d" % d,
    "path.pathdepth.glossy = %d" % d, "path.pathdepth.specular = %d" % d,
    "path.russianroulette.depth = 1000",
    'film.outputs.0.type = "RGB"', 'film.outputs.0.filename = "%s"' % a.out,
    'film.imagepipelines.0.0.type = "TONEMAP_LINEAR"', "film.imagepipelines.0.0.scale = 1"]
if not a.adaptive:
    lines += ["sampler.random.adaptive.strength = 0", "sampler.sobol.adaptive.strength = 0"]
if a.spp > 0:
    lines.append("batch.haltspp = %d" % a.spp)
if a.halttime > 0:
    lines.append("batch.halttime = %g" % a.halttime)
if a.threads > 0:
    lines.append("native.threads.count = %d" % a.threads)
cfg = pyluxcore.Properties()
cfg.SetFromString("\n".join(lines))
session = pyluxcore.RenderSession(pyluxcore.RenderConfig(cfg, scene))
t0 = time.time()
session.Start()
while not session.HasDone():
    time.sleep(0.05)
    session.UpdateStats()
elapsed = time.time() - t0
session.Stop()
st = session.GetStats()
print("luxcore engine=%s sampler=%s spp=%d res=%d elapsed=%.3f samples_per_s=%.0f" % (
    a.engine, a.sampler, st.Get("stats.renderengine.pass").GetInt(), a.res, elapsed,
    st.Get("stats.renderengine.total.samplesec").GetFloat()))
session.GetFilm().Save()
os._exit(0)  # pyluxcore's teardown can abort the interpreter; the film is saved
