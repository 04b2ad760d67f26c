"""First Volume-on-Surface figures (a benchmark, not a test): Foot at every
2nd voxel (128^3), its bone isosurface (iso 80), 800x600 off-screen, the
camera turning 5 degrees a frame. Prints the median time per frame of VoS^M*
at each level of detail, VoS^M's previsualization and camera-only frames, its
memory report, and ray casting the same frames (vtkAdaptiveVolumeMapper,
Riemann h 0.5, and VTK's fixed-point mapper at the same step).

    PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 scripts/bench-vos.py
"""

import os
import time

import avos
from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D
from vtkmodules.vtkImagingCore import vtkExtractVOI
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderWindow, vtkRenderer,
                                         vtkVolume, vtkVolumeProperty)
from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL render window)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401  (volume display helper)

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data")


def main():
    reader = vtkXMLImageDataReader()
    reader.SetFileName(os.path.join(DATA, "volumes", "foot_zfp.vti"))
    volume = vtkExtractVOI()
    volume.SetInputConnection(reader.GetOutputPort())
    volume.SetSampleRate(2, 2, 2)
    volume.Update()
    surface = vtkFlyingEdges3D()
    surface.SetInputConnection(volume.GetOutputPort())
    surface.SetValue(0, 80)
    surface.ComputeNormalsOn()
    surface.Update()
    print("Foot 128^3 (every 2nd voxel), iso 80: %d triangles, %d vertices"
          % (surface.GetOutput().GetNumberOfPolys(), surface.GetOutput().GetNumberOfPoints()))

    tf = avos.vtkTransferFunction1DReader()
    tf.SetFileName(os.path.join(DATA, "tf", "Foot.tf1d"))
    tf.SetOpacityModelToVTK()
    tf.SetUnitDistance(2)  # one voxel of the coarse grid
    prop = vtkVolumeProperty()
    prop.SetInterpolationTypeToLinear()
    tf.FillVolumeProperty(prop)

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(800, 600)
    renderer = vtkRenderer()
    window.AddRenderer(renderer)

    def median_frame(n=5):
        times = []
        for _ in range(n):
            renderer.GetActiveCamera().Azimuth(5)
            start = time.perf_counter()
            window.Render()
            times.append(time.perf_counter() - start)
        return sorted(times)[len(times) // 2]

    # VoS^M*: one ray per visible vertex each frame.
    vos_mapper = avos.vtkVolumeOnSurfaceMapper()
    vos_mapper.SetInputConnection(surface.GetOutputPort())
    vos_mapper.SetVolumeConnection(volume.GetOutputPort())
    vos_mapper.SetVolumeProperty(prop)
    actor = vtkActor()
    actor.SetMapper(vos_mapper)
    renderer.AddActor(actor)
    renderer.ResetCamera()
    window.Render()  # builds the levels of detail
    for level in range(vos_mapper.GetNumberOfLevelsOfDetail()):
        vos_mapper.SetLevelOfDetail(level)
        window.Render()
        print("VoS^M* level %d: %.3f s/frame, %d visible vertices"
              % (level, median_frame(), vos_mapper.GetNumberOfVisibleVertices()))
    renderer.RemoveActor(actor)

    # VoS^M: cones cast once, colours reassigned per camera.
    vos = avos.vtkVolumeOnSurfaceFilter()
    vos.SetInputConnection(surface.GetOutputPort())
    vos.SetVolumeConnection(volume.GetOutputPort())
    vos.SetVolumeProperty(prop)
    vos.SetCamera(renderer.GetActiveCamera())
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(vos.GetOutputPort())
    mapper.SetColorModeToDirectScalars()
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer.AddActor(actor)
    start = time.perf_counter()
    window.Render()
    print("VoS^M first frame (previsualization): %.2f s, %d rays"
          % (time.perf_counter() - start, vos.GetNumberOfRaysCast()))
    print("VoS^M camera-only frames: %.3f s/frame" % median_frame())
    print("VoS^M memory: volume %.1f MB, surface %.1f MB, cones %.1f MB"
          % (vos.GetVolumeMemory() / 1e6, vos.GetSurfaceMemory() / 1e6, vos.GetConesMemory() / 1e6))
    renderer.RemoveActor(actor)

    # Ray casting the same frames.
    adaptive = avos.vtkAdaptiveVolumeMapper()
    adaptive.SetIntegrationMethodToRiemann()
    adaptive.SetSampleDistance(0.5)  # voxel units
    fixed = vtkFixedPointVolumeRayCastMapper()
    fixed.SetSampleDistance(1.0)  # world units: half a coarse voxel
    fixed.SetAutoAdjustSampleDistances(0)
    for name, ray_caster in [("vtkAdaptiveVolumeMapper Riemann h 0.5", adaptive),
                             ("VTK fixed-point h 0.5", fixed)]:
        ray_caster.SetInputConnection(volume.GetOutputPort())
        prop_volume = vtkVolume()
        prop_volume.SetMapper(ray_caster)
        prop_volume.SetProperty(prop)
        renderer.AddVolume(prop_volume)
        window.Render()
        print("%s: %.3f s/frame" % (name, median_frame(3)))
        renderer.RemoveVolume(prop_volume)


if __name__ == "__main__":
    main()
