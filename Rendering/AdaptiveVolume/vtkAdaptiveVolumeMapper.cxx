#include "vtkAdaptiveVolumeMapper.h"

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRayCastImageDisplayHelper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkTable.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "avosClippingPlanes.h"
#include "avosEmptySpaceRanges.h"
#include "avosEngineVolume.h"
#include "avosImageGrid.h"
#include "avosMonitoredWork.h"
#include "avosTransferFunctionFromProperty.h"

#include "avos/engine/EmptySpace.h"
#include "avos/engine/PieceKernels.h"
#include "avos/engine/PiecewiseRays.h"
#include "avos/engine/PixelRays.h"
#include "avos/engine/Riemann.h"
#include "avos/numerics/Accumulation.h"
#include "avos/numerics/Clipping.h"
#include "avos/numerics/EmptySpace.h"
#include "avos/numerics/Extremum.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/Shading.h"
#include "avos/numerics/TransferFunction.h"
#include "avos/numerics/Volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace
{
namespace an = avos::numerics;
using TransferFunction = an::TransferFunction<double>;
using Segments = std::vector<an::Interval<double>>;

constexpr int TileSize = 16;

// A thread's scratch lists for one ray: the visible segments, the part the
// clipping planes and cropping keep, and their intersection; the blocks'
// parts of the ray for the intensity projections. And for a tile's row of
// rays, set up and walked through the empty-space map at once
// (avos/engine/PixelRays.h, EmptySpace.h): their pixels, origins and
// directions (three doubles each), lengths and segments.
struct RayBuffers
{
  Segments Visible, Kept, Clipped;
  std::vector<an::EmptySpaceMap<double>::Span> Spans;
  std::array<int, TileSize> RowX;
  std::array<double, 3 * TileSize> RowOrigins, RowDirections;
  std::array<double, TileSize> RowLengths;
  std::array<Segments, TileSize> RowSegments;
  // A tile's rays for the lanes of the Riemann kernel or the piecewise one.
  std::array<Segments, TileSize * TileSize> TileSegments;
  std::array<avos::engine::RiemannRay, TileSize * TileSize> TileRays;
  std::array<avos::engine::RayOutput, TileSize * TileSize> TileOutputs;
  std::array<avos::engine::PiecewiseOutput, TileSize * TileSize> TilePieceOutputs;
  std::array<int, TileSize * TileSize> TileX, TileY;
};
// Widening of the empty-space segments, in voxel units: far above rounding,
// far below any step.
constexpr double SegmentPad = 1e-6;

// What a frame's ray cast depends on, besides the data and the property.
struct FrameGeometry
{
  // Camera, grid and image: what the pixels' rays depend on (Rays.Depth
  // points into Depth).
  avos::engine::FrameRays Rays;
  int Rect[4] = { 0, 0, 0, 0 }; // pixels cast: [x0, x1) x [y0, y1)
  std::vector<float> Depth;     // the depth buffer, Rays.Width x Rays.Height
  an::ClipRegion<double> Clip;  // clipping planes and cropping, in grid coordinates
};

struct ThreadStatistics
{
  vtkIdType Rays = 0;
  vtkIdType Samples = 0;
  vtkIdType MaximumSamples = 0;
  vtkIdType Rejected = 0;
  vtkIdType Cells = 0;
  vtkIdType Pieces = 0;
  vtkIdType Failed = 0;   // rays whose integration reported an error
  std::string FirstError; // the first such error
};

glm::dvec4 Multiply(const double m[16], const glm::dvec4& p)
{
  glm::dvec4 r;
  for (int i = 0; i < 4; ++i)
  {
    r[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3] * p[3];
  }
  return r;
}

// The pixel's ray from its centre on the near plane to the depth buffer, in
// grid coordinates (voxel units), clipped to the grid's box.
bool PixelRay(
  const FrameGeometry& g, int x, int y, glm::dvec3& origin, glm::dvec3& direction, double& D)
{
  return avos::engine::PixelRay(g.Rays, x, y, &origin.x, &direction.x, D);
}

// The integration settings of one frame.
struct Method
{
  int Kind = vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED;
  int Blend = vtkVolumeMapper::COMPOSITE_BLEND; // or the maximum / minimum intensity
  an::AdaptiveSettings<double> Adaptive;
  double SampleDistance = 0.5;
  double TerminationBound = 0.0;
  // The transfer function in pieces with polynomial extinction (Pieces.h),
  // for the piecewise methods (PIECEWISE_ADAPTIVE; REFERENCE in the
  // extinction model).
  const an::PiecewiseTransferFunction<double>* Pieces = nullptr;
  // The vectorised engine's copy of the volume and transfer function, for
  // RIEMANN (null: the scalar sum).
  const avos::engine::Volume* EngineVolume = nullptr;
  const avos::engine::TransferTable* EngineTable = nullptr;
  // PIECEWISE_ADAPTIVE's kernels, given the same copy where the scalars are
  // 8- or 16-bit (else its cells take the scalar walk), and there its pieces'
  // table for the ray-per-lane integrator (null: a ray at a time).
  avos::engine::PieceKernels Kernels;
  const avos::engine::PiecewiseTable* PieceTable = nullptr;
  // Gradient shading of the emission (null: none), with the grid-to-world
  // matrix's linear part (ray directions to world) and the normal matrix
  // (grid gradients to world).
  const an::ShadingModel<double>* Shading = nullptr;
  // The average projection's range, and the data's range, to which the
  // projections normalise the scalar.
  const an::AverageRange<double>* Range = nullptr;
  double ScalarMinimum = 0.0, ScalarMaximum = 1.0;
  glm::dmat3 GridToWorld{ 1.0 };
  glm::dmat3 NormalMatrix{ 1.0 };
};

// The property's shading coefficients and the renderer's switched-on lights
// (directional: from the focal point towards the position, each light's
// colours times its intensity), and the same as numbers in `key`; empty, or
// why the frame cannot be shaded.
std::string PrepareShading(vtkRenderer* ren, vtkVolumeProperty* property, int blend, int method,
  an::ShadingModel<double>& model, std::vector<double>& key)
{
  if (blend != vtkVolumeMapper::COMPOSITE_BLEND)
  {
    return "shading applies to the composite blend mode only, not to projections; turn the "
           "property's Shade off";
  }
  if (method == vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE)
  {
    return "the piecewise method's closed forms need an emission that depends on the scalar "
           "alone; shade with the Riemann, coupled, decoupled or reference method";
  }
  model = an::ShadingModel<double>();
  model.Ambient = property->GetAmbient(0);
  model.Diffuse = property->GetDiffuse(0);
  model.Specular = property->GetSpecular(0);
  model.SpecularPower = property->GetSpecularPower(0);
  model.TwoSided = ren->GetTwoSidedLighting() != 0;
  vtkLightCollection* lights = ren->GetLights();
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    if (!light->GetSwitch())
    {
      continue;
    }
    if (light->GetPositional())
    {
      return "positional lights are not supported, only directional ones";
    }
    double position[3], focal[3];
    light->GetTransformedPosition(position);
    light->GetTransformedFocalPoint(focal);
    glm::dvec3 direction(position[0] - focal[0], position[1] - focal[1], position[2] - focal[2]);
    const double length = glm::length(direction);
    if (!(length > 0.0) || !std::isfinite(length))
    {
      return "a light's position and focal point coincide";
    }
    const double intensity = light->GetIntensity();
    const double* diffuse = light->GetDiffuseColor();
    const double* specular = light->GetSpecularColor();
    model.Lights.push_back(
      { direction / length, intensity * glm::dvec3(diffuse[0], diffuse[1], diffuse[2]),
        intensity * glm::dvec3(specular[0], specular[1], specular[2]) });
  }
  const std::string invalid = model.Validate();
  if (!invalid.empty())
  {
    return invalid;
  }
  key = { model.Ambient, model.Diffuse, model.Specular, model.SpecularPower,
    model.TwoSided ? 1.0 : 0.0 };
  for (const auto& light : model.Lights)
  {
    for (const glm::dvec3& v : { light.Direction, light.Diffuse, light.Specular })
    {
      key.insert(key.end(), { v.x, v.y, v.z });
    }
  }
  return std::string();
}

// Calls f(field) with the ray start + t direction's field (grid coordinates):
// shaded when the method shades, the scalar alone otherwise.
template <typename Storage, typename F>
an::RayResult<double> WithField(const an::TrilinearVolume<double, Storage>& volume,
  const Method& method, const glm::dvec3& start, const glm::dvec3& direction, F&& f)
{
  using Volume = an::TrilinearVolume<double, Storage>;
  if (method.Shading)
  {
    const glm::dvec3 toViewer = -glm::normalize(method.GridToWorld * direction);
    return f(an::ShadedRayField<double, Volume>{
      volume, start, direction, method.NormalMatrix, toViewer, *method.Shading });
  }
  return f(an::RayField<double, Volume>{ volume, start, direction });
}

// The Riemann sum over the kept parts of a ray, each its own ray from its
// entry (as VTK's mappers start a clipped ray at the plane), front to back;
// `segments` are the visible ones of [0, D].
template <typename Storage>
void ClippedRiemann(const an::TrilinearVolume<double, Storage>& volume, const TransferFunction& tf,
  const Method& method, const glm::dvec3& origin, const glm::dvec3& direction,
  const Segments& segments, RayBuffers& buffers, an::RayResult<double>& result,
  std::vector<an::StepRecord<double>>* steps)
{
  // The sums' own termination test, on the whole ray's transmittance.
  const double stop = method.TerminationBound / std::max(1.0, tf.GetMaximumColor());
  glm::dvec3 color(0.0);
  double T = 1.0;
  for (const an::Interval<double>& part : buffers.Kept)
  {
    if (T <= stop)
    {
      break;
    }
    buffers.Clipped.clear();
    for (const an::Interval<double>& v : segments)
    {
      const double a = std::max(v.Begin, part.Begin), b = std::min(v.End, part.End);
      if (a < b)
      {
        buffers.Clipped.push_back({ a - part.Begin, b - part.Begin });
      }
    }
    if (buffers.Clipped.empty())
    {
      continue;
    }
    const glm::dvec3 start = origin + part.Begin * direction;
    const double D = part.End - part.Begin;
    // What is left of the bound after the transmittance spent before.
    const double bound = method.TerminationBound > 0.0 ? method.TerminationBound / T : 0.0;
    const std::size_t recorded = steps ? steps->size() : 0;
    glm::dvec4 rgba;
    if (method.EngineVolume && !steps)
    {
      avos::engine::RayOutput out;
      avos::engine::CastRiemann(*method.EngineVolume, *method.EngineTable, &start.x, &direction.x,
        D, method.SampleDistance, buffers.Clipped.data(), buffers.Clipped.size(), bound, out);
      rgba = glm::dvec4(out.RGBA[0], out.RGBA[1], out.RGBA[2], out.RGBA[3]);
      result.Statistics.Samples += out.Samples;
    }
    else
    {
      const an::RayResult<double> r = WithField(volume, method, start, direction,
        [&](const auto& field)
        {
          return an::IntegrateRiemann(field, tf, D, method.SampleDistance,
            an::RiemannForm::Exponential, buffers.Clipped.data(), buffers.Clipped.size(), bound,
            steps);
        });
      if (!r.Error.empty())
      {
        result.Error = r.Error;
        return;
      }
      rgba = r.RGBA;
      result.Statistics.Samples += r.Statistics.Samples;
    }
    for (std::size_t i = recorded; steps && i < steps->size(); ++i)
    {
      (*steps)[i].Start += part.Begin;
    }
    color += T * glm::dvec3(rgba);
    T *= 1.0 - rgba.a;
  }
  result.RGBA = glm::dvec4(color, 1.0 - T);
}

// Whether the rays of `method` are integrated over the map's visible
// segments (the intensity projections search the blocks themselves).
bool WalksSegments(const an::EmptySpaceMap<double>* map, const Method& method)
{
  return map && method.Blend == vtkVolumeMapper::COMPOSITE_BLEND;
}

// Integrates the ray origin + t direction, t in [0, D], through the visible
// blocks (all of the box without a map) that the clipping planes and
// cropping keep; when WalksSegments, buffers.Visible holds the ray's visible
// segments on entry. `steps`, when given, receives the accepted outer steps.
template <typename Storage>
void IntegrateRay(const an::TrilinearVolume<double, Storage>& volume, const FrameGeometry& g,
  const TransferFunction& tf, const an::EmptySpaceMap<double>* map, const Method& method,
  const glm::dvec3& origin, const glm::dvec3& direction, double D, RayBuffers& buffers,
  an::RayResult<double>& result, std::vector<an::StepRecord<double>>* steps = nullptr)
{
  Segments& segments = buffers.Visible;
  const bool projection = method.Blend != vtkVolumeMapper::COMPOSITE_BLEND;
  if (!WalksSegments(map, method))
  {
    segments.assign(1, { 0.0, D });
  }
  if (!g.Clip.IsEmpty() && !segments.empty())
  {
    g.Clip.Kept(origin, direction, D, buffers.Kept);
    if (method.Kind == vtkAdaptiveVolumeMapper::RIEMANN && !projection)
    {
      ClippedRiemann(volume, tf, method, origin, direction, segments, buffers, result, steps);
      return;
    }
    // The other methods integrate exactly the segments they are given (tau
    // taken as 0 elsewhere), within their tolerance over the whole ray.
    an::ClipRegion<double>::Intersect(segments, buffers.Kept, buffers.Clipped);
    std::swap(segments, buffers.Clipped);
  }
  if (segments.empty())
  {
    return;
  }
  if (method.Blend == vtkVolumeMapper::ADDITIVE_BLEND ||
    method.Blend == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND)
  {
    // Shown as VTK's GPU mapper shows them: grey, clamped to [0, 1], opaque
    // wherever the ray meets the volume (the average: the range).
    an::Accumulation<double> a;
    if (method.Blend == vtkVolumeMapper::ADDITIVE_BLEND)
    {
      a = an::AdditiveAlongRay(volume, origin, direction, segments.data(), segments.size(),
        *method.Pieces, method.ScalarMinimum, method.ScalarMaximum);
      a.Length = 1.0;
    }
    else
    {
      a = an::AverageAlongRay(volume, origin, direction, segments.data(), segments.size(),
        *method.Range, tf, method.SampleDistance, method.ScalarMinimum, method.ScalarMaximum,
        method.Adaptive.Tolerance);
    }
    result.Error = a.Error;
    if (a.Error.empty() && a.Length > 0.0)
    {
      const double v = std::min(std::max(a.Value, 0.0), 1.0);
      result.RGBA = glm::dvec4(v, v, v, 1.0);
    }
    result.Statistics.Cells = a.Cells;
    result.Statistics.Samples = a.Cells;
    return;
  }
  if (projection)
  {
    // The exact extremum of the ray's scalar, shown as VTK's mappers show a
    // projection: its colour times the opacity function's value there.
    const bool maximum = method.Blend == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND;
    // Blocks best first where the map gives their ranges.
    const an::RayExtremum<double> e = map
      ? an::ExtremumByBlocks(volume, *map, origin, direction, D, SegmentPad, segments.data(),
          segments.size(), maximum, buffers.Spans)
      : an::ExtremumAlongRay(volume, origin, direction, segments.data(), segments.size(), maximum);
    if (e.Found)
    {
      const double alpha = std::min(std::max(tf.GetOpacityValue(e.Value), 0.0), 1.0);
      result.RGBA = glm::dvec4(tf.GetColor(e.Value) * alpha, alpha);
    }
    result.Statistics.Cells = e.Cells;
    result.Statistics.Samples = e.Cells;
    return;
  }
  switch (method.Kind)
  {
    case vtkAdaptiveVolumeMapper::RIEMANN:
      if (method.EngineVolume && !steps)
      {
        // The same sum in float SIMD lanes (within 1e-4, avos/engine/Riemann.h).
        avos::engine::RayOutput out;
        avos::engine::CastRiemann(*method.EngineVolume, *method.EngineTable, &origin.x,
          &direction.x, D, method.SampleDistance, segments.data(), segments.size(),
          method.TerminationBound, out);
        result.RGBA = glm::dvec4(out.RGBA[0], out.RGBA[1], out.RGBA[2], out.RGBA[3]);
        result.Statistics.Samples = out.Samples;
        break;
      }
      result = WithField(volume, method, origin, direction,
        [&](const auto& field)
        {
          return an::IntegrateRiemann(field, tf, D, method.SampleDistance,
            an::RiemannForm::Exponential, segments.data(), segments.size(), method.TerminationBound,
            steps);
        });
      break;
    case vtkAdaptiveVolumeMapper::REFERENCE:
      result = method.Pieces
        ? an::IntegratePiecewise(volume, origin, direction, segments.data(), segments.size(),
            *method.Pieces, an::PiecewiseReferenceTolerance<double>())
        : WithField(volume, method, origin, direction,
            [&](const auto& field)
            { return an::IntegrateReference(field, tf, segments.data(), segments.size()); });
      break;
    case vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE:
      // Its cells' and pieces' batches in SIMD lanes (avos/engine/PieceKernels.h).
      result = an::IntegratePiecewise(volume, origin, direction, segments.data(), segments.size(),
        *method.Pieces, method.Adaptive.Tolerance, true, steps, method.Kernels);
      break;
    default:
      result = WithField(volume, method, origin, direction,
        [&](const auto& field)
        {
          return an::IntegrateAdaptive(
            field, tf, segments.data(), segments.size(), method.Adaptive, steps);
        });
  }
}

// IntegrateRay for the pixel's ray, its segments walked here. False when
// the ray misses the volume's box.
template <typename Storage>
bool IntegratePixel(const an::TrilinearVolume<double, Storage>& volume, const FrameGeometry& g,
  const TransferFunction& tf, const an::EmptySpaceMap<double>* map, const Method& method, int x,
  int y, RayBuffers& buffers, an::RayResult<double>& result,
  std::vector<an::StepRecord<double>>* steps = nullptr)
{
  glm::dvec3 origin, direction;
  double D;
  if (!PixelRay(g, x, y, origin, direction, D))
  {
    return false;
  }
  if (WalksSegments(map, method))
  {
    map->Segments(origin, direction, D, SegmentPad, buffers.Visible);
  }
  IntegrateRay(volume, g, tf, map, method, origin, direction, D, buffers, result, steps);
  return true;
}

template <typename Storage>
class RayCaster
{
public:
  RayCaster(const Storage* data, const FrameGeometry& geometry, const TransferFunction& tf,
    const an::EmptySpaceMap<double>* map, const Method& method, float* image,
    vtkSMPThreadLocal<ThreadStatistics>& statistics, vtkSMPThreadLocal<RayBuffers>& buffers,
    avos::WorkMonitor& monitor)
    : Volume(data, geometry.Rays.Dimensions)
    , Geometry(geometry)
    , TF(tf)
    , Map(map)
    , Settings(method)
    , Image(image)
    , Statistics(statistics)
    , Buffers(buffers)
    , Monitor(monitor)
  {
    this->TilesX = (geometry.Rect[1] - geometry.Rect[0] + TileSize - 1) / TileSize;
    const bool lanes = method.Kind == vtkAdaptiveVolumeMapper::RIEMANN
      ? method.EngineVolume != nullptr
      : method.Kind == vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE && method.PieceTable;
    this->RaysPerLane =
      lanes && method.Blend == vtkVolumeMapper::COMPOSITE_BLEND && geometry.Clip.IsEmpty();
  }

  // Tiles [begin, end) in row-major order over the cast rectangle. Once the
  // frame is aborted, the remaining tiles are skipped.
  void operator()(vtkIdType begin, vtkIdType end)
  {
    ThreadStatistics& stats = this->Statistics.Local();
    RayBuffers& buffers = this->Buffers.Local();
    const int* rect = this->Geometry.Rect;
    for (vtkIdType tile = begin; tile < end && !this->Monitor.Aborted(); ++tile)
    {
      const int x0 = rect[0] + static_cast<int>(tile % this->TilesX) * TileSize;
      const int y0 = rect[2] + static_cast<int>(tile / this->TilesX) * TileSize;
      if (this->RaysPerLane)
      {
        this->CastTile(x0, std::min(x0 + TileSize, rect[1]), y0, std::min(y0 + TileSize, rect[3]),
          stats, buffers);
      }
      else
      {
        for (int y = y0; y < std::min(y0 + TileSize, rect[3]); ++y)
        {
          this->CastRow(x0, std::min(x0 + TileSize, rect[1]), y, stats, buffers);
        }
      }
      this->Monitor.Finished(1);
    }
  }

private:
  // Pixels [x0, x1) of row y (at most a tile's width): the rays that meet
  // the box, set up and walked through the empty-space map as one packet.
  void CastRow(int x0, int x1, int y, ThreadStatistics& stats, RayBuffers& buffers)
  {
    const int count = this->SetUpRow(x0, x1, y, buffers);
    for (int i = 0; i < count; ++i)
    {
      std::swap(buffers.Visible, buffers.RowSegments[i]);
      const double* o = &buffers.RowOrigins[3 * i];
      const double* d = &buffers.RowDirections[3 * i];
      an::RayResult<double> result;
      IntegrateRay(this->Volume, this->Geometry, this->TF, this->Map, this->Settings,
        glm::dvec3(o[0], o[1], o[2]), glm::dvec3(d[0], d[1], d[2]), buffers.RowLengths[i], buffers,
        result);
      this->Store(buffers.RowX[i], y, result, stats);
    }
  }

  // The rays of pixels [x0, x1) of row y that meet the box into buffers.Row*
  // (their segments too where the rays walk the empty-space map); how many.
  int SetUpRow(int x0, int x1, int y, RayBuffers& buffers) const
  {
    const int count = avos::engine::RowRays(this->Geometry.Rays, y, x0, x1, buffers.RowX.data(),
      buffers.RowOrigins.data(), buffers.RowDirections.data(), buffers.RowLengths.data());
    if (WalksSegments(this->Map, this->Settings))
    {
      avos::engine::PacketSegments(*this->Map, static_cast<std::size_t>(count),
        buffers.RowOrigins.data(), buffers.RowDirections.data(), buffers.RowLengths.data(),
        SegmentPad, buffers.RowSegments.data());
    }
    return count;
  }

  // The Riemann sum or the piecewise method over a tile's rays, a ray per
  // lane of the engine's kernels (avos/engine/Riemann.h, PiecewiseRays.h):
  // what CastRow and IntegrateRay give without clipping, the rays refilling
  // the lanes across the tile's rows.
  void CastTile(int x0, int x1, int y0, int y1, ThreadStatistics& stats, RayBuffers& buffers)
  {
    const bool walks = WalksSegments(this->Map, this->Settings);
    std::size_t count = 0;
    for (int y = y0; y < y1; ++y)
    {
      const int n = this->SetUpRow(x0, x1, y, buffers);
      for (int i = 0; i < n; ++i, ++count)
      {
        Segments& segments = buffers.TileSegments[count];
        if (walks)
        {
          std::swap(segments, buffers.RowSegments[i]);
        }
        else
        {
          segments.assign(1, { 0.0, buffers.RowLengths[i] });
        }
        avos::engine::RiemannRay& ray = buffers.TileRays[count];
        std::copy_n(&buffers.RowOrigins[3 * i], 3, ray.Origin);
        std::copy_n(&buffers.RowDirections[3 * i], 3, ray.Direction);
        ray.D = buffers.RowLengths[i];
        ray.Segments = segments.data();
        ray.Count = segments.size();
        buffers.TileX[count] = buffers.RowX[i];
        buffers.TileY[count] = y;
      }
    }
    const Method& method = this->Settings;
    if (method.Kind == vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE)
    {
      avos::engine::CastPiecewiseRays(*method.Kernels.Scalars, *method.Pieces, *method.PieceTable,
        method.Adaptive.Tolerance, buffers.TileRays.data(), count, buffers.TilePieceOutputs.data());
      for (std::size_t i = 0; i < count; ++i)
      {
        avos::engine::PiecewiseOutput& out = buffers.TilePieceOutputs[i];
        an::RayResult<double> result;
        result.RGBA = glm::dvec4(out.RGBA[0], out.RGBA[1], out.RGBA[2], out.RGBA[3]);
        result.Statistics.Samples = out.Pieces;
        result.Statistics.Pieces = out.Pieces;
        result.Statistics.Cells = out.Cells;
        result.Statistics.Rejected = out.Rejected;
        std::swap(result.Error, out.Error);
        this->Store(buffers.TileX[i], buffers.TileY[i], result, stats);
      }
      return;
    }
    avos::engine::CastRiemannRays(*method.EngineVolume, *method.EngineTable, method.SampleDistance,
      method.TerminationBound, buffers.TileRays.data(), count, buffers.TileOutputs.data());
    for (std::size_t i = 0; i < count; ++i)
    {
      const avos::engine::RayOutput& out = buffers.TileOutputs[i];
      an::RayResult<double> result;
      result.RGBA = glm::dvec4(out.RGBA[0], out.RGBA[1], out.RGBA[2], out.RGBA[3]);
      result.Statistics.Samples = out.Samples;
      this->Store(buffers.TileX[i], buffers.TileY[i], result, stats);
    }
  }

  void Store(int x, int y, const an::RayResult<double>& result, ThreadStatistics& stats)
  {
    ++stats.Rays;
    if (!result.Error.empty())
    {
      if (stats.Failed++ == 0)
      {
        stats.FirstError = result.Error;
      }
    }
    float* pixel = this->Image + 4 * (static_cast<std::size_t>(y) * this->Geometry.Rays.Width + x);
    for (int c = 0; c < 4; ++c)
    {
      pixel[c] = static_cast<float>(result.RGBA[c]);
    }
    stats.Samples += result.Statistics.Samples;
    stats.MaximumSamples = std::max<vtkIdType>(stats.MaximumSamples, result.Statistics.Samples);
    stats.Rejected += result.Statistics.Rejected;
    stats.Cells += result.Statistics.Cells;
    stats.Pieces += result.Statistics.Pieces;
  }

  an::TrilinearVolume<double, Storage> Volume;
  const FrameGeometry& Geometry;
  const TransferFunction& TF;
  const an::EmptySpaceMap<double>* Map;
  const Method& Settings;
  float* Image;
  vtkSMPThreadLocal<ThreadStatistics>& Statistics;
  vtkSMPThreadLocal<RayBuffers>& Buffers;
  avos::WorkMonitor& Monitor;
  bool RaysPerLane = false;
  int TilesX = 0;
};

} // namespace

class vtkAdaptiveVolumeMapper::vtkInternals
{
public:
  // Data: the empty-space map's ranges.
  avos::EmptySpaceRanges Ranges;

  // Property: the transfer function and the blocks' visibility.
  TransferFunction TF;
  vtkMTimeType PropertyTime = 0;
  int OpacityModel = -1;
  double Voxel = 0.0;
  vtkTimeStamp ClassifyTime;
  std::size_t VisibleBlocks = 0;
  // The transfer function in pieces, built for a relative error (the alpha
  // model's share of the tolerance) when a piecewise method needs it.
  an::PiecewiseTransferFunction<double> Pieces;
  double PiecesRelativeError = 0.0;
  vtkTimeStamp PiecesTime;
  // The average projection's range (AverageAlongRay), rebuilt every frame.
  an::AverageRange<double> AverageRange;
  // The vectorised engine's inputs (RIEMANN): the scalars as the kernels
  // read them, and the transfer table, rebuilt with the classification.
  avos::EngineVolume EngineScalars;
  avos::engine::TransferTable EngineTable;
  vtkTimeStamp EngineTableTime;
  avos::engine::PiecewiseTable PieceTable;
  vtkTimeStamp PieceTableTime;

  // Frame: what the last image depends on.
  std::array<double, 16> Projection{};
  std::array<double, 16> VolumeMatrix{};
  std::array<int, 6> Viewport{ { 0, 0, 0, 0, 0, 0 } }; // origin, viewport and image sizes
  std::vector<float> ViewportDepth;                    // the depth buffer under the viewport
  std::vector<float> LastDepth;
  vtkMTimeType FrameMapperTime = 0;
  vtkMTimeType FrameClassifyTime = 0;
  vtkMTimeType FrameRangesTime = 0;
  bool HaveImage = false;
  // The last ray cast's image sample distance and time (auto-adjustment).
  double CastDistance = 1.0;
  double CastSeconds = 0.0;
  // What TraceRay re-casts: the last frame's data, method and map use.
  vtkSmartPointer<vtkDataArray> FrameScalars;
  Method FrameMethod;
  bool FrameSkipping = false;
  // The shading of the current frame (Method::Shading points here) and the
  // last cast's, as numbers: a light or coefficient change recasts.
  an::ShadingModel<double> Shading;
  std::vector<double> ShadingKey, FrameShadingKey;

  FrameGeometry Geometry;
  vtkNew<vtkImageData> Image;
  std::vector<std::uint16_t> Display;
  vtkSmartPointer<vtkRayCastImageDisplayHelper> DisplayHelper;
};

vtkStandardNewMacro(vtkAdaptiveVolumeMapper);

vtkAdaptiveVolumeMapper::vtkAdaptiveVolumeMapper()
  : Internals(new vtkInternals)
{
  this->Internals->DisplayHelper =
    vtkSmartPointer<vtkRayCastImageDisplayHelper>::Take(vtkRayCastImageDisplayHelper::New());
  if (this->Internals->DisplayHelper)
  {
    this->Internals->DisplayHelper->PreMultipliedColorsOn();
  }
}

vtkAdaptiveVolumeMapper::~vtkAdaptiveVolumeMapper() = default;

const char* vtkAdaptiveVolumeMapper::GetIntegrationMethodAsString()
{
  switch (this->IntegrationMethod)
  {
    case RIEMANN:
      return "Riemann";
    case ADAPTIVE_COUPLED:
      return "AdaptiveCoupled";
    case ADAPTIVE_DECOUPLED:
      return "AdaptiveDecoupled";
    case PIECEWISE_ADAPTIVE:
      return "PiecewiseAdaptive";
    default:
      return "Reference";
  }
}

vtkImageData* vtkAdaptiveVolumeMapper::GetRenderedImage()
{
  return this->Internals->Image;
}

vtkIdType vtkAdaptiveVolumeMapper::GetNumberOfBlocks()
{
  return static_cast<vtkIdType>(this->Internals->Ranges.GetMap().GetNumberOfBlocks());
}

vtkIdType vtkAdaptiveVolumeMapper::GetNumberOfVisibleBlocks()
{
  return static_cast<vtkIdType>(this->Internals->VisibleBlocks);
}

void vtkAdaptiveVolumeMapper::ReleaseGraphicsResources(vtkWindow* win)
{
  if (this->Internals->DisplayHelper)
  {
    this->Internals->DisplayHelper->ReleaseGraphicsResources(win);
  }
}

void vtkAdaptiveVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  vtkInternals& internals = *this->Internals;
  this->LastRenderReused = false;
  // Every early return below leaves an empty image and draws nothing.
  auto fail = [&]()
  {
    internals.Image->Initialize();
    internals.HaveImage = false;
    timer->StopTimer();
    this->LastRenderTime = timer->GetElapsedTime();
  };

  // Parameters.
  an::AdaptiveSettings<double> adaptive;
  adaptive.Tolerance = this->Tolerance;
  adaptive.InitialStep = this->InitialStep;
  adaptive.MinimumStep = this->MinimumStep;
  adaptive.MaximumStep = this->MaximumStep;
  adaptive.Coupling =
    this->IntegrationMethod == ADAPTIVE_DECOUPLED ? an::Strategy::Decoupled : an::Strategy::Coupled;
  const std::string invalid = adaptive.Validate();
  if (!invalid.empty())
  {
    vtkErrorMacro(<< "Invalid integration settings: " << invalid << " (tolerance "
                  << this->Tolerance << ", steps " << this->InitialStep << " / "
                  << this->MinimumStep << " / " << this->MaximumStep << ").");
    return fail();
  }
  // (The additive projection integrates the same pieces at the tolerance.)
  if (this->IntegrationMethod == PIECEWISE_ADAPTIVE ||
    this->BlendMode == vtkVolumeMapper::ADDITIVE_BLEND)
  {
    const std::string error = an::ValidatePiecewiseTolerance(this->Tolerance,
      this->OpacityModel == EXTINCTION_OPACITY ? an::OpacityModel::Extinction
                                               : an::OpacityModel::Alpha);
    if (!error.empty())
    {
      vtkErrorMacro(<< "Invalid tolerance " << this->Tolerance << ": " << error << ".");
      return fail();
    }
  }
  for (const double step :
    { this->SampleDistance, this->InitialStep, this->MinimumStep, this->MaximumStep })
  {
    if (!(step >= GetSmallestStep() && step <= GetLargestStep()))
    {
      vtkErrorMacro(<< "The sample distance and the steps must be within [" << GetSmallestStep()
                    << ", " << GetLargestStep() << "] voxel units; got sample distance "
                    << this->SampleDistance << ", steps " << this->InitialStep << " / "
                    << this->MinimumStep << " / " << this->MaximumStep << ".");
      return fail();
    }
  }
  if (this->BlendMode != vtkVolumeMapper::COMPOSITE_BLEND &&
    this->BlendMode != vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND &&
    this->BlendMode != vtkVolumeMapper::MINIMUM_INTENSITY_BLEND &&
    this->BlendMode != vtkVolumeMapper::AVERAGE_INTENSITY_BLEND &&
    this->BlendMode != vtkVolumeMapper::ADDITIVE_BLEND)
  {
    vtkErrorMacro(<< "Blend mode " << this->BlendMode
                  << " is not supported: composite, maximum, minimum and average intensity, "
                     "and additive are.");
    return fail();
  }

  // Input.
  if (!this->GetInput())
  {
    vtkErrorMacro(<< "No input.");
    return fail();
  }
  this->GetInputAlgorithm()->Update();
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  if (!input)
  {
    vtkErrorMacro(<< "The input must be a vtkImageData, not a " << this->GetInput()->GetClassName()
                  << ".");
    return fail();
  }
  int cellFlag = 0;
  vtkDataArray* scalars = vtkAbstractMapper::GetScalars(
    input, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag);
  int dims[3];
  input->GetDimensions(dims);
  if (!scalars)
  {
    vtkErrorMacro(<< "The input has no scalars to render.");
    return fail();
  }
  if (cellFlag)
  {
    vtkErrorMacro(<< "Cell scalars are not supported; use point scalars.");
    return fail();
  }
  if (scalars->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro(<< "Only single-component scalars are supported, not "
                  << scalars->GetNumberOfComponents() << " components.");
    return fail();
  }
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2 ||
    scalars->GetNumberOfTuples() != static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2])
  {
    vtkErrorMacro(<< "The input must have at least 2 points along each axis and one scalar per "
                     "point; its dimensions are "
                  << dims[0] << " x " << dims[1] << " x " << dims[2] << ".");
    return fail();
  }
  const double* spacing = input->GetSpacing();
  if (spacing[0] == 0.0 || spacing[1] == 0.0 || spacing[2] == 0.0 ||
    !std::isfinite(spacing[0] * spacing[1] * spacing[2]))
  {
    vtkErrorMacro(<< "The input's spacing must be non-zero and finite, not (" << spacing[0] << ", "
                  << spacing[1] << ", " << spacing[2] << ").");
    return fail();
  }

  // Grid -> world: the image's placement, then the volume's matrix.
  vtkNew<vtkMatrix4x4> gridToWorld;
  const double voxel = avos::GridToWorld(input, vol->GetMatrix(), gridToWorld);
  vtkNew<vtkMatrix4x4> worldToGrid;
  vtkMatrix4x4::Invert(gridToWorld, worldToGrid);
  if (!(voxel > 0.0) || !std::isfinite(voxel) || gridToWorld->Determinant() == 0.0)
  {
    vtkErrorMacro(<< "The volume's grid is degenerate in world space (zero spacing or a "
                     "singular volume matrix).");
    return fail();
  }

  // Clipping planes (world) and cropping (the volume's coordinates, as VTK's
  // mappers: origin and spacing) -> grid coordinates.
  an::ClipRegion<double> clip;
  const std::string planesError =
    avos::AddClippingPlanes(this->ClippingPlanes, gridToWorld->GetData(), clip);
  if (!planesError.empty())
  {
    vtkErrorMacro(<< planesError << ".");
    return fail();
  }
  if (this->Cropping)
  {
    vtkMatrix3x3* orientation = input->GetDirectionMatrix();
    if (!orientation->IsIdentity() || spacing[0] < 0.0 || spacing[1] < 0.0 || spacing[2] < 0.0)
    {
      vtkErrorMacro(<< "Cropping needs an input with positive spacing and no direction matrix "
                       "(its region planes are in the volume's axis-aligned coordinates).");
      return fail();
    }
    const double* origin = input->GetOrigin();
    const int* extent = input->GetExtent();
    double planes[6];
    for (int c = 0; c < 6; ++c)
    {
      const int a = c / 2;
      planes[c] = (this->CroppingRegionPlanes[c] - origin[a]) / spacing[a] - extent[2 * a];
    }
    clip.SetCropping(planes, this->CroppingRegionFlags);
  }
  const std::string unusable = clip.Validate();
  if (!unusable.empty())
  {
    vtkErrorMacro(<< "Unusable clipping or cropping: " << unusable << ".");
    return fail();
  }

  // Data -> empty-space ranges, when the scalars changed.
  if (!internals.Ranges.Update(scalars, dims))
  {
    vtkErrorMacro(<< "Unsupported scalar type " << scalars->GetDataTypeAsString() << ".");
    return fail();
  }
  if (internals.Ranges.GetNaNCount() > 0)
  {
    vtkErrorMacro(<< "The input has " << internals.Ranges.GetNaNCount()
                  << " NaN scalars; a volume with undefined values is not rendered.");
    return fail();
  }

  // Property -> transfer function and block visibility.
  vtkVolumeProperty* property = vol->GetProperty();
  // What the mapper does not honour is refused, never ignored.
  const std::string unsupported = avos::UnsupportedPropertySettings(property, true);
  if (!unsupported.empty())
  {
    vtkErrorMacro(<< unsupported << ".");
    return fail();
  }
  const bool shade = property->GetShade(0) != 0;
  internals.ShadingKey.clear();
  if (shade)
  {
    const std::string error = PrepareShading(ren, property, this->BlendMode,
      this->IntegrationMethod, internals.Shading, internals.ShadingKey);
    if (!error.empty())
    {
      vtkErrorMacro(<< "Cannot shade: " << error << ".");
      return fail();
    }
  }
  if (property->GetMTime() != internals.PropertyTime ||
    this->OpacityModel != internals.OpacityModel || voxel != internals.Voxel ||
    internals.ClassifyTime.GetMTime() < internals.Ranges.GetTime())
  {
    const std::string error = avos::TransferFunctionFromProperty(
      property, this->OpacityModel == EXTINCTION_OPACITY, voxel, internals.TF);
    if (!error.empty())
    {
      vtkErrorMacro(<< "Unusable transfer function: " << error << ".");
      internals.PropertyTime = 0;
      return fail();
    }
    internals.VisibleBlocks = internals.Ranges.GetMap().Classify(internals.TF);
    internals.PropertyTime = property->GetMTime();
    internals.OpacityModel = this->OpacityModel;
    internals.Voxel = voxel;
    internals.ClassifyTime.Modified();
  }

  // Transfer function -> pieces with polynomial extinction, for the
  // piecewise methods.
  // (A shaded reference is the adaptive one: the pieces' closed forms need an
  // emission that depends on the scalar alone.)
  const bool additive = this->BlendMode == vtkVolumeMapper::ADDITIVE_BLEND;
  const bool piecewise = this->IntegrationMethod == PIECEWISE_ADAPTIVE || additive ||
    (this->IntegrationMethod == REFERENCE && this->OpacityModel == EXTINCTION_OPACITY && !shade);
  if (piecewise)
  {
    // The relative error only matters in VTK's alpha model (the extinction
    // model's pieces are exact); the reference never uses the alpha model here.
    const double relativeError = this->IntegrationMethod == PIECEWISE_ADAPTIVE || additive
      ? an::PiecewiseRelativeError(this->Tolerance)
      : an::PiecewiseRelativeError(an::PiecewiseReferenceTolerance<double>());
    if (internals.PiecesTime.GetMTime() < internals.ClassifyTime.GetMTime() ||
      relativeError != internals.PiecesRelativeError)
    {
      const std::string error = internals.Pieces.Build(internals.TF, relativeError);
      if (!error.empty())
      {
        vtkErrorMacro(<< "The piecewise method cannot use this transfer function at tolerance "
                      << this->Tolerance << ": " << error << ".");
        internals.PiecesRelativeError = 0.0;
        return fail();
      }
      internals.PiecesRelativeError = relativeError;
      internals.PiecesTime.Modified();
    }
  }

  // The data's range: bounds of the trilinear field, and the projections'
  // normalisation.
  double dataRange[2];
  scalars->GetRange(dataRange, 0);
  // The average projection's range, within the data's (VTK's default range
  // is the whole float line), as pieces that mark it.
  if (this->BlendMode == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND)
  {
    const double r0 = std::max(this->AverageIPScalarRange[0], dataRange[0]);
    const double r1 = std::min(this->AverageIPScalarRange[1], dataRange[1]);
    // A range beside the data's holds no ray: zero width.
    const std::string error = internals.AverageRange.Build(internals.TF, r0, std::max(r0, r1));
    if (!error.empty())
    {
      vtkErrorMacro(<< "Unusable average intensity range [" << this->AverageIPScalarRange[0] << ", "
                    << this->AverageIPScalarRange[1] << "]: " << error << ".");
      return fail();
    }
  }

  // Scalars and transfer function -> the vectorised engine's copies (RIEMANN;
  // volumes beyond its 32-bit indices take the scalar sum), and the scalars
  // alone for the piecewise method's cells where they are 8- or 16-bit (no
  // float copy: the cells' kernel does not take it).
  // (Shaded sums take the scalar path: the kernels do not shade.)
  const bool riemannEngine = this->IntegrationMethod == RIEMANN && !shade;
  const bool cellEngine = this->IntegrationMethod == PIECEWISE_ADAPTIVE &&
    avos::EngineVolume::StoredType(scalars->GetDataType()) != avos::engine::Volume::Type::Float32;
  const avos::engine::Volume* engineScalars =
    riemannEngine || cellEngine ? internals.EngineScalars.Update(scalars, dims) : nullptr;
  const avos::engine::Volume* engine = riemannEngine ? engineScalars : nullptr;
  if (engine && internals.EngineTableTime.GetMTime() < internals.ClassifyTime.GetMTime())
  {
    const std::string error = internals.EngineTable.Build(internals.TF);
    if (!error.empty())
    {
      vtkErrorMacro(<< "Unusable transfer function: " << error << ".");
      return fail();
    }
    internals.EngineTableTime.Modified();
  }
  // The pieces' table for the piecewise method's ray-per-lane integrator,
  // where it can read the scalars.
  const bool pieceLanes = cellEngine && engineScalars &&
    avos::engine::ValidatePiecewiseRays(*engineScalars, internals.Pieces).empty();
  if (pieceLanes && internals.PieceTableTime.GetMTime() < internals.PiecesTime.GetMTime())
  {
    const std::string error = internals.PieceTable.Build(internals.Pieces);
    if (!error.empty())
    {
      vtkErrorMacro(<< "Unusable transfer function: " << error << ".");
      return fail();
    }
    internals.PieceTableTime.Modified();
  }

  // Frame: camera, viewport, image size and depth buffer.
  int viewportWidth, viewportHeight, x0, y0;
  ren->GetTiledSizeAndOrigin(&viewportWidth, &viewportHeight, &x0, &y0);
  if (viewportWidth < 1 || viewportHeight < 1)
  {
    return fail();
  }
  double distance = this->ImageSampleDistance;
  if (this->AutoAdjustSampleDistances)
  {
    // What fits the renderer's time for the volume, the cast time taken as
    // proportional to the number of rays (1 / distance^2).
    const double budget = vol->GetAllocatedRenderTime();
    distance = internals.CastDistance;
    if (internals.CastSeconds > 0.0 && budget > 0.0)
    {
      distance *= std::sqrt(internals.CastSeconds / budget);
    }
    // Within 10 % of the last distance the last one is kept, so that timing
    // noise does not resize (and cast again) an unchanged frame; at the
    // minimum it is exact, so a still render is at full resolution.
    if (distance > this->MinimumImageSampleDistance &&
      std::abs(distance - internals.CastDistance) <= 0.1 * internals.CastDistance)
    {
      distance = internals.CastDistance;
    }
    distance = std::min(std::max(distance, this->MinimumImageSampleDistance),
      std::max(this->MinimumImageSampleDistance, this->MaximumImageSampleDistance));
  }
  const int width = std::max(1, static_cast<int>(std::ceil(viewportWidth / distance - 1e-9)));
  const int height = std::max(1, static_cast<int>(std::ceil(viewportHeight / distance - 1e-9)));
  FrameGeometry& g = internals.Geometry;
  g.Rays.Width = width;
  g.Rays.Height = height;
  std::copy(dims, dims + 3, g.Rays.Dimensions);
  g.Rays.Voxel = voxel;
  internals.ViewportDepth.resize(static_cast<std::size_t>(viewportWidth) * viewportHeight);
  if (!ren->GetRenderWindow()->GetZbufferData(
        x0, y0, x0 + viewportWidth - 1, y0 + viewportHeight - 1, internals.ViewportDepth.data()))
  {
    std::fill(internals.ViewportDepth.begin(), internals.ViewportDepth.end(), 1.0f);
  }
  // Each ray stops at the depth under its own centre.
  g.Depth.resize(static_cast<std::size_t>(width) * height);
  g.Rays.Depth = g.Depth.data();
  for (int y = 0; y < height; ++y)
  {
    const int vy =
      std::min(static_cast<int>((y + 0.5) * viewportHeight / height), viewportHeight - 1);
    for (int x = 0; x < width; ++x)
    {
      const int vx =
        std::min(static_cast<int>((x + 0.5) * viewportWidth / width), viewportWidth - 1);
      g.Depth[static_cast<std::size_t>(y) * width + x] =
        internals.ViewportDepth[static_cast<std::size_t>(vy) * viewportWidth + vx];
    }
  }
  vtkMatrix4x4* projection = ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(
    ren->GetTiledAspectRatio(), -1, 1);
  std::array<double, 16> projectionValues, volumeValues;
  std::copy(projection->GetData(), projection->GetData() + 16, projectionValues.begin());
  std::copy(vol->GetMatrix()->GetData(), vol->GetMatrix()->GetData() + 16, volumeValues.begin());
  const std::array<int, 6> viewport{ { x0, y0, viewportWidth, viewportHeight, width, height } };

  if (internals.HaveImage && projectionValues == internals.Projection &&
    volumeValues == internals.VolumeMatrix && viewport == internals.Viewport &&
    g.Depth == internals.LastDepth && clip == g.Clip &&
    this->GetMTime() == internals.FrameMapperTime &&
    internals.ClassifyTime.GetMTime() == internals.FrameClassifyTime &&
    internals.Ranges.GetTime() == internals.FrameRangesTime &&
    internals.ShadingKey == internals.FrameShadingKey)
  {
    this->LastRenderReused = true;
  }
  else
  {
    vtkNew<vtkMatrix4x4> ndcToWorld;
    vtkMatrix4x4::Invert(projection, ndcToWorld);
    std::copy(ndcToWorld->GetData(), ndcToWorld->GetData() + 16, g.Rays.NDCToWorld);
    std::copy(worldToGrid->GetData(), worldToGrid->GetData() + 16, g.Rays.WorldToGrid);
    g.Clip = clip;

    // Cast only the box's footprint on the screen (all of it when a corner
    // is behind the eye).
    g.Rect[0] = width;
    g.Rect[1] = 0;
    g.Rect[2] = height;
    g.Rect[3] = 0;
    bool footprint = true;
    for (int c = 0; c < 8 && footprint; ++c)
    {
      const glm::dvec4 corner((c & 1) * (dims[0] - 1.0), ((c >> 1) & 1) * (dims[1] - 1.0),
        ((c >> 2) & 1) * (dims[2] - 1.0), 1.0);
      const glm::dvec4 world = Multiply(gridToWorld->GetData(), corner);
      const glm::dvec4 onScreen = Multiply(projection->GetData(), world);
      if (!(onScreen.w > 0.0))
      {
        footprint = false;
        break;
      }
      const double px = (onScreen.x / onScreen.w + 1.0) * 0.5 * width;
      const double py = (onScreen.y / onScreen.w + 1.0) * 0.5 * height;
      g.Rect[0] = std::min(g.Rect[0], static_cast<int>(std::max(std::floor(px), -1.0)));
      g.Rect[1] = std::max(g.Rect[1], static_cast<int>(std::min(std::ceil(px) + 1, width + 1.0)));
      g.Rect[2] = std::min(g.Rect[2], static_cast<int>(std::max(std::floor(py), -1.0)));
      g.Rect[3] = std::max(g.Rect[3], static_cast<int>(std::min(std::ceil(py) + 1, height + 1.0)));
    }
    if (!footprint)
    {
      g.Rect[0] = g.Rect[2] = 0;
      g.Rect[1] = width;
      g.Rect[3] = height;
    }
    g.Rect[0] = std::max(g.Rect[0], 0);
    g.Rect[2] = std::max(g.Rect[2], 0);
    g.Rect[1] = std::min(g.Rect[1], width);
    g.Rect[3] = std::min(g.Rect[3], height);

    // The image.
    internals.Image->SetDimensions(width, height, 1);
    vtkNew<vtkFloatArray> rgba;
    rgba->SetName("RGBA");
    rgba->SetNumberOfComponents(4);
    rgba->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
    rgba->Fill(0.0);
    internals.Image->GetPointData()->SetScalars(rgba);
    float* image = rgba->GetPointer(0);

    Method method;
    method.Kind = this->IntegrationMethod;
    method.Blend = this->BlendMode;
    method.Adaptive = adaptive;
    // Trilinear values never leave the data's range.
    method.Adaptive.FieldMinimum = dataRange[0];
    method.Adaptive.FieldMaximum = dataRange[1];
    method.SampleDistance = this->SampleDistance;
    method.TerminationBound = 0.2 * this->Tolerance;
    method.Range = &internals.AverageRange;
    method.ScalarMinimum = dataRange[0];
    // A constant volume: any positive span gives n = 0 everywhere.
    method.ScalarMaximum = dataRange[1] > dataRange[0] ? dataRange[1] : dataRange[0] + 1.0;
    method.Pieces = piecewise ? &internals.Pieces : nullptr;
    method.EngineVolume = engine;
    method.EngineTable = engine ? &internals.EngineTable : nullptr;
    method.Kernels = avos::engine::PieceKernels(cellEngine ? engineScalars : nullptr);
    method.PieceTable = pieceLanes ? &internals.PieceTable : nullptr;
    if (shade)
    {
      method.Shading = &internals.Shading;
      for (int r = 0; r < 3; ++r)
      {
        for (int c = 0; c < 3; ++c)
        {
          // glm is column-major: m[column][row]. The normal matrix is the
          // transpose of world-to-grid's linear part.
          method.NormalMatrix[r][c] = g.Rays.WorldToGrid[4 * r + c];
        }
      }
      method.GridToWorld = glm::inverse(glm::transpose(method.NormalMatrix));
    }

    vtkSMPThreadLocal<ThreadStatistics> statistics;
    vtkSMPThreadLocal<RayBuffers> buffers;
    const an::EmptySpaceMap<double>* map =
      this->EmptySpaceSkipping ? &internals.Ranges.GetMap() : nullptr;
    bool aborted = false;
    auto cast = [&](auto* data)
    {
      using Storage = std::remove_const_t<std::remove_pointer_t<decltype(data)>>;
      const vtkIdType tiles =
        static_cast<vtkIdType>((g.Rect[3] - g.Rect[2] + TileSize - 1) / TileSize) *
        ((g.Rect[1] - g.Rect[0] + TileSize - 1) / TileSize);
      avos::WorkMonitor monitor;
      RayCaster<Storage> caster(
        data, g, internals.TF, map, method, image, statistics, buffers, monitor);
      // Progress and the render window's abort check (an interactor's, or
      // avos-render's Ctrl-C) every WorkMonitor::Interval, whatever the SMP
      // backend; an abort takes effect within that plus one tile per thread.
      aborted = !monitor.Run(
                  tiles, [&] { vtkSMPTools::For(0, tiles, 1, caster); },
                  [this, ren](double fraction)
                  {
                    this->UpdateProgress(fraction);
                    return ren->GetRenderWindow()->CheckAbortStatus() != 0;
                  }) ||
        ren->GetRenderWindow()->CheckAbortStatus() != 0;
      if (!aborted)
      {
        this->UpdateProgress(1.0);
      }
    };
    // (With every block transparent nothing composites; the projections
    // still show the volume: an opaque black or grey.)
    if (!map || internals.VisibleBlocks > 0 || this->BlendMode != vtkVolumeMapper::COMPOSITE_BLEND)
    {
      switch (scalars->GetDataType())
      {
        vtkTemplateMacro(cast(static_cast<const VTK_TT*>(scalars->GetVoidPointer(0))));
      }
    }
    if (aborted)
    {
      return fail();
    }

    ThreadStatistics total;
    for (const ThreadStatistics& s : statistics)
    {
      total.Rays += s.Rays;
      total.Samples += s.Samples;
      total.MaximumSamples = std::max(total.MaximumSamples, s.MaximumSamples);
      total.Rejected += s.Rejected;
      total.Cells += s.Cells;
      total.Pieces += s.Pieces;
      total.Failed += s.Failed;
      if (total.FirstError.empty())
      {
        total.FirstError = s.FirstError;
      }
    }
    if (total.Failed > 0)
    {
      // No silent holes: the frame is refused with what went wrong.
      vtkErrorMacro(<< total.Failed << " ray(s) could not be integrated: " << total.FirstError
                    << ".");
      return fail();
    }
    this->RaysCast = total.Rays;
    this->MeanSamplesPerRay =
      total.Rays > 0 ? static_cast<double>(total.Samples) / static_cast<double>(total.Rays) : 0.0;
    this->MaximumSamplesPerRay = total.MaximumSamples;
    this->RejectedSteps = total.Rejected;
    const double rays = static_cast<double>(std::max<vtkIdType>(total.Rays, 1));
    this->MeanCellsPerRay = static_cast<double>(total.Cells) / rays;
    this->MeanPiecesPerRay = static_cast<double>(total.Pieces) / rays;

    // 16-bit premultiplied RGBA for the display helper, in parallel (a
    // serial pass over the image weighed on two threads). v * 65535 + 0.5
    // is exact in float for v in [0, 1] (at most 8 fractional bits there),
    // so truncating it rounds as lround did; NaN gives 0.
    internals.Display.resize(4 * static_cast<std::size_t>(width) * height);
    std::uint16_t* display = internals.Display.data();
    vtkSMPTools::For(0, static_cast<vtkIdType>(internals.Display.size()),
      [display, image](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType i = begin; i < end; ++i)
        {
          const float v = image[i] > 0.0f ? std::min(image[i], 1.0f) : 0.0f;
          display[i] = static_cast<std::uint16_t>(v * 65535.0f + 0.5f);
        }
      });

    internals.Projection = projectionValues;
    internals.VolumeMatrix = volumeValues;
    internals.Viewport = viewport;
    internals.LastDepth = g.Depth;
    internals.FrameMapperTime = this->GetMTime();
    internals.FrameClassifyTime = internals.ClassifyTime.GetMTime();
    internals.FrameRangesTime = internals.Ranges.GetTime();
    internals.HaveImage = true;
    internals.FrameScalars = scalars;
    internals.FrameMethod = method;
    internals.FrameSkipping = map != nullptr;
    internals.FrameShadingKey = internals.ShadingKey;
    internals.CastDistance = distance;
    timer->StopTimer();
    internals.CastSeconds = timer->GetElapsedTime();
    this->LastImageSampleDistance = distance;
  }

  if (internals.DisplayHelper)
  {
    int size[2] = { width, height };
    int origin[2] = { 0, 0 };
    // In front of everything: occlusion by opaque geometry is already in
    // the image (rays stop at the depth buffer).
    internals.DisplayHelper->RenderTexture(
      vol, ren, size, size, size, origin, 1e-6f, internals.Display.data());
  }
  else
  {
    vtkErrorMacro(<< "No ray cast image display helper: is VTK::RenderingVolumeOpenGL2 linked?");
  }
  timer->StopTimer();
  this->LastRenderTime = timer->GetElapsedTime();
}

bool vtkAdaptiveVolumeMapper::TraceRay(int x, int y, vtkTable* steps)
{
  if (!steps)
  {
    vtkErrorMacro(<< "TraceRay needs a table to fill.");
    return false;
  }
  steps->Initialize();
  vtkInternals& internals = *this->Internals;
  const FrameGeometry& g = internals.Geometry;
  if (!internals.HaveImage)
  {
    vtkErrorMacro(<< "TraceRay re-casts a pixel of the last render: there is none.");
    return false;
  }
  if (internals.FrameMethod.Kind == REFERENCE)
  {
    vtkErrorMacro(<< "The reference method records no steps to trace.");
    return false;
  }
  if (x < 0 || y < 0 || x >= g.Rays.Width || y >= g.Rays.Height)
  {
    vtkErrorMacro(<< "Pixel (" << x << ", " << y << ") is outside the " << g.Rays.Width << " x "
                  << g.Rays.Height << " image.");
    return false;
  }
  std::vector<an::StepRecord<double>> records;
  an::RayResult<double> result;
  RayBuffers buffers;
  bool hit = false;
  auto trace = [&](auto* data)
  {
    using Storage = std::remove_const_t<std::remove_pointer_t<decltype(data)>>;
    const an::TrilinearVolume<double, Storage> volume(data, g.Rays.Dimensions);
    hit = IntegratePixel(volume, g, internals.TF,
      internals.FrameSkipping ? &internals.Ranges.GetMap() : nullptr, internals.FrameMethod, x, y,
      buffers, result, &records);
  };
  vtkDataArray* scalars = internals.FrameScalars;
  switch (scalars->GetDataType())
  {
    vtkTemplateMacro(trace(static_cast<const VTK_TT*>(scalars->GetVoidPointer(0))));
  }
  const char* names[3] = { "Start", "Length", "Opacity" };
  vtkNew<vtkDoubleArray> columns[3];
  for (int c = 0; c < 3; ++c)
  {
    columns[c]->SetName(names[c]);
    columns[c]->SetNumberOfValues(static_cast<vtkIdType>(records.size()));
  }
  for (std::size_t i = 0; i < records.size(); ++i)
  {
    const auto row = static_cast<vtkIdType>(i);
    columns[0]->SetValue(row, records[i].Start);
    columns[1]->SetValue(row, records[i].Length);
    columns[2]->SetValue(row, records[i].Opacity);
  }
  for (auto& column : columns)
  {
    steps->AddColumn(column);
  }
  return hit;
}

void vtkAdaptiveVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IntegrationMethod: " << this->GetIntegrationMethodAsString() << "\n";
  os << indent << "OpacityModel: " << (this->OpacityModel == VTK_OPACITY ? "VTK" : "Extinction")
     << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "InitialStep: " << this->InitialStep << "\n";
  os << indent << "MinimumStep: " << this->MinimumStep << "\n";
  os << indent << "MaximumStep: " << this->MaximumStep << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "EmptySpaceSkipping: " << this->EmptySpaceSkipping << "\n";
  os << indent << "ImageSampleDistance: " << this->ImageSampleDistance << "\n";
  os << indent << "MinimumImageSampleDistance: " << this->MinimumImageSampleDistance << "\n";
  os << indent << "MaximumImageSampleDistance: " << this->MaximumImageSampleDistance << "\n";
  os << indent << "AutoAdjustSampleDistances: " << this->AutoAdjustSampleDistances << "\n";
  os << indent << "LastImageSampleDistance: " << this->LastImageSampleDistance << "\n";
  os << indent << "LastRenderTime: " << this->LastRenderTime << "\n";
  os << indent << "RaysCast: " << this->RaysCast << "\n";
  os << indent << "MeanSamplesPerRay: " << this->MeanSamplesPerRay << "\n";
  os << indent << "MaximumSamplesPerRay: " << this->MaximumSamplesPerRay << "\n";
  os << indent << "RejectedSteps: " << this->RejectedSteps << "\n";
  os << indent << "MeanCellsPerRay: " << this->MeanCellsPerRay << "\n";
  os << indent << "MeanPiecesPerRay: " << this->MeanPiecesPerRay << "\n";
  os << indent << "LastRenderReused: " << this->LastRenderReused << "\n";
}
