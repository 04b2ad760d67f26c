#!/usr/bin/env python3
"""What a second component costs (a benchmark, not a test): each dataset
with its paper transfer function (VTK's opacity model), and the same
volume with a second component appended, side by side in one session on
the same frame (800x600, default view, 2 threads, median of 3 frames):

- one component;
- two, the second of opacity 0 (the first's image, the mixture's path);
- two, the second the volume mirrored along x through the same transfer
  function (weight 1): about twice the visible matter;
- two, the first alone rendered (vtkAdaptiveVolumeMapper's vector mode
  COMPONENT, as ParaView colours by a component);
- VTK's fixed-point mapper (step 0.5) on the one and the two components;
- with --methods, the GPU mapper's sampled methods (gpu-riemann,
  gpu-coupled at eps 1e-3: every channel read at each sample) on the one
  component, the second transparent and the mirrored pair.

Per run: seconds, the ratio to the one-component frame of the same method,
cells and pieces per ray, and for the piecewise method the largest
difference from the one-component image where the second is transparent.

    PYTHONPATH=build/python xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" /usr/bin/python3 \\
        scripts/bench-components.py [--datasets Bonsai,Foot,Engine] [--size 800x600] \\
        [--methods piecewise,riemann,vtk-fixed-point,gpu-riemann,gpu-coupled]
"""

import argparse
import os
import statistics
import time

import avos
from vtkmodules.vtkImagingCore import vtkImageAppendComponents, vtkImageFlip
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderer, vtkVolume, vtkVolumeProperty
from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL render window)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401  (volume display helper)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "..", "shared", "data")
DATASETS = {
    "Bonsai": ("volumes/bonsai_zfp.vti", "tf/Bonsai.1.256x256x256.linear.tf1d"),
    "Foot": ("volumes/foot_zfp.vti", "tf/Foot.tf1d"),
    "Engine": ("volumes/engine_zfp.vti", "tf/Engine.1.256x256x128.linear.tf1d"),
}


def volumes(path):
    """The volume, and the volume with its mirror image as a second component."""
    reader = vtkXMLImageDataReader()
    reader.SetFileName(os.path.join(DATA, path))
    reader.Update()
    mirror = vtkImageFlip()
    mirror.SetInputConnection(reader.GetOutputPort())
    mirror.SetFilteredAxis(0)
    append = vtkImageAppendComponents()
    append.AddInputConnection(reader.GetOutputPort())
    append.AddInputConnection(mirror.GetOutputPort())
    append.Update()
    # Copies: the filters' outputs are emptied when the filters go.
    one, two = vtkImageData(), vtkImageData()
    one.DeepCopy(reader.GetOutput())
    two.DeepCopy(append.GetOutput())
    return one, two


def property_of(tf_path, second):
    """The paper's transfer function for both components; the second's
    opacity 0 unless `second`."""
    tf = avos.vtkTransferFunction1DReader()
    tf.SetFileName(os.path.join(DATA, tf_path))
    tf.SetOpacityModelToVTK()
    prop = vtkVolumeProperty()
    tf.FillVolumeProperty(prop)
    prop.SetInterpolationTypeToLinear()
    prop.SetColor(1, prop.GetRGBTransferFunction(0))
    if second:
        prop.SetScalarOpacity(1, prop.GetScalarOpacity(0))
    else:
        clear = vtkPiecewiseFunction()
        clear.AddPoint(0.0, 0.0)
        clear.AddPoint(255.0, 0.0)
        prop.SetScalarOpacity(1, clear)
    return prop


def run(image, prop, mapper, size, frames):
    """Median seconds of `frames` renders (the camera nudged each time so
    that nothing is reused), and the mapper."""
    mapper.SetInputData(image)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.SetSize(*size)
    window.AddRenderer(renderer)
    renderer.ResetCamera()
    window.Render()  # conversions, ranges and the first frame
    seconds = []
    for i in range(frames):
        renderer.GetActiveCamera().Azimuth(0.01 if i % 2 else -0.01)
        start = time.perf_counter()
        window.Render()
        seconds.append(time.perf_counter() - start)
    return statistics.median(seconds)


def avos_mapper(method):
    mapper = avos.vtkAdaptiveVolumeMapper()
    mapper.SetAutoAdjustSampleDistances(0)
    if method == "piecewise":
        mapper.SetIntegrationMethodToPiecewiseAdaptive()
        mapper.SetTolerance(1e-3)
    else:
        mapper.SetIntegrationMethodToRiemann()
        mapper.SetSampleDistance(0.5)
    return mapper


def gpu_mapper(method):
    mapper = avos.vtkOpenGLAdaptiveVolumeMapper()
    if method == "gpu-riemann":
        mapper.SetIntegrationMethodToRiemann()
    else:
        mapper.SetIntegrationMethodToAdaptiveCoupled()
        mapper.SetTolerance(1e-3)
    return mapper


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default="Bonsai,Foot,Engine")
    parser.add_argument("--size", default="800x600")
    parser.add_argument("--frames", type=int, default=3)
    parser.add_argument("--methods", default="piecewise,riemann,vtk-fixed-point")
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    print("| dataset | method | components | seconds | ratio to one | cells/ray | pieces/ray |")
    print("|---|---|---|---|---|---|---|")
    for name in args.datasets.split(","):
        path, tf_path = DATASETS[name]
        one, two = volumes(path)
        for method in args.methods.split(","):
            baseline = None
            image_one = None
            for label, image, second in (("1", one, False), ("2, second transparent", two, False),
                                         ("2, second mirrored", two, True),
                                         ("2, vector mode COMPONENT 0", two, False)):
                if method == "vtk-fixed-point" and not label.endswith("mirrored") and label != "1":
                    continue
                gpu = method.startswith("gpu-")
                if gpu and label.startswith("2, vector mode"):
                    continue
                mapper = (vtkFixedPointVolumeRayCastMapper() if method == "vtk-fixed-point"
                          else gpu_mapper(method) if gpu else avos_mapper(method))
                if label.startswith("2, vector mode"):
                    mapper.SetVectorMode(avos.vtkAdaptiveVolumeMapper.COMPONENT)
                    mapper.SetVectorComponent(0)
                if method == "vtk-fixed-point":
                    mapper.SetSampleDistance(0.5)
                    mapper.SetAutoAdjustSampleDistances(0)
                seconds = run(image, property_of(tf_path, second), mapper, size, args.frames)
                baseline = baseline or seconds
                cells = pieces = ""
                extra = ""
                if method != "vtk-fixed-point" and not gpu:
                    cells = "%.1f" % mapper.GetMeanCellsPerRay()
                    pieces = "%.1f" % mapper.GetMeanPiecesPerRay()
                    rgba = mapper.GetRenderedImage().GetPointData().GetScalars()
                    if label == "1":
                        image_one = [rgba.GetValue(i) for i in range(rgba.GetNumberOfValues())]
                    elif not second:
                        apart = max(abs(rgba.GetValue(i) - image_one[i])
                                    for i in range(0, rgba.GetNumberOfValues(), 7))
                        extra = " (%.1e off the one-component image)" % apart
                print("| %s | %s | %s | %.3f | %.2fx%s | %s | %s |" % (
                    name, method, label, seconds, seconds / baseline, extra, cells, pieces),
                    flush=True)


if __name__ == "__main__":
    main()
