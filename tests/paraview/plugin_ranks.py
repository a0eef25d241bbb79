"""The plugin under MPI: `mpirun -np N pvbatch` with the grid spread over the ranks (ParaView's
RedistributeDataSet), each rank drawing its piece through the plugin and ParaView's ordered
compositing (IceT) joining them, gives the 1-rank image.

The bound, per pixel and channel, in 8-bit levels: 1 + N for N ranks. Each rank's image is a
premultiplied layer that IceT keeps in 8 bits a channel: the layer's colour and alpha are
rounded (0.5 each, alpha's scaled by what lies behind, <= 1), so each extra layer along a ray adds
up to 1 level; the 1-rank image carries its own rounding (about 1). A seam, cells composited out
of order along a piece's boundary, would show as lines tens of levels off; the mean, at most 0.25
levels, says the differences are rounding spread over the image and not such lines.

Also: the same grid unsplit (all on rank 0, the other ranks' pieces empty) on 4 ranks.

  plugin_ranks.py --pvpython scripts/pvpython.sh --plugin SO --out DIR          (the driver, pvpython)
  plugin_ranks.py --worker N --backend B --split 0|1 --plugin SO --out DIR     (under mpirun, pvbatch)
"""
import os
import subprocess

import numpy as np

import pvtest


def worker(a):
    from paraview import servermanager
    from paraview.simple import ColorBy, ProcessIdScalars, RedistributeDataSet, Show
    pvtest.load_plugin(a["plugin"])
    ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    if ranks != int(a["worker"]):
        pvtest.fail("asked for %s ranks, running on %d" % (a["worker"], ranks))
    scene = pvtest.Scene(os.path.join(a["out"], "wavelet.vtu"))
    source = scene.reader
    if a["split"] == "1":
        source = RedistributeDataSet(Input=source)
    ids = ProcessIdScalars(Input=source)
    ids.UpdatePipeline()
    lo, hi = ids.PointData["ProcessId"].GetRange()
    print("RANKS %d: cells on ranks %d to %d, %d cells in all" % (ranks, lo, hi, ids.GetDataInformation().GetNumberOfCells()), flush=True)
    scene.rep.Visibility = 0
    rep = Show(ids, scene.view)
    rep.Representation = "Prismoid Volume"
    ColorBy(rep, ("POINTS", "RTData"))
    rep.ScalarOpacityUnitDistance = scene.unit_distance
    rep.PrismoidBackend = int(a["backend"])
    scene.screenshot(os.path.join(a["out"], "ranks%s_backend%s_split%s.png" % (a["worker"], a["backend"], a["split"])))


def driver(a):
    out = a["out"]
    pvtest.write_wavelet(os.path.join(out, "wavelet.vtu"))
    # pvpython, itself an MPI program, leaves its own MPI's variables in the environment: a
    # nested mpirun must not see them.
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PRTE_"))}
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    failures = 0

    def run(ranks, backend, split):
        cmd = ["mpirun", "--oversubscribe", "-np", str(ranks), a["pvpython"], "--batch", os.path.abspath(__file__),
               "--worker", str(ranks), "--backend", str(backend), "--split", str(split), "--plugin", a["plugin"], "--out", out]
        done = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600)
        text = done.stdout + done.stderr
        for line in text.splitlines():
            if line.startswith("RANKS") or "Prismoid volume:" in line or line.startswith("FAIL"):
                print("   " + line.strip())
        if done.returncode != 0 or "Loguru caught a signal" in text:
            print(text[-3000:])
            pvtest.fail("mpirun -np %d exited %d" % (ranks, done.returncode))
        return pvtest.read_png(os.path.join(out, "ranks%d_backend%d_split%d.png" % (ranks, backend, split)))

    for backend in (0, 1):
        one = run(1, backend, 1)
        for ranks, split in ((2, 1), (4, 1), (4, 0)):
            image = run(ranks, backend, split)
            d = np.abs(image - one).max(axis=2)
            bound = 1.0 + ranks
            ok = d.max() <= bound and d.mean() <= 0.25
            print("backend %d, %d ranks%s: against 1 rank largest %.0f levels (bound %.0f), mean %.3f: %s"
                  % (backend, ranks, "" if split else " (all cells on rank 0)", d.max(), bound, d.mean(), "ok" if ok else "NOT ok"), flush=True)
            failures += 0 if ok else 1
    if failures:
        pvtest.fail("%d comparisons beyond the bound" % failures)
    print("PASS")


def main():
    a = pvtest.options()
    if "worker" in a:
        worker(a)
    else:
        driver(a)


main()
