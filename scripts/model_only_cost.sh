#!/bin/bash
# "Model only what a scene requires", measured (issue 16): the Cornell benchmark scene as is
# (no media, no dispersion), with a scattering homogeneous medium inside its glass sphere, and
# with a dispersive glass (cauchyb), rendered by two luxfarm binaries alternately (e.g. a build
# from before media and spectra landed, and the current one). Prints per render the wall time
# and peak memory of build + 1 spp (scene build cost) and of 64 spp, and the samples/s.
#
#   scripts/model_only_cost.sh OLD_BINARY NEW_BINARY [ROUNDS] [SHARED_DIR]
set -euo pipefail
OLD=$(realpath "$1"); NEW=$(realpath "$2"); N=${3:-3}
SHARED=$(realpath "${4:-../shared}")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$SHARED/scenes/cornell/cornell-mesh.lxs" "$dir" <<'PY'
import re, sys
src, out = sys.argv[1], sys.argv[2]
s = open(src).read()
s = re.sub(r'"integer haltspp" \[\d+\]', '"integer haltspp" [64]', s)
for k in ("write_png", "write_exr", "write_resume_flm"):
    s = s.replace('"bool %s" ["true"]' % k, '"bool %s" ["false"]' % k)
media = s.replace('WorldBegin\n', 'WorldBegin\nMakeNamedVolume "smoke" "homogeneous" '
                  '"color sigma_a" [0.4 0.8 1.2] "color sigma_s" [2 2 2] "float g" [0.3]\n', 1)
media = media.replace('AttributeBegin # s2\n', 'AttributeBegin # s2\n  Interior "smoke"\n', 1)
media = media.replace('SurfaceIntegrator "path"', 'VolumeIntegrator "multi"\nSurfaceIntegrator "path"', 1)
disp = s.replace('"float index" [1.5]', '"float index" [1.5] "float cauchyb" [0.0085]', 1)
assert media.count("smoke") == 2 and disp != s, "unexpected cornell-mesh.lxs layout"
for name, text in (("plain", s), ("media", media), ("dispersion", disp)):
    open("%s/%s.lxs" % (out, name), "w").write(text)
PY
echo "machine: $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GiB; load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for r in $(seq 1 "$N"); do
  for s in plain media dispersion; do
    for b in old new; do
      bin=$OLD; [ "$b" = new ] && bin=$NEW
      /usr/bin/time -f "%e s %M kB" -o "$dir/t1" "$bin" render "$dir/$s.lxs" --haltspp 1 -o "$dir/out" > /dev/null 2> "$dir/log1"
      /usr/bin/time -f "%e s %M kB" -o "$dir/t2" "$bin" render "$dir/$s.lxs" --haltspp 64 -o "$dir/out" > /dev/null 2> "$dir/log2"
      rate=$(grep -o "[0-9]* samples/s" "$dir/log2" | head -1)
      warn=$(grep -c -i "warn" "$dir/log2" || true)
      echo "round $r $s $b: 1 spp $(cat "$dir/t1") | 64 spp $(cat "$dir/t2") | $rate | $warn warnings"
    done
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
