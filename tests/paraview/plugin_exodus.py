"""An Exodus II file in ParaView, read by ParaView's own reader (IOSS) and drawn through the plugin:
the wavelet as one TETRA block, RTData a nodal variable over three steps (scaled by 0.6, 1 and
1.4). At each step's time the image is `prismoid render FILE.exo --time-step N`'s (Prismoid's own
Exodus reader) and the CPU reference's, within the bound of plugin_matches_render.py (2 levels:
ParaView's 8-bit framebuffer); the steps share their points and cells, so the plugin uploads the
mesh once and each later step's fields alone.
"""
import os
import subprocess

import pvtest

BOUND = 2.0
SCALES = [0.6, 1.0, 1.4]
TIMES = [0.0, 0.5, 2.0]


def main():
    a, out, vtu, tf = pvtest.start()
    exo = os.path.join(out, "wavelet.exo")
    write = subprocess.run([a["exodus-writer"], vtu, "RTData", exo] + ["%r:%r" % (t, s) for t, s in zip(TIMES, SCALES)],
                           capture_output=True, text=True)
    if write.returncode != 0:
        pvtest.fail("write_exodus_steps exited %d: %s" % (write.returncode, write.stdout + write.stderr))
    pvtest.check_steps(a, pvtest.Scene(exo), exo, tf, out, TIMES, BOUND)
    print("PASS")


main()
