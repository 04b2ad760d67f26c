"""The `avos` package exposes every wrapped class, and its readers work from
Python: a .tf1d and a raw volume from the shared data when present, else
files written here."""

import json
import math
import os
import tempfile

import avos
from vtkmodules.test import Testing


class TestReadersPython(Testing.vtkTest):
    def test_package_exposes_classes(self):
        for name in ("vtkTransferFunction1DReader", "vtkVolvisRawReader",
                     "vtkAnalyticVolumeSource"):
            self.assertTrue(hasattr(avos, name), name)

    def test_transfer_function(self):
        path = os.path.join(Testing.VTK_DATA_ROOT, "tf",
                            "Bonsai.1.256x256x256.linear.tf1d")
        if not os.path.exists(path):
            path = os.path.join(tempfile.mkdtemp(), "Bonsai.tf1d")
            with open(path, "w") as f:
                f.write("linear\n0\n5\n0.0 0.0 0.00 0\n0.0 0.5 0.00 60\n"
                        "1.0 0.3 0.07 110\n0.0 0.7 0.00 205\n0.6 0.0 0.00 255\n"
                        "6\n0.00 0\n0.20 60\n0.15 150\n0.15 180\n0.10 240\n0.05 255\n")
        reader = avos.vtkTransferFunction1DReader()
        reader.SetFileName(path)
        self.assertTrue(reader.Update())
        self.assertEqual(reader.GetColorTransferFunction().GetSize(), 5)
        self.assertEqual(reader.GetExtinctionFunction().GetSize(), 6)
        self.assertEqual(reader.GetExtinctionFunction().GetValue(60.0), 0.2)

        # As a ParaView preset: every knot back exactly, the opacity in the
        # reader's model (VTK's: alpha = 1 - exp(-tau)), the name escaped.
        reader.SetOpacityModelToVTK()
        name = 'Bonsai "AVoS" \\ 1'
        preset = json.loads(reader.GetParaViewPreset(name))
        self.assertEqual(len(preset), 1)
        self.assertEqual(preset[0]["Name"], name)
        self.assertEqual(preset[0]["ColorSpace"], "RGB")
        colours, opacity = preset[0]["RGBPoints"], preset[0]["Points"]
        ctf, tau = reader.GetColorTransferFunction(), reader.GetExtinctionFunction()
        self.assertEqual(len(colours), 4 * ctf.GetSize())
        self.assertEqual(len(opacity), 4 * tau.GetSize())
        node = [0.0] * 6  # x, r, g, b, midpoint, sharpness
        for i in range(ctf.GetSize()):
            ctf.GetNodeValue(i, node)
            self.assertEqual(colours[4 * i:4 * i + 4], node[:4])
        node = [0.0] * 4  # x, tau, midpoint, sharpness
        for i in range(tau.GetSize()):
            tau.GetNodeValue(i, node)
            self.assertEqual(opacity[4 * i], node[0])
            self.assertEqual(opacity[4 * i + 1], -math.expm1(-node[1]))
        out = os.path.join(tempfile.mkdtemp(), "preset.json")
        self.assertTrue(reader.WriteParaViewPreset(out, name))
        with open(out) as f:
            self.assertEqual(json.load(f), preset)

    def test_raw_volume(self):
        path = os.path.join(Testing.VTK_DATA_ROOT, "volumes", "Fuel.1.64x64x64.raw")
        dims = (64, 64, 64)
        if not os.path.exists(path):
            path = os.path.join(tempfile.mkdtemp(), "Small.1.4x3x2.raw")
            dims = (4, 3, 2)
            with open(path, "wb") as f:
                f.write(bytes(range(24)))
        reader = avos.vtkVolvisRawReader()
        reader.SetFileName(path)
        reader.Update()
        image = reader.GetOutput()
        self.assertEqual(image.GetDimensions(), dims)
        low, high = image.GetScalarRange()
        self.assertLess(low, high)


if __name__ == "__main__":
    Testing.main([(TestReadersPython, "test")])
