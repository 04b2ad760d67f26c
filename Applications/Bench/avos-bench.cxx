// avos-bench: the adaptive-integration paper's evaluation on this machine.
// For each dataset it renders the reference once, then every method and
// parameter set of the paper on the same camera and image size, plus VTK's
// fixed-point and GPU mappers at the Riemann steps, and writes one folder:
//
//   results.csv       one row per run: time per frame, samples per ray, and per
//                     RGBA channel the % of rays above 0.01 / 0.005 / 0.001 and
//                     the mean, max and 99.9th-percentile error
//   histograms.csv    the error histograms (Figures 4 and 5)
//   steps.csv         the steps along one Bonsai ray (Figure 6)
//   report.md         the paper's Tables I, II, III, V and VI beside ours
//   *.png             histograms, steps, run time against error; images/
//
// Two families of runs, each against its own reference: "paper" renders the
// .tf1d in the paper's extinction semantics (our methods only, as the paper
// did); "vtk" converts it to VTK's opacity semantics so that VTK's mappers
// and ours render the same integral side by side.
//
// C++ rather than a script over avos-render: one process reads each volume
// once, the runs use the very classes a user calls (each in a window of its
// own), and the plots come from VTK's charts, so the tool needs nothing VTK
// does not have.
#include "AdversarialReport.h"
#include "avosBenchPlots.h"
#include "avosPaperTables.h"
#include "avosRenderSession.h"

#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAlgorithm.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"
#include "vtkTimerLog.h"
#include "vtkVariant.h"
#include "vtkVolumeMapper.h"
#include "vtkVolumeProperty.h"

#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace
{
namespace app = avos::app;
namespace bench = avos::bench;
namespace paper = avos::paper;

const char* Usage =
  "usage: avos-bench [--data DIR] [--datasets NAME,...] [--size WxH] [--frames N]\n"
  "                  [--threads N] [--output DIR] [--trace X,Y] [--quick] [--replot]\n"
  "                  [--adversarial RAYS]\n"
  "--data: the shared data folder (default ../shared/data).\n"
  "--datasets: any of BluntFin, Bonsai, Engine, Foot (default all four).\n"
  "--size: image size (default 800x600). --frames: timed frames per run, after\n"
  "one untimed warm-up frame (default 3; the median is reported).\n"
  "--trace: the pixel whose ray Figure 6 follows (default: chosen on Bonsai).\n"
  "--quick: BluntFin and Bonsai at 96x72, one frame, no warm-up (for CI).\n"
  "--output: the results folder (default out/bench).\n"
  "--replot: no rendering; redraw the plots from the CSV files in --output.\n"
  "--adversarial: no rendering; the numerical core's adversarial accuracy suite (thin\n"
  "layers, jumps, extinction 50, Marschner-Lobb, random 64-knot functions) with RAYS\n"
  "random rays per case, the piecewise, coupled and decoupled methods against the\n"
  "exact reference, then shaded, and shaded with gradient opacity, on RAYS / 10 rays,\n"
  "into --output/adversarial.md\n"
  "(100000 for the issue's figures).\n";

struct Dataset
{
  const char* Name;
  const char* Volume;
  const char* TF;
};
const Dataset Datasets[] = {
  { "BluntFin", "volumes/BluntFin.1.256x128x64.raw", "tf/BluntFin.1.256x128x64.linear.tf1d" },
  { "Bonsai", "volumes/bonsai_zfp.vti", "tf/Bonsai.1.256x256x256.linear.tf1d" },
  { "Engine", "volumes/engine_zfp.vti", "tf/Engine.1.256x256x128.linear.tf1d" },
  { "Foot", "volumes/foot_zfp.vti", "tf/Foot.tf1d" },
};
const char* TraceDataset = "Bonsai";
const double Tolerances[3] = { 0.01, 0.005, 0.001 };
const char* Channels = "RGBA";

struct Options
{
  std::string Data = "../shared/data";
  std::vector<std::string> Names;
  int Width = 800;
  int Height = 600;
  int Frames = 3;
  bool WarmUp = true;
  int Threads = 0;
  std::string Output = "out/bench";
  int TraceX = -1;
  int TraceY = -1;
  bool Replot = false;
  long AdversarialRays = 0; // > 0: only the adversarial suite
};

struct Run
{
  std::string Dataset;
  std::string Family; // "paper" or "vtk"
  app::MethodSettings Settings;
  double Median = std::numeric_limits<double>::quiet_NaN();
  double Minimum = std::numeric_limits<double>::quiet_NaN();
  double SamplesPerRay = std::numeric_limits<double>::quiet_NaN();
  long Rays = -1;
  app::ImageError Error;
  bool Failed = false;

  bool Is(const std::string& method, double tolerance = 0, double hmin = 0.1) const
  {
    const app::MethodSettings& s = this->Settings;
    if (s.Method != method)
    {
      return false;
    }
    if (method == "coupled" || method == "decoupled")
    {
      return s.Tolerance == tolerance && s.HMin == hmin;
    }
    return method == "reference" || s.Step == tolerance;
  }
};

// The runs of one dataset, references first (the others are measured
// against them).
std::vector<Run> Plan(const std::string& dataset)
{
  std::vector<Run> runs;
  auto add = [&](const std::string& family, const std::string& method, double value,
               double hmin = 0.1, double hmax = 2.0)
  {
    Run run;
    run.Dataset = dataset;
    run.Family = family;
    run.Settings.Method = method;
    run.Settings.VTKOpacity = family == "vtk";
    if (method == "coupled" || method == "decoupled")
    {
      run.Settings.Tolerance = value;
    }
    else if (method != "reference")
    {
      run.Settings.Step = value;
    }
    run.Settings.HMin = hmin;
    run.Settings.HMax = hmax;
    runs.push_back(run);
  };
  for (const char* family : { "paper", "vtk" })
  {
    add(family, "reference", 0.0);
  }
  for (double h : paper::RiemannSteps)
  {
    add("paper", "riemann", h);
  }
  for (const auto& clamp : { std::pair<double, double>{ 0.1, 2.0 }, { 0.4, 4.0 } })
  {
    for (double eps : Tolerances)
    {
      for (const char* method : { "coupled", "decoupled" })
      {
        add("paper", method, eps, clamp.first, clamp.second);
      }
    }
  }
  for (const char* method : { "riemann", "vtk-fixed-point", "vtk-gpu" })
  {
    for (double h : paper::RiemannSteps)
    {
      add("vtk", method, h);
    }
  }
  for (double eps : Tolerances)
  {
    add("vtk", "coupled", eps);
  }
  return runs;
}

std::string Parse(int argc, char* argv[], Options& o)
{
  bool quick = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help")
    {
      return "help";
    }
    if (arg == "--quick" || arg == "--replot")
    {
      (arg == "--quick" ? quick : o.Replot) = true;
      continue;
    }
    if (i + 1 >= argc)
    {
      return "option " + arg + " needs a value";
    }
    const std::string value = argv[++i];
    std::istringstream in(value);
    char x = 0;
    if (arg == "--data")
    {
      o.Data = value;
    }
    else if (arg == "--output")
    {
      o.Output = value;
    }
    else if (arg == "--datasets")
    {
      std::string name;
      while (std::getline(in, name, ','))
      {
        const auto known = std::find_if(std::begin(Datasets), std::end(Datasets),
          [&](const Dataset& d)
          { return vtksys::SystemTools::Strucmp(d.Name, name.c_str()) == 0; });
        if (known == std::end(Datasets))
        {
          return "unknown dataset '" + name + "' (BluntFin, Bonsai, Engine, Foot)";
        }
        o.Names.push_back(known->Name);
      }
    }
    else if (arg == "--size")
    {
      if (!(in >> o.Width >> x >> o.Height) || x != 'x' || o.Width < 8 || o.Height < 8 ||
        o.Width > 8192 || o.Height > 8192)
      {
        return "--size needs WxH between 8x8 and 8192x8192, e.g. 800x600";
      }
    }
    else if (arg == "--trace")
    {
      if (!(in >> o.TraceX >> x >> o.TraceY) || x != ',' || o.TraceX < 0 || o.TraceY < 0)
      {
        return "--trace needs X,Y pixel coordinates";
      }
    }
    else if (arg == "--adversarial")
    {
      if (!(in >> o.AdversarialRays) || !in.eof() || o.AdversarialRays < 1 ||
        o.AdversarialRays > 10000000)
      {
        return "--adversarial needs a number of rays between 1 and 10000000";
      }
    }
    else if (arg == "--frames" || arg == "--threads")
    {
      int n = 0;
      if (!(in >> n) || !in.eof() || n < (arg == "--frames" ? 1 : 0) || n > 1000)
      {
        return "option " + arg + " needs a whole number in [" + (arg == "--frames" ? "1" : "0") +
          ", 1000]";
      }
      (arg == "--frames" ? o.Frames : o.Threads) = n;
    }
    else
    {
      return "unknown option " + arg;
    }
  }
  if (quick)
  {
    o.Width = 96;
    o.Height = 72;
    o.Frames = 1;
    o.WarmUp = false;
    if (o.Names.empty())
    {
      o.Names = { "BluntFin", "Bonsai" };
    }
  }
  if (o.Names.empty())
  {
    for (const Dataset& d : Datasets)
    {
      o.Names.push_back(d.Name);
    }
  }
  if (o.TraceX >= o.Width || o.TraceY >= o.Height)
  {
    return "--trace is outside the image";
  }
  return std::string();
}

// One line per run; redrawn in place on a terminal.
class ProgressBar
{
public:
  explicit ProgressBar(std::size_t total)
    : Total(total)
    , Terminal(isatty(STDERR_FILENO) != 0)
  {
    this->Clock->StartTimer();
  }
  void Show(std::size_t done, const std::string& what)
  {
    constexpr int Width = 30;
    const int filled = static_cast<int>(Width * done / std::max<std::size_t>(this->Total, 1));
    this->Clock->StopTimer();
    std::ostringstream line;
    line << "[" << std::string(filled, '#') << std::string(Width - filled, '.') << "] "
         << std::setw(3) << done << "/" << this->Total << "  " << std::fixed << std::setprecision(0)
         << this->Clock->GetElapsedTime() << " s  " << what;
    std::cerr << (this->Terminal ? "\r\033[K" : "") << line.str() << (this->Terminal ? "" : "\n")
              << std::flush;
  }
  void Finish() const
  {
    if (this->Terminal)
    {
      std::cerr << "\n";
    }
  }

private:
  std::size_t Total;
  bool Terminal;
  vtkNew<vtkTimerLog> Clock;
};

// The pixel Figure 6 follows: the covered pixel nearest the image's centre
// whose reference opacity is between 0.5 and 0.95 (a ray that crosses
// structure without being opaque at once).
bool ChooseTracePixel(const std::vector<float>& reference, int width, int height, int& x, int& y)
{
  double best = std::numeric_limits<double>::infinity();
  for (int j = 0; j < height; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      const float alpha = reference[4 * (static_cast<std::size_t>(j) * width + i) + 3];
      const double d = std::hypot(i - 0.5 * width, j - 0.5 * height);
      if (alpha >= 0.5f && alpha <= 0.95f && d < best)
      {
        best = d;
        x = i;
        y = j;
      }
    }
  }
  return std::isfinite(best);
}

struct Trace
{
  std::string Label;
  std::vector<double> Start, Length, Opacity;
};

Trace TraceOf(vtkAdaptiveVolumeMapper* mapper, const std::string& label, int x, int y)
{
  Trace trace;
  trace.Label = label;
  vtkNew<vtkTable> steps;
  if (mapper && mapper->TraceRay(x, y, steps))
  {
    for (vtkIdType r = 0; r < steps->GetNumberOfRows(); ++r)
    {
      trace.Start.push_back(steps->GetValueByName(r, "Start").ToDouble());
      trace.Length.push_back(steps->GetValueByName(r, "Length").ToDouble());
      trace.Opacity.push_back(steps->GetValueByName(r, "Opacity").ToDouble());
    }
  }
  return trace;
}

std::string Number(double v, int digits = 4)
{
  if (!std::isfinite(v))
  {
    return "—";
  }
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << v;
  return out.str();
}

const Run* Find(const std::vector<Run>& runs, const std::string& dataset, const std::string& family,
  const std::string& method, double value = 0, double hmin = 0.1)
{
  for (const Run& r : runs)
  {
    if (r.Dataset == dataset && r.Family == family && !r.Failed && r.Is(method, value, hmin))
    {
      return &r;
    }
  }
  return nullptr;
}

// Tables I and II's layout: rows Riemann h, Coupled, Decoupled (at eps = the
// column's threshold); each cell "ours (paper)".
void AccuracyTable(std::ostream& md, const std::vector<Run>& runs, const std::string& dataset,
  const double (*paperTable)[12], double hmin)
{
  md << "| | E > 0.01 R | G | B | A | E > 0.005 R | G | B | A | E > 0.001 R | G | B | A |\n"
     << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  auto cell = [&](const Run* run, int t, int ch, const double* p)
  {
    std::string text = run ? Number(run->Error.Exceeding[t][ch]) : "—";
    if (p)
    {
      text += " (" + Number(p[4 * t + ch]) + ")";
    }
    return text;
  };
  const bool bothRows = hmin == 0.1;
  for (int row = 0; row < 7; ++row)
  {
    if (row < 5 && !bothRows)
    {
      continue;
    }
    const double* p = paperTable ? paperTable[row] : nullptr;
    std::ostringstream name;
    if (row < 5)
    {
      name << "Riemann (h = " << paper::RiemannSteps[row] << ")";
    }
    else
    {
      name << (row == 5 ? "Coupled" : "Decoupled");
    }
    md << "| " << name.str();
    for (int t = 0; t < 3; ++t)
    {
      const Run* run = row < 5
        ? Find(runs, dataset, "paper", "riemann", paper::RiemannSteps[row])
        : Find(runs, dataset, "paper", row == 5 ? "coupled" : "decoupled", Tolerances[t], hmin);
      for (int ch = 0; ch < 4; ++ch)
      {
        md << " | " << cell(run, t, ch, p);
      }
    }
    md << " |\n";
  }
}

void WriteReport(std::ostream& md, const Options& o, const std::vector<Run>& runs,
  const std::string& command, double seconds, const std::string& traceNote)
{
  auto has = [&](const char* name)
  { return std::find(o.Names.begin(), o.Names.end(), name) != o.Names.end(); };
  md << "# avos-bench report\n\n"
     << "Made by `" << command << "` in " << Number(seconds / 60.0, 1) << " minutes; " << o.Width
     << "x" << o.Height << " pixels, " << vtkSMPTools::GetEstimatedNumberOfThreads()
     << " threads, median of " << o.Frames << " frame(s)"
     << (o.WarmUp ? " after an untimed warm-up" : "")
     << ". Errors are per RGBA channel against the fine reference of the same family, over the "
        "rays that met the volume (pixels where either image is not transparent). Cells read "
        "**ours (paper)**; the paper's figures come from its 2.66 GHz quad core and its own "
        "renderer, so only their trends compare.\n\n";

  for (const auto& table : { std::make_pair("I", "Bonsai"), std::make_pair("II", "BluntFin") })
  {
    if (!has(table.second))
    {
      continue;
    }
    md << "## Table " << table.first << ": % of rays above the tolerance, " << table.second
       << "\n\nCoupled and decoupled at eps = the column's threshold, h0 = 0.5, hmin = 0.1, "
          "hmax = 2.0 (the paper's extinction semantics).\n\n";
    AccuracyTable(md, runs, table.second,
      std::string(table.first) == "I" ? paper::TableI : paper::TableII, 0.1);
    md << "\n";
  }
  for (const std::string& name : o.Names)
  {
    if (name == "Bonsai" || name == "BluntFin")
    {
      continue;
    }
    md << "## The same table for " << name << " (not in the paper)\n\n";
    AccuracyTable(md, runs, name, nullptr, 0.1);
    md << "\n";
  }

  md << "## Table III: CPU seconds per frame\n\nThe paper's Teapot is not among our data; its "
        "column is left out.\n\n| | |";
  const int paperColumn[4] = { 0, 1, 3, -1 }; // BluntFin, Bonsai, Engine, (Foot)
  for (const std::string& name : o.Names)
  {
    md << " " << name << " |";
  }
  md << "\n|---|---|"
     << [&]
  {
    std::string s;
    for (std::size_t i = 0; i < o.Names.size(); ++i)
    {
      s += "---:|";
    }
    return s;
  }() << "\n";
  for (int row = 0; row < 11; ++row)
  {
    const bool riemann = row < 5;
    const int k = riemann ? 0 : (row - 5) / 2;
    const std::string method = riemann ? "riemann" : ((row - 5) % 2 ? "decoupled" : "coupled");
    const double value = riemann ? paper::RiemannSteps[row] : Tolerances[k];
    md << "| "
       << (riemann                  ? "Riemann"
              : method == "coupled" ? "Coupled"
                                    : "Decoupled")
       << " | " << (riemann ? "h = " : "eps = ") << value << " |";
    for (const std::string& name : o.Names)
    {
      const Run* run = Find(runs, name, "paper", method, value);
      const auto d = std::find_if(std::begin(Datasets), std::end(Datasets),
                       [&](const Dataset& ds) { return name == ds.Name; }) -
        std::begin(Datasets);
      md << " " << (run ? Number(run->Median, 3) : "—");
      if (paperColumn[d] >= 0)
      {
        md << " (" << Number(paper::TableIII[row][paperColumn[d]], 2) << ")";
      }
      md << " |";
    }
    md << "\n";
  }
  md << "\n";

  if (has("Bonsai"))
  {
    const Run* rows[3] = { Find(runs, "Bonsai", "paper", "riemann", 0.1),
      Find(runs, "Bonsai", "paper", "coupled", 0.001, 0.4),
      Find(runs, "Bonsai", "paper", "decoupled", 0.001, 0.4) };
    const char* names[3] = { "Riemann (h = 0.1)", "Coupled (eps = 0.001)",
      "Decoupled (eps = 0.001)" };
    md << "## Table V: Bonsai with hmin = 0.4, hmax = 4.0\n\nOurs is CPU only (the paper's GPU "
          "column is its GLSL renderer's; there is no adaptive GPU mapper here).\n\n"
       << "| | CPU s ours (paper) | GPU fps (paper) |\n|---|---:|---:|\n";
    for (int r = 0; r < 3; ++r)
    {
      md << "| " << names[r] << " | " << (rows[r] ? Number(rows[r]->Median, 3) : "—") << " ("
         << Number(paper::TableV[r][0], 2) << ") | " << Number(paper::TableV[r][1], 0) << " |\n";
    }
    md << "\n## Table VI: % of rays above 0.001, Bonsai, eps = 0.001, hmin = 0.4, hmax = 4.0\n\n"
       << "| | R | G | B | A |\n|---|---:|---:|---:|---:|\n";
    for (int r = 0; r < 3; ++r)
    {
      md << "| " << names[r];
      for (int ch = 0; ch < 4; ++ch)
      {
        md << " | " << (rows[r] ? Number(rows[r]->Error.Exceeding[2][ch]) : "—") << " ("
           << Number(paper::TableVI[r][ch]) << ")";
      }
      md << " |\n";
    }
    md << "\n";
  }

  md << "## Every run\n\nmean / 99.9th percentile / max error, per channel; samples per ray "
        "for our mapper (rays that entered the volume's box); pixels compared (covered in "
        "either image).\n\n"
     << "| dataset | family | run | s / frame | samples / ray | pixels | R | G | B | A |\n"
     << "|---|---|---|---:|---:|---:|---|---|---|---|\n";
  for (const Run& r : runs)
  {
    md << "| " << r.Dataset << " | " << r.Family << " | " << r.Settings.Label() << " | "
       << (r.Failed ? "failed" : Number(r.Median, 3)) << " | " << Number(r.SamplesPerRay, 1)
       << " | " << r.Error.Pixels;
    for (int ch = 0; ch < 4; ++ch)
    {
      md << " | " << Number(r.Error.Mean[ch], 5) << " / " << Number(r.Error.Percentile999[ch], 4)
         << " / " << Number(r.Error.Maximum[ch], 4);
    }
    md << " |\n";
  }
  md << "\n## Plots\n\n";
  for (const std::string& name : o.Names)
  {
    md << "- " << name << ": error histograms at eps = 0.001 (Figures 4, 5) `histograms-" << name
       << ".png`, run time against error `time-error-" << name << ".png`\n";
  }
  md << "- Figure 6: `steps.png` (" << traceNote << ")\n";
}

void WriteCSV(std::ostream& csv, const std::vector<Run>& runs, int width, int height, int frames)
{
  csv << "dataset,family,method,tolerance,step,h0,hmin,hmax,width,height,frames,median_s,min_s,"
         "rays,samples_per_ray,pixels";
  for (int ch = 0; ch < 4; ++ch)
  {
    for (const char* field :
      { "gt_0.01", "gt_0.005", "gt_0.001", "mean", "max", "p99.9", "psnr", "ssim" })
    {
      csv << "," << Channels[ch] << "_" << field;
    }
  }
  csv << "\n" << std::setprecision(8);
  for (const Run& r : runs)
  {
    const app::MethodSettings& s = r.Settings;
    csv << r.Dataset << "," << r.Family << "," << s.Method << "," << s.Tolerance << "," << s.Step
        << "," << s.H0 << "," << s.HMin << "," << s.HMax << "," << width << "," << height << ","
        << frames << "," << r.Median << "," << r.Minimum << "," << r.Rays << "," << r.SamplesPerRay
        << "," << r.Error.Pixels;
    for (int ch = 0; ch < 4; ++ch)
    {
      const app::ImageError& e = r.Error;
      csv << "," << e.Exceeding[0][ch] << "," << e.Exceeding[1][ch] << "," << e.Exceeding[2][ch]
          << "," << e.Mean[ch] << "," << e.Maximum[ch] << "," << e.Percentile999[ch] << ","
          << e.PSNR[ch] << "," << e.SSIM[ch];
    }
    csv << "\n";
  }
}

void WriteHistograms(std::ostream& csv, const std::vector<Run>& runs)
{
  csv << "dataset,family,run,channel,bin_lower,bin_upper,count,percent\n" << std::setprecision(8);
  for (const Run& r : runs)
  {
    if (r.Failed || r.Settings.Method == "reference" || r.Error.Pixels == 0)
    {
      continue;
    }
    for (int ch = 0; ch < 4; ++ch)
    {
      for (int b = 0; b < app::ImageError::Bins; ++b)
      {
        const long count = r.Error.Histogram[ch][b];
        csv << r.Dataset << "," << r.Family << ",\"" << r.Settings.Label() << "\"," << Channels[ch]
            << "," << app::ImageError::BinLowerEdge(b) << ","
            << (b + 1 < app::ImageError::Bins ? app::ImageError::BinLowerEdge(b + 1) : 1.0) << ","
            << count << "," << 100.0 * count / r.Error.Pixels << "\n";
      }
    }
  }
}

bool WritePlots(const Options& o, const std::vector<Run>& runs, const std::vector<Trace>& traces)
{
  bool ok = true;
  for (const std::string& name : o.Names)
  {
    // Figures 4 and 5: the error's distribution per channel, eps = 0.001.
    std::vector<bench::Chart> charts;
    for (int ch = 0; ch < 4; ++ch)
    {
      bench::Chart chart;
      chart.Title = name + ", channel " + Channels[ch];
      chart.XTitle = "|error| (bin centre)";
      chart.YTitle = "% of rays";
      chart.LogX = true;
      for (const Run* r : { Find(runs, name, "paper", "riemann", 0.5),
             Find(runs, name, "paper", "riemann", 0.1), Find(runs, name, "paper", "coupled", 0.001),
             Find(runs, name, "paper", "decoupled", 0.001) })
      {
        if (!r || r->Error.Pixels == 0)
        {
          continue;
        }
        bench::Series series;
        series.Label = r->Settings.Label();
        for (int b = 0; b < app::ImageError::Bins; ++b)
        {
          const double lo = b == 0 ? 1e-7 : app::ImageError::BinLowerEdge(b);
          const double hi =
            b + 1 < app::ImageError::Bins ? app::ImageError::BinLowerEdge(b + 1) : 1.0;
          series.X.push_back(std::sqrt(lo * hi));
          series.Y.push_back(100.0 * r->Error.Histogram[ch][b] / r->Error.Pixels);
        }
        chart.Data.push_back(series);
      }
      charts.push_back(chart);
    }
    ok &= bench::WriteCharts(o.Output + "/histograms-" + name + ".png", charts, 2, 1200, 900);

    // Run time against error: one curve per method, the figure a user picks from.
    bench::Chart chart;
    chart.Title = name + ": run time against error";
    chart.XTitle = "seconds per frame";
    chart.YTitle = "99.9th percentile |error|, worst channel";
    chart.LogX = chart.LogY = true;
    struct Curve
    {
      const char* Label;
      const char* Family;
      const char* Method;
      double HMin;
    };
    for (const Curve& c : { Curve{ "Riemann h 0.5..0.1", "paper", "riemann", 0.1 },
           Curve{ "coupled eps 0.01..0.001", "paper", "coupled", 0.1 },
           Curve{ "decoupled eps 0.01..0.001", "paper", "decoupled", 0.1 },
           Curve{ "coupled, hmin 0.4 hmax 4", "paper", "coupled", 0.4 },
           Curve{ "Riemann (VTK semantics)", "vtk", "riemann", 0.1 },
           Curve{ "VTK fixed point h 0.5..0.1", "vtk", "vtk-fixed-point", 0.1 },
           Curve{ "VTK GPU (llvmpipe) h 0.5..0.1", "vtk", "vtk-gpu", 0.1 } })
    {
      bench::Series series;
      series.Label = c.Label;
      for (const Run& r : runs)
      {
        if (r.Dataset == name && r.Family == c.Family && r.Settings.Method == c.Method &&
          !r.Failed && r.Settings.HMin == c.HMin)
        {
          series.X.push_back(r.Median);
          series.Y.push_back(*std::max_element(r.Error.Percentile999, r.Error.Percentile999 + 4));
        }
      }
      chart.Data.push_back(series);
    }
    ok &= bench::WriteCharts(o.Output + "/time-error-" + name + ".png", { chart }, 1, 900, 650);
  }

  // Figure 6: opacity along the traced ray, the fine Riemann sum as the
  // curve and each adaptive step's end as a point; below, the step sizes.
  if (!traces.empty())
  {
    bench::Chart opacity;
    opacity.Title = "Adaptive steps along one Bonsai ray (alpha channel)";
    opacity.XTitle = "distance along the ray (voxels)";
    opacity.YTitle = "opacity 1 - T";
    bench::Chart steps;
    steps.Title = "Step sizes";
    steps.XTitle = opacity.XTitle;
    steps.YTitle = "step length (voxels)";
    for (const Trace& t : traces)
    {
      const bool adaptive = t.Label.rfind("riemann", 0) != 0;
      bench::Series alpha, length;
      alpha.Label = length.Label = t.Label;
      alpha.Points = length.Points = adaptive;
      for (std::size_t i = 0; i < t.Start.size(); ++i)
      {
        alpha.X.push_back(t.Start[i] + t.Length[i]);
        alpha.Y.push_back(t.Opacity[i]);
        length.X.push_back(t.Start[i]);
        length.Y.push_back(t.Length[i]);
      }
      opacity.Data.push_back(alpha);
      if (adaptive)
      {
        steps.Data.push_back(length);
      }
    }
    ok &= bench::WriteCharts(o.Output + "/steps.png", { opacity, steps }, 1, 1000, 900);
  }
  return ok;
}
// The fields of one CSV line; quoted fields may hold commas.
std::vector<std::string> SplitCSV(const std::string& line)
{
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char c : line)
  {
    if (c == '"')
    {
      quoted = !quoted;
    }
    else if (c == ',' && !quoted)
    {
      fields.emplace_back();
    }
    else
    {
      fields.back() += c;
    }
  }
  return fields;
}

// Rows of a CSV file as name -> value maps; empty when it cannot be read.
std::vector<std::map<std::string, std::string>> ReadCSV(const std::string& path)
{
  std::vector<std::map<std::string, std::string>> rows;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line))
  {
    std::cerr << "error: cannot read '" << path << "'\n";
    return rows;
  }
  const std::vector<std::string> header = SplitCSV(line);
  while (std::getline(in, line))
  {
    const std::vector<std::string> fields = SplitCSV(line);
    if (fields.size() != header.size())
    {
      std::cerr << "error: '" << path << "' has a malformed line: " << line << "\n";
      return {};
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size(); ++i)
    {
      row[header[i]] = fields[i];
    }
    rows.push_back(row);
  }
  return rows;
}

// The runs, histograms and traces of an earlier run, from its CSV files.
bool ReadResults(Options& o, std::vector<Run>& runs, std::vector<Trace>& traces)
{
  auto number = [](const std::string& text) { return std::strtod(text.c_str(), nullptr); };
  o.Names.clear();
  for (const auto& row : ReadCSV(o.Output + "/results.csv"))
  {
    Run run;
    run.Dataset = row.at("dataset");
    run.Family = row.at("family");
    app::MethodSettings& s = run.Settings;
    s.Method = row.at("method");
    s.Tolerance = number(row.at("tolerance"));
    s.Step = number(row.at("step"));
    s.H0 = number(row.at("h0"));
    s.HMin = number(row.at("hmin"));
    s.HMax = number(row.at("hmax"));
    run.Median = number(row.at("median_s"));
    run.Minimum = number(row.at("min_s"));
    run.SamplesPerRay = number(row.at("samples_per_ray"));
    run.Error.Pixels = std::atol(row.at("pixels").c_str());
    for (int ch = 0; ch < 4; ++ch)
    {
      const std::string c(1, Channels[ch]);
      run.Error.Exceeding[0][ch] = number(row.at(c + "_gt_0.01"));
      run.Error.Exceeding[1][ch] = number(row.at(c + "_gt_0.005"));
      run.Error.Exceeding[2][ch] = number(row.at(c + "_gt_0.001"));
      run.Error.Mean[ch] = number(row.at(c + "_mean"));
      run.Error.Maximum[ch] = number(row.at(c + "_max"));
      run.Error.Percentile999[ch] = number(row.at(c + "_p99.9"));
    }
    run.Failed = !std::isfinite(run.Median);
    if (std::find(o.Names.begin(), o.Names.end(), run.Dataset) == o.Names.end())
    {
      o.Names.push_back(run.Dataset);
    }
    runs.push_back(run);
  }
  for (const auto& row : ReadCSV(o.Output + "/histograms.csv"))
  {
    for (Run& run : runs)
    {
      if (run.Dataset == row.at("dataset") && run.Family == row.at("family") &&
        run.Settings.Label() == row.at("run"))
      {
        const int ch = static_cast<int>(std::string(Channels).find(row.at("channel")));
        const double lower = number(row.at("bin_lower"));
        int bin = 0;
        while (bin + 1 < app::ImageError::Bins && app::ImageError::BinLowerEdge(bin + 1) <= lower)
        {
          ++bin;
        }
        run.Error.Histogram[ch][bin] = std::atol(row.at("count").c_str());
      }
    }
  }
  for (const auto& row : ReadCSV(o.Output + "/steps.csv"))
  {
    if (traces.empty() || traces.back().Label != row.at("run"))
    {
      traces.push_back(Trace{ row.at("run"), {}, {}, {} });
    }
    traces.back().Start.push_back(number(row.at("start")));
    traces.back().Length.push_back(number(row.at("length")));
    traces.back().Opacity.push_back(number(row.at("opacity")));
  }
  return !runs.empty();
}
} // namespace

int main(int argc, char* argv[])
{
  Options o;
  const int status = app::CommandLineStatus(Parse(argc, argv, o), Usage);
  if (status >= 0)
  {
    return status;
  }
  if (o.Replot)
  {
    std::vector<Run> runs;
    std::vector<Trace> traces;
    if (!ReadResults(o, runs, traces))
    {
      std::cerr << "error: no results to plot in '" << o.Output << "'\n";
      return EXIT_FAILURE;
    }
    return WritePlots(o, runs, traces) ? EXIT_SUCCESS : EXIT_FAILURE;
  }
  if (o.AdversarialRays > 0)
  {
    const std::string path = o.Output + "/adversarial.md";
    app::AtomicFile atomic(path);
    std::FILE* file = vtksys::SystemTools::MakeDirectory(o.Output)
      ? vtksys::SystemTools::Fopen(atomic.Path(), "w")
      : nullptr;
    if (!file)
    {
      std::cerr << "error: cannot write '" << path << "'\n";
      return EXIT_FAILURE;
    }
    // (The mixtures' oracle costs about 50 ms a ray: a fiftieth of the rays.)
    adversarial::WriteReport(file, o.AdversarialRays, o.Threads > 0 ? o.Threads : 2,
      o.AdversarialRays / 10, o.AdversarialRays / 50);
    if (std::fclose(file) != 0 || !atomic.Commit())
    {
      std::cerr << "error: cannot write '" << path << "'\n";
      return EXIT_FAILURE;
    }
    std::cout << "adversarial suite: " << path << "\n";
    return EXIT_SUCCESS;
  }
  if (o.Threads > 0)
  {
    vtkSMPTools::Initialize(o.Threads);
  }
  if (!vtksys::SystemTools::MakeDirectory(o.Output + "/images"))
  {
    std::cerr << "error: cannot create '" << o.Output << "/images'\n";
    return EXIT_FAILURE;
  }
  std::string command = "avos-bench";
  for (int i = 1; i < argc; ++i)
  {
    command += std::string(" ") + argv[i];
  }

  std::vector<Run> all;
  std::vector<std::vector<Run>> plans;
  std::size_t total = 0;
  for (const std::string& name : o.Names)
  {
    plans.push_back(Plan(name));
    total += plans.back().size();
  }
  ProgressBar bar(total);
  vtkNew<vtkTimerLog> clock;
  clock->StartTimer();
  std::vector<Trace> traces;
  std::string traceNote = "no traced ray: Bonsai was not benchmarked";
  std::size_t done = 0;
  for (std::size_t d = 0; d < o.Names.size(); ++d)
  {
    const std::string& name = o.Names[d];
    const Dataset& dataset = *std::find_if(
      std::begin(Datasets), std::end(Datasets), [&](const Dataset& x) { return name == x.Name; });
    const std::string volumePath = o.Data + "/" + dataset.Volume;
    const std::string tfPath = o.Data + "/" + dataset.TF;
    std::string error;
    vtkSmartPointer<vtkAlgorithm> reader = app::MakeReader(volumePath, error);
    vtkImageData* volume = reader ? app::ReadVolume(reader, volumePath, error) : nullptr;
    if (!volume)
    {
      std::cerr << "error: " << error << "\n";
      return EXIT_FAILURE;
    }
    const double voxel = app::VoxelLength(volume);

    std::vector<Run>& runs = plans[d];
    for (const char* family : { "paper", "vtk" })
    {
      vtkNew<vtkVolumeProperty> property;
      property->SetInterpolationTypeToLinear();
      if (!app::LoadTransferFunction(tfPath, std::string(family) == "vtk", voxel, property))
      {
        std::cerr << "error: cannot use the transfer function '" << tfPath << "'\n";
        return EXIT_FAILURE;
      }
      std::vector<float> reference;
      int traceX = o.TraceX, traceY = o.TraceY;
      for (Run& run : runs)
      {
        if (run.Family != family)
        {
          continue;
        }
        bar.Show(done, name + " " + run.Family + ": " + run.Settings.Label());
        run.Settings.Threads = o.Threads;
        vtkSmartPointer<vtkVolumeMapper> mapper = app::MakeMapper(run.Settings, voxel);
        const bool isReference = run.Settings.Method == "reference";
        // A window of its own for every run: no state carries over.
        app::RenderSession session(reader, property, o.Width, o.Height, 0.0, 0.0, 1.0);
        if (o.WarmUp && !isReference)
        {
          session.Render(mapper, 1);
        }
        const std::vector<double> times = session.Render(mapper, isReference ? 1 : o.Frames);
        ++done;
        if (times.empty() || (!isReference && reference.empty()))
        {
          run.Failed = true;
          std::cerr << "\nerror: " << name << " " << run.Settings.Label() << " failed\n";
          continue;
        }
        run.Median = app::Median(times);
        run.Minimum = *std::min_element(times.begin(), times.end());
        auto* adaptive = vtkAdaptiveVolumeMapper::SafeDownCast(mapper);
        if (adaptive)
        {
          run.SamplesPerRay = adaptive->GetMeanSamplesPerRay();
          run.Rays = adaptive->GetRaysCast();
        }
        const std::vector<float> image = session.Image();
        if (isReference)
        {
          reference = image;
        }
        run.Error = app::Compare(image, reference, o.Width, o.Height);
        std::ostringstream file;
        file << o.Output << "/images/" << name << "-" << run.Family << "-" << run.Settings.Method
             << "-"
             << (run.Settings.Method == "coupled" || run.Settings.Method == "decoupled"
                    ? run.Settings.Tolerance
                    : run.Settings.Step);
        if (run.Settings.HMin != 0.1)
        {
          file << "-hmin" << run.Settings.HMin;
        }
        app::WriteImage(file.str() + (isReference ? ".exr" : ".png"), o.Width, o.Height, image);

        // Figure 6 on Bonsai: the paper's eps = 0.01, hmin 0.4, hmax 4, and
        // the fine Riemann sum along the same ray.
        if (name == TraceDataset && run.Family == "paper")
        {
          if (isReference && traceX < 0 &&
            !ChooseTracePixel(reference, o.Width, o.Height, traceX, traceY))
          {
            traceX = o.Width / 2;
            traceY = o.Height / 2;
          }
          if (run.Is("riemann", 0.1) || run.Is("coupled", 0.01, 0.4))
          {
            traces.push_back(TraceOf(adaptive, run.Settings.Label(), traceX, traceY));
            std::ostringstream note;
            note << "Bonsai, pixel (" << traceX << ", " << traceY << ") from the bottom left";
            traceNote = note.str();
          }
        }
      }
    }
    all.insert(all.end(), runs.begin(), runs.end());
  }
  bar.Show(done, "done");
  bar.Finish();
  clock->StopTimer();

  // Each file whole or not at all (app::WriteTextFile).
  const bool written =
    app::WriteTextFile(o.Output + "/results.csv",
      [&](std::ostream& out) { WriteCSV(out, all, o.Width, o.Height, o.Frames); }) &&
    app::WriteTextFile(
      o.Output + "/histograms.csv", [&](std::ostream& out) { WriteHistograms(out, all); }) &&
    app::WriteTextFile(o.Output + "/steps.csv",
      [&](std::ostream& csv)
      {
        csv << "run,start,length,opacity\n" << std::setprecision(10);
        for (const Trace& t : traces)
        {
          for (std::size_t i = 0; i < t.Start.size(); ++i)
          {
            csv << "\"" << t.Label << "\"," << t.Start[i] << "," << t.Length[i] << ","
                << t.Opacity[i] << "\n";
          }
        }
      }) &&
    app::WriteTextFile(o.Output + "/report.md",
      [&](std::ostream& out)
      { WriteReport(out, o, all, command, clock->GetElapsedTime(), traceNote); });
  const bool plotted = written && WritePlots(o, all, traces);
  const bool failed = std::any_of(all.begin(), all.end(), [](const Run& r) { return r.Failed; });
  std::cout << "avos-bench: " << all.size() << " runs in " << Number(clock->GetElapsedTime(), 1)
            << " s; results in " << o.Output << "\n";
  return plotted && !failed ? EXIT_SUCCESS : EXIT_FAILURE;
}
