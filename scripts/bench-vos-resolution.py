#!/usr/bin/env python3
"""Volume on Surface's quality against the volume's resolution (a benchmark,
not a test): each dataset's scene of scripts/bench-vos.py (its transfer
function, the isosurface where it starts to show, closed at the grid's
boundary, the same camera from the front), at every 2nd voxel (the paper's
isosurface sizes, bench-vos.py's scenes) and at full resolution, 800x600.

Per scene: the isosurface's vertices, VoS^M* on the full mesh drawn unlit
(its rays' colours as they are; the paper's Riemann sum at h 0.5 and the
piecewise method at eps 0.001) against the reference (vtkAdaptiveVolumeMapper,
coupled eps 0.001): PSNR and SSIM (avos-compare) and the PSNR over the
surface's footprint; beside them the reference against itself moved by half
a pixel (the floor of sampling off the pixel centres once per pixel), and
the seconds of one VoS^M* frame and of the reference.

    PYTHONPATH=build/python xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" /usr/bin/python3 \\
        scripts/bench-vos-resolution.py [--datasets Foot,Bonsai,Engine] [--output out/bench-vos-resolution]
"""

import argparse
import importlib.util
import os
import time

from vtkmodules.vtkRenderingCore import vtkActor, vtkVolume

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_spec = importlib.util.spec_from_file_location("bench_vos", os.path.join(ROOT, "scripts",
                                                                      "bench-vos.py"))
vos = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(vos)


def measure(name, rate, output):
    """The row of one dataset at one sample rate."""
    volume, surface, tf_path = vos.load(name, rate)
    size = vos.SIZES[0]
    scene = vos.Scene(size, volume)
    tag = "%s-%d" % (name, rate)
    mask = os.path.join(output, "footprint-%s.png" % tag)
    vos.footprint(scene, surface, mask)
    reference = vos.avos.vtkAdaptiveVolumeMapper()
    reference.SetIntegrationMethodToAdaptiveCoupled()
    reference.SetTolerance(0.001)
    reference.SetAutoAdjustSampleDistances(0)
    reference.SetInputConnection(volume.GetOutputPort())
    ray_cast = vtkVolume()
    ray_cast.SetMapper(reference)
    ray_cast.SetProperty(vos.make_property(tf_path, name, rate))
    scene.renderer.AddVolume(ray_cast)
    scene.reset()
    start = time.perf_counter()
    scene.window.Render()
    reference_s = time.perf_counter() - start
    reference_png = os.path.join(output, "reference-%s.png" % tag)
    scene.save(reference_png)
    shifted = os.path.join(output, "reference-half-pixel-%s.png" % tag)
    scene.camera.SetWindowCenter(1.0 / size[0], 1.0 / size[1])
    scene.window.Render()
    scene.save(shifted)
    scene.camera.SetWindowCenter(0.0, 0.0)
    scene.renderer.RemoveVolume(ray_cast)
    row = {"dataset": name, "rate": rate, "vertices": surface.GetOutput().GetNumberOfPoints(),
           "reference_s": reference_s,
           "floor": vos.masked_psnr(shifted, reference_png, mask)}
    for method in ("Levoy", "Piecewise"):
        star = vos.vos_star(surface, volume, vos.make_property(tf_path, name, rate))
        getattr(star, "SetIntegrationMethodTo" + method)()
        star.AddLevelOfDetailReduction(0.0)
        star.SetLevelOfDetail(0)
        actor = vtkActor()
        actor.SetMapper(star)
        actor.GetProperty().LightingOff()
        scene.renderer.AddActor(actor)
        scene.reset()
        scene.window.Render()  # the first frame casts every vertex once
        scene.camera.Azimuth(1.0)
        scene.reset()
        start = time.perf_counter()
        scene.window.Render()  # the same view again: the rays of a camera change
        seconds = time.perf_counter() - start
        png = os.path.join(output, "VoS-Mstar-unlit-%s-%s.png" % (method, tag))
        scene.save(png)
        psnr, ssim = vos.quality(png, reference_png)
        row[method] = (psnr, ssim, vos.masked_psnr(png, reference_png, mask), seconds)
        scene.renderer.RemoveActor(actor)
    scene.window.Finalize()
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default="Foot,Bonsai,Engine")
    parser.add_argument("--output", default=os.path.join(ROOT, "out", "bench-vos-resolution"))
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    lines = ["| dataset | voxels | isosurface vertices | VoS^M* unlit, Riemann h 0.5: PSNR, SSIM, "
             "footprint PSNR | VoS^M* unlit, piecewise eps 1e-3 | half-pixel floor (footprint) "
             "| seconds: VoS^M* Riemann frame / reference |",
             "|---|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    for name in args.datasets.split(","):
        for rate in (2, 1):
            r = measure(name, rate, args.output)
            cells = ["%s" % r["dataset"], "every %s" % ("voxel" if rate == 1 else "2nd voxel"),
                     "{:,}".format(r["vertices"])]
            for method in ("Levoy", "Piecewise"):
                psnr, ssim, foot, _ = r[method]
                cells.append("%.1f dB, %.3f, %.1f dB" % (psnr, ssim, foot))
            cells.append("%.1f dB" % r["floor"])
            cells.append("%.3f / %.3f" % (r["Levoy"][3], r["reference_s"]))
            line = "| " + " | ".join(cells) + " |"
            lines.append(line)
            print(line, flush=True)
    with open(os.path.join(args.output, "report.md"), "w") as report:
        report.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
