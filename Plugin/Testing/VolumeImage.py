"""Renders Neghip in ParaView with a volume representation type ("AVoS
Volume", with an integration method, or ParaView's own "Volume") on any
number of MPI ranks (pvbatch), the pieces composited by ParaView in
visibility order; rank 0 saves the image. VolumeImages.py compares them.
  pvbatch VolumeImage.py PLUGIN DATA_DIR OUT.png "AVoS Volume"|"Volume" [METHOD]
"""

import sys

from paraview.simple import (ColorBy, CreateView, GetColorTransferFunction,
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
shown = Show(reader, view)
shown.SetRepresentationType(representation)
ColorBy(shown, ("POINTS", "density"))
GetColorTransferFunction("density").RGBPoints = [0.0, 0.1, 0.2, 1.0, 255.0, 1.0, 0.4, 0.1]
GetOpacityTransferFunction("density").Points = [0.0, 0.0, 0.5, 0.0, 255.0, 0.3, 0.5, 0.0]
if representation == "AVoS Volume":
    shown.IntegrationMethod = method
    shown.IntegrationTolerance = 0.001
view.CameraPosition = [32.0, 20.0, 200.0]
view.CameraFocalPoint = [32.0, 32.0, 32.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
Render(view)
SaveScreenshot(out, view, ImageResolution=[300, 240])
