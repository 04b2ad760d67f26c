// The frame engine (VTK-free): one frame's pixel rays cast through a volume
// with one integration method, tile by tile, in the caller's parallel loop.
//
// The VTK classes own the stages that depend on VTK (the input, the property,
// the camera and the display) and hand the engine plain values: the frame's
// rays (Frame: camera, image size, depth buffer, footprint, clip region), a
// view of the scalars read in place (Scalars), and the method with the tables
// it reads (FrameMethod). FrameCaster casts the footprint's 16x16 tiles with
// the scratch lists of its pool, so the caller's loop (vtkSMPTools::For in
// the VTK classes) needs no thread-local state; each ray goes where its
// method's fastest path is: a ray per lane of the Riemann or the piecewise
// kernels for unclipped composite rays where the kernels read the scalars,
// else a ray at a time through IntegrateRay (the numerics' integrators, the
// engine's kernels inside). Modules/Engine/Testing checks every pixel against
// the numerics core ray by ray.
#ifndef avos_engine_Frame_h
#define avos_engine_Frame_h

#include "avos/engine/PieceKernels.h"
#include "avos/engine/PiecewiseRays.h"
#include "avos/engine/PixelRays.h"
#include "avos/engine/Riemann.h"
#include "avos/engine/WorkMonitor.h"
#include "avos/numerics/Accumulation.h"
#include "avos/numerics/Clipping.h"
#include "avos/numerics/EmptySpace.h"
#include "avos/numerics/GradientOpacity.h"
#include "avos/numerics/Mixture.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/Shading.h"
#include "avos/numerics/TransferFunction.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace avos
{
namespace engine
{

// The types the engine reads scalars of, in place.
enum class ScalarType
{
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Int64,
  UInt64,
  Float32,
  Float64
};

// How scalars fill the grid's box (VTK's array association and the
// property's interpolation type).
enum class ScalarField
{
  Trilinear,  // point scalars, the trilinear interpolant (linear interpolation)
  Nearest,    // point scalars, each point's value nearest to it (nearest)
  Cells,      // cell scalars, one value per cell (nearest)
  CellCentres // cell scalars, trilinear between the cells' centres (linear)
};

// A scalar volume read in place, x fastest: one tuple of Components values
// (interleaved; 2 to 4 make a mixture, FrameMethod::Mixture) per grid point,
// or per cell for the cell fields, Stride values from one tuple to the next
// (0: Components; more: one component of wider tuples). Dimensions are the
// grid points' (the box) in every field.
struct Scalars
{
  const void* Data = nullptr;
  ScalarType Type = ScalarType::Float32;
  int Dimensions[3] = { 0, 0, 0 };
  ScalarField Field = ScalarField::Trilinear;
  int Components = 1;
  int Stride = 0;

  int GetStride() const { return this->Stride > 0 ? this->Stride : this->Components; }
};

// How a ray is integrated (vtkAdaptiveVolumeMapper's IntegrationMethod).
enum class Integration
{
  Riemann,
  AdaptiveCoupled,
  AdaptiveDecoupled,
  Reference,
  Piecewise
};

// What a ray shows (vtkVolumeMapper's blend modes the engine casts).
enum class Blend
{
  Composite,
  Maximum,
  Minimum,
  Average,
  Additive
};

// The integration settings of one frame and the tables they read (owned by
// the caller, alive while the frame is cast).
struct FrameMethod
{
  Integration Kind = Integration::AdaptiveCoupled;
  Blend Mode = Blend::Composite;
  numerics::AdaptiveSettings<double> Adaptive;
  double SampleDistance = 0.5;
  double TerminationBound = 0.0;
  const numerics::TransferFunction<double>* TF = nullptr;
  // Scalars of several components: their medium (in place of TF) and, for
  // the piecewise methods, its pieces (in place of Pieces); composite rays,
  // unshaded, without the kernels.
  const numerics::MixtureTransferFunction<double>* Mixture = nullptr;
  const numerics::PiecewiseMixture<double>* MixturePieces = nullptr;
  // The empty-space map whose visible segments composite rays integrate
  // (null: the whole box); the projections search its blocks.
  const numerics::EmptySpaceMap<double>* Map = nullptr;
  // The transfer function in pieces with polynomial extinction (Pieces.h),
  // for the piecewise methods (Piecewise; Reference in the extinction model;
  // the additive projection).
  const numerics::PiecewiseTransferFunction<double>* Pieces = nullptr;
  // The Riemann kernel's volume and table (null: the scalar sum; shaded
  // rays take the scalar sum whatever they are: the kernels do not shade).
  const Volume* EngineVolume = nullptr;
  const TransferTable* EngineTable = nullptr;
  // The piecewise method's kernels (their cells read 8- and 16-bit scalars),
  // and its pieces' table for the ray-per-lane integrator (null: a ray at a
  // time). The kernels' volumes (these and EngineVolume) hold the field the
  // rays integrate: the scalars' one component (of interleaved tuples too),
  // or that of a mixture of which it alone shows (GetSingleComponent: the
  // frame is cast as that component alone; no other mixture takes them).
  PieceKernels Kernels;
  const PiecewiseTable* PieceTable = nullptr;
  // Gradient shading of the emission (null: none), with the grid-to-world
  // map (x_world = GridToWorld x_grid + GridToWorldOffset: ray directions
  // and positional lights) and the normal matrix (grid gradients to world).
  const numerics::ShadingModel<double>* Shading = nullptr;
  // Gradient opacity (null: none), its normal matrix set: every composite
  // method (the piecewise ones and the reference through
  // PiecewiseGradientOpacity.h where Pieces are given).
  const numerics::GradientOpacity<double>* GradientOpacity = nullptr;
  glm::dmat3 GridToWorld{ 1.0 };
  glm::dvec3 GridToWorldOffset{ 0.0 };
  glm::dmat3 NormalMatrix{ 1.0 };
  // The average projection's range, and the data's range, to which the
  // projections normalise the scalar.
  const numerics::AverageRange<double>* Range = nullptr;
  double ScalarMinimum = 0.0, ScalarMaximum = 1.0;
};

// Widening of the empty-space segments, in voxel units: far above rounding,
// far below any step.
constexpr double SegmentPad = 1e-6;

// What a frame's ray cast depends on, besides the scalars and the method.
struct Frame
{
  FrameRays Rays;                    // Rays.Depth points into Depth
  int Rect[4] = { 0, 0, 0, 0 };      // pixels cast: [x0, x1) x [y0, y1)
  std::vector<float> Depth;          // the depth buffer, Rays.Width x Rays.Height
  numerics::ClipRegion<double> Clip; // clipping planes and cropping, in grid coordinates

  // Depth from the viewport's depth buffer (viewportWidth x viewportHeight,
  // row by row): each of the frame's Rays.Width x Rays.Height rays stops at
  // the depth under its own centre.
  void SampleDepth(const float* viewport, int viewportWidth, int viewportHeight);
  // Rect: the pixels the grid's box covers (all of the image when a corner
  // is behind the eye). Matrices row-major 4x4: the grid to world, and the
  // camera's composite projection (world to NDC).
  void SetFootprint(const double gridToWorld[16], const double projection[16]);
};

// What a frame's rays did, summed over its pixels.
struct FrameStatistics
{
  std::int64_t Rays = 0;
  std::int64_t Samples = 0;
  std::int64_t MaximumSamples = 0;
  std::int64_t Rejected = 0;
  std::int64_t Cells = 0;
  std::int64_t Pieces = 0;
  std::int64_t Failed = 0; // rays whose integration reported an error
  std::string FirstError;  // the first such error

  void Add(const numerics::RayResult<double>& ray);
  void Merge(const FrameStatistics& other);
};

// The caller's parallel loop: calls body(begin, end) over disjoint ranges
// covering [0, count), from any threads, and returns when all have returned.
using ParallelFor = std::function<void(
  std::int64_t count, const std::function<void(std::int64_t begin, std::int64_t end)>& body)>;

// One ray's lists: its visible segments (the map's, or what the clip region
// keeps of them), the clip region's parts of the ray and their
// intersection; the blocks' parts of the ray for the intensity projections.
struct RayScratch
{
  std::vector<numerics::Interval<double>> Visible, Kept, Clipped;
  std::vector<numerics::EmptySpaceMap<double>::Span> Spans;
};

// The method's ray origin + t direction (grid coordinates, a voxel unit per
// unit of t), t in [0, D], cut by `clip`. When the method walks the map
// (WalksSegments), scratch.Visible holds the ray's visible segments on entry.
// `steps`, when given, receives the accepted outer steps.
void IntegrateRay(const Scalars& scalars, const numerics::ClipRegion<double>& clip,
  const FrameMethod& method, const glm::dvec3& origin, const glm::dvec3& direction, double D,
  RayScratch& scratch, numerics::RayResult<double>& result,
  std::vector<numerics::StepRecord<double>>* steps = nullptr);

// Whether composite rays of `method` integrate the map's visible segments
// (the intensity projections search the blocks themselves).
bool WalksSegments(const FrameMethod& method);

// Empty when the engine can cast `scalars` with `method`, else why.
std::string Validate(const Scalars& scalars, const FrameMethod& method);

class FrameCaster
{
public:
  static constexpr int TileSize = 16;

  FrameCaster();
  ~FrameCaster();
  FrameCaster(const FrameCaster&) = delete;
  FrameCaster& operator=(const FrameCaster&) = delete;

  // The 16x16 tiles of the frame's Rect.
  static std::int64_t Tiles(const Frame& frame);

  // Casts the rays of frame.Rect into `image` (RGBA floats, premultiplied,
  // Rays.Width x Rays.Height, row by row; pixels outside Rect or whose ray
  // misses the box are left as they are). Tiles run in `loop`; each finished
  // tile is counted in `monitor`, and once it is aborted the remaining tiles
  // are skipped. The scalars and method must pass Validate.
  FrameStatistics Cast(const Frame& frame, const Scalars& scalars, const FrameMethod& method,
    float* image, const ParallelFor& loop, WorkMonitor& monitor);

  // The ray of pixel (x, y) a ray at a time, its outer steps into `steps`:
  // false when it misses the box.
  static bool TracePixel(const Frame& frame, const Scalars& scalars, const FrameMethod& method,
    int x, int y, numerics::RayResult<double>& result,
    std::vector<numerics::StepRecord<double>>* steps);

  // A tile's scratch lists and its tiles' statistics (Frame.cxx).
  struct Scratch;

private:
  Scratch* Acquire();
  void Release(Scratch* scratch);

  std::mutex PoolMutex;
  std::vector<std::unique_ptr<Scratch>> Pool; // every scratch, one per concurrent tile
  std::vector<Scratch*> Free;
};

} // namespace engine
} // namespace avos

#endif
