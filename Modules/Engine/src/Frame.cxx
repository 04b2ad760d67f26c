#include "avos/engine/Frame.h"

#include "avos/engine/EmptySpace.h"
#include "avos/numerics/Extremum.h"
#include "avos/numerics/PiecewiseGradientOpacity.h"
#include "avos/numerics/PiecewiseShading.h"
#include "avos/numerics/Volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

namespace avos
{
namespace engine
{
namespace
{
namespace an = avos::numerics;
using Segments = std::vector<an::Interval<double>>;
constexpr int TileSize = FrameCaster::TileSize;

// Calls f(data) with the scalars as a pointer to their type.
template <typename F>
void DispatchScalars(const Scalars& scalars, F&& f)
{
  switch (scalars.Type)
  {
    case ScalarType::Int8:
      return f(static_cast<const std::int8_t*>(scalars.Data));
    case ScalarType::UInt8:
      return f(static_cast<const std::uint8_t*>(scalars.Data));
    case ScalarType::Int16:
      return f(static_cast<const std::int16_t*>(scalars.Data));
    case ScalarType::UInt16:
      return f(static_cast<const std::uint16_t*>(scalars.Data));
    case ScalarType::Int32:
      return f(static_cast<const std::int32_t*>(scalars.Data));
    case ScalarType::UInt32:
      return f(static_cast<const std::uint32_t*>(scalars.Data));
    case ScalarType::Int64:
      return f(static_cast<const std::int64_t*>(scalars.Data));
    case ScalarType::UInt64:
      return f(static_cast<const std::uint64_t*>(scalars.Data));
    case ScalarType::Float32:
      return f(static_cast<const float*>(scalars.Data));
    case ScalarType::Float64:
      return f(static_cast<const double*>(scalars.Data));
  }
}

// Whether a volume type is a mixture's components (Mixture.h).
template <typename VolumeT>
struct IsMixture : std::false_type
{
};
template <typename VolumeT>
struct IsMixture<an::ComponentVolumes<double, VolumeT>> : std::true_type
{
};

// The frame as it is cast: a mixture of which one component alone shows
// (MixtureTransferFunction::GetSingle, PiecewiseMixture::GetSingle) is
// that component's medium, so its frame is a single component's, the
// component read in place (it takes the single component's kernels and
// lanes); any other frame as it is.
struct Resolved
{
  Scalars TheScalars;
  FrameMethod Method;

  Resolved(const Scalars& scalars, const FrameMethod& method)
    : TheScalars(scalars)
    , Method(method)
  {
    const int k = scalars.Components > 1 && method.Mixture && scalars.Data
      ? method.Mixture->GetSingleComponent()
      : -1;
    const bool piecewise = method.MixturePieces != nullptr;
    if (k < 0 || (piecewise && method.MixturePieces->GetSingleComponent() != k) ||
      method.Mixture->GetNumberOfComponents() != scalars.Components)
    {
      return; // (Validate says what is wrong, if anything)
    }
    DispatchScalars(scalars, [&](const auto* data) { this->TheScalars.Data = data + k; });
    this->TheScalars.Stride = scalars.GetStride();
    this->TheScalars.Components = 1;
    this->Method.TF = method.Mixture->GetSingle();
    this->Method.Pieces = piecewise ? method.MixturePieces->GetSingle() : nullptr;
    this->Method.Mixture = nullptr;
    this->Method.MixturePieces = nullptr;
  }
};

// Calls f(volume) with the field of the scalars: the trilinear interpolant,
// a field constant per cell, or cell scalars between their centres
// (avos/numerics/Volume.h); with several components, each component's field
// (ComponentVolumes).
template <typename F>
void DispatchVolume(const Scalars& scalars, F&& f)
{
  DispatchScalars(scalars,
    [&](const auto* data)
    {
      using Storage = std::remove_const_t<std::remove_pointer_t<decltype(data)>>;
      using Constant = an::CellConstantVolume<double, Storage>;
      const int n = scalars.Components, stride = scalars.GetStride();
      const int* dims = scalars.Dimensions;
      // make(k) is component k's field.
      auto with = [&](auto make)
      {
        if (n == 1)
        {
          return f(make(0));
        }
        return f(an::ComponentVolumes<double, decltype(make(0))>(n, make));
      };
      switch (scalars.Field)
      {
        case ScalarField::Trilinear:
          return with(
            [&](int k) { return an::TrilinearVolume<double, Storage>(data + k, dims, stride); });
        case ScalarField::Nearest:
          return with([&](int k)
            { return Constant(data + k, dims, Constant::Layout::NearestPoints, stride); });
        case ScalarField::Cells:
          return with(
            [&](int k) { return Constant(data + k, dims, Constant::Layout::Cells, stride); });
        case ScalarField::CellCentres:
          return with(
            [&](int k) { return an::CellCentredVolume<double, Storage>(data + k, dims, stride); });
      }
    });
}

// The medium the sampled methods classify with: the transfer function, or
// a mixture's.
template <typename VolumeT>
const an::TransferFunction<double>& MediumOf(const FrameMethod& method, const VolumeT&)
{
  return *method.TF;
}
template <typename VolumeT>
const an::MixtureTransferFunction<double>& MediumOf(
  const FrameMethod& method, const an::ComponentVolumes<double, VolumeT>&)
{
  return *method.Mixture;
}

// Whether the volume's walk coordinates (ToWalk: the same t) are the point
// grid's, whose cells the empty-space map's blocks hold.
template <typename VolumeT>
bool WalksPointCells(const VolumeT& volume)
{
  return volume.ToWalk(glm::dvec3(1.0)) == glm::dvec3(1.0);
}

glm::dvec4 Multiply(const double m[16], const glm::dvec4& p)
{
  glm::dvec4 r;
  for (int i = 0; i < 4; ++i)
  {
    r[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3] * p[3];
  }
  return r;
}

// Whether the Riemann sums run in the kernel's float lanes: its volume is
// given and the rays are neither shaded nor scaled by gradient opacity (the
// kernels do neither).
bool RiemannKernel(const FrameMethod& method)
{
  return method.EngineVolume && !method.Shading && !method.GradientOpacity;
}

// The shading of the ray start + t direction (grid coordinates): towards
// the viewer and the ray itself in world space.
an::RayShading<double> ShadingOf(
  const FrameMethod& method, const glm::dvec3& start, const glm::dvec3& direction)
{
  const glm::dvec3 worldDirection = method.GridToWorld * direction;
  return { method.Shading, method.NormalMatrix, -glm::normalize(worldDirection),
    method.GridToWorld * start + method.GridToWorldOffset, worldDirection };
}

// Calls f(field) with the ray start + t direction's field (grid coordinates):
// shaded when the method shades, the scalar alone otherwise.
// Calls f(field) with `field`, its extinction scaled by the method's gradient
// opacity where it has one.
template <typename Field, typename F>
an::RayResult<double> WithOpacity(const FrameMethod& method, const Field& field, F&& f)
{
  if (method.GradientOpacity)
  {
    return f(an::GradientOpacityField<double, Field>{ field, method.GradientOpacity });
  }
  return f(field);
}

template <typename VolumeT, typename F>
an::RayResult<double> WithField(const VolumeT& volume, const FrameMethod& method,
  const glm::dvec3& start, const glm::dvec3& direction, F&& f)
{
  // (Validate refuses shaded mixtures, and their gradient opacity.)
  if constexpr (!IsMixture<VolumeT>::value)
  {
    if (method.Shading)
    {
      return WithOpacity(method,
        an::ShadedRayField<double, VolumeT>{
          volume, start, direction, ShadingOf(method, start, direction) },
        f);
    }
    return WithOpacity(method, an::RayField<double, VolumeT>{ volume, start, direction }, f);
  }
  else
  {
    return f(an::RayField<double, VolumeT>{ volume, start, direction });
  }
}

// The Riemann sum over the kept parts of a ray, each its own ray from its
// entry (as VTK's mappers start a clipped ray at the plane), front to back;
// `segments` are the visible ones of [0, D].
template <typename VolumeT>
void ClippedRiemann(const VolumeT& volume, const FrameMethod& method, const glm::dvec3& origin,
  const glm::dvec3& direction, const Segments& segments, RayScratch& scratch,
  an::RayResult<double>& result, std::vector<an::StepRecord<double>>* steps)
{
  const auto& tf = MediumOf(method, volume);
  // The sums' own termination test, on the whole ray's transmittance.
  const double stop = method.TerminationBound / std::max(1.0, tf.GetMaximumColor());
  glm::dvec3 color(0.0);
  double T = 1.0;
  for (const an::Interval<double>& part : scratch.Kept)
  {
    if (T <= stop)
    {
      break;
    }
    scratch.Clipped.clear();
    for (const an::Interval<double>& v : segments)
    {
      const double a = std::max(v.Begin, part.Begin), b = std::min(v.End, part.End);
      if (a < b)
      {
        scratch.Clipped.push_back({ a - part.Begin, b - part.Begin });
      }
    }
    if (scratch.Clipped.empty())
    {
      continue;
    }
    const glm::dvec3 start = origin + part.Begin * direction;
    const double D = part.End - part.Begin;
    // What is left of the bound after the transmittance spent before.
    const double bound = method.TerminationBound > 0.0 ? method.TerminationBound / T : 0.0;
    const std::size_t recorded = steps ? steps->size() : 0;
    glm::dvec4 rgba;
    if (RiemannKernel(method) && !steps)
    {
      RayOutput out;
      CastRiemann(*method.EngineVolume, *method.EngineTable, &start.x, &direction.x, D,
        method.SampleDistance, scratch.Clipped.data(), scratch.Clipped.size(), bound, out);
      rgba = glm::dvec4(out.RGBA[0], out.RGBA[1], out.RGBA[2], out.RGBA[3]);
      result.Statistics.Samples += out.Samples;
    }
    else
    {
      const an::RayResult<double> r = WithField(volume, method, start, direction,
        [&](const auto& field)
        {
          return an::IntegrateRiemann(field, tf, D, method.SampleDistance,
            an::RiemannForm::Exponential, scratch.Clipped.data(), scratch.Clipped.size(), bound,
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

// The additive and average projections, shown as VTK's GPU mapper shows
// them: grey, clamped to [0, 1], opaque wherever the ray meets the volume
// (the average: the range).
template <typename VolumeT>
void Accumulate(const VolumeT& volume, const FrameMethod& method, const glm::dvec3& origin,
  const glm::dvec3& direction, const Segments& segments, an::RayResult<double>& result)
{
  an::Accumulation<double> a;
  if (method.Mode == Blend::Additive)
  {
    a = an::AdditiveAlongRay(volume, origin, direction, segments.data(), segments.size(),
      *method.Pieces, method.ScalarMinimum, method.ScalarMaximum);
    a.Length = 1.0;
  }
  else
  {
    a = an::AverageAlongRay(volume, origin, direction, segments.data(), segments.size(),
      *method.Range, *method.TF, method.SampleDistance, method.ScalarMinimum, method.ScalarMaximum,
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
}

// The exact extremum of the ray's scalar, shown as VTK's mappers show a
// projection: its colour times the opacity function's value there.
template <typename VolumeT>
void Extremum(const VolumeT& volume, const FrameMethod& method, const glm::dvec3& origin,
  const glm::dvec3& direction, double D, RayScratch& scratch, an::RayResult<double>& result)
{
  const Segments& segments = scratch.Visible;
  const bool maximum = method.Mode == Blend::Maximum;
  // Blocks best first where the map gives their ranges (its blocks are
  // the volume's cells: the ray is the same in both).
  const an::RayExtremum<double> e = method.Map && WalksPointCells(volume)
    ? an::ExtremumByBlocks(volume, *method.Map, origin, direction, D, SegmentPad, segments.data(),
        segments.size(), maximum, scratch.Spans)
    : an::ExtremumAlongRay(volume, origin, direction, segments.data(), segments.size(), maximum);
  if (e.Found)
  {
    const an::TransferFunction<double>& tf = *method.TF;
    const double alpha = std::min(std::max(tf.GetOpacityValue(e.Value), 0.0), 1.0);
    result.RGBA = glm::dvec4(tf.GetColor(e.Value) * alpha, alpha);
  }
  result.Statistics.Cells = e.Cells;
  result.Statistics.Samples = e.Cells;
}

// The piecewise method with the method's gradient opacity (and shading)
// over `segments` within `tolerance`.
template <typename VolumeT>
an::RayResult<double> PiecewiseGradientOpacity(const VolumeT& volume, const FrameMethod& method,
  const glm::dvec3& origin, const glm::dvec3& direction, const Segments& segments, double tolerance,
  std::vector<an::StepRecord<double>>* steps)
{
  const an::RayShading<double> shading =
    method.Shading ? ShadingOf(method, origin, direction) : an::RayShading<double>{};
  return an::IntegratePiecewiseGradientOpacity(volume, origin, direction, segments.data(),
    segments.size(), *method.Pieces, tolerance, *method.GradientOpacity,
    method.Shading ? &shading : nullptr, true, steps);
}

// The composite integral of the ray over `segments` by the method.
template <typename VolumeT>
void Composite(const VolumeT& volume, const FrameMethod& method, const glm::dvec3& origin,
  const glm::dvec3& direction, double D, const Segments& segments, an::RayResult<double>& result,
  std::vector<an::StepRecord<double>>* steps)
{
  const an::TransferFunction<double>& tf = *method.TF;
  switch (method.Kind)
  {
    case Integration::Riemann:
      if (RiemannKernel(method) && !steps)
      {
        // The same sum in float SIMD lanes (within 1e-4, avos/engine/Riemann.h).
        RayOutput out;
        CastRiemann(*method.EngineVolume, *method.EngineTable, &origin.x, &direction.x, D,
          method.SampleDistance, segments.data(), segments.size(), method.TerminationBound, out);
        result.RGBA = glm::dvec4(out.RGBA[0], out.RGBA[1], out.RGBA[2], out.RGBA[3]);
        result.Statistics.Samples = out.Samples;
        return;
      }
      result = WithField(volume, method, origin, direction,
        [&](const auto& field)
        {
          return an::IntegrateRiemann(field, tf, D, method.SampleDistance,
            an::RiemannForm::Exponential, segments.data(), segments.size(), method.TerminationBound,
            steps);
        });
      return;
    case Integration::Reference:
      if (method.Pieces && method.GradientOpacity)
      {
        result = PiecewiseGradientOpacity(volume, method, origin, direction, segments,
          an::PiecewiseReferenceTolerance<double>(), steps);
        return;
      }
      if (method.Pieces)
      {
        const double tolerance = an::PiecewiseReferenceTolerance<double>();
        result = method.Shading
          ? an::IntegratePiecewiseShaded(volume, origin, direction, segments.data(),
              segments.size(), *method.Pieces, tolerance, ShadingOf(method, origin, direction))
          : an::IntegratePiecewise(volume, origin, direction, segments.data(), segments.size(),
              *method.Pieces, tolerance);
        return;
      }
      result = WithField(volume, method, origin, direction,
        [&](const auto& field)
        { return an::IntegrateReference(field, tf, segments.data(), segments.size()); });
      return;
    case Integration::Piecewise:
      if (method.GradientOpacity)
      {
        result = PiecewiseGradientOpacity(
          volume, method, origin, direction, segments, method.Adaptive.Tolerance, steps);
        return;
      }
      if (method.Shading)
      {
        result = an::IntegratePiecewiseShaded(volume, origin, direction, segments.data(),
          segments.size(), *method.Pieces, method.Adaptive.Tolerance,
          ShadingOf(method, origin, direction), true, steps);
        return;
      }
      // Its cells' and pieces' batches in SIMD lanes (avos/engine/PieceKernels.h).
      result = an::IntegratePiecewise(volume, origin, direction, segments.data(), segments.size(),
        *method.Pieces, method.Adaptive.Tolerance, true, steps, method.Kernels);
      return;
    case Integration::AdaptiveCoupled:
    case Integration::AdaptiveDecoupled:
      result = WithField(volume, method, origin, direction,
        [&](const auto& field)
        {
          return an::IntegrateAdaptive(
            field, tf, segments.data(), segments.size(), method.Adaptive, steps);
        });
      return;
  }
}

// The composite integral of a mixture's ray over `segments` by the method:
// its medium for the sampled methods, its pieces for the piecewise ones.
template <typename VolumeT>
void Composite(const an::ComponentVolumes<double, VolumeT>& volume, const FrameMethod& method,
  const glm::dvec3& origin, const glm::dvec3& direction, double D, const Segments& segments,
  an::RayResult<double>& result, std::vector<an::StepRecord<double>>* steps)
{
  const an::MixtureTransferFunction<double>& medium = *method.Mixture;
  const an::RayField<double, an::ComponentVolumes<double, VolumeT>> field{ volume, origin,
    direction };
  switch (method.Kind)
  {
    case Integration::Riemann:
      result =
        an::IntegrateRiemann(field, medium, D, method.SampleDistance, an::RiemannForm::Exponential,
          segments.data(), segments.size(), method.TerminationBound, steps);
      return;
    case Integration::Reference:
      result = method.MixturePieces
        ? an::IntegratePiecewiseMixture(volume, origin, direction, segments.data(), segments.size(),
            *method.MixturePieces, an::PiecewiseReferenceTolerance<double>())
        : an::IntegrateReference(field, medium, segments.data(), segments.size());
      return;
    case Integration::Piecewise:
      result = an::IntegratePiecewiseMixture(volume, origin, direction, segments.data(),
        segments.size(), *method.MixturePieces, method.Adaptive.Tolerance, true, steps);
      return;
    case Integration::AdaptiveCoupled:
    case Integration::AdaptiveDecoupled:
      result = an::IntegrateAdaptive(
        field, medium, segments.data(), segments.size(), method.Adaptive, steps);
      return;
  }
}

// The ray origin + t direction (point-grid coordinates) through the volume
// by the method: the map's segments and the clip region in the point grid,
// the integrals in the volume's walk coordinates.
template <typename VolumeT>
void Integrate(const VolumeT& volume, const an::ClipRegion<double>& clip, const FrameMethod& method,
  const glm::dvec3& origin, const glm::dvec3& direction, double D, RayScratch& scratch,
  an::RayResult<double>& result, std::vector<an::StepRecord<double>>* steps)
{
  const glm::dvec3 o = volume.ToWalk(origin), d = volume.ToWalk(direction);
  Segments& segments = scratch.Visible;
  const bool projection = method.Mode != Blend::Composite;
  if (!WalksSegments(method))
  {
    segments.assign(1, { 0.0, D });
  }
  if (!clip.IsEmpty() && !segments.empty())
  {
    clip.Kept(origin, direction, D, scratch.Kept);
    if (method.Kind == Integration::Riemann && !projection)
    {
      ClippedRiemann(volume, method, o, d, segments, scratch, result, steps);
      return;
    }
    // The other methods integrate exactly the segments they are given (tau
    // taken as 0 elsewhere), within their tolerance over the whole ray.
    an::ClipRegion<double>::Intersect(segments, scratch.Kept, scratch.Clipped);
    std::swap(segments, scratch.Clipped);
  }
  if (segments.empty())
  {
    return;
  }
  if constexpr (!IsMixture<VolumeT>::value) // (Validate refuses their projections)
  {
    if (method.Mode == Blend::Additive || method.Mode == Blend::Average)
    {
      Accumulate(volume, method, o, d, segments, result);
      return;
    }
    if (projection)
    {
      Extremum(volume, method, o, d, D, scratch, result);
      return;
    }
  }
  Composite(volume, method, o, d, D, segments, result, steps);
}

// The ray of pixel (x, y) through IntegrateRay, its segments walked here.
// False when the ray misses the volume's box.
bool IntegratePixel(const Frame& frame, const Scalars& scalars, const FrameMethod& method, int x,
  int y, RayScratch& scratch, an::RayResult<double>& result,
  std::vector<an::StepRecord<double>>* steps)
{
  glm::dvec3 origin, direction;
  double D;
  if (!PixelRay(frame.Rays, x, y, &origin.x, &direction.x, D))
  {
    return false;
  }
  if (WalksSegments(method))
  {
    method.Map->Segments(origin, direction, D, SegmentPad, scratch.Visible);
  }
  IntegrateRay(scalars, frame.Clip, method, origin, direction, D, scratch, result, steps);
  return true;
}
} // namespace

// A tile's scratch lists and the statistics of the tiles it cast: the ray's
// (RayScratch), a tile row's rays set up and walked through the empty-space
// map at once (avos/engine/PixelRays.h, EmptySpace.h): their pixels, origins
// and directions (three doubles each), lengths and segments; a tile's rays
// for the lanes of the Riemann kernel or the piecewise one.
struct FrameCaster::Scratch
{
  RayScratch Ray;
  std::array<int, TileSize> RowX;
  std::array<double, 3 * TileSize> RowOrigins, RowDirections;
  std::array<double, TileSize> RowLengths;
  std::array<Segments, TileSize> RowSegments;
  std::array<Segments, TileSize * TileSize> TileSegments;
  std::array<RiemannRay, TileSize * TileSize> TileRays;
  std::array<RayOutput, TileSize * TileSize> TileOutputs;
  std::array<PiecewiseOutput, TileSize * TileSize> TilePieceOutputs;
  std::array<int, TileSize * TileSize> TileX, TileY;
  FrameStatistics Statistics;
};

namespace
{
// Casts tiles of one frame with a scratch at a time.
template <typename VolumeT>
class TileCaster
{
public:
  using Scratch = FrameCaster::Scratch;

  TileCaster(const Frame& frame, const VolumeT& volume, const FrameMethod& method, float* image)
    : Volume(volume)
    , TheFrame(frame)
    , Method(method)
    , Image(image)
  {
    this->TilesX = (frame.Rect[1] - frame.Rect[0] + TileSize - 1) / TileSize;
    const bool lanes = method.Kind == Integration::Riemann
      ? RiemannKernel(method)
      : method.Kind == Integration::Piecewise && method.PieceTable && !method.Shading &&
        !method.GradientOpacity;
    this->RaysPerLane = lanes && method.Mode == Blend::Composite && frame.Clip.IsEmpty();
  }

  void CastTile(std::int64_t tile, Scratch& scratch) const
  {
    const int* rect = this->TheFrame.Rect;
    const int x0 = rect[0] + static_cast<int>(tile % this->TilesX) * TileSize;
    const int y0 = rect[2] + static_cast<int>(tile / this->TilesX) * TileSize;
    const int x1 = std::min(x0 + TileSize, rect[1]), y1 = std::min(y0 + TileSize, rect[3]);
    if (this->RaysPerLane)
    {
      this->CastLanes(x0, x1, y0, y1, scratch);
      return;
    }
    for (int y = y0; y < y1; ++y)
    {
      this->CastRow(x0, x1, y, scratch);
    }
  }

private:
  // Pixels [x0, x1) of row y (at most a tile's width): the rays that meet
  // the box, set up and walked through the empty-space map as one packet.
  void CastRow(int x0, int x1, int y, Scratch& scratch) const
  {
    const int count = this->SetUpRow(x0, x1, y, scratch);
    for (int i = 0; i < count; ++i)
    {
      std::swap(scratch.Ray.Visible, scratch.RowSegments[i]);
      const double* o = &scratch.RowOrigins[3 * i];
      const double* d = &scratch.RowDirections[3 * i];
      an::RayResult<double> result;
      Integrate(this->Volume, this->TheFrame.Clip, this->Method, glm::dvec3(o[0], o[1], o[2]),
        glm::dvec3(d[0], d[1], d[2]), scratch.RowLengths[i], scratch.Ray, result, nullptr);
      this->Store(scratch.RowX[i], y, result, scratch);
    }
  }

  // The rays of pixels [x0, x1) of row y that meet the box into
  // scratch.Row* (their segments too where the rays walk the empty-space
  // map); how many.
  int SetUpRow(int x0, int x1, int y, Scratch& scratch) const
  {
    const int count = RowRays(this->TheFrame.Rays, y, x0, x1, scratch.RowX.data(),
      scratch.RowOrigins.data(), scratch.RowDirections.data(), scratch.RowLengths.data());
    if (WalksSegments(this->Method))
    {
      PacketSegments(*this->Method.Map, static_cast<std::size_t>(count), scratch.RowOrigins.data(),
        scratch.RowDirections.data(), scratch.RowLengths.data(), SegmentPad,
        scratch.RowSegments.data());
    }
    return count;
  }

  // The Riemann sum or the piecewise method over a tile's rays, a ray per
  // lane of the engine's kernels (Riemann.h, PiecewiseRays.h): what CastRow
  // gives without clipping, the rays refilling the lanes across the tile's
  // rows.
  void CastLanes(int x0, int x1, int y0, int y1, Scratch& scratch) const
  {
    const std::size_t count = this->SetUpTile(x0, x1, y0, y1, scratch);
    const FrameMethod& method = this->Method;
    if (method.Kind == Integration::Piecewise)
    {
      CastPiecewiseRays(*method.Kernels.Scalars, *method.Pieces, *method.PieceTable,
        method.Adaptive.Tolerance, scratch.TileRays.data(), count, scratch.TilePieceOutputs.data());
      for (std::size_t i = 0; i < count; ++i)
      {
        PiecewiseOutput& out = scratch.TilePieceOutputs[i];
        an::RayResult<double> result;
        result.RGBA = glm::dvec4(out.RGBA[0], out.RGBA[1], out.RGBA[2], out.RGBA[3]);
        result.Statistics.Samples = out.Pieces;
        result.Statistics.Pieces = out.Pieces;
        result.Statistics.Cells = out.Cells;
        result.Statistics.Rejected = out.Rejected;
        std::swap(result.Error, out.Error);
        this->Store(scratch.TileX[i], scratch.TileY[i], result, scratch);
      }
      return;
    }
    CastRiemannRays(*method.EngineVolume, *method.EngineTable, method.SampleDistance,
      method.TerminationBound, scratch.TileRays.data(), count, scratch.TileOutputs.data());
    for (std::size_t i = 0; i < count; ++i)
    {
      const RayOutput& out = scratch.TileOutputs[i];
      an::RayResult<double> result;
      result.RGBA = glm::dvec4(out.RGBA[0], out.RGBA[1], out.RGBA[2], out.RGBA[3]);
      result.Statistics.Samples = out.Samples;
      this->Store(scratch.TileX[i], scratch.TileY[i], result, scratch);
    }
  }

  // The tile's rays that meet the box into scratch.Tile*, row after row;
  // how many.
  std::size_t SetUpTile(int x0, int x1, int y0, int y1, Scratch& scratch) const
  {
    const bool walks = WalksSegments(this->Method);
    std::size_t count = 0;
    for (int y = y0; y < y1; ++y)
    {
      const int n = this->SetUpRow(x0, x1, y, scratch);
      for (int i = 0; i < n; ++i, ++count)
      {
        Segments& segments = scratch.TileSegments[count];
        if (walks)
        {
          std::swap(segments, scratch.RowSegments[i]);
        }
        else
        {
          segments.assign(1, { 0.0, scratch.RowLengths[i] });
        }
        RiemannRay& ray = scratch.TileRays[count];
        std::copy_n(&scratch.RowOrigins[3 * i], 3, ray.Origin);
        std::copy_n(&scratch.RowDirections[3 * i], 3, ray.Direction);
        ray.D = scratch.RowLengths[i];
        ray.Segments = segments.data();
        ray.Count = segments.size();
        scratch.TileX[count] = scratch.RowX[i];
        scratch.TileY[count] = y;
      }
    }
    return count;
  }

  void Store(int x, int y, const an::RayResult<double>& result, Scratch& scratch) const
  {
    scratch.Statistics.Add(result);
    float* pixel = this->Image + 4 * (static_cast<std::size_t>(y) * this->TheFrame.Rays.Width + x);
    for (int c = 0; c < 4; ++c)
    {
      pixel[c] = static_cast<float>(result.RGBA[c]);
    }
  }

  const VolumeT& Volume;
  const Frame& TheFrame;
  const FrameMethod& Method;
  float* Image;
  bool RaysPerLane = false;
  int TilesX = 0;
};
} // namespace

void Frame::SampleDepth(const float* viewport, int viewportWidth, int viewportHeight)
{
  const int width = this->Rays.Width, height = this->Rays.Height;
  this->Depth.resize(static_cast<std::size_t>(width) * height);
  this->Rays.Depth = this->Depth.data();
  for (int y = 0; y < height; ++y)
  {
    const int vy =
      std::min(static_cast<int>((y + 0.5) * viewportHeight / height), viewportHeight - 1);
    for (int x = 0; x < width; ++x)
    {
      const int vx =
        std::min(static_cast<int>((x + 0.5) * viewportWidth / width), viewportWidth - 1);
      this->Depth[static_cast<std::size_t>(y) * width + x] =
        viewport[static_cast<std::size_t>(vy) * viewportWidth + vx];
    }
  }
}

void Frame::SetFootprint(const double gridToWorld[16], const double projection[16])
{
  const int width = this->Rays.Width, height = this->Rays.Height;
  const int* dims = this->Rays.Dimensions;
  int* rect = this->Rect;
  rect[0] = width;
  rect[1] = 0;
  rect[2] = height;
  rect[3] = 0;
  for (int c = 0; c < 8; ++c)
  {
    const glm::dvec4 corner((c & 1) * (dims[0] - 1.0), ((c >> 1) & 1) * (dims[1] - 1.0),
      ((c >> 2) & 1) * (dims[2] - 1.0), 1.0);
    const glm::dvec4 onScreen = Multiply(projection, Multiply(gridToWorld, corner));
    if (!(onScreen.w > 0.0))
    {
      // A corner behind the eye: the box may cover any pixel.
      rect[0] = rect[2] = 0;
      rect[1] = width;
      rect[3] = height;
      return;
    }
    const double px = (onScreen.x / onScreen.w + 1.0) * 0.5 * width;
    const double py = (onScreen.y / onScreen.w + 1.0) * 0.5 * height;
    rect[0] = std::min(rect[0], static_cast<int>(std::max(std::floor(px), -1.0)));
    rect[1] = std::max(rect[1], static_cast<int>(std::min(std::ceil(px) + 1, width + 1.0)));
    rect[2] = std::min(rect[2], static_cast<int>(std::max(std::floor(py), -1.0)));
    rect[3] = std::max(rect[3], static_cast<int>(std::min(std::ceil(py) + 1, height + 1.0)));
  }
  rect[0] = std::max(rect[0], 0);
  rect[2] = std::max(rect[2], 0);
  rect[1] = std::min(rect[1], width);
  rect[3] = std::min(rect[3], height);
}

void FrameStatistics::Add(const an::RayResult<double>& ray)
{
  ++this->Rays;
  if (!ray.Error.empty() && this->Failed++ == 0)
  {
    this->FirstError = ray.Error;
  }
  this->Samples += ray.Statistics.Samples;
  this->MaximumSamples = std::max<std::int64_t>(this->MaximumSamples, ray.Statistics.Samples);
  this->Rejected += ray.Statistics.Rejected;
  this->Cells += ray.Statistics.Cells;
  this->Pieces += ray.Statistics.Pieces;
}

void FrameStatistics::Merge(const FrameStatistics& other)
{
  this->Rays += other.Rays;
  this->Samples += other.Samples;
  this->MaximumSamples = std::max(this->MaximumSamples, other.MaximumSamples);
  this->Rejected += other.Rejected;
  this->Cells += other.Cells;
  this->Pieces += other.Pieces;
  this->Failed += other.Failed;
  if (this->FirstError.empty())
  {
    this->FirstError = other.FirstError;
  }
}

namespace
{
// Empty when a mixture of `scalars.Components` can be cast with `method`.
std::string ValidateMixture(const Scalars& scalars, const FrameMethod& method)
{
  if (scalars.Components < 1 || scalars.Components > numerics::MaximumComponents)
  {
    return "the engine reads 1 to 4 components";
  }
  if (!method.Mixture || method.Mixture->GetNumberOfComponents() != scalars.Components)
  {
    return "scalars of several components need their mixture";
  }
  if (method.Kind == Integration::Piecewise && !method.MixturePieces)
  {
    return "the piecewise method needs the mixture's pieces";
  }
  if (method.MixturePieces && method.MixturePieces->GetNumberOfComponents() != scalars.Components)
  {
    return "the mixture's pieces were built for another number of components";
  }
  if (method.Mode != Blend::Composite)
  {
    return "scalars of several components are composited only (no projections)";
  }
  if (method.Shading || method.GradientOpacity)
  {
    return "scalars of several components are not shaded, nor scaled by gradient opacity";
  }
  if (method.EngineVolume || method.Kernels.Scalars || method.PieceTable)
  {
    return "the engine's kernels read a mixture only where one component alone shows (as that "
           "component)";
  }
  return std::string();
}
} // namespace

namespace
{
// Empty when `method`'s gradient opacity can be cast.
std::string ValidateGradientOpacity(const Scalars& scalars, const FrameMethod& method)
{
  const std::string error = method.GradientOpacity->Validate();
  if (!error.empty())
  {
    return error;
  }
  if (method.Mode != Blend::Composite)
  {
    return "gradient opacity applies to the composite blend mode only";
  }
  if (scalars.Field != ScalarField::Trilinear)
  {
    return "gradient opacity needs point scalars with linear interpolation (a field constant per "
           "cell has no gradient)";
  }
  return std::string();
}
} // namespace

bool WalksSegments(const FrameMethod& method)
{
  return method.Map && method.Mode == Blend::Composite;
}

std::string Validate(const Scalars& given, const FrameMethod& givenMethod)
{
  const Resolved resolved(given, givenMethod);
  const Scalars& scalars = resolved.TheScalars;
  const FrameMethod& method = resolved.Method;
  if (!scalars.Data)
  {
    return "no scalars";
  }
  for (const int n : scalars.Dimensions)
  {
    if (n < 2)
    {
      return "the volume needs at least 2 points along each axis";
    }
  }
  if (scalars.GetStride() < scalars.Components)
  {
    return "a tuple's stride must hold its components";
  }
  if (scalars.Components != 1)
  {
    const std::string error = ValidateMixture(scalars, method);
    if (!error.empty())
    {
      return error;
    }
  }
  else if (!method.TF)
  {
    return "no transfer function";
  }
  const bool additive = method.Mode == Blend::Additive;
  if ((method.Kind == Integration::Piecewise || additive) && scalars.Components == 1 &&
    !method.Pieces)
  {
    return "the piecewise method and the additive projection need the transfer function's pieces";
  }
  if (method.Mode == Blend::Average && !method.Range)
  {
    return "the average projection needs its range";
  }
  if (method.EngineVolume && !method.EngineTable)
  {
    return "the Riemann kernel needs its transfer table";
  }
  if (method.PieceTable && !(method.Kernels.Scalars && method.Pieces))
  {
    return "the piecewise rays per lane need the kernels' scalars and the pieces";
  }
  if (method.GradientOpacity)
  {
    const std::string error = ValidateGradientOpacity(scalars, method);
    if (!error.empty())
    {
      return error;
    }
  }
  if (scalars.Field != ScalarField::Trilinear)
  {
    // The kernels read the trilinear interpolant of point scalars; shading
    // needs its gradient (a field constant per cell has none; cell centres'
    // is not modelled).
    if (method.EngineVolume || method.Kernels.Scalars || method.PieceTable)
    {
      return "the engine's kernels read the trilinear interpolant of point scalars only";
    }
    if (method.Shading)
    {
      return "only point scalars with linear interpolation are shaded (a field constant per cell "
             "has no gradient)";
    }
  }
  return std::string();
}

void IntegrateRay(const Scalars& scalars, const an::ClipRegion<double>& clip,
  const FrameMethod& method, const glm::dvec3& origin, const glm::dvec3& direction, double D,
  RayScratch& scratch, an::RayResult<double>& result, std::vector<an::StepRecord<double>>* steps)
{
  const Resolved resolved(scalars, method);
  DispatchVolume(resolved.TheScalars,
    [&](const auto& volume)
    { Integrate(volume, clip, resolved.Method, origin, direction, D, scratch, result, steps); });
}

FrameCaster::FrameCaster() = default;
FrameCaster::~FrameCaster() = default;

std::int64_t FrameCaster::Tiles(const Frame& frame)
{
  return static_cast<std::int64_t>((frame.Rect[3] - frame.Rect[2] + TileSize - 1) / TileSize) *
    ((frame.Rect[1] - frame.Rect[0] + TileSize - 1) / TileSize);
}

FrameCaster::Scratch* FrameCaster::Acquire()
{
  std::lock_guard<std::mutex> lock(this->PoolMutex);
  if (this->Free.empty())
  {
    this->Pool.push_back(std::make_unique<Scratch>());
    return this->Pool.back().get();
  }
  Scratch* scratch = this->Free.back();
  this->Free.pop_back();
  return scratch;
}

void FrameCaster::Release(Scratch* scratch)
{
  std::lock_guard<std::mutex> lock(this->PoolMutex);
  this->Free.push_back(scratch);
}

FrameStatistics FrameCaster::Cast(const Frame& frame, const Scalars& scalars,
  const FrameMethod& method, float* image, const ParallelFor& loop, WorkMonitor& monitor)
{
  for (const auto& scratch : this->Pool)
  {
    scratch->Statistics = FrameStatistics();
  }
  const Resolved resolved(scalars, method);
  DispatchVolume(resolved.TheScalars,
    [&](const auto& volume)
    {
      const TileCaster<std::decay_t<decltype(volume)>> caster(
        frame, volume, resolved.Method, image);
      loop(Tiles(frame),
        [&](std::int64_t begin, std::int64_t end)
        {
          // A scratch per call: its lists stay allocated across tiles and
          // frames, and no two threads share one.
          Scratch* scratch = this->Acquire();
          for (std::int64_t tile = begin; tile < end && !monitor.Aborted(); ++tile)
          {
            caster.CastTile(tile, *scratch);
            monitor.Finished(1);
          }
          this->Release(scratch);
        });
    });
  FrameStatistics total;
  for (const auto& scratch : this->Pool)
  {
    total.Merge(scratch->Statistics);
  }
  return total;
}

bool FrameCaster::TracePixel(const Frame& frame, const Scalars& scalars, const FrameMethod& method,
  int x, int y, an::RayResult<double>& result, std::vector<an::StepRecord<double>>* steps)
{
  RayScratch scratch;
  return IntegratePixel(frame, scalars, method, x, y, scratch, result, steps);
}

} // namespace engine
} // namespace avos
