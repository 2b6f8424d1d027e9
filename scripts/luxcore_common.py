"""What the LuxCore comparison scripts share: running a render session to its halt condition,
reading its film as an RGB image, and the 32-pixel block means the block comparisons print.

The scripts import it as a sibling module (`python3 scripts/luxcore_X.py` puts `scripts/` on
the module path). pyluxcore must already be initialised (`pyluxcore.Init`).
"""
import numpy as np
import pyluxcore


def render_rgb(cfg, scene, width, height, output=None):
    """Runs a session of `cfg` (pyluxcore.Properties) on `scene` until its halt condition and
    returns the film's `output` (default RGB, linear) as a height x width x 3 float32 array, in
    LuxCore's row order (GetOutputFloat's: bottom row first)."""
    output = pyluxcore.FilmOutputType.RGB if output is None else output
    session = pyluxcore.RenderSession(pyluxcore.RenderConfig(cfg, scene))
    session.Start()
    while not session.HasDone():
        session.UpdateStats()
    session.Stop()
    buf = np.zeros(width * height * 3, dtype=np.float32)
    session.GetFilm().GetOutputFloat(output, buf)
    return buf.reshape(height, width, 3)


def luminance(img):
    """Y of a linear sRGB-primaries image (0.2126 R + 0.7152 G + 0.0722 B)."""
    return img[..., 0] * 0.2126 + img[..., 1] * 0.7152 + img[..., 2] * 0.0722


def block_means(y, res, block):
    """Means of `block`-pixel blocks of a res x res image given top row first, over LuxCore's
    rows 1..res-1: LuxCore's film lies one row below the scene's pixel centres, so its row r + 1
    is luxfarm's row r (see scripts/luxcore_photometric.py). The last block row is one row short.
    Rows from the top, then columns."""
    y = y[1:]
    n = res // block
    out = []
    for by in range(n):
        rows = y[by * block:min((by + 1) * block, res - 1)]
        for bx in range(n):
            out.append(rows[:, bx * block:(bx + 1) * block].mean())
    return out
