"""vtkVolumeOnSurfaceFilter in a wrapped pipeline: source -> vtkFlyingEdges3D ->
vtkOpenMeshDecimation -> VoS^M. Every vertex gets a colour array entry, a
camera change only reassigns (also when the volume's image was touched but
its scalars were not), and the memory report adds up. The mapper's
settings of this round are wrapped (screen density, visibility test). A
volume of two components (vtkImageAppendComponents) and the property's
default nearest interpolation are coloured, not refused. Shaded, the rays
take the lights of the renderer given (SetRenderer): under a scene light a
camera change only reassigns, and without a renderer the shaded property
is refused."""

import avos
from vtkmodules.test import Testing
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D
from vtkmodules.vtkImagingCore import vtkImageAppendComponents
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkRenderingCore import (vtkCamera, vtkColorTransferFunction, vtkLight, vtkRenderer,
                                         vtkVolumeProperty)


def transfer_functions(first_opacity, last_opacity):
    """The tests' colour map over the distances [0, 2] and a linear opacity."""
    color = vtkColorTransferFunction()
    color.AddRGBPoint(0.0, 1.0, 0.5, 0.2)
    color.AddRGBPoint(2.0, 0.2, 0.5, 1.0)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(0.0, first_opacity)
    opacity.AddPoint(2.0, last_opacity)
    return color, opacity


def sphere_distance(dimensions):
    """The distance from the centre sampled on dimensions^3 points, and its
    isosurface at 0.5 with normals."""
    volume = avos.vtkAnalyticVolumeSource()
    volume.SetFunctionToSphereDistance()
    volume.SetDimensions(dimensions, dimensions, dimensions)
    surface = vtkFlyingEdges3D()
    surface.SetInputConnection(volume.GetOutputPort())
    surface.SetValue(0, 0.5)
    surface.ComputeNormalsOn()
    return volume, surface


def linear_property(color, opacity):
    prop = vtkVolumeProperty()
    prop.SetInterpolationTypeToLinear()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    return prop


class TestVolumeOnSurfaceFilterPython(Testing.vtkTest):
    def test_pipeline(self):
        volume, contour = sphere_distance(32)
        decimate = avos.vtkOpenMeshDecimation()
        decimate.SetInputConnection(contour.GetOutputPort())
        decimate.SetTargetReduction(0.5)
        prop = linear_property(*transfer_functions(0.1, 0.1))
        camera = vtkCamera()
        camera.SetPosition(0, 0, 6)
        vos = avos.vtkVolumeOnSurfaceFilter()
        vos.SetInputConnection(decimate.GetOutputPort())
        vos.SetVolumeConnection(volume.GetOutputPort())
        vos.SetVolumeProperty(prop)
        vos.SetCamera(camera)
        vos.FlipNormalsOn()  # distance grows outwards: the normals point in
        vos.Update()
        out = vos.GetOutput()
        n = out.GetNumberOfPoints()
        self.assertGreater(n, 100)
        self.assertEqual(vos.GetNumberOfRaysCast(), 12 * n)
        self.assertEqual(out.GetPointData().GetScalars().GetName(), "VoSColors")
        # The drawn RGB ("VoSDisplayColors") is the colours' RGB.
        display = out.GetPointData().GetArray("VoSDisplayColors")
        colours = out.GetPointData().GetScalars()
        self.assertEqual(display.GetNumberOfComponents(), 3)
        self.assertTrue(all(display.GetComponent(v, k) == colours.GetComponent(v, k)
                            for v in range(0, n, 7) for k in range(3)))
        self.assertEqual(vos.GetConesMemory(), 12 * n * 28)
        visible = sum(1 for v in range(n) if out.GetPointData().GetArray("VoSRay").GetValue(v) >= 0)
        self.assertGreater(visible, n // 3)
        camera.Azimuth(30)
        vos.Update()
        self.assertEqual(vos.GetNumberOfRaysCast(), 0)
        # The volume is recognised by its content: a pipeline that touches
        # the image (ParaView modifies its point data on every update) with
        # the same scalars casts nothing again.
        volume.GetOutput().GetPointData().Modified()
        camera.Azimuth(30)
        vos.Update()
        self.assertEqual(vos.GetNumberOfRaysCast(), 0)
        # Another volume under the same surface does.
        other = avos.vtkAnalyticVolumeSource()
        other.SetFunctionToSphereDistance()
        other.SetDimensions(40, 40, 40)
        vos.SetVolumeConnection(other.GetOutputPort())
        vos.Update()
        self.assertEqual(vos.GetNumberOfRaysCast(), 12 * n)

    def test_components_and_nearest(self):
        volume, surface = sphere_distance(24)
        pair = vtkImageAppendComponents()
        pair.AddInputConnection(volume.GetOutputPort())
        pair.AddInputConnection(volume.GetOutputPort())
        color, opacity = transfer_functions(0.4, 0.05)
        camera = vtkCamera()
        camera.SetPosition(0, 0, 6)

        def colours(source, prop):
            vos = avos.vtkVolumeOnSurfaceFilter()
            vos.SetInputConnection(surface.GetOutputPort())
            vos.SetVolumeConnection(source.GetOutputPort())
            vos.SetVolumeProperty(prop)
            vos.SetCamera(camera)
            vos.FlipNormalsOn()
            vos.Update()
            rgba = vos.GetOutput().GetPointData().GetScalars()
            self.assertIsNotNone(rgba)
            return [rgba.GetValue(i) for i in range(rgba.GetNumberOfValues())]

        one = vtkVolumeProperty()  # nearest interpolation: VTK's default
        one.SetColor(color)
        one.SetScalarOpacity(opacity)
        halves = vtkVolumeProperty()
        for k in range(2):
            halves.SetColor(k, color)
            halves.SetScalarOpacity(k, opacity)
            halves.SetComponentWeight(k, 0.5)
        single = colours(volume, one)
        self.assertGreater(max(single), 100)
        # Two halves of one medium are that medium (within eps 1e-2 and a count).
        mixed = colours(pair, halves)
        self.assertEqual(len(mixed), len(single))
        self.assertLessEqual(max(abs(a - b) for a, b in zip(mixed, single)), 6)

    def test_shading(self):
        volume, surface = sphere_distance(24)
        prop = linear_property(*transfer_functions(0.4, 0.05))
        camera = vtkCamera()
        camera.SetPosition(0, 0, 6)
        renderer = vtkRenderer()
        light = vtkLight()
        light.SetLightTypeToSceneLight()
        light.SetPosition(1, 1, 3)
        renderer.AddLight(light)
        vos = avos.vtkVolumeOnSurfaceFilter()
        vos.SetInputConnection(surface.GetOutputPort())
        vos.SetVolumeConnection(volume.GetOutputPort())
        vos.SetVolumeProperty(prop)
        vos.SetCamera(camera)
        vos.SetRenderer(renderer)
        vos.FlipNormalsOn()
        errors = []
        vos.AddObserver(vtkCommand.ErrorEvent, lambda caller, event: errors.append(event))

        def colours():
            vos.Update()
            rgba = vos.GetOutput().GetPointData().GetScalars()
            return [rgba.GetValue(i) for i in range(rgba.GetNumberOfValues())] if rgba else []

        unshaded = colours()
        prop.ShadeOn()
        shaded = colours()
        self.assertEqual(vos.GetNumberOfRaysCast(), 12 * vos.GetOutput().GetNumberOfPoints())
        self.assertEqual(len(shaded), len(unshaded))
        self.assertGreater(max(abs(a - b) for a, b in zip(shaded, unshaded)), 20)
        camera.Azimuth(5)
        colours()
        self.assertEqual(vos.GetNumberOfRaysCast(), 0)
        self.assertEqual(errors, [])
        vos.SetRenderer(None)
        self.assertEqual(colours(), [])
        self.assertEqual(len(errors), 1)

    def test_mapper_settings(self):
        mapper = avos.vtkVolumeOnSurfaceMapper()
        self.assertEqual(mapper.GetPixelsPerVertex(), 2.0)
        mapper.SetPixelsPerVertex(-1.0)  # clamped: 0 turns the density rule off
        self.assertEqual(mapper.GetPixelsPerVertex(), 0.0)
        self.assertEqual(mapper.GetVisibilityTest(), mapper.AUTOMATIC_VISIBILITY)
        mapper.SetVisibilityTest(mapper.DEPTH_VISIBILITY)
        self.assertEqual(mapper.GetVisibilityTest(), mapper.DEPTH_VISIBILITY)
        self.assertEqual(mapper.GetScreenPixelsPerVertex(), -1.0)  # nothing drawn yet
        self.assertFalse(mapper.GetDrawFullSurface())
        mapper.DrawFullSurfaceOn()
        self.assertTrue(mapper.GetDrawFullSurface())


if __name__ == "__main__":
    Testing.main([(TestVolumeOnSurfaceFilterPython, "test")])
