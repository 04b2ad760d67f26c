"""Reader -> Contour -> OpenMesh Decimation, and Volume on Surface on the
contour, in ParaView with the AVoS plugin, run by pvbatch --symmetric on any
number of MPI ranks (or by pvpython): every rank prints its own work (its
piece's triangles, owned and ghost, before and after decimation, its border
vertices, the vertices of its own triangles it coloured) and writes those
vertices' colours to OUT.rankK.json; rank 0 writes the totals to OUT.json,
for ComparePieces.py to compare across rank counts. (The colours are
compared on the contour: a decimated vertex's colour depends on its
normal, which the decimation of each piece changes.)
  pvbatch --symmetric PipelinePieces.py PLUGIN DATA_DIR OUT.json
"""

import json
import sys

from paraview.simple import (Contour, GetColorTransferFunction, GetOpacityTransferFunction,
                             LoadPlugin)
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
                  ComputeNormals=1, ComputeScalars=0)
decimate = OpenMeshDecimation(  # noqa: F821
    Input=contour, TargetReduction=0.75, DecimaterType="Exact")
colours = GetColorTransferFunction("density")
colours.RGBPoints = [0.0, 0.1, 0.2, 1.0, 255.0, 1.0, 0.4, 0.1]
opacity = GetOpacityTransferFunction("density")
opacity.Points = [0.0, 0.0, 0.5, 0.0, 255.0, 0.3, 0.5, 0.0]
# The volume port shares the contour's reader: each rank receives its piece
# of the volume, and the filter gathers the pieces into the whole volume
# (vtkPVVolumeOnSurfaceFilter::AssembleVolume). VolumeImage.py gives the
# volume port a reader of its own, the other way.
vos = VolumeonSurface(  # noqa: F821
    Input=contour, Volume=reader, ColorTransferFunction=colours,
    ScalarOpacityFunction=opacity, CameraPosition=[32.0, 20.0, 250.0],
    CameraFocalPoint=[32.0, 32.0, 32.0])
vos.UpdatePipeline()
decimate.UpdatePipeline()
vos.UpdatePropertyInformation()
cast = vos.GetPropertyValue("NumberOfRaysCast")


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
coloured = local(vos)
rgba = coloured.GetPointData().GetArray("VoSColors")
vertices = []
for i in sorted(owned):  # the points of this rank's own triangles
    vertices.append(list(coloured.GetPoint(i)) + [rgba.GetValue(4 * i + c) for c in range(4)])
with open("%s.rank%d.json" % (out, rank), "w") as f:
    json.dump(vertices, f)
# A new camera: the cone rays are cast again only if the volume changed,
# and the gathered volume must not look changed (it is reused).
vos.CameraPosition = [60.0, 40.0, 240.0]
vos.UpdatePipeline()
vos.UpdatePropertyInformation()
recast = vos.GetPropertyValue("NumberOfRaysCast")
print("rank %d of %d: %d rays cast, %d after a camera change" % (rank, ranks, cast, recast),
      flush=True)
mine = [ownedCells, surface.GetNumberOfCells() - ownedCells, decimated, border, cast, recast]
print("rank %d of %d: contour %d owned + %d ghost triangles, %d border vertices; "
      "decimated %d triangles; %d vertices coloured" % (rank, ranks, mine[0], mine[1], mine[3],
                                                         mine[2], len(vertices)), flush=True)

# Totals on rank 0.
totals = list(mine)
if controller and ranks > 1:
    from vtkmodules.vtkCommonCore import vtkIdTypeArray
    send = vtkIdTypeArray()
    for v in mine:
        send.InsertNextValue(v)
    receive = vtkIdTypeArray()
    controller.Reduce(send, receive, 2, 0)  # 2: sum
    totals = [receive.GetValue(i) for i in range(len(mine))] if rank == 0 else totals
if rank == 0:
    with open(out, "w") as f:
        json.dump({"ranks": ranks, "owned": totals[0], "ghost": totals[1],
                   "decimated": totals[2], "border": totals[3], "cast": totals[4],
                   "recast": totals[5]}, f)
    print("totals: %s" % totals, flush=True)
