#include "avosRenderSession.h"

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
#include "vtkOpenGLAdaptiveVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkVolvisRawReader.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLImageDataReader.h"

#include <vtksys/SystemTools.hxx>

#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include "avos/numerics/ImageMetrics.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace avos
{
namespace app
{

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
  auto named = [&](auto reader)
  {
    reader->SetFileName(path.c_str());
    return vtkSmartPointer<vtkAlgorithm>(reader);
  };
  if (ext == ".vti")
  {
    return named(vtkSmartPointer<vtkXMLImageDataReader>::New());
  }
  if (ext == ".mhd" || ext == ".mha")
  {
    return named(vtkSmartPointer<vtkMetaImageReader>::New());
  }
  if (ext == ".nrrd" || ext == ".nhdr")
  {
    return named(vtkSmartPointer<vtkNrrdReader>::New());
  }
  if (ext == ".raw")
  {
    return named(vtkSmartPointer<vtkVolvisRawReader>::New());
  }
  error =
    "unknown volume format '" + ext + "' (.vti, .mhd, .mha, .nrrd, .nhdr, .raw, DICOM folder)";
  return nullptr;
}

vtkImageData* ReadVolume(vtkAlgorithm* reader, const std::string& path, std::string& error)
{
  reader->Update();
  vtkImageData* image = vtkImageData::SafeDownCast(reader->GetOutputDataObject(0));
  if (!image || !image->GetPointData()->GetScalars() || image->GetNumberOfPoints() < 8)
  {
    error = "'" + path + "' holds no volume with point scalars";
    return nullptr;
  }
  return image;
}

double VoxelLength(vtkImageData* volume)
{
  const double* spacing = volume->GetSpacing();
  return std::min({ std::abs(spacing[0]), std::abs(spacing[1]), std::abs(spacing[2]) });
}

bool LoadTransferFunction(
  const std::string& path, bool vtkSemantics, double voxel, vtkVolumeProperty* property)
{
  vtkNew<vtkTransferFunction1DReader> tf;
  tf->SetFileName(path.c_str());
  if (vtkSemantics)
  {
    tf->SetOpacityModelToVTK();
    tf->SetUnitDistance(voxel);
  }
  return tf->FillVolumeProperty(property);
}

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

const std::vector<std::string> MethodSettings::Methods = { "riemann", "coupled", "decoupled",
  "piecewise", "reference", "vtk-fixed-point", "vtk-gpu", "gpu-riemann", "gpu-coupled",
  "gpu-decoupled", "gpu-piecewise" };

std::string MethodSettings::Label() const
{
  std::ostringstream out;
  out << this->Method;
  if (this->Method == "coupled" || this->Method == "decoupled" || this->Method == "gpu-coupled" ||
    this->Method == "gpu-decoupled")
  {
    out << " eps " << this->Tolerance << " (hmin " << this->HMin << ", hmax " << this->HMax << ")";
  }
  else if (this->Method == "piecewise" || this->Method == "gpu-piecewise")
  {
    out << " eps " << this->Tolerance;
  }
  else if (this->Method != "reference")
  {
    out << " h " << this->Step;
  }
  return out.str();
}

vtkSmartPointer<vtkVolumeMapper> MakeMapper(const MethodSettings& settings, double voxel)
{
  if (settings.Method == "vtk-fixed-point")
  {
    auto fixedPoint = vtkSmartPointer<vtkFixedPointVolumeRayCastMapper>::New();
    fixedPoint->SetSampleDistance(settings.Step * voxel);
    fixedPoint->SetAutoAdjustSampleDistances(0);
    fixedPoint->SetImageSampleDistance(1.0);
    if (settings.Threads > 0)
    {
      fixedPoint->SetNumberOfThreads(settings.Threads);
    }
    return fixedPoint;
  }
  if (settings.Method == "vtk-gpu")
  {
    auto gpu = vtkSmartPointer<vtkGPUVolumeRayCastMapper>::New();
    gpu->SetSampleDistance(settings.Step * voxel);
    gpu->SetAutoAdjustSampleDistances(0);
    gpu->SetUseJittering(0);
    return gpu;
  }
  const std::map<std::string, int> gpuMethods = { { "gpu-riemann",
                                                    vtkOpenGLAdaptiveVolumeMapper::RIEMANN },
    { "gpu-coupled", vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_COUPLED },
    { "gpu-decoupled", vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED },
    { "gpu-piecewise", vtkOpenGLAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE } };
  const auto gpuMethod = gpuMethods.find(settings.Method);
  if (gpuMethod != gpuMethods.end())
  {
    auto gpu = vtkSmartPointer<vtkOpenGLAdaptiveVolumeMapper>::New();
    gpu->SetIntegrationMethod(gpuMethod->second);
    gpu->SetOpacityModel(settings.VTKOpacity ? vtkOpenGLAdaptiveVolumeMapper::VTK_OPACITY
                                             : vtkOpenGLAdaptiveVolumeMapper::EXTINCTION_OPACITY);
    gpu->SetTolerance(settings.Tolerance);
    gpu->SetRiemannStep(settings.Step);
    gpu->SetInitialStep(settings.H0);
    gpu->SetMinimumStep(settings.HMin);
    gpu->SetMaximumStep(settings.HMax);
    gpu->SetAutoAdjustSampleDistances(0);
    gpu->SetUseJittering(0);
    return gpu;
  }
  const std::map<std::string, int> methods = { { "riemann", vtkAdaptiveVolumeMapper::RIEMANN },
    { "coupled", vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED },
    { "decoupled", vtkAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED },
    { "piecewise", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE },
    { "reference", vtkAdaptiveVolumeMapper::REFERENCE } };
  const auto method = methods.find(settings.Method);
  if (method == methods.end())
  {
    return nullptr;
  }
  auto ours = vtkSmartPointer<vtkAdaptiveVolumeMapper>::New();
  ours->SetIntegrationMethod(method->second);
  ours->SetOpacityModel(settings.VTKOpacity ? vtkAdaptiveVolumeMapper::VTK_OPACITY
                                            : vtkAdaptiveVolumeMapper::EXTINCTION_OPACITY);
  ours->SetTolerance(settings.Tolerance);
  ours->SetSampleDistance(settings.Step);
  ours->SetInitialStep(settings.H0);
  ours->SetMinimumStep(settings.HMin);
  ours->SetMaximumStep(settings.HMax);
  ours->SetAutoAdjustSampleDistances(0); // every pixel, as VTK's mappers above
  return ours;
}

RenderSession::RenderSession(vtkAlgorithm* input, vtkVolumeProperty* property, int width,
  int height, double azimuth, double elevation, double zoom)
  : Width(width)
  , Height(height)
{
  // A placeholder mapper gives ResetCamera() the volume's bounds.
  vtkNew<vtkAdaptiveVolumeMapper> bounds;
  bounds->SetInputConnection(input->GetOutputPort());
  this->Volume->SetMapper(bounds);
  this->Volume->SetProperty(property);
  this->Renderer->SetBackground(0.0, 0.0, 0.0);
  this->Renderer->AddVolume(this->Volume);
  this->Window->SetOffScreenRendering(1);
  this->Window->SetSize(width, height);
  this->Window->SetMultiSamples(0);
  this->Window->SetAlphaBitPlanes(1);
  this->Window->AddRenderer(this->Renderer);
  this->Renderer->ResetCamera();
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  camera->Azimuth(azimuth);
  camera->Elevation(elevation);
  camera->OrthogonalizeViewUp();
  camera->Zoom(zoom);
  this->Renderer->ResetCameraClippingRange();
}

RenderSession::~RenderSession()
{
  // The mappers' graphics resources go with this window.
  this->Volume->GetMapper()->ReleaseGraphicsResources(this->Window);
}

std::vector<double> RenderSession::Render(vtkVolumeMapper* mapper, int frames, vtkCommand* progress)
{
  vtkAbstractVolumeMapper* previous = this->Volume->GetMapper();
  if (previous != mapper)
  {
    previous->ReleaseGraphicsResources(this->Window);
    mapper->SetInputConnection(previous->GetInputConnection(0, 0));
    this->Volume->SetMapper(mapper);
  }
  unsigned long observer = 0;
  if (progress)
  {
    observer = mapper->AddObserver(vtkCommand::ProgressEvent, progress);
  }
  if (auto* gpu = vtkOpenGLAdaptiveVolumeMapper::SafeDownCast(mapper))
  {
    // Refused settings are reported once here, not once per frame.
    mapper->GetInputAlgorithm()->Update();
    const std::string problem = gpu->CheckRenderable(this->Renderer, this->Volume->GetProperty());
    if (!problem.empty())
    {
      std::cerr << "error: " << problem << "\n";
      return std::vector<double>();
    }
  }
  auto* adaptive = vtkAdaptiveVolumeMapper::SafeDownCast(mapper);
  std::vector<double> times;
  vtkNew<vtkTimerLog> timer;
  for (int frame = 0; frame < frames; ++frame)
  {
    mapper->Modified();
    timer->StartTimer();
    this->Window->Render();
    timer->StopTimer();
    times.push_back(timer->GetElapsedTime());
    if (adaptive && adaptive->GetRenderedImage()->GetNumberOfPoints() == 0)
    {
      times.clear();
      break;
    }
  }
  if (progress)
  {
    mapper->RemoveObserver(observer);
  }
  return times;
}

std::vector<float> RenderSession::Image() const
{
  std::vector<float> rgba(4 * static_cast<std::size_t>(this->Width) * this->Height, 0.0f);
  vtkAbstractVolumeMapper* mapper = this->Volume->GetMapper();
  if (auto* adaptive = vtkAdaptiveVolumeMapper::SafeDownCast(mapper))
  {
    auto* pixels =
      vtkFloatArray::SafeDownCast(adaptive->GetRenderedImage()->GetPointData()->GetScalars());
    if (pixels && pixels->GetNumberOfValues() == static_cast<vtkIdType>(rgba.size()))
    {
      std::copy(pixels->GetPointer(0), pixels->GetPointer(0) + rgba.size(), rgba.begin());
    }
  }
  else if (auto* gpu = vtkOpenGLAdaptiveVolumeMapper::SafeDownCast(mapper))
  {
    // The shader's float values, one quantity per render into the float
    // depth image (the window itself has 8 bits per channel). Pixels with no
    // fragment keep the image's clear value, 1, in every quantity: where the
    // ray's entry and length both read 1 the pixel is transparent.
    gpu->SetRenderToImage(1);
    gpu->SetDepthImageScalarTypeToFloat();
    const int quantities[6] = { vtkOpenGLAdaptiveVolumeMapper::RED,
      vtkOpenGLAdaptiveVolumeMapper::GREEN, vtkOpenGLAdaptiveVolumeMapper::BLUE,
      vtkOpenGLAdaptiveVolumeMapper::ALPHA, vtkOpenGLAdaptiveVolumeMapper::RAY_ENTRY,
      vtkOpenGLAdaptiveVolumeMapper::RAY_LENGTH };
    const std::size_t pixels = static_cast<std::size_t>(this->Width) * this->Height;
    std::vector<float> values(6 * pixels, 0.0f);
    vtkNew<vtkImageData> channel;
    for (int q = 0; q < 6; ++q)
    {
      gpu->SetImageQuantity(quantities[q]);
      this->Window->Render();
      gpu->GetDepthImage(channel);
      vtkDataArray* scalars = channel->GetPointData()->GetScalars();
      const int* dims = channel->GetDimensions();
      if (scalars && dims[0] == this->Width && dims[1] == this->Height)
      {
        for (std::size_t i = 0; i < pixels; ++i)
        {
          values[q * pixels + i] = static_cast<float>(scalars->GetComponent(vtkIdType(i), 0));
        }
      }
    }
    std::size_t failed = 0;
    for (std::size_t i = 0; i < pixels; ++i)
    {
      const bool fragment = !(values[4 * pixels + i] == 1.0f && values[5 * pixels + i] == 1.0f);
      failed += fragment && values[3 * pixels + i] < 0.0f ? 1 : 0;
      for (int c = 0; c < 4 && fragment; ++c)
      {
        rgba[4 * i + c] = values[c * pixels + i];
      }
    }
    if (failed > 0)
    {
      // Alpha -1: rays the shader could not finish (drawn magenta on screen).
      std::cerr << "warning: " << failed
                << " ray(s) could not be integrated on this OpenGL device (alpha -1 in the "
                   "image; llvmpipe ends a fragment's loops after 65535 iterations)\n";
    }
    gpu->SetImageQuantity(vtkOpenGLAdaptiveVolumeMapper::DEPTH);
    gpu->SetRenderToImage(0);
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
        if (vx < 0 || vy < 0 || vx >= this->Width || vy >= this->Height)
        {
          continue;
        }
        for (int c = 0; c < 4; ++c)
        {
          rgba[4 * (static_cast<std::size_t>(vy) * this->Width + vx) + c] =
            pixels[4 * (static_cast<std::size_t>(y) * memory[0] + x) + c] / 32767.0f;
        }
      }
    }
  }
  else
  {
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(this->Window);
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
  return rgba;
}

double Median(std::vector<double> values)
{
  if (values.empty())
  {
    return 0.0;
  }
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

int CommandLineStatus(const std::string& problem, const char* usage)
{
  if (problem == "help")
  {
    std::cout << usage;
    return EXIT_SUCCESS;
  }
  if (!problem.empty())
  {
    std::cerr << "error: " << problem << "\n" << usage;
    return 2;
  }
  return -1;
}

AtomicFile::AtomicFile(const std::string& target)
  : Target(target)
{
  const std::string directory = vtksys::SystemTools::GetFilenamePath(target);
  this->Temporary = (directory.empty() ? std::string() : directory + "/") + "." +
    vtksys::SystemTools::GetFilenameWithoutLastExtension(target) + ".partial-" +
    std::to_string(::getpid()) + vtksys::SystemTools::GetFilenameLastExtension(target);
}

AtomicFile::~AtomicFile()
{
  if (!this->Committed)
  {
    std::remove(this->Temporary.c_str());
  }
}

bool AtomicFile::Commit()
{
  if (std::rename(this->Temporary.c_str(), this->Target.c_str()) != 0)
  {
    std::cerr << "error: cannot write '" << this->Target << "': " << std::strerror(errno) << "\n";
    return false;
  }
  this->Committed = true;
  return true;
}

bool WriteTextFile(const std::string& target, const std::function<void(std::ostream&)>& write)
{
  AtomicFile file(target);
  std::ofstream out(file.Path());
  write(out);
  out.close();
  if (!out)
  {
    std::cerr << "error: cannot write '" << target << "'\n";
    return false;
  }
  return file.Commit();
}

bool WriteImage(const std::string& target, int width, int height, const std::vector<float>& rgba)
{
  const std::string ext =
    vtksys::SystemTools::LowerCase(vtksys::SystemTools::GetFilenameLastExtension(target));
  const bool exr = ext == ".exr";
  if (!exr && ext != ".png")
  {
    std::cerr << "error: an image must end in .png or .exr: '" << target << "'\n";
    return false;
  }
  AtomicFile file(target);
  const std::string& path = file.Path();
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
  {
    std::cerr << "error: cannot write '" << target << "': " << OIIO::geterror() << "\n";
    return false;
  }
  const int channels = exr ? 4 : 3;
  OIIO::ImageSpec spec(
    width, height, channels, exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec))
  {
    std::cerr << "error: cannot write '" << target << "': " << out->geterror() << "\n";
    return false;
  }
  // Image files store the top row first.
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(width) * 4 * sizeof(float);
  const char* last = reinterpret_cast<const char*>(rgba.data()) + row * (height - 1);
  const bool ok = out->write_image(OIIO::TypeDesc::FLOAT, last, 4 * sizeof(float), -row);
  if (!out->close() || !ok)
  {
    std::cerr << "error: writing '" << target << "' failed: " << out->geterror() << "\n";
    return false;
  }
  return file.Commit();
}

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

constexpr double ImageError::Thresholds[3];

double ImageError::BinLowerEdge(int bin)
{
  return bin == 0 ? 0.0 : std::pow(10.0, -6.0 + 0.25 * (bin - 1));
}

ImageError Compare(
  const std::vector<float>& image, const std::vector<float>& reference, int width, int height)
{
  ImageError c;
  for (int ch = 0; ch < 4; ++ch)
  {
    const avos::numerics::ImageChannel<float> a{ image.data(), width, height, 4, ch };
    const avos::numerics::ImageChannel<float> b{ reference.data(), width, height, 4, ch };
    c.PSNR[ch] = avos::numerics::PSNR(a, b);
    c.SSIM[ch] = avos::numerics::SSIM(a, b);
  }
  std::array<std::vector<double>, 4> errors;
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
      errors[ch].push_back(e);
      const int bin = e < 1e-6 ? 0
                               : std::min(ImageError::Bins - 1,
                                   1 + static_cast<int>(std::floor(4.0 * (std::log10(e) + 6.0))));
      ++c.Histogram[ch][bin];
    }
  }
  if (c.Pixels == 0)
  {
    return c;
  }
  for (int ch = 0; ch < 4; ++ch)
  {
    std::vector<double>& e = errors[ch];
    double sum = 0.0;
    long counts[3] = {};
    for (double v : e)
    {
      sum += v;
      for (int t = 0; t < 3; ++t)
      {
        counts[t] += v > ImageError::Thresholds[t];
      }
    }
    for (int t = 0; t < 3; ++t)
    {
      c.Exceeding[t][ch] = 100.0 * counts[t] / c.Pixels;
    }
    c.Mean[ch] = sum / c.Pixels;
    c.Maximum[ch] = *std::max_element(e.begin(), e.end());
    // Nearest rank.
    const auto rank = static_cast<std::size_t>(std::ceil(0.999 * e.size())) - 1;
    std::nth_element(e.begin(), e.begin() + rank, e.end());
    c.Percentile999[ch] = e[rank];
  }
  return c;
}

} // namespace app
} // namespace avos
