"""Render a volume with a .tf1d transfer function and write a PNG and a report.

The pipeline: reader (AVoS's vtkVolvisRawReader, VTK's XML reader, or AVoS's
analytic source) -> vtkVolumeProperty filled by vtkTransferFunction1DReader ->
volume mapper -> off-screen render window -> PNG.

    python3 render_volume.py --data ../shared/data --output out
    python3 render_volume.py --volume Fuel.1.64x64x64.raw --tf my.tf1d --output out
"""

import argparse
import json
import os
import sys
import time

import avos
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
from vtkmodules.vtkRenderingCore import (vtkRenderWindow, vtkRenderer, vtkVolume,
                                         vtkVolumeProperty, vtkWindowToImageFilter)
from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL render window)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401  (volume display helper)

HERE = os.path.dirname(os.path.abspath(__file__))
PROJECT_DATA = os.path.join(HERE, "..", "..", "Data")


def default_scene(data):
    """Bonsai with the paper's transfer function if the shared data is there."""
    volume = os.path.join(data, "volumes", "bonsai_zfp.vti")
    tf = os.path.join(data, "tf", "Bonsai.1.256x256x256.linear.tf1d")
    if os.path.exists(volume) and os.path.exists(tf):
        return volume, tf
    return None, os.path.join(PROJECT_DATA, "Sphere.tf1d")


def make_source(volume):
    if volume is None:
        source = avos.vtkAnalyticVolumeSource()
        source.SetFunctionToSphereDistance()
        source.SetDimensions(96, 96, 96)
        source.SetBounds(-48, 48, -48, 48, -48, 48)
        source.SetScalarScale(100.0 / 48.0)
        return source, "analytic sphere distance, 96^3"
    if volume.endswith(".vti"):
        source = vtkXMLImageDataReader()
    else:
        source = avos.vtkVolvisRawReader()
    source.SetFileName(volume)
    return source, os.path.basename(volume)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.path.join(HERE, "..", "..", "..", "shared", "data"))
    parser.add_argument("--volume", help="volume file (.vti or volvis .raw)")
    parser.add_argument("--tf", help=".tf1d transfer function (extinction per voxel unit)")
    parser.add_argument("--size", default="800x600")
    parser.add_argument("--output", default="out")
    args = parser.parse_args(argv)

    volume_path, tf_path = (args.volume, args.tf) if args.volume else default_scene(args.data)
    tf_path = args.tf or tf_path
    source, description = make_source(volume_path)
    source.Update()
    image = source.GetOutput()
    if image.GetNumberOfPoints() == 0:
        print("error: could not read the volume", file=sys.stderr)
        return 1

    prop = vtkVolumeProperty()
    prop.SetInterpolationTypeToLinear()
    tf = avos.vtkTransferFunction1DReader()
    tf.SetFileName(tf_path)
    tf.SetOpacityModelToVTK()  # VTK's mapper: alpha per voxel of spacing[0]
    tf.SetUnitDistance(image.GetSpacing()[0])
    if not tf.FillVolumeProperty(prop):
        return 1

    mapper = vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    mapper.SetSampleDistance(0.5 * min(image.GetSpacing()))
    actor = vtkVolume()
    actor.SetMapper(mapper)
    actor.SetProperty(prop)

    width, height = (int(v) for v in args.size.split("x"))
    renderer = vtkRenderer()
    renderer.AddVolume(actor)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(width, height)
    window.AddRenderer(renderer)
    renderer.ResetCamera()

    start = time.perf_counter()
    window.Render()
    seconds = time.perf_counter() - start

    os.makedirs(args.output, exist_ok=True)
    png = os.path.join(args.output, "volume.png")
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    writer = vtkPNGWriter()
    writer.SetInputConnection(grab.GetOutputPort())
    writer.SetFileName(png)
    writer.Write()

    report = {
        "volume": description,
        "dimensions": image.GetDimensions(),
        "scalar_range": image.GetScalarRange(),
        "transfer_function": os.path.basename(tf_path),
        "mapper": "vtkFixedPointVolumeRayCastMapper",
        "image_size": [width, height],
        "render_seconds": round(seconds, 3),
        "image": os.path.basename(png),
    }
    with open(os.path.join(args.output, "report.json"), "w") as f:
        json.dump(report, f, indent=2)
    print(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
