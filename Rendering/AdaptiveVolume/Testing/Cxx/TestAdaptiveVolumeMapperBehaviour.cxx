// What vtkAdaptiveVolumeMapper promises besides exactness, checked on its
// float image: rays stop at opaque geometry; nothing is recomputed when
// nothing changed; empty-space skipping changes no pixel of a Riemann sum;
// every common scalar type gives the same image; the grid's placement (origin,
// spacing, direction, the volume's matrix) is honoured; bad input gives a
// clear error and an empty image, never a crash.
#include "vtkActor.h"
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRectilinearGrid.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVariant.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "avosTestHelpers.h"

#include <glm/glm.hpp>

#include <cmath>
#include <iostream>
#include <limits>

namespace
{
constexpr int N = 40;
constexpr int Size = 48;

// A blob: s = 200 - 1.5 r^2 (r anisotropic) around the grid's centre, integer valued, so
// every scalar type holds it exactly. Index (i, j, k) of the stored array.
double Blob(int i, int j, int k)
{
  const double c = 0.5 * (N - 1);
  const double r2 = (i - c) * (i - c) + 0.5 * (j - c) * (j - c) + 2.0 * (k - c) * (k - c);
  return std::max(0.0, std::floor(200.0 - 1.5 * r2));
}

vtkSmartPointer<vtkImageData> MakeVolume(int type)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(N, N, N);
  image->SetSpacing(1.0, 1.0, 1.0);
  auto scalars = vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(type));
  scalars->SetNumberOfTuples(N * N * N);
  vtkIdType n = 0;
  for (int k = 0; k < N; ++k)
  {
    for (int j = 0; j < N; ++j)
    {
      for (int i = 0; i < N; ++i)
      {
        scalars->SetTuple1(n++, Blob(i, j, k));
      }
    }
  }
  image->GetPointData()->SetScalars(scalars);
  return image;
}

struct Scene
{
  vtkNew<vtkColorTransferFunction> Color;
  vtkNew<vtkPiecewiseFunction> Opacity;
  vtkNew<vtkVolumeProperty> Property;
  vtkNew<vtkAdaptiveVolumeMapper> Mapper;
  vtkNew<vtkVolume> Volume;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;

  Scene()
  {
    this->Color->AddRGBPoint(0, 0.1, 0.2, 0.9);
    this->Color->AddRGBPoint(120, 0.9, 0.5, 0.1);
    this->Color->AddRGBPoint(200, 1.0, 1.0, 0.8);
    this->Opacity->AddPoint(0, 0.0);
    this->Opacity->AddPoint(40, 0.0);
    this->Opacity->AddPoint(200, 0.3);
    this->Property->SetColor(this->Color);
    this->Property->SetScalarOpacity(this->Opacity);
    this->Property->SetInterpolationTypeToLinear();
    this->Volume->SetMapper(this->Mapper);
    this->Volume->SetProperty(this->Property);
    this->Renderer->AddVolume(this->Volume);
    this->Window->SetOffScreenRendering(1);
    this->Window->SetSize(Size, Size);
    this->Window->AddRenderer(this->Renderer);
  }

  void ResetView()
  {
    this->Renderer->ResetCamera();
    this->Renderer->GetActiveCamera()->Azimuth(25.0);
    this->Renderer->GetActiveCamera()->Elevation(15.0);
    this->Renderer->ResetCameraClippingRange();
  }

  // A copy of the float image of a new render.
  vtkSmartPointer<vtkFloatArray> Render()
  {
    this->Window->Render();
    auto copy = vtkSmartPointer<vtkFloatArray>::New();
    auto* rgba = this->Mapper->GetRenderedImage()->GetPointData()->GetScalars();
    if (rgba)
    {
      copy->DeepCopy(rgba);
    }
    return copy;
  }
};

double MaxDifference(vtkFloatArray* a, vtkFloatArray* b)
{
  if (a->GetNumberOfValues() != b->GetNumberOfValues() || a->GetNumberOfValues() == 0)
  {
    return std::numeric_limits<double>::infinity();
  }
  double m = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
  {
    m = std::max(m, std::abs(double(a->GetValue(i)) - double(b->GetValue(i))));
  }
  return m;
}

double MaxAlpha(vtkFloatArray* a)
{
  double m = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
  {
    m = std::max(m, double(a->GetComponent(i, 3)));
  }
  return m;
}

avostest::Checklist Expect;
} // namespace

int TestAdaptiveVolumeMapperBehaviour(int, char*[])
{
  Scene scene;
  vtkSmartPointer<vtkImageData> volume = MakeVolume(VTK_UNSIGNED_CHAR);
  scene.Mapper->SetInputData(volume);
  scene.ResetView();
  vtkSmartPointer<vtkFloatArray> reference = scene.Render();
  Expect(MaxAlpha(reference) > 0.5, "the blob is visible");
  Expect(!scene.Mapper->GetLastRenderReused(), "first render casts rays");
  Expect(scene.Mapper->GetRaysCast() > 0 && scene.Mapper->GetMeanSamplesPerRay() > 0,
    "statistics are filled");

  // Nothing changed: the image is drawn again without a ray cast.
  scene.Render();
  Expect(scene.Mapper->GetLastRenderReused(), "an unchanged frame is reused");
  scene.Opacity->AddPoint(100, 0.1);
  vtkSmartPointer<vtkFloatArray> changed = scene.Render();
  Expect(!scene.Mapper->GetLastRenderReused(), "a transfer-function change casts again");
  Expect(MaxDifference(changed, reference) > 1e-3, "the new transfer function shows");
  scene.Opacity->RemovePoint(100);
  scene.Renderer->GetActiveCamera()->Azimuth(1.0);
  scene.Render();
  Expect(!scene.Mapper->GetLastRenderReused(), "a camera change casts again");
  scene.Renderer->GetActiveCamera()->Azimuth(-1.0);
  Expect(MaxDifference(scene.Render(), reference) < 1e-7, "back to the first frame");
  // The image's placement moves the rays, the scalars unchanged.
  double origin[3];
  volume->GetOrigin(origin);
  volume->SetOrigin(origin[0] + 3.0, origin[1], origin[2]);
  vtkSmartPointer<vtkFloatArray> moved = scene.Render();
  Expect(!scene.Mapper->GetLastRenderReused(), "a new image origin casts again");
  Expect(MaxDifference(moved, reference) > 1e-3, "the moved volume shows");
  volume->SetOrigin(origin);
  Expect(MaxDifference(scene.Render(), reference) < 1e-7, "back in place");

  // TraceRay re-casts a pixel: its steps tile the ray and end at the pixel's
  // alpha; for Riemann they are uniform; off-image pixels are refused.
  for (int method : { vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED, vtkAdaptiveVolumeMapper::RIEMANN })
  {
    scene.Mapper->SetIntegrationMethod(method);
    vtkSmartPointer<vtkFloatArray> image = scene.Render();
    const int x = Size / 2, y = Size / 2;
    vtkNew<vtkTable> steps;
    const std::string name = scene.Mapper->GetIntegrationMethodAsString();
    Expect(scene.Mapper->TraceRay(x, y, steps) && steps->GetNumberOfRows() > 3,
      name + ": the centre ray has steps");
    const vtkIdType rows = steps->GetNumberOfRows();
    bool tiled = rows > 0, uniform = true;
    for (vtkIdType r = 1; r < rows; ++r)
    {
      const double end = steps->GetValueByName(r - 1, "Start").ToDouble() +
        steps->GetValueByName(r - 1, "Length").ToDouble();
      tiled = tiled && steps->GetValueByName(r, "Start").ToDouble() >= end - 1e-9 &&
        steps->GetValueByName(r, "Opacity").ToDouble() >=
          steps->GetValueByName(r - 1, "Opacity").ToDouble();
      uniform = uniform &&
        (r + 1 == rows || std::abs(steps->GetValueByName(r, "Length").ToDouble() - 0.5) < 1e-12);
    }
    Expect(tiled, name + ": the steps follow one another with growing opacity");
    Expect(rows > 0 &&
        std::abs(steps->GetValueByName(rows - 1, "Opacity").ToDouble() -
          image->GetComponent(y * Size + x, 3)) < 1e-6,
      name + ": the last step's opacity is the pixel's alpha");
    if (method == vtkAdaptiveVolumeMapper::RIEMANN)
    {
      Expect(uniform, "Riemann's steps are the sample distance");
    }
  }
  {
    vtkNew<vtkTable> steps;
    avostest::ExpectedErrors errors(scene.Mapper);
    Expect(!scene.Mapper->TraceRay(Size, 0, steps) && steps->GetNumberOfColumns() == 0 &&
        errors.Check("off-image trace", "outside the"),
      "an off-image pixel is refused");
  }
  scene.Mapper->SetIntegrationMethodToAdaptiveCoupled();

  // Empty-space skipping: a Riemann sum is the same, pixel for pixel.
  scene.Mapper->SetIntegrationMethodToRiemann();
  vtkSmartPointer<vtkFloatArray> skipped = scene.Render();
  Expect(scene.Mapper->GetNumberOfVisibleBlocks() < scene.Mapper->GetNumberOfBlocks(),
    "some blocks are empty");
  scene.Mapper->EmptySpaceSkippingOff();
  Expect(MaxDifference(scene.Render(), skipped) == 0.0, "skipping changes no Riemann pixel");
  scene.Mapper->EmptySpaceSkippingOn();
  // The Riemann kernel reads 8- and 16-bit and float scalars in place, the
  // others converted to float: the same integers, the same image.
  for (int type : { VTK_SHORT, VTK_UNSIGNED_SHORT, VTK_INT, VTK_FLOAT, VTK_DOUBLE })
  {
    scene.Mapper->SetInputData(MakeVolume(type));
    Expect(MaxDifference(scene.Render(), skipped) == 0.0,
      std::string("same Riemann image from ") + vtkImageScalarTypeNameMacro(type));
  }
  scene.Mapper->SetInputData(volume);
  scene.Mapper->SetIntegrationMethodToAdaptiveCoupled();

  // Every common scalar type holds the same integers: the same image.
  for (int type : { VTK_SHORT, VTK_UNSIGNED_SHORT, VTK_INT, VTK_FLOAT, VTK_DOUBLE })
  {
    scene.Mapper->SetInputData(MakeVolume(type));
    Expect(MaxDifference(scene.Render(), reference) == 0.0,
      std::string("same image from ") + vtkImageScalarTypeNameMacro(type));
  }
  // The piecewise method casts 8- and 16-bit scalars a ray per lane
  // (avos/engine/PiecewiseRays.h), the others a ray at a time: the same
  // image (within 1e-15 before the float image's rounding).
  scene.Mapper->SetIntegrationMethodToPiecewiseAdaptive();
  vtkSmartPointer<vtkFloatArray> piecewise = scene.Render(); // double scalars
  Expect(MaxAlpha(piecewise) > 0.5, "the piecewise blob is visible");
  for (int type : { VTK_UNSIGNED_CHAR, VTK_UNSIGNED_SHORT, VTK_FLOAT })
  {
    scene.Mapper->SetInputData(MakeVolume(type));
    Expect(MaxDifference(scene.Render(), piecewise) == 0.0,
      std::string("same piecewise image from ") + vtkImageScalarTypeNameMacro(type));
  }
  scene.Mapper->SetIntegrationMethodToAdaptiveCoupled();

  // Placement: origin and spacing in the image, or the same through the
  // volume's matrix, or a direction matrix with the axes' data permuted.
  // With a Riemann sum the samples sit at the same world points whatever the
  // grid's orientation (adaptive steps may differ within eps, as the empty
  // blocks do).
  {
    scene.Mapper->SetIntegrationMethodToRiemann();
    vtkSmartPointer<vtkImageData> placed = MakeVolume(VTK_FLOAT);
    placed->SetOrigin(3.0, -2.0, 1.0);
    placed->SetSpacing(0.5, 0.5, 0.5);
    scene.Mapper->SetInputData(placed);
    scene.ResetView();
    vtkSmartPointer<vtkFloatArray> byImage = scene.Render();
    Expect(MaxAlpha(byImage) > 0.5, "placed volume visible");

    scene.Mapper->SetInputData(MakeVolume(VTK_FLOAT));
    scene.Volume->SetScale(0.5);
    scene.Volume->SetPosition(3.0, -2.0, 1.0);
    Expect(MaxDifference(scene.Render(), byImage) < 1e-6, "volume matrix = image placement");
    scene.Volume->SetScale(1.0);
    scene.Volume->SetPosition(0.0, 0.0, 0.0);

    // Direction: index axis i along world -y, j along world x. The array is
    // stored so that the world field is the same as `placed`'s.
    vtkSmartPointer<vtkImageData> rotated = MakeVolume(VTK_FLOAT);
    vtkDataArray* s = rotated->GetPointData()->GetScalars();
    vtkIdType n = 0;
    for (int k = 0; k < N; ++k)
    {
      for (int j = 0; j < N; ++j)
      {
        for (int i = 0; i < N; ++i)
        {
          // World x = j, world y = (N - 1) - i in placed's index terms.
          s->SetTuple1(n++, Blob(j, N - 1 - i, k));
        }
      }
    }
    const double direction[9] = { 0, 1, 0, -1, 0, 0, 0, 0, 1 };
    rotated->SetDirectionMatrix(direction);
    rotated->SetSpacing(0.5, 0.5, 0.5);
    rotated->SetOrigin(3.0, -2.0 + 0.5 * (N - 1), 1.0);
    scene.Mapper->SetInputData(rotated);
    Expect(MaxDifference(scene.Render(), byImage) < 1e-6, "direction matrix honoured");
    scene.Mapper->SetIntegrationMethodToAdaptiveCoupled();
  }

  // Opaque geometry in front of the lower half of the view: rays stop there.
  {
    scene.Mapper->SetInputData(volume);
    scene.ResetView();
    double fp[3], pos[3];
    scene.Renderer->GetActiveCamera()->GetFocalPoint(fp);
    scene.Renderer->GetActiveCamera()->GetPosition(pos);
    // A plane facing the camera between it and the volume, lower half only.
    vtkNew<vtkPlaneSource> square;
    const glm::dvec3 f(fp[0], fp[1], fp[2]), p(pos[0], pos[1], pos[2]);
    const glm::dvec3 c = f + 0.6 * (p - f);
    double up[3];
    scene.Renderer->GetActiveCamera()->GetViewUp(up);
    const glm::dvec3 u(up[0], up[1], up[2]);
    const glm::dvec3 r = glm::normalize(glm::cross(f - p, u));
    const glm::dvec3 o = c - 100.0 * r - 100.0 * u;
    const glm::dvec3 p1 = c + 100.0 * r - 100.0 * u;
    const glm::dvec3 p2 = c - 100.0 * r;
    square->SetOrigin(o.x, o.y, o.z);
    square->SetPoint1(p1.x, p1.y, p1.z);
    square->SetPoint2(p2.x, p2.y, p2.z);
    vtkNew<vtkPolyDataMapper> polyMapper;
    polyMapper->SetInputConnection(square->GetOutputPort());
    vtkNew<vtkActor> actor;
    actor->SetMapper(polyMapper);
    scene.Renderer->AddActor(actor);
    scene.Renderer->ResetCameraClippingRange();
    vtkSmartPointer<vtkFloatArray> occluded = scene.Render();
    double below = 0.0, above = 0.0;
    for (int y = 0; y < Size; ++y)
    {
      for (int x = 0; x < Size; ++x)
      {
        const double a = occluded->GetComponent(y * Size + x, 3);
        double& half = y < Size / 2 - 1 ? below : above;
        half = std::max(half, a);
      }
    }
    Expect(below == 0.0, "no volume behind opaque geometry");
    Expect(above > 0.5, "volume above the geometry");
    scene.Renderer->RemoveActor(actor);
  }

  // Image sample distance: a ray every 2 pixels gives the image of a window
  // half the size (the same ray through each image pixel's centre).
  // Auto-adjusted, the distance grows to the maximum when the renderer
  // allots a microsecond, and a still render is at full resolution again.
  {
    scene.Mapper->SetInputData(volume);
    scene.ResetView();
    scene.Mapper->AutoAdjustSampleDistancesOff();
    scene.Window->SetSize(Size / 2, Size / 2);
    vtkSmartPointer<vtkFloatArray> half = scene.Render();
    scene.Window->SetSize(Size, Size);
    vtkSmartPointer<vtkFloatArray> full = scene.Render();
    scene.Mapper->SetImageSampleDistance(2.0);
    vtkSmartPointer<vtkFloatArray> sampled = scene.Render();
    const int* dims = scene.Mapper->GetRenderedImage()->GetDimensions();
    Expect(dims[0] == Size / 2 && dims[1] == Size / 2 &&
        scene.Mapper->GetLastImageSampleDistance() == 2.0,
      "image sample distance 2: a half-size image");
    Expect(MaxDifference(sampled, half) < 1e-7, "the rays of a half-size window");
    vtkNew<vtkUnsignedCharArray> pixels;
    scene.Window->GetRGBACharPixelData(0, 0, Size - 1, Size - 1, 0, pixels);
    int lit = 0, cast = 0;
    for (vtkIdType p = 0; p < Size * Size; ++p)
    {
      lit +=
        pixels->GetComponent(p, 0) + pixels->GetComponent(p, 1) + pixels->GetComponent(p, 2) > 30;
      cast += full->GetComponent(p, 3) > 0.1;
    }
    Expect(std::abs(lit - cast) < Size * 2, "the smaller image covers the viewport");

    scene.Mapper->SetImageSampleDistance(1.0);
    scene.Mapper->AutoAdjustSampleDistancesOn();
    scene.Window->SetDesiredUpdateRate(1e6);
    for (int frame = 0; frame < 2; ++frame) // the first measures the cast time
    {
      scene.Renderer->GetActiveCamera()->Azimuth(1.0);
      scene.Render();
    }
    dims = scene.Mapper->GetRenderedImage()->GetDimensions();
    Expect(scene.Mapper->GetLastImageSampleDistance() == 10.0 && dims[0] == (Size + 9) / 10 &&
        dims[1] == (Size + 9) / 10,
      "a microsecond per frame: the coarsest image");
    scene.Render();
    Expect(scene.Mapper->GetLastRenderReused(), "auto-adjusted, an unchanged frame is reused");
    scene.Window->SetDesiredUpdateRate(0.0001);
    scene.Renderer->GetActiveCamera()->Azimuth(-2.0);
    Expect(MaxDifference(scene.Render(), full) < 1e-7 &&
        scene.Mapper->GetLastImageSampleDistance() == 1.0,
      "a still render: full resolution again");
  }

  // The camera inside the volume: rays start at the near plane, in the blob.
  {
    scene.Mapper->SetInputData(volume);
    vtkCamera* camera = scene.Renderer->GetActiveCamera();
    const double c = 0.5 * (N - 1);
    camera->SetFocalPoint(c + 10.0, c, c);
    camera->SetPosition(c - 2.0, c, c);
    camera->SetViewUp(0, 0, 1);
    camera->SetClippingRange(0.1, 100.0);
    vtkSmartPointer<vtkFloatArray> inside = scene.Render();
    Expect(MaxAlpha(inside) > 0.5 && scene.Mapper->GetRaysCast() == Size * Size,
      "camera inside: every ray starts in the volume");
    // A far clipping plane inside the volume shortens every ray.
    camera->SetClippingRange(0.1, 3.0);
    vtkSmartPointer<vtkFloatArray> clipped = scene.Render();
    double less = 0.0;
    for (vtkIdType p = 0; p < clipped->GetNumberOfTuples(); ++p)
    {
      less = std::max(less, inside->GetComponent(p, 3) - clipped->GetComponent(p, 3));
    }
    Expect(less > 0.1 && MaxAlpha(clipped) > 0.0, "the far clipping plane is honoured");
    scene.ResetView();
  }

  // Bad input: a clear error, an empty image.
  avostest::ExpectedErrors errors(scene.Mapper);
  auto expectError = [&](const std::string& what, const std::string& message)
  {
    scene.Window->Render();
    Expect(errors.Check(what, message), what);
    Expect(scene.Mapper->GetRenderedImage()->GetNumberOfPoints() == 0, what + ": empty image");
  };
  scene.Mapper->SetInputData(volume);
  scene.Mapper->SetTolerance(0.0);
  expectError("tolerance 0", "tolerance must be positive");
  scene.Mapper->SetTolerance(-1.0);
  expectError("negative tolerance", "tolerance must be positive");
  scene.Mapper->SetTolerance(0.01);
  scene.Mapper->SetMinimumStep(3.0);
  expectError("hmin > hmax", "minimum step <= maximum step");
  scene.Mapper->SetMinimumStep(0.1);
  scene.Mapper->SetIntegrationMethodToRiemann();
  scene.Mapper->SetSampleDistance(0.0);
  expectError("zero sample distance", "within [0.001, 1000] voxel units");
  scene.Mapper->SetSampleDistance(1e-6);
  expectError("a step of 1e-6 voxel", "within [0.001, 1000] voxel units");
  scene.Mapper->SetSampleDistance(0.5);
  scene.Mapper->SetMinimumStep(1e-5);
  expectError("hmin 1e-5", "within [0.001, 1000] voxel units");
  scene.Mapper->SetMinimumStep(0.1);
  scene.Mapper->SetIntegrationMethodToAdaptiveCoupled();

  vtkNew<vtkImageData> noScalars;
  noScalars->SetDimensions(N, N, N);
  scene.Mapper->SetInputData(noScalars);
  expectError("no scalars", "no scalars");

  vtkNew<vtkImageData> fiveComponents;
  fiveComponents->SetDimensions(N, N, N);
  vtkNew<vtkFloatArray> tuples;
  tuples->SetNumberOfComponents(5);
  tuples->SetNumberOfTuples(N * N * N);
  tuples->Fill(1.0);
  fiveComponents->GetPointData()->SetScalars(tuples);
  scene.Mapper->SetInputData(fiveComponents);
  expectError("five components", "1 to 4 components are supported");

  vtkNew<vtkImageData> empty;
  vtkNew<vtkFloatArray> none;
  empty->GetPointData()->SetScalars(none);
  scene.Mapper->SetInputData(empty);
  expectError("empty extent", "at least 2 points");

  vtkSmartPointer<vtkImageData> flat = MakeVolume(VTK_FLOAT);
  flat->SetSpacing(1.0, 0.0, 1.0);
  scene.Mapper->SetInputData(flat);
  expectError("zero spacing", "spacing must be non-zero");

  vtkNew<vtkRectilinearGrid> rectilinear;
  scene.Mapper->SetInputData(rectilinear);
  expectError("not image data", "must be a vtkImageData");

  scene.Mapper->SetInputData(volume);
  scene.Window->Render();
  Expect(errors.None("good input again") && MaxAlpha(scene.Render()) > 0.5, "recovers");

  // NaN scalars: every cell with a NaN corner is transparent, in every
  // method (the piecewise method within eps of the reference, which takes
  // NaN samples as transparent), said once per change of the scalars.
  {
    vtkSmartPointer<vtkImageData> withNaN = MakeVolume(VTK_FLOAT);
    vtkDataArray* values = withNaN->GetPointData()->GetScalars();
    for (vtkIdType id : { vtkIdType(77), vtkIdType(N * N * N / 2 + N / 2 + N * N / 3) })
    {
      values->SetTuple1(id, std::nan(""));
    }
    scene.Mapper->SetInputData(withNaN);
    const int method = scene.Mapper->GetIntegrationMethod();
    scene.Mapper->SetIntegrationMethodToReference();
    vtkSmartPointer<vtkFloatArray> exact = scene.Render();
    Expect(errors.CheckWarning("NaN data",
             "2 NaN scalars: the cells they touch are rendered "
             "transparent"),
      "NaN data is rendered, with a warning");
    auto finite = [](vtkFloatArray* image)
    {
      for (vtkIdType i = 0; i < image->GetNumberOfValues(); ++i)
      {
        if (!std::isfinite(image->GetValue(i)))
        {
          return false;
        }
      }
      return image->GetNumberOfValues() > 0;
    };
    Expect(finite(exact) && MaxAlpha(exact) > 0.5, "the reference around NaN");
    for (int m : { vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE, vtkAdaptiveVolumeMapper::RIEMANN,
           vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED })
    {
      scene.Mapper->SetIntegrationMethod(m);
      scene.Mapper->SetTolerance(0.001);
      vtkSmartPointer<vtkFloatArray> image = scene.Render();
      const std::string name = scene.Mapper->GetIntegrationMethodAsString();
      Expect(errors.None(name + " around NaN, the warning said once"), name + ": no new warning");
      Expect(finite(image) &&
          MaxDifference(image, exact) <
            (m == vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE ? 0.0011 : 0.05),
        name + " around NaN: finite, and as the reference");
    }
    scene.Mapper->SetBlendModeToMaximumIntensity();
    Expect(finite(scene.Render()) && errors.None("MIP around NaN"), "MIP around NaN");
    scene.Mapper->SetBlendModeToComposite();
    scene.Mapper->SetIntegrationMethod(method);
    scene.Mapper->SetTolerance(0.01);
    scene.Mapper->SetInputData(volume);
    scene.Window->Render();
  }

  vtkNew<vtkPiecewiseFunction> noOpacity;
  scene.Property->SetScalarOpacity(noOpacity);
  expectError("empty opacity function", "scalar opacity function is empty");
  scene.Property->SetScalarOpacity(scene.Opacity);
  vtkNew<vtkColorTransferFunction> noColor;
  scene.Property->SetColor(noColor);
  expectError("empty colour function", "colour transfer function is empty");
  scene.Property->SetColor(scene.Color);
  scene.Opacity->AddPoint(60, std::nan(""));
  expectError("NaN opacity", "Unusable transfer function");
  scene.Opacity->RemovePoint(60);

  scene.Mapper->SetBlendModeToIsoSurface();
  expectError(
    "isosurface blend", "composite, maximum, minimum and average intensity, and additive are");
  scene.Mapper->SetBlendModeToComposite();
  // Shading with the piecewise method is drawn; where it cannot be
  // honoured (a projection, a light without a bounded attenuation) it is
  // refused.
  scene.Property->ShadeOn();
  const int method = scene.Mapper->GetIntegrationMethod();
  scene.Mapper->SetIntegrationMethodToPiecewiseAdaptive();
  Expect(
    MaxAlpha(scene.Render()) > 0.1 && errors.None("shaded piecewise"), "shaded piecewise is drawn");
  scene.Mapper->SetIntegrationMethod(method);
  scene.Mapper->SetBlendModeToMaximumIntensity();
  expectError("shaded projection", "shading applies to the composite blend mode only");
  scene.Mapper->SetBlendModeToComposite();
  vtkNew<vtkLight> lamp;
  lamp->SetPositional(true);
  lamp->SetAttenuationValues(0.0, 0.0, 1.0);
  scene.Renderer->AddLight(lamp);
  expectError("unbounded attenuation", "the constant one > 0");
  scene.Renderer->RemoveLight(lamp);
  scene.Property->ShadeOff();
  scene.Property->UseClippedVoxelIntensityOn();
  expectError("clipped voxel intensity", "UseClippedVoxelIntensity");
  scene.Property->UseClippedVoxelIntensityOff();
  scene.Property->SetTransferFunctionMode(vtkVolumeProperty::TF_2D);
  expectError("2D transfer function", "A 2D transfer function (ParaView's Use 2D Transfer");
  scene.Property->SetTransferFunctionMode(vtkVolumeProperty::TF_1D);
  scene.Property->SetInterpolationTypeToNearest();
  scene.Property->ShadeOn();
  expectError(
    "shaded nearest interpolation", "Cannot shade: only point scalars with linear interpolation");
  scene.Property->ShadeOff();
  scene.Window->Render();
  Expect(errors.None("nearest interpolation"), "nearest interpolation is rendered");
  scene.Property->SetInterpolationTypeToLinear();
  // VTK's default gradient opacity (constant 1, created on first access)
  // changes nothing and is accepted; a real one is rendered by every
  // composite method.
  scene.Property->GetGradientOpacity()->RemoveAllPoints();
  scene.Property->GetGradientOpacity()->AddPoint(0.0, 1.0);
  scene.Window->Render();
  Expect(errors.None("constant gradient opacity"), "a constant 1 gradient opacity is accepted");
  scene.Property->GetGradientOpacity()->AddPoint(10.0, 0.2);
  const int before = scene.Mapper->GetIntegrationMethod();
  scene.Mapper->SetIntegrationMethodToAdaptiveCoupled();
  scene.Window->Render();
  Expect(errors.None("gradient opacity, coupled"), "gradient opacity is rendered (coupled)");
  scene.Mapper->SetIntegrationMethodToPiecewiseAdaptive();
  scene.Window->Render();
  Expect(errors.None("gradient opacity, piecewise"), "gradient opacity is rendered (piecewise)");
  scene.Mapper->SetIntegrationMethod(before);
  scene.Property->DisableGradientOpacityOn();
  scene.Window->Render();
  Expect(errors.None("disabled gradient opacity"), "a disabled gradient opacity is accepted");
  scene.Mapper->SetBlendModeToComposite();
  scene.Window->Render();
  Expect(errors.None("good again"), "recovers at the end");
  return Expect.Result();
}
