"""vtkAdaptiveVolumeMapper in a wrapped pipeline: source -> mapper -> window.
The float image and the statistics reach Python; the adaptive image agrees
with the reference within the tolerance on every pixel; a bad tolerance is
reported and renders nothing. The piecewise method agrees with the
reference within its tolerance, with fewer samples than the paper's coupled
rule at the same tolerance, and reports its cells and pieces; with colour
maps and opacity curves VTK does not interpolate linearly it stays within
its tolerance of the integral of VTK's own functions. Clipping
planes and cropping cut the image, and moving a plane recasts it; shaded,
under the headlight or positional lights and spots, the piecewise method
agrees with the shaded reference, and the image does not change when the
scene moves rigidly. Nearest interpolation and cell scalars render
their own fields, each within 3/255 (mean) of VTK's GPU mapper's image, and
so do independent and dependent components where VTK's semantics are the
same."""

import avos
from vtkmodules.test import Testing
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkLight, vtkLightKit,
                                         vtkRenderWindow, vtkRenderer, vtkVolume,
                                         vtkVolumeProperty, vtkWindowToImageFilter)
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction, vtkPlane
from vtkmodules.vtkFiltersCore import vtkPointDataToCellData
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL render window)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401  (image display helper)


class TestAdaptiveVolumeMapperPython(Testing.vtkTest):
    def setUp(self):
        source = avos.vtkAnalyticVolumeSource()
        source.SetFunctionToMarschnerLobb()
        source.SetDimensions(33, 33, 33)
        color = vtkColorTransferFunction()
        color.AddRGBPoint(0.0, 0.1, 0.3, 1.0)
        color.AddRGBPoint(1.0, 1.0, 0.8, 0.2)
        opacity = vtkPiecewiseFunction()
        opacity.AddPoint(0.0, 0.0)
        opacity.AddPoint(0.5, 0.0)
        opacity.AddPoint(1.0, 0.4)
        prop = vtkVolumeProperty()
        prop.SetColor(color)
        prop.SetScalarOpacity(opacity)
        prop.SetInterpolationTypeToLinear()
        self.mapper = avos.vtkAdaptiveVolumeMapper()
        self.mapper.SetInputConnection(source.GetOutputPort())
        self.mapper.SetOpacityModelToExtinction()
        self.prop = prop
        volume = vtkVolume()
        volume.SetMapper(self.mapper)
        volume.SetProperty(prop)
        self.volume = volume
        renderer = vtkRenderer()
        renderer.AddVolume(volume)
        self.renderer = renderer
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(40, 30)
        self.window.AddRenderer(renderer)
        renderer.ResetCamera()
        renderer.GetActiveCamera().Elevation(30.0)

    def render(self):
        self.window.Render()
        rgba = self.mapper.GetRenderedImage().GetPointData().GetScalars()
        return [rgba.GetValue(i) for i in range(rgba.GetNumberOfValues())] if rgba else []

    def colour_maps(self):
        """VTK colour maps whose colours are not piecewise linear in the
        scalar, each as a user sets it."""
        def rgb_points(f, points):
            for p in points:
                f.AddRGBPoint(*p)
            return f
        hsv = rgb_points(vtkColorTransferFunction(), [
            (0.0, 0.0, 0.0, 1.0), (0.6, 0.0, 1.0, 0.2, 0.3, 0.0), (1.0, 1.0, 0.0, 0.0)])
        hsv.SetColorSpaceToHSV()
        # ParaView's default map, "Cool to Warm".
        diverging = rgb_points(vtkColorTransferFunction(), [
            (0.0, 0.231373, 0.298039, 0.752941), (1.0, 0.705882, 0.0156863, 0.14902)])
        diverging.SetColorSpaceToDiverging()
        lab = rgb_points(vtkColorTransferFunction(), [
            (0.0, 0.1, 0.1, 0.9), (0.55, 1.0, 1.0, 0.2), (1.0, 0.9, 0.1, 0.1)])
        lab.SetColorSpaceToLab()
        hermite = rgb_points(vtkColorTransferFunction(), [
            (0.0, 0.1, 0.3, 1.0, 0.2, 0.5), (1.0, 1.0, 0.8, 0.2)])
        log = rgb_points(vtkColorTransferFunction(), [
            (0.05, 0.1, 0.3, 1.0), (0.3, 0.2, 1.0, 0.3), (1.0, 1.0, 0.8, 0.2)])
        log.SetScaleToLog10()
        return {"HSV": hsv, "Diverging": diverging, "Lab": lab,
                "midpoint 0.2, sharpness 0.5": hermite, "log scale": log}

    @staticmethod
    def sampled(function):
        """A colour or opacity function sampled at 20001 points of [0, 1],
        linear between them: within 1e-6 of it."""
        colour = isinstance(function, vtkColorTransferFunction)
        samples = vtkColorTransferFunction() if colour else vtkPiecewiseFunction()
        for i in range(20001):
            s = i / 20000.0
            if colour:
                samples.AddRGBPoint(s, *function.GetColor(s))
            else:
                samples.AddPoint(s, function.GetValue(s))
        return samples

    def assert_within_tolerance_of_sampled(self, use, function, sampled):
        """The image at eps 1e-3 with `function` (set by `use`) within eps of
        the one at eps 1e-5 with its dense samples `sampled`."""
        self.mapper.SetTolerance(1e-5)
        use(sampled)
        reference = self.render()
        self.assertGreater(max(reference), 0.2)
        use(function)
        self.mapper.SetTolerance(1e-3)
        image = self.render()
        error = max(abs(a - r) for a, r in zip(image, reference))
        self.assertLessEqual(error, 1e-3 + 1e-5)

    def test_piecewise_colour_maps_within_tolerance(self):
        # HSV, Diverging and Lab spaces, a Hermite curve, a log scale: the
        # piecewise method converts each within eps / 2 of VTK's colours (a
        # proven bound) and integrates to eps / 2, so every pixel is within
        # eps of the integral of VTK's own function. That integral: the same
        # method at eps 1e-5 on VTK's function sampled at 20001 RGB points
        # (linear between them: within 1e-6 of it).
        warnings = []
        self.mapper.AddObserver(vtkCommand.WarningEvent, lambda o, e: warnings.append(e))
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        for name, colours in self.colour_maps().items():
            with self.subTest(colour_map=name):
                self.assert_within_tolerance_of_sampled(
                    self.prop.SetColor, colours, self.sampled(colours))
                self.assertEqual(warnings, [], "the colours are certified, not approximated")

    def test_reference_certifies_curved_functions(self):
        # The reference converts VTK's curved colour functions within 1e-7
        # (a proven bound) and integrates at 1e-10: its image lies within
        # 1e-7 + 1e-9 of the integral of VTK's own function, here the
        # reference on the function sampled at 20001 points (within 1e-6 of
        # it): 1.2e-6 in all (measured 1.5e-7, the float image's rounding). No
        # warning: nothing is approximated. (Resampled with 16 points per
        # interval without a bound, the reference was 7.3e-3 off on the
        # Diverging map, 3.7e-3 on HSV.)
        warnings = []
        self.mapper.AddObserver(vtkCommand.WarningEvent, lambda o, e: warnings.append(e))
        self.mapper.SetIntegrationMethodToReference()
        for name, colours in self.colour_maps().items():
            with self.subTest(colour_map=name):
                self.prop.SetColor(self.sampled(colours))
                reference = self.render()
                self.prop.SetColor(colours)
                image = self.render()
                error = max(abs(a - r) for a, r in zip(image, reference))
                self.assertLessEqual(error, 1.2e-6)
                self.assertEqual(warnings, [], "the colours are certified, not approximated")
        # Opacity curves, in both models: a Hermite curve (1e-5 in the
        # extinction model: 1e-7 would need more knots than an interval may
        # take), a log scale; measured within 6e-7.
        for model in ("Extinction", "VTK"):
            getattr(self.mapper, "SetOpacityModelTo" + model)()
            for name, opacity in self.opacity_curves().items():
                with self.subTest(opacity=name, model=model):
                    self.prop.SetScalarOpacity(self.sampled(opacity))
                    reference = self.render()
                    self.prop.SetScalarOpacity(opacity)
                    image = self.render()
                    error = max(abs(a - r) for a, r in zip(image, reference))
                    self.assertLessEqual(error, 1e-5 + 1e-6 + 1e-9)
                    self.assertEqual(warnings, [], "the opacity is certified, not approximated")

    @staticmethod
    def opacity_curves():
        hermite = vtkPiecewiseFunction()
        hermite.AddPoint(0.0, 0.0)
        hermite.AddPoint(0.5, 0.0, 0.3, 0.5)
        hermite.AddPoint(1.0, 0.6)
        log = vtkPiecewiseFunction()
        log.AddPoint(0.05, 0.0)
        log.AddPoint(0.5, 0.05)
        log.AddPoint(1.0, 0.6)
        log.UseLogScaleOn()
        return {"midpoint 0.3, sharpness 0.5": hermite, "log scale": log}

    def test_piecewise_opacity_curves_within_tolerance(self):
        # Opacity curves VTK does not interpolate linearly (a Hermite curve,
        # a log scale), in both opacity models: the piecewise method converts
        # them within three quarters of eps (the extinction budget, a proven
        # bound; the colours are exact), and integrates to the rest, so
        # every pixel is within eps of the integral of VTK's own opacity. That
        # integral: the same method at eps 1e-5 on VTK's opacity sampled at
        # 20001 points.
        warnings = []
        self.mapper.AddObserver(vtkCommand.WarningEvent, lambda o, e: warnings.append(e))
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        for model in ("Extinction", "VTK"):
            getattr(self.mapper, "SetOpacityModelTo" + model)()
            for name, opacity in self.opacity_curves().items():
                with self.subTest(opacity=name, model=model):
                    self.assert_within_tolerance_of_sampled(
                        self.prop.SetScalarOpacity, opacity, self.sampled(opacity))
                    self.assertEqual(warnings, [], "the opacity is certified, not approximated")

    def test_adaptive_within_tolerance_of_reference(self):
        self.mapper.SetIntegrationMethodToReference()
        reference = self.render()
        self.assertEqual(len(reference), 40 * 30 * 4)
        self.assertGreater(max(reference), 0.2)
        self.mapper.SetIntegrationMethodToAdaptiveCoupled()
        self.mapper.SetTolerance(0.005)
        self.assertEqual(self.mapper.GetIntegrationMethodAsString(), "AdaptiveCoupled")
        adaptive = self.render()
        error = max(abs(a - r) for a, r in zip(adaptive, reference))
        self.assertLessEqual(error, 0.005)
        self.assertGreater(self.mapper.GetRaysCast(), 0)
        self.assertGreater(self.mapper.GetMeanSamplesPerRay(), 1.0)
        self.assertGreaterEqual(self.mapper.GetMaximumSamplesPerRay(),
                                self.mapper.GetMeanSamplesPerRay())
        self.assertGreater(self.mapper.GetLastRenderTime(), 0.0)

    def test_piecewise_within_tolerance_of_reference(self):
        self.mapper.SetIntegrationMethodToReference()
        reference = self.render()
        self.mapper.SetIntegrationMethodToAdaptiveCoupled()
        self.mapper.SetTolerance(0.001)
        self.render()
        coupled_samples = self.mapper.GetMeanSamplesPerRay()
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        self.assertEqual(self.mapper.GetIntegrationMethodAsString(), "PiecewiseAdaptive")
        piecewise = self.render()
        error = max(abs(a - r) for a, r in zip(piecewise, reference))
        self.assertLessEqual(error, 0.001)
        self.assertGreater(self.mapper.GetMeanPiecesPerRay(), 1.0)
        self.assertGreater(self.mapper.GetMeanCellsPerRay(), 1.0)
        self.assertLess(self.mapper.GetMeanSamplesPerRay(), coupled_samples)

    def test_clipping_and_cropping(self):
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        whole = self.render()
        plane = vtkPlane()
        plane.SetOrigin(0.0, 0.0, 0.0)
        plane.SetNormal(1.0, 0.0, 0.0)
        self.mapper.AddClippingPlane(plane)
        half = self.render()
        self.assertLess(sum(half[3::4]), 0.8 * sum(whole[3::4]))
        self.assertGreater(sum(half[3::4]), 0.2 * sum(whole[3::4]))
        # A moved plane (the mapper itself unchanged) is seen: a new image.
        plane.SetOrigin(0.5, 0.0, 0.0)
        less = self.render()
        self.assertFalse(self.mapper.GetLastRenderReused())
        self.assertLess(sum(less[3::4]), sum(half[3::4]))
        self.mapper.RemoveAllClippingPlanes()
        self.mapper.SetCropping(1)
        self.mapper.SetCroppingRegionPlanes(-0.5, 0.5, -0.5, 0.5, -0.5, 0.5)
        self.mapper.SetCroppingRegionFlagsToSubVolume()
        inner = self.render()
        self.mapper.SetCroppingRegionFlagsToInvertedCross()
        outer = self.render()
        self.assertGreater(sum(inner[3::4]), 0.0)
        self.assertLess(sum(inner[3::4]), sum(whole[3::4]))
        self.assertLess(sum(outer[3::4]), sum(whole[3::4]))

    def test_maximum_intensity_projection(self):
        # The opacity function reaches 0.4 at the field's top (1): the
        # brightest pixel's alpha, exact along its ray, cannot exceed it.
        self.mapper.SetBlendModeToMaximumIntensity()
        mip = self.render()
        self.assertLessEqual(max(mip[3::4]), 0.4 + 1e-6)
        self.assertGreater(max(mip[3::4]), 0.3)
        errors = []
        self.mapper.AddObserver(vtkCommand.ErrorEvent,
                                lambda caller, event: errors.append(event))
        # Additive: grey and opaque over the volume; the isosurface mode is refused.
        self.mapper.SetBlendModeToAdditive()
        added = self.render()
        self.assertEqual(max(added[3::4]), 1.0)
        self.assertGreater(max(added[0::4]), 0.0)
        self.assertEqual(added[0::4], added[1::4])
        self.assertEqual(len(errors), 0)
        self.mapper.SetBlendModeToIsoSurface()
        self.assertEqual(self.render(), [])
        self.assertEqual(len(errors), 1)

    def test_shading(self):
        # Lit by the renderer's headlight: the alpha channel (optical depth)
        # is unchanged, the colours change; the piecewise method's pixels
        # within its eps of the shaded reference's (itself within 1e-5).
        self.mapper.SetIntegrationMethodToAdaptiveCoupled()
        unlit = self.render()
        self.prop.ShadeOn()
        lit = self.render()
        self.assertEqual(len(lit), len(unlit))
        self.assertLess(max(abs(a - b) for a, b in zip(lit[3::4], unlit[3::4])), 0.003)
        self.assertGreater(max(abs(a - b) for a, b in zip(lit[0::4], unlit[0::4])), 0.02)
        errors = []
        self.mapper.AddObserver(vtkCommand.ErrorEvent,
                                lambda caller, event: errors.append(event))
        self.mapper.SetIntegrationMethodToReference()
        reference = self.render()
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        self.mapper.SetTolerance(1e-3)
        piecewise = self.render()
        self.assertEqual(errors, [])
        self.assertEqual(len(piecewise), len(reference))
        self.assertLess(max(abs(a - b) for a, b in zip(piecewise, reference)), 1e-3 + 1e-5)
        self.assertGreater(max(abs(a - b) for a, b in zip(piecewise[0::4], unlit[0::4])), 0.02)

    def piecewise_within_eps_of_reference(self):
        """The piecewise method's image at eps 1e-3, checked within its eps
        of the reference method's (itself within 1e-5)."""
        self.mapper.SetIntegrationMethodToReference()
        reference = self.render()
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        self.mapper.SetTolerance(1e-3)
        piecewise = self.render()
        self.assertEqual(len(piecewise), len(reference))
        self.assertGreater(len(piecewise), 0)
        self.assertLess(max(abs(a - b) for a, b in zip(piecewise, reference)), 1e-3 + 1e-5)
        return piecewise

    def test_positional_lights(self):
        # A point light beside the volume and a narrow spot whose cone's edge
        # crosses it (scene lights): the piecewise method within its eps of
        # the shaded reference; the scene moved rigidly (volume, lights and
        # camera) draws the same image, so that the lights are placed in
        # world space; a point light far away along a direction draws the
        # directional light's image.
        errors = []
        self.mapper.AddObserver(vtkCommand.ErrorEvent,
                                lambda caller, event: errors.append(event))
        self.prop.ShadeOn()
        bounds = self.mapper.GetBounds()
        centre = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
        bulb = vtkLight()
        bulb.SetLightTypeToSceneLight()
        bulb.SetPositional(True)
        bulb.SetPosition(centre[0] + 20.0, centre[1] + 8.0, centre[2] + 25.0)
        bulb.SetFocalPoint(centre)
        bulb.SetAttenuationValues(0.5, 0.02, 0.001)
        spot = vtkLight()
        spot.SetLightTypeToSceneLight()
        spot.SetPositional(True)
        spot.SetPosition(centre[0] - 30.0, centre[1] + 40.0, centre[2] + 60.0)
        spot.SetFocalPoint(centre)
        spot.SetConeAngle(8.0)
        spot.SetExponent(4.0)
        spot.SetDiffuseColor(0.3, 0.5, 1.0)
        self.renderer.AddLight(bulb)
        self.renderer.AddLight(spot)
        piecewise = self.piecewise_within_eps_of_reference()
        self.assertEqual(errors, [])
        spot.SwitchOff()
        self.assertGreater(max(abs(a - b) for a, b in zip(self.render(), piecewise)), 0.01)
        spot.SwitchOn()

        shift = (7.0, -3.0, 11.0)
        moved = lambda p: [p[i] + shift[i] for i in range(3)]
        camera = self.renderer.GetActiveCamera()
        self.volume.SetPosition(shift)
        for thing in (bulb, spot, camera):
            thing.SetPosition(moved(thing.GetPosition()))
            thing.SetFocalPoint(moved(thing.GetFocalPoint()))
        self.renderer.ResetCameraClippingRange()
        self.assertLess(max(abs(a - b) for a, b in zip(self.render(), piecewise)), 1e-6)
        self.assertEqual(errors, [])

        self.renderer.RemoveAllLights()
        towards = [0.3, 0.5, 0.8]
        sun = vtkLight()
        sun.SetLightTypeToSceneLight()
        sun.SetPosition(towards)
        sun.SetFocalPoint(0.0, 0.0, 0.0)
        self.renderer.AddLight(sun)
        directional = self.render()
        far = vtkLight()
        far.SetLightTypeToSceneLight()
        far.SetPositional(True)
        far.SetPosition([c + 1e7 * t for c, t in zip(moved(centre), towards)])
        self.renderer.RemoveAllLights()
        self.renderer.AddLight(far)
        self.assertLess(max(abs(a - b) for a, b in zip(self.render(), directional)), 2e-3)
        self.assertEqual(errors, [])

    def test_light_kit(self):
        # vtkLightKit's key, fill, two back and head lights (camera lights):
        # the piecewise method within its eps of the shaded reference, and
        # each light counts (the key light alone draws another image).
        errors = []
        self.mapper.AddObserver(vtkCommand.ErrorEvent,
                                lambda caller, event: errors.append(event))
        self.prop.ShadeOn()
        kit = vtkLightKit()
        kit.AddLightsToRenderer(self.renderer)
        self.assertEqual(self.renderer.GetLights().GetNumberOfItems(), 5)
        piecewise = self.piecewise_within_eps_of_reference()
        self.assertEqual(errors, [])
        self.renderer.RemoveAllLights()
        key = vtkLightKit()
        key.SetFillLightWarmth(0.5)
        key.SetKeyToFillRatio(1e6)
        key.SetKeyToHeadRatio(1e6)
        key.SetKeyToBackRatio(1e6)
        key.AddLightsToRenderer(self.renderer)
        self.assertGreater(max(abs(a - b) for a, b in zip(self.render(), piecewise)), 0.01)
        self.assertEqual(errors, [])

    def test_nearest_interpolation_and_cell_scalars(self):
        # VTK's default interpolation (nearest) and cell scalars render, each
        # as its own field: the piecewise method within eps of the reference
        # on the same field, and the nearest image is not the trilinear one.
        errors = []
        self.mapper.AddObserver(vtkCommand.ErrorEvent,
                                lambda caller, event: errors.append(event))
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        self.mapper.SetTolerance(1e-3)
        trilinear = self.render()
        self.prop.SetInterpolationType(vtkVolumeProperty().GetInterpolationType())
        self.assertEqual(self.prop.GetInterpolationTypeAsString(), "Nearest Neighbor")
        fields = {"nearest": self.mapper.GetInputConnection(0, 0)}
        cells = vtkPointDataToCellData()
        cells.SetInputConnection(fields["nearest"])
        cells.ProcessAllArraysOn()
        fields["cell scalars"] = cells.GetOutputPort()
        for name, port in fields.items():
            with self.subTest(field=name):
                self.mapper.SetInputConnection(port)
                self.mapper.SetIntegrationMethodToReference()
                reference = self.render()
                self.assertGreater(max(reference), 0.2)
                self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
                piecewise = self.render()
                error = max(abs(a - r) for a, r in zip(piecewise, reference))
                self.assertLessEqual(error, 1e-3)
                self.assertGreater(max(abs(a - b) for a, b in zip(piecewise, trilinear)), 0.02)
        self.assertEqual(errors, [])

    def window_rgb(self, window):
        grab = vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.SetInputBufferTypeToRGB()
        grab.ReadFrontBufferOff()
        grab.Update()
        rgb = grab.GetOutput().GetPointData().GetScalars()
        return [rgb.GetValue(i) for i in range(rgb.GetNumberOfValues())]

    def test_fields_agree_with_vtk_gpu_mapper(self):
        # Each reading of the scalars (point or cell, nearest or linear)
        # against VTK's GPU mapper on the same scene at a step of 0.1: the
        # mean RGB difference over the pixels the volume covers within 3/255
        # (measured 0.56-0.77/255: the Riemann sum's step and llvmpipe's 8-bit
        # textures); the reference and the piecewise method at eps 1e-3.
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        self.mapper.SetTolerance(1e-3)
        self.mapper.SetOpacityModelToVTK()
        self.window.SetSize(120, 100)
        gpu = vtkOpenGLGPUVolumeRayCastMapper()
        gpu.SetAutoAdjustSampleDistances(0)
        gpu.SetSampleDistance(0.1 * 2.0 / 32.0)
        gpu_volume = vtkVolume()
        gpu_volume.SetMapper(gpu)
        gpu_volume.SetProperty(self.prop)
        gpu_renderer = vtkRenderer()
        gpu_renderer.AddVolume(gpu_volume)
        renderer = self.window.GetRenderers().GetFirstRenderer()
        gpu_renderer.SetActiveCamera(renderer.GetActiveCamera())
        gpu_window = vtkRenderWindow()
        gpu_window.SetOffScreenRendering(1)
        gpu_window.SetSize(120, 100)
        gpu_window.AddRenderer(gpu_renderer)
        points = self.mapper.GetInputConnection(0, 0)
        cells = vtkPointDataToCellData()
        cells.SetInputConnection(points)
        for name, port in (("points", points), ("cells", cells.GetOutputPort())):
            for interpolation in ("Nearest", "Linear"):
                with self.subTest(scalars=name, interpolation=interpolation):
                    getattr(self.prop, "SetInterpolationTypeTo" + interpolation)()
                    self.mapper.SetInputConnection(port)
                    gpu.SetInputConnection(port)
                    self.window.Render()
                    gpu_window.Render()
                    ours = self.window_rgb(self.window)
                    theirs = self.window_rgb(gpu_window)
                    covered = [i for i in range(0, len(ours), 3) if sum(ours[i:i + 3]) > 0]
                    self.assertGreater(len(covered), len(ours) // 30)
                    mean = sum(abs(ours[i + c] - theirs[i + c])
                               for i in covered for c in range(3)) / (3.0 * len(covered))
                    self.assertLessEqual(mean, 3.0)

    def gpu_window(self, prop, port):
        """VTK's GPU mapper on `port` with `prop`, at a step of 0.1 voxel,
        seen through this test's camera, in a window of the same size."""
        gpu = vtkOpenGLGPUVolumeRayCastMapper()
        gpu.SetAutoAdjustSampleDistances(0)
        gpu.SetSampleDistance(0.1 * 2.0 / 32.0)
        gpu.SetInputConnection(port)
        volume = vtkVolume()
        volume.SetMapper(gpu)
        volume.SetProperty(prop)
        renderer = vtkRenderer()
        renderer.AddVolume(volume)
        renderer.SetActiveCamera(self.window.GetRenderers().GetFirstRenderer().GetActiveCamera())
        window = vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetSize(*self.window.GetSize())
        window.AddRenderer(renderer)
        window.Render()
        return window

    def mean_difference(self, ours, theirs):
        """The mean RGB difference (0-255) over the pixels either covers."""
        covered = [i for i in range(0, len(ours), 3)
                   if sum(ours[i:i + 3]) + sum(theirs[i:i + 3]) > 0]
        self.assertGreater(len(covered), len(ours) // 30)
        return sum(abs(ours[i + c] - theirs[i + c])
                   for i in covered for c in range(3)) / (3.0 * len(covered))

    def test_components_agree_with_vtk_gpu_mapper(self):
        # Two to four components on the Marschner-Lobb grid, against VTK's
        # GPU mapper where the semantics are the same: independent components
        # whose visible parts are apart (the left and the right half: where
        # both show, VTK averages their opacities, AVoS adds their
        # extinctions), the colour of one component with the opacity of
        # another, RGB and opacity in unsigned char. Mean RGB difference over
        # the covered pixels within 3/255; a second component of opacity 0
        # leaves the first component's image (within eps); where both
        # independent components show everywhere, the images differ by design.
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.vtkCommonCore import vtkFloatArray, vtkUnsignedCharArray
        from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer
        self.mapper.SetIntegrationMethodToPiecewiseAdaptive()
        self.mapper.SetTolerance(1e-3)
        self.mapper.SetOpacityModelToVTK()
        self.window.SetSize(120, 100)
        source = self.mapper.GetInputAlgorithm()
        source.Update()
        ml = source.GetOutput().GetPointData().GetScalars()
        n = 33

        def volume(values, components, array_type=vtkFloatArray):
            image = vtkImageData()
            image.DeepCopy(source.GetOutput())
            array = array_type()
            array.SetNumberOfComponents(components)
            array.SetNumberOfTuples(len(values) // components)
            for i, v in enumerate(values):
                array.SetValue(i, v)
            image.GetPointData().SetScalars(array)
            producer = vtkTrivialProducer()
            producer.SetOutput(image)
            return producer

        def halves(i):
            # Marschner-Lobb in the left half for the first component, the
            # right half for the second, 0 elsewhere.
            v, x = ml.GetValue(i), i % n
            return [v if x < n // 2 else 0.0, v if x > n // 2 else 0.0]

        def colour(r, g, b):
            f = vtkColorTransferFunction()
            f.AddRGBPoint(0.0, 0.1, 0.1, 0.1)
            f.AddRGBPoint(1.0, r, g, b)
            return f

        def opacity(top):
            f = vtkPiecewiseFunction()
            f.AddPoint(0.0, 0.0)
            f.AddPoint(0.5, 0.0)
            f.AddPoint(1.0, top)
            return f

        prop = vtkVolumeProperty()
        prop.SetInterpolationTypeToLinear()
        prop.SetColor(0, colour(1.0, 0.3, 0.1))
        prop.SetScalarOpacity(0, opacity(0.4))
        prop.SetColor(1, colour(0.1, 0.4, 1.0))
        prop.SetScalarOpacity(1, opacity(0.6))
        self.volume.SetProperty(prop)
        count = ml.GetNumberOfTuples()
        apart = volume([v for i in range(count) for v in halves(i)], 2)
        rgba = volume([int(255 * min(max(c, 0.0), 1.0)) for i in range(count)
                       for c in (ml.GetValue(i), 1.0 - ml.GetValue(i), 0.5, ml.GetValue(i))],
                      4, vtkUnsignedCharArray)
        rgba_opacity = vtkPiecewiseFunction()
        rgba_opacity.AddPoint(0.0, 0.0)
        rgba_opacity.AddPoint(128.0, 0.0)
        rgba_opacity.AddPoint(255.0, 0.5)
        cases = (("independent, apart", apart, True, None),
                 ("colour of the first, opacity of the second", apart, False, None),
                 ("RGB and opacity, unsigned char", rgba, False, rgba_opacity))
        for name, producer, independent, first_opacity in cases:
            with self.subTest(case=name):
                prop.SetIndependentComponents(independent)
                if first_opacity:
                    prop.SetScalarOpacity(0, first_opacity)
                self.mapper.SetInputConnection(producer.GetOutputPort())
                self.window.Render()
                self.assertTrue(self.mapper.GetRenderedImage().GetNumberOfPoints() > 0)
                theirs = self.window_rgb(self.gpu_window(prop, producer.GetOutputPort()))
                mean = self.mean_difference(self.window_rgb(self.window), theirs)
                print(name, "mean RGB difference against VTK's GPU mapper", mean)
                self.assertLessEqual(mean, 3.0)
        prop.SetScalarOpacity(0, opacity(0.4))
        prop.SetIndependentComponents(True)

        # The second component transparent: the first component's image.
        self.mapper.SetInputConnection(apart.GetOutputPort())
        prop.SetScalarOpacity(1, opacity(0.0))
        both = self.render()
        first = volume([halves(i)[0] for i in range(count)], 1)
        self.mapper.SetInputConnection(first.GetOutputPort())
        alone = self.render()
        self.assertGreater(max(alone), 0.2)
        self.assertLessEqual(max(abs(a - b) for a, b in zip(both, alone)), 2e-3)

    def test_bad_tolerance_is_reported(self):
        errors = []
        self.mapper.AddObserver(vtkCommand.ErrorEvent,
                                lambda caller, event: errors.append(event))
        self.mapper.SetTolerance(-1.0)
        self.assertEqual(self.render(), [])
        self.assertEqual(len(errors), 1)


if __name__ == "__main__":
    Testing.main([(TestAdaptiveVolumeMapperPython, "test")])
