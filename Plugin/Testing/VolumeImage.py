"""Renders Neghip in ParaView on any number of MPI ranks (pvbatch), the
pieces composited by ParaView; rank 0 saves the image. VolumeImages.py
compares them. The representation is a volume type ("AVoS Volume", with an
integration method, or ParaView's own "Volume"), or "Volume on Surface":
the contour at 60 coloured by the plugin's Volume on Surface filter
(VoSDisplayColors, drawn unlit).
  pvbatch VolumeImage.py PLUGIN DATA_DIR OUT.png REPRESENTATION [METHOD]
"""

import sys

from paraview.simple import (ColorBy, Contour, CreateView, GetColorTransferFunction,
                             GetOpacityTransferFunction, LoadPlugin, Render, SaveScreenshot,
                             Show)

plugin, data, out, representation = sys.argv[1:5]
method = sys.argv[5] if len(sys.argv) > 5 else "Piecewise"
LoadPlugin(plugin, remote=False, ns=globals())
reader = VolvisRawReader(  # noqa: F821
    FileName=data + "/volumes/Neghip.1.64x64x64.raw")
view = CreateView("RenderView")
view.ViewSize = [300, 240]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [0.0, 0.0, 0.0]
# FXAA (on by default in pvbatch) smooths edges in screen space, and
# differently on several ranks than on one: up to 19/255 at the edges of
# bright structures, the same pixels for ParaView's own mapper. The images
# compare the integration and the compositing, so it is off.
view.UseFXAA = 0
colours = GetColorTransferFunction("density")
colours.RGBPoints = [0.0, 0.1, 0.2, 1.0, 255.0, 1.0, 0.4, 0.1]
opacity = GetOpacityTransferFunction("density")
opacity.Points = [0.0, 0.0, 0.5, 0.0, 255.0, 0.3, 0.5, 0.0]
if representation == "Volume on Surface":
    contour = Contour(Input=reader, ContourBy=["POINTS", "density"], Isosurfaces=[60.0],
                      ComputeNormals=1, ComputeScalars=0)
    vos = VolumeonSurface(  # noqa: F821
        Input=contour, Volume=VolvisRawReader(  # noqa: F821, a producer of its own
            FileName=data + "/volumes/Neghip.1.64x64x64.raw"),
        ColorTransferFunction=colours, ScalarOpacityFunction=opacity,
        CameraPosition=[32.0, 20.0, 200.0], CameraFocalPoint=[32.0, 32.0, 32.0])
    shown = Show(vos, view)
    ColorBy(shown, ("POINTS", "VoSDisplayColors"))
    shown.MapScalars = 0
    shown.Ambient = 1.0
    shown.Diffuse = 0.0
else:
    shown = Show(reader, view)
    shown.SetRepresentationType(representation)
    ColorBy(shown, ("POINTS", "density"))
if representation == "AVoS Volume":
    shown.IntegrationMethod = method
    shown.IntegrationTolerance = 0.001
view.CameraPosition = [32.0, 20.0, 200.0]
view.CameraFocalPoint = [32.0, 32.0, 32.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
Render(view)
SaveScreenshot(out, view, ImageResolution=[300, 240])
