"""ParaView draws a grid through the plugin; the image equals `prismoid render` of the same camera,
array and transfer function, and the CPU double-precision reference, within the bound below.

The bound, in 8-bit levels, per channel and pixel. The plugin hands OpenGL its frame as float
premultiplied colour and alpha; ParaView's framebuffer holds 8 bits a channel, so the blending
unit quantizes the source colour (0.5) and alpha (0.5 times the background, <= 0.5) and rounds
the result (0.5); the background it blends over was itself rounded to 8 bits when cleared (0.5,
times the volume's transmittance). So 2.0. Against the CPU reference the GPU's own error adds
about 0.03 levels on such a grid (RMSE ~1e-6, largest ~1e-4, measured by render
--reference-error), inside the same bound.
"""
import os

import numpy as np

import pvtest

BOUND = 2.0


def main():
    a, out, vtu, tf = pvtest.start()
    black = os.path.join(out, "tf_black.json")
    pvtest.write_prismoid_tf(black, black=True)
    scene = pvtest.Scene(vtu)
    reference = scene.prismoid(a["prismoid"], vtu, tf, os.path.join(out, "reference.pfm"), ["--mode", "reference"])
    # Some volume must show, or the comparison proves nothing.
    background = np.array(pvtest.BACKGROUND)
    covered = (np.abs(reference - background).max(axis=2) > 0.05).mean()
    if covered < 0.2:
        pvtest.fail("the volume covers only %.2f of the image" % covered)
    black_reference = scene.prismoid(a["prismoid"], vtu, black, os.path.join(out, "reference_black.pfm"), ["--mode", "reference"])
    # (name, backend, ordering, quantity, prismoid render's mode)
    cases = [
        ("mesh backend, GPU sort", 0, 0, 0, ["--mode", "interval-sorted"]),
        ("mesh backend, exact order", 0, 1, 0, ["--mode", "interval-exact-order"]),
        ("compute backend", 1, 0, 0, ["--mode", "interval-exact-order", "--volume-backend", "compute"]),
        ("absorption only, mesh backend", 0, 0, 1, ["--mode", "interval-sorted"]),
    ]
    failures = 0
    for name, backend, ordering, quantity, flags in cases:
        scene.rep.PrismoidBackend = backend
        scene.rep.PrismoidOrdering = ordering
        scene.rep.PrismoidQuantity = quantity
        tag = "b%d_o%d_q%d" % (backend, ordering, quantity)
        pv = scene.screenshot(os.path.join(out, "paraview_%s.png" % tag))
        # Absorption only is emission-absorption with every colour black.
        gpu = scene.prismoid(a["prismoid"], vtu, black if quantity else tf, os.path.join(out, "render_%s.pfm" % tag), flags)
        reference_now = black_reference if quantity else reference
        d_render = pvtest.levels(pv, gpu)
        d_reference = pvtest.levels(pv, reference_now)
        print("%s: ParaView against prismoid render: largest %.3f levels, mean %.4f; against the CPU reference: "
              "largest %.3f, mean %.4f" % (name, d_render.max(), d_render.mean(), d_reference.max(), d_reference.mean()), flush=True)
        if d_render.max() > BOUND or d_reference.max() > BOUND:
            failures += 1
            print("  beyond %.1f levels: %d pixels" % (BOUND, int((np.maximum(d_render, d_reference) > BOUND).sum())))
    # Hexahedra: ParaView's volume representation cuts them into tetrahedra before the plugin sees
    # them, `prismoid render` cuts them itself; both use VTK's ordered split (vtkDataSetTriangleFilter,
    # tetrahedra only), so the images agree within the same bound.
    voxels = os.path.join(out, "wavelet_voxels.vtu")
    pvtest.write_wavelet_voxels(voxels)
    hex_scene = pvtest.Scene(voxels)
    hex_scene.rep.PrismoidBackend = 1
    pv = hex_scene.screenshot(os.path.join(out, "paraview_hexahedra.png"))
    gpu = hex_scene.prismoid(a["prismoid"], voxels, tf, os.path.join(out, "render_hexahedra.pfm"),
                             ["--mode", "interval-exact-order", "--volume-backend", "compute"])
    d = pvtest.levels(pv, gpu)
    print("hexahedra, compute backend: ParaView against prismoid render: largest %.3f levels, mean %.4f" % (d.max(), d.mean()), flush=True)
    if d.max() > BOUND:
        failures += 1
    if failures:
        pvtest.fail("%d of %d cases beyond the bound" % (failures, len(cases) + 1))
    print("PASS")


main()
