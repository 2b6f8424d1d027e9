#!/usr/bin/env python3
"""Writes src/spectrum/data/lamp_spectra.txt: the measured lamp spectra of LuxRender's
`lampspectrum` texture, read from LuxCore (pyluxcore), which ships the same tables
(LuxRender 1.x lights/data/lamp_spect.h) and hands them back through its `irregulardata`
texture. Candle, Incandescent1 and Incandescent2 are blackbodies in LuxRender 1.x (1020 K,
2750 K, 2900 K) and are not tables.

Usage: pip install pyluxcore; python3 scripts/extract_lamp_spectra.py src/spectrum/data/lamp_spectra.txt
(pyluxcore 2.11 prints library notes on stdout and may abort while unloading: judge by the file.)
Format: one lamp per line: NAME, then `wl:` 250 wavelengths (nm), then `v:` 250 values.
"""
import sys
import pyluxcore

NAMES = """Alcohol AntiInsect Ar BLAU BLNG BLP Butane CarbonArc Cd CFL27K CFL4K CFL6K CL42053
CobaltGlass Daylight FeCo FL37K FLAV17K FLAV8K FLBL FLBLB FLD2 GaPb GreenLaser GroLux GRUN HPM2
HPMFL1 HPMFL2 HPMFL2Glow HPMFLCL42053 HPMFLCobaltGlass HPMFLRedGlass HPMSB HPMSBFL HPS HPX LCDS
LEDB LPM2 LPS MHD MHN MHSc MHWWD MPS Ne NeKrFL NeXeFL1 NeXeFL2 OliveOil PLANTA Rb RedGlass
RedLaser SHPS SS1 SS2 TV UVA Welsbach Xe XeI Zn""".split()

pyluxcore.Init(lambda s: None)
lines = []
for name in NAMES:
    props = pyluxcore.Properties()
    props.Set(pyluxcore.Property("scene.textures.t.type", "lampspectrum"))
    props.Set(pyluxcore.Property("scene.textures.t.name", name))
    scene = pyluxcore.Scene()
    scene.Parse(props)
    out = scene.ToProperties()
    wl = out.Get("scene.textures.t.wavelengths").GetValuesString()
    data = out.Get("scene.textures.t.data").GetValuesString()
    wl = wl if isinstance(wl, str) else " ".join(map(str, wl))
    data = data if isinstance(data, str) else " ".join(map(str, data))
    assert len(wl.split()) == 250 and len(data.split()) == 250, name
    lines.append(f"{name} wl: {wl} v: {data}\n")
with open(sys.argv[1], "w") as f:
    f.writelines(lines)
