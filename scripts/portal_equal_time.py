"""Portal sampling at equal time: the RMSE of a room lit through its window by a light at
infinity, rendered for the same wall time with and without a portal over the window, against
a long reference rendered with the portal (issue 17's benchmark).

    pip install numpy OpenEXR
    cargo build --release
    python3 scripts/portal_equal_time.py [--luxfarm target/release/luxfarm] [--seconds 20]
        [--reference-seconds 240] [--rounds 3] [--integrator path|bidirectional] [--out DIR]

The room (the one of tests/render_portals.rs): x, y in [-2, 2], z in [0, 2.5], grey matte
(0.7) walls, floor and ceiling, a 1.0 x 0.8 m window in the wall x = 2, a constant infinite
light; 96x96 pixels seen from inside. Each round renders the scene without and then with the
portal for --seconds each (`halttime`), so both see the same machine load. Prints each render's
RMSE of Y over the reference's mean Y, the means, and their ratio (portal / none).
"""
import argparse
import os
import subprocess
import tempfile

import Imath
import numpy as np
import OpenEXR

X0, X1, Y0, Y1, Z0, Z1 = -2, 2, -2, 2, 0, 2.5
WINDOW = (-0.5, 0.5, 1.0, 1.8)
INTEGRATORS = {
    "path": '"path" "integer maxdepth" [4]',
    "bidirectional": '"bidirectional" "integer eyedepth" [5] "integer lightdepth" [5]',
}


def quad(p):
    pts = " ".join("%g %g %g" % tuple(v) for v in p)
    return 'Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [%s]\n' % pts


def room():
    wy0, wy1, wz0, wz1 = WINDOW
    return "".join([
        quad([[X0, Y0, Z0], [X1, Y0, Z0], [X1, Y1, Z0], [X0, Y1, Z0]]),
        quad([[X0, Y0, Z1], [X0, Y1, Z1], [X1, Y1, Z1], [X1, Y0, Z1]]),
        quad([[X0, Y0, Z0], [X0, Y1, Z0], [X0, Y1, Z1], [X0, Y0, Z1]]),
        quad([[X0, Y0, Z0], [X0, Y0, Z1], [X1, Y0, Z1], [X1, Y0, Z0]]),
        quad([[X0, Y1, Z0], [X1, Y1, Z0], [X1, Y1, Z1], [X0, Y1, Z1]]),
        quad([[X1, Y0, Z0], [X1, Y0, wz0], [X1, Y1, wz0], [X1, Y1, Z0]]),
        quad([[X1, Y0, wz1], [X1, Y0, Z1], [X1, Y1, Z1], [X1, Y1, wz1]]),
        quad([[X1, Y0, wz0], [X1, Y0, wz1], [X1, wy0, wz1], [X1, wy0, wz0]]),
        quad([[X1, wy1, wz0], [X1, wy1, wz1], [X1, Y1, wz1], [X1, Y1, wz0]]),
    ])


def scene(path, name, portal, seconds, integrator):
    wy0, wy1, wz0, wz1 = WINDOW
    text = f'''LookAt -1.8 -0.3 1.3  2 0.2 0.6  0 0 1
Camera "perspective" "float fov" [75]
Film "fleximage" "integer xresolution" [96] "integer yresolution" [96] "integer halttime" [{seconds}]
  "bool write_exr" ["true"] "bool write_exr_applyimaging" ["false"]
  "bool write_exr_halftype" ["false"] "bool write_png" ["false"] "bool write_tga" ["false"]
  "string filename" ["{name}"]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [4]
SurfaceIntegrator {INTEGRATORS[integrator]}
WorldBegin
AttributeBegin
LightSource "infinite" "color L" [1 1 1]
'''
    if portal:
        text += ('PortalShape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" '
                 f'[2 {wy0} {wz0}  2 {wy1} {wz0}  2 {wy1} {wz1}  2 {wy0} {wz1}]\n')
    text += 'AttributeEnd\nMaterial "matte" "color Kd" [0.7 0.7 0.7]\n' + room() + "WorldEnd\n"
    with open(path, "w") as f:
        f.write(text)


def luminance(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    c = [np.frombuffer(f.channel(k, pt), dtype=np.float32).reshape(h, w) for k in "RGB"]
    return (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]).astype(np.float64)


def render(args, d, name, portal, seconds):
    lxs = os.path.join(d, name + ".lxs")
    scene(lxs, name, portal, seconds, args.integrator)
    subprocess.run([args.luxfarm, "render", lxs], cwd=d, check=True, capture_output=True)
    return luminance(os.path.join(d, name + ".exr"))


ap = argparse.ArgumentParser()
ap.add_argument("--luxfarm", default="target/release/luxfarm")
ap.add_argument("--seconds", type=int, default=20)
ap.add_argument("--reference-seconds", type=int, default=240)
ap.add_argument("--rounds", type=int, default=3)
ap.add_argument("--integrator", choices=sorted(INTEGRATORS), default="path")
ap.add_argument("--out")
args = ap.parse_args()
args.luxfarm = os.path.abspath(args.luxfarm)
d = args.out or tempfile.mkdtemp(prefix="portal-bench-")
os.makedirs(d, exist_ok=True)
ref = render(args, d, "reference", True, args.reference_seconds)
mean = ref.mean()
rmse = {"none": [], "portal": []}
for r in range(args.rounds):
    for kind, portal in (("none", False), ("portal", True)):
        img = render(args, d, "%s_%d" % (kind, r), portal, args.seconds)
        rmse[kind].append(np.sqrt(((img - ref) ** 2).mean()) / mean)
        print("round %d %-6s RMSE/mean %.4f (image mean / reference %.4f)"
              % (r, kind, rmse[kind][-1], img.mean() / mean))
a, b = np.mean(rmse["none"]), np.mean(rmse["portal"])
print("%s, %d s each: RMSE/mean without portal %.4f, with %.4f: ratio %.3f"
      % (args.integrator, args.seconds, a, b, b / a))
