#!/usr/bin/python3
"""Resident memory each volume mapper adds over the loaded volume, side by
side: vtkAdaptiveVolumeMapper (piecewise, eps 1e-3, and Riemann, h 0.5, VTK's
opacity model) and VTK's vtkFixedPointVolumeRayCastMapper, each alone in a
process, on
generated volumes (a smooth field, 800^3 uint8 and 512^3 uint16 by default).

    PYTHONPATH=build/lib/python3.11/dist-packages xvfb-run -a /usr/bin/python3 scripts/memory.py

What is measured: VmRSS after two 400x300 frames minus VmRSS with the
volume loaded and the window already rendered once without it (so the
OpenGL context is in both), and the same for the peak (VmHWM).
"""
import argparse
import json
import subprocess
import sys


def resident():
    fields = {}
    with open("/proc/self/status") as status:
        for line in status:
            key, _, value = line.partition(":")
            if key in ("VmRSS", "VmHWM"):
                fields[key] = int(value.split()[0]) / 1024.0  # MiB
    return fields


def child(mapper_name, size, kind):
    import numpy as np
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer,
                                             vtkRenderWindow, vtkVolume, vtkVolumeProperty)
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL factories)
    import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

    top = 255 if kind == "uint8" else 65535
    # A smooth field: a ball of rising values with ripples, built a slab at a
    # time so that the generator's temporaries stay small.
    data = np.empty((size, size, size), dtype=np.uint8 if kind == "uint8" else np.uint16)
    axis = np.linspace(-1.0, 1.0, size, dtype=np.float32)
    y, x = np.meshgrid(axis, axis, indexing="ij")
    for k in range(size):
        r = np.sqrt(x * x + y * y + axis[k] * axis[k])
        v = np.clip(1.0 - r, 0.0, 1.0) * (0.8 + 0.2 * np.sin(9.0 * x + 7.0 * axis[k]))
        data[k] = (v * top).astype(data.dtype)
    image = vtkImageData()
    image.SetDimensions(size, size, size)
    array = numpy_support.numpy_to_vtk(data.reshape(-1), deep=0)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(400, 300)
    renderer = vtkRenderer()
    window.AddRenderer(renderer)
    window.Render()
    before = resident()

    color = vtkColorTransferFunction()
    color.AddRGBPoint(0, 0.1, 0.2, 0.9)
    color.AddRGBPoint(top, 1.0, 0.9, 0.6)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(0, 0.0)
    opacity.AddPoint(0.3 * top, 0.0)
    opacity.AddPoint(0.6 * top, 0.05)
    opacity.AddPoint(top, 0.2)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    if mapper_name.startswith("avos"):
        import avos
        mapper = avos.vtkAdaptiveVolumeMapper()
        if mapper_name == "avos-riemann":
            mapper.SetIntegrationMethodToRiemann()
            mapper.SetSampleDistance(0.5)
        else:
            mapper.SetIntegrationMethodToPiecewiseAdaptive()
            mapper.SetTolerance(1e-3)
        mapper.SetOpacityModelToVTK()
    else:
        from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
        mapper = vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputData(image)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer.AddVolume(volume)
    renderer.ResetCamera()
    window.Render()
    renderer.GetActiveCamera().Azimuth(20)
    window.Render()
    after = resident()
    print(json.dumps({
        "volume_mib": data.nbytes / 2**20,
        "added_mib": after["VmRSS"] - before["VmRSS"],
        "peak_added_mib": after["VmHWM"] - before["VmRSS"],
    }))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--child", nargs=3, metavar=("MAPPER", "SIZE", "TYPE"))
    parser.add_argument("--volumes", default="800:uint8,512:uint16")
    args = parser.parse_args()
    if args.child:
        child(args.child[0], int(args.child[1]), args.child[2])
        return 0
    mappers = ("vtk", "avos-piecewise", "avos-riemann")
    print("| volume | size | VTK fixed point: added (peak) | AVoS piecewise: added (peak), "
          "ratio | AVoS Riemann: added (peak), ratio |")
    print("|---|---|---|---|---|")
    for spec in args.volumes.split(","):
        size, kind = spec.split(":")
        row = {}
        for mapper in mappers:
            out = subprocess.run([sys.executable, __file__, "--child", mapper, size, kind],
                                 capture_output=True, text=True, check=True)
            row[mapper] = json.loads(out.stdout.strip().splitlines()[-1])
        v = row["vtk"]
        cells = ["+%.0f MiB (+%.0f)" % (v["added_mib"], v["peak_added_mib"])]
        for mapper in mappers[1:]:
            a = row[mapper]
            cells.append("+%.0f MiB (+%.0f), %.2f" % (a["added_mib"], a["peak_added_mib"],
                                                      a["added_mib"] / max(v["added_mib"], 1.0)))
        print("| %s^3 %s | %.0f MiB | %s |" % (size, kind, v["volume_mib"], " | ".join(cells)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
