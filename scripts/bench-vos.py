"""The Volume-on-Surface paper's evaluation on this machine (a benchmark, not
a test): Foot, Bonsai and Engine, each at every 2nd voxel (so that their
isosurfaces have the size of the paper's, about 10^5 vertices), 800x600 and
400x300 off screen, the same camera for every technique.

- Table II: isosurface vertices and triangles (vtkFlyingEdges3D).
- Table III: memory of VoS^M (volume, isosurface, cones), VoS^M* (volume,
  isosurface) and ray casting (volume), from the classes' own reports.
- Figures 6 and 7: seconds per frame while the camera turns about the view
  up axis, without and with a transfer-function change every frame, for
  VoS^M, VoS^M*, vtkAdaptiveVolumeMapper (Riemann h 0.5) and VTK's
  fixed-point mapper (h 0.5), at both sizes.
- Figure 10 and Table IV: VoS^M* on the isosurface decimated 0/25/50/75/90 %
  by vtkOpenMeshDecimation: time per frame and isosurface memory.
- VoS^M* auto: the mapper's automatic level of detail over the same five
  levels (a still window: the screen-density rule picks the level).
- Quality: PSNR and SSIM (avos-compare) of every technique's first frame
  against the ray-cast reference (vtkAdaptiveVolumeMapper, coupled Simpson,
  eps 0.001) on the same camera, and the PSNR over the surface's footprint
  only (the pixels an unlit drawing of the isosurface covers), where VoS
  has something to show; images saved, and one labelled figure per dataset.

Every window renders without multisampling (VTK's default 8x costs every
technique and doubles a mesh draw on llvmpipe).

Writes report.md, results.csv and images/ into the output folder:

    PYTHONPATH=build/python xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" /usr/bin/python3 \\
        scripts/bench-vos.py [--datasets Foot,Bonsai,Engine] [--frames 12] [--output out/bench-vos]
"""

import argparse
import csv
import json
import os
import statistics
import subprocess
import time

import math

import avos
from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D
from vtkmodules.vtkImagingCore import vtkExtractVOI
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
from vtkmodules.vtkImagingCore import vtkImageConstantPad
from vtkmodules.vtkRenderingCore import (vtkActor, vtkImageActor, vtkPolyDataMapper,
                                         vtkRenderWindow, vtkRenderer, vtkTextActor, vtkVolume,
                                         vtkVolumeProperty, vtkWindowToImageFilter)
from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
import vtkmodules.vtkRenderingFreeType  # noqa: F401  (the figures' labels)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL render window)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401  (volume display helper)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "..", "shared", "data")
COMPARE = os.path.join(ROOT, "build", "bin", "avos-compare")

# Volume, transfer function, and the isovalue where the transfer function
# starts to show: VoS replaces the (empty) space in front of the visible
# volume by the surface, and each vertex's ray integrates what lies behind
# it. Engine's linear file is transparent up to 30; Bonsai's linear file is
# not transparent anywhere above 0 (a fog in front of any surface: VoS cannot
# show it), so its scene takes Bonsai's other file, transparent up to 35;
# Foot.tf1d makes the air a fog (opacity 0.3 at scalar 0) and the bone
# almost transparent, so its scene keeps the file's colours with soft tissue
# 0.05 (scalars 60 to 110) and bone 0.1 (from 170), transparent below 40.
# What still lies in front of each surface is measured (VoS^M* integrating
# the volume in front, IN_FRONT_OF_SURFACE) and reported.
FOOT_OPACITY = [(0, 0.0), (40, 0.0), (60, 0.05), (110, 0.05), (130, 0.0), (160, 0.0), (170, 0.1),
                (255, 0.1)]
DATASETS = {
    "Foot": ("foot_zfp.vti", "Foot.tf1d", 45,
             "its colours; opacity " + ", ".join("%g: %g" % k for k in FOOT_OPACITY)),
    "Bonsai": ("bonsai_zfp.vti", "Bonsai.1.256x256x256.tf1d", 35, ""),
    "Engine": ("engine_zfp.vti", "Engine.1.256x256x128.linear.tf1d", 35, ""),
}
SIZES = [(800, 600), (400, 300)]
REDUCTIONS = [0.0, 0.25, 0.5, 0.75, 0.9]
# The paper's Foot (102x247x200): Table II, Table III (MB) and Table IV (MB).
PAPER_FOOT = {"vertices": 120720, "polygons": 238816,
              "vos_m": (4.8, 5.8, 20.9, 31.5), "vos_m_star": (4.8, 5.8, 10.6), "rc": 4.8,
              "decimated": (5.8, 4.4, 2.9, 1.5, 1.3)}


def load(name, rate=2):
    """The volume at every `rate`-th voxel, its closed isosurface, and the
    transfer function's file."""
    volume_file, tf_file, iso, _ = DATASETS[name]
    reader = vtkXMLImageDataReader()
    reader.SetFileName(os.path.join(DATA, "volumes", volume_file))
    if rate == 1:
        # (vtkExtractVOI at rate 1 makes VTK 9.1's XML reader read a
        # sub-extent of these files and crash.)
        volume = reader
    else:
        volume = vtkExtractVOI()
        volume.SetInputConnection(reader.GetOutputPort())
        volume.SetSampleRate(rate, rate, rate)
    volume.Update()
    # Closed where the visible volume meets the grid's boundary (Bonsai's
    # soil and pot are cut by it): contoured on the volume padded with one
    # layer of 0, below every isovalue, so that the surface caps the cut
    # and its vertices there cast their rays into the volume.
    extent = volume.GetOutput().GetExtent()
    pad = vtkImageConstantPad()
    pad.SetInputConnection(volume.GetOutputPort())
    pad.SetConstant(0)
    pad.SetOutputWholeExtent(extent[0] - 1, extent[1] + 1, extent[2] - 1, extent[3] + 1,
                             extent[4] - 1, extent[5] + 1)
    surface = vtkFlyingEdges3D()
    surface.SetInputConnection(pad.GetOutputPort())
    surface.SetValue(0, iso)
    surface.ComputeNormalsOn()
    surface.Update()
    return volume, surface, os.path.join(DATA, "tf", tf_file)


def make_property(tf_path, name, rate=2):
    tf = avos.vtkTransferFunction1DReader()
    tf.SetFileName(tf_path)
    tf.SetOpacityModelToVTK()
    tf.SetUnitDistance(rate)  # one voxel of the grid rendered
    prop = vtkVolumeProperty()
    prop.SetInterpolationTypeToLinear()
    if not tf.FillVolumeProperty(prop):
        raise SystemExit("cannot read " + tf_path)
    if name == "Foot":
        opacity = prop.GetScalarOpacity()
        opacity.RemoveAllPoints()
        for value, alpha in FOOT_OPACITY:
            opacity.AddPoint(value, alpha)
    return prop


class Scene:
    """One off-screen window; the camera reset on the volume from the front."""

    def __init__(self, size, volume):
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(*size)
        self.window.SetMultiSamples(0)
        self.renderer = vtkRenderer()
        self.renderer.SetBackground(0, 0, 0)
        self.window.AddRenderer(self.renderer)
        bounds = volume.GetOutput().GetBounds()
        self.renderer.ResetCamera(bounds)
        self.camera = self.renderer.GetActiveCamera()
        self.start = (self.camera.GetPosition(), self.camera.GetFocalPoint(),
                      self.camera.GetViewUp())

    def reset(self):
        self.camera.SetPosition(self.start[0])
        self.camera.SetFocalPoint(self.start[1])
        self.camera.SetViewUp(self.start[2])
        self.renderer.ResetCameraClippingRange()

    def frames(self, n, step_degrees, change=None):
        """Seconds per frame while turning; `change` is called before each."""
        times = []
        for i in range(n):
            self.camera.Azimuth(step_degrees)
            self.renderer.ResetCameraClippingRange()
            if change:
                change(i)
            start = time.perf_counter()
            self.window.Render()
            times.append(time.perf_counter() - start)
        return times

    def save(self, path):
        save_png(self.window, path)


def save_png(window, path):
    """Writes what `window` last drew (its back buffer) to `path`."""
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()


def tf_wiggle(prop):
    """A transfer-function change per frame: the opacity of every knot scaled
    by 0.9 or back, so the data stay the same but every technique must redo
    what depends on the transfer function."""
    opacity = prop.GetScalarOpacity()
    knots = [[0.0] * 4 for _ in range(opacity.GetSize())]
    for k, knot in enumerate(knots):
        opacity.GetNodeValue(k, knot)

    def change(i):
        scale = 0.9 if i % 2 == 0 else 1.0
        for k, knot in enumerate(knots):
            opacity.SetNodeValue(k, [knot[0], knot[1] * scale, knot[2], knot[3]])
    return change, lambda: change(1)


def pixels(path):
    """The RGB bytes of a PNG, row by row, and its width."""
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    scalars = data.GetPointData().GetScalars()
    n = scalars.GetNumberOfComponents()
    raw = bytes(memoryview(scalars))
    rgb = raw if n == 3 else bytes(b for i, b in enumerate(raw) if i % n < 3)
    return rgb, data.GetDimensions()[0]


def masked_psnr(image, reference, mask):
    """PSNR (dB, RGB, 8-bit) over the pixels where `mask` is not black."""
    a, b, m = pixels(image)[0], pixels(reference)[0], pixels(mask)[0]
    total, count = 0, 0
    for i in range(0, len(m), 3):
        if m[i] or m[i + 1] or m[i + 2]:
            count += 3
            total += sum((a[i + k] - b[i + k]) ** 2 for k in range(3))
    if count == 0 or total == 0:
        return float("inf")
    return 10.0 * math.log10(255.0 ** 2 / (total / count))


def vos_star(surface, volume, prop):
    """A VoS^M* mapper with the paper's Riemann sum (h 0.5, the ray casters'
    step) and no level of detail yet."""
    star = avos.vtkVolumeOnSurfaceMapper()
    star.SetIntegrationMethodToLevoy()
    star.SetInputConnection(surface.GetOutputPort())
    star.SetVolumeConnection(volume.GetOutputPort())
    star.SetVolumeProperty(prop)
    star.RemoveAllLevelOfDetailReductions()
    return star


def footprint(scene, surface, path):
    """Saves the isosurface's footprint (white, unlit, on black)."""
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(surface.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().LightingOff()
    actor.GetProperty().SetColor(1, 1, 1)
    scene.renderer.AddActor(actor)
    scene.reset()
    scene.window.Render()
    scene.save(path)
    scene.renderer.RemoveActor(actor)


def figure(path, shots, size):
    """One labelled figure: (label, image) pairs at half size, 4 a row."""
    columns, w, h = 4, size[0] // 2, size[1] // 2
    rows = (len(shots) + columns - 1) // columns
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.SetSize(columns * w, rows * h)
    for k, (label, shot) in enumerate(shots):
        reader = vtkPNGReader()
        reader.SetFileName(shot)
        reader.Update()
        renderer = vtkRenderer()
        c, r = k % columns, rows - 1 - k // columns
        renderer.SetViewport(c / columns, r / rows, (c + 1) / columns, (r + 1) / rows)
        image = vtkImageActor()
        image.GetMapper().SetInputConnection(reader.GetOutputPort())
        renderer.AddActor(image)
        text = vtkTextActor()
        text.SetInput(label)
        text.GetTextProperty().SetFontSize(13)
        text.GetTextProperty().SetColor(1, 1, 0.4)
        text.SetPosition(6, h - 40)
        renderer.AddActor2D(text)
        renderer.ResetCamera()
        renderer.GetActiveCamera().ParallelProjectionOn()
        renderer.GetActiveCamera().SetParallelScale(0.5 * size[1])
        window.AddRenderer(renderer)
    window.Render()
    save_png(window, path)
    window.Finalize()


def quality(image, reference):
    out = subprocess.run([COMPARE, image, reference, "--json"], capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit("avos-compare failed: " + out.stderr)
    m = json.loads(out.stdout)
    psnr = [p for p in m["psnr"] if p != "inf"]
    return (statistics.mean(psnr) if psnr else float("inf")), statistics.mean(m["ssim"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default="Foot,Bonsai,Engine")
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--output", default=os.path.join(ROOT, "out", "bench-vos"))
    args = parser.parse_args()
    names = args.datasets.split(",")
    os.makedirs(os.path.join(args.output, "images"), exist_ok=True)
    step = 360.0 / 36  # degrees per frame
    rows = []
    tables = {"II": [], "III": [], "IV": []}
    t0 = time.perf_counter()

    def record(dataset, size, technique, situation, times, extra=None):
        row = {"dataset": dataset, "size": "%dx%d" % size, "technique": technique,
               "situation": situation, "frames": len(times),
               "median_s": statistics.median(times), "mean_s": statistics.mean(times),
               "fps": 1.0 / statistics.median(times)}
        row.update(extra or {})
        rows.append(row)
        print("%-7s %-8s %-34s %-16s %.3f s/frame" % (dataset, row["size"], technique, situation,
                                                     row["median_s"]), flush=True)

    for name in names:
        volume, surface, tf_path = load(name)
        poly = surface.GetOutput()
        tables["II"].append((name, volume.GetOutput().GetDimensions(), poly.GetNumberOfPoints(),
                             poly.GetNumberOfPolys()))
        memory = {}
        for size in SIZES:
            scene = Scene(size, volume)
            tag = "%s-%dx%d" % (name, size[0], size[1])
            image = lambda technique: os.path.join(args.output, "images", tag + "-" + technique
                                                   + ".png")

            mask = image("footprint")
            footprint(scene, surface, mask)
            shots = []

            # Ray casting: the reference (coupled eps 0.001), then the ray
            # casters the paper's "Ray Casting" stands for: ours and VTK's
            # fixed-point mapper (both skip empty space and stop opaque
            # rays), and ours without empty-space skipping, nearer the
            # paper's (which also went on through opaque parts).
            prop = make_property(tf_path, name)
            for technique, mapper in [("reference", avos.vtkAdaptiveVolumeMapper()),
                                      ("RC adaptive Riemann h 0.5", avos.vtkAdaptiveVolumeMapper()),
                                      ("RC adaptive Riemann h 0.5 no skipping",
                                       avos.vtkAdaptiveVolumeMapper()),
                                      ("RC VTK fixed point h 0.5",
                                       vtkFixedPointVolumeRayCastMapper())]:
                if technique == "reference":
                    mapper.SetIntegrationMethodToAdaptiveCoupled()
                    mapper.SetTolerance(0.001)
                elif isinstance(mapper, avos.vtkAdaptiveVolumeMapper):
                    mapper.SetIntegrationMethodToRiemann()
                    mapper.SetSampleDistance(0.5)
                    mapper.SetEmptySpaceSkipping("no skipping" not in technique)
                else:
                    mapper.SetSampleDistance(1.0)  # world units: half a coarse voxel
                mapper.SetAutoAdjustSampleDistances(0)  # a ray per pixel, whatever the timing
                mapper.SetInputConnection(volume.GetOutputPort())
                actor = vtkVolume()
                actor.SetMapper(mapper)
                actor.SetProperty(prop)
                scene.renderer.AddVolume(actor)
                scene.reset()
                scene.window.Render()
                shot = image(technique.replace(" h 0.5", "").replace(" ", "-"))
                scene.save(shot)
                if technique == "reference":
                    # The floor of any technique whose samples are not the
                    # pixel centres (VoS samples at its vertices): the exact
                    # image against itself moved by half a pixel diagonally.
                    shifted = image("reference-half-pixel")
                    scene.camera.SetWindowCenter(1.0 / size[0], 1.0 / size[1])
                    scene.window.Render()
                    scene.save(shifted)
                    scene.camera.SetWindowCenter(0.0, 0.0)
                    tables.setdefault("floor", []).append(
                        (name, size, masked_psnr(shifted, shot, mask)))
                if "no skipping" not in technique:
                    shots.append((technique, shot))
                if technique != "reference":
                    # The reference is rendered first: its image is already saved.
                    psnr, ssim = quality(shot, image("reference"))
                    record(name, size, technique, "rotation", scene.frames(args.frames, step),
                           {"psnr": psnr, "ssim": ssim,
                            "footprint_psnr": masked_psnr(shot, image("reference"), mask)})
                    change, restore = tf_wiggle(prop)
                    record(name, size, technique, "rotation + TF",
                           scene.frames(args.frames, step, change))
                    restore()
                scene.renderer.RemoveVolume(actor)
            memory["rc"] = volume.GetOutput().GetPointData().GetScalars() \
                .GetActualMemorySize() * 1024
            reference = image("reference")

            # VoS^M: cones cast once (the previsualization), colours assigned
            # per camera; a transfer-function change casts the cones again.
            prop = make_property(tf_path, name)
            vos = avos.vtkVolumeOnSurfaceFilter()
            vos.SetIntegrationMethodToLevoy()  # the paper's model, the ray caster's step
            vos.SetInputConnection(surface.GetOutputPort())
            vos.SetVolumeConnection(volume.GetOutputPort())
            vos.SetVolumeProperty(prop)
            vos.SetCamera(scene.camera)
            mapper = vtkPolyDataMapper()
            mapper.SetInputConnection(vos.GetOutputPort())
            mapper.SetColorModeToDirectScalars()
            # Opaque, as VoS^M* draws: the colours' RGB (see the filter).
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectColorArray("VoSDisplayColors")
            actor = vtkActor()
            actor.SetMapper(mapper)
            scene.reset()
            # The previsualization, timed alone: adding the actor would run it
            # inside the clipping-range reset (the mapper's bounds update it).
            start = time.perf_counter()
            vos.Update()
            previs = time.perf_counter() - start
            scene.renderer.AddActor(actor)
            scene.reset()
            scene.window.Render()
            scene.save(image("VoS-M"))
            psnr, ssim = quality(image("VoS-M"), reference)
            shots.append(("VoS^M", image("VoS-M")))
            record(name, size, "VoS^M", "rotation", scene.frames(args.frames, step),
                   {"previsualization_s": previs, "psnr": psnr, "ssim": ssim,
                    "footprint_psnr": masked_psnr(image("VoS-M"), reference, mask)})
            change, restore = tf_wiggle(prop)
            record(name, size, "VoS^M", "rotation + TF",
                   scene.frames(min(args.frames, 3), step, change))
            restore()
            memory["vos_m"] = (vos.GetVolumeMemory(), vos.GetSurfaceMemory(), vos.GetConesMemory())
            scene.renderer.RemoveActor(actor)

            # VoS^M*: one ray per visible vertex each frame, on the isosurface
            # decimated 0..90 % (one level of detail each), then with the
            # mapper's automatic level over all five (a still window: the
            # screen-density rule decides).
            prop = make_property(tf_path, name)
            # Then the full mesh with visible-only casting: a depth pass
            # before the rays, forced on (the default measures it and keeps
            # it only where it pays); and the full mesh drawn with the rays
            # cast at the 75 and 90 % levels (DrawFullSurface).
            for reduction in (REDUCTIONS if size == SIZES[0] else [0.0]) + \
                    ["visible"] + (["cast 75", "cast 90"] if size == SIZES[0] else []) + ["auto"]:
                auto, visible = reduction == "auto", reduction == "visible"
                cast = float(reduction[5:]) / 100 if str(reduction).startswith("cast ") else None
                star = vos_star(surface, volume, prop)
                levels = REDUCTIONS if auto else [0.0] if visible else [0.0, cast] if cast else \
                    [reduction]
                for r in levels:
                    star.AddLevelOfDetailReduction(r)
                star.SetLevelOfDetail(-1 if auto else 1 if cast else 0)
                star.SetDrawFullSurface(cast is not None)
                if visible:
                    star.SetVisibilityTest(star.DEPTH_VISIBILITY)
                actor = vtkActor()
                actor.SetMapper(star)
                scene.renderer.AddActor(actor)
                scene.reset()
                scene.window.Render()  # decimates (not timed: done once per surface)
                tag_name = "auto" if auto else "visible" if visible else \
                    "cast-%d" % round(100 * cast) if cast else "%d" % round(100 * reduction)
                label = "VoS^M* auto" if auto else "VoS^M* visible only" if visible else \
                    "VoS^M* %d %% cast, full drawn" % round(100 * cast) if cast else \
                    "VoS^M* %d %%" % round(100 * reduction)
                shot = image("VoS-Mstar-" + tag_name)
                scene.save(shot)
                if reduction == 0.0 and size == SIZES[0]:
                    # (Before the rotation below: the reference's camera.)
                    # The same colours drawn unlit (the rays' RGB as they are,
                    # as the unlit ray cast shows them), and what lies in
                    # front of the surface: the opacity VoS leaves out.
                    actor.GetProperty().LightingOff()
                    start = time.perf_counter()
                    scene.window.Render()
                    unlit_s = time.perf_counter() - start
                    unlit = image("VoS-Mstar-unlit")
                    scene.save(unlit)
                    psnr_unlit, ssim_unlit = quality(unlit, reference)
                    shots.append(("VoS^M* unlit", unlit))
                    record(name, size, "VoS^M* 0 % unlit", "first frame", [unlit_s],
                           {"psnr": psnr_unlit, "ssim": ssim_unlit,
                            "footprint_psnr": masked_psnr(unlit, reference, mask)})
                    actor.GetProperty().LightingOn()
                    front = vos_star(surface, volume, prop)
                    front.AddLevelOfDetailReduction(0.0)
                    front.SetLevelOfDetail(0)
                    front.SetVolumeSideToInFrontOfSurface()
                    actor.SetMapper(front)
                    scene.window.Render()
                    colours = front.GetColoredSurface().GetPointData().GetScalars()
                    # Vertices not cast keep alpha 0: the mean is over the cast ones.
                    alphas = [colours.GetComponent(v, 3) / 255.0
                              for v in range(colours.GetNumberOfTuples())]
                    cast_count = max(1, front.GetNumberOfRaysCast())
                    tables.setdefault("front", []).append(
                        (name, sum(alphas) / cast_count, max(alphas), cast_count))
                    actor.SetMapper(star)
                    scene.window.Render()
                if auto or reduction in (0.0, 0.75) or cast == 0.75:
                    shots.append((label, shot))
                psnr, ssim = quality(shot, reference)
                extra = {"psnr": psnr, "ssim": ssim,
                         "footprint_psnr": masked_psnr(shot, reference, mask),
                         "vertices": star.GetColoredSurface().GetNumberOfPoints(),
                         "surface_bytes": star.GetSurfaceMemory(
                             0 if cast else star.GetLastLevelOfDetail())}
                if reduction != 0.0:
                    # Against the full mesh's VoS image: what decimation loses,
                    # which the ray cast's far larger difference hides.
                    extra["psnr_vs_full"] = quality(shot, image("VoS-Mstar-0"))[0]
                if auto:
                    extra["level"] = REDUCTIONS[star.GetLastLevelOfDetail()]
                    extra["pixels_per_vertex"] = star.GetScreenPixelsPerVertex()
                if visible:
                    # The first view's front-facing vertices in the frustum
                    # that the depth pass left without a ray.
                    extra["hidden_share"] = star.GetNumberOfHiddenVertices() / max(
                        1, star.GetNumberOfVisibleVertices())
                record(name, size, label, "rotation", scene.frames(args.frames, step), extra)
                if auto or visible or cast:
                    scene.renderer.RemoveActor(actor)
                    continue
                if reduction == 0.0:
                    # The floor of a frame: the same view again, nothing
                    # recast, only the draw (a ray-cast frame over this is
                    # the most VoS^M* on the full mesh can gain).
                    record(name, size, label, "draw only", scene.frames(args.frames, 0.0))
                    if star.GetNumberOfRaysCast() != 0:
                        raise SystemExit("the draw-only frames cast rays")
                    change, restore = tf_wiggle(prop)
                    record(name, size, label, "rotation + TF",
                           scene.frames(args.frames, step, change))
                    restore()
                    memory["vos_m_star"] = (star.GetVolumeMemory(), star.GetSurfaceMemory(0))
                if size == SIZES[0]:
                    tables["IV"].append((name, reduction, star.GetSurfaceMemory(0),
                                         extra["vertices"]))
                scene.renderer.RemoveActor(actor)

            scene.window.Finalize()  # one X connection per window: give it back
            labelled = []
            for technique, shot in shots:
                # The unlit drawing is timed on its first frame only.
                key = {"VoS^M* unlit": ("VoS^M* 0 % unlit", "first frame")}.get(
                    technique, (technique, "rotation"))
                row = next((r for r in rows if r["dataset"] == name and r["size"] == "%dx%d" % size
                            and (r["technique"], r["situation"]) == key), None)
                labelled.append((technique + ("\n%.3f s, footprint PSNR %.1f dB"
                                              % (row["median_s"], row["footprint_psnr"])
                                              if row else "\n(the reference)"), shot))
            figure(os.path.join(args.output, tag + "-techniques.png"), labelled, size)

        tables["III"].append((name, memory))

    minutes = (time.perf_counter() - t0) / 60
    with open(os.path.join(args.output, "results.csv"), "w", newline="") as f:
        fields = ["dataset", "size", "technique", "situation", "frames", "median_s", "mean_s", "fps",
                  "previsualization_s", "psnr", "ssim", "vertices", "surface_bytes",
                  "footprint_psnr", "level", "pixels_per_vertex", "psnr_vs_full", "hidden_share"]
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        for row in rows:
            writer.writerow(row)
    write_report(args, names, rows, tables, minutes)
    print("bench-vos: %.1f minutes; results in %s" % (minutes, args.output))


def median_of(rows, dataset, size, technique, situation):
    """The median seconds per frame of a row, or nan when there is none."""
    return next((r["median_s"] for r in rows if r["dataset"] == dataset and r["size"] == size and
                 r["technique"] == technique and r["situation"] == situation), float("nan"))


def write_report(args, names, rows, tables, minutes):
    mb = lambda b: "%.1f" % (b / 1e6)
    out = ["# Volume on Surface: the paper's evaluation on this machine", "",
           "Made by `scripts/bench-vos.py --datasets %s --frames %d` in %.1f minutes (2 cores, "
           "Mesa llvmpipe). Every volume at every 2nd voxel; VTK opacity semantics; camera from "
           "the front, turning %d frames of 10 degrees about the view up axis; medians; no "
           "multisampling." % (",".join(names), args.frames, minutes, args.frames), "",
           "Scenes (isovalue of the isosurface where the transfer function starts to show it):",
           ""]
    for name in names:
        volume_file, tf_file, iso, change = DATASETS[name]
        out.append("- %s: `%s`, `%s`%s, isovalue %g." % (name, volume_file, tf_file,
                                                     " (" + change + ")" if change else "", iso))
    out += ["", "What lies in front of each surface (VoS^M* integrating the volume between "
            "each cast vertex and the eye, 800x600, first frame): the opacity VoS leaves out.",
            "", "| dataset | mean opacity in front | largest | vertices |", "|---|---:|---:|---:|"]
    for name, mean, largest, count in tables.get("front", []):
        out.append("| %s | %.4f | %.4f | %d |" % (name, mean, largest, count))
    out += ["", "The sampling floor: the footprint PSNR of the reference against itself with "
            "the camera moved by half a pixel diagonally (`vtkCamera::SetWindowCenter`). VoS "
            "samples at its vertices, not at the pixel centres, and interpolates between them: "
            "where the image has detail at the pixel's scale, this is the PSNR that samples half "
            "a pixel away from the centres reach with no other error.", "",
            "| dataset | size | footprint PSNR, half a pixel (dB) |", "|---|---|---:|"]
    for name, size, psnr in tables.get("floor", []):
        out.append("| %s | %dx%d | %.1f |" % (name, size[0], size[1], psnr))
    out += ["", "The paper's ray caster covered every pixel and went on through opaque parts; "
           "ours and VTK's fixed-point mapper skip empty blocks and stop opaque rays. The row "
           "`no skipping` is ours without empty-space skipping, nearer the paper's baseline "
           "(early termination stays on).", "",
           "## Table II: isosurfaces", "", "| dataset | volume | vertices | triangles |",
           "|---|---|---:|---:|"]
    for name, dims, vertices, polygons in tables["II"]:
        out.append("| %s | %dx%dx%d | %d | %d |" % ((name,) + tuple(dims) + (vertices, polygons)))
    out.append("| Foot (paper) | 102x247x200 | %d | %d |"
               % (PAPER_FOOT["vertices"], PAPER_FOOT["polygons"]))
    out += ["", "## Table III: memory (MB)", "",
            "| dataset | VoS^M volume | isosurface | cones | total | VoS^M* volume | isosurface "
            "| total | ray casting volume |", "|---|" + "---:|" * 8]
    for name, m in tables["III"]:
        vm, star = m["vos_m"], m["vos_m_star"]
        out.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |"
                   % (name, mb(vm[0]), mb(vm[1]), mb(vm[2]), mb(sum(vm)), mb(star[0]),
                      mb(star[1]), mb(sum(star)), mb(m["rc"])))
    p = PAPER_FOOT
    out.append("| Foot (paper) | %s | %s | %s | %s | %s | %s | %s | %s |"
               % (p["vos_m"] + p["vos_m_star"] + (p["rc"],)))
    for situation, figure in (("rotation", "Figure 6"), ("rotation + TF", "Figure 7")):
        out += ["", "## %s: seconds per frame, %s" % (figure, situation), "",
                "| dataset | size | VoS^M | VoS^M* | VoS^M* auto | RC adaptive Riemann h 0.5 | "
                "same, no skipping | RC VTK fixed point h 0.5 | RC adaptive / VoS^M* | "
                "RC adaptive / auto | no skipping / auto | RC fixed point / auto |",
                "|---|---|" + "---:|" * 10]
        for name in names:
            for size in SIZES:
                s = "%dx%d" % size
                get = lambda t: median_of(rows, name, s, t, situation)
                vm, star, auto = get("VoS^M"), get("VoS^M* 0 %"), get("VoS^M* auto")
                ada, fixed = get("RC adaptive Riemann h 0.5"), get("RC VTK fixed point h 0.5")
                full = get("RC adaptive Riemann h 0.5 no skipping")
                out.append("| %s | %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f | %.2f | "
                           "%.2f | %.2f |" % (name, s, vm, star, auto, ada, full, fixed,
                                              ada / star, ada / auto, full / auto, fixed / auto))
    out += ["", "## The floor of a VoS^M* frame: the draw", "",
            "The full mesh's VoS^M* frame with the camera unchanged (nothing recast: the draw "
            "alone), against the same frame turning and the ray casters: our ray caster over the "
            "draw is the most VoS^M* on the full mesh can gain on this OpenGL, whatever its rays "
            "cost.", "",
            "| dataset | size | VoS^M* turning | draw only | RC adaptive Riemann h 0.5 | "
            "RC adaptive / draw only | RC VTK fixed point h 0.5 | RC fixed point / draw only |",
            "|---|---|" + "---:|" * 6]
    for name in names:
        for size in SIZES:
            s = "%dx%d" % size
            get = lambda t, situation: median_of(rows, name, s, t, situation)
            turning, draw = get("VoS^M* 0 %", "rotation"), get("VoS^M* 0 %", "draw only")
            ada = get("RC adaptive Riemann h 0.5", "rotation")
            fixed = get("RC VTK fixed point h 0.5", "rotation")
            out.append("| %s | %s | %.3f | %.3f | %.3f | %.2f | %.3f | %.2f |"
                       % (name, s, turning, draw, ada, ada / draw, fixed, fixed / draw))
    out += ["", "## Visible-only casting: a depth pass before the rays", "",
            "VoS^M* on the full mesh with `VisibilityTest` DEPTH forced (the default, AUTOMATIC, "
            "measures the pass and keeps it only where the rays it saves outweigh it): the share "
            "of front-facing vertices in the frustum it leaves without a ray (first view), the "
            "time per turning frame beside the same mesh without the pass, and what the image "
            "loses against it.", "",
            "| dataset | size | hidden | s / frame, visible only | s / frame, all rays | "
            "PSNR against all rays (dB) |", "|---|---|---:|---:|---:|---:|"]
    for r in rows:
        if r["technique"] == "VoS^M* visible only":
            full = median_of(rows, r["dataset"], r["size"], "VoS^M* 0 %", "rotation")
            out.append("| %s | %s | %.1f %% | %.3f | %.3f | %.2f |"
                       % (r["dataset"], r["size"], 100.0 * r["hidden_share"], r["median_s"], full,
                          r["psnr_vs_full"]))
    out += ["", "VoS^M's first frame (the previsualization, every cone's rays cast): "
            + ", ".join("%s %s %.2f s" % (r["dataset"], r["size"], r["previsualization_s"])
                        for r in rows if "previsualization_s" in r) + "."]
    out += ["", "## Figure 10 and Table IV: VoS^M* on decimated isosurfaces, 800x600", "",
            "| dataset | decimation | vertices | isosurface MB | s / frame | PSNR (dB) | SSIM | "
            "PSNR against the full mesh's VoS^M* (dB) |",
            "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for name in names:
        for r in rows:
            if r["dataset"] == name and r["size"] == "800x600" and \
                    r["technique"].startswith("VoS^M* ") and r["situation"] == "rotation" and \
                    r["technique"] != "VoS^M* visible only":
                out.append("| %s | %s | %d | %s | %.3f | %.2f | %.4f | %s |"
                           % (name, r["technique"][7:], r["vertices"], mb(r["surface_bytes"]),
                              r["median_s"], r["psnr"], r["ssim"],
                              "%.2f" % r["psnr_vs_full"] if "psnr_vs_full" in r else ""))
    out.append("| Foot (paper), MB | 0/25/50/75/90 %% | | %s | | | | |"
               % " / ".join(str(v) for v in PAPER_FOOT["decimated"]))
    out += ["", "VoS^M* auto picked (covered pixels per cast vertex of the full surface in the "
            "first view, level): " + ", ".join(
                "%s %s %.2f px, %d %%" % (r["dataset"], r["size"], r["pixels_per_vertex"],
                                          round(100 * r["level"]))
                for r in rows if "level" in r) + "."]
    out += ["", "## Quality against the ray-cast reference (coupled Simpson, eps 0.001)", "",
            "Mean over R, G, B of the first frame (8-bit, black background); footprint: PSNR over "
            "the pixels the isosurface covers only, where VoS has something to show.", "",
            "| dataset | size | technique | PSNR (dB) | footprint PSNR (dB) | SSIM |",
            "|---|---|---|---:|---:|---:|"]
    for r in rows:
        if "psnr" in r and r["situation"] == "rotation" and \
                (r["technique"] in ("VoS^M", "VoS^M* 0 %", "VoS^M* auto") or
                 r["technique"].startswith("RC")):
            out.append("| %s | %s | %s | %.2f | %.2f | %.4f |"
                       % (r["dataset"], r["size"], r["technique"], r["psnr"],
                          r["footprint_psnr"], r["ssim"]))
    out += ["", "Figures (first frame, 800x600; time per frame and footprint PSNR in the "
            "labels): " + ", ".join("[%s](%s-800x600-techniques.png)" % (n, n) for n in names)
            + "."]
    with open(os.path.join(args.output, "report.md"), "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
