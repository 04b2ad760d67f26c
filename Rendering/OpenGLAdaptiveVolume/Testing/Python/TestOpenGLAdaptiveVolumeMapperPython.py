"""vtkOpenGLAdaptiveVolumeMapper from Python: the GPU's float opacity image
(RenderToImage's depth image, ImageQuantity ALPHA) agrees with the CPU
mapper's on the same frame within the tolerance, for the coupled and
decoupled strategies and the Riemann sum, and its maximum and minimum
intensity projections are the CPU mapper's (both exact); its piecewise
method certifies ParaView's default colour map within eps of the exact
integral; clipping planes and cropping cut its rays where they cut the CPU
mapper's; it reads signed, 32-bit and double scalars, nearest
interpolation, cell scalars, NaN, one component of several and mixtures of
several in the sampled methods, and shades,
scales by gradient opacity and projects additively or by the average as the
CPU mapper does; a bad tolerance is refused and draws nothing."""

import avos
from vtkmodules.test import Testing
from vtkmodules import vtkCommonCore
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction, vtkPlane
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkLight, vtkRenderWindow,
                                         vtkRenderer, vtkVolume, vtkVolumeProperty)
from vtkmodules.vtkFiltersCore import vtkPointDataToCellData
from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer
from vtkmodules.vtkImagingCore import vtkImageAppendComponents, vtkImageShiftScale
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL render window)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401  (image display helper)

SIZE = 32


def colours(*points):
    """A vtkColorTransferFunction through the (x, r, g, b) points."""
    f = vtkColorTransferFunction()
    for point in points:
        f.AddRGBPoint(*point)
    return f


def opacities(*points):
    """A vtkPiecewiseFunction through the (x, value[, midpoint, sharpness]) points."""
    f = vtkPiecewiseFunction()
    for point in points:
        f.AddPoint(*point)
    return f


class TestOpenGLAdaptiveVolumeMapperPython(Testing.vtkTest):
    def setUp(self):
        source = avos.vtkAnalyticVolumeSource()
        source.SetFunctionToMarschnerLobb()
        source.SetDimensions(33, 33, 33)
        source.SetOutputScalarTypeToFloat()
        color = colours((0.0, 0.1, 0.3, 1.0), (1.0, 1.0, 0.8, 0.2))
        opacity = opacities((0.0, 0.0), (0.5, 0.0), (1.0, 0.4))
        self.prop = vtkVolumeProperty()
        self.prop.SetColor(color)
        self.prop.SetScalarOpacity(opacity)
        self.prop.SetInterpolationTypeToLinear()
        self.source = source

    def render(self, mapper):
        volume = vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(self.prop)
        renderer = vtkRenderer()
        renderer.AddVolume(volume)
        if getattr(self, "light", None):
            renderer.CreateLight()  # the headlight first, as VTK makes it
            renderer.AddLight(self.light)
        renderer.SetTwoSidedLighting(getattr(self, "twoSided", True))
        window = vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetMultiSamples(0)
        window.SetSize(SIZE, SIZE)
        window.AddRenderer(renderer)
        renderer.ResetCamera()
        renderer.GetActiveCamera().Azimuth(30.0)
        renderer.GetActiveCamera().Elevation(20.0)
        renderer.ResetCameraClippingRange()
        window.Render()
        return window

    def testAgreesWithTheCPUMapper(self):
        for method, eps in (("Riemann", 0.01), ("AdaptiveCoupled", 0.001),
                            ("AdaptiveDecoupled", 0.001)):
            gpu = avos.vtkOpenGLAdaptiveVolumeMapper()
            gpu.SetInputConnection(self.source.GetOutputPort())
            gpu.SetOpacityModelToExtinction()
            getattr(gpu, "SetIntegrationMethodTo" + method)()
            gpu.SetTolerance(eps)
            gpu.SetRenderToImage(1)
            gpu.SetDepthImageScalarTypeToFloat()
            gpu.SetImageQuantity(avos.vtkOpenGLAdaptiveVolumeMapper.ALPHA)
            self.window = self.render(gpu)  # the image lives in its context
            alpha = vtkImageData()
            gpu.GetDepthImage(alpha)

            cpu = avos.vtkAdaptiveVolumeMapper()
            cpu.SetInputConnection(self.source.GetOutputPort())
            cpu.SetOpacityModelToExtinction()
            getattr(cpu, "SetIntegrationMethodTo" + method)()
            cpu.SetTolerance(eps)
            cpu.EmptySpaceSkippingOff()
            self.render(cpu)
            rgba = cpu.GetRenderedImage().GetPointData().GetScalars()

            gpuAlpha = alpha.GetPointData().GetScalars()
            self.assertEqual(gpuAlpha.GetNumberOfTuples(), SIZE * SIZE)
            worst, covered = 0.0, 0
            for i in range(SIZE * SIZE):
                a = gpuAlpha.GetValue(i)
                if a == 1.0:  # no fragment: the image's clear value
                    a = 0.0
                covered += rgba.GetComponent(i, 3) > 0.01
                worst = max(worst, abs(a - rgba.GetComponent(i, 3)))
            self.assertGreater(covered, SIZE * SIZE // 8, method)
            self.assertLessEqual(worst, eps, method)

    def cpuImage(self, configure):
        """The CPU mapper's float RGBA image, the mapper set up by configure."""
        cpu = avos.vtkAdaptiveVolumeMapper()
        cpu.SetInputConnection(self.source.GetOutputPort())
        configure(cpu)
        self.render(cpu)
        return cpu.GetRenderedImage().GetPointData().GetScalars()

    def gpuDifference(self, configure, expected, warningCount=0, firstSource=None):
        """The largest difference over pixels and RGBA between the GPU's float
        image (the mapper set up by configure) and `expected`, and the pixels
        expected covers; warningCount warnings must be emitted (none by
        default). With firstSource, the mapper first renders it in the same
        window (its shader then built for that input)."""
        gpu = avos.vtkOpenGLAdaptiveVolumeMapper()
        gpu.SetInputConnection((firstSource or self.source).GetOutputPort())
        configure(gpu)
        gpu.SetRenderToImage(1)
        gpu.SetDepthImageScalarTypeToFloat()
        warnings = []
        gpu.AddObserver(vtkCommand.WarningEvent, lambda caller, event: warnings.append(event))
        self.window = self.render(gpu)  # the images live in its context
        gpu.SetInputConnection(self.source.GetOutputPort())
        worst, covered = 0.0, 0
        for channel in range(4):
            gpu.SetImageQuantity(avos.vtkOpenGLAdaptiveVolumeMapper.RED + channel)
            self.window.Render()
            image = vtkImageData()
            gpu.GetDepthImage(image)
            values = image.GetPointData().GetScalars()
            self.assertEqual(values.GetNumberOfTuples(), SIZE * SIZE)
            for i in range(SIZE * SIZE):
                v = values.GetValue(i)
                if v == 1.0 and expected.GetComponent(i, 3) == 0.0:
                    v = 0.0  # no fragment: the image's clear value
                covered += channel == 3 and expected.GetComponent(i, 3) > 0.01
                worst = max(worst, abs(v - expected.GetComponent(i, channel)))
        self.assertEqual(len(warnings), warningCount)
        return worst, covered

    def assertPiecewiseWithinEps(self, eps, message=None):
        """The GPU's piecewise method at eps within eps - 1e-5 of the CPU's at
        1e-5 (itself within 1e-5 of the exact integral) on every pixel."""
        def exact(cpu):
            cpu.SetIntegrationMethodToPiecewiseAdaptive()
            cpu.SetTolerance(1e-5)

        def piecewise(gpu):
            gpu.SetIntegrationMethodToPiecewiseAdaptive()
            gpu.SetTolerance(eps)
        worst, covered = self.gpuDifference(piecewise, self.cpuImage(exact))
        self.assertGreater(covered, SIZE * SIZE // 8, message)
        self.assertLessEqual(worst, eps - 1e-5, message)

    def testProjectionsAgreeWithTheCPUMapper(self):
        # Both mappers' projections are exact (the extremum of the trilinear
        # field along the ray): the GPU's float RGBA within 1e-5 of the
        # CPU's on every pixel (the parity bound is 2/255 in the mean).
        for blend in ("MaximumIntensity", "MinimumIntensity"):
            def configure(mapper):
                getattr(mapper, "SetBlendModeTo" + blend)()
            worst, covered = self.gpuDifference(configure, self.cpuImage(configure))
            self.assertGreater(covered, SIZE * SIZE // 16, blend)  # the minimum is often clear
            self.assertLessEqual(worst, 1e-5, blend)

    def testPiecewiseCertifiesVTKsColourMap(self):
        # ParaView's default "Cool to Warm" (Diverging space) with a Hermite
        # opacity curve: the GPU's piecewise method converts them within
        # shares of eps as the CPU does (no approximation warning) and every
        # channel of every pixel lies within eps of the exact integral of
        # VTK's functions: the CPU mapper's piecewise method at 1e-5, itself
        # certified within 1e-5 of it (measured: 7e-5 apart).
        color = colours((0.0, 0.231, 0.298, 0.753), (1.0, 0.706, 0.016, 0.149))
        color.SetColorSpaceToDiverging()
        opacity = opacities((0.0, 0.0, 0.5, 0.6), (1.0, 0.5))
        self.prop.SetColor(color)
        self.prop.SetScalarOpacity(opacity)
        self.assertPiecewiseWithinEps(1e-3)

    @staticmethod
    def exactCases(riemannBound):
        """(name, CPU set-up, GPU set-up, bound): the piecewise method at eps
        1e-3 within eps of the CPU's at 1e-5 (itself within 1e-5 of the
        exact integral), the exact maximum as the CPU's within 1e-5, the
        Riemann sum as the CPU's within riemannBound."""
        eps = 1e-3
        return (
            ("piecewise",
             lambda m: (m.SetIntegrationMethodToPiecewiseAdaptive(), m.SetTolerance(1e-5)),
             lambda m: (m.SetIntegrationMethodToPiecewiseAdaptive(), m.SetTolerance(eps)),
             eps - 1e-5),
            ("maximum", lambda m: m.SetBlendModeToMaximumIntensity(),
             lambda m: m.SetBlendModeToMaximumIntensity(), 1e-5),
            ("Riemann", lambda m: m.SetIntegrationMethodToRiemann(),
             lambda m: m.SetIntegrationMethodToRiemann(), riemannBound))

    def assertCutAsTheCPUMapper(self, cut):
        # The piecewise method within eps of the CPU's exact image, the exact
        # maximum intensity and the Riemann sum (restarted at each kept
        # part's entry, as VTK's mappers do) as the CPU's, on a volume the
        # mappers cut (cut sets them up).
        def cutting(setting):
            def configure(mapper):
                cut(mapper)
                setting(mapper)
            return configure
        # The Riemann sum in float against double, restarted at each kept
        # part's entry: 3e-7 apart on the planes and the fence, but a sum
        # jumps by a sample's contribution where a part's length rounds
        # across a multiple of h (3 of the subvolume's rays, 3.9e-3).
        cases = self.exactCases(1e-2)
        whole = self.cpuImage(lambda m: m.SetBlendModeToMaximumIntensity())
        for name, cpu, gpu, bound in cases:
            expected = self.cpuImage(cutting(cpu))
            if name == "maximum":
                changed = sum(abs(expected.GetComponent(i, 3) - whole.GetComponent(i, 3)) > 0.01
                              for i in range(SIZE * SIZE))
                self.assertGreater(changed, SIZE * SIZE // 32, "the cut changes the image")
            worst, covered = self.gpuDifference(cutting(gpu), expected)
            self.assertGreater(covered, SIZE * SIZE // 16, name)
            self.assertLessEqual(worst, bound, name)

    def testClippingPlanesAsTheCPUMapper(self):
        planes = []
        for normal, origin in (((1.0, 0.3, 0.2), (-0.3, 0.0, 0.0)), ((0.0, -1.0, 0.4), (0.0, 0.4, 0.0))):
            plane = vtkPlane()
            plane.SetNormal(normal)
            plane.SetOrigin(origin)
            planes.append(plane)

        def cut(mapper):
            for plane in planes:
                mapper.AddClippingPlane(plane)
        self.assertCutAsTheCPUMapper(cut)

    def testCroppingAsTheCPUMapper(self):
        # VTK's fence (several kept parts on most rays) and a subvolume.
        for flags in ("Fence", "SubVolume"):
            def cut(mapper):
                mapper.CroppingOn()
                mapper.SetCroppingRegionPlanes(-0.8, 0.5, -0.7, 0.6, -0.4, 0.7)
                getattr(mapper, "SetCroppingRegionFlagsTo" + flags)()
            self.assertCutAsTheCPUMapper(cut)

    def testEveryScalarType(self):
        # Signed 8- and 16-bit scalars (SNORM textures), 32-bit integers and
        # double (scaled onto [0, 1] by VTK) read back exactly, or within
        # float's rounding of the range for double: the piecewise method
        # within eps of the CPU's at 1e-5 on the same values.
        for name, lo, hi in (("SIGNED_CHAR", -100.0, 100.0), ("SHORT", -1000.0, 1000.0),
                             ("INT", -100000.0, 100000.0), ("DOUBLE", 0.0, 1000.0)):
            scaled = vtkImageShiftScale()
            scaled.SetInputConnection(self.source.GetOutputPort())
            scaled.SetShift(lo / (hi - lo))
            scaled.SetScale(hi - lo)
            scaled.SetOutputScalarType(getattr(vtkCommonCore, "VTK_" + name))
            self.source = scaled
            color = colours((lo, 0.1, 0.3, 1.0), (hi, 1.0, 0.8, 0.2))
            opacity = opacities((lo, 0.0), (0.5 * (lo + hi), 0.0), (hi, 0.4))
            self.prop.SetColor(color)
            self.prop.SetScalarOpacity(opacity)
            self.assertPiecewiseWithinEps(1e-3, name)
            self.setUp()

    def testAdditiveAndAverageAsTheCPUMapper(self):
        # VTK's additive and average projections, integrated along the ray
        # as the CPU mapper integrates them (its meaning: Accumulation.h).
        # Additive: both exact on the same pieces of the transfer function
        # (apart by the float uniforms' rounding); average: both within the
        # tolerance of the exact mean, so within twice it of each other;
        # over the whole data range and over a part of it.
        eps = 1e-3
        for name, blend, scalarRange, bound in (
                ("additive", "Additive", None, 1e-5),
                ("average", "AverageIntensity", None, 2 * eps),
                ("average in [0.3, 0.9]", "AverageIntensity", (0.3, 0.9), 2 * eps)):
            def configure(mapper):
                getattr(mapper, "SetBlendModeTo" + blend)()
                mapper.SetTolerance(eps)
                if scalarRange:
                    mapper.SetAverageIPScalarRange(*scalarRange)
            expected = self.cpuImage(configure)
            worst, covered = self.gpuDifference(configure, expected)
            self.assertGreater(covered, SIZE * SIZE // 8, name)
            self.assertLessEqual(worst, bound, name)

    @staticmethod
    def sampledCases():
        """(name, set-up, bound) of the sampled methods compared with the
        CPU's on the same scene: the Riemann sum, the same samples in float
        against double; the coupled rule at eps 1e-3, both within eps of the
        integral (the same rule on the same samples)."""
        def method(name):
            def configure(mapper):
                getattr(mapper, "SetIntegrationMethodTo" + name)()
                mapper.SetTolerance(1e-3)
            return configure
        return (("Riemann", method("Riemann"), 1e-4),
                ("AdaptiveCoupled", method("AdaptiveCoupled"), 1e-3))

    def testShadingAsTheCPUMapper(self):
        # The CPU mapper's shading (the exact gradient of the trilinear
        # field, Blinn-Phong, the renderer's lights) in the sampled methods:
        # the headlight alone, then with a coloured spot light whose cone
        # cuts the volume, and one-sided (sampledCases).
        self.prop.ShadeOn()
        self.prop.SetSpecularPower(32.0)
        spot = vtkLight()
        spot.SetPositional(1)
        spot.SetPosition(2.0, 1.5, 1.0)
        spot.SetFocalPoint(0.0, 0.0, 0.0)
        spot.SetConeAngle(25.0)
        spot.SetExponent(2.0)
        spot.SetAttenuationValues(1.0, 0.2, 0.0)
        spot.SetColor(1.0, 0.6, 0.3)
        def difference(a, b):
            return max(abs(a.GetComponent(i, k) - b.GetComponent(i, k))
                       for i in range(SIZE * SIZE) for k in range(3))
        self.prop.ShadeOff()
        previous = self.cpuImage(lambda m: m.SetIntegrationMethodToRiemann())
        self.prop.ShadeOn()
        for lights, twoSided in ((None, True), (spot, True), (spot, False)):
            self.light = lights
            self.twoSided = twoSided
            for method, configure, bound in self.sampledCases():
                expected = self.cpuImage(configure)
                case = "%s, spot %s, two-sided %s" % (method, lights is not None, twoSided)
                if method == "Riemann":  # each setting changes the image
                    self.assertGreater(difference(expected, previous), 0.05, case)
                    previous = expected
                worst, covered = self.gpuDifference(configure, expected)
                self.assertGreater(covered, SIZE * SIZE // 8, case)
                self.assertLessEqual(worst, bound, case)

    def testGradientOpacityAsTheCPUMapper(self):
        # The CPU mapper's gradient opacity (the extinction times G of the
        # exact gradient's length, scalar units per world unit) in the
        # sampled methods, unshaded and shaded, with a G whose knots the
        # field's gradients cross: as in testShadingAsTheCPUMapper.
        gradient = opacities((0.0, 0.1), (1.0, 1.0), (3.0, 0.3))
        plain = self.cpuImage(lambda m: m.SetIntegrationMethodToRiemann())
        self.prop.SetGradientOpacity(gradient)
        for shade in (False, True):
            self.prop.SetShade(shade)
            for method, configure, bound in self.sampledCases():
                expected = self.cpuImage(configure)
                case = "%s, shaded %s" % (method, shade)
                if method == "Riemann" and not shade:
                    changed = max(abs(expected.GetComponent(i, 3) - plain.GetComponent(i, 3))
                                  for i in range(SIZE * SIZE))
                    self.assertGreater(changed, 0.05, "G changes the image")
                worst, covered = self.gpuDifference(configure, expected)
                self.assertGreater(covered, SIZE * SIZE // 16, case)
                self.assertLessEqual(worst, bound, case)

    def testNearestAndCellScalarsAsTheCPUMapper(self):
        # Nearest interpolation of point scalars (vtkVolumeProperty's
        # default), cell scalars constant per cell (nearest) and trilinear
        # between the cells' centres (linear): the fields the CPU mapper
        # integrates, walked on the same refined grid. The piecewise method
        # within eps of the CPU's exact image, the maximum as the CPU's
        # (exact), the Riemann sum as the CPU's (same samples, float sums).
        cells = vtkPointDataToCellData()
        cells.SetInputConnection(self.source.GetOutputPort())
        point = self.source
        cases = self.exactCases(1e-4)
        linear = self.cpuImage(lambda m: m.SetBlendModeToMaximumIntensity())
        for field, source, interpolation in (("point nearest", point, "Nearest"),
                                             ("cell nearest", cells, "Nearest"),
                                             ("cell linear", cells, "Linear")):
            self.source = source
            getattr(self.prop, "SetInterpolationTypeTo" + interpolation)()
            for name, cpu, gpu, bound in cases:
                expected = self.cpuImage(cpu)
                if name == "maximum":
                    changed = sum(abs(expected.GetComponent(i, 3) - linear.GetComponent(i, 3))
                                  > 0.01 for i in range(SIZE * SIZE))
                    self.assertGreater(changed, SIZE * SIZE // 32, field + ": another field")
                worst, covered = self.gpuDifference(gpu, expected)
                self.assertGreater(covered, SIZE * SIZE // 16, field + ", " + name)
                self.assertLessEqual(worst, bound, field + ", " + name)

    def testNaNAsTheCPUMapper(self):
        # NaN scalars, one rule on both mappers: every cell with a NaN corner
        # is empty (transparent), the count said once per change of the
        # scalars. A plane of points through the opaque lower part is NaN:
        # the slab of cells on either side of it is empty.
        self.source.Update()
        image = vtkImageData()
        image.DeepCopy(self.source.GetOutput())
        values = image.GetPointData().GetScalars()
        for index in range(33 * 33 * 8, 33 * 33 * 9):
            values.SetValue(index, float("nan"))
        producer = vtkTrivialProducer()
        producer.SetOutput(image)
        whole = self.cpuImage(lambda m: m.SetIntegrationMethodToRiemann())
        self.source = producer
        for name, cpu, gpu, bound in self.exactCases(1e-4):
            expected = self.cpuImage(cpu)
            if name == "Riemann":
                changed = sum(abs(expected.GetComponent(i, 3) - whole.GetComponent(i, 3)) > 0.01
                              for i in range(SIZE * SIZE))
                self.assertGreater(changed, SIZE * SIZE // 16, "the NaN cells change the image")
            worst, covered = self.gpuDifference(gpu, expected, warningCount=1)
            self.assertGreater(covered, SIZE * SIZE // 16, name)
            self.assertLessEqual(worst, bound, name)

    def testOneComponentOfSeveralAsTheCPUMapper(self):
        # Scalars of three components of which the last alone shows (the
        # first transparent, the second of weight 0): the GPU reads that
        # channel of VTK's texture with its medium, its weight 1.5 in its
        # extinction, as the CPU mapper casts it: the piecewise method within
        # eps of the CPU's exact image, the Riemann sum as the CPU's. Float
        # (RGB32F) and unsigned short (normalised RGB16) textures.
        for name, top in (("FLOAT", 1.0), ("UNSIGNED_SHORT", 60000.0)):
            self.setUp()
            shown = vtkImageShiftScale()
            shown.SetInputConnection(self.source.GetOutputPort())
            shown.SetScale(top)
            shown.SetOutputScalarType(getattr(vtkCommonCore, "VTK_" + name))
            hidden = vtkImageShiftScale()
            hidden.SetInputConnection(self.source.GetOutputPort())
            hidden.SetShift(-1.0)
            hidden.SetScale(-0.5 * top)  # another field: 1 - s, halved
            hidden.SetOutputScalarType(getattr(vtkCommonCore, "VTK_" + name))
            tuples = vtkImageAppendComponents()
            for part in (hidden, hidden, shown):
                tuples.AddInputConnection(part.GetOutputPort())
            color = colours((0.0, 0.1, 0.3, 1.0), (top, 1.0, 0.8, 0.2))
            opacity = opacities((0.0, 0.0), (0.5 * top, 0.0), (top, 0.4))
            none = opacities((0.0, 0.0), (top, 0.0))
            for k, (function, weight) in enumerate(((none, 1.0), (opacity, 0.0), (opacity, 1.5))):
                self.prop.SetColor(k, color)
                self.prop.SetScalarOpacity(k, function)
                self.prop.SetComponentWeight(k, weight)
            self.source = tuples
            for case, cpu, gpu, bound in self.exactCases(1e-4):
                if case == "maximum":
                    continue  # (several components take the composite blend only)
                worst, covered = self.gpuDifference(gpu, self.cpuImage(cpu))
                self.assertGreater(covered, SIZE * SIZE // 16, name + ", " + case)
                self.assertLessEqual(worst, bound, name + ", " + case)

    def shiftScale(self, shift, scale, scalarType):
        part = vtkImageShiftScale()
        part.SetInputConnection(self.source.GetOutputPort())
        part.SetShift(shift)
        part.SetScale(scale)
        part.SetOutputScalarType(getattr(vtkCommonCore, "VTK_" + scalarType))
        return part

    def testMixturesAsTheCPUMapper(self):
        # Several components that show, in the sampled methods: each sample
        # reads every component's channel and classifies them together
        # (numerics::MixtureTransferFunction), as the CPU mapper samples them:
        # the Riemann sum as the CPU's (float against double), the coupled
        # rule within eps of it. Independent components of different
        # functions and weights (float), the dependent pair (colour of the
        # first, opacity of the second) and RGBA (unsigned char). The
        # piecewise method refuses them. For the independent ones the mapper
        # renders one component first: its shader, built without the
        # mixture's code, must be rebuilt for the mixture. NaN in one
        # component empties its cells for it alone, on both mappers.
        color = colours((0.0, 1.0, 0.2, 0.1), (1.0, 0.1, 0.9, 0.3))
        shell = opacities((0.0, 0.0), (0.3, 0.5), (0.6, 0.0))
        ramp = opacities((0.0, 0.0), (255.0, 0.5))

        def independent():
            self.prop.SetColor(1, color)
            self.prop.SetScalarOpacity(1, shell)
            self.prop.SetComponentWeight(1, 0.7)
            return (self.shiftScale(0.0, 1.0, "FLOAT"), self.shiftScale(-1.0, -1.0, "FLOAT"))

        def independentWithNaN():
            # A plane of the second component NaN: the cells on either side
            # of it are empty for that component alone.
            parts = independent()
            parts[1].Update()
            image = vtkImageData()
            image.DeepCopy(parts[1].GetOutput())
            values = image.GetPointData().GetScalars()
            for index in range(33 * 33 * 8, 33 * 33 * 9):
                values.SetValue(index, float("nan"))
            producer = vtkTrivialProducer()
            producer.SetOutput(image)
            return (parts[0], producer)

        def dependent():
            self.prop.IndependentComponentsOff()
            return (self.shiftScale(-1.0, -1.0, "FLOAT"), self.shiftScale(0.0, 1.0, "FLOAT"))

        def rgba():
            self.prop.IndependentComponentsOff()
            self.prop.SetScalarOpacity(ramp)
            return (self.shiftScale(0.0, 255.0, "UNSIGNED_CHAR"),
                    self.shiftScale(-1.0, -255.0, "UNSIGNED_CHAR"),
                    self.shiftScale(0.0, 127.0, "UNSIGNED_CHAR"),
                    self.shiftScale(0.0, 255.0, "UNSIGNED_CHAR"))

        images = {}
        for name, make in (("independent", independent), ("NaN", independentWithNaN),
                           ("colour and opacity", dependent), ("RGBA", rgba)):
            self.setUp()
            first = self.shiftScale(0.0, 1.0, "FLOAT") if make == independent else None
            tuples = vtkImageAppendComponents()
            for part in make():
                tuples.AddInputConnection(part.GetOutputPort())
            self.source = tuples
            for method, configure, bound in self.sampledCases():
                images[name, method] = expected = self.cpuImage(configure)
                if name == "NaN":
                    whole = images["independent", method]
                    changed = sum(abs(expected.GetComponent(i, 3) - whole.GetComponent(i, 3))
                                  > 0.01 for i in range(SIZE * SIZE))
                    self.assertGreater(changed, SIZE * SIZE // 32, "the NaN cells show")
                worst, covered = self.gpuDifference(configure, expected,
                                                    warningCount=int(name == "NaN"),
                                                    firstSource=first)
                self.assertGreater(covered, SIZE * SIZE // 16, name + ", " + method)
                self.assertLessEqual(worst, bound, name + ", " + method)
            gpu = avos.vtkOpenGLAdaptiveVolumeMapper()
            gpu.SetInputConnection(self.source.GetOutputPort())
            gpu.SetIntegrationMethodToPiecewiseAdaptive()
            errors = []
            gpu.AddObserver(vtkCommand.ErrorEvent, lambda caller, event: errors.append(event))
            self.render(gpu)
            self.assertEqual(len(errors), 1, name + ": the piecewise method refuses")

    def testRefusesABadTolerance(self):
        gpu = avos.vtkOpenGLAdaptiveVolumeMapper()
        gpu.SetInputConnection(self.source.GetOutputPort())
        gpu.SetTolerance(-1.0)
        errors = []
        gpu.AddObserver(vtkCommand.ErrorEvent, lambda caller, event: errors.append(event))
        self.render(gpu)
        self.assertEqual(len(errors), 1)


if __name__ == "__main__":
    Testing.main([(TestOpenGLAdaptiveVolumeMapperPython, "test")])
