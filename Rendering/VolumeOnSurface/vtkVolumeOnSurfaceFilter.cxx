#include "vtkVolumeOnSurfaceFilter.h"

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumeProperty.h"

#include "avosVolumeRay.h"

#include "avos/engine/WorkMonitor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace
{

// Everything the previsualization depends on: when it is unchanged, an
// execution only assigns colours.
struct PrevisualizationKey
{
  std::vector<double> Angles;
  int RaysPerCone = 0;
  bool Flip = false;
  int Side = 0;
  int Method = 0;
  double SampleDistance = 0.0;
  double Tolerance = 0.0;
  bool Extinction = false;
  bool Skipping = false;
  vtkMTimeType Surface = 0;
  // The volume by its content (scalars, extent, geometry), not by the image
  // object's MTime: ParaView modifies the volume's point data on every
  // update of the filter while its scalars array stays the same.
  vtkMTimeType VolumeScalars = 0;
  std::array<double, 21> VolumeGrid{}; // vtkVolumeOnSurfaceFilter::GetGrid
  vtkMTimeType Property = 0;
  std::vector<double> Shading; // the lights and coefficients, when the property shades

  bool operator==(const PrevisualizationKey& o) const
  {
    return this->Angles == o.Angles && this->RaysPerCone == o.RaysPerCone && this->Flip == o.Flip &&
      this->Side == o.Side && this->Method == o.Method &&
      this->SampleDistance == o.SampleDistance && this->Tolerance == o.Tolerance &&
      this->Extinction == o.Extinction && this->Skipping == o.Skipping &&
      this->Surface == o.Surface && this->VolumeScalars == o.VolumeScalars &&
      this->VolumeGrid == o.VolumeGrid && this->Property == o.Property &&
      this->Shading == o.Shading;
  }
};

// Unit vectors u, w completing the unit normal n to an orthonormal basis.
void Basis(const glm::dvec3& n, glm::dvec3& u, glm::dvec3& w)
{
  const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  u = glm::normalize(glm::cross(n, helper));
  w = glm::cross(n, u);
}

// The cone rays' directions around `normal` (any length): perCone rays
// evenly around each opening angle, cone by cone. False, with nothing
// written, for a zero or non-finite normal.
bool ConeDirections(
  glm::dvec3 normal, const std::vector<double>& angles, int perCone, glm::dvec3* directions)
{
  const double length = glm::length(normal);
  if (!(length > 0.0) || !std::isfinite(length))
  {
    return false;
  }
  normal /= length;
  glm::dvec3 u, w;
  Basis(normal, u, w);
  std::size_t r = 0;
  for (double angle : angles)
  {
    const double theta = vtkMath::RadiansFromDegrees(angle);
    for (int k = 0; k < perCone; ++k, ++r)
    {
      const double phi = 2.0 * vtkMath::Pi() * k / perCone;
      directions[r] =
        std::cos(theta) * normal + std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * w);
    }
  }
  return true;
}
} // namespace

class vtkVolumeOnSurfaceFilter::vtkInternals
{
public:
  std::vector<double> Angles{ 20.0, 45.0, 70.0 };
  PrevisualizationKey Key;
  bool HaveRays = false;
  avos::EmptySpaceCache EmptySpace;
  avos::EngineVolume EngineScalars;
  const avos::VolumeRaySetup* Setup = nullptr; // while CastCones runs
  // Per vertex and ray: the direction (world) and the integrated RGBA.
  std::vector<glm::fvec3> Directions;
  std::vector<glm::fvec4> Colors;
  // The surface with normals (the input's, or computed once per surface).
  vtkSmartPointer<vtkPolyData> WithNormals;
  vtkPolyData* NormalsSource = nullptr;
  vtkMTimeType NormalsTime = 0;
  // The headlight a renderer without a light switched on creates at its
  // first render (ShadingLights).
  vtkNew<vtkLightCollection> AutomaticLights;
  vtkNew<vtkLight> Headlight;

  vtkInternals()
  {
    this->Headlight->SetLightTypeToHeadlight();
    this->AutomaticLights->AddItem(this->Headlight);
  }
};

vtkStandardNewMacro(vtkVolumeOnSurfaceFilter);
vtkCxxSetObjectMacro(vtkVolumeOnSurfaceFilter, VolumeProperty, vtkVolumeProperty);

vtkVolumeOnSurfaceFilter::vtkVolumeOnSurfaceFilter()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
}

vtkVolumeOnSurfaceFilter::~vtkVolumeOnSurfaceFilter()
{
  this->SetVolumeProperty(nullptr);
  this->SetCamera(nullptr);
}

void vtkVolumeOnSurfaceFilter::SetCamera(vtkCamera* camera)
{
  if (camera != this->Camera)
  {
    vtkCamera* old = this->Camera;
    this->Camera = camera;
    if (camera)
    {
      camera->Register(this);
    }
    if (old)
    {
      old->UnRegister(this);
    }
    this->Modified();
  }
}

void vtkVolumeOnSurfaceFilter::SetRenderer(vtkRenderer* renderer)
{
  if (renderer != this->Renderer)
  {
    this->Renderer = renderer;
    this->Modified();
  }
}

vtkRenderer* vtkVolumeOnSurfaceFilter::GetRenderer()
{
  return this->Renderer;
}

void vtkVolumeOnSurfaceFilter::SetVolumeConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

void vtkVolumeOnSurfaceFilter::AddOpeningAngle(double degrees)
{
  this->Internals->Angles.push_back(degrees);
  this->Modified();
}

void vtkVolumeOnSurfaceFilter::RemoveAllOpeningAngles()
{
  this->Internals->Angles.clear();
  this->Modified();
}

int vtkVolumeOnSurfaceFilter::GetNumberOfCones()
{
  return static_cast<int>(this->Internals->Angles.size());
}

double vtkVolumeOnSurfaceFilter::GetOpeningAngle(int cone)
{
  return cone >= 0 && cone < this->GetNumberOfCones() ? this->Internals->Angles[cone] : 0.0;
}

vtkMTimeType vtkVolumeOnSurfaceFilter::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->Camera)
  {
    t = std::max(t, this->Camera->GetMTime());
  }
  if (this->VolumeProperty)
  {
    t = std::max(t, this->VolumeProperty->GetMTime());
  }
  if (this->Renderer)
  {
    // Its two-sided lighting, its set of lights and each light.
    vtkLightCollection* lights = this->Renderer->GetLights();
    t = std::max({ t, this->Renderer->GetMTime(), lights->GetMTime() });
    vtkCollectionSimpleIterator it;
    lights->InitTraversal(it);
    while (vtkLight* light = lights->GetNextLight(it))
    {
      t = std::max(t, light->GetMTime());
    }
  }
  return t;
}

int vtkVolumeOnSurfaceFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), port == 0 ? "vtkPolyData" : "vtkImageData");
  return 1;
}

int vtkVolumeOnSurfaceFilter::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The surface: the piece asked of this filter (the superclass's request).
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  // The volume: whole, whatever the piece (rays cross the pieces' borders).
  vtkInformation* volumeInfo = inputVector[1]->GetInformationObject(0);
  if (volumeInfo && volumeInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    volumeInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      volumeInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
    volumeInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    volumeInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    volumeInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
    volumeInfo->Set(vtkStreamingDemandDrivenPipeline::EXACT_EXTENT(), 1);
  }
  return 1;
}

void vtkVolumeOnSurfaceFilter::GetGrid(vtkImageData* image, double grid[21])
{
  const int* extent = image->GetExtent();
  std::copy_n(extent, 6, grid);
  std::copy_n(image->GetOrigin(), 3, grid + 6);
  std::copy_n(image->GetSpacing(), 3, grid + 9);
  std::copy_n(image->GetDirectionMatrix()->GetData(), 9, grid + 12);
}

bool vtkVolumeOnSurfaceFilter::HoldsPart(
  vtkImageData* received, vtkInformation* volumeInfo, int whole[6])
{
  if (!received || !volumeInfo ||
    !volumeInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    return false;
  }
  volumeInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  int extent[6];
  received->GetExtent(extent);
  return !std::equal(extent, extent + 6, whole);
}

vtkSmartPointer<vtkImageData> vtkVolumeOnSurfaceFilter::AssembleVolume(
  vtkImageData* received, vtkInformation* volumeInfo)
{
  // The whole volume was requested (RequestUpdateExtent); a part of it means
  // that another consumer of the same producer output asked for a piece
  // later in the same update (one output holds one request): the rays would
  // end at the piece's border.
  int whole[6];
  if (HoldsPart(received, volumeInfo, whole))
  {
    int extent[6];
    received->GetExtent(extent);
    vtkErrorMacro(<< "The volume holds extent (" << extent[0] << ".." << extent[1] << ", "
                  << extent[2] << ".." << extent[3] << ", " << extent[4] << ".." << extent[5]
                  << ") of (" << whole[0] << ".." << whole[1] << ", " << whole[2] << ".."
                  << whole[3] << ", " << whole[4] << ".." << whole[5]
                  << "): its producer also feeds a branch that asked for a piece. Give the "
                     "volume port a producer of its own (for example a second reader).");
    return nullptr;
  }
  return received;
}

int vtkVolumeOnSurfaceFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0]);
  vtkImageData* received = vtkImageData::GetData(inputVector[1]);
  const vtkSmartPointer<vtkImageData> volume =
    this->AssembleVolume(received, inputVector[1]->GetInformationObject(0));
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->NumberOfRaysCast = 0;
  // A clear error and an empty output for each bad input.
  if (!this->ValidateInputs(surface, received, volume))
  {
    return 1;
  }
  vtkPolyData* withNormals = this->UpdateNormals(surface);
  if (!this->Previsualize(volume, withNormals))
  {
    return 1;
  }
  this->AssignColours(withNormals, output);
  // The technique's memory (the paper's Table III).
  vtkInternals& in = *this->Internals;
  bool cellScalars = false;
  this->VolumeMemory =
    static_cast<vtkIdType>(avos::VolumeScalars(volume, cellScalars)->GetActualMemorySize()) * 1024;
  this->SurfaceMemory =
    static_cast<vtkIdType>(withNormals->GetPoints()->GetData()->GetActualMemorySize() +
      withNormals->GetPointData()->GetNormals()->GetActualMemorySize() +
      withNormals->GetPolys()->GetActualMemorySize() +
      output->GetPointData()->GetScalars()->GetActualMemorySize()) *
    1024;
  this->ConesMemory = static_cast<vtkIdType>(
    in.Directions.size() * sizeof(glm::fvec3) + in.Colors.size() * sizeof(glm::fvec4));
  return 1;
}

bool vtkVolumeOnSurfaceFilter::ValidateInputs(
  vtkPolyData* surface, vtkImageData* received, vtkImageData* volume)
{
  // The volume's own checks are VolumeRaySetup::Prepare's (Previsualize).
  vtkInternals& in = *this->Internals;
  if (!surface || surface->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro(<< "The surface (input 0) is empty.");
    return false;
  }
  if (!received)
  {
    vtkErrorMacro(<< "No volume: connect one to input port 1 (SetVolumeConnection).");
    return false;
  }
  if (!volume)
  {
    return false; // AssembleVolume said why
  }
  if (!this->VolumeProperty)
  {
    vtkErrorMacro(<< "No volume property: SetVolumeProperty().");
    return false;
  }
  if (this->RaysPerCone < 1 || in.Angles.empty())
  {
    vtkErrorMacro(<< "There must be at least one cone and one ray per cone (cones: "
                  << in.Angles.size() << ", rays per cone: " << this->RaysPerCone << ").");
    return false;
  }
  for (double a : in.Angles)
  {
    if (!(a > 0.0 && a <= 90.0))
    {
      vtkErrorMacro(<< "Opening angles must be in (0, 90] degrees, not " << a << ".");
      return false;
    }
  }
  if (!this->Camera)
  {
    vtkErrorMacro(<< "No camera to assign the colours for: SetCamera().");
    return false;
  }
  if (this->VolumeProperty->GetShade(0) && !this->Renderer)
  {
    vtkErrorMacro(<< "The volume property shades: give the renderer whose lights light the rays "
                     "(SetRenderer()), or turn its Shade off.");
    return false;
  }
  double surfaceBounds[6], volumeBounds[6];
  surface->GetBounds(surfaceBounds);
  volume->GetBounds(volumeBounds);
  bool overlap = true;
  for (int a = 0; a < 3; ++a)
  {
    overlap = overlap && surfaceBounds[2 * a] <= volumeBounds[2 * a + 1] &&
      surfaceBounds[2 * a + 1] >= volumeBounds[2 * a];
  }
  if (!overlap)
  {
    vtkErrorMacro(<< "The surface lies outside the volume.");
  }
  return overlap;
}

vtkLightCollection* vtkVolumeOnSurfaceFilter::ShadingLights()
{
  // A renderer with no light switched on creates a headlight at its first
  // render (vtkRenderer::CreateLight): a pipeline updated before it (a
  // ResetCamera asks for the bounds) takes that light now.
  vtkLightCollection* lights = this->Renderer->GetLights();
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    if (light->GetSwitch())
    {
      return lights;
    }
  }
  if (!this->Renderer->GetAutomaticLightCreation())
  {
    return lights;
  }
  vtkInternals& in = *this->Internals;
  in.Headlight->SetPosition(this->Camera->GetPosition());
  in.Headlight->SetFocalPoint(this->Camera->GetFocalPoint());
  return in.AutomaticLights;
}

vtkPolyData* vtkVolumeOnSurfaceFilter::UpdateNormals(vtkPolyData* surface)
{
  // The input's, or computed once per surface: a camera change must stay
  // cheap.
  vtkInternals& in = *this->Internals;
  if (surface->GetPointData()->GetNormals())
  {
    in.WithNormals = surface;
  }
  else if (in.NormalsSource != surface || in.NormalsTime != surface->GetMTime() || !in.WithNormals)
  {
    vtkNew<vtkPolyDataNormals> computed;
    computed->SetInputData(surface);
    computed->SplittingOff();
    computed->ConsistencyOn();
    computed->Update();
    in.WithNormals = computed->GetOutput();
    in.NormalsSource = surface;
    in.NormalsTime = surface->GetMTime();
  }
  return in.WithNormals;
}

bool vtkVolumeOnSurfaceFilter::Previsualize(vtkImageData* volume, vtkPolyData* withNormals)
{
  // Unless nothing it depends on changed.
  vtkInternals& in = *this->Internals;
  PrevisualizationKey key;
  key.Angles = in.Angles;
  key.RaysPerCone = this->RaysPerCone;
  key.Flip = this->FlipNormals != 0;
  key.Side = this->VolumeSide;
  key.Method = this->IntegrationMethod;
  key.SampleDistance = this->SampleDistance;
  key.Tolerance = this->Tolerance;
  key.Extinction = this->ExtinctionOpacity != 0;
  key.Skipping = this->EmptySpaceSkipping != 0;
  key.Surface = withNormals->GetMTime();
  bool cellScalars = false;
  vtkDataArray* volumeScalars = avos::VolumeScalars(volume, cellScalars);
  key.VolumeScalars = volumeScalars ? volumeScalars->GetMTime() : 0;
  GetGrid(volume, key.VolumeGrid.data());
  key.Property = this->VolumeProperty->GetMTime();
  vtkLightCollection* lights = nullptr;
  const bool twoSided = this->Renderer && this->Renderer->GetTwoSidedLighting();
  if (this->VolumeProperty->GetShade(0))
  {
    // (Lights that cannot be used are reported by Prepare.)
    lights = this->ShadingLights();
    avos::numerics::ShadingModel<double> model;
    avos::ShadingFromLights(lights, twoSided, this->VolumeProperty, model, key.Shading);
  }
  if (in.HaveRays && key == in.Key)
  {
    return true;
  }
  in.HaveRays = false;
  avos::VolumeRaySetup setup;
  const std::string error = setup.Prepare(volume, this->VolumeProperty, key.Extinction,
    static_cast<avos::RayIntegration>(this->IntegrationMethod), this->SampleDistance,
    this->Tolerance, nullptr, lights, twoSided);
  if (!avos::ReportPrepared(this, error, setup))
  {
    return false;
  }
  setup.Side = static_cast<avos::VolumeSide>(this->VolumeSide);
  avos::UseCaches(this, setup, in.EmptySpace, in.EngineScalars, key.Skipping);
  in.Setup = &setup;
  const bool cast = this->CastCones(withNormals);
  in.Setup = nullptr;
  if (!cast)
  {
    in.Directions.clear();
    in.Colors.clear();
    return false;
  }
  in.Key = key;
  // Read again after the transfer functions were: a
  // vtkDiscretizableColorTransferFunction (ParaView's colour maps) builds
  // its table on first use, which modifies it without changing a value.
  in.Key.Property = this->VolumeProperty->GetMTime();
  in.HaveRays = true;
  this->NumberOfRaysCast = static_cast<vtkIdType>(in.Colors.size());
  return true;
}

bool vtkVolumeOnSurfaceFilter::CastCones(vtkPolyData* withNormals)
{
  vtkInternals& in = *this->Internals;
  const avos::VolumeRaySetup& setup = *in.Setup;
  vtkDataArray* normals = withNormals->GetPointData()->GetNormals();
  const vtkIdType n = withNormals->GetNumberOfPoints();
  const std::size_t perVertex = in.Angles.size() * static_cast<std::size_t>(this->RaysPerCone);
  in.Directions.assign(static_cast<std::size_t>(n) * perVertex, glm::fvec3(0.0f));
  in.Colors.assign(static_cast<std::size_t>(n) * perVertex, glm::fvec4(0.0f));
  // The cones' axis: the normal as given (FlipNormals: its opposite) points
  // to the observer's side of a visible vertex; the volume behind the
  // surface lies on the other side.
  const double flip = this->FlipNormals ? -1.0 : 1.0;
  const double sign = this->VolumeSide == BEHIND_SURFACE ? -flip : flip;
  avos::engine::WorkMonitor monitor;
  avos::RayFailures failures;
  auto previsualize = [&](const auto& caster)
  {
    vtkSMPTools::For(0, n,
      [&](vtkIdType begin, vtkIdType end)
      {
        // A vertex's cone rays are cast together (their empty-space walks
        // in SIMD lanes).
        std::vector<glm::dvec3> starts(perVertex), directions(perVertex);
        const std::vector<double> reaches(perVertex, std::numeric_limits<double>::infinity());
        std::vector<avos::numerics::RayResult<double>> rays(perVertex);
        for (vtkIdType v = begin; v < end && !monitor.Aborted(); ++v, monitor.Finished(1))
        {
          double p[3], nv[3];
          withNormals->GetPoint(v, p);
          normals->GetTuple(v, nv);
          if (!ConeDirections(glm::dvec3(nv[0], nv[1], nv[2]) * sign, in.Angles, this->RaysPerCone,
                directions.data()))
          {
            continue; // no normal, no cones: the vertex stays unassigned
          }
          std::fill(starts.begin(), starts.end(), glm::dvec3(p[0], p[1], p[2]));
          caster.Cast(perVertex, starts.data(), directions.data(), reaches.data(), rays.data());
          const std::size_t first = static_cast<std::size_t>(v) * perVertex;
          for (std::size_t r = 0; r < perVertex; ++r)
          {
            if (!rays[r].Error.empty())
            {
              failures.Add(rays[r].Error);
            }
            in.Directions[first + r] = glm::fvec3(directions[r]);
            in.Colors[first + r] = glm::fvec4(rays[r].RGBA);
          }
        }
      });
  };
  // The previsualization is the long part (all cone rays): progress and
  // AbortExecute are honoured while it runs (within WorkMonitor::Interval
  // plus one vertex's rays per thread); an aborted run leaves no output.
  bool dispatched = true;
  const bool completed = monitor.Run(
    n, [&] { dispatched = setup.Dispatch(previsualize); },
    [this](double fraction)
    {
      this->UpdateProgress(fraction);
      return this->GetAbortExecute() != 0;
    });
  if (!dispatched)
  {
    vtkErrorMacro(<< "Unsupported scalar type " << setup.Scalars->GetDataTypeAsString() << ".");
    return false;
  }
  if (failures.GetCount() > 0)
  {
    vtkErrorMacro(<< failures.GetMessage() << ".");
  }
  return completed && failures.GetCount() == 0;
}

void vtkVolumeOnSurfaceFilter::AssignColours(vtkPolyData* withNormals, vtkPolyData* output)
{
  // Each vertex takes the colour of its ray with the largest positive dot
  // product with the observation line (none: transparent), directed away
  // from the observer for the volume behind the surface, towards it for the
  // volume in front.
  vtkInternals& in = *this->Internals;
  const vtkIdType n = withNormals->GetNumberOfPoints();
  const int raysPerVertex = static_cast<int>(in.Angles.size()) * this->RaysPerCone;
  double eye[3], projection[3];
  this->Camera->GetPosition(eye);
  this->Camera->GetDirectionOfProjection(projection);
  const bool parallel = this->Camera->GetParallelProjection() != 0;
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("VoSColors");
  colors->SetNumberOfComponents(4);
  colors->SetNumberOfTuples(n);
  vtkNew<vtkUnsignedCharArray> display;
  display->SetName("VoSDisplayColors");
  display->SetNumberOfComponents(3);
  display->SetNumberOfTuples(n);
  vtkNew<vtkIntArray> chosen;
  chosen->SetName("VoSRay");
  chosen->SetNumberOfTuples(n);
  vtkSMPTools::For(0, n,
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType v = begin; v < end; ++v)
      {
        double p[3];
        withNormals->GetPoint(v, p);
        glm::dvec3 line = parallel ? -glm::dvec3(projection[0], projection[1], projection[2])
                                   : glm::dvec3(eye[0] - p[0], eye[1] - p[1], eye[2] - p[2]);
        line = glm::normalize(line) * (this->VolumeSide == BEHIND_SURFACE ? -1.0 : 1.0);
        int best = -1;
        double bestDot = 0.0;
        const std::size_t first = static_cast<std::size_t>(v) * raysPerVertex;
        for (int r = 0; r < raysPerVertex; ++r)
        {
          const double dot = glm::dot(glm::dvec3(in.Directions[first + r]), line);
          if (dot > bestDot)
          {
            bestDot = dot;
            best = r;
          }
        }
        const std::array<unsigned char, 4> rgba = best >= 0
          ? avos::ToBytes(glm::dvec4(in.Colors[first + best]))
          : std::array<unsigned char, 4>{ { 0, 0, 0, 0 } };
        colors->SetTypedTuple(v, rgba.data());
        display->SetTypedTuple(v, rgba.data());
        chosen->SetValue(v, best);
      }
    });
  output->ShallowCopy(withNormals);
  output->GetPointData()->SetScalars(colors);
  output->GetPointData()->AddArray(display);
  output->GetPointData()->AddArray(chosen);
}

void vtkVolumeOnSurfaceFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VolumeSide: "
     << (this->VolumeSide == BEHIND_SURFACE ? "BehindSurface" : "InFrontOfSurface") << "\n";
  os << indent << "OpeningAngles:";
  for (double a : this->Internals->Angles)
  {
    os << " " << a;
  }
  os << "\n" << indent << "RaysPerCone: " << this->RaysPerCone << "\n";
  os << indent << "FlipNormals: " << this->FlipNormals << "\n";
  const char* methods[3] = { "Levoy", "Adaptive", "Piecewise" };
  os << indent << "IntegrationMethod: " << methods[this->IntegrationMethod] << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "ExtinctionOpacity: " << this->ExtinctionOpacity << "\n";
  os << indent << "EmptySpaceSkipping: " << this->EmptySpaceSkipping << "\n";
  os << indent << "VolumeProperty: " << this->VolumeProperty << "\n";
  os << indent << "Camera: " << this->Camera << "\n";
  os << indent << "Renderer: " << this->Renderer.GetPointer() << "\n";
  os << indent << "NumberOfRaysCast: " << this->NumberOfRaysCast << "\n";
}
