"""An Exodus II file in ParaView, read by ParaView's own reader (IOSS) and drawn through the plugin:
the wavelet as one TETRA block, RTData a nodal variable over three steps (scaled by 0.6, 1 and
1.4). At each step's time the image is `prismoid render FILE.exo --time-step N`'s (Prismoid's own
Exodus reader) and the CPU reference's, within the bound of plugin_matches_render.py (2 levels:
ParaView's 8-bit framebuffer); the steps share their points and cells, so the plugin uploads the
mesh once and each later step's fields alone.
"""
import os
import subprocess

import numpy as np
from paraview.simple import GetAnimationScene, Render

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
    scene = pvtest.Scene(exo)
    animation = GetAnimationScene()
    animation.UpdateAnimationUsingDataTimeSteps()
    failures = 0
    images = []
    for i, t in enumerate(TIMES):
        animation.AnimationTime = t
        Render(scene.view)
        pv = scene.screenshot(os.path.join(out, "paraview_step%d.png" % i))
        gpu = scene.prismoid(a["prismoid"], exo, tf, os.path.join(out, "render_step%d.pfm" % i), ["--mode", "interval-sorted", "--time-step", str(i)])
        reference = scene.prismoid(a["prismoid"], exo, tf, os.path.join(out, "reference_step%d.pfm" % i), ["--mode", "reference", "--time-step", str(i)])
        d_render = pvtest.levels(pv, gpu)
        d_reference = pvtest.levels(pv, reference)
        print("step %d (t = %r): ParaView's Exodus reader and the plugin against prismoid render --time-step %d: largest %.3f levels; "
              "against the CPU reference: largest %.3f" % (i, t, i, d_render.max(), d_reference.max()), flush=True)
        if d_render.max() > BOUND or d_reference.max() > BOUND:
            failures += 1
        images.append(reference)
    for i in range(1, len(images)):
        change = np.abs(images[i] - images[0]).max()
        print("step %d against step 0: largest difference %.3f (linear colour)" % (i, change), flush=True)
        if change < 0.02:
            pvtest.fail("steps 0 and %d look alike: the file's steps prove nothing" % i)
    if failures:
        pvtest.fail("%d of %d steps beyond the bound" % (failures, len(TIMES)))
    scene.rep.UpdatePropertyInformation()
    meshes = scene.rep.GetPropertyValue("PrismoidMeshUploads")
    fields = scene.rep.GetPropertyValue("PrismoidFieldUploads")
    print("uploads: %d mesh, %d field sets" % (meshes, fields), flush=True)
    if meshes != 1 or fields != len(TIMES) - 1:
        pvtest.fail("expected the mesh uploaded once and %d field sets, got %d and %d" % (len(TIMES) - 1, meshes, fields))
    print("PASS")


main()
