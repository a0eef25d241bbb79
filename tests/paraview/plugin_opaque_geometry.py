"""A slice through the volume: the plugin's rays end at it, as the CPU reference's rays end at
the same plane. ParaView draws the slice first; the plugin reads its depth buffer. The reference
is made independently: each pixel ray's depth at the plane z = 0, computed here in closed form,
given to `prismoid render --mode reference --depth-limit` (colour over black and over white, for
the premultiplied colour C and the transmittance 1 - A), and composited over ParaView's own
image of the slice alone: expected = C + (1 - A) x slice image.

Bound, in 8-bit levels: as plugin_matches_render.py's, 2.0 (the blend's quantization of colour
and alpha, and its rounding; the slice image is the framebuffer's own content, so no background
rounding is added). The depth buffer's 24 bits move the ray's end by about 1e-6 of the depth,
far below a level. Pixels on the slice's outline (where rasterization and the closed form may
disagree about coverage) and their neighbours are left out and counted.
"""
import math
import os

import numpy as np

import pvtest
from paraview.simple import ColorBy, Show, Slice

BOUND = 2.0


def plane_depths(camera, w, h, half):
    """Per pixel (row 0 at the top), the depth along the viewing axis where the pixel-centre ray meets
    z = 0 inside the slice's square [-half, half]^2, +inf elsewhere; and that mask."""
    eye = np.array(camera.GetPosition())
    forward = np.array(camera.GetFocalPoint()) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, np.array(camera.GetViewUp()))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    tan_half = math.tan(math.radians(camera.GetViewAngle()) / 2.0)
    xs = (2.0 * (np.arange(w) + 0.5) / w - 1.0) * tan_half * w / h
    ys = (1.0 - 2.0 * (np.arange(h) + 0.5) / h) * tan_half
    dirs = forward[None, None, :] + xs[None, :, None] * right[None, None, :] + ys[:, None, None] * up[None, None, :]
    s = -eye[2] / dirs[:, :, 2]  # the ray eye + s dir meets z = 0; its depth along forward is s
    hit = eye[None, None, :] + s[:, :, None] * dirs
    inside = (s > 0) & (np.abs(hit[:, :, 0]) <= half) & (np.abs(hit[:, :, 1]) <= half)
    return np.where(inside, s, np.inf), inside


def write_pfm(path, image):
    h, w = image.shape
    with open(path, "wb") as f:
        f.write(b"Pf\n%d %d\n-1.0\n" % (w, h))
        f.write(np.ascontiguousarray(image[::-1], dtype="<f4").tobytes())  # PFM rows run bottom to top


def main():
    a = pvtest.args()
    pvtest.load_plugin(a["plugin"])
    out = a["out"]
    half = 6
    vtu = os.path.join(out, "wavelet.vtu")
    pvtest.write_wavelet(vtu, half=half)
    tf = os.path.join(out, "tf.json")
    pvtest.write_prismoid_tf(tf)
    scene = pvtest.Scene(vtu)
    w, h = scene.size
    cut = Slice(Input=scene.reader)
    cut.SliceType = "Plane"
    cut.SliceType.Origin = [0.0, 0.0, 0.0]
    cut.SliceType.Normal = [0.0, 0.0, 1.0]
    surface = Show(cut, scene.view)
    ColorBy(surface, None)
    surface.DiffuseColor = [0.85, 0.8, 0.7]
    failures = 0
    for backend in (1, 0):
        scene.rep.PrismoidBackend = backend
        scene.rep.Visibility = 0
        slice_only = scene.screenshot(os.path.join(out, "slice_only.png"))
        scene.rep.Visibility = 1
        both = scene.screenshot(os.path.join(out, "slice_and_volume_b%d.png" % backend))
        depths, inside = plane_depths(scene.view.GetActiveCamera(), w, h, half)
        limit = os.path.join(out, "depth_limit.pfm")
        write_pfm(limit, depths)
        saved = pvtest.BACKGROUND
        pvtest.BACKGROUND = [0.0, 0.0, 0.0]
        c = scene.prismoid(a["prismoid"], vtu, tf, os.path.join(out, "reference_black.pfm"), ["--mode", "reference", "--depth-limit", limit])
        pvtest.BACKGROUND = [1.0, 1.0, 1.0]
        white = scene.prismoid(a["prismoid"], vtu, tf, os.path.join(out, "reference_white.pfm"), ["--mode", "reference", "--depth-limit", limit])
        pvtest.BACKGROUND = saved
        transmittance = (white - c)[:, :, :1]
        expected = c + transmittance * slice_only / 255.0
        # Where the slice was drawn, by ParaView and by the closed form; their disagreements
        # (the outline) and the pixels next to them are left out.
        drawn = np.abs(slice_only / 255.0 - np.array(pvtest.BACKGROUND)).max(axis=2) > 0.02
        disagree = drawn != inside
        near = disagree.copy()
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                near |= np.roll(np.roll(disagree, dy, 0), dx, 1)
        d = pvtest.levels(both, expected)
        d[near] = 0.0
        # The slice must hide part of the volume, or the test proves nothing: the same frame without
        # the limit differs there.
        unlimited = scene.prismoid(a["prismoid"], vtu, tf, os.path.join(out, "reference_unlimited.pfm"), ["--mode", "reference"])
        hidden = pvtest.levels(255.0 * c + 255.0 * transmittance * np.array(pvtest.BACKGROUND), unlimited)[inside & ~near]
        ok = d.max() <= BOUND and inside.sum() > 1000 and hidden.max() > 20
        print("backend %d: the slice covers %d pixels (%d on its outline left out); against the reference ended at it: "
              "largest %.3f levels, mean %.4f; the slice hides up to %.0f levels of the volume: %s"
              % (backend, int(inside.sum()), int(near.sum()), d.max(), d.mean(), hidden.max(), "ok" if ok else "NOT ok"), flush=True)
        failures += 0 if ok else 1
    if failures:
        pvtest.fail("%d of 2 cases beyond the bound" % failures)
    print("PASS")


main()
