"""Reader -> Contour -> OpenMesh Decimation in ParaView with the AVoS plugin,
run by pvbatch --symmetric on any number of MPI ranks (or by pvpython): every
rank prints its own work (its piece's triangles, owned and ghost, before and
after decimation, and its border vertices) and rank 0 writes the totals as
JSON for scripts/test-paraview.sh to compare across rank counts.
  pvbatch --symmetric PipelinePieces.py PLUGIN DATA_DIR OUT.json
"""

import json
import sys

from paraview.simple import Contour, LoadPlugin
from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes
from vtkmodules.vtkParallelCore import vtkMultiProcessController

plugin, data, out = sys.argv[1:4]
# The plugin's proxies (VolvisRawReader, OpenMeshDecimation) join globals().
LoadPlugin(plugin, remote=False, ns=globals())
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller else 0
ranks = controller.GetNumberOfProcesses() if controller else 1

reader = VolvisRawReader(  # noqa: F821
    FileName=data + "/volumes/Neghip.1.64x64x64.raw")
contour = Contour(Input=reader, ContourBy=["POINTS", "density"], Isosurfaces=[60.0],
                  ComputeScalars=0)
decimate = OpenMeshDecimation(  # noqa: F821
    Input=contour, TargetReduction=0.75, DecimaterType="Exact")
decimate.UpdatePipeline()


def local(proxy):
    """This rank's piece of a proxy's output."""
    return proxy.GetClientSideObject().GetOutputDataObject(0)


surface = local(contour)
ghosts = surface.GetCellData().GetArray(vtkDataSetAttributes.GhostArrayName())
owned = set()
ghost = set()
ownedCells = 0
for c in range(surface.GetNumberOfCells()):
    isGhost = ghosts is not None and ghosts.GetValue(c) & vtkDataSetAttributes.DUPLICATECELL
    ids = surface.GetCell(c).GetPointIds()
    for i in range(ids.GetNumberOfIds()):
        (ghost if isGhost else owned).add(ids.GetId(i))
    ownedCells += 0 if isGhost else 1
border = len(owned & ghost)
decimated = local(decimate).GetNumberOfCells()
mine = [ownedCells, surface.GetNumberOfCells() - ownedCells, decimated, border]
print("rank %d of %d: contour %d owned + %d ghost triangles, %d border vertices; "
      "decimated %d triangles" % (rank, ranks, mine[0], mine[1], mine[3], mine[2]), flush=True)

# Totals on rank 0.
totals = list(mine)
if controller and ranks > 1:
    from vtkmodules.vtkCommonCore import vtkIdTypeArray
    send = vtkIdTypeArray()
    for v in mine:
        send.InsertNextValue(v)
    receive = vtkIdTypeArray()
    controller.Reduce(send, receive, 2, 0)  # 2: sum
    totals = [receive.GetValue(i) for i in range(4)] if rank == 0 else totals
if rank == 0:
    with open(out, "w") as f:
        json.dump({"ranks": ranks, "owned": totals[0], "ghost": totals[1],
                   "decimated": totals[2], "border": totals[3]}, f)
    print("totals: %s" % totals, flush=True)
