// Scalars of several components through the whole mapper, pixel by pixel:
// random values on [-1, 1]^3 (9^3 points, linear interpolation), each
// component with its own colour, opacity and weight (independent, 2 and 3
// components), and the dependent mixtures (the first component's colour
// function of s_0 and opacity of s_1; unsigned char RGB and the opacity of
// s_3), seen through the oblique orthographic view of the closed-form
// tests. Each pixel's ray is rebuilt from the renderer and integrated by the
// numerical core's mixture (Mixture.h, proven against an independent oracle
// in the numerics tests) at the reference's 1e-10, from transfer functions
// built here from the same knots: this checks what the mapper adds (the
// property's functions per component, the weights, the tuples read in
// place, the empty-space map of the mixture). Required: the piecewise
// method within eps on every pixel, the reference within 1e-5, the adaptive
// rule at 1e-5 within 1e-3, the Riemann sum first order (a tenth of the
// step at least 5 times closer); the oracle with the weights ignored must differ
// by more than 0.01 (it tells a wrong mixture from a right one); a second
// component of opacity 0 leaves the first component's image; what the
// mapper cannot honour is refused. The vector modes render one component,
// or the tuples' norms, as the one-component volume of them. The second
// component's and the vector mode's checks run on double, unsigned char and
// unsigned short tuples (the latter two read by the vectorised kernels, one
// component of the tuples in place).
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTrivialProducer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedShortArray.h"
#include "vtkVolumeProperty.h"

#include "ObliqueScene.h"
#include "avosTestHelpers.h"

#include "avos/numerics/Mixture.h"
#include "avos/numerics/Volume.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace
{
namespace an = avos::numerics;
constexpr int Size = 64;
constexpr int Points = 9;
constexpr double Voxel = 2.0 / (Points - 1);

// Knots (scalar, r, g, b, tau per voxel unit) of each component.
const double First[][5] = { { 10, 0.2, 0.2, 0.9, 0.0 }, { 40, 0.9, 0.6, 0.1, 0.05 },
  { 60, 0.1, 0.9, 0.3, 0.4 }, { 85, 0.9, 0.9, 0.9, 0.1 } };
const double Second[][5] = { { 0, 1.0, 0.0, 0.0, 0.0 }, { 50, 1.0, 0.3, 0.0, 0.0 },
  { 70, 0.0, 0.3, 1.0, 0.6 }, { 95, 0.0, 1.0, 0.2, 0.6 } };
const double Third[][5] = { { 0, 0.5, 0.5, 0.5, 0.2 }, { 95, 1.0, 1.0, 0.0, 0.0 } };

// Component k's functions into the property and the core's function.
template <std::size_t N>
void Fill(
  const double (&knots)[N][5], vtkVolumeProperty* property, int k, an::TransferFunction<double>& tf)
{
  vtkNew<vtkColorTransferFunction> color;
  vtkNew<vtkPiecewiseFunction> opacity;
  tf = an::TransferFunction<double>();
  for (const auto& knot : knots)
  {
    color->AddRGBPoint(knot[0], knot[1], knot[2], knot[3]);
    opacity->AddPoint(knot[0], knot[4]);
    tf.AddColorKnot(knot[0], knot[1], knot[2], knot[3]);
    tf.AddOpacityKnot(knot[0], knot[4]);
  }
  tf.Finalize();
  property->SetColor(k, color);
  property->SetScalarOpacity(k, opacity);
}

// Pixel (x, y)'s RGBA by the core: the mixture `pieces` of the volume
// `values` (interleaved, `components` per point) at the reference's
// tolerance.
glm::dvec4 Exact(vtkRenderer* renderer, const std::vector<double>& values, int components,
  const an::PiecewiseMixture<double>& pieces, int x, int y)
{
  const obliquescene::PixelRay ray = obliquescene::RayOf(renderer, x, y);
  if (!(ray.T0 < ray.T1))
  {
    return glm::dvec4(0.0);
  }
  using Volume = an::TrilinearVolume<double, double>;
  const int dims[3] = { Points, Points, Points };
  const an::ComponentVolumes<double, Volume> volumes(
    components, [&](int k) { return Volume(values.data() + k, dims, components); });
  const glm::dvec3 o = (ray.Start + ray.T0 * ray.Direction + 1.0) / Voxel;
  const an::Interval<double> whole{ 0.0, (ray.T1 - ray.T0) / Voxel };
  return an::IntegratePiecewiseMixture(
    volumes, o, ray.Direction, &whole, 1, pieces, an::PiecewiseReferenceTolerance<double>(), false)
    .RGBA;
}

struct Run
{
  const char* Name;
  int Method;
  double Tolerance;
  double Required; // maximum error on any pixel
  double Step = 0.5;
};

// The mapper's image against the core's mixture; failures counted.
int Check(const char* name, obliquescene::Scene& scene, avostest::ExpectedErrors& errors,
  const std::vector<double>& values, int components, const an::MixtureTransferFunction<double>& mix,
  const an::MixtureTransferFunction<double>* wrong)
{
  an::PiecewiseMixture<double> pieces, wrongPieces;
  if (!pieces.Build(mix, 1e-7).empty() || (wrong && !wrongPieces.Build(*wrong, 1e-7).empty()))
  {
    std::cerr << "FAIL " << name << ": the oracle's mixture\n";
    return 1;
  }
  std::vector<glm::dvec4> exact, other;
  for (int y = 0; y < Size; ++y)
  {
    for (int x = 0; x < Size; ++x)
    {
      exact.push_back(Exact(scene.Renderer, values, components, pieces, x, y));
      if (wrong)
      {
        other.push_back(Exact(scene.Renderer, values, components, wrongPieces, x, y));
      }
    }
  }
  int failures = 0;
  double discrimination = 0.0;
  for (std::size_t i = 0; i < other.size(); ++i)
  {
    for (int k = 0; k < 4; ++k)
    {
      discrimination = std::max(discrimination, std::abs(other[i][k] - exact[i][k]));
    }
  }
  if (wrong && discrimination <= 1e-2)
  {
    std::cerr << "FAIL " << name << ": the wrong mixture is only " << discrimination << " off\n";
    ++failures;
  }
  // The Riemann sums' bound: first order from their error at h 0.5 (set below).
  double riemann = 1.0;
  const Run runs[] = { { "piecewise eps 1e-3", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE, 1e-3,
                         1e-3 },
    { "piecewise eps 1e-2", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE, 1e-2, 1e-2 },
    { "reference", vtkAdaptiveVolumeMapper::REFERENCE, 1e-2, 1e-5 },
    { "coupled eps 1e-5", vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED, 1e-5, 1e-3 },
    { "riemann h 0.5", vtkAdaptiveVolumeMapper::RIEMANN, 1e-2, 1.0, 0.5 },
    { "riemann h 0.05", vtkAdaptiveVolumeMapper::RIEMANN, 1e-2, 0.0, 0.05 } };
  vtkAdaptiveVolumeMapper* mapper = scene.Mapper;
  for (const Run& run : runs)
  {
    mapper->SetIntegrationMethod(run.Method);
    mapper->SetTolerance(run.Tolerance);
    mapper->SetSampleDistance(run.Step);
    scene.Window->Render();
    auto* rgba =
      vtkFloatArray::SafeDownCast(mapper->GetRenderedImage()->GetPointData()->GetScalars());
    if (!rgba || !errors.None(run.Name))
    {
      std::cerr << "FAIL " << name << ", " << run.Name << ": nothing rendered\n";
      ++failures;
      continue;
    }
    double maxError = 0.0, opacity = 0.0;
    for (vtkIdType i = 0; i < Size * Size; ++i)
    {
      for (int k = 0; k < 4; ++k)
      {
        maxError = std::max(maxError, std::abs(rgba->GetComponent(i, k) - exact[i][k]));
      }
      opacity = std::max(opacity, exact[i].a);
    }
    std::cout << name << ", " << run.Name << ": max error " << maxError << " (discrimination "
              << discrimination << ", largest opacity " << opacity << ")\n";
    const double required = run.Required > 0.0 ? run.Required : riemann / 5.0;
    riemann = maxError;
    // The image is stored in float: 6e-8 relative.
    if (maxError > required + 1e-7 || opacity < 0.3)
    {
      std::cerr << "FAIL " << name << ", " << run.Name << ": max error " << maxError << "\n";
      ++failures;
    }
  }
  return failures;
}

// `components` random values per point in [0, top), interleaved.
std::vector<double> Random(int components, double top, bool integral, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, top);
  std::vector<double> values;
  for (int i = 0; i < Points * Points * Points * components; ++i)
  {
    values.push_back(integral ? std::floor(u(rng)) : u(rng));
  }
  return values;
}

template <typename Array>
void SetScalars(vtkImageData* image, const std::vector<double>& values, int components)
{
  vtkNew<Array> scalars;
  scalars->SetName("values");
  scalars->SetNumberOfComponents(components);
  for (const double v : values)
  {
    scalars->InsertNextValue(static_cast<typename Array::ValueType>(v));
  }
  image->GetPointData()->SetScalars(scalars);
  image->Modified();
}

// The scalar types whose reading differs: double (the scalar walk), unsigned
// char and unsigned short (read in place by the vectorised kernels, one
// component of interleaved tuples too), the values rounded for the latter.
enum class Stored
{
  Double,
  UnsignedChar,
  UnsignedShort
};
const char* NameOf(Stored type)
{
  return type == Stored::Double ? "double" : (type == Stored::UnsignedChar ? "uchar" : "ushort");
}
void SetScalars(vtkImageData* image, std::vector<double> values, int components, Stored type)
{
  if (type == Stored::Double)
  {
    SetScalars<vtkDoubleArray>(image, values, components);
    return;
  }
  for (double& v : values)
  {
    v = std::round(v);
  }
  type == Stored::UnsignedChar ? SetScalars<vtkUnsignedCharArray>(image, values, components)
                               : SetScalars<vtkUnsignedShortArray>(image, values, components);
}
} // namespace

int TestAdaptiveVolumeMapperComponents(int, char*[])
{
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  an::TransferFunction<double> tf[3];
  Fill(First, property, 0, tf[0]);
  Fill(Second, property, 1, tf[1]);
  Fill(Third, property, 2, tf[2]);
  obliquescene::Cube cube(Points);
  vtkImageData* image = cube.Image;
  obliquescene::Scene scene(cube.Producer, property, Size);
  vtkAdaptiveVolumeMapper* mapper = scene.Mapper;
  mapper->SetOpacityModelToExtinction();
  avostest::ExpectedErrors errors(mapper);
  int failures = 0;
  const an::TransferFunction<double>* functions[3] = { &tf[0], &tf[1], &tf[2] };
  const double ones[3] = { 1.0, 1.0, 1.0 };

  // Independent, two components weighted 1 and 0.4, then three (0.5 on the third).
  const std::vector<double> two = Random(2, 95.0, false, 3);
  SetScalars<vtkDoubleArray>(image, two, 2);
  const double weights[3] = { 1.0, 0.4, 0.5 };
  property->SetComponentWeight(1, weights[1]);
  an::MixtureTransferFunction<double> mix, wrong;
  mix.SetIndependent(2, functions, weights);
  wrong.SetIndependent(2, functions, ones);
  failures += Check("two independent components", scene, errors, two, 2, mix, &wrong);
  const std::vector<double> three = Random(3, 95.0, false, 5);
  SetScalars<vtkDoubleArray>(image, three, 3);
  property->SetComponentWeight(2, weights[2]);
  mix.SetIndependent(3, functions, weights);
  wrong.SetIndependent(3, functions, ones);
  failures += Check("three independent components", scene, errors, three, 3, mix, &wrong);

  // A second component of opacity 0 leaves the first's image.
  vtkNew<vtkPiecewiseFunction> clear;
  clear->AddPoint(0.0, 0.0);
  clear->AddPoint(95.0, 0.0);
  vtkPiecewiseFunction* secondOpacity = property->GetScalarOpacity(1);
  secondOpacity->Register(nullptr);
  property->SetScalarOpacity(1, clear);
  std::vector<double> alone;
  for (std::size_t i = 0; i < two.size(); i += 2)
  {
    alone.push_back(two[i]);
  }
  mapper->SetIntegrationMethodToPiecewiseAdaptive();
  mapper->SetTolerance(1e-3);
  for (const Stored type : { Stored::Double, Stored::UnsignedChar, Stored::UnsignedShort })
  {
    SetScalars(image, two, 2, type);
    scene.Window->Render();
    vtkNew<vtkFloatArray> mixed;
    mixed->DeepCopy(mapper->GetRenderedImage()->GetPointData()->GetScalars());
    const bool drawn = errors.None("the mixture");
    SetScalars(image, alone, 1, type);
    scene.Window->Render();
    auto* single =
      vtkFloatArray::SafeDownCast(mapper->GetRenderedImage()->GetPointData()->GetScalars());
    double apart = 1.0;
    if (drawn && single && single->GetNumberOfTuples() == Size * Size &&
      mixed->GetNumberOfTuples() == Size * Size)
    {
      apart = 0.0;
      for (vtkIdType i = 0; i < 4 * single->GetNumberOfTuples(); ++i)
      {
        apart = std::max(apart, std::abs(double(single->GetValue(i)) - mixed->GetValue(i)));
      }
    }
    std::cout << "transparent second component against the first alone, " << NameOf(type) << ": "
              << apart << "\n";
    if (!(apart <= 2e-3))
    {
      std::cerr << "FAIL a transparent second component changes the image by " << apart << " ("
                << NameOf(type) << ")\n";
      ++failures;
    }
  }
  property->SetScalarOpacity(1, secondOpacity);
  secondOpacity->UnRegister(nullptr);

  // Dependent: the colour function of s_0, the opacity function of s_1.
  property->IndependentComponentsOff();
  SetScalars<vtkDoubleArray>(image, two, 2);
  mix.SetColourOpacity(tf[0]);
  failures += Check("dependent colour and opacity", scene, errors, two, 2, mix, nullptr);
  // Dependent RGBA: unsigned char, RGB / 255, the opacity function of s_3.
  const std::vector<double> rgba = Random(4, 95.0, true, 7);
  SetScalars<vtkUnsignedCharArray>(image, rgba, 4);
  mix.SetRGBOpacity(tf[0], 1.0 / 255.0);
  failures += Check("dependent RGB and opacity", scene, errors, rgba, 4, mix, nullptr);

  // The vector modes: one component read in place (the second of three), or
  // the tuples' norms, each through the property's first functions: the
  // image of that component, or of the norms, as a one-component volume.
  mapper->SetIntegrationMethodToPiecewiseAdaptive();
  mapper->SetTolerance(1e-3);
  std::vector<double> second, norms;
  for (std::size_t i = 0; i < three.size(); i += 3)
  {
    second.push_back(three[i + 1]);
    norms.push_back(
      std::sqrt(three[i] * three[i] + three[i + 1] * three[i + 1] + three[i + 2] * three[i + 2]));
  }
  auto rendered = [&]()
  {
    scene.Window->Render();
    std::vector<float> values(4 * Size * Size, -1.0f);
    auto* drawn =
      vtkFloatArray::SafeDownCast(mapper->GetRenderedImage()->GetPointData()->GetScalars());
    for (std::size_t i = 0; drawn && i < values.size() && errors.None("vector mode"); ++i)
    {
      values[i] = drawn->GetValue(static_cast<vtkIdType>(i));
    }
    return values;
  };
  struct Mode
  {
    const char* Name;
    int VectorMode;
    const std::vector<double>* Alone;
  };
  for (const Mode mode : { Mode{ "component 1", vtkAdaptiveVolumeMapper::COMPONENT, &second },
         Mode{ "magnitude", vtkAdaptiveVolumeMapper::MAGNITUDE, &norms } })
  {
    mapper->SetVectorMode(mode.VectorMode);
    mapper->SetVectorComponent(1);
    // The norms are floats whatever the tuples: the double tuples only.
    for (const Stored type : { Stored::Double, Stored::UnsignedChar, Stored::UnsignedShort })
    {
      if (mode.VectorMode == vtkAdaptiveVolumeMapper::MAGNITUDE && type != Stored::Double)
      {
        continue;
      }
      SetScalars(image, three, 3, type);
      const std::vector<float> of = rendered();
      SetScalars(image, *mode.Alone, 1, type);
      const std::vector<float> own = rendered();
      float difference = 0.0f, largest = 0.0f;
      for (std::size_t i = 0; i < of.size(); ++i)
      {
        difference = std::max(difference, std::abs(of[i] - own[i]));
        largest = std::max(largest, own[i]);
      }
      std::cout << mode.Name << ", " << NameOf(type) << ": " << difference
                << " from its own image (largest value " << largest << ")\n";
      if (!(difference <= 1e-6f) || largest < 0.2f)
      {
        std::cerr << "FAIL vector mode " << mode.Name << ", " << NameOf(type) << ": " << difference
                  << " apart\n";
        ++failures;
      }
    }
  }
  mapper->SetVectorMode(vtkAdaptiveVolumeMapper::DISABLED);

  // What is refused, never ignored.
  auto refused = [&](const char* what, const char* expected)
  {
    scene.Window->Render();
    failures += errors.Check(what, expected) ? 0 : 1;
  };
  SetScalars<vtkDoubleArray>(image, Random(4, 95.0, false, 9), 4);
  refused("4 dependent doubles", "4 dependent components (RGB and opacity) must be unsigned char");
  SetScalars<vtkDoubleArray>(image, three, 3);
  refused("3 dependent components", "dependent components must be 2");
  property->IndependentComponentsOn();
  SetScalars<vtkDoubleArray>(image, Random(5, 95.0, false, 9), 5);
  refused("5 components", "1 to 4 components are supported, not 5");
  SetScalars<vtkDoubleArray>(image, two, 2);
  property->ShadeOn();
  refused("shading", "Cannot shade scalars of 2 components");
  property->ShadeOff();
  mapper->SetBlendModeToMaximumIntensity();
  refused("maximum intensity", "rendered with the composite blend mode only");
  mapper->SetBlendModeToComposite();
  vtkNew<vtkPiecewiseFunction> gradient;
  gradient->AddPoint(0.0, 0.0);
  gradient->AddPoint(10.0, 1.0);
  property->SetGradientOpacity(1, gradient);
  refused("gradient opacity of the second component", "no gradient opacity");
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
