"""What the plugin's tests share: a small grid written as .vtu, ParaView set up to draw it with
the plugin, the same frame asked of `prismoid render`, images read back as numbers."""
import json
import math
import os
import struct
import subprocess
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403 (pvpython's API)
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

# The colour map and opacity function every test uses: linear RGB segments (no midpoint,
# sharpness or Lab interpolation), so that VTK's functions and Prismoid's are the same
# piecewise-linear functions of the scalar.
COLOURS = [0.0, 0.10, 0.20, 0.90, 0.5, 0.90, 0.90, 0.20, 1.0, 0.90, 0.10, 0.10]
OPACITY = [0.0, 0.0, 0.5, 0.0, 0.3, 0.05, 0.5, 0.0, 1.0, 0.9, 0.5, 0.0]
BACKGROUND = [0.2, 0.25, 0.3]


def fail(message):
    print("FAIL: " + message, flush=True)
    sys.exit(1)


def options():
    """The script's --name value pairs as a dict; --out's folder made."""
    a = {}
    it = iter(sys.argv[1:])
    for k in it:
        a[k.lstrip("-")] = next(it)
    if "out" in a:
        os.makedirs(a["out"], exist_ok=True)
    return a


def args():
    """--prismoid BIN --plugin SO --out DIR"""
    a = options()
    for k in ("prismoid", "plugin", "out"):
        if k not in a:
            fail("missing --" + k)
    return a


def start():
    """What most scripts begin with: their arguments, the plugin loaded, the wavelet grid and the
    test's transfer function written to --out. Returns (args, out, vtu, tf)."""
    a = args()
    load_plugin(a["plugin"])
    out = a["out"]
    vtu = os.path.join(out, "wavelet.vtu")
    write_wavelet(vtu)
    tf = os.path.join(out, "tf.json")
    write_prismoid_tf(tf)
    return a, out, vtu, tf


def load_plugin(path):
    LoadPlugin(path, ns=globals())


def write_wavelet(path, half=6):
    """A tetrahedralized wavelet ((2 half)^3 voxels, 5 tetrahedra each) with its point array RTData."""
    w = Wavelet(WholeExtent=[-half, half, -half, half, -half, half])
    t = Tetrahedralize(Input=w)
    SaveData(path, proxy=t)
    Delete(t)
    Delete(w)


def write_scaled(source, path, scale, offset):
    """`source`'s grid with every point p moved to (p + offset) * scale."""
    reader = XMLUnstructuredGridReader(FileName=[source])
    t = Transform(Input=reader)
    t.Transform = "Transform"
    t.Transform.Translate = [o * scale for o in offset]
    t.Transform.Scale = [scale, scale, scale]
    SaveData(path, proxy=t)
    Delete(t)
    Delete(reader)


def write_wavelet_voxels(path, half=6):
    """The same wavelet as hexahedral cells (a Threshold keeping every voxel): ParaView's volume
    representation and `prismoid render` each cut them into tetrahedra themselves."""
    w = Wavelet(WholeExtent=[-half, half, -half, half, -half, half])
    t = Threshold(Input=w, Scalars=["POINTS", "RTData"], LowerThreshold=-1e30, UpperThreshold=1e30)
    SaveData(path, proxy=t)
    Delete(t)
    Delete(w)


def srgb(c):
    return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1.0 / 2.4) - 0.055


def write_prismoid_tf(path, black=False):
    """The same colour map for `prismoid render`: it reads ParaView's JSON as sRGB and decodes it to
    linear, while VTK uses the numbers as they are; so the file holds their sRGB encoding. `black`:
    every colour black (absorption only, the plugin's second quantity)."""
    rgb = []
    for i in range(0, len(COLOURS), 4):
        c = [0.0, 0.0, 0.0] if black else COLOURS[i + 1:i + 4]
        rgb += [COLOURS[i]] + [srgb(x) for x in c]
    with open(path, "w") as f:
        json.dump([{"Name": "test", "ColorSpace": "RGB", "RGBPoints": rgb, "Points": OPACITY}], f)


class Scene:
    """ParaView's view of a .vtu through the plugin, the camera fixed."""

    def __init__(self, vtu, size=(240, 180), unit_distance=3.0, array="RTData", scale=1.0, offset=(0.0, 0.0, 0.0)):
        """`scale`, `offset`: the camera and unit distance for a copy of the grid scaled by `scale`
        and then moved by `offset` times it (write_scaled)."""
        self.size = size
        self.render_array = array  # what `prismoid render` colours by (a component's own array for a vector)
        unit_distance *= scale
        self.unit_distance = unit_distance
        # A time series (.pvd) through ParaView's own collection reader, an Exodus file through the
        # reader ParaView picks for it, each at its first step.
        if vtu.endswith(".pvd"):
            self.reader = PVDReader(FileName=vtu)
        elif vtu.endswith(".exo"):
            self.reader = OpenDataFile(vtu)
        else:
            self.reader = XMLUnstructuredGridReader(FileName=[vtu])
        self.reader.UpdatePipeline()
        self.range = self.reader.PointData[array].GetRange()
        self.view = CreateView("RenderView")
        self.view.ViewSize = list(size)
        self.view.OrientationAxesVisibility = 0
        self.view.UseColorPaletteForBackground = 0
        self.view.Background = BACKGROUND
        self.view.UseFXAA = 0
        self.rep = Show(self.reader, self.view)
        self.rep.Representation = "Prismoid Volume"
        ColorBy(self.rep, ("POINTS", array))
        self.set_functions(array)
        self.rep.ScalarOpacityUnitDistance = unit_distance
        Render(self.view)  # the first render resets the camera: the fixed one is set after it
        cam = self.view.GetActiveCamera()
        place = lambda p: [(x + o) * scale for x, o in zip(p, offset)]
        cam.SetPosition(*place((9.0, 14.0, 31.0)))
        cam.SetFocalPoint(*place((0.3, -0.2, 0.1)))
        cam.SetViewUp(0.0, 1.0, 0.0)
        cam.SetViewAngle(30.0)
        Render(self.view)  # the clipping range (the near plane given to prismoid render) follows the camera

    def set_functions(self, array):
        """The test's colour map and opacity over self.range, on `array`'s functions, never rescaled."""
        lo, hi = self.range
        lut = GetColorTransferFunction(array)
        lut.AutomaticRescaleRangeMode = "Never"
        lut.ColorSpace = "RGB"
        lut.Discretize = 0
        lut.RGBPoints = [lo + x * (hi - lo) if i % 4 == 0 else x for i, x in enumerate(COLOURS)]
        pwf = GetOpacityTransferFunction(array)
        pwf.Points = [lo + x * (hi - lo) if i % 4 == 0 else x for i, x in enumerate(OPACITY)]
        return lut

    def screenshot(self, path):
        Render(self.view)
        SaveScreenshot(path, self.view, ImageResolution=list(self.size), TransparentBackground=0)
        return read_png(path)

    def camera_args(self):
        cam = self.view.GetActiveCamera()
        vec = lambda v: ",".join(repr(float(x)) for x in v)
        return ["--eye", vec(cam.GetPosition()), "--target", vec(cam.GetFocalPoint()), "--up", vec(cam.GetViewUp()),
                "--fovy", repr(cam.GetViewAngle()), "--near", repr(cam.GetClippingRange()[0])]

    def prismoid(self, binary, vtu, tf_json, out, extra):
        lo, hi = self.range
        cmd = [binary, "render", vtu, "--quantity", "color", "--array", self.render_array, "--tf", tf_json,
               "--tf-range", "%r,%r" % (lo, hi), "--density-scale", repr(1.0 / self.unit_distance),
               "--background", ",".join(repr(x) for x in BACKGROUND), "--size", "%dx%d" % self.size,
               "--output", out] + self.camera_args() + extra
        run = subprocess.run(cmd, capture_output=True, text=True)
        if run.returncode != 0:
            fail(" ".join(cmd) + " exited " + str(run.returncode) + ":\n" + run.stdout + run.stderr)
        return read_pfm(out)


def read_png(path):
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    image = r.GetOutput()
    w, h, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3]
    return pixels[::-1].astype(np.float64)  # row 0 at the top


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    channels = 3 if kind == b"PF" else 1
    return data.reshape(h, w, channels)[::-1].astype(np.float64)  # PFM rows run bottom to top


def levels(pv, linear):
    """How far ParaView's 8-bit image is from a linear image, in 8-bit levels, per pixel."""
    return np.abs(pv - 255.0 * linear).max(axis=2)


def write_series(vtu, out, scales, times):
    """A ParaView collection (.pvd) beside copies of `vtu` whose RTData is scaled by `scales`, one
    step each at `times`, as ParaView writes one. Returns the .pvd's path."""
    entries = []
    for i, scale in enumerate(scales):
        reader = XMLUnstructuredGridReader(FileName=[vtu])
        calc = Calculator(Input=reader, Function="RTData*%r" % scale, ResultArrayName="RTData")
        name = "step_%d.vtu" % i
        SaveData(os.path.join(out, name), proxy=calc)
        Delete(calc)
        Delete(reader)
        entries.append('    <DataSet timestep="%r" part="0" file="%s"/>\n' % (times[i], name))
    pvd = os.path.join(out, "series.pvd")
    with open(pvd, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n')
        f.writelines(entries)
        f.write("  </Collection>\n</VTKFile>\n")
    return pvd


def check_steps(a, scene, data, tf, out, times, bound):
    """ParaView's time moved to each of `times` and the frame drawn through the plugin: each
    step's image against `prismoid render DATA --time-step N` and the CPU reference, within
    `bound` levels; the steps must differ (else matching each proves nothing); and the steps share
    their points and cells, so the plugin uploads the mesh once and a field set per later step.
    Fails the test otherwise."""
    animation = GetAnimationScene()
    animation.UpdateAnimationUsingDataTimeSteps()
    failures = 0
    images = []
    for i, t in enumerate(times):
        animation.AnimationTime = t
        Render(scene.view)
        pv = scene.screenshot(os.path.join(out, "paraview_step%d.png" % i))
        gpu = scene.prismoid(a["prismoid"], data, tf, os.path.join(out, "render_step%d.pfm" % i), ["--mode", "interval-sorted", "--time-step", str(i)])
        reference = scene.prismoid(a["prismoid"], data, tf, os.path.join(out, "reference_step%d.pfm" % i), ["--mode", "reference", "--time-step", str(i)])
        d_render = levels(pv, gpu)
        d_reference = levels(pv, reference)
        print("step %d (t = %r): ParaView against prismoid render --time-step %d: largest %.3f levels; against the CPU reference: "
              "largest %.3f" % (i, t, i, d_render.max(), d_reference.max()), flush=True)
        if d_render.max() > bound or d_reference.max() > bound:
            failures += 1
        images.append(reference)
    for i in range(1, len(images)):
        change = np.abs(images[i] - images[0]).max()
        print("step %d against step 0: largest difference %.3f (linear colour)" % (i, change), flush=True)
        if change < 0.02:
            fail("steps 0 and %d look alike: the steps prove nothing" % i)
    if failures:
        fail("%d of %d steps beyond the bound" % (failures, len(times)))
    scene.rep.UpdatePropertyInformation()
    meshes = scene.rep.GetPropertyValue("PrismoidMeshUploads")
    fields = scene.rep.GetPropertyValue("PrismoidFieldUploads")
    print("uploads: %d mesh, %d field sets" % (meshes, fields), flush=True)
    if meshes != 1 or fields != len(times) - 1:
        fail("expected the mesh uploaded once and %d field sets, got %d and %d" % (len(times) - 1, meshes, fields))
