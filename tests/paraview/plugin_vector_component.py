"""Colouring by a vector's component draws that component: the wavelet's gradient coloured by X
through the plugin gives the image `prismoid render` gives of the X component as its own array,
and the CPU reference's, within the bound of plugin_matches_render.py (2 levels); coloured by
the magnitude it gives the magnitude's image. (The plugin once mapped the magnitude through the
component's range whatever the colouring asked: uniformly red.)
"""
import os

import numpy as np
from paraview.simple import Calculator, ColorBy, Delete, GradientOfUnstructuredDataSet, SaveData, XMLUnstructuredGridReader

import pvtest

BOUND = 2.0


def main():
    a, out, vtu, tf = pvtest.start()
    # The gradient, and its X component and magnitude as arrays of their own.
    reader = XMLUnstructuredGridReader(FileName=[vtu])
    grad = GradientOfUnstructuredDataSet(Input=reader, ScalarArray=["POINTS", "RTData"], ResultArrayName="Gradient")
    gx = Calculator(Input=grad, Function="Gradient_X", ResultArrayName="gx")
    gm = Calculator(Input=gx, Function="mag(Gradient)", ResultArrayName="gm")
    with_gradient = os.path.join(out, "gradient.vtu")
    SaveData(with_gradient, proxy=gm)
    for p in (gm, gx, grad, reader):
        Delete(p)
    failures = 0
    # (what ParaView colours by, the array `prismoid render` is given)
    for colouring, own in ((("POINTS", "Gradient", "X"), "gx"), (("POINTS", "Gradient", "Magnitude"), "gm")):
        scene = pvtest.Scene(with_gradient, array=own)
        ColorBy(scene.rep, colouring)
        lut = scene.set_functions("Gradient")
        if colouring[2] == "X" and (lut.VectorMode != "Component" or lut.VectorComponent != 0):
            pvtest.fail("ColorBy did not select component X: %s %s" % (lut.VectorMode, lut.VectorComponent))
        tag = colouring[2].lower()
        pv = scene.screenshot(os.path.join(out, "paraview_%s.png" % tag))
        gpu = scene.prismoid(a["prismoid"], with_gradient, tf, os.path.join(out, "render_%s.pfm" % tag), ["--mode", "interval-sorted"])
        reference = scene.prismoid(a["prismoid"], with_gradient, tf, os.path.join(out, "reference_%s.pfm" % tag), ["--mode", "reference"])
        covered = (np.abs(reference - np.array(pvtest.BACKGROUND)).max(axis=2) > 0.05).mean()
        d_render = pvtest.levels(pv, gpu)
        d_reference = pvtest.levels(pv, reference)
        print("colour by %s: the volume covers %.2f of the image; ParaView against prismoid render of '%s': largest %.3f "
              "levels; against the CPU reference: largest %.3f" % (colouring[2], covered, own, d_render.max(), d_reference.max()),
              flush=True)
        if covered < 0.2 or d_render.max() > BOUND or d_reference.max() > BOUND:
            failures += 1
        Delete(scene.rep)
    if failures:
        pvtest.fail("%d of 2 colourings beyond the bound" % failures)
    print("PASS")


main()
