"""avos-render end to end: every method renders a small shared volume and
writes the image and the report it was asked for; an EXR keeps float RGBA;
bad command lines and unreadable inputs fail with a message, not a crash.

    python3 TestAvosRender.py AVOS_RENDER SHARED_DATA_DIR SCRATCH_DIR AVOS_COMPARE
"""

import json
import math
import struct
import os
import pty
import signal
import subprocess
import sys
import time

EXE, DATA, SCRATCH, COMPARE = sys.argv[1:5]
VOLUME = os.path.join(DATA, "volumes", "Neghip.1.64x64x64.raw")
TF = os.path.join(DATA, "tf", "BluntFin.1.256x128x64.linear.tf1d")
failures = []


def run(*args):
    result = subprocess.run([EXE, *args], capture_output=True, text=True, timeout=600)
    return result.returncode, result.stdout + result.stderr


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL", what)


if not os.path.exists(VOLUME):
    print("shared data absent: skipping")
    sys.exit(125)

os.makedirs(SCRATCH, exist_ok=True)
for method in ["riemann", "coupled", "decoupled", "piecewise", "reference", "vtk-fixed-point",
               "vtk-gpu", "gpu-riemann", "gpu-coupled", "gpu-decoupled"]:
    png = os.path.join(SCRATCH, method + ".png")
    report = os.path.join(SCRATCH, method + ".json")
    for path in (png, report):
        if os.path.exists(path):
            os.remove(path)
    code, out = run(VOLUME, "--tf", TF, "--method", method, "--size", "64x48", "--frames", "2",
                    "--azimuth", "30", "--elevation", "10", "--zoom", "1.2",
                    "--output", png, "--report", report)
    check(code == 0, method + " exits 0: " + out)
    check(os.path.getsize(png) > 100 if os.path.exists(png) else False, method + " writes a PNG")
    if os.path.exists(report):
        r = json.load(open(report))
        check(r["method"] == method and r["width"] == 64 and r["height"] == 48 and
              r["frames"] == 2 and 0 < r["min_seconds"] <= r["median_seconds"],
              method + " report fields")
        if not method.startswith(("vtk-", "gpu-")):
            check(r["rays_cast"] > 0 and r["mean_samples_per_ray"] > 1, method + " statistics")
        if method == "piecewise":
            check(r["mean_pieces_per_ray"] > 1 and r["mean_cells_per_ray"] > 1,
                  "piecewise reports cells and pieces")
    else:
        check(False, method + " writes a report")

# EXR: float RGBA, read back through OpenImageIO's command-line tool.
exr = os.path.join(SCRATCH, "coupled.exr")
code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--output", exr)
check(code == 0 and os.path.exists(exr), "EXR written: " + out)
info = subprocess.run(["oiiotool", "--info", "-v", exr], capture_output=True, text=True).stdout
check("4 channel" in info and "float" in info, "EXR is float RGBA: " + info)

# Other input formats: a MetaImage written by VTK, a detached NRRD header.
try:
    from vtkmodules.vtkIOImage import vtkMetaImageWriter
except ImportError:
    vtkMetaImageWriter = None
nhdr = os.path.join(SCRATCH, "neghip.nhdr")
with open(nhdr, "w") as f:
    f.write("NRRD0004\ntype: unsigned char\ndimension: 3\nsizes: 64 64 64\n"
            "spacings: 1 1 1\nencoding: raw\ndata file: %s\n" % os.path.abspath(VOLUME))
inputs = [nhdr]
if vtkMetaImageWriter is not None:
    from vtkmodules.vtkIOImage import vtkImageReader2
    raw = vtkImageReader2()
    raw.SetFileName(VOLUME)
    raw.SetDataExtent(0, 63, 0, 63, 0, 63)
    raw.SetDataScalarTypeToUnsignedChar()
    raw.SetFileDimensionality(3)
    mhd = os.path.join(SCRATCH, "neghip.mhd")
    writer = vtkMetaImageWriter()
    writer.SetInputConnection(raw.GetOutputPort())
    writer.SetFileName(mhd)
    writer.SetCompression(False)
    writer.Write()
    inputs.append(mhd)
# A DICOM folder: Neghip as 64 CT slices of 16-bit pixels, written with
# pydicom; it must render exactly as the NRRD of the same voxels.
from pydicom.dataset import Dataset, FileMetaDataset
from pydicom.uid import CTImageStorage, ExplicitVRLittleEndian, generate_uid
dicom = os.path.join(SCRATCH, "neghip-dicom")
os.makedirs(dicom, exist_ok=True)
voxels = open(VOLUME, "rb").read()
study, series = generate_uid(), generate_uid()
for k in range(64):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = CTImageStorage
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = Dataset()
    ds.file_meta = meta
    ds.is_little_endian, ds.is_implicit_VR = True, False
    ds.SOPClassUID, ds.SOPInstanceUID = CTImageStorage, meta.MediaStorageSOPInstanceUID
    ds.StudyInstanceUID, ds.SeriesInstanceUID = study, series
    ds.Modality, ds.PatientName, ds.PatientID = "CT", "AVoS^Test", "0"
    ds.InstanceNumber = k + 1
    ds.ImagePositionPatient = [0, 0, k]
    ds.ImageOrientationPatient = [1, 0, 0, 0, 1, 0]
    ds.PixelSpacing, ds.SliceThickness = [1, 1], 1
    ds.Rows = ds.Columns = 64
    ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 0
    ds.RescaleIntercept, ds.RescaleSlope = 0, 1
    # vtkDICOMImageReader puts the last row and the last slice first: store
    # both reversed so that it reads back exactly the raw volume.
    z = 63 - k
    rows = [voxels[4096 * z + 64 * (63 - j):4096 * z + 64 * (64 - j)] for j in range(64)]
    ds.PixelData = struct.pack("<4096H", *b"".join(rows))
    ds.save_as(os.path.join(dicom, "slice%03d.dcm" % k), write_like_original=False)
inputs.append(dicom)

reference_output = None
for path in inputs:
    report = path + ".json"
    code, out = run(path, "--tf", TF, "--size", "32x24", "--azimuth", "30", "--elevation", "20",
                    "--report", report, "--output", path + ".exr")
    check(code == 0 and os.path.exists(report), "reads " + path + ": " + out)
    if code == 0:
        rays = json.load(open(report))["rays_cast"]
        check(reference_output in (None, rays), path + " gives the same rays as the others")
        reference_output = rays

# --compare against a reference image: per-channel thresholds, PSNR, SSIM.
reference = os.path.join(SCRATCH, "reference.exr")
report = os.path.join(SCRATCH, "compare.json")
run(VOLUME, "--tf", TF, "--size", "32x24", "--method", "reference", "--output", reference)
code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--method", "riemann", "--step", "1",
                "--compare", reference, "--report", report)
check(code == 0 and "SSIM" in out, "compare runs: " + out)
# The piecewise method at eps 1e-3: no channel of any pixel off by more than 2 eps.
pw_report = os.path.join(SCRATCH, "compare-piecewise.json")
code_pw, out_pw = run(VOLUME, "--tf", TF, "--size", "32x24", "--method", "piecewise",
                      "--tolerance", "0.001", "--compare", reference, "--report", pw_report)
check(code_pw == 0 and max(json.load(open(pw_report))["compare"]["max_error_rgba"]) <= 0.002,
      "piecewise within 2 eps of the reference: " + out_pw)
if code == 0:
    c = json.load(open(report))["compare"]
    check(c["pixels"] > 0 and all(0.0 < v <= 1.0 for v in c["ssim_rgba"]) and
          all(v is None or v > 20.0 for v in c["psnr_rgba"]), "compare figures: %r" % c)

# The GPU mapper's EXR holds the shader's float values: against the CPU mapper
# with the same method on the same frame, Riemann within 1e-4 (the same
# samples; float against double), coupled and decoupled within 2 eps (both
# within eps of the integral, their steps differ: the CPU skips empty space).
for method, tolerance, bound in [("riemann", "0.01", 1e-4), ("coupled", "0.001", 0.002),
                                 ("decoupled", "0.001", 0.002)]:
    cpu = os.path.join(SCRATCH, "cpu-" + method + ".exr")
    gpu_report = os.path.join(SCRATCH, "gpu-" + method + ".json")
    run(VOLUME, "--tf", TF, "--size", "32x24", "--method", method, "--tolerance", tolerance,
        "--output", cpu)
    code_gpu, out_gpu = run(VOLUME, "--tf", TF, "--size", "32x24", "--method", "gpu-" + method,
                            "--tolerance", tolerance, "--compare", cpu, "--report", gpu_report)
    check(code_gpu == 0 and json.load(open(gpu_report))["compare"]["pixels"] > 100 and
          max(json.load(open(gpu_report))["compare"]["max_error_rgba"]) <= bound,
          "gpu-%s within %g of the CPU mapper: %s" % (method, bound, out_gpu))

same = subprocess.run([COMPARE, dicom + ".exr", nhdr + ".exr", "--json"], capture_output=True,
                      text=True)
check(same.returncode == 0 and json.loads(same.stdout)["max_error"] == [0.0] * 4,
      "the DICOM folder renders exactly as the NRRD: " + same.stdout + same.stderr)

# avos-compare: the same PSNR and SSIM as --compare; its PSNR over all
# channels agrees with OpenImageIO's own (oiiotool --diff); identical images
# give an infinite PSNR and an SSIM of 1; shapes that differ are refused.
riemann = os.path.join(SCRATCH, "riemann-step1.exr")
run(VOLUME, "--tf", TF, "--size", "32x24", "--method", "riemann", "--step", "1", "--output", riemann)
result = subprocess.run([COMPARE, riemann, reference, "--json"], capture_output=True, text=True)
check(result.returncode == 0, "avos-compare runs: " + result.stderr)
if result.returncode == 0 and code == 0:
    m = json.loads(result.stdout)
    c = json.load(open(report))["compare"]
    check(m["channels"] == 4 and all(abs(a - b) < 1e-3 for a, b in zip(m["ssim"], c["ssim_rgba"])),
          "avos-compare's SSIM is --compare's: %r %r" % (m["ssim"], c["ssim_rgba"]))
    mse = sum(10 ** (-p / 10) for p in m["psnr"] if p != "inf") / 4
    diff = subprocess.run(["oiiotool", riemann, reference, "--diff"], capture_output=True,
                          text=True).stdout
    peak = [float(line.split("=")[1]) for line in diff.splitlines() if "Peak SNR" in line]
    check(len(peak) == 1 and abs(10 * math.log10(1 / mse) - peak[0]) < 0.01,
          "PSNR agrees with oiiotool --diff: %r vs %r" % (10 * math.log10(1 / mse), peak))
same = subprocess.run([COMPARE, reference, reference, "--json"], capture_output=True, text=True)
check(same.returncode == 0 and json.loads(same.stdout)["psnr"] == ["inf"] * 4 and
      json.loads(same.stdout)["ssim"] == [1.0] * 4, "identical images: " + same.stdout)
png = os.path.join(SCRATCH, "riemann.png")
for args, what in [([riemann, png], "differ in shape"), ([riemann, os.path.join(SCRATCH, "no.exr")],
                                                         "cannot read"), ([riemann], "usage")]:
    bad = subprocess.run([COMPARE, *args], capture_output=True, text=True)
    check(bad.returncode != 0 and what in bad.stderr, "avos-compare refuses %r: %s" % (args, bad.stderr))

# Clipping planes and cropping (--clip, --crop, --crop-mode): the mean alpha
# (oiiotool --printstats) of the kept part is below the whole's, nothing
# kept is transparent, a crop box around the whole volume changes nothing,
# and VTK's fixed-point mapper given the same plane keeps the same half.
def mean_alpha(*args):
    path = os.path.join(SCRATCH, "clip.exr")
    if os.path.exists(path):
        os.remove(path)
    code, out = run(VOLUME, "--tf", TF, "--size", "64x48", "--azimuth", "30", "--output", path,
                    *args)
    check(code == 0, "%s renders: %s" % (args, out))
    stats = subprocess.run(["oiiotool", path, "--printstats"], capture_output=True, text=True)
    for line in stats.stdout.splitlines():
        if "Stats Avg:" in line:
            return float(line.split()[5])
    return float("nan")


whole = mean_alpha("--method", "piecewise")
half = mean_alpha("--method", "piecewise", "--clip", "1,0,0,32,0,0")
other = mean_alpha("--method", "piecewise", "--clip", "-1,0,0,32,0,0")
none = mean_alpha("--method", "piecewise", "--clip", "1,0,0,1000,0,0")
box = mean_alpha("--method", "piecewise", "--crop", "-1,100,-1,100,-1,100")
inner = mean_alpha("--method", "piecewise", "--crop", "20,40,20,40,20,40")
fence = mean_alpha("--method", "piecewise", "--crop", "20,40,20,40,20,40", "--crop-mode", "fence")
fixed = mean_alpha("--method", "vtk-fixed-point", "--opacity", "vtk", "--clip", "1,0,0,32,0,0")
fixed_whole = mean_alpha("--method", "vtk-fixed-point", "--opacity", "vtk")
print("mean alpha: whole %.5f, x >= 32 %.5f, x <= 32 %.5f, nothing %.5f, box %.5f, "
      "sub-volume %.5f, fence %.5f; fixed point x >= 32 %.5f of %.5f"
      % (whole, half, other, none, box, inner, fence, fixed, fixed_whole))
check(0 < half < whole and 0 < other < whole, "a clipping plane keeps a part")
check(none == 0.0, "a plane keeping nothing leaves the image transparent")
check(box == whole, "cropping around the whole volume changes nothing")
check(0 < inner < fence < whole, "sub-volume < fence < whole")
check(abs(fixed / fixed_whole - half / whole) < 0.1,
      "VTK's fixed-point mapper keeps the same side of the plane")

# Intensity projections (--blend): exact here, sampled by VTK's fixed-point
# mapper, whose maximum can only fall short (up to its scalar rounding).
mip = mean_alpha("--method", "piecewise", "--blend", "maximum")
minip = mean_alpha("--method", "piecewise", "--blend", "minimum")
fixed_mip = mean_alpha("--method", "vtk-fixed-point", "--blend", "maximum")
print("mean alpha: maximum %.5f (fixed point %.5f), minimum %.5f" % (mip, fixed_mip, minip))
check(mip > 0 and 0 <= minip < mip, "a maximum projection shows, the minimum below it")
check(abs(fixed_mip - mip) < 0.05 * mip, "the fixed-point maximum agrees within 5 %")

# Additive and average: opaque grey wherever the ray meets the volume (the
# average: its range), so some pixels are opaque and a narrower range covers
# fewer of them.
additive = mean_alpha("--method", "coupled", "--blend", "additive")
wide = mean_alpha("--method", "coupled", "--blend", "average")
narrow = mean_alpha("--method", "coupled", "--blend", "average", "--average-range", "100,120")
print("mean alpha: additive %.5f, average %.5f, average over [100, 120] %.5f"
      % (additive, wide, narrow))
check(additive > 0.1 and 0 < narrow < wide, "additive and average render")

# Shading: the coupled and piecewise methods light the emission (the report
# says so); a projection refuses it with a message.
shaded_report = os.path.join(SCRATCH, "shaded.json")
for method in ("coupled", "piecewise"):
    code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--method", method, "--shade",
                    "--report", shaded_report)
    check(code == 0 and json.load(open(shaded_report))["shade"] is True,
          method + " --shade renders: " + out)
code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--blend", "maximum", "--shade")
check(code not in (0, -6, -11) and "Cannot shade" in out, "a projection refuses --shade: " + out)

# Gradient opacity: the piecewise method renders it (the report says so) and
# it changes the image; bad knots are refused.
plain_png = os.path.join(SCRATCH, "plain.png")
graded_png = os.path.join(SCRATCH, "graded.png")
code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--method", "piecewise", "--output",
                plain_png)
check(code == 0, "piecewise renders: " + out)
code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--method", "piecewise",
                "--gradient-opacity", "0,0,20,1", "--output", graded_png, "--report", shaded_report)
check(code == 0 and json.load(open(shaded_report))["gradient_opacity"] is True,
      "piecewise --gradient-opacity renders: " + out)
check(code == 0 and open(plain_png, "rb").read() != open(graded_png, "rb").read(),
      "gradient opacity changes the image")
for bad in ("0,0,20", "0,x", "0,nan"):
    code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--gradient-opacity", bad)
    check(code not in (0, -6, -11) and "--gradient-opacity needs pairs" in out,
          "--gradient-opacity " + bad + " is refused: " + out)

# Outputs are written whole or not at all: a failing run leaves the previous
# image and report as they were, and no partial file stays behind.
kept_png = os.path.join(SCRATCH, "kept.png")
kept_json = os.path.join(SCRATCH, "kept.json")
code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--output", kept_png, "--report", kept_json)
check(code == 0, "a good run: " + out)
before = (open(kept_png, "rb").read(), open(kept_json, "rb").read())
code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--method", "piecewise", "--tolerance",
                "1e-13", "--output", kept_png, "--report", kept_json)
check(code != 0, "a failing render fails: " + out)
check((open(kept_png, "rb").read(), open(kept_json, "rb").read()) == before,
      "a failing render leaves the previous files untouched")
check(not [f for f in os.listdir(SCRATCH) if ".partial-" in f], "no partial file left behind")

# Ctrl-C: a long render (Riemann at the smallest step, 512x512: minutes here)
# shows its progress on a terminal (a pseudo-terminal here) with an estimate
# of the time left; SIGINT then aborts the frame, nothing is written (the
# previous files stay) and the status is 130. The seconds from SIGINT to exit
# are printed, not asserted (no timed test); a mapper that ignored the abort
# would run into the wait's limit and fail.
terminal, terminal_end = pty.openpty()
proc = subprocess.Popen([EXE, VOLUME, "--tf", TF, "--size", "512x512", "--method", "riemann",
                         "--step", "0.001", "--output", kept_png, "--report", kept_json],
                        stdout=subprocess.PIPE, stderr=terminal_end)
os.close(terminal_end)
progress = b""
while b"s left" not in progress and proc.poll() is None:
    try:
        chunk = os.read(terminal, 4096)
    except OSError:
        break
    if not chunk:
        break
    progress += chunk
check(b"rendering" in progress and b"s left" in progress,
      "a long render shows progress and an estimate: %r" % progress[-200:])
sent = time.monotonic()
proc.send_signal(signal.SIGINT)
def read_terminal():
    rest = b""
    while True:
        try:
            chunk = os.read(terminal, 4096)
        except OSError:
            return rest
        if not chunk:
            return rest
        rest += chunk


try:
    proc.wait(timeout=60)
    print("Ctrl-C to exit: %.3f s" % (time.monotonic() - sent))
except subprocess.TimeoutExpired:
    proc.kill()
    proc.wait()
    check(False, "SIGINT stops the render")
rest = read_terminal()
os.close(terminal)
check(proc.returncode == 130 and b"interrupted" in rest,
      "an interrupted render exits 130 with a message: %d %r" % (proc.returncode, rest[-200:]))
check((open(kept_png, "rb").read(), open(kept_json, "rb").read()) == before,
      "an interrupted render leaves the previous files untouched")
check(not [f for f in os.listdir(SCRATCH) if ".partial-" in f], "no partial file after Ctrl-C")
# Into a log (stderr not a terminal) a frame of over a second leaves one
# final line, no carriage-return updates.
# (A frame of under a second, on a faster machine, leaves none.)
code, out = run(VOLUME, "--tf", TF, "--size", "512x512", "--method", "riemann", "--step", "0.005",
                "--output", os.path.join(SCRATCH, "logged.png"))
seconds = float(out.split("median ")[1].split(" s")[0]) if "median " in out else 0.0
final = out.count("rendered a frame in")
check(code == 0 and "\r" not in out and "s left" not in out and
      (final == (1 if seconds > 1.5 else 0) or (0.9 < seconds <= 1.5 and final <= 1)),
      "a log gets the final line only: %r" % out[-300:])
code, out = run(VOLUME, "--tf", TF, "--size", "32x24", "--output",
                os.path.join(SCRATCH, "no-such-folder", "x.png"))
check(code not in (0, -6, -11) and "cannot write" in out, "an unwritable output: " + out)

# Default transfer function (no --tf) and the VTK opacity model.
code, out = run(VOLUME, "--size", "32x24", "--opacity", "vtk")
check(code == 0 and "rays" in out, "default transfer function: " + out)

# Bad input: a message and a non-zero exit, never a crash.
for args, message in [((), "no input"),
                      ((VOLUME, "--method", "simpson"), "unknown method"),
                      ((VOLUME, "--size", "0x10"), "--size"),
                      ((VOLUME, "--tolerance", "abc"), "finite number"),
                      ((os.path.join(SCRATCH, "missing.vti"),), "no such file"),
                      ((VOLUME, "--tf", os.path.join(SCRATCH, "missing.tf1d")),
                       "transfer function"),
                      ((VOLUME, "--tolerance", "-1"), "tolerance"),
                      ((VOLUME, "--hmin", "5", "--hmax", "1"), "--hmin must not exceed --hmax"),
                      ((VOLUME, "--size", "100000x100000"), "each within [1, 16384]"),
                      ((VOLUME, "--frames", "1e9"), "--frames needs a whole number in [1, 100000]"),
                      ((VOLUME, "--threads", "2000"), "--threads needs a whole number in [0, 1024]"),
                      ((VOLUME, "--output", os.path.join(SCRATCH, "x.bmp")), ".png or .exr"),
                      ((VOLUME, "--clip", "0,0,0,1,1,1"), "--clip"),
                      ((VOLUME, "--clip", "1,0,0,1"), "--clip"),
                      ((VOLUME, "--crop", "5,1,0,1,0,1"), "--crop"),
                      ((VOLUME, "--crop-mode", "diagonal"), "--crop-mode"),
                      ((VOLUME, "--blend", "isosurface"), "--blend"),
                      ((VOLUME, "--blend", "average", "--average-range", "5,1"),
                       "--average-range"),
                      ((VOLUME, "--method", "riemann", "--step", "1e-6"), "--step must be within"),
                      ((VOLUME, "--hmin", "0"), "--hmin must be within"),
                      ((VOLUME, "--threads", "-1"), "--threads"),
                      ((VOLUME, "--method", "gpu-piecewise", "--shade"), "does not shade")]:
    code, out = run(*args)
    check(code not in (0, -6, -11) and message in out, "%s -> %r: %s" % (args, message, out))

print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
