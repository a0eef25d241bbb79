"""Runs a Python script under ParaView's pvpython or pvbatch with ParaView's own Python modules.

scripts/setup.sh unpacks python3-paraview under /opt/prismoid/python3-paraview (it conflicts
with the system VTK's python3-vtk9). pvpython puts the system's dist-packages, where VTK 9.1's
vtkmodules lives, ahead of PYTHONPATH; this moves the unpacked modules back in front before
anything imports vtkmodules, then runs the script as __main__ with its own arguments.
Used as: pvpython pvrun.py SCRIPT [ARGS...] (scripts/pvpython.sh does it).
"""
import os
import runpy
import sys

root = os.environ.get("PRISMOID_PARAVIEW_PYTHON", "/opt/prismoid/python3-paraview") + "/usr/lib/python3/dist-packages"
if root in sys.path:
    sys.path.remove(root)
sys.path.insert(0, root)
if len(sys.argv) < 2:
    sys.exit("usage: pvrun.py SCRIPT [ARGS...]")
sys.argv = sys.argv[1:]
sys.path.insert(1, os.path.dirname(os.path.abspath(sys.argv[0])))
runpy.run_path(sys.argv[0], run_name="__main__")
