"""The plugin follows ParaView's time: a time series (.pvd) of three steps, whose field is the
wavelet's scaled by 0.6, 1 and 1.4, drawn at each step's time through the plugin, gives at each
step the image `prismoid render --time-step N` gives of that step, and the CPU reference's, within
the bound of plugin_matches_render.py (2 levels: ParaView's 8-bit framebuffer). The transfer
function's range is the first step's throughout, so the steps look different; a plugin that kept
the first step's mesh would match only the first. The steps share their points and cells, so the
mesh is uploaded once and each later step sends its fields alone (counted by the plugin).
"""
import os

import numpy as np
from paraview.simple import Calculator, Delete, GetAnimationScene, Render, SaveData, XMLUnstructuredGridReader

import pvtest

BOUND = 2.0
SCALES = [0.6, 1.0, 1.4]
TIMES = [0.0, 0.5, 2.0]


def main():
    a, out, vtu, tf = pvtest.start()
    # The steps: RTData scaled (beside the collection, as ParaView writes one).
    entries = []
    for i, scale in enumerate(SCALES):
        reader = XMLUnstructuredGridReader(FileName=[vtu])
        calc = Calculator(Input=reader, Function="RTData*%r" % scale, ResultArrayName="RTData")
        name = "step_%d.vtu" % i
        SaveData(os.path.join(out, name), proxy=calc)
        Delete(calc)
        Delete(reader)
        entries.append('    <DataSet timestep="%r" part="0" file="%s"/>\n' % (TIMES[i], name))
    pvd = os.path.join(out, "series.pvd")
    with open(pvd, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n')
        f.writelines(entries)
        f.write("  </Collection>\n</VTKFile>\n")

    scene = pvtest.Scene(pvd)
    animation = GetAnimationScene()
    animation.UpdateAnimationUsingDataTimeSteps()
    failures = 0
    images = []
    for i, t in enumerate(TIMES):
        animation.AnimationTime = t
        Render(scene.view)
        pv = scene.screenshot(os.path.join(out, "paraview_step%d.png" % i))
        gpu = scene.prismoid(a["prismoid"], pvd, tf, os.path.join(out, "render_step%d.pfm" % i), ["--mode", "interval-sorted", "--time-step", str(i)])
        reference = scene.prismoid(a["prismoid"], pvd, tf, os.path.join(out, "reference_step%d.pfm" % i), ["--mode", "reference", "--time-step", str(i)])
        d_render = pvtest.levels(pv, gpu)
        d_reference = pvtest.levels(pv, reference)
        print("step %d (t = %r): ParaView against prismoid render --time-step %d: largest %.3f levels; against the CPU reference: "
              "largest %.3f" % (i, t, i, d_render.max(), d_reference.max()), flush=True)
        if d_render.max() > BOUND or d_reference.max() > BOUND:
            failures += 1
        images.append(reference)
    # The steps differ (so matching each is not matching one image three times).
    for i in range(1, len(images)):
        change = np.abs(images[i] - images[0]).max()
        print("step %d against step 0: largest difference %.3f (linear colour)" % (i, change), flush=True)
        if change < 0.02:
            pvtest.fail("steps 0 and %d look alike: the series proves nothing" % i)
    if failures:
        pvtest.fail("%d of %d steps beyond the bound" % (failures, len(TIMES)))
    # The steps share their points and cells: the mesh went to the GPU once, each later step's
    # fields alone.
    scene.rep.UpdatePropertyInformation()
    meshes = scene.rep.GetPropertyValue("PrismoidMeshUploads")
    fields = scene.rep.GetPropertyValue("PrismoidFieldUploads")
    print("uploads: %d mesh, %d field sets" % (meshes, fields), flush=True)
    if meshes != 1 or fields != len(TIMES) - 1:
        pvtest.fail("expected the mesh uploaded once and %d field sets, got %d and %d" % (len(TIMES) - 1, meshes, fields))
    print("PASS")


main()
