#!/usr/bin/python3
"""Reads a `simulate --vtk DIR` folder with VTK's own readers (Debian's
python3-vtk9) and checks what ParaView will show: frames.pvd names one .vtm
per frame; each .vtm has the named blocks body, surface (tet models),
instrument; the body carries its arrays; the instrument is placed at frame 0
and moves; the displacement is the points' motion from frame 0; the fixed
mask marks NFIXED nodes that never move.

usage: vtk_check.py DIR NFIXED; prints one line per failed check and exits 1
on any, else prints "ok: ..." and exits 0."""
import sys
import xml.etree.ElementTree as ET

import vtk

folder, nfixed = sys.argv[1], int(sys.argv[2])
failed = []


def check(cond, what):
    if not cond:
        failed.append(what)


frames = [(float(d.get("timestep")), d.get("file"))
          for d in ET.parse(folder + "/frames.pvd").getroot().iter("DataSet")]
check(len(frames) >= 2, "frames.pvd lists %d frames" % len(frames))


def blocks(vtm):
    r = vtk.vtkXMLMultiBlockDataReader()
    r.SetFileName(folder + "/" + vtm)
    r.Update()
    mb = r.GetOutput()
    out = {}
    for i in range(mb.GetNumberOfBlocks()):
        out[mb.GetMetaData(i).Get(vtk.vtkCompositeDataSet.NAME())] = mb.GetBlock(i)
    return out


first, last = blocks(frames[0][1]), blocks(frames[-1][1])
check(sorted(first) == ["body", "instrument", "surface"], "blocks %s" % sorted(first))
body0, body1 = first["body"], last["body"]
pd, cd = body1.GetPointData(), body1.GetCellData()
for name in ("displacement", "velocity", "fixed", "driven"):
    check(pd.GetArray(name) is not None, "body lacks point data " + name)
for name in ("equivalent_green_strain", "von_mises_stress", "inverted"):
    check(cd.GetArray(name) is not None, "body lacks cell data " + name)
check(body1.GetCellType(0) == vtk.VTK_TETRA, "body cells are not tets")


def points(ds):
    return [ds.GetPoint(i) for i in range(ds.GetNumberOfPoints())]


def tuples(a):
    return [a.GetTuple(i) for i in range(a.GetNumberOfTuples())]


def most(pairs):
    """The largest coordinate difference between paired 3-vectors."""
    return max((abs(p[k] - q[k]) for p, q in pairs for k in range(3)), default=0)


x0, x1 = points(body0), points(body1)
u = tuples(pd.GetArray("displacement"))
moved = [tuple(b[k] - a[k] for k in range(3)) for a, b in zip(x0, x1)]
scale = 1 + max(abs(c) for p in x0 for c in p)
check(most(zip(u, moved)) <= 1e-12 * scale, "displacement is not the motion from frame 0")
fixed = [int(t[0]) for t in tuples(pd.GetArray("fixed"))]
check(sum(fixed) == nfixed, "%d fixed nodes, not %d" % (sum(fixed), nfixed))
check(most((a, b) for a, b, f in zip(x0, x1, fixed) if f) == 0, "a fixed node moved")
check(most((p, (0, 0, 0)) for p in u) > 0, "nothing moved")
t0, t1 = points(first["instrument"]), points(last["instrument"])
check(most((p, t0[0]) for p in t0) > 0, "frame 0's instrument is collapsed to a point")
check(most(zip(t0, t1)) > 0, "the instrument does not move")
check(first["instrument"].GetPointData().GetArray("displacement") is None,
      "the instrument carries the body's arrays")
surf = last["surface"]
check(surf.GetNumberOfCells() > 0 and surf.GetCellType(0) == vtk.VTK_TRIANGLE,
      "the surface block has no triangles")
for f in failed:
    print("vtk_check:", f)
if not failed:
    print("ok: %d frames, body %d points %d cells, instrument %d points" %
          (len(frames), body1.GetNumberOfPoints(), body1.GetNumberOfCells(),
           last["instrument"].GetNumberOfPoints()))
sys.exit(1 if failed else 0)
