"""The plugin beside ParaView's own unstructured-grid volume mappers, in pvpython or pvbatch: the
same grid, camera, colour map and opacity function; time per frame (wall, ParaView's Render: the
whole frame as a user waits for it) and error against Prismoid's CPU double-precision reference,
in 8-bit levels of ParaView's image. Results: docs/results.md ("Inside ParaView").

  scripts/pvpython.sh paraview/bench.py --prismoid build/app/prismoid --plugin SO --out DIR \\
      [--half 16] [--size 512x384] [--frames 5] [--mappers all|prismoid]
  mpirun -np N scripts/pvpython.sh --batch paraview/bench.py ... --mappers prismoid --split 1
  scripts/pvpython.sh paraview/bench.py ... --steps N [--rounds R]

--steps N: a time series instead (a .pvd of N steps of that grid, RTData scaled by 0.6 to 1.4),
stepped through with ParaView's animation time, the plugin beside ParaView's projected
tetrahedra: each step's Render() timed (ParaView reads the step, moves it to the mapper, draws),
R rounds through the steps after one untimed round, then N frames of the last step without a
time change; and the plugin's uploads (the mesh whole, then fields alone).
"""
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "paraview"))
import pvtest  # noqa: E402

from paraview import servermanager  # noqa: E402
from paraview.simple import ColorBy, GetAnimationScene, RedistributeDataSet, Render, Show  # noqa: E402

PRISMOID = [("Prismoid, mesh backend, GPU sort", 0, 0), ("Prismoid, mesh backend, exact order", 0, 1),
            ("Prismoid, compute backend", 1, 0)]
VTK = ["Projected tetra", "Z sweep", "Bunyk ray cast"]


def use_mapper(scene, representation, backend, ordering, mapper):
    """ParaView's mapper `mapper`, or (None) the plugin with that backend and ordering."""
    scene.rep.Representation = representation
    if mapper:
        scene.rep.SelectMapper = mapper
    else:
        scene.rep.PrismoidBackend = backend
        scene.rep.PrismoidOrdering = ordering


def timed_render(scene, mapper):
    """One Render(): its wall ms, and the plugin's part of it (None for ParaView's mappers)."""
    start = time.perf_counter()
    Render(scene.view)
    ms = 1000.0 * (time.perf_counter() - start)
    if mapper:
        return ms, None
    scene.rep.UpdatePropertyInformation()
    return ms, scene.rep.GetPropertyValue("PrismoidLastFrameMilliseconds")


def steps_main(a, vtu, size):
    steps, rounds = int(a["steps"]), int(a.get("rounds", "2"))
    pvd = pvtest.write_series(vtu, a["out"], [0.6 + 0.8 * i / max(steps - 1, 1) for i in range(steps)], list(range(steps)))
    scene = pvtest.Scene(pvd, size=size, unit_distance=3.0 * int(a["half"]) / 6.0)
    cells = scene.reader.GetDataInformation().GetNumberOfCells()
    animation = GetAnimationScene()
    animation.UpdateAnimationUsingDataTimeSteps()
    cases = [(name, "Prismoid Volume", backend, ordering, None) for name, backend, ordering in PRISMOID[1:]]
    cases.append(("VTK Projected tetra", "Volume", 0, 0, "Projected tetra"))
    print("\n%d steps of the wavelet, %d tetrahedra each; %dx%d; %d rounds after one untimed" % (steps, cells, size[0], size[1], rounds))
    print("| mapper | a step's frame, median (best-worst) ms | the plugin's part, median ms | a still frame of the last step, median ms "
          "(plugin's part) | uploads (meshes, field sets) |")
    print("|---|---:|---:|---:|---|")
    for name, representation, backend, ordering, mapper in cases:
        use_mapper(scene, representation, backend, ordering, mapper)
        times, plugin = [], []
        for r in range(rounds + 1):
            for i in range(steps):
                animation.AnimationTime = float(i)
                frame = timed_render(scene, mapper)
                if r > 0:
                    times.append(frame[0])
                    if not mapper:
                        plugin.append(frame[1])
        # The same view without a time change, for comparison (same run, same step).
        still, still_plugin = [], []
        for _ in range(steps):
            frame = timed_render(scene, mapper)
            still.append(frame[0])
            if not mapper:
                still_plugin.append(frame[1])
        uploads = ""
        if not mapper:
            scene.rep.UpdatePropertyInformation()
            uploads = "%d, %d" % (scene.rep.GetPropertyValue("PrismoidMeshUploads"), scene.rep.GetPropertyValue("PrismoidFieldUploads"))
        print("| %s | %.0f (%.0f-%.0f) | %s | %.0f%s | %s |" % (
            name, statistics.median(times), min(times), max(times), "%.0f" % statistics.median(plugin) if plugin else "",
            statistics.median(still), " (%.0f)" % statistics.median(still_plugin) if still_plugin else "", uploads))
        sys.stdout.flush()


def main():
    a = {"half": "16", "size": "512x384", "frames": "5", "mappers": "all", "split": "0", "steps": "0"}
    a.update(pvtest.options())
    ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    pvtest.load_plugin(a["plugin"])
    vtu = os.path.join(a["out"], "wavelet_%s.vtu" % a["half"])
    if not os.path.exists(vtu):
        pvtest.write_wavelet(vtu, half=int(a["half"]))
    w, h = (int(x) for x in a["size"].split("x"))
    if a["steps"] != "0":
        steps_main(a, vtu, (w, h))
        return
    scene = pvtest.Scene(vtu, size=(w, h), unit_distance=3.0 * int(a["half"]) / 6.0)
    source = scene.reader
    if a["split"] == "1":
        source = RedistributeDataSet(Input=source)
        scene.rep.Visibility = 0
        rep = Show(source, scene.view)
        ColorBy(rep, ("POINTS", "RTData"))
        rep.ScalarOpacityUnitDistance = scene.unit_distance
        scene.rep = rep
    cells = source.GetDataInformation().GetNumberOfCells()
    tf = os.path.join(a["out"], "tf.json")
    pvtest.write_prismoid_tf(tf)
    reference = scene.prismoid(a["prismoid"], vtu, tf, os.path.join(a["out"], "reference_%s.pfm" % a["half"]), ["--mode", "reference"])
    rows = []
    cases = [(name, "Prismoid Volume", backend, ordering, None) for name, backend, ordering in PRISMOID]
    if a["mappers"] == "all":
        cases += [("VTK " + m, "Volume", 0, 0, m) for m in VTK]
    for name, representation, backend, ordering, mapper in cases:
        use_mapper(scene, representation, backend, ordering, mapper)
        Render(scene.view)  # first frame: uploads, pipelines, caches
        times, plugin = [], []
        for _ in range(int(a["frames"])):
            frame = timed_render(scene, mapper)
            times.append(frame[0])
            if not mapper:
                plugin.append(frame[1])
        image = scene.screenshot(os.path.join(a["out"], "bench_%d_%s.png" % (ranks, name.replace(" ", "_").replace(",", ""))))
        d = np.abs(image - 255.0 * reference)
        rows.append((name, statistics.median(times), min(times), statistics.median(plugin) if plugin else None,
                     float(np.sqrt((d ** 2).mean())), float(d.max())))
    print("\n%d rank(s); wavelet, %d tetrahedra; %dx%d; %s frames each (median, best)" % (ranks, cells, w, h, a["frames"]))
    print("| mapper | frame, median (best) ms | the plugin's part on rank 0, ms | RMSE vs CPU reference (8-bit levels) | largest |")
    print("|---|---:|---:|---:|---:|")
    for name, median, best, plugin, rmse, largest in rows:
        print("| %s | %.0f (%.0f) | %s | %.2f | %.0f |" % (name, median, best, "%.0f" % plugin if plugin is not None else "", rmse, largest))
    sys.stdout.flush()


main()
