"""The isosurface path of the VoS pipeline in Python: volume ->
vtkFlyingEdges3D (with normals) -> vtkOpenMeshDecimation -> .vtp. Every
decimated vertex keeps its normal and records its original id.

    python3 isosurface.py VOLUME.vti|VOLUME.raw ISOVALUE REDUCTION OUTPUT.vtp
"""

import sys
import time

import avos
from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLPolyDataWriter


def main(argv):
    if len(argv) != 4:
        print(__doc__.strip().splitlines()[-1].strip(), file=sys.stderr)
        return 2
    volume, isovalue, reduction, output = argv[0], float(argv[1]), float(argv[2]), argv[3]
    reader = avos.vtkVolvisRawReader() if volume.endswith(".raw") else vtkXMLImageDataReader()
    reader.SetFileName(volume)
    contour = vtkFlyingEdges3D()
    contour.SetInputConnection(reader.GetOutputPort())
    contour.SetValue(0, isovalue)
    contour.ComputeNormalsOn()
    decimate = avos.vtkOpenMeshDecimation()
    decimate.SetInputConnection(contour.GetOutputPort())
    decimate.SetTargetReduction(reduction)

    start = time.perf_counter()
    decimate.Update()
    full, out = contour.GetOutput(), decimate.GetOutput()
    print("%d -> %d triangles (%.1f %% fewer) in %.2f s" % (
        full.GetNumberOfPolys(), out.GetNumberOfPolys(), 100 * decimate.GetAchievedReduction(),
        time.perf_counter() - start))
    ids = out.GetPointData().GetArray("vtkOriginalPointIds")
    print("vertex 0 of the decimated surface is vertex %d of the isosurface" % ids.GetValue(0))

    writer = vtkXMLPolyDataWriter()
    writer.SetInputConnection(decimate.GetOutputPort())
    writer.SetFileName(output)
    return 0 if writer.Write() else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
