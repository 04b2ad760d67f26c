"""vtkAnalyticVolumeSource from Python: the linear ramp is exact, the
Marschner-Lobb signal has its known value at the origin."""

import avos
from vtkmodules.test import Testing


class TestAnalyticVolumeSourcePython(Testing.vtkTest):
    def test_ramp(self):
        source = avos.vtkAnalyticVolumeSource()
        source.SetFunctionToLinearRamp()
        source.SetRampAxis(1)
        source.SetDimensions(5, 9, 3)
        source.SetBounds(0, 4, 0, 8, 0, 2)
        source.SetScalarScale(2.0)
        source.SetScalarShift(1.0)
        source.Update()
        image = source.GetOutput()
        for j in range(9):
            self.assertEqual(image.GetScalarComponentAsDouble(2, j, 1, 0), 1.0 + 2.0 * j)

    def test_marschner_lobb(self):
        source = avos.vtkAnalyticVolumeSource()
        source.SetFunctionToMarschnerLobb()
        source.SetDimensions(41, 41, 41)
        source.Update()
        value = source.GetOutput().GetScalarComponentAsDouble(20, 20, 20, 0)
        self.assertAlmostEqual(value, 0.6, places=6)


if __name__ == "__main__":
    Testing.main([(TestAnalyticVolumeSourcePython, "test")])
