"""Scaled copies of a grid look the same through the plugin: the wavelet grid scaled by S from
1e-12 to 1e20 and moved off the origin by 2S, seen by the camera scaled with it and with its
opacity unit distance scaled by S, gives ParaView the image of S = 1 and of the CPU reference,
within the bound of plugin_matches_render.py (2 levels: ParaView's 8-bit blending). Before the
renderer drew in units of the data's size, S = 3e10 showed holes and diagonal artefacts.
"""
import os

import numpy as np
from paraview.simple import Delete

import pvtest

BOUND = 2.0
OFFSET = (2.0, -1.0, 0.5)
SCALES = [1e-12, 1e-6, 3e10, 1e15, 1e20]


def main():
    a, out, vtu, tf = pvtest.start()
    one = os.path.join(out, "wavelet_1.vtu")
    pvtest.write_scaled(vtu, one, 1.0, OFFSET)
    scene = pvtest.Scene(one, offset=OFFSET)
    reference = scene.prismoid(a["prismoid"], one, tf, os.path.join(out, "reference.pfm"), ["--mode", "reference"])
    covered = (np.abs(reference - np.array(pvtest.BACKGROUND)).max(axis=2) > 0.05).mean()
    if covered < 0.2:
        pvtest.fail("the volume covers only %.2f of the image" % covered)
    at_one = scene.screenshot(os.path.join(out, "paraview_1.png"))
    failures = 0
    for s in SCALES:
        path = os.path.join(out, "wavelet_%g.vtu" % s)
        pvtest.write_scaled(vtu, path, s, OFFSET)
        scaled = pvtest.Scene(path, scale=s, offset=OFFSET)
        for backend in (0, 1):
            scaled.rep.PrismoidBackend = backend
            pv = scaled.screenshot(os.path.join(out, "paraview_%g_b%d.png" % (s, backend)))
            d_reference = pvtest.levels(pv, reference)
            d_one = np.abs(pv - at_one).max(axis=2)
            print("S = %g, backend %d: against the CPU reference at S = 1 largest %.3f levels, against ParaView's "
                  "image at S = 1 largest %.0f" % (s, backend, d_reference.max(), d_one.max()), flush=True)
            if d_reference.max() > BOUND or d_one.max() > BOUND:
                failures += 1
        Delete(scaled.rep)
    if failures:
        pvtest.fail("%d of %d cases beyond the bound" % (failures, 2 * len(SCALES)))
    print("PASS")


main()
