"""The options ParaView's volume representation passes, with the "AVoS
Volume" representation (pvbatch, one process): each rendered as ParaView's
own "Volume" representation renders it, or drawing a warning that names
it.

- A vector array (the gradient of Neghip) coloured by its magnitude, and
  by one component: AVoS's image within 4/255 (mean over the pixels either
  covers) of ParaView's own on the same view, and the two AVoS images
  differ (the colour map's vector mode reaches the mapper). The opacity unit
  distance is 1: ParaView sets it on component 0 only, and VTK's smart
  mapper renders a component through a copy of component 0's functions
  without it, where AVoS takes component 0's unit distance too (13.6/255
  apart with ParaView's default unit distance).
- A separate opacity array (the gradient's magnitude coloured, Neghip's
  density the opacity: ParaView's 2-component "_and_opacity" array,
  dependent components): within 4/255 of ParaView's own.
- ParaView's default colour map (Cool to Warm, discretized to 256 colours)
  certified: no approximation notice.
- ParaView's Shade checkbox with the representation's defaults (the
  piecewise method at its default tolerance) on Neghip's density: lit,
  without an error or notice, its shading effect (mean change from the
  unshaded image) within a third of ParaView's own and the shaded images
  within half that effect of each other (the two light the same scene by
  different normals: the exact gradient against central differences).
- A 2D transfer function (ParaView's gradient-dependent opacity): refused
  with an error naming it.
- VolumeRenderingMode other than the default, global illumination reach,
  volumetric scattering blending: a warning each.
  pvbatch VolumeOptions.py PLUGIN DATA_DIR
"""

import sys

from paraview import servermanager
from paraview.simple import (ColorBy, CreateView, GetColorTransferFunction,
                             GetOpacityTransferFunction, Gradient, Hide, LoadPlugin, Render,
                             Show)
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

plugin, data = sys.argv[1:3]
LoadPlugin(plugin, remote=False, ns=globals())
reader = VolvisRawReader(FileName=data + "/volumes/Neghip.1.64x64x64.raw")  # noqa: F821
gradient = Gradient(Input=reader)
gradient.ScalarArray = ["POINTS", "density"]
gradient.ResultArrayName = "g"
view = CreateView("RenderView")
view.ViewSize = [200, 160]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [0.0, 0.0, 0.0]
view.UseFXAA = 0
view.CameraPosition = [32.0, 20.0, 200.0]
view.CameraFocalPoint = [32.0, 32.0, 32.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
failures = 0


def check(ok, what):
    global failures
    print("%s %s" % ("ok  " if ok else "FAIL", what), flush=True)
    failures += 0 if ok else 1


def pixels():
    Render(view)
    grab = vtkWindowToImageFilter()
    grab.SetInput(view.GetRenderWindow())
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    rgb = grab.GetOutput().GetPointData().GetScalars()
    return [rgb.GetValue(i) for i in range(rgb.GetNumberOfValues())]


def mean_difference(a, b):
    covered = [i for i in range(0, len(a), 3) if sum(a[i:i + 3]) + sum(b[i:i + 3]) > 0]
    return (sum(abs(a[i + c] - b[i + c]) for i in covered for c in range(3)) /
            (3.0 * max(len(covered), 1)), len(covered))


def both(shown):
    """The image with the AVoS Volume representation, then with ParaView's own."""
    shown.SetRepresentationType("AVoS Volume")
    shown.IntegrationMethod = "Piecewise"
    shown.IntegrationTolerance = 0.001
    ours = pixels()
    shown.SetRepresentationType("Volume")
    theirs = pixels()
    shown.SetRepresentationType("AVoS Volume")
    return ours, theirs


def warnings_of(render):
    """What `render()` writes to VTK's output window (pvbatch prints Python's
    output through it too: no check while it is caught)."""
    original = vtkOutputWindow.GetInstance()
    log = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(log)
    render()
    vtkOutputWindow.SetInstance(original)
    return log.GetOutput()


shown = Show(gradient, view)
shown.SetRepresentationType("AVoS Volume")
# ParaView's default colour map (Cool to Warm, discretized to 256 colours)
# at the piecewise method's default: certified, no approximation notice.
ColorBy(shown, ("POINTS", "g", "Magnitude"))
default_map = warnings_of(lambda: Render(view))
# ParaView sets the unit distance of component 0 only, and VTK's smart mapper
# renders a vector's component through a copy of component 0's functions
# without it (its unit distance stays 1): 1 for both.
shown.ScalarOpacityUnitDistance = 1.0
colours = GetColorTransferFunction("g")
opacity = GetOpacityTransferFunction("g")
images = {}
for mode, component in (("Magnitude", 0), ("Component", 1)):
    ColorBy(shown, ("POINTS", "g", mode if mode == "Magnitude" else "Y"))
    colours.RescaleTransferFunction(-40.0, 40.0)
    opacity.RescaleTransferFunction(-40.0, 40.0)
    opacity.Points = [-40.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.5, 0.0, 40.0, 0.4, 0.5, 0.0]
    ours, theirs = both(shown)
    images[mode] = ours
    mean, covered = mean_difference(ours, theirs)
    check(covered > 500 and mean <= 4.0,
          "vector mode %s: %d pixels, %.2f/255 from ParaView's own" % (mode, covered, mean))
mean, _ = mean_difference(images["Magnitude"], images["Component"])
check(mean > 4.0, "magnitude and component images differ by %.2f/255" % mean)

ColorBy(shown, ("POINTS", "g", "Magnitude"))
colours.RescaleTransferFunction(0.0, 60.0)
opacity.RescaleTransferFunction(0.0, 255.0)
shown.UseSeparateOpacityArray = 1
shown.OpacityArray = ["POINTS", "density"]
ours, theirs = both(shown)
mean, covered = mean_difference(ours, theirs)
check(covered > 500 and mean <= 4.0,
      "separate opacity array: %d pixels, %.2f/255 from ParaView's own" % (covered, mean))
shown.UseSeparateOpacityArray = 0

# Shade with the representation's defaults (not both(): no method or
# tolerance set), against ParaView's own shaded and unshaded images.
Hide(gradient, view)
lit = Show(reader, view)
lit.SetRepresentationType("AVoS Volume")
ColorBy(lit, ("POINTS", "density"))
GetColorTransferFunction("density").RescaleTransferFunction(0.0, 255.0)
density_opacity = GetOpacityTransferFunction("density")
density_opacity.Points = [0.0, 0.0, 0.5, 0.0, 60.0, 0.0, 0.5, 0.0, 255.0, 0.6, 0.5, 0.0]
lit.ScalarOpacityUnitDistance = 1.0
plain = {}
shaded = {}
for name in ("AVoS Volume", "Volume"):
    lit.SetRepresentationType(name)
    lit.Shade = 0
    plain[name] = pixels()
    lit.Shade = 1
    log = warnings_of(lambda: Render(view))
    shaded[name] = pixels()
    if name == "AVoS Volume":
        check(log.strip() == "", "Shade with the defaults: no error or notice (%r)" % log[:200])
ours_effect, covered = mean_difference(shaded["AVoS Volume"], plain["AVoS Volume"])
their_effect, _ = mean_difference(shaded["Volume"], plain["Volume"])
apart, _ = mean_difference(shaded["AVoS Volume"], shaded["Volume"])
print("Shade: %d pixels; effect %.2f/255 (ParaView's own %.2f/255); shaded images %.2f/255 apart"
      % (covered, ours_effect, their_effect, apart))
check(covered > 500 and abs(ours_effect - their_effect) <= their_effect / 3.0,
      "Shade lights the volume as ParaView's own does (effect %.2f against %.2f/255)"
      % (ours_effect, their_effect))
check(apart <= their_effect / 2.0,
      "shaded images within half the effect: %.2f/255" % apart)
lit.Shade = 0
lit.SetRepresentationType("AVoS Volume")
lit.UseTransfer2D = 1
text = warnings_of(lambda: Render(view))
check("2D transfer function" in text, "a 2D transfer function is refused with an error naming it")
lit.UseTransfer2D = 0
Hide(reader, view)
shown = Show(gradient, view)

check("approximated" not in default_map,
      "ParaView's default colour map is certified (no approximation notice)")
for name, value in (("VolumeRenderingMode", "GPU Based"), ("GlobalIlluminationReach", 0.5),
                    ("VolumetricScatteringBlending", 0.5)):
    text = warnings_of(lambda: (setattr(shown, name, value), Render(view)))
    check("not honoured" in text or "always renders with" in text,
          "%s = %s draws a warning" % (name, value))
if failures:
    raise SystemExit("%d check(s) failed" % failures)
