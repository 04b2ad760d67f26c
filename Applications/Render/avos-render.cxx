// avos-render: render a volume with vtkAdaptiveVolumeMapper (or, side by
// side, with VTK's own mappers) to an image and a JSON report.
//
//   avos-render INPUT [--tf FILE.tf1d] [--method riemann|coupled|decoupled|piecewise|
//               reference|vtk-fixed-point|vtk-gpu|gpu-riemann|gpu-coupled|gpu-decoupled|
//               gpu-piecewise]
//               [--opacity extinction|vtk] [--tolerance E]
//               [--step H] [--h0 H] [--hmin H] [--hmax H] [--size WxH] [--azimuth DEG]
//               [--elevation DEG] [--zoom Z] [--frames N] [--threads N]
//               [--output FILE.png|FILE.exr] [--report FILE.json] [--compare REF.exr]
//               [--clip NX,NY,NZ,OX,OY,OZ]... [--crop X0,X1,Y0,Y1,Z0,Z1]
//               [--crop-mode subvolume|fence|inverted-fence|cross|inverted-cross]
//               [--blend composite|maximum|minimum]
//
// INPUT: .vti, .mhd/.mha, .nrrd/.nhdr, a volvis .raw name (Name.1.XxYxZ.raw)
// or a DICOM folder. Runs in an off-screen window (under Xvfb on a headless
// machine: xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" avos-render ...).
#include "avosRenderSession.h"

#include "vtkAdaptiveVolumeMapper.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlane.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTimerLog.h"
#include "vtkVolumeMapper.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h> // isatty

namespace
{
namespace app = avos::app;

// The ranges of the knobs that multiply work (the steps' range is the mapper's).
constexpr int MaximumSide = 16384;
constexpr int MaximumFrames = 100000;
constexpr int MaximumThreads = 1024;

const char* Usage =
  "usage: avos-render INPUT [--tf FILE.tf1d]\n"
  "         [--method riemann|coupled|decoupled|piecewise|reference|vtk-fixed-point|vtk-gpu|\n"
  "                   gpu-riemann|gpu-coupled|gpu-decoupled|gpu-piecewise]\n"
  "         [--opacity extinction|vtk] [--tolerance E] [--step H] [--h0 H] [--hmin H]\n"
  "         [--hmax H] [--size WxH] [--azimuth DEG] [--elevation DEG] [--zoom Z]\n"
  "         [--frames N] [--threads N] [--output FILE.png|FILE.exr] [--report FILE.json]\n"
  "         [--compare REF.exr] [--clip NX,NY,NZ,OX,OY,OZ]... [--crop X0,X1,Y0,Y1,Z0,Z1]\n"
  "         [--crop-mode subvolume|fence|inverted-fence|cross|inverted-cross]\n"
  "         [--blend composite|maximum|minimum|average|additive] [--average-range LO,HI]\n"
  "         [--shade] [--gradient-opacity G,V[,G,V]...]\n"
  "INPUT: .vti, .mhd/.mha, .nrrd/.nhdr, volvis .raw (Name.1.XxYxZ.raw) or a DICOM folder.\n"
  "--tf gives the paper's extinction semantics (tau per voxel unit); without it a\n"
  "transfer function is derived from the data range, in VTK's semantics.\n"
  "--opacity vtk renders the TF converted to VTK's semantics (alpha = 1 - exp(-tau) per\n"
  "voxel unit at the knots), as vtk-fixed-point and vtk-gpu always do.\n"
  "gpu-riemann|gpu-coupled|gpu-decoupled|gpu-piecewise: vtkOpenGLAdaptiveVolumeMapper, the\n"
  "same methods in GLSL on the OpenGL device (the piecewise one in double where the device\n"
  "has GL_ARB_gpu_shader_fp64, else in float); its image (--output .exr, --compare) holds\n"
  "the shader's float values, read back one channel per extra render.\n"
  "Steps (--step, --h0, --hmin, --hmax) are in voxel units within [0.001, 1000]; --threads 0\n"
  "(the default) uses every core, at most 1024; --frames at most 100000; --size at most\n"
  "16384x16384 (a common OpenGL limit; the float image then takes 4 GiB).\n"
  "--compare: per RGBA channel, the percentage of pixels whose error against REF.exr (a\n"
  "float image of the same size, e.g. --method reference) exceeds 0.01, 0.005, 0.001, over\n"
  "the pixels where either image is not transparent; in the report too.\n"
  "--clip: a clipping plane (normal, then a point on it, in the volume's world\n"
  "coordinates) keeping the side the normal points to; repeat for more planes.\n"
  "--crop: VTK's cropping region planes (the volume's coordinates); --crop-mode: which\n"
  "of the 27 regions are kept (default subvolume: the box between the planes).\n"
  "--blend maximum|minimum: the intensity projections (exact in avos's methods: the\n"
  "extremum of the trilinear field along the ray, not of samples). --blend additive|average:\n"
  "VTK's GPU mapper's meaning (opacity-weighted normalised scalar, summed, or averaged over\n"
  "the scalars in --average-range), integrated along the ray in avos's methods.\n"
  "--shade: gradient shading (VTK's ambient 0.1, diffuse 0.7, specular 0.2, power 10,\n"
  "the headlight), with the analytic gradient of the trilinear field in avos's methods\n"
  "(riemann, coupled, decoupled, piecewise within its tolerance, reference).\n"
  "--gradient-opacity: the property's gradient opacity, knots (G, V): the factor V at the\n"
  "gradient magnitude G in scalar units per world unit (VTK's mappers read G on their own\n"
  "axes: docs/GUIDE.md).\n";

struct Options
{
  std::string Input;
  std::string TF;
  avos::app::MethodSettings Settings;
  std::string Opacity;
  int Width = 800;
  int Height = 600;
  double Azimuth = 0.0;
  double Elevation = 0.0;
  double Zoom = 1.0;
  int Frames = 1;
  std::string Output;
  std::string Report;
  std::string Compare;
  std::vector<std::vector<double>> Clip; // normal and origin of each plane
  std::vector<double> Crop;              // empty: no cropping
  std::vector<double> AverageRange;      // empty: VTK's default (every scalar)
  int CropFlags = VTK_CROP_SUBVOLUME;
  int Blend = vtkVolumeMapper::COMPOSITE_BLEND;
  bool Shade = false;
  std::vector<double> GradientOpacity; // (G, V) pairs; empty: none
};

// "a,b,c" -> numbers; false unless exactly `count` finite numbers.
bool ParseList(const std::string& text, std::size_t count, std::vector<double>& values)
{
  values.clear();
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
  {
    std::istringstream number(item);
    double v = 0.0;
    if (!(number >> v) || !number.eof() || !std::isfinite(v))
    {
      return false;
    }
    values.push_back(v);
  }
  return values.size() == count;
}

bool ParseNumber(const std::string& text, double& value)
{
  std::istringstream in(text);
  in >> value;
  return !in.fail() && in.eof() && std::isfinite(value);
}

// Empty string on success, else what is wrong.
std::string Parse(int argc, char* argv[], Options& o)
{
  const std::map<std::string, double*> numbers = { { "--tolerance", &o.Settings.Tolerance },
    { "--step", &o.Settings.Step }, { "--h0", &o.Settings.H0 }, { "--hmin", &o.Settings.HMin },
    { "--hmax", &o.Settings.HMax }, { "--azimuth", &o.Azimuth }, { "--elevation", &o.Elevation },
    { "--zoom", &o.Zoom } };
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help")
    {
      return "help";
    }
    if (arg.rfind("--", 0) != 0)
    {
      if (!o.Input.empty())
      {
        return "more than one input: '" + o.Input + "' and '" + arg + "'";
      }
      o.Input = arg;
      continue;
    }
    if (arg == "--shade")
    {
      o.Shade = true;
      continue;
    }
    if (i + 1 >= argc)
    {
      return "option " + arg + " needs a value";
    }
    const std::string value = argv[++i];
    double number = 0.0;
    if (numbers.count(arg))
    {
      if (!ParseNumber(value, number))
      {
        return "option " + arg + " needs a finite number, not '" + value + "'";
      }
      *numbers.at(arg) = number;
    }
    else if (arg == "--frames" || arg == "--threads")
    {
      const bool frames = arg == "--frames";
      const double lowest = frames ? 1 : 0, highest = frames ? MaximumFrames : MaximumThreads;
      if (!ParseNumber(value, number) || number != std::floor(number) || number < lowest ||
        number > highest)
      {
        return "option " + arg + " needs a whole number in [" + std::to_string(int(lowest)) + ", " +
          std::to_string(int(highest)) + "]";
      }
      (arg == "--frames" ? o.Frames : o.Settings.Threads) = static_cast<int>(number);
    }
    else if (arg == "--size")
    {
      char x = 0;
      std::istringstream in(value);
      if (!(in >> o.Width >> x >> o.Height) || x != 'x' || o.Width < 1 || o.Height < 1 ||
        o.Width > MaximumSide || o.Height > MaximumSide)
      {
        return "--size needs WxH, each within [1, " + std::to_string(MaximumSide) +
          "], e.g. 800x600";
      }
    }
    else if (arg == "--tf")
    {
      o.TF = value;
    }
    else if (arg == "--method")
    {
      o.Settings.Method = value;
    }
    else if (arg == "--opacity")
    {
      o.Opacity = value;
    }
    else if (arg == "--output")
    {
      o.Output = value;
    }
    else if (arg == "--report")
    {
      o.Report = value;
    }
    else if (arg == "--compare")
    {
      o.Compare = value;
    }
    else if (arg == "--clip")
    {
      std::vector<double> plane;
      if (!ParseList(value, 6, plane) || (plane[0] == 0.0 && plane[1] == 0.0 && plane[2] == 0.0))
      {
        return "--clip needs NX,NY,NZ,OX,OY,OZ (a non-zero normal, a point)";
      }
      o.Clip.push_back(plane);
    }
    else if (arg == "--gradient-opacity")
    {
      const std::size_t count = std::count(value.begin(), value.end(), ',') + 1;
      if (count % 2 != 0 || !ParseList(value, count, o.GradientOpacity))
      {
        return "--gradient-opacity needs pairs G,V of finite numbers";
      }
    }
    else if (arg == "--average-range")
    {
      if (!ParseList(value, 2, o.AverageRange) || o.AverageRange[0] > o.AverageRange[1])
      {
        return "--average-range needs LO,HI with LO at most HI";
      }
    }
    else if (arg == "--crop")
    {
      if (!ParseList(value, 6, o.Crop) || o.Crop[0] > o.Crop[1] || o.Crop[2] > o.Crop[3] ||
        o.Crop[4] > o.Crop[5])
      {
        return "--crop needs X0,X1,Y0,Y1,Z0,Z1, each minimum at most its maximum";
      }
    }
    else if (arg == "--blend")
    {
      const std::map<std::string, int> modes = { { "composite", vtkVolumeMapper::COMPOSITE_BLEND },
        { "maximum", vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND },
        { "minimum", vtkVolumeMapper::MINIMUM_INTENSITY_BLEND },
        { "average", vtkVolumeMapper::AVERAGE_INTENSITY_BLEND },
        { "additive", vtkVolumeMapper::ADDITIVE_BLEND } };
      if (!modes.count(value))
      {
        return "--blend is composite, maximum, minimum, average or additive";
      }
      o.Blend = modes.at(value);
    }
    else if (arg == "--crop-mode")
    {
      const std::map<std::string, int> modes = { { "subvolume", VTK_CROP_SUBVOLUME },
        { "fence", VTK_CROP_FENCE }, { "inverted-fence", VTK_CROP_INVERTED_FENCE },
        { "cross", VTK_CROP_CROSS }, { "inverted-cross", VTK_CROP_INVERTED_CROSS } };
      if (!modes.count(value))
      {
        return "--crop-mode is subvolume, fence, inverted-fence, cross or inverted-cross";
      }
      o.CropFlags = modes.at(value);
    }
    else
    {
      return "unknown option " + arg;
    }
  }
  if (o.Input.empty())
  {
    return "no input";
  }
  const std::vector<std::string>& methods = avos::app::MethodSettings::Methods;
  if (std::find(methods.begin(), methods.end(), o.Settings.Method) == methods.end())
  {
    return "unknown method '" + o.Settings.Method + "'";
  }
  if (o.Opacity.empty())
  {
    o.Opacity = o.TF.empty() ? "vtk" : "extinction";
  }
  if (o.Opacity != "vtk" && o.Opacity != "extinction")
  {
    return "--opacity is extinction or vtk";
  }
  if (o.Settings.IsVTK())
  {
    o.Opacity = "vtk"; // VTK's mappers know no other model
  }
  o.Settings.VTKOpacity = o.Opacity == "vtk";
  if (!(o.Zoom > 0.0))
  {
    return "--zoom must be positive";
  }
  // The mapper's range (at most 1000 samples per voxel), checked before any
  // data is read.
  for (const auto& step :
    { std::make_pair("--step", o.Settings.Step), std::make_pair("--h0", o.Settings.H0),
      std::make_pair("--hmin", o.Settings.HMin), std::make_pair("--hmax", o.Settings.HMax) })
  {
    if (!(step.second >= vtkAdaptiveVolumeMapper::GetSmallestStep() &&
          step.second <= vtkAdaptiveVolumeMapper::GetLargestStep()))
    {
      std::ostringstream problem;
      problem << step.first << " must be within [" << vtkAdaptiveVolumeMapper::GetSmallestStep()
              << ", " << vtkAdaptiveVolumeMapper::GetLargestStep() << "] voxel units";
      return problem.str();
    }
  }
  if (!(o.Settings.HMin <= o.Settings.HMax))
  {
    return "--hmin must not exceed --hmax";
  }
  if (!(o.Settings.Tolerance > 0.0 && o.Settings.Tolerance <= 1.0))
  {
    return "--tolerance must be in (0, 1]";
  }
  return std::string();
}

// Prints the mapper's progress once a frame takes a second: on a terminal a
// line updated in place, with the time left estimated from the share of
// tiles done so far; into a log (stderr redirected) only the final line.
class ProgressPrinter : public vtkCommand
{
public:
  static ProgressPrinter* New() { return new ProgressPrinter; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    // 0 and 1 also come from the pipeline's own updates: only the ray
    // cast's reports in between are shown. A smaller fraction: a new frame.
    const double fraction = *static_cast<double*>(data);
    if (fraction < this->Last)
    {
      this->Timer->StartTimer();
    }
    this->Last = fraction;
    this->Timer->StopTimer();
    const double elapsed = this->Timer->GetElapsedTime();
    if (fraction >= 1.0 && this->Printed)
    {
      if (this->Terminal)
      {
        std::cerr << "\r" << std::string(48, ' ') << "\r" << std::flush;
      }
      else
      {
        std::cerr << "rendered a frame in " << std::fixed << std::setprecision(1) << elapsed << " s"
                  << std::defaultfloat << std::setprecision(6) << std::endl;
      }
      this->Printed = false;
    }
    else if (elapsed > 1.0 && fraction > 0.0 && fraction < 1.0)
    {
      if (this->Terminal)
      {
        const double left = elapsed * (1.0 - fraction) / fraction;
        std::cerr << "\rrendering " << std::setw(3) << static_cast<int>(100.0 * fraction)
                  << " %, about " << std::fixed << std::setprecision(0) << std::ceil(left)
                  << " s left  " << std::defaultfloat << std::setprecision(6) << std::flush;
      }
      this->Printed = true;
    }
  }

protected:
  ProgressPrinter() { this->Timer->StartTimer(); }

private:
  vtkNew<vtkTimerLog> Timer;
  const bool Terminal = isatty(STDERR_FILENO) != 0;
  double Last = 0.0;
  bool Printed = false;
};

// Ctrl-C: the first one aborts the frame being rendered (the mapper checks
// the render window about every 0.1 s) and the command exits with status 130
// without writing anything; a second one kills the process as usual.
volatile std::sig_atomic_t Interrupted = 0;

void OnInterrupt(int)
{
  Interrupted = 1;
  std::signal(SIGINT, SIG_DFL);
}

class InterruptCheck : public vtkCommand
{
public:
  static InterruptCheck* New() { return new InterruptCheck; }
  void Execute(vtkObject* caller, unsigned long, void*) override
  {
    if (Interrupted)
    {
      static_cast<vtkRenderWindow*>(caller)->SetAbortRender(1);
    }
  }
};

std::string JsonString(const std::string& s)
{
  std::string out = "\"";
  for (char c : s)
  {
    if (c == '"' || c == '\\')
    {
      out += '\\';
    }
    out += c;
  }
  return out + "\"";
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
  if (o.Settings.Threads > 0)
  {
    vtkSMPTools::Initialize(o.Settings.Threads);
  }

  std::string error;
  vtkSmartPointer<vtkAlgorithm> reader = app::MakeReader(o.Input, error);
  vtkImageData* image = reader ? app::ReadVolume(reader, o.Input, error) : nullptr;
  if (!image)
  {
    std::cerr << "error: " << error << "\n";
    return EXIT_FAILURE;
  }
  const double voxel = app::VoxelLength(image);

  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  if (!o.TF.empty())
  {
    if (!app::LoadTransferFunction(o.TF, o.Settings.VTKOpacity, voxel, property))
    {
      std::cerr << "error: cannot use the transfer function '" << o.TF << "'\n";
      return EXIT_FAILURE;
    }
  }
  else
  {
    app::DefaultTransferFunction(image->GetPointData()->GetScalars()->GetRange(0), voxel, property);
  }

  property->SetShade(o.Shade);
  if (!o.GradientOpacity.empty())
  {
    vtkNew<vtkPiecewiseFunction> gradient;
    for (std::size_t k = 0; k + 1 < o.GradientOpacity.size(); k += 2)
    {
      gradient->AddPoint(o.GradientOpacity[k], o.GradientOpacity[k + 1]);
    }
    property->SetGradientOpacity(gradient);
  }

  vtkSmartPointer<vtkVolumeMapper> mapper = app::MakeMapper(o.Settings, voxel);
  auto* adaptive = vtkAdaptiveVolumeMapper::SafeDownCast(mapper);
  mapper->SetBlendMode(o.Blend);
  if (!o.AverageRange.empty())
  {
    mapper->SetAverageIPScalarRange(o.AverageRange[0], o.AverageRange[1]);
  }
  for (const std::vector<double>& p : o.Clip)
  {
    vtkNew<vtkPlane> plane;
    plane->SetNormal(p[0], p[1], p[2]);
    plane->SetOrigin(p[3], p[4], p[5]);
    mapper->AddClippingPlane(plane);
  }
  if (!o.Crop.empty())
  {
    mapper->SetCropping(1);
    mapper->SetCroppingRegionPlanes(o.Crop.data());
    mapper->SetCroppingRegionFlags(o.CropFlags);
  }
  app::RenderSession session(reader, property, o.Width, o.Height, o.Azimuth, o.Elevation, o.Zoom);
  vtkNew<ProgressPrinter> progress;
  vtkNew<InterruptCheck> interruptCheck;
  session.GetRenderer()->GetRenderWindow()->AddObserver(
    vtkCommand::AbortCheckEvent, interruptCheck);
  std::signal(SIGINT, OnInterrupt);
  const std::vector<double> times = session.Render(mapper, o.Frames, progress);
  std::signal(SIGINT, SIG_DFL);
  if (Interrupted)
  {
    std::cerr << "\ninterrupted: the render was aborted, nothing written\n";
    return 130;
  }
  if (times.empty())
  {
    std::cerr << "error: the render failed (see the message above)\n";
    return EXIT_FAILURE;
  }
  const std::vector<float> rgba = session.Image();
  if (!o.Output.empty() && !app::WriteImage(o.Output, o.Width, o.Height, rgba))
  {
    return EXIT_FAILURE;
  }

  app::ImageError comparison;
  if (!o.Compare.empty())
  {
    const std::vector<float> reference = app::ReadImage(o.Compare, o.Width, o.Height);
    if (reference.empty())
    {
      return EXIT_FAILURE;
    }
    comparison = app::Compare(rgba, reference, o.Width, o.Height);
    std::cout << "error against " << o.Compare << " over " << comparison.Pixels
              << " pixels, % exceeding (R G B A):";
    for (int t = 0; t < 3; ++t)
    {
      std::cout << std::defaultfloat << "  " << app::ImageError::Thresholds[t] << ":" << std::fixed;
      for (int ch = 0; ch < 4; ++ch)
      {
        std::cout << " " << std::setprecision(3) << comparison.Exceeding[t][ch];
      }
    }
    std::cout << std::defaultfloat << std::setprecision(6) << "\n  PSNR (dB):";
    for (int ch = 0; ch < 4; ++ch)
    {
      std::cout << " " << comparison.PSNR[ch];
    }
    std::cout << "  SSIM:";
    for (int ch = 0; ch < 4; ++ch)
    {
      std::cout << " " << comparison.SSIM[ch];
    }
    std::cout << "\n";
  }

  const double median = app::Median(times);
  const double fastest = *std::min_element(times.begin(), times.end());
  std::cout << o.Settings.Method << ": " << o.Width << "x" << o.Height << ", median " << median
            << " s, min " << fastest << " s over " << o.Frames << " frame(s)";
  if (adaptive)
  {
    std::cout << ", " << adaptive->GetRaysCast() << " rays, " << adaptive->GetMeanSamplesPerRay()
              << " samples per ray";
    if (adaptive->GetMeanPiecesPerRay() > 0.0)
    {
      std::cout << " (" << adaptive->GetMeanCellsPerRay() << " cells, "
                << adaptive->GetMeanPiecesPerRay() << " pieces)";
    }
  }
  std::cout << "\n";

  if (!o.Report.empty())
  {
    app::AtomicFile file(o.Report);
    std::ofstream report(file.Path());
    report << std::setprecision(10) << "{\n"
           << "  \"input\": " << JsonString(o.Input) << ",\n"
           << "  \"transfer_function\": " << (o.TF.empty() ? "null" : JsonString(o.TF)) << ",\n"
           << "  \"method\": " << JsonString(o.Settings.Method) << ",\n"
           << "  \"opacity_model\": " << JsonString(o.Opacity) << ",\n"
           << "  \"shade\": " << (o.Shade ? "true" : "false") << ",\n"
           << "  \"gradient_opacity\": " << (o.GradientOpacity.empty() ? "false" : "true") << ",\n"
           << "  \"parameters\": {\"tolerance\": " << o.Settings.Tolerance
           << ", \"step\": " << o.Settings.Step << ", \"h0\": " << o.Settings.H0
           << ", \"hmin\": " << o.Settings.HMin << ", \"hmax\": " << o.Settings.HMax
           << ", \"azimuth\": " << o.Azimuth << ", \"elevation\": " << o.Elevation
           << ", \"zoom\": " << o.Zoom
           << ", \"threads\": " << vtkSMPTools::GetEstimatedNumberOfThreads() << "},\n"
           << "  \"width\": " << o.Width << ",\n  \"height\": " << o.Height << ",\n"
           << "  \"frames\": " << o.Frames << ",\n"
           << "  \"median_seconds\": " << median << ",\n  \"min_seconds\": " << fastest << ",\n";
    if (!o.Compare.empty())
    {
      report << "  \"compare\": {\"reference\": " << JsonString(o.Compare)
             << ", \"pixels\": " << comparison.Pixels << ", \"max_error_rgba\": ["
             << comparison.Maximum[0] << ", " << comparison.Maximum[1] << ", "
             << comparison.Maximum[2] << ", " << comparison.Maximum[3] << "]";
      for (int t = 0; t < 3; ++t)
      {
        report << ", \"percent_above_" << app::ImageError::Thresholds[t] << "\": ["
               << comparison.Exceeding[t][0] << ", " << comparison.Exceeding[t][1] << ", "
               << comparison.Exceeding[t][2] << ", " << comparison.Exceeding[t][3] << "]";
      }
      auto list = [&](const double* v)
      {
        std::ostringstream out;
        out << "[";
        for (int ch = 0; ch < 4; ++ch)
        {
          // JSON has no infinity: identical channels give null.
          out << (ch ? ", " : "") << (std::isfinite(v[ch]) ? std::to_string(v[ch]) : "null");
        }
        return out.str() + "]";
      };
      report << ", \"psnr_rgba\": " << list(comparison.PSNR)
             << ", \"ssim_rgba\": " << list(comparison.SSIM) << "},\n";
    }
    if (adaptive)
    {
      report << "  \"rays_cast\": " << adaptive->GetRaysCast() << ",\n"
             << "  \"mean_samples_per_ray\": " << adaptive->GetMeanSamplesPerRay() << ",\n"
             << "  \"max_samples_per_ray\": " << adaptive->GetMaximumSamplesPerRay() << ",\n"
             << "  \"rejected_steps\": " << adaptive->GetRejectedSteps() << ",\n"
             << "  \"mean_cells_per_ray\": " << adaptive->GetMeanCellsPerRay() << ",\n"
             << "  \"mean_pieces_per_ray\": " << adaptive->GetMeanPiecesPerRay() << "\n";
    }
    else
    {
      report << "  \"rays_cast\": null,\n  \"mean_samples_per_ray\": null\n";
    }
    report << "}\n";
    report.close();
    if (!report)
    {
      std::cerr << "error: cannot write '" << o.Report << "'\n";
      return EXIT_FAILURE;
    }
    if (!file.Commit())
    {
      return EXIT_FAILURE;
    }
  }
  return EXIT_SUCCESS;
}
