"""What the plugin does with input it cannot draw: a clear ParaView error naming the problem, the
rest of the frame drawn, never a crash or a hang. Each case runs in a child pvpython, so that a
crash is seen as one (the parent checks the child's exit and its output).

  plugin_errors.py --pvpython scripts/pvpython.sh --plugin SO --out DIR   (the parent)
  plugin_errors.py --case NAME --plugin SO --out DIR                      (one case, in a child)
"""
import os
import subprocess

import numpy as np

import pvtest

# case: (environment for the child, what its output must contain, whether the volume is drawn)
CASES = {
    # ParaView draws a grid coloured by nothing as nothing (its own mappers too): nothing breaks,
    # and the plugin says why (it once said nothing).
    "no-array": ({}, "Prismoid volume: no array to colour by", False),
    "non-finite": ({}, "Prismoid volume: the array 'bad' has a non-finite value", False),
    "empty": ({}, "Prismoid volume: the input has no cells", False),
    # A constant array falls on the opacity function's first point, 0 here: nothing is drawn,
    # and said.
    "constant": ({}, "Prismoid volume: the opacity function is 0 over every value of the array 'c' (5, constant)", False),
    "no-device": ({"VK_ICD_FILENAMES": "/nonexistent/icd.json", "VK_DRIVER_FILES": "/nonexistent/icd.json"}, "Prismoid volume:", False),
    "hexahedra": ({}, "HEXAHEDRA OK", None),
}


def child(name, a):
    from paraview.simple import (ColorBy, GetOpacityTransferFunction, ProgrammableFilter, Render, SaveScreenshot, Show, Threshold)
    pvtest.load_plugin(a["plugin"])
    out = a["out"]
    vtu = os.path.join(out, "wavelet.vtu")
    if not os.path.exists(vtu):
        pvtest.write_wavelet(vtu, half=4)
    scene = pvtest.Scene(vtu)
    if name == "no-array":
        ColorBy(scene.rep, None)
    elif name == "non-finite":
        bad = ProgrammableFilter(Input=scene.reader)
        bad.Script = ("import numpy as np\n"
                      "a = np.array(inputs[0].PointData['RTData'], dtype=np.float64)\n"
                      "a[7] = np.nan\n"
                      "output.ShallowCopy(inputs[0].VTKObject)\n"
                      "output.PointData.append(a, 'bad')\n")
        scene.rep.Visibility = 0
        rep = Show(bad, scene.view)
        rep.Representation = "Prismoid Volume"
        ColorBy(rep, ("POINTS", "bad"))
    elif name == "empty":
        lo, hi = scene.range
        nothing = Threshold(Input=scene.reader, Scalars=["POINTS", "RTData"], LowerThreshold=hi + 1.0, UpperThreshold=hi + 2.0)
        scene.rep.Visibility = 0
        rep = Show(nothing, scene.view)
        rep.Representation = "Prismoid Volume"
        ColorBy(rep, ("POINTS", "RTData"))
    elif name == "constant":
        from paraview.simple import Calculator
        constant = Calculator(Input=scene.reader, Function="5", ResultArrayName="c")
        scene.rep.Visibility = 0
        rep = Show(constant, scene.view)
        rep.Representation = "Prismoid Volume"
        ColorBy(rep, ("POINTS", "c"))
        pwf = GetOpacityTransferFunction("c")
        pwf.Points = [5.0, 0.0, 0.5, 0.0, 6.0, 1.0, 0.5, 0.0]
    elif name == "hexahedra":
        from paraview.simple import Wavelet
        voxels = Threshold(Input=Wavelet(WholeExtent=[-4, 4, -4, 4, -4, 4]), Scalars=["POINTS", "RTData"], LowerThreshold=0.0, UpperThreshold=1e9)
        scene.rep.Visibility = 0
        rep = Show(voxels, scene.view)
        rep.Representation = "Prismoid Volume"
        ColorBy(rep, ("POINTS", "RTData"))
    image = scene.screenshot(os.path.join(out, "error_%s.png" % name))
    drawn = float((np.abs(image / 255.0 - np.array(pvtest.BACKGROUND)).max(axis=2) > 0.02).mean())
    print("%s: %.3f of the image differs from the background" % (name.upper(), drawn), flush=True)
    if name == "empty" and drawn == 0.0:
        print("EMPTY DRAWN NOTHING", flush=True)
    if name == "hexahedra":
        print("HEXAHEDRA OK", flush=True)


def parent(a):
    failures = 0
    for name, (env_extra, expected, drawn) in CASES.items():
        env = dict(os.environ)
        env.update(env_extra)
        cmd = [a["pvpython"], os.path.abspath(__file__), "--case", name, "--plugin", a["plugin"], "--out", a["out"]]
        try:
            run = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
        except subprocess.TimeoutExpired:
            print("%s: hung (no end in 300 s)" % name)
            failures += 1
            continue
        text = run.stdout + run.stderr
        crashed = run.returncode != 0 or "Loguru caught a signal" in text or "Segmentation fault" in text
        ok = not crashed and expected in text
        if drawn is False:
            ok = ok and ("%s: 0.000 of the image" % name.upper()) in text
        print("%s: %s (exit %d)" % (name, "as expected" if ok else "NOT as expected", run.returncode), flush=True)
        for line in text.splitlines():
            if "Prismoid volume:" in line or line.startswith(name.upper()):
                print("   " + line.strip()[:300])
        if not ok:
            failures += 1
            print(text[-3000:])
    if failures:
        pvtest.fail("%d of %d cases not as expected" % (failures, len(CASES)))
    print("PASS")


def main():
    a = pvtest.options()
    if "case" in a:
        child(a["case"], a)
    else:
        parent(a)


main()
