"""Time and memory per rank of the distributed pipeline on a larger volume
(pvbatch --symmetric on 1, 2, ... ranks): an analytic Marschner-Lobb volume
(AVoS Analytic Volume, N^3, every rank computing only its extent) ->
Contour -> OpenMesh Decimation (75 %), and Volume on Surface on the contour
(its own source on the volume port: the whole volume on every rank). Each
rank prints its seconds and peak resident memory; rank 0 appends a JSON line
to OUT.
  pvbatch --symmetric Scaling.py PLUGIN N OUT
"""

import json
import resource
import sys
import time

from paraview.simple import (Contour, GetColorTransferFunction, GetOpacityTransferFunction,
                             LoadPlugin)
from vtkmodules.vtkParallelCore import vtkMultiProcessController

plugin, size, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
LoadPlugin(plugin, remote=False, ns=globals())
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller else 0
ranks = controller.GetNumberOfProcesses() if controller else 1


def volume():
    return AVoSAnalyticVolume(Function="Marschner-Lobb",  # noqa: F821
                              Dimensions=[size, size, size])


start = time.perf_counter()
contour = Contour(Input=volume(), ContourBy=["POINTS", "scalars"], Isosurfaces=[0.5],
                  ComputeNormals=1, ComputeScalars=0)
decimate = OpenMeshDecimation(Input=contour, TargetReduction=0.75)  # noqa: F821
colours = GetColorTransferFunction("scalars")
colours.RGBPoints = [0.0, 0.1, 0.2, 1.0, 1.0, 1.0, 0.4, 0.1]
opacity = GetOpacityTransferFunction("scalars")
opacity.Points = [0.0, 0.0, 0.5, 0.0, 1.0, 0.3, 0.5, 0.0]
vos = VolumeonSurface(  # noqa: F821
    Input=contour, Volume=volume(), ColorTransferFunction=colours,
    ScalarOpacityFunction=opacity, CameraPosition=[0.5, 0.8, 4.0])
decimate.UpdatePipeline()
vos.UpdatePipeline()
seconds = time.perf_counter() - start
memory = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # MiB
triangles = contour.GetClientSideObject().GetOutputDataObject(0).GetNumberOfCells()
print("rank %d of %d: %.2f s, %.0f MiB peak, %d contour triangles" % (
    rank, ranks, seconds, memory, triangles), flush=True)

if controller and ranks > 1:
    from vtkmodules.vtkCommonCore import vtkDoubleArray
    send = vtkDoubleArray()
    send.InsertNextValue(seconds)
    send.InsertNextValue(memory)
    receive = vtkDoubleArray()
    controller.Reduce(send, receive, 0, 0)  # 0: max
    seconds, memory = receive.GetValue(0), receive.GetValue(1)
if rank == 0:
    with open(out, "a") as f:
        f.write(json.dumps({"ranks": ranks, "size": size, "seconds": seconds,
                            "memory": memory}) + "\n")
