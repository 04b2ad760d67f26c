#include "vtkOpenGLAdaptiveVolumeMapper.h"

#include "avosAdaptiveIntegratorGLSL.h"
#include "avosClippingPlanes.h"
#include "avosEmptySpaceRanges.h"
#include "avosEngineVolume.h"
#include "avosImageGrid.h"
#include "avosShadingFromRenderer.h"
#include "avosTransferFunctionFromProperty.h"
#include "avosVolumeInput.h"
#include "vtkAdaptiveVolumeMapper.h"

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderProperty.h"
#include "vtkPlaneCollection.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"
#include "vtkTimeStamp.h"
#include "vtkUniforms.h"
#include "vtkVolume.h"
#include "vtkVolumeInputHelper.h"
#include "vtkVolumeProperty.h"
#include "vtk_glew.h"

#include "avos/numerics/Accumulation.h"
#include "avos/numerics/PiecewiseIntegrator.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkOpenGLAdaptiveVolumeMapper);

namespace
{
// Uniform vectors the shader needs besides the transfer function's pieces
// (VTK's own uniforms and ours), kept free of the GPU's fragment storage.
constexpr int ReservedUniformVectors = 256;

// The clipping planes the shader takes (as VTK's GPU mapper).
constexpr int MaximumClippingPlanes = 6;

// The light slots of the shader (avos_lit's).
constexpr int MaximumLights = 8;

// The most pieces of a gradient opacity function the shader searches
// (avos_gradientFactor's 7 steps).
constexpr int MaximumGradientPieces = 128;

// The field the scalars make (avos::FieldOf), numbered as the shader's
// avos_fieldKind numbers it: point scalars trilinear (0) or nearest (1), cell
// scalars constant per cell (nearest, 2) or trilinear between the cells'
// centres (linear, 3).
using Field = avos::engine::ScalarField;
static_assert(static_cast<int>(Field::Trilinear) == 0 && static_cast<int>(Field::Nearest) == 1 &&
    static_cast<int>(Field::Cells) == 2 && static_cast<int>(Field::CellCentres) == 3,
  "the shader's avos_fieldKind numbers");

// How the shader reads the data's scalar (component `component`, a channel
// of the texture) from VTK 9.1's texture: texel * Scale + Bias, rounded to
// an integer where Round. 8- and 16-bit integers
// are uploaded normalised (unsigned: UNORM, k / (2^b - 1); signed: SNORM,
// k / (2^(b-1) - 1), where -2^(b-1) reads as -2^(b-1) + 1); float as is;
// other types (double, 32- and 64-bit integers) cast to float after VTK's
// scale and bias onto [0, 1] over their finite range
// (vtkVolumeTexture::GetScaleAndBias), which the shader inverts within
// float's rounding of that range; with several components VTK uploads those
// types to an 8-bit texture (GL_RG, GL_RGB, GL_RGBA), which loses them: they
// are refused. Empty, or why the scalars cannot be read.
struct TexelMap
{
  float Scale = 1.0f;
  float Bias = 0.0f;
  bool Round = false;
};

std::string TexelToScalar(vtkDataArray* scalars, TexelMap& map, int component = 0)
{
  map = TexelMap();
  const int type = scalars->GetDataType();
  double range[2];
  scalars->GetFiniteRange(range, component);
  auto integers = [&](double unit, double minimum)
  {
    map.Scale = static_cast<float>(unit);
    map.Round = true;
    if (range[0] == minimum)
    {
      return std::string("scalars of type ") + scalars->GetDataTypeAsString() + " that reach " +
        std::to_string(static_cast<long>(minimum)) +
        " (VTK's normalised texture reads it as the next value up): convert them with "
        "vtkImageCast to float";
    }
    return std::string();
  };
  switch (type)
  {
    case VTK_UNSIGNED_CHAR:
      return integers(255.0, -1.0);
    case VTK_UNSIGNED_SHORT:
      return integers(65535.0, -1.0);
    case VTK_SIGNED_CHAR:
      return integers(127.0, -128.0);
    case VTK_SHORT:
      return integers(32767.0, -32768.0);
    case VTK_FLOAT:
      return std::string();
    case VTK_DOUBLE:
    case VTK_INT:
    case VTK_UNSIGNED_INT:
    case VTK_LONG:
    case VTK_UNSIGNED_LONG:
    case VTK_LONG_LONG:
    case VTK_UNSIGNED_LONG_LONG:
    {
      if (scalars->GetNumberOfComponents() > 1)
      {
        return std::string("scalars of several components of type ") +
          scalars->GetDataTypeAsString() +
          " (VTK uploads them to an 8-bit texture, which loses them): convert them with "
          "vtkImageCast to float";
      }
      // VTK: texel = float(v scale + bias), scale = float(1 / (hi - lo)),
      // bias = float(-lo scale), lo and hi the finite range in float.
      const double lo = static_cast<float>(range[0]);
      double hi = static_cast<float>(range[1]);
      hi = hi == lo ? lo + 1e-6 : hi;
      const double scale = static_cast<float>(1.0 / (hi - lo));
      const double bias = static_cast<float>(0.0 - lo * scale);
      map.Scale = static_cast<float>(1.0 / scale);
      map.Bias = static_cast<float>(-bias / scale);
      // Integers within 2^20 of each other come back exactly.
      map.Round = type != VTK_DOUBLE && hi - lo <= 1048576.0;
      return std::string();
    }
    default:
      return std::string("scalars of type ") + scalars->GetDataTypeAsString() +
        " are not supported (8-, 16-, 32- and 64-bit integers, float, double): convert them with "
        "vtkImageCast";
  }
}

// What the shader reads of the property's transfer function for scalars
// of one or several components.
struct ShaderMedium
{
  // One medium: the scalars' only component's function, or that of the one
  // component of several that alone shows (the others of weight 0 or
  // transparent; MixtureTransferFunction::GetSingle: its weight in its
  // extinction), read from texture channel Component.
  avos::numerics::TransferFunction<double> TF;
  int Component = 0;
  // Several components that show, or dependent ones: their mixture, every
  // channel read (Mixed; the sampled methods only).
  avos::MixtureFunctions Mixture;
  bool Mixed = false;

  // The functions the shader's pieces hold: TF, or the mixture's (one per
  // independent component, the one of dependent ones).
  std::vector<const avos::numerics::TransferFunction<double>*> Functions() const
  {
    if (!this->Mixed)
    {
      return { &this->TF };
    }
    const auto& m = this->Mixture.Mixture;
    const int n =
      m.GetMix() == avos::numerics::ComponentMix::Independent ? m.GetNumberOfComponents() : 1;
    std::vector<const avos::numerics::TransferFunction<double>*> functions;
    for (int f = 0; f < n; ++f)
    {
      functions.push_back(&m.GetFunction(f));
    }
    return functions;
  }

  // The pieces of Functions(), in all.
  std::size_t PieceCount() const
  {
    std::size_t count = 0;
    for (const auto* f : this->Functions())
    {
      count += f->GetPieces().size();
    }
    return count;
  }

  // The range of the field the shader reads: the rendered component's, or
  // every component's.
  void GetRange(vtkDataArray* scalars, double range[2]) const
  {
    scalars->GetRange(range, this->Component);
    for (int k = 0; k < scalars->GetNumberOfComponents() && this->Mixed; ++k)
    {
      const double* component = scalars->GetRange(k);
      range[0] = std::min(range[0], component[0]);
      range[1] = std::max(range[1], component[1]);
    }
  }

  // The property's transfer function for the scalars, within `budget`
  // (TransferFunctionFromProperty; MixtureFromProperty). Empty, or why not.
  std::string Convert(vtkVolumeProperty* property, vtkDataArray* scalars, bool extinction,
    double voxel, avos::ConversionBudget& budget)
  {
    const int components = scalars->GetNumberOfComponents();
    this->Component = 0;
    this->Mixed = false;
    if (components == 1)
    {
      return avos::TransferFunctionFromProperty(property, extinction, voxel, this->TF, &budget);
    }
    const std::string error = avos::MixtureFromProperty(
      property, components, scalars->GetDataType(), extinction, voxel, this->Mixture, &budget);
    if (!error.empty())
    {
      return error;
    }
    const avos::numerics::MixtureTransferFunction<double>& medium = this->Mixture.Mixture;
    if (medium.GetSingle())
    {
      this->TF = *medium.GetSingle();
      this->Component = medium.GetSingleComponent();
      return std::string();
    }
    this->Mixed = true;
    return std::string();
  }
};

// Empty, or why the shader's uniforms cannot hold `pieces` transfer-function
// pieces (3 vectors each) and `piecewisePieces` piecewise ones (4 each; the
// shader's knot searches take 12 steps: at most 4096 of either) beside the
// others.
std::string UniformStorageProblem(std::size_t pieces, std::size_t piecewisePieces, bool piecewise)
{
  GLint vectors = 0;
  glGetIntegerv(GL_MAX_FRAGMENT_UNIFORM_VECTORS, &vectors);
  const std::size_t needed = 3 * pieces + 4 * piecewisePieces;
  if (static_cast<GLint>(needed) <= vectors - ReservedUniformVectors && pieces <= 4096 &&
    piecewisePieces <= 4096)
  {
    return std::string();
  }
  std::ostringstream message;
  message << "the transfer function has " << pieces << " pieces"
          << (piecewise ? " and " + std::to_string(piecewisePieces) + " piecewise ones" : "")
          << ": " << needed << " uniform vectors, more than this GPU's fragment uniforms hold ("
          << std::max(0, vectors - ReservedUniformVectors) << ")";
  return message.str();
}

// x = hi + lo to about 2^-48 relative: hi is x rounded to float, lo the rest.
void Split(double x, float& hi, float& lo)
{
  hi = static_cast<float>(x);
  lo = static_cast<float>(x - static_cast<double>(hi));
}

} // namespace

class vtkOpenGLAdaptiveVolumeMapper::vtkInternals
{
public:
  // The property's transfer function (ShaderMedium), converted again only
  // when the property, the opacity model, the voxel size, the conversion's
  // budget or the scalars' components change.
  ShaderMedium Medium;
  int TFComponents = 1;            // the scalars' components Medium was converted for
  int TablesComponents = 0;        // the scalars' components VTK's tables were made for
  vtkMTimeType TFPropertyTime = 0; // 0: not converted (or refused)
  int TFModel = 0;
  double TFVoxel = 0.0;
  avos::ConversionBudget Conversion;       // what the conversion took (the piecewise method's)
  avos::numerics::ClipRegion<double> Clip; // the planes and cropping in grid coordinates
  vtkTimeStamp TFTime;
  int PieceCount = -1; // the size the piece arrays were declared with

  // The piecewise method's pieces (PIECEWISE_ADAPTIVE only), rebuilt when
  // the transfer function or the tolerance changes; the tolerance the rays
  // are integrated to (what the conversion left of eps; eps for the other
  // methods).
  avos::numerics::PiecewiseTransferFunction<double> Pieces;
  vtkTimeStamp PiecesTime;
  double PiecesTolerance = 0.0;
  double IntegrationTolerance = 0.0;
  int PiecewiseCount = -1; // the size the avos_pp arrays were declared with

  // The average projection's range as pieces that mark it (built each
  // frame: the knots of one function), and the data's range, which the
  // additive and average projections normalise the scalar to.
  avos::numerics::AverageRange<double> AverageRange;
  double DataRange[2] = { 0.0, 1.0 };

  // The pieces the shader's piece walk reads this frame: the transfer
  // function's for the piecewise method and the additive projection, the
  // range's marks for the average (avos_averagePiece; none for a range that
  // holds no ray), none otherwise.
  const avos::numerics::PiecewiseTransferFunction<double>* WalkedPieces(
    int method, int blendMode) const
  {
    if (blendMode == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND)
    {
      return this->AverageRange.IsEmpty() ? nullptr : &this->AverageRange.GetPieces();
    }
    const bool walks = method == vtkOpenGLAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE ||
      blendMode == vtkVolumeMapper::ADDITIVE_BLEND;
    return walks ? &this->Pieces : nullptr;
  }

  // The field of this frame's scalars (PrepareFrame).
  Field ScalarField = Field::Trilinear;

  // This frame's shading (UpdateShading): the property's and the
  // renderer's lights.
  bool Shade = false;
  avos::numerics::ShadingModel<double> Shading;
  std::vector<double> ShadingKey;

  // This frame's gradient opacity (UpdateGradientOpacity): G as the
  // opacity knots of a transfer function over the gradient's magnitude.
  bool UsesGradientOpacity = false;
  avos::GradientOpacityConversion GradientConversion;

  // Empty-space skipping: the blocks' ranges (rebuilt when the scalars
  // change) and their visibility as a 3D texture (rebuilt when the ranges or
  // the transfer function change).
  avos::EmptySpaceRanges Ranges;
  vtkNew<vtkTextureObject> Blocks;
  bool BlocksHoldMap = false; // else a 1^3 placeholder (skipping off)
  vtkMTimeType BlocksRangesTime = 0;
  vtkTimeStamp BlocksTime;
};

//------------------------------------------------------------------------------
vtkOpenGLAdaptiveVolumeMapper::vtkOpenGLAdaptiveVolumeMapper()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkOpenGLAdaptiveVolumeMapper::~vtkOpenGLAdaptiveVolumeMapper() = default;

//------------------------------------------------------------------------------
const char* vtkOpenGLAdaptiveVolumeMapper::GetIntegrationMethodAsString()
{
  switch (this->IntegrationMethod)
  {
    case RIEMANN:
      return "Riemann";
    case ADAPTIVE_COUPLED:
      return "AdaptiveCoupled";
    case ADAPTIVE_DECOUPLED:
      return "AdaptiveDecoupled";
    default:
      return "PiecewiseAdaptive";
  }
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::CheckRenderable(
  vtkRenderer* ren, vtkVolumeProperty* property)
{
  std::string problem = this->CheckInput();
  if (problem.empty())
  {
    problem = this->CheckVTKSettings(ren);
  }
  if (problem.empty())
  {
    problem = this->CheckMethodSettings();
  }
  const int components = problem.empty() ? this->GetRenderedScalars()->GetNumberOfComponents() : 1;
  if (problem.empty())
  {
    problem = avos::UnsupportedPropertySettings(property, components);
  }
  if (problem.empty())
  {
    problem = avos::UnsupportedForComponents(
      property, components, this->BlendMode == vtkVolumeMapper::COMPOSITE_BLEND);
  }
  return problem.empty() ? this->CheckGradientSettings(property) : problem;
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::CheckGradientSettings(vtkVolumeProperty* property)
{
  if (!property)
  {
    return std::string();
  }
  // The CPU mapper's rules, in the sampled methods (their samples are lit
  // and scaled).
  const bool gradientOpacity = avos::UsesGradientOpacity(property, 0);
  if (!gradientOpacity && !property->GetShade(0))
  {
    return std::string();
  }
  const bool piecewise = this->IntegrationMethod == PIECEWISE_ADAPTIVE;
  const bool composite = this->BlendMode == vtkVolumeMapper::COMPOSITE_BLEND;
  const bool trilinear = static_cast<Field>(this->ScalarFieldOf(property)) == Field::Trilinear;
  if (gradientOpacity && (piecewise || !composite || !trilinear))
  {
    return "Gradient opacity is supported by the GPU's sampled methods (not its piecewise "
           "method: its certified version is vtkAdaptiveVolumeMapper's) with point scalars, "
           "linear interpolation and the composite blend; disable the property's gradient "
           "opacity";
  }
  if (!property->GetShade(0))
  {
    return std::string();
  }
  if (piecewise)
  {
    return "the GPU's piecewise method does not shade (its certified lit colour is the CPU "
           "mapper's): turn the property's Shade off, use a sampled method, or "
           "vtkAdaptiveVolumeMapper";
  }
  if (!trilinear)
  {
    return "Cannot shade: only point scalars with linear interpolation are shaded (a field "
           "constant per cell has no gradient; cell scalars' between their centres is not "
           "modelled)";
  }
  if (!composite)
  {
    return "Cannot shade: shading applies to the composite blend mode only, not to projections; "
           "turn the property's Shade off";
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkOpenGLAdaptiveVolumeMapper::ScalarFieldOf(vtkVolumeProperty* property)
{
  int cellFlag = 0;
  vtkAbstractMapper::GetScalars(this->GetInput(), this->ScalarMode, this->ArrayAccessMode,
    this->ArrayId, this->ArrayName, cellFlag);
  const bool nearest = property->GetInterpolationType() == VTK_NEAREST_INTERPOLATION;
  return static_cast<int>(avos::FieldOf(cellFlag != 0, nearest));
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::CheckInput()
{
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  if (!input)
  {
    return "the input is not a vtkImageData";
  }
  int cellFlag = 0;
  vtkDataArray* scalars = vtkAbstractMapper::GetScalars(
    input, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag);
  const std::string invalid =
    avos::ValidateVolumeInput(input, scalars, cellFlag != 0, avos::numerics::MaximumComponents);
  if (!invalid.empty())
  {
    return invalid;
  }
  if (this->GetInputCount() > 1)
  {
    return "a vtkMultiVolume's inputs beyond the first are not supported";
  }
  std::string unreadable;
  for (int k = 0; k < scalars->GetNumberOfComponents() && unreadable.empty(); ++k)
  {
    TexelMap texels;
    unreadable = TexelToScalar(scalars, texels, k);
  }
  return unreadable;
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::CheckVTKSettings(vtkRenderer* ren)
{
  if (this->BlendMode != vtkVolumeMapper::COMPOSITE_BLEND &&
    this->BlendMode != vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND &&
    this->BlendMode != vtkVolumeMapper::MINIMUM_INTENSITY_BLEND &&
    this->BlendMode != vtkVolumeMapper::AVERAGE_INTENSITY_BLEND &&
    this->BlendMode != vtkVolumeMapper::ADDITIVE_BLEND)
  {
    return "only the composite blend mode and the maximum, minimum and average intensity and "
           "additive projections are supported";
  }
  if (this->ClippingPlanes && this->ClippingPlanes->GetNumberOfItems() > MaximumClippingPlanes)
  {
    return "at most " + std::to_string(MaximumClippingPlanes) + " clipping planes are supported";
  }
  if (this->MaskInput)
  {
    return "masks are not supported";
  }
  if (this->Partitioned)
  {
    return "partitions (SetPartitions) are not supported: the rays read the whole volume from "
           "one texture";
  }
  if (this->UseJittering)
  {
    return "UseJittering is not supported: the methods place their own samples (turn it off)";
  }
  if (this->UseDepthPass)
  {
    return "UseDepthPass (the depth of contour values) is not supported";
  }
  if (this->ColorRangeType != vtkGPUVolumeRayCastMapper::SCALAR ||
    this->ScalarOpacityRangeType != vtkGPUVolumeRayCastMapper::SCALAR ||
    this->GradientOpacityRangeType != vtkGPUVolumeRayCastMapper::SCALAR)
  {
    return "only the SCALAR transfer-function range types are supported (the transfer function "
           "is evaluated where VTK's GetColor and GetValue evaluate it)";
  }
  if (ren && ren->GetUseDepthPeeling() && ren->GetUseDepthPeelingForVolumes())
  {
    return "dual depth peeling of volumes is not supported: turn the renderer's "
           "UseDepthPeelingForVolumes off";
  }
  if (this->ImageQuantity != DEPTH &&
    (!this->RenderToImage || this->DepthImageScalarType != VTK_FLOAT))
  {
    return "an ImageQuantity other than DEPTH needs RenderToImage with a float depth image";
  }
  return std::string();
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetPartitions(
  unsigned short x, unsigned short y, unsigned short z)
{
  this->Partitioned = x > 1 || y > 1 || z > 1;
  this->Superclass::SetPartitions(x, y, z);
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::CheckMethodSettings()
{
  if (!(this->Tolerance > 0.0 && this->Tolerance <= 1.0))
  {
    return "the tolerance must be in (0, 1]";
  }
  if ((this->IntegrationMethod == PIECEWISE_ADAPTIVE ||
        this->BlendMode == vtkVolumeMapper::ADDITIVE_BLEND ||
        this->BlendMode == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND) &&
    !(this->Tolerance >= 1e-5))
  {
    return "the GPU's piecewise method and its additive and average projections take a tolerance "
           "from 1e-5 to 1 (the transfer function is held in float)";
  }
  const double smallest = vtkAdaptiveVolumeMapper::GetSmallestStep();
  const double largest = vtkAdaptiveVolumeMapper::GetLargestStep();
  for (double step : { this->InitialStep, this->MinimumStep, this->MaximumStep, this->RiemannStep })
  {
    if (!(step >= smallest && step <= largest))
    {
      std::ostringstream message;
      message << "every step must lie in [" << smallest << ", " << largest << "] voxel units; got "
              << step;
      return message.str();
    }
  }
  if (this->MinimumStep > this->MaximumStep)
  {
    return "the minimum step exceeds the maximum step";
  }
  return std::string();
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::GPURender(vtkRenderer* ren, vtkVolume* vol)
{
  vtkNew<vtkMatrix4x4> gridToWorld;
  double voxel = 0.0;
  const std::string error = this->PrepareFrame(ren, vol, gridToWorld, voxel);
  if (!error.empty())
  {
    vtkErrorMacro(<< error << "; nothing is drawn.");
    return;
  }
  auto* shaderProperty = vtkOpenGLShaderProperty::SafeDownCast(vol->GetShaderProperty());
  this->AddShaderReplacements(shaderProperty);
  vtkUniforms* uniforms = shaderProperty->GetFragmentCustomUniforms();
  this->SetVolumeUniforms(uniforms);
  this->SetPieceUniforms(uniforms);
  this->SetMethodUniforms(uniforms);
  this->SetShadingUniforms(uniforms, gridToWorld);
  this->SetGradientOpacityUniforms(uniforms);
  this->UpdateRanges();
  this->UpdateBlocks(ren, shaderProperty);
  this->SetRayUniforms(ren, uniforms, gridToWorld, voxel);
  this->SetCutUniforms(uniforms);
  // Our shader blends (avos_blend), clips and crops (SetCutUniforms): the
  // superclass builds its composite shader without planes or cropping,
  // whose ray loop ours replaces (its projections would overwrite our
  // colour after the loop, its clipping discard fragments by its own
  // rounding).
  const int blendMode = this->BlendMode;
  const vtkTypeBool cropping = this->Cropping;
  vtkSmartPointer<vtkPlaneCollection> planes = this->ClippingPlanes;
  this->BlendMode = vtkVolumeMapper::COMPOSITE_BLEND;
  this->Cropping = 0;
  this->ClippingPlanes = nullptr;
  // VTK makes its lookup tables (one per independent component) when the
  // property changes, not when the scalars' components do: scalars of more
  // components would then read tables never made (a crash in VTK 9.1).
  const int components = this->GetRenderedScalars()->GetNumberOfComponents();
  if (components != this->Internals->TablesComponents)
  {
    for (auto& input : this->AssembledInputs)
    {
      input.second.ForceTransferInit();
    }
    this->Internals->TablesComponents = components;
  }
  this->Superclass::GPURender(ren, vol);
  this->BlendMode = blendMode;
  this->Cropping = cropping;
  this->ClippingPlanes = planes;
  this->Internals->Blocks->Deactivate();
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::PrepareFrame(
  vtkRenderer* ren, vtkVolume* vol, vtkMatrix4x4* gridToWorld, double& voxel)
{
  vtkVolumeProperty* property = vol->GetProperty();
  std::string error = this->CheckRenderable(ren, property);
  if (!error.empty())
  {
    return error;
  }
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  this->Internals->ScalarField = static_cast<Field>(this->ScalarFieldOf(property));
  voxel = avos::GridToWorld(input, vol->GetMatrix(), gridToWorld);
  if (!(voxel > 0.0) || !std::isfinite(voxel) || gridToWorld->Determinant() == 0.0)
  {
    return "the image's spacing or the volume's matrix is degenerate";
  }
  error = avos::ClipRegionOfMapper(this, input, gridToWorld->GetData(), this->Internals->Clip);
  if (!error.empty())
  {
    return error;
  }
  error = this->UpdateShading(ren, property);
  if (error.empty())
  {
    error = this->UpdateGradientOpacity(property);
  }
  if (!error.empty())
  {
    return error;
  }
  error = this->UpdateTransferFunction(property, gridToWorld, voxel);
  if (!error.empty())
  {
    return error;
  }
  // The shader's rays assume what VTK's cameras give: a homogeneous w of the
  // inverse projection that depends on the depth alone.
  vtkNew<vtkMatrix4x4> ndcToWorld;
  vtkMatrix4x4::Invert(ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(
                         ren->GetTiledAspectRatio(), -1, 1),
    ndcToWorld);
  const double* w = ndcToWorld->GetData() + 12;
  if (std::abs(w[0]) + std::abs(w[1]) > 1e-12 * (std::abs(w[2]) + std::abs(w[3])))
  {
    return "the camera's projection is not a perspective or parallel one";
  }
  return std::string();
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::UpdateGradientOpacity(vtkVolumeProperty* property)
{
  // (CheckGradientSettings has checked where it applies.)
  vtkInternals& internals = *this->Internals;
  internals.UsesGradientOpacity = avos::UsesGradientOpacity(property, 0);
  if (internals.UsesGradientOpacity)
  {
    // (No budget: the sampled methods certify nothing.)
    int approximated = 0;
    const std::string error =
      internals.GradientConversion.Update(property, 0.0, avos::ConversionBudget(), approximated);
    if (!error.empty())
    {
      return "unusable gradient opacity: " + error;
    }
    if (approximated > 0)
    {
      vtkWarningMacro(<< avos::ApproximationNotice(approximated) << ".");
    }
    if (internals.GradientConversion.Get().GetPieces().size() >
      static_cast<std::size_t>(MaximumGradientPieces))
    {
      return "the gradient opacity function has more than " +
        std::to_string(MaximumGradientPieces) + " pieces";
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::UpdateShading(
  vtkRenderer* ren, vtkVolumeProperty* property)
{
  // (CheckGradientSettings has checked where it applies.)
  vtkInternals& internals = *this->Internals;
  internals.Shade = property->GetShade(0) != 0;
  if (!internals.Shade)
  {
    return std::string();
  }
  std::string error =
    avos::ShadingFromRenderer(ren, property, internals.Shading, internals.ShadingKey);
  if (!error.empty())
  {
    return "Cannot shade: " + error;
  }
  if (internals.Shading.Lights.size() > static_cast<std::size_t>(MaximumLights))
  {
    return "Cannot shade with " + std::to_string(internals.Shading.Lights.size()) +
      " lights switched on: the GPU mapper takes at most " + std::to_string(MaximumLights);
  }
  return std::string();
}

//------------------------------------------------------------------------------
std::string vtkOpenGLAdaptiveVolumeMapper::UpdateTransferFunction(
  vtkVolumeProperty* property, vtkMatrix4x4* gridToWorld, double voxel)
{
  std::string error;
  vtkInternals& internals = *this->Internals;
  const bool piecewise = this->IntegrationMethod == PIECEWISE_ADAPTIVE;
  const bool additive = this->BlendMode == vtkVolumeMapper::ADDITIVE_BLEND;
  const bool average = this->BlendMode == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND;
  const bool fp64 = this->UseDoublePrecision && GLEW_ARB_gpu_shader_fp64;
  if ((additive || average) && !fp64)
  {
    return "the additive and average projections need double precision in shaders "
           "(GL_ARB_gpu_shader_fp64), which this OpenGL context lacks or UseDoublePrecision turns "
           "off: use vtkAdaptiveVolumeMapper";
  }
  // Float rounding is outside the piecewise method's certificate: its float
  // path keeps 2 eps on the tests' scenes from eps 1e-4 on.
  if (piecewise && !fp64 && this->Tolerance < 1e-4)
  {
    return "the piecewise method in float (without GL_ARB_gpu_shader_fp64, or with "
           "UseDoublePrecision off) takes a tolerance from 1e-4 to 1";
  }
  // The piecewise method converts VTK's functions within shares of its eps
  // where they are not piecewise linear, as the CPU mapper does, and
  // integrates to the rest; the sampled methods certify no conversion.
  avos::ConversionBudget budget;
  if (piecewise)
  {
    const int* dims = vtkImageData::SafeDownCast(this->GetInput())->GetDimensions();
    budget = avos::ConversionBudget::ForTolerance(
      this->Tolerance, 1.0, avos::LongestChord(gridToWorld, dims) / voxel);
  }
  vtkDataArray* scalars = this->GetRenderedScalars();
  const int components = scalars->GetNumberOfComponents();
  if (property->GetMTime() != internals.TFPropertyTime || this->OpacityModel != internals.TFModel ||
    voxel != internals.TFVoxel || !budget.SameAs(internals.Conversion) ||
    components != internals.TFComponents)
  {
    error = internals.Medium.Convert(
      property, scalars, this->OpacityModel == EXTINCTION_OPACITY, voxel, budget);
    internals.TFPropertyTime = error.empty() ? property->GetMTime() : 0;
    internals.TFModel = this->OpacityModel;
    internals.TFVoxel = voxel;
    internals.TFComponents = components;
    internals.Conversion = budget;
    internals.TFTime.Modified();
    if (!error.empty())
    {
      return error;
    }
    if (budget.Approximated > 0)
    {
      vtkWarningMacro(<< avos::ApproximationNotice(budget.Approximated) << ".");
    }
  }
  if (piecewise && internals.Medium.Mixed)
  {
    return "the GPU's piecewise method renders scalars of several components where one alone "
           "shows (the others of weight 0 or an opacity of 0 everywhere); in this mixture "
           "several show (or the components are dependent): take a sampled method (Riemann, "
           "coupled, decoupled) or vtkAdaptiveVolumeMapper";
  }
  internals.Medium.GetRange(scalars, internals.DataRange);
  internals.IntegrationTolerance =
    piecewise ? avos::IntegrationTolerance(this->Tolerance, internals.Conversion) : this->Tolerance;
  // (The additive projection integrates the same pieces at the tolerance.)
  if ((piecewise || additive) &&
    (internals.PiecesTime < internals.TFTime ||
      internals.PiecesTolerance != internals.IntegrationTolerance))
  {
    error = internals.Pieces.Build(
      internals.Medium.TF, avos::numerics::PiecewiseRelativeError(internals.IntegrationTolerance));
    if (!error.empty())
    {
      return error;
    }
    internals.PiecesTime.Modified();
    internals.PiecesTolerance = internals.IntegrationTolerance;
  }
  // The average's range, within the data's (VTK's default range is the
  // whole float line); a range beside the data's holds no ray.
  if (average)
  {
    const double r0 = std::max(this->AverageIPScalarRange[0], internals.DataRange[0]);
    const double r1 = std::min(this->AverageIPScalarRange[1], internals.DataRange[1]);
    error = internals.AverageRange.Build(internals.Medium.TF, r0, std::max(r0, r1));
    if (!error.empty())
    {
      return "unusable average intensity range: " + error;
    }
  }
  const auto* walked = internals.WalkedPieces(this->IntegrationMethod, this->BlendMode);
  return UniformStorageProblem(
    internals.Medium.PieceCount(), walked ? walked->GetNumberOfPieces() : 1, piecewise);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::AddShaderReplacements(vtkOpenGLShaderProperty* shaderProperty)
{
  // Replacements of a tag are keyed by it: adding them again changes nothing.
  const std::string integrator =
    std::string("//VTK::Shading::Dec\n") + avos::AdaptiveIntegratorGLSL;
  shaderProperty->AddFragmentShaderReplacement("//VTK::Shading::Dec", true, integrator, false);
  // Directives must precede any declaration: after the version line. A
  // change of them changes the replacement, and VTK rebuilds the shader.
  this->DoublePrecisionRays = this->UseDoublePrecision && GLEW_ARB_gpu_shader_fp64 ? 1 : 0;
  std::string directives = "//VTK::System::Dec\n";
  if (this->DoublePrecisionRays)
  {
    directives += "#extension GL_ARB_gpu_shader_fp64 : require\n#define AVOS_DOUBLE_PRECISION\n";
  }
  const ShaderMedium& medium = this->Internals->Medium;
  if (medium.Mixed)
  {
    // The sampled methods' code for this mixture (the shader's transfer-function section).
    using Mix = avos::numerics::ComponentMix;
    const Mix mix = medium.Mixture.Mixture.GetMix();
    const int kind = mix == Mix::Independent ? 1 : mix == Mix::ColourOpacity ? 2 : 3;
    directives += "#define AVOS_MIXTURE " +
      std::to_string(medium.Mixture.Mixture.GetNumberOfComponents()) + "\n#define AVOS_MIX_KIND " +
      std::to_string(kind) + "\n";
  }
  shaderProperty->AddFragmentShaderReplacement("//VTK::System::Dec", true, directives, false);
  shaderProperty->AddFragmentShaderReplacement("//VTK::Shading::Init", true,
    "//VTK::Shading::Init\n  avos_castRay();\n"
    "  g_fragColor = avos_result.a < 0.0 ? vec4(1.0, 0.0, 1.0, 1.0) : avos_result;\n"
    "  g_exit = true;\n",
    false);
  shaderProperty->AddFragmentShaderReplacement("//VTK::RenderToImage::Exit", true,
    "//VTK::RenderToImage::Exit\n  avos_writeQuantity();\n", false);
}

//------------------------------------------------------------------------------
vtkDataArray* vtkOpenGLAdaptiveVolumeMapper::GetRenderedScalars()
{
  int cellFlag = 0;
  return vtkAbstractMapper::GetScalars(this->GetInput(), this->ScalarMode, this->ArrayAccessMode,
    this->ArrayId, this->ArrayName, cellFlag);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetVolumeUniforms(vtkUniforms* uniforms)
{
  vtkDataArray* scalars = this->GetRenderedScalars();
  TexelMap texels;
  // (Of several components, every channel's texel map is that of the
  // rendered one: their types' maps do not depend on the range.)
  TexelToScalar(scalars, texels, this->Internals->Medium.Component);
  uniforms->SetUniformi("avos_component", this->Internals->Medium.Component);
  uniforms->SetUniformf("avos_texelScale", texels.Scale);
  uniforms->SetUniformf("avos_texelBias", texels.Bias);
  uniforms->SetUniformi("avos_texelRound", texels.Round ? 1 : 0);
  const int* dims = vtkImageData::SafeDownCast(this->GetInput())->GetDimensions();
  const float dimensions[3] = { float(dims[0]), float(dims[1]), float(dims[2]) };
  uniforms->SetUniform3f("avos_dimensions", dimensions);
  // The walk grid refines the point grid by 2 where the field's pieces are
  // half cells (see the shader's avos_cornerValues).
  const Field field = this->Internals->ScalarField;
  uniforms->SetUniformi("avos_fieldKind", static_cast<int>(field));
  uniforms->SetUniformi(
    "avos_walkScale", field == Field::Nearest || field == Field::CellCentres ? 2 : 1);
  // The field's values never leave the data's range: knots outside it are never crossed.
  const double* range = this->Internals->DataRange;
  const float fieldRange[2] = { float(range[0]), float(range[1]) };
  uniforms->SetUniform2f("avos_fieldRange", fieldRange);
  // The additive and average projections' n = (s - smin) / (smax - smin)
  // (a constant volume: any positive span gives n = 0, as on the CPU).
  const double span = range[1] > range[0] ? range[1] - range[0] : 1.0;
  const float accumulation[2] = { float(range[0]), float(1.0 / span) };
  uniforms->SetUniform2f("avos_accumulationRange", accumulation);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetPieceUniforms(vtkUniforms* uniforms)
{
  // The pieces of every function the shader reads, one after the other
  // (avos_fn*: where each function's lie), and how a mixture mixes them
  // (avos_mix*; see the shader's transfer-function section).
  vtkInternals& internals = *this->Internals;
  const ShaderMedium& medium = internals.Medium;
  const auto functions = medium.Functions();
  const int count = static_cast<int>(medium.PieceCount());
  // A new count changes the arrays' declared sizes: removing them first
  // makes VTK rebuild the shader.
  if (count != internals.PieceCount)
  {
    uniforms->RemoveUniform("avos_pieceA");
    uniforms->RemoveUniform("avos_pieceC");
    uniforms->RemoveUniform("avos_pieceS");
    internals.PieceCount = count;
  }
  std::vector<float> a, c, s;
  int first[4] = { 0, 0, 0, 0 }, counts[4];
  float below[4][4], unit[4], jumps[4];
  for (std::size_t f = 0; f < 4; ++f)
  {
    // (Slots past the functions repeat the first: never read.)
    const auto& tf = *functions[f < functions.size() ? f : 0];
    const auto& pieces = tf.GetPieces();
    first[f] = f < functions.size() ? static_cast<int>(a.size() / 4) : 0;
    counts[f] = static_cast<int>(pieces.size());
    // The core's jump counts, which the shader's avos_hasJumpInOf reads as HasJumpIn does.
    const std::vector<std::size_t>& jumpsBefore = tf.GetJumpsBefore();
    for (std::size_t i = 0; i < pieces.size() && f < functions.size(); ++i)
    {
      const auto& p = pieces[i];
      a.insert(
        a.end(), { float(p.Start), float(p.Length), float(p.Opacity), float(p.OpacitySlope) });
      c.insert(c.end(),
        { float(p.Colour[0]), float(p.Colour[1]), float(p.Colour[2]), float(jumpsBefore[i]) });
      s.insert(s.end(),
        { float(p.ColourSlope[0]), float(p.ColourSlope[1]), float(p.ColourSlope[2]), 0.0f });
    }
    const auto colourBelow = tf.GetColorBelow();
    for (int k = 0; k < 3; ++k)
    {
      below[f][k] = float(colourBelow[k]);
    }
    below[f][3] = float(tf.GetOpacityBelow());
    unit[f] = float(tf.GetUnitDistance());
    jumps[f] = float(jumpsBefore[pieces.size()]);
  }
  uniforms->SetUniform4fv("avos_pieceA", count, reinterpret_cast<const float(*)[4]>(a.data()));
  uniforms->SetUniform4fv("avos_pieceC", count, reinterpret_cast<const float(*)[4]>(c.data()));
  uniforms->SetUniform4fv("avos_pieceS", count, reinterpret_cast<const float(*)[4]>(s.data()));
  uniforms->SetUniform1iv("avos_fnFirst", 4, first);
  uniforms->SetUniform1iv("avos_fnCount", 4, counts);
  uniforms->SetUniform4fv("avos_fnBelow", 4, below);
  uniforms->SetUniform4f("avos_fnUnit", unit);
  uniforms->SetUniform4f("avos_fnJumpsTotal", jumps);
  const auto& mixture = medium.Mixture.Mixture;
  float weights[4];
  for (int k = 0; k < 4; ++k)
  {
    weights[k] = medium.Mixed ? float(mixture.GetWeight(k)) : 1.0f;
  }
  uniforms->SetUniform4f("avos_mixWeight", weights);
  uniforms->SetUniformf("avos_mixScale", medium.Mixed ? float(mixture.GetScale()) : 1.0f);
  uniforms->SetUniformi("avos_alphaModel",
    functions[0]->GetOpacityModel() == avos::numerics::OpacityModel::Alpha ? 1 : 0);
  this->SetPiecewiseUniforms(uniforms);
  uniforms->SetUniformf("avos_maximumColour",
    float(medium.Mixed ? mixture.GetMaximumColor() : medium.TF.GetMaximumColor()));
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetPiecewiseUniforms(vtkUniforms* uniforms)
{
  // The pieces the piece walk reads (vtkInternals::WalkedPieces, see the shader's
  // avos_pp*), one unused piece where it reads none.
  vtkInternals& internals = *this->Internals;
  const bool average = this->BlendMode == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND;
  const auto* walked = internals.WalkedPieces(this->IntegrationMethod, this->BlendMode);
  const int count = walked ? static_cast<int>(walked->GetNumberOfPieces()) : 1;
  if (count != internals.PiecewiseCount)
  {
    for (const char* name : { "avos_ppA", "avos_ppB", "avos_ppC", "avos_ppS" })
    {
      uniforms->RemoveUniform(name);
    }
    internals.PiecewiseCount = count;
  }
  std::vector<float> a(4 * count, 0.0f), b(4 * count, 0.0f), c(4 * count, 0.0f), s(4 * count, 0.0f);
  for (int i = 0; i < count && walked; ++i)
  {
    const auto& pp = *walked;
    const auto& p = pp[static_cast<std::size_t>(i)];
    a[4 * i] = float(p.Start);
    a[4 * i + 1] = float(p.Tau);
    a[4 * i + 2] = float(p.TauSlope);
    a[4 * i + 3] = float(p.TauCurvature);
    b[4 * i] = float(p.TauCubic);
    // The visible pieces among the first i + 1 (exact in float below 2^24).
    b[4 * i + 1] = float(pp.IsVisible(static_cast<std::size_t>(i))) + (i > 0 ? b[4 * i - 3] : 0.0f);
    b[4 * i + 2] = average
      ? float(internals.AverageRange.IsTransparent(static_cast<std::size_t>(i)))
      : float(p.ColourSlopeMaximum);
    for (int k = 0; k < 3; ++k)
    {
      c[4 * i + k] = float(p.Colour[k]);
      s[4 * i + k] = float(p.ColourSlope[k]);
    }
  }
  uniforms->SetUniform4fv("avos_ppA", count, reinterpret_cast<const float(*)[4]>(a.data()));
  uniforms->SetUniform4fv("avos_ppB", count, reinterpret_cast<const float(*)[4]>(b.data()));
  uniforms->SetUniform4fv("avos_ppC", count, reinterpret_cast<const float(*)[4]>(c.data()));
  uniforms->SetUniform4fv("avos_ppS", count, reinterpret_cast<const float(*)[4]>(s.data()));
  uniforms->SetUniformi("avos_ppCount", count);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetShadingUniforms(
  vtkUniforms* uniforms, vtkMatrix4x4* gridToWorld)
{
  // See the shader's avos_lit. Every slot is uploaded (fixed array sizes).
  const vtkInternals& internals = *this->Internals;
  const avos::numerics::ShadingModel<double>& model = internals.Shading;
  uniforms->SetUniformi("avos_shade", internals.Shade ? 1 : 0);
  const float coefficients[4] = { float(model.Ambient), float(model.Diffuse), float(model.Specular),
    float(model.SpecularPower) };
  uniforms->SetUniform4f("avos_shading", coefficients);
  uniforms->SetUniformi("avos_twoSided", model.TwoSided ? 1 : 0);
  const int count = internals.Shade ? static_cast<int>(model.Lights.size()) : 0;
  uniforms->SetUniformi("avos_lightCount", count);
  float position[MaximumLights][4] = {}, diffuse[MaximumLights][4] = {},
        specular[MaximumLights][4] = {}, attenuation[MaximumLights][4] = {},
        axis[MaximumLights][4] = {};
  for (int i = 0; i < count; ++i)
  {
    const auto& light = model.Lights[static_cast<std::size_t>(i)];
    const auto& at = light.Positional ? light.Position : light.Direction;
    const double cone =
      light.IsSpot() ? std::cos(vtkMath::RadiansFromDegrees(light.ConeAngle)) : -3.0; // no cone
    for (int k = 0; k < 3; ++k)
    {
      position[i][k] = float(at[k]);
      diffuse[i][k] = float(light.Diffuse[k]);
      specular[i][k] = float(light.Specular[k]);
      attenuation[i][k] = float(light.Attenuation[k]);
      axis[i][k] = float(light.Axis[k]);
    }
    position[i][3] = light.Positional ? 1.0f : 0.0f;
    attenuation[i][3] = float(cone);
    axis[i][3] = float(light.Exponent);
  }
  uniforms->SetUniform4fv("avos_lightPosition", MaximumLights, position);
  uniforms->SetUniform4fv("avos_lightDiffuse", MaximumLights, diffuse);
  uniforms->SetUniform4fv("avos_lightSpecular", MaximumLights, specular);
  uniforms->SetUniform4fv("avos_lightAttenuation", MaximumLights, attenuation);
  uniforms->SetUniform4fv("avos_lightAxis", MaximumLights, axis);
  // The rows of the grid-to-world map's affine part and of the normal
  // matrix (grid gradients to world: glm's columns).
  const glm::dmat3 normal = avos::NormalMatrix(gridToWorld->GetData());
  float rows[3][4], normalRows[3][4];
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      rows[r][c] = float(gridToWorld->GetElement(r, c));
      normalRows[r][c] = c < 3 ? float(normal[c][r]) : 0.0f;
    }
  }
  uniforms->SetUniform4fv("avos_gridToWorld", 3, rows);
  uniforms->SetUniform4fv("avos_normalRows", 3, normalRows);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetGradientOpacityUniforms(vtkUniforms* uniforms)
{
  // G's pieces (see the shader's avos_gradientFactor); the gradient's map
  // to world space is the shading's (SetShadingUniforms).
  const vtkInternals& internals = *this->Internals;
  uniforms->SetUniformi("avos_gradientOpacity", internals.UsesGradientOpacity ? 1 : 0);
  float pieces[MaximumGradientPieces][4] = {};
  const auto& g = internals.GradientConversion.Get().GetPieces();
  const int count = internals.UsesGradientOpacity ? static_cast<int>(g.size()) : 0;
  for (int i = 0; i < count; ++i)
  {
    const auto& p = g[static_cast<std::size_t>(i)];
    pieces[i][0] = float(p.Start);
    pieces[i][1] = float(p.Length);
    pieces[i][2] = float(p.Opacity);
    pieces[i][3] = float(p.OpacitySlope);
  }
  uniforms->SetUniform4fv("avos_gPiece", MaximumGradientPieces, pieces);
  uniforms->SetUniformi("avos_gCount", std::max(count, 1));
  uniforms->SetUniformf(
    "avos_gBelow", count > 0 ? float(internals.GradientConversion.Get().GetOpacityBelow()) : 1.0f);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetMethodUniforms(vtkUniforms* uniforms)
{
  uniforms->SetUniformi("avos_method", this->IntegrationMethod);
  // The shader's blends: composite 0, maximum 1, minimum 2, additive 3, average 4.
  const int mode = this->BlendMode;
  const int blend = mode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND ? 1
    : mode == vtkVolumeMapper::MINIMUM_INTENSITY_BLEND               ? 2
    : mode == vtkVolumeMapper::ADDITIVE_BLEND                        ? 3
    : mode == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND               ? 4
                                                                     : 0;
  uniforms->SetUniformi("avos_blend", blend);
  uniforms->SetUniformf("avos_tolerance", float(this->Internals->IntegrationTolerance));
  const float steps[4] = { float(this->InitialStep), float(this->MinimumStep),
    float(this->MaximumStep), float(this->RiemannStep) };
  uniforms->SetUniform4f("avos_steps", steps);
  uniforms->SetUniformi("avos_earlyTermination", this->EarlyTermination ? 1 : 0);
  uniforms->SetUniformi("avos_quantity", this->RenderToImage ? this->ImageQuantity : 0);
  uniforms->SetUniformi("avos_two", 2); // the shader's loop-limit canary (avos_castRay)
  // Empty-space skipping (see avos_nextSegment).
  // (The average counts the length of transparent blocks in its range.)
  uniforms->SetUniformi("avos_skipping",
    this->EmptySpaceSkipping && this->BlendMode != vtkVolumeMapper::AVERAGE_INTENSITY_BLEND ? 1
                                                                                            : 0);
  uniforms->SetUniformf(
    "avos_blockSize", static_cast<float>(avos::numerics::EmptySpaceMap<double>::BlockSize));
  // Against rounding of the block crossings: 1e-6 voxel in double, 1e-3 in
  // float (t of a few hundred voxels carries 3e-5).
  uniforms->SetUniformf("avos_segmentPad", this->DoublePrecisionRays ? 1e-6f : 1e-3f);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::UpdateRanges()
{
  // The blocks' value ranges, rebuilt when the scalars or their field
  // change (the types TexelToScalar accepts all work). A block's range
  // covers what its cells' field reads (cell scalars: their cells, and the
  // neighbours between centres).
  // Of several components, the ranges of the one that shows.
  vtkInternals& internals = *this->Internals;
  internals.Ranges.Update(this->GetRenderedScalars(),
    vtkImageData::SafeDownCast(this->GetInput())->GetDimensions(),
    avos::SamplesOf(internals.ScalarField),
    internals.Medium.Mixed ? -1 : internals.Medium.Component);
  // NaN, as on the CPU: every cell with a NaN corner is empty (the shader's
  // avos_corners; a sample there is NaN, transparent). Said once per change
  // of the scalars.
  internals.Ranges.WarnOfNaNs(this);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::UpdateBlocks(
  vtkRenderer* ren, vtkOpenGLShaderProperty* shaderProperty)
{
  // The blocks' visibility for this transfer function, uploaded when the
  // ranges or the transfer function change.
  vtkInternals& internals = *this->Internals;
  vtkTextureObject* blocks = internals.Blocks;
  blocks->SetContext(vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow()));
  if (this->EmptySpaceSkipping)
  {
    auto& map = internals.Ranges.GetMap();
    if (!internals.BlocksHoldMap || internals.BlocksRangesTime != internals.Ranges.GetTime() ||
      internals.BlocksTime < internals.TFTime || blocks->GetHandle() == 0)
    {
      const ShaderMedium& medium = internals.Medium;
      if (medium.Mixed)
      {
        map.ClassifyBlocks([&medium](const double* lo, const double* hi)
          { return medium.Mixture.Mixture.IsVisible(lo, hi); });
      }
      else
      {
        map.Classify(medium.TF);
      }
      std::vector<unsigned char> visible;
      visible.reserve(map.GetNumberOfBlocks());
      for (int z = 0; z < map.GetNumberOfBlocks(2); ++z)
      {
        for (int y = 0; y < map.GetNumberOfBlocks(1); ++y)
        {
          for (int x = 0; x < map.GetNumberOfBlocks(0); ++x)
          {
            visible.push_back(map.IsVisible(x, y, z) ? 255 : 0);
          }
        }
      }
      blocks->SetMinificationFilter(vtkTextureObject::Nearest);
      blocks->SetMagnificationFilter(vtkTextureObject::Nearest);
      blocks->Create3DFromRaw(map.GetNumberOfBlocks(0), map.GetNumberOfBlocks(1),
        map.GetNumberOfBlocks(2), 1, VTK_UNSIGNED_CHAR, visible.data());
      internals.BlocksHoldMap = true;
      internals.BlocksRangesTime = internals.Ranges.GetTime();
      internals.BlocksTime.Modified();
    }
  }
  else if (internals.BlocksHoldMap || blocks->GetHandle() == 0)
  {
    // Never read, but a sampler needs a texture of its type on its unit.
    unsigned char one = 255;
    blocks->Create3DFromRaw(1, 1, 1, 1, VTK_UNSIGNED_CHAR, &one);
    internals.BlocksHoldMap = false;
  }
  blocks->Activate();
  shaderProperty->GetFragmentCustomUniforms()->SetUniformi("avos_blocks", blocks->GetTextureUnit());
  shaderProperty->AddFragmentShaderReplacement(
    "uniform int avos_blocks;", false, "uniform sampler3D avos_blocks;", false);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetRayUniforms(
  vtkRenderer* ren, vtkUniforms* uniforms, vtkMatrix4x4* gridToWorld, double voxel)
{
  vtkMatrix4x4* projection = ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(
    ren->GetTiledAspectRatio(), -1, 1);
  vtkNew<vtkMatrix4x4> ndcToWorld;
  vtkMatrix4x4::Invert(projection, ndcToWorld);
  const int* dims = vtkImageData::SafeDownCast(this->GetInput())->GetDimensions();
  // The rays (see avos_setUpRay): in double, the near- and far-plane points'
  // coefficients in NDC x, y, then the point on the plane through the
  // volume's centre and the near-to-far vector; grid vectors -> voxel units.
  vtkNew<vtkMatrix4x4> worldToGrid, ndcToGrid;
  vtkMatrix4x4::Invert(gridToWorld, worldToGrid);
  vtkMatrix4x4::Multiply4x4(worldToGrid, ndcToWorld, ndcToGrid);
  const double* m = ndcToGrid->GetData();
  double plane[2][3][3]; // [near, far][offset, x, y][grid axis]
  double planeW[2];
  for (int p = 0; p < 2; ++p)
  {
    const double z = p == 0 ? -1.0 : 1.0;
    planeW[p] = m[14] * z + m[15];
    for (int r = 0; r < 3; ++r)
    {
      plane[p][0][r] = (m[4 * r + 2] * z + m[4 * r + 3]) / planeW[p];
      plane[p][1][r] = m[4 * r] / planeW[p];
      plane[p][2][r] = m[4 * r + 1] / planeW[p];
    }
  }
  double centreWorld[4] = { 0.0, 0.0, 0.0, 1.0 };
  double centreGrid[4] = { 0.5 * (dims[0] - 1), 0.5 * (dims[1] - 1), 0.5 * (dims[2] - 1), 1.0 };
  gridToWorld->MultiplyPoint(centreGrid, centreWorld);
  double centreNDC[4];
  projection->MultiplyPoint(centreWorld, centreNDC);
  const double depth = 0.5 * (std::min(std::max(centreNDC[2] / centreNDC[3], -1.0), 1.0) + 1.0);
  const double centreFraction = planeW[1] * depth / (planeW[0] * (1.0 - depth) + planeW[1] * depth);
  // Each double goes as float hi + lo (the shader adds them back in double
  // where it has fp64), so nothing here is rounded to float's 24 bits.
  float centre[2][3][3], span[2][3][3];
  for (int k = 0; k < 3; ++k)
  {
    for (int r = 0; r < 3; ++r)
    {
      const double d = plane[1][k][r] - plane[0][k][r];
      Split(d, span[0][k][r], span[1][k][r]);
      Split(plane[0][k][r] + centreFraction * d, centre[0][k][r], centre[1][k][r]);
    }
  }
  uniforms->SetUniform3fv("avos_centre", 3, centre[0]);
  uniforms->SetUniform3fv("avos_centreLo", 3, centre[1]);
  uniforms->SetUniform3fv("avos_span", 3, span[0]);
  uniforms->SetUniform3fv("avos_spanLo", 3, span[1]);
  float planeWValues[2][2], fraction[2];
  Split(planeW[0], planeWValues[0][0], planeWValues[1][0]);
  Split(planeW[1], planeWValues[0][1], planeWValues[1][1]);
  Split(centreFraction, fraction[0], fraction[1]);
  uniforms->SetUniform2f("avos_planeW", planeWValues[0]);
  uniforms->SetUniform2f("avos_planeWLo", planeWValues[1]);
  uniforms->SetUniform2f("avos_centreFraction", fraction);
  float gridToVoxel[2][9];
  for (int r = 0; r < 3; ++r)
  {
    for (int k = 0; k < 3; ++k)
    {
      Split(gridToWorld->GetElement(r, k) / voxel, gridToVoxel[0][3 * k + r],
        gridToVoxel[1][3 * k + r]);
    }
  }
  uniforms->SetUniformMatrix3x3("avos_gridToVoxel", gridToVoxel[0]);
  uniforms->SetUniformMatrix3x3("avos_gridToVoxelLo", gridToVoxel[1]);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::SetCutUniforms(vtkUniforms* uniforms)
{
  // The clipping planes in grid coordinates (numerics::ClipRegion: keeps
  // normal . x + offset >= 0), each double as float hi + lo.
  const auto& planes = this->Internals->Clip.GetPlanes(); // at most 6 (CheckVTKSettings)
  float clip[2][MaximumClippingPlanes][4] = {};
  for (std::size_t i = 0; i < planes.size(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      Split(planes[i].Normal[k], clip[0][i][k], clip[1][i][k]);
    }
    Split(planes[i].Offset, clip[0][i][3], clip[1][i][3]);
  }
  uniforms->SetUniform4fv("avos_clipPlanes", MaximumClippingPlanes, clip[0]);
  uniforms->SetUniform4fv("avos_clipPlanesLo", MaximumClippingPlanes, clip[1]);
  uniforms->SetUniformi("avos_clipPlaneCount", static_cast<int>(planes.size()));

  // Cropping: the region planes in grid coordinates and the 27 regions'
  // flags.
  const avos::numerics::ClipRegion<double>& region = this->Internals->Clip;
  float crop[2][2][3]; // [min, max][hi, lo][axis]
  for (int c = 0; c < 6; ++c)
  {
    Split(region.GetCropPlanes()[c], crop[c % 2][0][c / 2], crop[c % 2][1][c / 2]);
  }
  uniforms->SetUniformi("avos_cropping", region.GetCropping() ? 1 : 0);
  uniforms->SetUniformi("avos_cropFlags", region.GetCropFlags());
  uniforms->SetUniform3f("avos_cropMin", crop[0][0]);
  uniforms->SetUniform3f("avos_cropMinLo", crop[0][1]);
  uniforms->SetUniform3f("avos_cropMax", crop[1][0]);
  uniforms->SetUniform3f("avos_cropMaxLo", crop[1][1]);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Internals->Blocks->ReleaseGraphicsResources(window);
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
void vtkOpenGLAdaptiveVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "IntegrationMethod: " << this->GetIntegrationMethodAsString() << "\n";
  os << indent << "OpacityModel: " << (this->OpacityModel == VTK_OPACITY ? "VTK" : "Extinction")
     << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "InitialStep: " << this->InitialStep << "\n";
  os << indent << "MinimumStep: " << this->MinimumStep << "\n";
  os << indent << "MaximumStep: " << this->MaximumStep << "\n";
  os << indent << "RiemannStep: " << this->RiemannStep << "\n";
  os << indent << "EarlyTermination: " << this->EarlyTermination << "\n";
  os << indent << "ImageQuantity: " << this->ImageQuantity << "\n";
  os << indent << "EmptySpaceSkipping: " << this->EmptySpaceSkipping << "\n";
  os << indent << "DoublePrecisionRays: " << this->DoublePrecisionRays << "\n";
  os << indent << "UseDoublePrecision: " << this->UseDoublePrecision << "\n";
}
