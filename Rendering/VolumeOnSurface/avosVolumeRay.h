// The ray both Volume-on-Surface classes cast from a surface vertex. As the
// paper defines it (VolumeSide::Behind), it starts at the vertex and runs
// along the observation line, away from the observer, through the volume
// behind the surface to the volume's far boundary: integrated front to back
// from the vertex on, it is what a ray cast shows through that point once
// the surface has replaced the (empty) space in front of it. The other side
// (VolumeSide::InFront) integrates the volume between the vertex and the eye
// instead, from the eye's end back to the vertex. Private to the module.
#ifndef avosVolumeRay_h
#define avosVolumeRay_h

#include "vtkAbstractMapper.h"
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPlaneCollection.h"
#include "vtkPointData.h"
#include "vtkSetGet.h"
#include "vtkType.h"

#include "avosClippingPlanes.h"
#include "avosEmptySpaceRanges.h"
#include "avosEngineVolume.h"
#include "avosImageGrid.h"
#include "avosShadingFromRenderer.h"
#include "avosTransferFunctionFromProperty.h"
#include "avosVolumeInput.h"

#include "avos/engine/EmptySpace.h"
#include "avos/engine/Frame.h"
#include "avos/engine/PieceKernels.h"
#include "avos/numerics/Clipping.h"
#include "avos/numerics/EmptySpace.h"
#include "avos/numerics/Mixture.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/RayIntegrators.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

class vtkLightCollection;

namespace avos
{
// How both classes integrate a ray (their IntegrationMethod values).
enum class RayIntegration
{
  Levoy = 0, // Riemann sum, step SampleDistance
  Adaptive,  // the paper's adaptive Simpson, coupled, to Tolerance
  Piecewise  // piecewise adaptive (PiecewiseIntegrator.h), to Tolerance
};

// Which volume a vertex's ray integrates (the classes' VolumeSide values).
enum class VolumeSide
{
  Behind = 0, // from the vertex away from the observer (the paper's)
  InFront     // between the vertex and the observer
};

// The volume's scalars as VTK's volume mappers take them by default
// (SCALAR_MODE_DEFAULT): its point scalars, else its cell scalars
// (`cellScalars` set); null for none.
inline vtkDataArray* VolumeScalars(vtkImageData* volume, bool& cellScalars)
{
  int cellFlag = 0;
  vtkDataArray* scalars = volume ? vtkAbstractMapper::GetScalars(volume, VTK_SCALAR_MODE_DEFAULT,
                                     VTK_GET_ARRAY_BY_ID, 0, nullptr, cellFlag)
                                 : nullptr;
  cellScalars = cellFlag != 0;
  return scalars;
}

// What every ray of one execution shares: the volume's grid, its field and
// transfer function, the integration method. The volume is read as
// vtkAdaptiveVolumeMapper reads it: point or cell scalars, linear or nearest
// interpolation (avos::FieldOf), 1 to 4 components (several: their mixture,
// avos/numerics/Mixture.h, unshaded and without gradient opacity).
struct VolumeRaySetup
{
  int Dimensions[3] = { 0, 0, 0 };
  double WorldToGrid[16];
  double Voxel = 1.0; // world length of one voxel unit (the shortest grid step)
  avos::engine::ScalarField Field = avos::engine::ScalarField::Trilinear;
  int Components = 1;
  avos::numerics::TransferFunction<double> TF;              // one component
  avos::numerics::PiecewiseTransferFunction<double> Pieces; // for RayIntegration::Piecewise
  avos::MixtureFunctions Mixture;                           // several components
  avos::numerics::PiecewiseMixture<double> MixturePieces;   // their pieces
  // For RayIntegration::Levoy: the vectorised Riemann kernel's volume
  // (EngineVolume: ShownComponent's; null: the scalar sum) and transfer
  // table. For RayIntegration::Piecewise: the same volume for the cells'
  // kernel (null: the scalar walk; see ReadsEngineScalars).
  const avos::engine::Volume* Engine = nullptr;
  avos::engine::TransferTable Table;
  RayIntegration Method = RayIntegration::Levoy;
  VolumeSide Side = VolumeSide::Behind;
  double SampleDistance = 0.5;
  avos::numerics::AdaptiveSettings<double> Settings;
  vtkDataArray* Scalars = nullptr;
  // The blocks the transfer function leaves visible (EmptySpaceCache), or
  // null to integrate every ray over its whole length.
  const avos::numerics::EmptySpaceMap<double>* Map = nullptr;

  // Intervals of the transfer function not taken exactly (ApproximationNotice).
  int ApproximatedIntervals = 0;

  // The clipping planes that cut the rays (grid coordinates; AddClippingPlanes).
  avos::numerics::ClipRegion<double> Clip;

  // Gradient shading of the emission (the property's Shade under `lights`'
  // lights) and the grid-to-world map the rays' shading reads.
  bool Shade = false;
  avos::numerics::ShadingModel<double> Shading;
  double GridToWorldMatrix[16];

  // The property's gradient opacity where it changes anything (Gradient's
  // Function then points at GradientFunction: the setup is not copied).
  bool UsesGradientOpacity = false;
  avos::numerics::TransferFunction<double> GradientFunction;
  avos::numerics::GradientOpacity<double> Gradient;

  VolumeRaySetup() = default;
  VolumeRaySetup(const VolumeRaySetup&) = delete;
  VolumeRaySetup& operator=(const VolumeRaySetup&) = delete;

  // The component whose transfer function alone makes the medium (the
  // scalars' only one, or that of a mixture of which it alone shows), or -1.
  int ShownComponent() const
  {
    return this->Components > 1 ? this->Mixture.Mixture.GetSingleComponent() : 0;
  }
  // That component's medium (null: none).
  const avos::numerics::TransferFunction<double>* SingleMedium() const
  {
    return this->Components > 1 ? this->Mixture.Mixture.GetSingle() : &this->TF;
  }

  // Empty, or why the volume or the property cannot be used. `planes`: the
  // clipping planes (world coordinates) that cut every ray; null: none.
  // `lights` (their switched-on ones) and `twoSided` lighting shade the rays
  // when the property shades (a renderer's); null: shading is refused.
  std::string Prepare(vtkImageData* volume, vtkVolumeProperty* property, bool extinction,
    RayIntegration method, double sampleDistance, double tolerance,
    vtkPlaneCollection* planes = nullptr, vtkLightCollection* lights = nullptr,
    bool twoSided = true)
  {
    bool cellScalars = false;
    this->Scalars = VolumeScalars(volume, cellScalars);
    const std::string unusable =
      ValidateVolumeInput(volume, this->Scalars, cellScalars, avos::numerics::MaximumComponents);
    if (!unusable.empty())
    {
      return unusable;
    }
    volume->GetDimensions(this->Dimensions);
    this->Components = this->Scalars->GetNumberOfComponents();
    this->Field = FieldOf(
      cellScalars, property && property->GetInterpolationType() == VTK_NEAREST_INTERPOLATION);
    // The ray caster's step range bounds the work of one ray.
    const double smallest = vtkAdaptiveVolumeMapper::GetSmallestStep();
    const double largest = vtkAdaptiveVolumeMapper::GetLargestStep();
    if (!(sampleDistance >= smallest && sampleDistance <= largest))
    {
      return "the sample distance must be within [" + std::to_string(smallest) + ", " +
        std::to_string(largest) + "] voxel units, not " + std::to_string(sampleDistance);
    }
    if (!(tolerance > 0.0 && tolerance <= 1.0))
    {
      return "the tolerance must be within (0, 1], not " + std::to_string(tolerance);
    }
    if (method == RayIntegration::Piecewise)
    {
      const std::string invalid = avos::numerics::ValidatePiecewiseTolerance(tolerance,
        extinction ? avos::numerics::OpacityModel::Extinction
                   : avos::numerics::OpacityModel::Alpha);
      if (!invalid.empty())
      {
        return invalid;
      }
    }
    vtkNew<vtkMatrix4x4> gridToWorld, inverse;
    this->Voxel = GridToWorld(volume, nullptr, gridToWorld);
    if (!(this->Voxel > 0.0) || !std::isfinite(this->Voxel))
    {
      return "the volume's spacing must be non-zero and finite";
    }
    const std::string unsupported = UnsupportedPropertySettings(property, this->Components);
    if (!unsupported.empty())
    {
      return unsupported;
    }
    const std::string unlit = this->PrepareShading(property, lights, twoSided);
    if (!unlit.empty())
    {
      return unlit;
    }
    const std::string unconverted =
      this->PrepareTransferFunction(property, extinction, method, tolerance, gridToWorld);
    if (!unconverted.empty())
    {
      return unconverted;
    }
    const std::string ungraded =
      this->PrepareGradientOpacity(property, method, tolerance, gridToWorld);
    if (!ungraded.empty())
    {
      return ungraded;
    }
    const std::string unpieced = this->PreparePieces(method, tolerance);
    if (!unpieced.empty())
    {
      return unpieced;
    }
    this->Clip = avos::numerics::ClipRegion<double>();
    const std::string planesError = AddClippingPlanes(planes, gridToWorld->GetData(), this->Clip);
    if (!planesError.empty())
    {
      return planesError;
    }
    vtkMatrix4x4::Invert(gridToWorld, inverse);
    std::copy(inverse->GetData(), inverse->GetData() + 16, this->WorldToGrid);
    std::copy(gridToWorld->GetData(), gridToWorld->GetData() + 16, this->GridToWorldMatrix);
    this->Method = method;
    this->SampleDistance = sampleDistance;
    // Bounds of the field (every component's).
    this->Settings.FieldMinimum = this->Scalars->GetRange(0)[0];
    this->Settings.FieldMaximum = this->Scalars->GetRange(0)[1];
    for (int k = 1; k < this->Components; ++k)
    {
      const double* range = this->Scalars->GetRange(k);
      this->Settings.FieldMinimum = std::min(this->Settings.FieldMinimum, range[0]);
      this->Settings.FieldMaximum = std::max(this->Settings.FieldMaximum, range[1]);
    }
    return std::string();
  }

  // The transfer function, its table for `method`, and the tolerance the
  // rays are integrated to (Settings.Tolerance): the piecewise method's
  // colours and opacity are converted within shares of its eps where VTK's
  // are not piecewise linear, the rays integrated to the rest; lit, a
  // colour's error is multiplied by up to the shading's colour gain.
  std::string PrepareTransferFunction(vtkVolumeProperty* property, bool extinction,
    RayIntegration method, double tolerance, vtkMatrix4x4* gridToWorld)
  {
    ConversionBudget budget;
    if (method == RayIntegration::Piecewise)
    {
      budget = ConversionBudget::ForTolerance(
        tolerance, this->ColourGain(), this->LongestRay(gridToWorld));
    }
    const bool mixture = this->Components > 1;
    const std::string error = mixture
      ? MixtureFromProperty(property, this->Components, this->Scalars->GetDataType(), extinction,
          this->Voxel, this->Mixture, &budget)
      : TransferFunctionFromProperty(property, extinction, this->Voxel, this->TF, &budget);
    this->ApproximatedIntervals = budget.Approximated;
    this->Settings.Tolerance = IntegrationTolerance(tolerance, budget);
    if (!error.empty())
    {
      return "unusable transfer function: " + error;
    }
    // (The Riemann kernel's table is that of a single medium: a mixture of
    // which several components show takes the scalar sums.)
    if (method == RayIntegration::Levoy && this->SingleMedium())
    {
      const std::string tableError = this->Table.Build(*this->SingleMedium());
      if (!tableError.empty())
      {
        return "unusable transfer function: " + tableError;
      }
    }
    return std::string();
  }

  // The pieces of the piecewise method, for the tolerance the rays are
  // integrated to (after every conversion).
  std::string PreparePieces(RayIntegration method, double tolerance)
  {
    const bool mixture = this->Components > 1;
    if (method == RayIntegration::Piecewise)
    {
      const double relativeError = avos::numerics::PiecewiseRelativeError(this->Settings.Tolerance);
      const std::string piecesError = mixture
        ? this->MixturePieces.Build(this->Mixture.Mixture, relativeError)
        : this->Pieces.Build(this->TF, relativeError);
      if (!piecesError.empty())
      {
        return "the piecewise method cannot use this transfer function at tolerance " +
          std::to_string(tolerance) + ": " + piecesError;
      }
    }
    return std::string();
  }

  // The gradient opacity from the property (the extinction times G of the
  // gradient's magnitude in scalar units per world unit, as
  // vtkAdaptiveVolumeMapper's; the piecewise method's curved G within
  // GradientShare of its eps, taken off Settings.Tolerance); empty, or why it
  // cannot be used.
  std::string PrepareGradientOpacity(
    vtkVolumeProperty* property, RayIntegration method, double tolerance, vtkMatrix4x4* gridToWorld)
  {
    this->UsesGradientOpacity = avos::UsesGradientOpacity(property, 0);
    if (!this->UsesGradientOpacity)
    {
      return std::string();
    }
    const std::string unmodelled = this->Ungraded();
    if (!unmodelled.empty())
    {
      return "gradient opacity is not supported with " + unmodelled +
        "; disable the property's gradient opacity";
    }
    ConversionBudget budget;
    if (method == RayIntegration::Piecewise)
    {
      budget = ConversionBudget::ForGradientOpacity(
        tolerance, this->ColourGain(), this->LongestRay(gridToWorld));
    }
    const double largest = this->TF.GetMaximumExtinction(
      -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
    const std::string error =
      GradientOpacityFromProperty(property, largest, this->GradientFunction, budget);
    if (!error.empty())
    {
      return "unusable gradient opacity: " + error;
    }
    this->ApproximatedIntervals += budget.Approximated;
    this->Settings.Tolerance -= budget.Spent;
    this->Gradient.Function = &this->GradientFunction;
    this->Gradient.NormalMatrix = NormalMatrix(gridToWorld->GetData());
    return std::string();
  }

  // Shade and Shading from the property, `lights` and `twoSided`; empty, or
  // why they cannot be used.
  std::string PrepareShading(vtkVolumeProperty* property, vtkLightCollection* lights, bool twoSided)
  {
    this->Shade = property && property->GetShade(0) != 0;
    if (!this->Shade)
    {
      return std::string();
    }
    const std::string unmodelled = this->Ungraded();
    if (!unmodelled.empty())
    {
      return "cannot shade " + unmodelled + "; turn the property's Shade off";
    }
    if (!lights)
    {
      return "cannot shade: no lights given";
    }
    std::vector<double> key; // the mapper's view key holds its own copy
    const std::string invalid = ShadingFromLights(lights, twoSided, property, this->Shading, key);
    return invalid.empty() ? invalid : "cannot shade: " + invalid;
  }

  // What a conversion's budget is for: the colours' gain under the shading
  // and the longest ray (voxel units).
  double ColourGain() const
  {
    return this->Shade ? std::max(1.0, this->Shading.ColourGain()) : 1.0;
  }
  double LongestRay(vtkMatrix4x4* gridToWorld) const
  {
    return LongestChord(gridToWorld, this->Dimensions) / this->Voxel;
  }

  // Empty, or the volume whose gradient (for shading and gradient opacity)
  // is not modelled, as vtkAdaptiveVolumeMapper's: several components, or a
  // field other than the trilinear interpolant of point scalars.
  std::string Ungraded() const
  {
    if (this->Components > 1)
    {
      return "scalars of " + std::to_string(this->Components) + " components";
    }
    return this->Field == avos::engine::ScalarField::Trilinear
      ? std::string()
      : "a field other than point scalars with linear interpolation (constant per cell: no "
        "gradient; cell scalars' between their centres is not modelled)";
  }

  // Calls f(caster) with the execution's VolumeRay; false for a scalar type
  // the engine does not read.
  template <typename F>
  bool Dispatch(F&& f) const;
};

// Whether the rays of `setup` read the engine's view of the scalars: the
// Riemann kernel's (unshaded, without gradient opacity), and the piecewise
// method's cells where the scalars are 8- or 16-bit unsigned (the only ones
// the cells' kernel reads). Both read the trilinear interpolant of one
// component (ShownComponent).
inline bool ReadsEngineScalars(const VolumeRaySetup& setup)
{
  const bool readable = setup.Scalars && setup.ShownComponent() >= 0 &&
    setup.Field == avos::engine::ScalarField::Trilinear;
  return readable &&
    ((setup.Method == RayIntegration::Levoy && !setup.Shade && !setup.UsesGradientOpacity) ||
      (setup.Method == RayIntegration::Piecewise &&
        avos::engine::ReadsCells(EngineVolume::EngineType(setup.Scalars->GetDataType()))));
}

// The rays of one execution, integrated as vtkAdaptiveVolumeMapper's are:
// through the frame engine's IntegrateRay (the same methods, clipping rule
// and early termination), and a ray per SIMD lane of the Riemann kernel for
// unclipped Levoy rays.
class VolumeRay
{
public:
  // `view`: the setup's scalars as the engine reads them in place.
  VolumeRay(const VolumeRaySetup& setup, const avos::engine::Scalars& view)
    : Setup(setup)
    , View(view)
  {
    avos::engine::FrameMethod& m = this->Method;
    m.Kind = setup.Method == RayIntegration::Levoy
      ? avos::engine::Integration::Riemann
      : (setup.Method == RayIntegration::Adaptive ? avos::engine::Integration::AdaptiveCoupled
                                                  : avos::engine::Integration::Piecewise);
    m.Adaptive = setup.Settings;
    m.SampleDistance = setup.SampleDistance;
    m.TerminationBound = this->TerminationBound();
    const bool mixture = setup.Components > 1;
    m.TF = mixture ? nullptr : &setup.TF;
    m.Mixture = mixture ? &setup.Mixture.Mixture : nullptr;
    m.Map = setup.Map;
    m.Pieces = mixture ? nullptr : &setup.Pieces;
    m.MixturePieces =
      mixture && setup.Method == RayIntegration::Piecewise ? &setup.MixturePieces : nullptr;
    m.EngineVolume = setup.Method == RayIntegration::Levoy ? setup.Engine : nullptr;
    m.EngineTable = &setup.Table;
    m.Kernels = avos::engine::PieceKernels(
      setup.Method == RayIntegration::Piecewise ? setup.Engine : nullptr);
    if (setup.Shade)
    {
      ShadeWith(setup.Shading, setup.GridToWorldMatrix, m);
    }
    m.GradientOpacity = setup.UsesGradientOpacity ? &setup.Gradient : nullptr;
  }

  // results[i]: the RGBA of the volume from vertices[i] along directions[i]
  // (a unit world vector: away from the observer for VolumeSide::Behind,
  // towards it for InFront) to the volume's boundary, at most
  // maximumLengths[i] world units long (InFront: the eye's distance, for an
  // eye inside the volume), for i in [0, count). A non-empty Error (an
  // overflow: scalars or extinctions beyond double's range along the ray)
  // comes with a zero RGBA; the classes refuse the frame or the
  // previsualization then (RayFailures). The empty-space walk of all the
  // rays is done at once, a ray per SIMD lane (avos::engine::PacketSegments:
  // the same segments to the bit, about a third of the scalar walk's time
  // per ray).
  void Cast(std::size_t count, const glm::dvec3* vertices, const glm::dvec3* directions,
    const double* maximumLengths, avos::numerics::RayResult<double>* results) const
  {
    thread_local std::vector<double> origins, marches, lengths;
    thread_local std::vector<std::size_t> rays; // which result each spanned ray is
    thread_local std::vector<std::vector<avos::numerics::Interval<double>>> segments;
    origins.resize(3 * count);
    marches.resize(3 * count);
    lengths.resize(count);
    rays.clear();
    for (std::size_t i = 0; i < count; ++i)
    {
      results[i] = avos::numerics::RayResult<double>();
      glm::dvec3 origin, march;
      double D = 0.0;
      if (this->Span(vertices[i], directions[i], maximumLengths[i], origin, march, D))
      {
        const std::size_t k = rays.size();
        std::copy(&origin.x, &origin.x + 3, &origins[3 * k]);
        std::copy(&march.x, &march.x + 3, &marches[3 * k]);
        lengths[k] = D;
        rays.push_back(i);
      }
    }
    const std::size_t spanned = rays.size();
    if (segments.size() < spanned)
    {
      segments.resize(spanned);
    }
    if (this->Setup.Map)
    {
      avos::engine::PacketSegments(*this->Setup.Map, spanned, origins.data(), marches.data(),
        lengths.data(), avos::engine::SegmentPad, segments.data());
    }
    for (std::size_t k = 0; k < spanned && !this->Setup.Map; ++k)
    {
      segments[k].assign(1, { 0.0, lengths[k] });
    }
    if (this->Setup.Engine && this->Setup.Method == RayIntegration::Levoy &&
      this->Setup.Clip.IsEmpty() && !this->Setup.Shade && !this->Setup.UsesGradientOpacity)
    {
      // A ray per lane of the engine's kernel, the same sums as Integrate's.
      thread_local std::vector<avos::engine::RiemannRay> lanes;
      thread_local std::vector<avos::engine::RayOutput> outputs;
      lanes.resize(spanned);
      outputs.resize(spanned);
      for (std::size_t k = 0; k < spanned; ++k)
      {
        std::copy_n(&origins[3 * k], 3, lanes[k].Origin);
        std::copy_n(&marches[3 * k], 3, lanes[k].Direction);
        lanes[k].D = lengths[k];
        lanes[k].Segments = segments[k].data();
        lanes[k].Count = segments[k].size();
      }
      avos::engine::CastRiemannRays(*this->Setup.Engine, this->Setup.Table,
        this->Setup.SampleDistance, this->TerminationBound(), lanes.data(), spanned,
        outputs.data());
      for (std::size_t k = 0; k < spanned; ++k)
      {
        const double* c = outputs[k].RGBA;
        results[rays[k]].RGBA = glm::dvec4(c[0], c[1], c[2], c[3]);
      }
      return;
    }
    for (std::size_t k = 0; k < spanned; ++k)
    {
      const double* o = &origins[3 * k];
      const double* b = &marches[3 * k];
      this->Integrate(glm::dvec3(o[0], o[1], o[2]), glm::dvec3(b[0], b[1], b[2]), lengths[k],
        segments[k], results[rays[k]]);
    }
  }

private:
  // The ray of Cast() in grid coordinates, integrated from `origin` along
  // `march` (a voxel unit per unit of t) over [0, D], front to back for the
  // observer: Behind, from the vertex (or where the ray enters the grid)
  // along `direction`; InFront, from the far end back to the vertex. False
  // when it misses the grid.
  bool Span(const glm::dvec3& vertex, const glm::dvec3& direction, double maximumLength,
    glm::dvec3& origin, glm::dvec3& march, double& D) const
  {
    const double* m = this->Setup.WorldToGrid;
    auto toGrid = [m](const glm::dvec3& p, double w)
    {
      return glm::dvec3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3] * w,
        m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7] * w,
        m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11] * w);
    };
    const glm::dvec3 start = toGrid(vertex, 1.0);
    const glm::dvec3 step = toGrid(direction * this->Setup.Voxel, 0.0); // per voxel unit
    double t0 = 0.0, t1 = maximumLength / this->Setup.Voxel;
    if (!avos::numerics::ClipToGrid(start, step, this->Setup.Dimensions, t0, t1))
    {
      return false;
    }
    D = t1 - t0;
    const bool behind = this->Setup.Side == VolumeSide::Behind;
    origin = start + (behind ? t0 : t1) * step;
    march = behind ? step : -step;
    return true;
  }

  // The spanned ray over `segments`, the parts of [0, D] in visible blocks
  // (all of it without skipping): a Riemann sum over them is the full sum
  // exactly, the other methods keep their bounds (RayIntegrators.h). The
  // clipping planes cut it exactly where the ray crosses them, as in
  // vtkAdaptiveVolumeMapper (engine::IntegrateRay).
  void Integrate(const glm::dvec3& origin, const glm::dvec3& march, double D,
    std::vector<avos::numerics::Interval<double>>& segments,
    avos::numerics::RayResult<double>& result) const
  {
    thread_local avos::engine::RayScratch scratch;
    std::swap(scratch.Visible, segments);
    avos::engine::IntegrateRay(
      this->View, this->Setup.Clip, this->Method, origin, march, D, scratch, result);
    std::swap(scratch.Visible, segments);
  }

  // The Riemann sums' early termination bound.
  double TerminationBound() const { return 0.2 * this->Setup.Settings.Tolerance; }

  const VolumeRaySetup& Setup;
  const avos::engine::Scalars View;
  avos::engine::FrameMethod Method;
};

// The rays of one execution that could not be integrated, counted across
// threads, with the first one's reason for the error message.
class RayFailures
{
public:
  void Add(const std::string& error)
  {
    if (this->Count.fetch_add(1, std::memory_order_relaxed) == 0)
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->First = error;
    }
  }
  // After the threads have joined.
  vtkIdType GetCount() const { return this->Count.load(); }
  std::string GetMessage() const
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    return std::to_string(this->Count.load()) + " ray(s) could not be integrated: " + this->First;
  }

private:
  std::atomic<vtkIdType> Count{ 0 };
  mutable std::mutex Mutex;
  std::string First;
};

// The volume's empty-space map, kept across executions by both classes: the
// blocks' ranges follow the scalars (EmptySpaceRanges), their visibility is
// renewed on every Update (one pass over the blocks).
class EmptySpaceCache
{
public:
  // The map for the prepared setup's volume and transfer function; null for
  // a scalar type the map cannot read.
  const avos::numerics::EmptySpaceMap<double>* Update(const VolumeRaySetup& setup)
  {
    if (!this->Ranges.Update(setup.Scalars, setup.Dimensions, SamplesOf(setup.Field)))
    {
      return nullptr;
    }
    if (setup.Components > 1)
    {
      const avos::numerics::MixtureTransferFunction<double>& medium = setup.Mixture.Mixture;
      this->Ranges.GetMap().ClassifyBlocks(
        [&medium](const double* lo, const double* hi) { return medium.IsVisible(lo, hi); });
    }
    else
    {
      this->Ranges.GetMap().Classify(setup.TF);
    }
    return &this->Ranges.GetMap();
  }

  // Warns of NaN scalars once per change of the scalars (EmptySpaceRanges).
  void WarnOfNaNs(vtkObject* caller) { this->Ranges.WarnOfNaNs(caller); }

private:
  EmptySpaceRanges Ranges;
};

// Points the prepared setup at the execution's empty-space map (when
// `skipping`) and at the engine's view of the scalars where its rays read
// it, both kept across executions by the calling class. The rays take NaN
// scalars as vtkAdaptiveVolumeMapper does (a cell with a NaN corner is
// empty), and `caller` warns of them as it does: once per change of the
// scalars, from the map's ranges (kept with skipping off too).
inline void UseCaches(vtkObject* caller, VolumeRaySetup& setup, EmptySpaceCache& emptySpace,
  EngineVolume& engineScalars, bool skipping)
{
  const avos::numerics::EmptySpaceMap<double>* map = emptySpace.Update(setup);
  emptySpace.WarnOfNaNs(caller);
  setup.Map = skipping ? map : nullptr;
  setup.Engine = ReadsEngineScalars(setup)
    ? engineScalars.Update(setup.Scalars, setup.Dimensions, setup.ShownComponent())
    : nullptr;
}

// Says on `caller` why the setup could not be prepared (`error`: an error,
// false returned) or that its transfer function is approximated (a
// warning).
inline bool ReportPrepared(vtkObject* caller, const std::string& error, const VolumeRaySetup& setup)
{
  if (!error.empty())
  {
    vtkErrorWithObjectMacro(caller, << "Cannot cast rays: " << error << ".");
    return false;
  }
  if (setup.ApproximatedIntervals > 0)
  {
    vtkWarningWithObjectMacro(caller, << ApproximationNotice(setup.ApproximatedIntervals) << ".");
  }
  return true;
}

// A ray's RGBA, clamped to [0, 1], as the 8-bit vertex colour both classes
// output.
inline std::array<unsigned char, 4> ToBytes(const glm::dvec4& rgba)
{
  std::array<unsigned char, 4> bytes;
  for (int k = 0; k < 4; ++k)
  {
    bytes[k] =
      static_cast<unsigned char>(std::lround(255.0 * std::min(std::max(rgba[k], 0.0), 1.0)));
  }
  return bytes;
}

template <typename F>
bool VolumeRaySetup::Dispatch(F&& f) const
{
  avos::engine::Scalars view;
  if (!ScalarsInPlace(this->Scalars, this->Dimensions, view))
  {
    return false;
  }
  view.Field = this->Field;
  f(VolumeRay(*this, view));
  return true;
}
}

#endif
