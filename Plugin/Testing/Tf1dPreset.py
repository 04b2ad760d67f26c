"""pvpython: the AVoS plugin turns a .tf1d file into a ParaView colour-map
preset (the TransferFunction1DReader proxy, VTK opacity model) that
ImportPresets() and ApplyPreset() put into a lookup table and an opacity
function, every knot as the file has it (colours) or as 1 - exp(-tau)
(opacities).
  pvpython Tf1dPreset.py PLUGIN TF1D_FILE OUT_DIR
"""

import json
import math
import os
import sys

from paraview import servermanager
from paraview.simple import (GetColorTransferFunction, GetOpacityTransferFunction,
                             ImportPresets, LoadPlugin)

plugin, tf1d, out = sys.argv[1:4]
LoadPlugin(plugin, remote=False, ns=globals())
preset = os.path.join(out, "preset.json")
name = "AVoS " + os.path.basename(tf1d)
reader = servermanager.misc.TransferFunction1DReader(FileName=tf1d, OpacityModel="VTK")
reader.WritePreset = [preset, name]
reader.UpdateVTKObjects()
ImportPresets(preset)
lut = GetColorTransferFunction("density")
lut.ApplyPreset(name, False)
pwf = GetOpacityTransferFunction("density")
pwf.ApplyPreset(name, False)

# The file's knots, read here as the format states them.
with open(tf1d) as f:
    words = f.read().split()
colours = int(words[2])
knots = [float(w) for w in words[3:3 + 4 * colours]]
expected_rgb = []
for i in range(colours):
    r, g, b, x = knots[4 * i:4 * i + 4]
    expected_rgb += [x, r, g, b]
rest = words[3 + 4 * colours:]
opacities = int(rest[0])
taus = [float(w) for w in rest[1:1 + 2 * opacities]]
expected_alpha = [(taus[2 * i + 1], -math.expm1(-taus[2 * i])) for i in range(opacities)]

rgb = list(lut.RGBPoints)
points = list(pwf.Points)
alpha = [(points[4 * i], points[4 * i + 1]) for i in range(len(points) // 4)]
failures = []
if rgb != expected_rgb:
    failures.append("colours %s, expected %s" % (rgb[:8], expected_rgb[:8]))
if len(alpha) != opacities or any(abs(a[0] - e[0]) > 0 or abs(a[1] - e[1]) > 1e-15
                                  for a, e in zip(alpha, expected_alpha)):
    failures.append("opacities %s, expected %s" % (alpha[:4], expected_alpha[:4]))
print("preset %s: %d colour knots, %d opacity knots, %s" % (
    name, colours, opacities, "equal" if not failures else "; ".join(failures)), flush=True)
with open(preset) as f:
    json.load(f)  # valid JSON
sys.exit(1 if failures else 0)
