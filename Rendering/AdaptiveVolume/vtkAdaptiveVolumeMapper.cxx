#include "vtkAdaptiveVolumeMapper.h"

#include "vtkArrayDispatch.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRayCastImageDisplayHelper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkTable.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "avosClippingPlanes.h"
#include "avosEmptySpaceRanges.h"
#include "avosEngineVolume.h"
#include "avosImageGrid.h"
#include "avosShadingFromRenderer.h"
#include "avosTransferFunctionFromProperty.h"
#include "avosVolumeInput.h"

#include "avos/engine/Frame.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Shading.h"
#include "avos/numerics/TransferFunction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

namespace
{
namespace an = avos::numerics;
using TransferFunction = an::TransferFunction<double>;

// The reference's budgets for VTK's curved functions (other colour spaces,
// Hermite curves, log scales), tightest first: converted within shares of
// the first that certifies every interval (a proven bound; the knots an
// interval may take are capped, and a Hermite opacity in the extinction
// model needs 1e-5), the rays integrated at PiecewiseReferenceTolerance, so
// a pixel lies within that budget + 1e-9 of the integral of VTK's own
// function. (At 1e-9 a Diverging map would need some 35,000 knots per
// interval.)
constexpr double ReferenceConversions[] = { 1e-7, 1e-6, 1e-5 };

// The blend mode as the engine names it (ValidateSettings admits these).
avos::engine::Blend EngineBlend(int blend)
{
  switch (blend)
  {
    case vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND:
      return avos::engine::Blend::Maximum;
    case vtkVolumeMapper::MINIMUM_INTENSITY_BLEND:
      return avos::engine::Blend::Minimum;
    case vtkVolumeMapper::AVERAGE_INTENSITY_BLEND:
      return avos::engine::Blend::Average;
    case vtkVolumeMapper::ADDITIVE_BLEND:
      return avos::engine::Blend::Additive;
    default:
      return avos::engine::Blend::Composite;
  }
}

// What the last image depends on besides the property's tables and the
// frame's depth buffer and clip region (compared with the last cast's
// copies): a frame whose key equals the last cast's is drawn again, not cast.
struct FrameKey
{
  std::array<double, 16> Projection{};
  std::array<double, 16> GridToWorld{};
  std::array<int, 6> Viewport{ { 0, 0, 0, 0, 0, 0 } }; // origin, viewport and image sizes
  vtkMTimeType MapperTime = 0;
  vtkMTimeType ClassifyTime = 0;
  vtkMTimeType RangesTime = 0;
  std::vector<double> Shading; // the shading's coefficients and lights, as numbers

  bool operator==(const FrameKey& o) const
  {
    return this->Projection == o.Projection && this->GridToWorld == o.GridToWorld &&
      this->Viewport == o.Viewport && this->MapperTime == o.MapperTime &&
      this->ClassifyTime == o.ClassifyTime && this->RangesTime == o.RangesTime &&
      this->Shading == o.Shading;
  }
};

// The Euclidean norm of each tuple into `out` (typed, in parallel).
struct MagnitudeWorker
{
  template <typename Array>
  void operator()(Array* array, vtkFloatArray* out)
  {
    const auto tuples = vtk::DataArrayTupleRange(array);
    float* norms = out->GetPointer(0);
    vtkSMPTools::For(0, static_cast<vtkIdType>(tuples.size()),
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType i = begin; i < end; ++i)
        {
          double sum = 0.0;
          for (const auto v : tuples[i])
          {
            sum += static_cast<double>(v) * static_cast<double>(v);
          }
          norms[i] = static_cast<float>(std::sqrt(sum));
        }
      });
  }
};

// vtkSMPTools as the engine's parallel loop.
void SMPFor(std::int64_t count, const std::function<void(std::int64_t, std::int64_t)>& body)
{
  vtkSMPTools::For(0, static_cast<vtkIdType>(count), 1,
    [&body](vtkIdType begin, vtkIdType end) { body(begin, end); });
}
} // namespace

// Each stage's inputs, caches and timestamps, in the order Render runs them.
class vtkAdaptiveVolumeMapper::vtkInternals
{
public:
  // ValidateSettings: the adaptive rule's settings.
  an::AdaptiveSettings<double> Adaptive;

  // UpdateInput: the input's scalars (per point, or per cell; 1 to 4
  // components, or one of them: Component, or their norms: Magnitude, kept
  // until the scalars change) and grid.
  vtkDataArray* Scalars = nullptr;
  bool CellData = false;
  int Components = 1;
  int Component = -1;
  vtkNew<vtkFloatArray> Magnitude;
  vtkDataArray* MagnitudeOf = nullptr; // identity only
  vtkMTimeType MagnitudeTime = 0;
  int Dimensions[3] = { 0, 0, 0 };

  // UpdateGeometry: grid to world and back, the voxel unit; the clipping
  // planes and cropping in grid coordinates go to Frame.Clip.
  vtkNew<vtkMatrix4x4> GridToWorld, WorldToGrid;
  double Voxel = 0.0;

  // UpdateScalars: the scalars' field (View.Field), the empty-space map's
  // ranges (rebuilt when the scalars or their field change), the data's
  // range, the engine's view of the scalars (in place).
  avos::EmptySpaceRanges Ranges;
  double DataRange[2] = { 0.0, 1.0 };
  avos::engine::Scalars View;

  // UpdateProperty: the transfer function (several components: their
  // mixture) and the blocks' visibility; the shading of the frame
  // (FrameMethod::Shading points here) and its key.
  TransferFunction TF;
  avos::MixtureFunctions Mixture;
  vtkMTimeType PropertyTime = 0;
  int OpacityModel = -1;
  double ClassifiedVoxel = 0.0;
  // The conversion's budget (avos::ConversionBudget::ForTolerance of the
  // piecewise method's eps or of one of ReferenceConversions, none
  // otherwise), and the tolerance the rays are integrated to: the piecewise
  // method's eps less the shares the conversion certified with.
  avos::ConversionBudget Conversion;
  avos::ConversionBudget ConversionRequest; // the budget asked for first
  double IntegrationTolerance = 0.0;
  vtkTimeStamp ClassifyTime;
  std::size_t VisibleBlocks = 0;
  bool Shade = false;
  an::ShadingModel<double> Shading;
  // UpdateGradientOpacity: the first component's gradient opacity, when it
  // changes anything (FrameMethod::GradientOpacity points here).
  bool UsesGradientOpacity = false;
  avos::GradientOpacityConversion GradientConversion;
  an::GradientOpacity<double> Gradient;
  std::vector<double> ShadingKey;
  // The transfer function in pieces, built for a relative error (the alpha
  // model's share of the tolerance) when a piecewise method needs it.
  bool Piecewise = false;
  an::PiecewiseTransferFunction<double> Pieces;
  an::PiecewiseMixture<double> MixturePieces;
  double PiecesRelativeError = 0.0;
  vtkTimeStamp PiecesTime;
  // The average projection's range (AverageAlongRay), rebuilt every frame.
  an::AverageRange<double> AverageRange;

  // UpdateKernelTables: the kernels' scalars (8- and 16-bit as they are,
  // other types as float; null: the scalar paths), the Riemann kernel's
  // transfer table and the piecewise rays' table.
  avos::EngineVolume EngineScalars;
  const avos::engine::Volume* RiemannScalars = nullptr;
  const avos::engine::Volume* CellScalars = nullptr;
  avos::engine::TransferTable EngineTable;
  vtkTimeStamp EngineTableTime;
  bool PieceLanes = false;
  avos::engine::PiecewiseTable PieceTable;
  vtkTimeStamp PieceTableTime;

  // SetUpFrame: the frame's rays and what they depend on; the image sample
  // distance and the viewport's depth buffer.
  avos::engine::Frame Frame;
  FrameKey Key;
  double Distance = 1.0;
  std::vector<float> ViewportDepth;

  // CastFrame: the caster's scratch, the last cast's method, key and
  // scalars (TraceRay re-casts its pixels), its image in float and 16-bit;
  // its distance and time (auto-adjustment).
  avos::engine::FrameCaster Caster;
  avos::engine::FrameMethod Method;
  FrameKey LastKey;
  std::vector<float> LastDepth;
  an::ClipRegion<double> LastClip;
  bool HaveImage = false;
  vtkSmartPointer<vtkDataArray> FrameScalars;
  vtkNew<vtkImageData> Image;
  std::vector<std::uint16_t> Display;
  double CastDistance = 1.0;
  double CastSeconds = 0.0;

  // DisplayFrame.
  vtkSmartPointer<vtkRayCastImageDisplayHelper> DisplayHelper;

  // What a conversion's budget is for: the colours' gain under the shading
  // and the longest ray (voxel units).
  double ColourGain() const
  {
    return this->Shade ? std::max(1.0, this->Shading.ColourGain()) : 1.0;
  }
  double LongestRay() const
  {
    return avos::LongestChord(this->GridToWorld, this->Dimensions) / this->Voxel;
  }
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
  vtkImageData* input = nullptr;
  bool drawn = this->ValidateSettings() && (input = this->UpdateInput()) != nullptr &&
    this->UpdateGeometry(input, vol) && this->UpdateScalars(vol) &&
    this->UpdateProperty(ren, vol) && this->UpdateKernelTables() && this->SetUpFrame(ren, vol);
  if (drawn)
  {
    const avos::engine::Frame& frame = internals.Frame;
    this->LastRenderReused = internals.HaveImage && internals.Key == internals.LastKey &&
      frame.Depth == internals.LastDepth && frame.Clip == internals.LastClip;
    drawn = this->LastRenderReused || this->CastFrame(ren);
    if (drawn && !this->LastRenderReused)
    {
      timer->StopTimer();
      internals.CastSeconds = timer->GetElapsedTime();
    }
  }
  if (drawn)
  {
    this->DisplayFrame(ren, vol);
  }
  else
  {
    // Nothing is drawn: an empty image.
    internals.Image->Initialize();
    internals.HaveImage = false;
  }
  timer->StopTimer();
  this->LastRenderTime = timer->GetElapsedTime();
}

bool vtkAdaptiveVolumeMapper::ValidateSettings()
{
  an::AdaptiveSettings<double>& adaptive = this->Internals->Adaptive;
  adaptive = an::AdaptiveSettings<double>();
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
    return false;
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
      return false;
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
      return false;
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
    return false;
  }
  return true;
}

vtkImageData* vtkAdaptiveVolumeMapper::UpdateInput()
{
  vtkInternals& internals = *this->Internals;
  if (!this->GetInput())
  {
    vtkErrorMacro(<< "No input.");
    return nullptr;
  }
  this->GetInputAlgorithm()->Update();
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  if (!input)
  {
    vtkErrorMacro(<< "The input must be a vtkImageData, not a " << this->GetInput()->GetClassName()
                  << ".");
    return nullptr;
  }
  int cellFlag = 0;
  vtkDataArray* scalars = vtkAbstractMapper::GetScalars(
    input, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag);
  const std::string error =
    avos::ValidateVolumeInput(input, scalars, cellFlag != 0, avos::numerics::MaximumComponents);
  if (!error.empty())
  {
    vtkErrorMacro(<< "Cannot render: " << error << ".");
    return nullptr;
  }
  input->GetDimensions(internals.Dimensions);
  internals.CellData = cellFlag != 0;
  internals.Scalars = this->ScalarsOfVectorMode(scalars);
  internals.Components = internals.Component >= 0 ? 1 : internals.Scalars->GetNumberOfComponents();
  return input;
}

vtkDataArray* vtkAdaptiveVolumeMapper::ScalarsOfVectorMode(vtkDataArray* scalars)
{
  vtkInternals& internals = *this->Internals;
  internals.Component = -1;
  const int components = scalars->GetNumberOfComponents();
  if (components == 1 || this->VectorMode == DISABLED)
  {
    return scalars;
  }
  if (this->VectorMode == COMPONENT)
  {
    internals.Component = std::min(this->VectorComponent, components - 1);
    return scalars;
  }
  if (scalars != internals.MagnitudeOf || scalars->GetMTime() != internals.MagnitudeTime)
  {
    vtkFloatArray* magnitude = internals.Magnitude;
    magnitude->SetName("Magnitude");
    magnitude->SetNumberOfTuples(scalars->GetNumberOfTuples());
    MagnitudeWorker worker;
    if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker, magnitude))
    {
      worker(scalars, magnitude);
    }
    magnitude->Modified();
    internals.MagnitudeOf = scalars;
    internals.MagnitudeTime = scalars->GetMTime();
  }
  return internals.Magnitude;
}

bool vtkAdaptiveVolumeMapper::UpdateGeometry(vtkImageData* input, vtkVolume* vol)
{
  vtkInternals& internals = *this->Internals;
  // Grid -> world: the image's placement, then the volume's matrix.
  internals.Voxel = avos::GridToWorld(input, vol->GetMatrix(), internals.GridToWorld);
  vtkMatrix4x4::Invert(internals.GridToWorld, internals.WorldToGrid);
  if (!(internals.Voxel > 0.0) || !std::isfinite(internals.Voxel) ||
    internals.GridToWorld->Determinant() == 0.0)
  {
    vtkErrorMacro(<< "The volume's grid is degenerate in world space (zero spacing or a "
                     "singular volume matrix).");
    return false;
  }
  // Clipping planes (world) and cropping (the volume's coordinates, as VTK's
  // mappers: origin and spacing) -> grid coordinates.
  const std::string unusable =
    avos::ClipRegionOfMapper(this, input, internals.GridToWorld->GetData(), internals.Frame.Clip);
  if (!unusable.empty())
  {
    vtkErrorMacro(<< unusable << ".");
    return false;
  }
  return true;
}

bool vtkAdaptiveVolumeMapper::UpdateScalars(vtkVolume* vol)
{
  vtkInternals& internals = *this->Internals;
  vtkDataArray* scalars = internals.Scalars;
  // The field, as VTK's GPU mapper reads the scalars; the map's blocks read
  // what its cells read.
  const bool nearest = vol->GetProperty()->GetInterpolationType() == VTK_NEAREST_INTERPOLATION;
  const avos::engine::ScalarField field = avos::FieldOf(internals.CellData, nearest);
  const avos::EmptySpaceRanges::Samples samples = avos::SamplesOf(field);
  // The empty-space ranges, when the scalars or their field changed.
  if (!internals.Ranges.Update(scalars, internals.Dimensions, samples, internals.Component) ||
    !avos::ScalarsInPlace(scalars, internals.Dimensions, internals.View, internals.Component))
  {
    vtkErrorMacro(<< "Unsupported scalar type " << scalars->GetDataTypeAsString() << ".");
    return false;
  }
  // NaN: the field is undefined in every cell with a NaN corner (a NaN
  // cell, a NaN point's nearest region), and each method takes it as empty
  // (transparent). Said once per change of the scalars.
  internals.Ranges.WarnOfNaNs(this);
  internals.View.Field = field;
  // Bounds of the trilinear field (every component's), and the projections'
  // normalisation.
  scalars->GetRange(internals.DataRange, std::max(internals.Component, 0));
  for (int k = 1; k < internals.Components; ++k)
  {
    const double* range = scalars->GetRange(k);
    internals.DataRange[0] = std::min(internals.DataRange[0], range[0]);
    internals.DataRange[1] = std::max(internals.DataRange[1], range[1]);
  }
  return true;
}

bool vtkAdaptiveVolumeMapper::UpdateProperty(vtkRenderer* ren, vtkVolume* vol)
{
  vtkInternals& internals = *this->Internals;
  vtkVolumeProperty* property = vol->GetProperty();
  // What the mapper does not honour is refused, never ignored.
  std::string unsupported = avos::UnsupportedPropertySettings(property, internals.Components);
  if (unsupported.empty())
  {
    unsupported = avos::UnsupportedForComponents(
      property, internals.Components, this->BlendMode == COMPOSITE_BLEND);
  }
  if (!unsupported.empty())
  {
    vtkErrorMacro(<< unsupported << ".");
    return false;
  }
  internals.Shade = property->GetShade(0) != 0;
  internals.ShadingKey.clear();
  if (internals.Shade && internals.View.Field != avos::engine::ScalarField::Trilinear)
  {
    vtkErrorMacro(<< "Cannot shade: only point scalars with linear interpolation are shaded (a "
                     "field constant per cell has no gradient; cell scalars' between their "
                     "centres is not modelled).");
    return false;
  }
  if (internals.Shade && this->BlendMode != COMPOSITE_BLEND)
  {
    vtkErrorMacro(<< "Cannot shade: shading applies to the composite blend mode only, not to "
                     "projections; turn the property's Shade off.");
    return false;
  }
  if (internals.Shade)
  {
    const std::string error =
      avos::ShadingFromRenderer(ren, property, internals.Shading, internals.ShadingKey);
    if (!error.empty())
    {
      vtkErrorMacro(<< "Cannot shade: " << error << ".");
      return false;
    }
  }
  return this->UpdateTransferFunction(property) && this->UpdateGradientOpacity(property) &&
    this->UpdatePieces();
}

bool vtkAdaptiveVolumeMapper::UpdateTransferFunction(vtkVolumeProperty* property)
{
  vtkInternals& internals = *this->Internals;
  const bool mixture = internals.Components > 1;
  // Property -> transfer function and block visibility. The piecewise
  // method's colours and opacity are converted within shares of its eps where
  // VTK's are not piecewise linear, and the rays integrated to the rest; lit,
  // a colour's error is multiplied by up to the shading's colour gain.
  const double gain = internals.ColourGain();
  const double chord = internals.LongestRay();
  const bool piecewise = this->IntegrationMethod == PIECEWISE_ADAPTIVE;
  const bool reference = this->IntegrationMethod == REFERENCE;
  avos::ConversionBudget request; // none: the sampled methods certify nothing
  if (piecewise || reference)
  {
    request = avos::ConversionBudget::ForTolerance(
      piecewise ? this->Tolerance : ReferenceConversions[0], gain, chord);
  }
  if (property->GetMTime() != internals.PropertyTime ||
    this->OpacityModel != internals.OpacityModel || internals.Voxel != internals.ClassifiedVoxel ||
    internals.ClassifyTime.GetMTime() < internals.Ranges.GetTime() ||
    !request.SameAs(internals.ConversionRequest))
  {
    const bool extinction = this->OpacityModel == EXTINCTION_OPACITY;
    auto convert = [&](avos::ConversionBudget& budget)
    {
      return mixture ? avos::MixtureFromProperty(property, internals.Components,
                         internals.Scalars->GetDataType(), extinction, internals.Voxel,
                         internals.Mixture, &budget)
                     : avos::TransferFunctionFromProperty(
                         property, extinction, internals.Voxel, internals.TF, &budget);
    };
    avos::ConversionBudget budget = request;
    std::string error = convert(budget);
    for (std::size_t k = 1; reference && error.empty() && budget.Approximated > 0 &&
         k < std::size(ReferenceConversions);
         ++k)
    {
      budget = avos::ConversionBudget::ForTolerance(ReferenceConversions[k], gain, chord);
      error = convert(budget);
    }
    internals.ConversionRequest = request;
    internals.Conversion = budget;
    if (!error.empty())
    {
      vtkErrorMacro(<< "Unusable transfer function: " << error << ".");
      internals.PropertyTime = 0;
      return false;
    }
    if (budget.Approximated > 0)
    {
      vtkWarningMacro(<< avos::ApproximationNotice(budget.Approximated) << ".");
    }
    const an::MixtureTransferFunction<double>& medium = internals.Mixture.Mixture;
    internals.VisibleBlocks = mixture
      ? internals.Ranges.GetMap().ClassifyBlocks(
          [&medium](const double* lo, const double* hi) { return medium.IsVisible(lo, hi); })
      : internals.Ranges.GetMap().Classify(internals.TF);
    internals.PropertyTime = property->GetMTime();
    internals.OpacityModel = this->OpacityModel;
    internals.ClassifiedVoxel = internals.Voxel;
    internals.ClassifyTime.Modified();
  }
  // (The reference integrates at its own tolerance.)
  internals.IntegrationTolerance =
    piecewise ? avos::IntegrationTolerance(this->Tolerance, internals.Conversion) : this->Tolerance;
  return true;
}

bool vtkAdaptiveVolumeMapper::UpdateGradientOpacity(vtkVolumeProperty* property)
{
  vtkInternals& internals = *this->Internals;
  internals.UsesGradientOpacity = avos::UsesGradientOpacity(property, 0);
  if (!internals.UsesGradientOpacity)
  {
    return true;
  }
  // (Several components are refused by UpdateProperty.)
  const char* refused = this->BlendMode != COMPOSITE_BLEND ? "projections"
    : internals.View.Field != avos::engine::ScalarField::Trilinear
    ? "a field constant per cell (it has no gradient)"
    : nullptr;
  if (refused)
  {
    vtkErrorMacro(<< "Gradient opacity is not supported with " << refused
                  << "; disable the property's gradient opacity.");
    return false;
  }
  // The piecewise method takes a curved G within GradientShare of its eps
  // (the rays integrated to the rest). The other methods, the reference
  // included, resample it: at the reference's conversion tolerances its
  // knots would be so dense that the enclosures of G's kinks could not
  // isolate them within a piece's sub-interval cap.
  const bool piecewise = this->IntegrationMethod == PIECEWISE_ADAPTIVE;
  const double largest = internals.TF.GetMaximumExtinction(
    -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  int approximated = 0;
  const std::string error = internals.GradientConversion.Update(property, largest,
    piecewise ? avos::ConversionBudget::ForGradientOpacity(
                  this->Tolerance, internals.ColourGain(), internals.LongestRay())
              : avos::ConversionBudget(),
    approximated);
  if (!error.empty())
  {
    vtkErrorMacro(<< "Unusable gradient opacity: " << error << ".");
    return false;
  }
  if (approximated > 0)
  {
    vtkWarningMacro(<< avos::ApproximationNotice(approximated) << ".");
  }
  if (piecewise)
  {
    internals.IntegrationTolerance -= internals.GradientConversion.GetBudget().Spent;
  }
  // Gradients in grid coordinates to world space (scalar units per world unit).
  internals.Gradient.Function = &internals.GradientConversion.Get();
  internals.Gradient.NormalMatrix = avos::NormalMatrix(internals.GridToWorld->GetData());
  return true;
}

bool vtkAdaptiveVolumeMapper::UpdatePieces()
{
  vtkInternals& internals = *this->Internals;
  // Transfer function -> pieces with polynomial extinction, for the
  // piecewise methods (the reference's too, shaded, scaled by gradient
  // opacity or not).
  const bool additive = this->BlendMode == vtkVolumeMapper::ADDITIVE_BLEND;
  internals.Piecewise = this->IntegrationMethod == PIECEWISE_ADAPTIVE || additive ||
    this->IntegrationMethod == REFERENCE;
  if (internals.Piecewise)
  {
    // The relative error only matters in VTK's alpha model (the extinction
    // model's pieces are exact).
    const double relativeError = this->IntegrationMethod == PIECEWISE_ADAPTIVE || additive
      ? an::PiecewiseRelativeError(internals.IntegrationTolerance)
      : an::PiecewiseRelativeError(an::PiecewiseReferenceTolerance<double>());
    if (internals.PiecesTime.GetMTime() < internals.ClassifyTime.GetMTime() ||
      relativeError != internals.PiecesRelativeError)
    {
      const std::string error = internals.Components > 1
        ? internals.MixturePieces.Build(internals.Mixture.Mixture, relativeError)
        : internals.Pieces.Build(internals.TF, relativeError);
      if (!error.empty())
      {
        vtkErrorMacro(<< "The piecewise method cannot use this transfer function at tolerance "
                      << this->Tolerance << ": " << error << ".");
        internals.PiecesRelativeError = 0.0;
        return false;
      }
      internals.PiecesRelativeError = relativeError;
      internals.PiecesTime.Modified();
    }
  }
  // The average projection's range, within the data's (VTK's default range
  // is the whole float line), as pieces that mark it.
  if (this->BlendMode == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND)
  {
    const double r0 = std::max(this->AverageIPScalarRange[0], internals.DataRange[0]);
    const double r1 = std::min(this->AverageIPScalarRange[1], internals.DataRange[1]);
    // A range beside the data's holds no ray: zero width.
    const std::string error = internals.AverageRange.Build(internals.TF, r0, std::max(r0, r1));
    if (!error.empty())
    {
      vtkErrorMacro(<< "Unusable average intensity range [" << this->AverageIPScalarRange[0] << ", "
                    << this->AverageIPScalarRange[1] << "]: " << error << ".");
      return false;
    }
  }
  return true;
}

bool vtkAdaptiveVolumeMapper::UpdateKernelTables()
{
  vtkInternals& internals = *this->Internals;
  vtkDataArray* scalars = internals.Scalars;
  // The Riemann kernel's scalars and table (volumes beyond its 32-bit
  // indices take the scalar sum; shaded sums too: the kernels do not shade),
  // and the scalars alone for the piecewise method's cells where they are 8-
  // or 16-bit unsigned (the only ones the cells' kernel reads). The kernels
  // read the trilinear interpolant of one component, in place: the scalars'
  // only one, the vector mode's, or the only one of a mixture that shows
  // (the engine casts that mixture as the component alone).
  const bool mixture = internals.Components > 1;
  const an::MixtureTransferFunction<double>& medium = internals.Mixture.Mixture;
  const int shown = mixture ? medium.GetSingleComponent() : std::max(internals.Component, 0);
  const bool readable = internals.View.Field == avos::engine::ScalarField::Trilinear && shown >= 0;
  const bool riemann = this->IntegrationMethod == RIEMANN && !internals.Shade &&
    !internals.UsesGradientOpacity && readable;
  const bool cells = this->IntegrationMethod == PIECEWISE_ADAPTIVE && readable &&
    avos::engine::ReadsCells(avos::EngineVolume::EngineType(scalars->GetDataType()));
  const avos::engine::Volume* kernelScalars = riemann || cells
    ? internals.EngineScalars.Update(scalars, internals.Dimensions, shown)
    : nullptr;
  internals.RiemannScalars = riemann ? kernelScalars : nullptr;
  internals.CellScalars = cells ? kernelScalars : nullptr;
  // (A change of the scalars' components reclassifies: ClassifyTime, then
  // PiecesTime, follow the mixture's single medium.)
  if (internals.RiemannScalars &&
    internals.EngineTableTime.GetMTime() < internals.ClassifyTime.GetMTime())
  {
    const std::string error =
      internals.EngineTable.Build(mixture ? *medium.GetSingle() : internals.TF);
    if (!error.empty())
    {
      vtkErrorMacro(<< "Unusable transfer function: " << error << ".");
      return false;
    }
    internals.EngineTableTime.Modified();
  }
  // The pieces' table for the piecewise method's ray-per-lane integrator,
  // where it can read the scalars.
  const an::PiecewiseTransferFunction<double>* pieces =
    mixture ? internals.MixturePieces.GetSingle() : &internals.Pieces;
  internals.PieceLanes = internals.CellScalars && pieces &&
    avos::engine::ValidatePiecewiseRays(*internals.CellScalars, *pieces).empty();
  if (internals.PieceLanes && internals.PieceTableTime.GetMTime() < internals.PiecesTime.GetMTime())
  {
    const std::string error = internals.PieceTable.Build(*pieces);
    if (!error.empty())
    {
      vtkErrorMacro(<< "Unusable transfer function: " << error << ".");
      return false;
    }
    internals.PieceTableTime.Modified();
  }
  return true;
}

bool vtkAdaptiveVolumeMapper::SetUpFrame(vtkRenderer* ren, vtkVolume* vol)
{
  vtkInternals& internals = *this->Internals;
  int viewportWidth, viewportHeight, x0, y0;
  ren->GetTiledSizeAndOrigin(&viewportWidth, &viewportHeight, &x0, &y0);
  if (viewportWidth < 1 || viewportHeight < 1)
  {
    return false;
  }
  const double distance = this->NextImageSampleDistance(vol);
  internals.Distance = distance;
  const int width = std::max(1, static_cast<int>(std::ceil(viewportWidth / distance - 1e-9)));
  const int height = std::max(1, static_cast<int>(std::ceil(viewportHeight / distance - 1e-9)));
  avos::engine::Frame& frame = internals.Frame;
  frame.Rays.Width = width;
  frame.Rays.Height = height;
  std::copy(internals.Dimensions, internals.Dimensions + 3, frame.Rays.Dimensions);
  frame.Rays.Voxel = internals.Voxel;
  internals.ViewportDepth.resize(static_cast<std::size_t>(viewportWidth) * viewportHeight);
  if (!ren->GetRenderWindow()->GetZbufferData(
        x0, y0, x0 + viewportWidth - 1, y0 + viewportHeight - 1, internals.ViewportDepth.data()))
  {
    std::fill(internals.ViewportDepth.begin(), internals.ViewportDepth.end(), 1.0f);
  }
  frame.SampleDepth(internals.ViewportDepth.data(), viewportWidth, viewportHeight);
  vtkMatrix4x4* projection = ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(
    ren->GetTiledAspectRatio(), -1, 1);
  vtkNew<vtkMatrix4x4> ndcToWorld;
  vtkMatrix4x4::Invert(projection, ndcToWorld);
  std::copy(ndcToWorld->GetData(), ndcToWorld->GetData() + 16, frame.Rays.NDCToWorld);
  std::copy(internals.WorldToGrid->GetData(), internals.WorldToGrid->GetData() + 16,
    frame.Rays.WorldToGrid);
  // Cast only the box's footprint on the screen.
  frame.SetFootprint(internals.GridToWorld->GetData(), projection->GetData());

  FrameKey& key = internals.Key;
  std::copy(projection->GetData(), projection->GetData() + 16, key.Projection.begin());
  std::copy(internals.GridToWorld->GetData(), internals.GridToWorld->GetData() + 16,
    key.GridToWorld.begin());
  key.Viewport = { { x0, y0, viewportWidth, viewportHeight, width, height } };
  key.MapperTime = this->GetMTime();
  key.ClassifyTime = internals.ClassifyTime.GetMTime();
  key.RangesTime = internals.Ranges.GetTime();
  key.Shading = internals.ShadingKey;
  return true;
}

double vtkAdaptiveVolumeMapper::NextImageSampleDistance(vtkVolume* vol) const
{
  const vtkInternals& internals = *this->Internals;
  if (!this->AutoAdjustSampleDistances)
  {
    return this->ImageSampleDistance;
  }
  // What fits the renderer's time for the volume, the cast time taken as
  // proportional to the number of rays (1 / distance^2).
  const double budget = vol->GetAllocatedRenderTime();
  double distance = internals.CastDistance;
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
  return std::min(std::max(distance, this->MinimumImageSampleDistance),
    std::max(this->MinimumImageSampleDistance, this->MaximumImageSampleDistance));
}

void vtkAdaptiveVolumeMapper::SetUpMethod()
{
  vtkInternals& internals = *this->Internals;
  avos::engine::FrameMethod& method = internals.Method;
  method = avos::engine::FrameMethod();
  const avos::engine::Integration kinds[] = { avos::engine::Integration::Riemann,
    avos::engine::Integration::AdaptiveCoupled, avos::engine::Integration::AdaptiveDecoupled,
    avos::engine::Integration::Reference, avos::engine::Integration::Piecewise };
  method.Kind = kinds[this->IntegrationMethod];
  method.Mode = EngineBlend(this->BlendMode);
  method.Adaptive = internals.Adaptive;
  method.Adaptive.Tolerance = internals.IntegrationTolerance;
  // Trilinear values never leave the data's range.
  method.Adaptive.FieldMinimum = internals.DataRange[0];
  method.Adaptive.FieldMaximum = internals.DataRange[1];
  method.SampleDistance = this->SampleDistance;
  method.TerminationBound = 0.2 * internals.IntegrationTolerance;
  method.TF = &internals.TF;
  method.Map = this->EmptySpaceSkipping ? &internals.Ranges.GetMap() : nullptr;
  method.Range = &internals.AverageRange;
  method.ScalarMinimum = internals.DataRange[0];
  // A constant volume: any positive span gives n = 0 everywhere.
  method.ScalarMaximum = internals.DataRange[1] > internals.DataRange[0]
    ? internals.DataRange[1]
    : internals.DataRange[0] + 1.0;
  const bool mixture = internals.Components > 1;
  method.Pieces = internals.Piecewise && !mixture ? &internals.Pieces : nullptr;
  method.Mixture = mixture ? &internals.Mixture.Mixture : nullptr;
  method.MixturePieces = internals.Piecewise && mixture ? &internals.MixturePieces : nullptr;
  method.EngineVolume = internals.RiemannScalars;
  method.EngineTable = internals.RiemannScalars ? &internals.EngineTable : nullptr;
  method.Kernels = avos::engine::PieceKernels(internals.CellScalars);
  method.PieceTable = internals.PieceLanes ? &internals.PieceTable : nullptr;
  if (internals.Shade)
  {
    avos::ShadeWith(internals.Shading, internals.GridToWorld->GetData(), method);
  }
  method.GradientOpacity = internals.UsesGradientOpacity ? &internals.Gradient : nullptr;
}

bool vtkAdaptiveVolumeMapper::CastFrame(vtkRenderer* ren)
{
  vtkInternals& internals = *this->Internals;
  const avos::engine::Frame& frame = internals.Frame;
  const int width = frame.Rays.Width, height = frame.Rays.Height;
  internals.Image->SetDimensions(width, height, 1);
  vtkNew<vtkFloatArray> rgba;
  rgba->SetName("RGBA");
  rgba->SetNumberOfComponents(4);
  rgba->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
  rgba->Fill(0.0);
  internals.Image->GetPointData()->SetScalars(rgba);
  float* image = rgba->GetPointer(0);
  this->SetUpMethod();
  const avos::engine::FrameMethod& method = internals.Method;
  const std::string invalid = avos::engine::Validate(internals.View, method);
  if (!invalid.empty())
  {
    vtkErrorMacro(<< "Cannot cast the frame: " << invalid << ".");
    return false;
  }
  avos::engine::FrameStatistics statistics;
  // (With every block transparent nothing composites; the projections
  // still show the volume: an opaque black or grey.)
  if (!method.Map || internals.VisibleBlocks > 0 ||
    this->BlendMode != vtkVolumeMapper::COMPOSITE_BLEND)
  {
    avos::engine::WorkMonitor monitor;
    // Progress and the render window's abort check (an interactor's, or
    // avos-render's Ctrl-C) every WorkMonitor::Interval, whatever the SMP
    // backend; an abort takes effect within that plus one tile per thread.
    const bool aborted =
      !monitor.Run(
        avos::engine::FrameCaster::Tiles(frame),
        [&] {
          statistics = internals.Caster.Cast(frame, internals.View, method, image, SMPFor, monitor);
        },
        [this, ren](double fraction)
        {
          this->UpdateProgress(fraction);
          return ren->GetRenderWindow()->CheckAbortStatus() != 0;
        }) ||
      ren->GetRenderWindow()->CheckAbortStatus() != 0;
    if (aborted)
    {
      return false;
    }
    this->UpdateProgress(1.0);
  }
  if (statistics.Failed > 0)
  {
    // No silent holes: the frame is refused with what went wrong.
    vtkErrorMacro(<< statistics.Failed
                  << " ray(s) could not be integrated: " << statistics.FirstError << ".");
    return false;
  }
  this->PublishStatistics(statistics.Rays, statistics.Samples, statistics.MaximumSamples,
    statistics.Rejected, statistics.Cells, statistics.Pieces);
  this->ConvertForDisplay(image, 4 * static_cast<std::size_t>(width) * height);
  internals.LastKey = internals.Key;
  internals.LastDepth = frame.Depth;
  internals.LastClip = frame.Clip;
  internals.HaveImage = true;
  internals.FrameScalars = internals.Scalars;
  internals.CastDistance = internals.Distance;
  this->LastImageSampleDistance = internals.Distance;
  return true;
}

void vtkAdaptiveVolumeMapper::PublishStatistics(vtkIdType rays, vtkIdType samples,
  vtkIdType maximumSamples, vtkIdType rejected, vtkIdType cells, vtkIdType pieces)
{
  this->RaysCast = rays;
  this->MeanSamplesPerRay =
    rays > 0 ? static_cast<double>(samples) / static_cast<double>(rays) : 0.0;
  this->MaximumSamplesPerRay = maximumSamples;
  this->RejectedSteps = rejected;
  const double count = static_cast<double>(std::max<vtkIdType>(rays, 1));
  this->MeanCellsPerRay = static_cast<double>(cells) / count;
  this->MeanPiecesPerRay = static_cast<double>(pieces) / count;
}

void vtkAdaptiveVolumeMapper::ConvertForDisplay(const float* image, std::size_t values)
{
  // 16-bit premultiplied RGBA for the display helper, in parallel (a serial
  // pass over the image weighed on two threads). v * 65535 + 0.5 is exact in
  // float for v in [0, 1] (at most 8 fractional bits there), so truncating
  // it rounds as lround did; NaN gives 0.
  std::vector<std::uint16_t>& display = this->Internals->Display;
  display.resize(values);
  std::uint16_t* out = display.data();
  vtkSMPTools::For(0, static_cast<vtkIdType>(values),
    [out, image](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType i = begin; i < end; ++i)
      {
        const float v = image[i] > 0.0f ? std::min(image[i], 1.0f) : 0.0f;
        out[i] = static_cast<std::uint16_t>(v * 65535.0f + 0.5f);
      }
    });
}

void vtkAdaptiveVolumeMapper::DisplayFrame(vtkRenderer* ren, vtkVolume* vol)
{
  vtkInternals& internals = *this->Internals;
  if (!internals.DisplayHelper)
  {
    vtkErrorMacro(<< "No ray cast image display helper: is VTK::RenderingVolumeOpenGL2 linked?");
    return;
  }
  int size[2] = { internals.Frame.Rays.Width, internals.Frame.Rays.Height };
  int origin[2] = { 0, 0 };
  // In front of everything: occlusion by opaque geometry is already in the
  // image (rays stop at the depth buffer).
  internals.DisplayHelper->RenderTexture(
    vol, ren, size, size, size, origin, 1e-6f, internals.Display.data());
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
  const avos::engine::Frame& frame = internals.Frame;
  if (!internals.HaveImage)
  {
    vtkErrorMacro(<< "TraceRay re-casts a pixel of the last render: there is none.");
    return false;
  }
  if (internals.Method.Kind == avos::engine::Integration::Reference)
  {
    vtkErrorMacro(<< "The reference method records no steps to trace.");
    return false;
  }
  if (x < 0 || y < 0 || x >= frame.Rays.Width || y >= frame.Rays.Height)
  {
    vtkErrorMacro(<< "Pixel (" << x << ", " << y << ") is outside the " << frame.Rays.Width << " x "
                  << frame.Rays.Height << " image.");
    return false;
  }
  std::vector<an::StepRecord<double>> records;
  an::RayResult<double> result;
  const bool hit = avos::engine::FrameCaster::TracePixel(
    frame, internals.View, internals.Method, x, y, result, &records);
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
  os << indent << "VectorMode: " << this->VectorMode << "\n";
  os << indent << "VectorComponent: " << this->VectorComponent << "\n";
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
