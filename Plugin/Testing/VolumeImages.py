"""Compares VolumeImage.py's images (python3 with ParaView's vtkmodules):
- the "AVoS Volume" representation renders with vtkAdaptiveVolumeMapper:
  its Riemann and piecewise images differ (only that mapper has the
  setting), and both differ from ParaView's own volume mapper's;
- on 2 and 4 ranks its image equals the one-process image within eps plus
  the 8-bit quantisation of the compositing, in 1/255 per channel: a ray
  cut into k pieces (k <= 2 on 2 ranks, whose pieces are two slabs; k <= 3
  on 4 ranks, a 2 x 2 split: a straight ray meets at most 3 of the 4 boxes)
  composites k integrals each within eps per channel, colour and alpha:
  2 k eps 255; each rank's image is rounded to 8 bits (0.5 per piece),
  and IceT blends 8-bit images, where each of the k - 1 blends rounds the
  front alpha (0.5 of the back's colour) and truncates (1); the
  one-process image is rounded (0.5). Bound: 2 k eps 255 + 0.5 k +
  1.5 (k - 1) + 0.5, 4 on 2 ranks and 6 on 4 at eps = 0.001. ParaView's
  own mapper's difference on the same frames is printed beside it;
- the Volume-on-Surface surface on 2 and 4 ranks: its vertices' colours are
  the one-process ones (PipelinePieces.py), so pixels may differ only where
  the pieces' border triangles meet (depth ties): at most 0.5 % of them.
  python3 VolumeImages.py DIR   (DIR holding avos-{1,2,4}.png, avos-riemann.png,
                                 paraview-{1,2,4}.png, surface-{1,2,4}.png)
"""

import os
import sys

from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader


def load(name):
    reader = vtkPNGReader()
    reader.SetFileName(os.path.join(sys.argv[1], name))
    reader.Update()
    return vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)


def difference(a, b):
    d = abs(load(a) - load(b))
    return int(d.max()), float(d.mean())


failures = 0


def check(ok, what):
    global failures
    print("%s %s" % ("ok  " if ok else "FAIL", what))
    failures += 0 if ok else 1


riemann = difference("avos-1.png", "avos-riemann.png")
paraview = difference("avos-1.png", "paraview-1.png")
check(riemann[1] > 0.0, "AVoS piecewise against AVoS Riemann: max %d, mean %.3f (/255)" % riemann)
check(paraview[1] > 0.0, "AVoS against ParaView's mapper: max %d, mean %.3f" % paraview)
check(load("avos-1.png").max() > 100, "the volume is visible")
eps = 0.001  # VolumeImage.py's IntegrationTolerance
for ranks, pieces in ((2, 2), (4, 3)):
    bound = 2 * pieces * eps * 255 + 0.5 * pieces + 1.5 * (pieces - 1) + 0.5
    ours = difference("avos-1.png", "avos-%d.png" % ranks)
    theirs = difference("paraview-1.png", "paraview-%d.png" % ranks)
    check(ours[0] <= bound,
          "%d ranks against 1: AVoS max %d, mean %.3f (bound %.2f); ParaView's own max %d, "
          "mean %.3f" % (ranks, ours[0], ours[1], bound, theirs[0], theirs[1]))
for ranks in (2, 4):
    d = abs(load("surface-1.png") - load("surface-%d.png" % ranks)).max(axis=1)
    share = float((d > 0).mean())
    check(share <= 0.005, "Volume on Surface, %d ranks against 1: %.3f %% of pixels differ "
          "(max %d)" % (ranks, 100.0 * share, int(d.max())))
sys.exit(1 if failures else 0)
