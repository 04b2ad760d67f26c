// What avos-render and avos-bench share: reading a volume and its transfer
// function, building any of the mappers they compare (ours and VTK's) from
// one description, rendering timed frames off screen on one camera, reading
// the float RGBA image back, image files, and the error of an image against
// a reference. Internal to the command-line tools (not a VTK module).
#ifndef avosRenderSession_h
#define avosRenderSession_h

#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <array>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkCommand;
class vtkImageData;
class vtkRenderWindow;
class vtkRenderer;
class vtkVolume;
class vtkVolumeMapper;
class vtkVolumeProperty;

namespace avos
{
namespace app
{

/// The reader for a .vti, .mhd/.mha, .nrrd/.nhdr, volvis .raw or DICOM folder
/// path, by its extension. Null with `error` set when the path is unusable.
vtkSmartPointer<vtkAlgorithm> MakeReader(const std::string& path, std::string& error);

/// The volume a reader produced, or null with `error` set when it holds no
/// point scalars.
vtkImageData* ReadVolume(vtkAlgorithm* reader, const std::string& path, std::string& error);

/// The smallest spacing: the length of one voxel unit.
double VoxelLength(vtkImageData* volume);

/// Fills the property from a .tf1d file (extinction semantics) or, with
/// `vtkSemantics`, converted to VTK's opacity per voxel unit. False on error.
bool LoadTransferFunction(
  const std::string& path, bool vtkSemantics, double voxel, vtkVolumeProperty* property);

/// A transfer function from the data range, in VTK's semantics: transparent
/// below 20 % of the range, then a ramp to an alpha of 0.15 per voxel.
void DefaultTransferFunction(const double range[2], double voxel, vtkVolumeProperty* property);

/// One way of rendering: one of Methods, with its parameters in voxel units.
struct MethodSettings
{
  static const std::vector<std::string> Methods; // riemann ... vtk-gpu
  std::string Method = "coupled";
  bool VTKOpacity = false; // VTK's opacity model (always, for vtk-*)
  double Tolerance = 0.01;
  double Step = 0.5; // Riemann and VTK's mappers
  double H0 = 0.5;
  double HMin = 0.1;
  double HMax = 2.0;
  int Threads = 0; // 0: all

  bool IsVTK() const { return this->Method.rfind("vtk-", 0) == 0; }
  /// "coupled eps 0.001 (hmin 0.1, hmax 2)" and so on.
  std::string Label() const;
};

/// The mapper for the settings (vtkAdaptiveVolumeMapper, or VTK's
/// fixed-point or GPU mapper with the same step), null for an unknown method.
vtkSmartPointer<vtkVolumeMapper> MakeMapper(const MethodSettings& settings, double voxel);

/// An off-screen window with one volume and a black background; the camera
/// is ResetCamera() from the front, then azimuth, elevation and zoom.
class RenderSession
{
public:
  RenderSession(vtkAlgorithm* input, vtkVolumeProperty* property, int width, int height,
    double azimuth, double elevation, double zoom);
  ~RenderSession();

  /// Renders `frames` full frames with the mapper (each one recast: the
  /// mapper is marked modified) and returns their wall times in seconds.
  /// Empty when vtkAdaptiveVolumeMapper reported a failure.
  std::vector<double> Render(vtkVolumeMapper* mapper, int frames, vtkCommand* progress = nullptr);

  /// The last frame as float RGBA, row 0 at the bottom: our mapper's own
  /// image, the fixed-point mapper's 15-bit image, else the window's pixels.
  std::vector<float> Image() const;

  int GetWidth() const { return this->Width; }
  int GetHeight() const { return this->Height; }
  vtkRenderer* GetRenderer() const { return this->Renderer; }

private:
  int Width;
  int Height;
  vtkNew<vtkVolume> Volume;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;
};

double Median(std::vector<double> values);

/// What a command does with its Parse() verdict: "help" prints the usage
/// (exit status 0), another non-empty text is an error printed before the
/// usage (status 2); -1 when the command line is good and the command goes on.
int CommandLineStatus(const std::string& problem, const char* usage);

/// A file written whole or not at all: write to Path() (a hidden file beside
/// the target, with its extension), then Commit() renames it onto the target
/// in one step. Destroyed uncommitted (a failure, an exception) it removes the
/// partial file: an interrupted or failed run leaves the previous file or
/// none, never a truncated one.
class AtomicFile
{
public:
  explicit AtomicFile(const std::string& target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& Path() const { return this->Temporary; }
  /// False, with a message on stderr, when the rename fails.
  bool Commit();

private:
  std::string Target;
  std::string Temporary;
  bool Committed = false;
};

/// Writes a text file atomically (AtomicFile) from `write`; false, with a
/// message, when it cannot.
bool WriteTextFile(const std::string& target, const std::function<void(std::ostream&)>& write);

/// Writes RGBA float pixels (row 0 at the bottom): EXR keeps the four float
/// channels, PNG gets RGB over the black background in 8 bits. Atomically
/// (AtomicFile).
bool WriteImage(const std::string& path, int width, int height, const std::vector<float>& rgba);

/// A float RGBA image of the given size, row 0 at the bottom; empty on error.
std::vector<float> ReadImage(const std::string& path, int width, int height);

/// The error of an image against a reference, per RGBA channel, over the
/// pixels where either is not transparent (the rays that met the volume).
struct ImageError
{
  static constexpr double Thresholds[3] = { 0.01, 0.005, 0.001 };
  /// Histogram bins of |error|: [0, 1e-6), then 4 per decade up to 1.
  static constexpr int Bins = 25;
  static double BinLowerEdge(int bin);

  long Pixels = 0;
  double Exceeding[3][4] = {}; // % of Pixels above Thresholds[t], [t][channel]
  double Mean[4] = {};
  double Maximum[4] = {};
  double Percentile999[4] = {}; // 99.9th percentile of |error|
  double PSNR[4] = {};          // dB, whole image (infinite when identical)
  double SSIM[4] = {};
  std::array<std::array<long, Bins>, 4> Histogram{};
};

ImageError Compare(
  const std::vector<float>& image, const std::vector<float>& reference, int width, int height);

} // namespace app
} // namespace avos

#endif
