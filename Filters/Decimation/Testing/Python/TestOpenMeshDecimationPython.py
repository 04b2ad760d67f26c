"""vtkOpenMeshDecimation from Python: the isosurface path of a pipeline
(source -> vtkFlyingEdges3D -> vtkOpenMeshDecimation) keeps normals and maps
every output vertex to its input vertex."""

import avos
from vtkmodules.test import Testing
from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D


class TestOpenMeshDecimationPython(Testing.vtkTest):
    def test_isosurface_path(self):
        volume = avos.vtkAnalyticVolumeSource()
        volume.SetFunctionToSphereDistance()
        volume.SetDimensions(40, 40, 40)
        contour = vtkFlyingEdges3D()
        contour.SetInputConnection(volume.GetOutputPort())
        contour.SetValue(0, 0.7)
        contour.ComputeNormalsOn()
        decimate = avos.vtkOpenMeshDecimation()
        decimate.SetInputConnection(contour.GetOutputPort())
        decimate.SetTargetReduction(0.75)
        decimate.Update()
        full = contour.GetOutput()
        out = decimate.GetOutput()
        self.assertAlmostEqual(decimate.GetAchievedReduction(), 0.75, delta=0.01)
        self.assertAlmostEqual(out.GetNumberOfPolys() / full.GetNumberOfPolys(), 0.25, delta=0.01)
        ids = out.GetPointData().GetArray("vtkOriginalPointIds")
        normals = out.GetPointData().GetNormals()
        self.assertIsNotNone(normals)
        for i in range(0, out.GetNumberOfPoints(), 37):
            j = ids.GetValue(i)
            self.assertEqual(out.GetPoint(i), full.GetPoint(j))
            self.assertEqual(normals.GetTuple3(i), full.GetPointData().GetNormals().GetTuple3(j))


if __name__ == "__main__":
    Testing.main([(TestOpenMeshDecimationPython, "test")])
