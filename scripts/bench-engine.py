#!/usr/bin/env python3
"""The speed benchmark of vtkAdaptiveVolumeMapper against VTK's fixed-point
mapper on the same frames (one avos-render process per run, side by side in
one session): BluntFin, Bonsai, Engine and Foot with the paper's transfer
functions in VTK's opacity semantics (the fixed-point mapper's), default and
oblique views (azimuth 37, elevation 23, zoom 1.3), 800x600, 2 threads; one
thread on the default view; Bonsai also at 400x300 and 1600x1200; analytic
volumes of 64^3 to 512^3 for the growth with volume size.

For each run: median and min of 5 frames, the ratio to the fixed-point
mapper's median on the same frame, samples per ray, ns per sample per core,
and the % of pixels whose worst channel is more than 1e-3 off the reference
(the piecewise method at eps 1e-5, whose error is proven below 1e-5).

Writes out/bench-engine/results.json, report.md (the tables and the log-log
slopes) and time-vs-error.png (VTK's charts), and prints the report.
  PYTHONPATH=build/python xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
    /usr/bin/python3 scripts/bench-engine.py [--quick]
"""

import argparse
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RENDER = os.path.join(os.environ.get("AVOS_BUILD_DIR", os.path.join(ROOT, "build")), "bin",
                      "avos-render")
DATA = os.path.join(ROOT, "..", "shared", "data")
OUT = os.path.join(ROOT, "out", "bench-engine")

DATASETS = {
    "BluntFin": ("volumes/BluntFin.1.256x128x64.raw", "tf/BluntFin.1.256x128x64.linear.tf1d"),
    "Bonsai": ("volumes/bonsai_zfp.vti", "tf/Bonsai.1.256x256x256.linear.tf1d"),
    "Engine": ("volumes/engine_zfp.vti", "tf/Engine.1.256x256x128.linear.tf1d"),
    "Foot": ("volumes/foot_zfp.vti", "tf/Foot.tf1d"),
}
VIEWS = {"default": ["--azimuth", "0", "--elevation", "0", "--zoom", "1"],
         "oblique": ["--azimuth", "37", "--elevation", "23", "--zoom", "1.3"]}
METHODS = [
    ("vtk-fixed-point h 0.5", ["--method", "vtk-fixed-point", "--step", "0.5"]),
    ("riemann h 0.5", ["--method", "riemann", "--step", "0.5"]),
    ("piecewise eps 0.01", ["--method", "piecewise", "--tolerance", "0.01"]),
    ("piecewise eps 0.001", ["--method", "piecewise", "--tolerance", "0.001"]),
    ("coupled eps 0.01", ["--method", "coupled", "--tolerance", "0.01"]),
    ("coupled eps 0.001", ["--method", "coupled", "--tolerance", "0.001"]),
    ("decoupled eps 0.01", ["--method", "decoupled", "--tolerance", "0.01"]),
    ("decoupled eps 0.001", ["--method", "decoupled", "--tolerance", "0.001"]),
]
REFERENCE = ["--method", "piecewise", "--tolerance", "1e-5"]


def render(scene, options, name, frames, compare=None, output=None):
    report = os.path.join(OUT, name + ".json")
    command = [RENDER] + scene + options + ["--frames", str(frames), "--report", report]
    if compare:
        command += ["--compare", compare]
    if output:
        command += ["--output", output]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("failed: %s\n%s%s" % (" ".join(command), result.stdout, result.stderr))
    return json.load(open(report))


def run_config(rows, dataset, scene, view, size, threads, frames, methods=METHODS):
    key = "%s-%s-%s-t%d" % (dataset, view, size, threads)
    reference = os.path.join(OUT, "%s-%s-%s-reference.exr" % (dataset, view, size))
    if not os.path.exists(reference):
        render(scene, REFERENCE + ["--threads", "2"], key + "-reference", 1, output=reference)
    baseline = None
    for label, options in methods:
        r = render(scene, options + ["--threads", str(threads)], key + "-" + label.replace(" ", "-"),
                   frames, compare=reference)
        c = r["compare"]
        row = {"dataset": dataset, "view": view, "size": size, "threads": threads,
               "method": label, "median": r["median_seconds"], "min": r["min_seconds"],
               "samples_per_ray": r.get("mean_samples_per_ray"), "rays": r.get("rays_cast"),
               "over_1e-3": max(c["percent_above_0.001"]), "max_error": max(c["max_error_rgba"])}
        if label.startswith("vtk-fixed-point"):
            baseline = row["median"]
        row["ratio"] = row["median"] / baseline if baseline else None
        if row["rays"] and row["samples_per_ray"]:
            row["ns_per_sample_per_core"] = (1e9 * row["median"] * threads /
                                             (row["rays"] * row["samples_per_ray"]))
        rows.append(row)
        print("%-8s %-7s %-9s t%d %-22s %7.3f s  ratio %s  %s samples/ray  >1e-3 %.4f %%" % (
            dataset, view, size, threads, label, row["median"],
            "%.2f" % row["ratio"] if row["ratio"] else "-",
            "%.1f" % row["samples_per_ray"] if row["samples_per_ray"] else "-", row["over_1e-3"]),
            flush=True)


def analytic_volumes(sizes):
    """Marschner-Lobb volumes (8-bit) of the given edge sizes, written once."""
    import avos
    from vtkmodules.vtkImagingCore import vtkImageShiftScale
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter
    paths = {}
    for n in sizes:
        path = os.path.join(OUT, "marschner-lobb-%d.vti" % n)
        if not os.path.exists(path):
            source = avos.vtkAnalyticVolumeSource()
            source.SetFunctionToMarschnerLobb()
            source.SetDimensions(n, n, n)
            cast = vtkImageShiftScale()
            cast.SetInputConnection(source.GetOutputPort())
            cast.SetScale(255.0)
            cast.SetOutputScalarTypeToUnsignedChar()
            writer = vtkXMLImageDataWriter()
            writer.SetInputConnection(cast.GetOutputPort())
            writer.SetFileName(path)
            writer.Write()
        paths[n] = path
    return paths


def slope(points):
    """Least-squares slope of log(y) against log(x)."""
    xs = [math.log(x) for x, _ in points]
    ys = [math.log(y) for _, y in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def plot(rows, path):
    """Time against error (Bonsai, default view, 800x600, 2 threads)."""
    from vtkmodules.vtkChartsCore import vtkAxis, vtkChart, vtkChartXY
    from vtkmodules.vtkCommonCore import vtkFloatArray
    from vtkmodules.vtkCommonDataModel import vtkTable
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
    from vtkmodules.vtkViewsContext2D import vtkContextView
    import vtkmodules.vtkRenderingContextOpenGL2  # noqa: F401
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    view = vtkContextView()
    view.GetRenderWindow().SetSize(900, 600)
    view.GetRenderWindow().SetOffScreenRendering(1)
    chart = vtkChartXY()
    chart.SetShowLegend(True)
    chart.SetTitle("Bonsai 800x600, default view: time against error (max |error|, worst channel)")
    view.GetScene().AddItem(chart)
    colors = {"vtk": (200, 40, 40), "riemann": (40, 40, 200), "piecewise": (30, 150, 30),
              "coupled": (150, 100, 20), "decoupled": (130, 40, 160)}
    for family, color in colors.items():
        selected = [r for r in rows if r["dataset"] == "Bonsai" and r["view"] == "default" and
                    r["size"] == "800x600" and r["threads"] == 2 and r["method"].startswith(family)]
        if not selected:
            continue
        table = vtkTable()
        for name in ("seconds", family):
            column = vtkFloatArray()
            column.SetName(name)
            table.AddColumn(column)
        table.SetNumberOfRows(len(selected))
        for i, r in enumerate(selected):
            table.SetValue(i, 0, r["median"])
            table.SetValue(i, 1, max(r["max_error"], 1e-7))
        points = chart.AddPlot(vtkChart.POINTS)
        points.SetInputData(table, 0, 1)
        points.SetColor(*color, 255)
        points.SetWidth(8.0)
    chart.GetAxis(vtkAxis.LEFT).SetLogScale(True)
    chart.GetAxis(vtkAxis.LEFT).SetTitle("max error")
    chart.GetAxis(vtkAxis.BOTTOM).SetTitle("seconds per frame (median of 5)")
    view.GetRenderWindow().Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(view.GetRenderWindow())
    writer = vtkPNGWriter()
    writer.SetInputConnection(grab.GetOutputPort())
    writer.SetFileName(path)
    writer.Write()


def report(rows, growth, path):
    lines = ["# Speed against VTK's fixed-point mapper", "",
             "One run of `scripts/bench-engine.py` (2 cores, llvmpipe). Ratio: median time "
             "over the fixed-point mapper's median on the same frame. `> 1e-3`: % of pixels whose "
             "worst channel is more than 1e-3 off the reference (piecewise, eps 1e-5).", "",
             "| dataset | view | size | threads | method | median s | min s | ratio | samples/ray "
             "| ns/sample/core | > 1e-3 % | max error |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| %s | %s | %s | %d | %s | %.3f | %.3f | %s | %s | %s | %.4f | %.1e |" % (
            r["dataset"], r["view"], r["size"], r["threads"], r["method"], r["median"], r["min"],
            "%.2f" % r["ratio"] if r["ratio"] else "", "%.1f" % r["samples_per_ray"]
            if r["samples_per_ray"] else "", "%.1f" % r["ns_per_sample_per_core"]
            if r.get("ns_per_sample_per_core") else "", r["over_1e-3"], r["max_error"]))
    lines += ["", "## Growth (log-log slopes of the median time)", ""]
    for line in growth:
        lines.append("- " + line)
    text = "\n".join(lines) + "\n"
    open(path, "w").write(text)
    print(text)


def main():
    global RENDER, DATA, OUT
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help="Bonsai only, default view, 400x300, 2 frames (a smoke run)")
    parser.add_argument("--render", default=RENDER, help="avos-render (default: build/bin)")
    parser.add_argument("--data", default=DATA, help="the shared data folder")
    parser.add_argument("--output", default=OUT, help="results folder (default out/bench-engine)")
    args = parser.parse_args()
    RENDER, DATA, OUT = args.render, args.data, args.output
    os.makedirs(OUT, exist_ok=True)
    rows = []
    frames = 2 if args.quick else 5
    scenes = {}
    for name, (volume, tf) in DATASETS.items():
        scenes[name] = [os.path.join(DATA, volume), "--tf", os.path.join(DATA, tf),
                        "--opacity", "vtk"]
    if args.quick:
        run_config(rows, "Bonsai", scenes["Bonsai"] + ["--size", "400x300"] + VIEWS["default"],
                   "default", "400x300", 2, frames)
        json.dump(rows, open(os.path.join(OUT, "results.json"), "w"), indent=1)
        report(rows, [], os.path.join(OUT, "report.md"))
        return
    for name in DATASETS:
        for view, options in VIEWS.items():
            run_config(rows, name, scenes[name] + ["--size", "800x600"] + options, view,
                       "800x600", 2, frames)
    for name in DATASETS:
        run_config(rows, name, scenes[name] + ["--size", "800x600"] + VIEWS["default"],
                   "default", "800x600", 1, frames)
    for size in ("400x300", "1600x1200"):
        run_config(rows, "Bonsai", scenes["Bonsai"] + ["--size", size] + VIEWS["default"],
                   "default", size, 2, frames)
    growth = []
    # Pixels: Bonsai at three sizes.
    for method in ("vtk-fixed-point h 0.5", "riemann h 0.5", "piecewise eps 0.001"):
        pts = [(int(r["size"].split("x")[0]) * int(r["size"].split("x")[1]), r["median"])
               for r in rows if r["dataset"] == "Bonsai" and r["view"] == "default" and
               r["threads"] == 2 and r["method"] == method]
        growth.append("%s against pixels (400x300 .. 1600x1200): %.2f" % (method, slope(pts)))
    # 1/eps: the adaptive methods at eps 0.01 and 0.001, every dataset and view.
    for family in ("piecewise", "coupled", "decoupled"):
        values = []
        for name in DATASETS:
            for view in VIEWS:
                pts = [(1.0 / float(r["method"].split()[-1]), r["median"]) for r in rows
                       if r["dataset"] == name and r["view"] == view and r["size"] == "800x600" and
                       r["threads"] == 2 and r["method"].startswith(family)]
                values.append(slope(pts))
        growth.append("%s against 1/eps (0.01 -> 0.001), per dataset and view: %s" % (
            family, ", ".join("%.2f" % v for v in values)))
    # Threads: 1 -> 2 on the default view.
    for name in DATASETS:
        for method, _ in METHODS:
            one = [r["median"] for r in rows if r["dataset"] == name and r["threads"] == 1 and
                   r["method"] == method]
            two = [r["median"] for r in rows if r["dataset"] == name and r["threads"] == 2 and
                   r["view"] == "default" and r["size"] == "800x600" and r["method"] == method]
            if one and two:
                growth.append("thread scaling 1 -> 2, %s, %s: %.2fx" % (name, method,
                                                                        one[0] / two[0]))
    # Volume size: Marschner-Lobb 64^3 .. 512^3 (its own transfer function from the data range).
    volumes = analytic_volumes((64, 128, 256, 512))
    sized = {}
    for n, path in volumes.items():
        scene = [path, "--size", "800x600", "--opacity", "vtk"] + VIEWS["oblique"]
        run_config(rows, "ML%d" % n, scene, "oblique", "800x600", 2, 3,
                   [METHODS[0], METHODS[1], METHODS[3]])
        for r in rows[-3:]:
            sized.setdefault(r["method"], []).append((n, r["median"]))
    for method, pts in sized.items():
        growth.append("%s against volume edge (64 .. 512): %.2f" % (method, slope(pts)))
    json.dump(rows, open(os.path.join(OUT, "results.json"), "w"), indent=1)
    plot(rows, os.path.join(OUT, "time-vs-error.png"))
    report(rows, growth, os.path.join(OUT, "report.md"))


if __name__ == "__main__":
    main()
