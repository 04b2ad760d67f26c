// avos-render: render a volume with vtkAdaptiveVolumeMapper (or, side by
// side, with VTK's own mappers) to an image and a JSON report.
//
//   avos-render INPUT [--tf FILE.tf1d] [--method riemann|coupled|decoupled|reference|
//               vtk-fixed-point|vtk-gpu] [--opacity extinction|vtk] [--tolerance E]
//               [--step H] [--h0 H] [--hmin H] [--hmax H] [--size WxH] [--azimuth DEG]
//               [--elevation DEG] [--zoom Z] [--frames N] [--threads N]
//               [--output FILE.png|FILE.exr] [--report FILE.json] [--compare REF.exr]
//
// INPUT: .vti, .mhd/.mha, .nrrd/.nhdr, a volvis .raw name (Name.1.XxYxZ.raw)
// or a DICOM folder. Runs in an off-screen window (under Xvfb on a headless
// machine: xvfb-run -a avos-render ...).
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkDICOMImageReader.h"
#include "vtkDataArray.h"
#include "vtkFixedPointRayCastImage.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkFloatArray.h"
#include "vtkGPUVolumeRayCastMapper.h"
#include "vtkImageData.h"
#include "vtkMetaImageReader.h"
#include "vtkNew.h"
#include "vtkNrrdReader.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTimerLog.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkVolvisRawReader.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLImageDataReader.h"

#include <vtksys/SystemTools.hxx>

#include <OpenImageIO/imageio.h>

#include "avos/numerics/ImageMetrics.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace
{
const char* Usage =
  "usage: avos-render INPUT [--tf FILE.tf1d]\n"
  "         [--method riemann|coupled|decoupled|reference|vtk-fixed-point|vtk-gpu]\n"
  "         [--opacity extinction|vtk] [--tolerance E] [--step H] [--h0 H] [--hmin H]\n"
  "         [--hmax H] [--size WxH] [--azimuth DEG] [--elevation DEG] [--zoom Z]\n"
  "         [--frames N] [--threads N] [--output FILE.png|FILE.exr] [--report FILE.json]\n"
  "         [--compare REF.exr]\n"
  "INPUT: .vti, .mhd/.mha, .nrrd/.nhdr, volvis .raw (Name.1.XxYxZ.raw) or a DICOM folder.\n"
  "--tf gives the paper's extinction semantics (tau per voxel unit); without it a\n"
  "transfer function is derived from the data range, in VTK's semantics.\n"
  "--opacity vtk renders the TF converted to VTK's semantics (alpha = 1 - exp(-tau) per\n"
  "voxel unit at the knots), as vtk-fixed-point and vtk-gpu always do.\n"
  "--compare: per RGBA channel, the percentage of pixels whose error against REF.exr (a\n"
  "float image of the same size, e.g. --method reference) exceeds 0.01, 0.005, 0.001, over\n"
  "the pixels where either image is not transparent; in the report too.\n";

struct Options
{
  std::string Input;
  std::string TF;
  std::string Method = "coupled";
  std::string Opacity;
  double Tolerance = 0.01;
  double Step = 0.5;
  double H0 = 0.5;
  double HMin = 0.1;
  double HMax = 2.0;
  int Width = 800;
  int Height = 600;
  double Azimuth = 0.0;
  double Elevation = 0.0;
  double Zoom = 1.0;
  int Frames = 1;
  int Threads = 0;
  std::string Output;
  std::string Report;
  std::string Compare;
};

bool ParseNumber(const std::string& text, double& value)
{
  std::istringstream in(text);
  in >> value;
  return !in.fail() && in.eof() && std::isfinite(value);
}

// Empty string on success, else what is wrong.
std::string Parse(int argc, char* argv[], Options& o)
{
  const std::map<std::string, double*> numbers = { { "--tolerance", &o.Tolerance },
    { "--step", &o.Step }, { "--h0", &o.H0 }, { "--hmin", &o.HMin }, { "--hmax", &o.HMax },
    { "--azimuth", &o.Azimuth }, { "--elevation", &o.Elevation }, { "--zoom", &o.Zoom } };
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
      if (!ParseNumber(value, number) || number != std::floor(number) || number < 0 ||
        (arg == "--frames" && number < 1) || number > 100000)
      {
        return "option " + arg + " needs a whole number" + (arg == "--frames" ? " >= 1" : "");
      }
      (arg == "--frames" ? o.Frames : o.Threads) = static_cast<int>(number);
    }
    else if (arg == "--size")
    {
      char x = 0;
      std::istringstream in(value);
      if (!(in >> o.Width >> x >> o.Height) || x != 'x' || o.Width < 1 || o.Height < 1 ||
        o.Width > 16384 || o.Height > 16384)
      {
        return "--size needs WxH, e.g. 800x600";
      }
    }
    else if (arg == "--tf")
    {
      o.TF = value;
    }
    else if (arg == "--method")
    {
      o.Method = value;
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
    else
    {
      return "unknown option " + arg;
    }
  }
  if (o.Input.empty())
  {
    return "no input";
  }
  static const char* methods[] = { "riemann", "coupled", "decoupled", "reference",
    "vtk-fixed-point", "vtk-gpu" };
  if (std::find(std::begin(methods), std::end(methods), o.Method) == std::end(methods))
  {
    return "unknown method '" + o.Method + "'";
  }
  if (o.Opacity.empty())
  {
    o.Opacity = o.TF.empty() ? "vtk" : "extinction";
  }
  if (o.Opacity != "vtk" && o.Opacity != "extinction")
  {
    return "--opacity is extinction or vtk";
  }
  if (o.Method.rfind("vtk-", 0) == 0)
  {
    o.Opacity = "vtk"; // VTK's mappers know no other model
  }
  if (!(o.Zoom > 0.0))
  {
    return "--zoom must be positive";
  }
  return std::string();
}

// The reader for INPUT, by its extension (a folder: DICOM).
vtkSmartPointer<vtkAlgorithm> MakeReader(const std::string& path, std::string& error)
{
  if (vtksys::SystemTools::FileIsDirectory(path))
  {
    auto reader = vtkSmartPointer<vtkDICOMImageReader>::New();
    reader->SetDirectoryName(path.c_str());
    return reader;
  }
  if (!vtksys::SystemTools::FileExists(path))
  {
    error = "cannot read '" + path + "': no such file or folder";
    return nullptr;
  }
  const std::string ext =
    vtksys::SystemTools::LowerCase(vtksys::SystemTools::GetFilenameLastExtension(path));
  if (ext == ".vti")
  {
    auto reader = vtkSmartPointer<vtkXMLImageDataReader>::New();
    reader->SetFileName(path.c_str());
    return reader;
  }
  if (ext == ".mhd" || ext == ".mha")
  {
    auto reader = vtkSmartPointer<vtkMetaImageReader>::New();
    reader->SetFileName(path.c_str());
    return reader;
  }
  if (ext == ".nrrd" || ext == ".nhdr")
  {
    auto reader = vtkSmartPointer<vtkNrrdReader>::New();
    reader->SetFileName(path.c_str());
    return reader;
  }
  if (ext == ".raw")
  {
    auto reader = vtkSmartPointer<vtkVolvisRawReader>::New();
    reader->SetFileName(path.c_str());
    return reader;
  }
  error =
    "unknown volume format '" + ext + "' (.vti, .mhd, .mha, .nrrd, .nhdr, .raw, DICOM folder)";
  return nullptr;
}

// A transfer function from the data range, in VTK's semantics: transparent
// below 20 % of the range, then a ramp to an alpha of 0.15 per voxel.
void DefaultTransferFunction(const double range[2], double voxel, vtkVolumeProperty* property)
{
  const double lo = range[0], span = std::max(range[1] - range[0], 1e-12);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(lo, 0.1, 0.2, 0.6);
  color->AddRGBPoint(lo + 0.4 * span, 0.9, 0.4, 0.1);
  color->AddRGBPoint(lo + 0.7 * span, 1.0, 0.85, 0.5);
  color->AddRGBPoint(lo + span, 1.0, 1.0, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(lo, 0.0);
  opacity->AddPoint(lo + 0.2 * span, 0.0);
  opacity->AddPoint(lo + span, 0.15);
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(voxel);
}

double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// RGBA float pixels, row 0 at the bottom as VTK stores them. EXR keeps the
// four float channels (RGB = I premultiplied, A = 1 - T); PNG gets RGB over
// the black background, 8 bits.
bool WriteImage(const std::string& path, int width, int height, const std::vector<float>& rgba)
{
  const std::string ext =
    vtksys::SystemTools::LowerCase(vtksys::SystemTools::GetFilenameLastExtension(path));
  const bool exr = ext == ".exr";
  if (!exr && ext != ".png")
  {
    std::cerr << "error: --output must end in .png or .exr\n";
    return false;
  }
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
  {
    std::cerr << "error: cannot write '" << path << "': " << OIIO::geterror() << "\n";
    return false;
  }
  const int channels = exr ? 4 : 3;
  OIIO::ImageSpec spec(
    width, height, channels, exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec))
  {
    std::cerr << "error: cannot write '" << path << "': " << out->geterror() << "\n";
    return false;
  }
  // Image files store the top row first.
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(width) * 4 * sizeof(float);
  const char* last = reinterpret_cast<const char*>(rgba.data()) + row * (height - 1);
  const bool ok = out->write_image(OIIO::TypeDesc::FLOAT, last, 4 * sizeof(float), -row);
  out->close();
  if (!ok)
  {
    std::cerr << "error: writing '" << path << "' failed\n";
  }
  return ok;
}

// A float RGBA image of the given size, row 0 at the bottom. Empty on error.
std::vector<float> ReadImage(const std::string& path, int width, int height)
{
  auto in = OIIO::ImageInput::open(path);
  if (!in)
  {
    std::cerr << "error: cannot read '" << path << "': " << OIIO::geterror() << "\n";
    return {};
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width != width || spec.height != height || spec.nchannels != 4)
  {
    std::cerr << "error: '" << path << "' is " << spec.width << "x" << spec.height << " with "
              << spec.nchannels << " channels, not " << width << "x" << height << " RGBA\n";
    return {};
  }
  std::vector<float> rgba(4 * static_cast<std::size_t>(width) * height);
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(width) * 4 * sizeof(float);
  char* last = reinterpret_cast<char*>(rgba.data()) + row * (height - 1);
  if (!in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, last, OIIO::AutoStride, -row))
  {
    std::cerr << "error: cannot read '" << path << "': " << in->geterror() << "\n";
    return {};
  }
  return rgba;
}

// Percentages of covered pixels whose error exceeds each threshold, per
// channel: [threshold][channel].
struct Comparison
{
  static constexpr double Thresholds[3] = { 0.01, 0.005, 0.001 };
  double Exceeding[3][4] = {};
  double MaximumError[4] = {};
  long Pixels = 0;
  double PSNR[4] = {}; // dB, whole image
  double SSIM[4] = {};
};

Comparison Compare(
  const std::vector<float>& image, const std::vector<float>& reference, int width, int height)
{
  Comparison c;
  for (int ch = 0; ch < 4; ++ch)
  {
    const avos::numerics::ImageChannel<float> a{ image.data(), width, height, 4, ch };
    const avos::numerics::ImageChannel<float> b{ reference.data(), width, height, 4, ch };
    c.PSNR[ch] = avos::numerics::PSNR(a, b);
    c.SSIM[ch] = avos::numerics::SSIM(a, b);
  }
  long counts[3][4] = {};
  for (std::size_t p = 0; p < image.size(); p += 4)
  {
    if (!(image[p + 3] > 1e-6f || reference[p + 3] > 1e-6f))
    {
      continue;
    }
    ++c.Pixels;
    for (int ch = 0; ch < 4; ++ch)
    {
      const double e = std::abs(double(image[p + ch]) - double(reference[p + ch]));
      c.MaximumError[ch] = std::max(c.MaximumError[ch], e);
      for (int t = 0; t < 3; ++t)
      {
        counts[t][ch] += e > Comparison::Thresholds[t];
      }
    }
  }
  for (int t = 0; t < 3; ++t)
  {
    for (int ch = 0; ch < 4; ++ch)
    {
      c.Exceeding[t][ch] = c.Pixels ? 100.0 * counts[t][ch] / c.Pixels : 0.0;
    }
  }
  return c;
}

// Prints the mapper's progress on the terminal once a render takes a second.
class ProgressPrinter : public vtkCommand
{
public:
  static ProgressPrinter* New() { return new ProgressPrinter; }
  void Start()
  {
    this->Timer->StartTimer();
    this->Printed = false;
  }
  void Finish()
  {
    if (this->Printed)
    {
      std::cerr << "\r" << std::string(24, ' ') << "\r" << std::flush;
    }
  }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    // 0 and 1 also come from the pipeline's own updates: only the ray
    // cast's bands in between are shown.
    const double fraction = *static_cast<double*>(data);
    this->Timer->StopTimer();
    if (this->Timer->GetElapsedTime() > 1.0 && fraction > 0.0 && fraction < 1.0)
    {
      std::cerr << "\rrendering " << std::setw(3) << static_cast<int>(100.0 * fraction) << " %"
                << std::flush;
      this->Printed = true;
    }
  }

private:
  vtkNew<vtkTimerLog> Timer;
  bool Printed = false;
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
  const std::string problem = Parse(argc, argv, o);
  if (problem == "help")
  {
    std::cout << Usage;
    return EXIT_SUCCESS;
  }
  if (!problem.empty())
  {
    std::cerr << "error: " << problem << "\n" << Usage;
    return 2;
  }
  if (o.Threads > 0)
  {
    vtkSMPTools::Initialize(o.Threads);
  }

  std::string error;
  vtkSmartPointer<vtkAlgorithm> reader = MakeReader(o.Input, error);
  if (!reader)
  {
    std::cerr << "error: " << error << "\n";
    return EXIT_FAILURE;
  }
  reader->Update();
  vtkImageData* image = vtkImageData::SafeDownCast(reader->GetOutputDataObject(0));
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  if (!scalars || image->GetNumberOfPoints() < 8)
  {
    std::cerr << "error: '" << o.Input << "' holds no volume with point scalars\n";
    return EXIT_FAILURE;
  }
  const double* spacing = image->GetSpacing();
  const double voxel =
    std::min({ std::abs(spacing[0]), std::abs(spacing[1]), std::abs(spacing[2]) });

  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  if (!o.TF.empty())
  {
    vtkNew<vtkTransferFunction1DReader> tf;
    tf->SetFileName(o.TF.c_str());
    if (o.Opacity == "vtk")
    {
      tf->SetOpacityModelToVTK();
      tf->SetUnitDistance(voxel);
    }
    if (!tf->FillVolumeProperty(property))
    {
      std::cerr << "error: cannot use the transfer function '" << o.TF << "'\n";
      return EXIT_FAILURE;
    }
  }
  else
  {
    DefaultTransferFunction(scalars->GetRange(0), voxel, property);
  }

  vtkSmartPointer<vtkVolumeMapper> mapper;
  vtkAdaptiveVolumeMapper* adaptive = nullptr;
  if (o.Method == "vtk-fixed-point")
  {
    auto fixedPoint = vtkSmartPointer<vtkFixedPointVolumeRayCastMapper>::New();
    fixedPoint->SetSampleDistance(o.Step * voxel);
    fixedPoint->SetAutoAdjustSampleDistances(0);
    fixedPoint->SetImageSampleDistance(1.0);
    if (o.Threads > 0)
    {
      fixedPoint->SetNumberOfThreads(o.Threads);
    }
    mapper = fixedPoint;
  }
  else if (o.Method == "vtk-gpu")
  {
    auto gpu = vtkSmartPointer<vtkGPUVolumeRayCastMapper>::New();
    gpu->SetSampleDistance(o.Step * voxel);
    gpu->SetAutoAdjustSampleDistances(0);
    gpu->SetUseJittering(0);
    mapper = gpu;
  }
  else
  {
    auto ours = vtkSmartPointer<vtkAdaptiveVolumeMapper>::New();
    const std::map<std::string, int> methods = { { "riemann", vtkAdaptiveVolumeMapper::RIEMANN },
      { "coupled", vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED },
      { "decoupled", vtkAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED },
      { "reference", vtkAdaptiveVolumeMapper::REFERENCE } };
    ours->SetIntegrationMethod(methods.at(o.Method));
    ours->SetOpacityModel(o.Opacity == "vtk" ? vtkAdaptiveVolumeMapper::VTK_OPACITY
                                             : vtkAdaptiveVolumeMapper::EXTINCTION_OPACITY);
    ours->SetTolerance(o.Tolerance);
    ours->SetSampleDistance(o.Step);
    ours->SetInitialStep(o.H0);
    ours->SetMinimumStep(o.HMin);
    ours->SetMaximumStep(o.HMax);
    adaptive = ours;
    mapper = ours;
  }
  mapper->SetInputConnection(reader->GetOutputPort());
  vtkNew<ProgressPrinter> progress;
  mapper->AddObserver(vtkCommand::ProgressEvent, progress);

  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(0.0, 0.0, 0.0);
  renderer->AddVolume(volume);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(o.Width, o.Height);
  window->SetMultiSamples(0);
  window->SetAlphaBitPlanes(1);
  window->AddRenderer(renderer);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Azimuth(o.Azimuth);
  renderer->GetActiveCamera()->Elevation(o.Elevation);
  renderer->GetActiveCamera()->OrthogonalizeViewUp();
  renderer->GetActiveCamera()->Zoom(o.Zoom);
  renderer->ResetCameraClippingRange();

  // Every frame is a full render: the mapper is marked modified so that
  // vtkAdaptiveVolumeMapper does not reuse its last image.
  std::vector<double> times;
  vtkNew<vtkTimerLog> timer;
  for (int frame = 0; frame < o.Frames; ++frame)
  {
    mapper->Modified();
    progress->Start();
    timer->StartTimer();
    window->Render();
    timer->StopTimer();
    progress->Finish();
    times.push_back(timer->GetElapsedTime());
    if (adaptive && adaptive->GetRenderedImage()->GetNumberOfPoints() == 0)
    {
      std::cerr << "error: the render failed (see the message above)\n";
      return EXIT_FAILURE;
    }
  }

  // The image: the mapper's float RGBA, or the window's pixels for VTK's.
  std::vector<float> rgba(4 * static_cast<std::size_t>(o.Width) * o.Height, 0.0f);
  if (adaptive)
  {
    auto* pixels =
      vtkFloatArray::SafeDownCast(adaptive->GetRenderedImage()->GetPointData()->GetScalars());
    std::copy(pixels->GetPointer(0), pixels->GetPointer(0) + rgba.size(), rgba.begin());
  }
  else if (auto* fixedPoint = vtkFixedPointVolumeRayCastMapper::SafeDownCast(mapper))
  {
    // Its own 15-bit image, finer than the window's 8 bits.
    vtkFixedPointRayCastImage* cast = fixedPoint->GetRayCastImage();
    const int* memory = cast->GetImageMemorySize();
    const int* used = cast->GetImageInUseSize();
    const int* origin = cast->GetImageOrigin();
    const unsigned short* pixels = cast->GetImage();
    for (int y = 0; y < used[1]; ++y)
    {
      for (int x = 0; x < used[0]; ++x)
      {
        const int vx = x + origin[0], vy = y + origin[1];
        if (vx < 0 || vy < 0 || vx >= o.Width || vy >= o.Height)
        {
          continue;
        }
        for (int c = 0; c < 4; ++c)
        {
          rgba[4 * (static_cast<std::size_t>(vy) * o.Width + vx) + c] =
            pixels[4 * (static_cast<std::size_t>(y) * memory[0] + x) + c] / 32767.0f;
        }
      }
    }
  }
  else
  {
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->SetInputBufferTypeToRGBA();
    grab->ReadFrontBufferOff();
    grab->Update();
    vtkDataArray* pixels = grab->GetOutput()->GetPointData()->GetScalars();
    for (std::size_t i = 0; i < rgba.size(); ++i)
    {
      rgba[i] =
        static_cast<float>(pixels->GetComponent(static_cast<vtkIdType>(i / 4), i % 4) / 255.0);
    }
  }
  if (!o.Output.empty() && !WriteImage(o.Output, o.Width, o.Height, rgba))
  {
    return EXIT_FAILURE;
  }

  Comparison comparison;
  if (!o.Compare.empty())
  {
    const std::vector<float> reference = ReadImage(o.Compare, o.Width, o.Height);
    if (reference.empty())
    {
      return EXIT_FAILURE;
    }
    comparison = Compare(rgba, reference, o.Width, o.Height);
    std::cout << "error against " << o.Compare << " over " << comparison.Pixels
              << " pixels, % exceeding (R G B A):";
    for (int t = 0; t < 3; ++t)
    {
      std::cout << std::defaultfloat << "  " << Comparison::Thresholds[t] << ":" << std::fixed;
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

  const double median = Median(times);
  const double fastest = *std::min_element(times.begin(), times.end());
  std::cout << o.Method << ": " << o.Width << "x" << o.Height << ", median " << median << " s, min "
            << fastest << " s over " << o.Frames << " frame(s)";
  if (adaptive)
  {
    std::cout << ", " << adaptive->GetRaysCast() << " rays, " << adaptive->GetMeanSamplesPerRay()
              << " samples per ray";
  }
  std::cout << "\n";

  if (!o.Report.empty())
  {
    std::ofstream report(o.Report);
    report << std::setprecision(10) << "{\n"
           << "  \"input\": " << JsonString(o.Input) << ",\n"
           << "  \"transfer_function\": " << (o.TF.empty() ? "null" : JsonString(o.TF)) << ",\n"
           << "  \"method\": " << JsonString(o.Method) << ",\n"
           << "  \"opacity_model\": " << JsonString(o.Opacity) << ",\n"
           << "  \"parameters\": {\"tolerance\": " << o.Tolerance << ", \"step\": " << o.Step
           << ", \"h0\": " << o.H0 << ", \"hmin\": " << o.HMin << ", \"hmax\": " << o.HMax
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
             << comparison.MaximumError[0] << ", " << comparison.MaximumError[1] << ", "
             << comparison.MaximumError[2] << ", " << comparison.MaximumError[3] << "]";
      for (int t = 0; t < 3; ++t)
      {
        report << ", \"percent_above_" << Comparison::Thresholds[t] << "\": ["
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
             << "  \"rejected_steps\": " << adaptive->GetRejectedSteps() << "\n";
    }
    else
    {
      report << "  \"rays_cast\": null,\n  \"mean_samples_per_ray\": null\n";
    }
    report << "}\n";
    if (!report)
    {
      std::cerr << "error: cannot write '" << o.Report << "'\n";
      return EXIT_FAILURE;
    }
  }
  return EXIT_SUCCESS;
}
