#!/usr/bin/python3
"""Surface and tetrahedral mesh steps of datasets/fetch-real.sh, through VTK's Python bindings
(python3-vtk9, which libvtk9-dev already brings in).

  meshprep.py info SURFACE.off                  vertices, triangles, boundary and non-manifold edges
  meshprep.py simplify IN.off OUT.off TRIANGLES quadric decimation down to about TRIANGLES
  meshprep.py finish TETGEN.vtk OUT.vtk          binary legacy .vtk with a cell array 'extinction' = 1
                                                 and a point array 'height' (y, 0..1)
  meshprep.py count MESH.vtk                     number of cells of a legacy .vtk unstructured grid

Run with Debian's /usr/bin/python3: a python3 from elsewhere (pyenv) has no vtk module.
"""

import sys
from collections import Counter

import vtk


def read_off(path):
    """Vertices and triangles of an OFF file (polygons are fanned into triangles)."""
    with open(path) as f:
        tokens = []
        for line in f:
            tokens.extend(line.split("#", 1)[0].split())
    if not tokens or not tokens[0].endswith("OFF"):
        raise SystemExit(f"{path}: not an OFF file")
    nv, nf = int(tokens[1]), int(tokens[2])
    pos = 4
    points = [tuple(float(t) for t in tokens[pos + 3 * i: pos + 3 * i + 3]) for i in range(nv)]
    pos += 3 * nv
    triangles = []
    for _ in range(nf):
        k = int(tokens[pos])
        ids = [int(t) for t in tokens[pos + 1: pos + 1 + k]]
        pos += 1 + k
        triangles.extend((ids[0], ids[j], ids[j + 1]) for j in range(1, k - 1))
    return points, triangles


def write_off(path, points, triangles):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(points)} {len(triangles)} 0\n")
        f.writelines(f"{x:.9g} {y:.9g} {z:.9g}\n" for x, y, z in points)
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in triangles)


def edge_report(triangles):
    """Counts of edges used by one triangle (boundary: a hole) and by more than two (non-manifold)."""
    uses = Counter()
    for a, b, c in triangles:
        for u, v in ((a, b), (b, c), (c, a)):
            uses[(min(u, v), max(u, v))] += 1
    boundary = sum(1 for n in uses.values() if n == 1)
    non_manifold = sum(1 for n in uses.values() if n > 2)
    return len(uses), boundary, non_manifold


def info(path):
    points, triangles = read_off(path)
    edges, boundary, non_manifold = edge_report(triangles)
    closed = boundary == 0 and non_manifold == 0
    # For a closed orientable surface V - E + F = 2 - 2g.
    genus = (2 - (len(points) - edges + len(triangles))) / 2 if closed else None
    print(f"{path}: {len(points)} vertices, {len(triangles)} triangles, {boundary} boundary edges, "
          f"{non_manifold} non-manifold edges: " + (f"closed (genus {genus:g})" if closed else "OPEN"))


def to_polydata(points, triangles):
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for p in points:
        pts.InsertNextPoint(p)
    cells = vtk.vtkCellArray()
    for t in triangles:
        cells.InsertNextCell(3, t)
    poly = vtk.vtkPolyData()
    poly.SetPoints(pts)
    poly.SetPolys(cells)
    return poly


def simplify(src, dst, target_triangles):
    points, triangles = read_off(src)
    decimate = vtk.vtkQuadricDecimation()
    decimate.SetInputData(to_polydata(points, triangles))
    decimate.SetTargetReduction(1.0 - target_triangles / len(triangles))
    decimate.VolumePreservationOn()  # keeps the bunny's volume, so the tetrahedra fill the same shape
    decimate.Update()
    out = decimate.GetOutput()
    new_points = [out.GetPoint(i) for i in range(out.GetNumberOfPoints())]
    ids = vtk.vtkIdList()
    new_triangles = []
    polys = out.GetPolys()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        new_triangles.append(tuple(ids.GetId(k) for k in range(ids.GetNumberOfIds())))
    write_off(dst, new_points, new_triangles)
    edges, boundary, non_manifold = edge_report(new_triangles)
    if boundary or non_manifold:
        raise SystemExit(f"{dst}: decimation left {boundary} boundary and {non_manifold} non-manifold edges")


def read_grid(path):
    reader = vtk.vtkUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def finish(src, dst):
    grid = read_grid(src)
    if grid.GetNumberOfCells() == 0:
        raise SystemExit(f"{src}: no cells read")
    types = {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())}
    if types != {vtk.VTK_TETRA}:
        raise SystemExit(f"{src}: cell types {sorted(types)}, expected tetrahedra only")
    # TetGen writes no arrays; a constant extinction makes the timing runs' input explicit.
    sigma = vtk.vtkFloatArray()
    sigma.SetName("extinction")
    sigma.SetNumberOfValues(grid.GetNumberOfCells())
    sigma.Fill(1.0)
    grid.GetCellData().AddArray(sigma)
    # A smooth point field for colour (transfer-function) runs: height along y, 0 to 1.
    y0, y1 = grid.GetBounds()[2:4]
    height = vtk.vtkFloatArray()
    height.SetName("height")
    height.SetNumberOfValues(grid.GetNumberOfPoints())
    for i in range(grid.GetNumberOfPoints()):
        height.SetValue(i, (grid.GetPoint(i)[1] - y0) / (y1 - y0) if y1 > y0 else 0.0)
    grid.GetPointData().AddArray(height)
    writer = vtk.vtkUnstructuredGridWriter()
    writer.SetFileName(dst)
    writer.SetFileTypeToBinary()
    # Format 4.2 stores cell indices as 32-bit integers (5.1 as 64-bit): the armadillo shrinks from
    # about 50 MB to 32 MB, which matters when it travels to the GPU machine.
    writer.SetFileVersion(vtk.vtkDataWriter.VTK_LEGACY_READER_VERSION_4_2)
    writer.SetInputData(grid)
    if not writer.Write():
        raise SystemExit(f"{dst}: VTK could not write the file")
    print(f"{dst}: {grid.GetNumberOfCells()} tetrahedra, {grid.GetNumberOfPoints()} points")


def main(argv):
    if len(argv) == 3 and argv[1] == "info":
        info(argv[2])
    elif len(argv) == 5 and argv[1] == "simplify":
        simplify(argv[2], argv[3], int(argv[4]))
    elif len(argv) == 4 and argv[1] == "finish":
        finish(argv[2], argv[3])
    elif len(argv) == 3 and argv[1] == "count":
        print(read_grid(argv[2]).GetNumberOfCells())
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
