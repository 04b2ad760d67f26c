// The closed-form tests' scene: a volume on [-1, 1]^3 rendered by a
// vtkAdaptiveVolumeMapper in one window, seen
// through an orthographic camera turned 30 degrees in azimuth and 35 in
// elevation (no ray along an axis), and each pixel's ray rebuilt from the
// renderer independently of the mapper, clipped to the box; the ramp volume
// and the piecewise-linear transfer functions they render.
#ifndef ObliqueScene_h
#define ObliqueScene_h

#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTrivialProducer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "avos/numerics/TransferFunction.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>

namespace obliquescene
{
struct Scene
{
  vtkNew<vtkAdaptiveVolumeMapper> Mapper;
  vtkNew<vtkVolume> Volume;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;

  // `source`'s volume rendered by Mapper with `property`, in a size x size window.
  Scene(vtkAlgorithm* source, vtkVolumeProperty* property, int size)
  {
    this->Mapper->SetInputConnection(source->GetOutputPort());
    this->Volume->SetMapper(this->Mapper);
    this->Volume->SetProperty(property);
    this->Renderer->AddVolume(this->Volume);
    this->Window->SetOffScreenRendering(1);
    this->Window->SetSize(size, size);
    this->Window->AddRenderer(this->Renderer);
    vtkCamera* camera = this->Renderer->GetActiveCamera();
    camera->ParallelProjectionOn();
    this->Renderer->ResetCamera();
    camera->Azimuth(30.0);
    camera->Elevation(35.0);
    camera->OrthogonalizeViewUp();
    this->Renderer->ResetCameraClippingRange();
  }
};

// An image of points^3 grid points on [-1, 1]^3, without scalars (the test
// sets them), behind a producer for Scene.
struct Cube
{
  vtkNew<vtkImageData> Image;
  vtkNew<vtkTrivialProducer> Producer;

  explicit Cube(int points)
  {
    const double voxel = 2.0 / (points - 1);
    this->Image->SetDimensions(points, points, points);
    this->Image->SetOrigin(-1.0, -1.0, -1.0);
    this->Image->SetSpacing(voxel, voxel, voxel);
    this->Producer->SetOutput(this->Image);
  }
};

// The ray through pixel (x, y)'s centre, Start + t Direction (world units),
// inside [-1, 1]^3 for t in [T0, T1]; T0 >= T1 when it misses the box.
struct PixelRay
{
  glm::dvec3 Start, Direction;
  double T0 = 0.0, T1 = 0.0;
};

inline PixelRay RayOf(vtkRenderer* renderer, int x, int y)
{
  PixelRay ray;
  renderer->SetDisplayPoint(x + 0.5, y + 0.5, 0.0);
  renderer->DisplayToWorld();
  const double* w = renderer->GetWorldPoint();
  ray.Start = glm::dvec3(w[0] / w[3], w[1] / w[3], w[2] / w[3]);
  double dop[3];
  renderer->GetActiveCamera()->GetDirectionOfProjection(dop);
  ray.Direction = glm::dvec3(dop[0], dop[1], dop[2]);
  ray.T1 = 1e30;
  for (int a = 0; a < 3; ++a)
  {
    double ta = (-1.0 - ray.Start[a]) / ray.Direction[a];
    double tb = (1.0 - ray.Start[a]) / ray.Direction[a];
    if (ta > tb)
    {
      std::swap(ta, tb);
    }
    ray.T0 = std::max(ray.T0, ta);
    ray.T1 = std::min(ray.T1, tb);
  }
  return ray;
}
// The ramp s = shift + scale z on [-1, 1]^3, 33^3 double points (one voxel
// unit = 1/16: trilinear interpolation reproduces it exactly).
inline void MakeRamp(vtkAnalyticVolumeSource* source, double shift, double scale)
{
  source->SetFunctionToLinearRamp();
  source->SetRampAxis(2);
  source->SetDimensions(33, 33, 33);
  source->SetScalarShift(shift);
  source->SetScalarScale(scale);
  source->SetOutputScalarTypeToDouble();
}

// Knots (scalar, r, g, b, opacity) as the property's piecewise-linear
// colour and opacity, and as the numerical core's transfer function when
// `tf` is given (the oracles evaluate that one).
template <std::size_t N>
void FillProperty(const double (&knots)[N][5], vtkVolumeProperty* property,
  avos::numerics::TransferFunction<double>* tf = nullptr)
{
  vtkNew<vtkColorTransferFunction> color;
  vtkNew<vtkPiecewiseFunction> opacity;
  for (const auto& k : knots)
  {
    color->AddRGBPoint(k[0], k[1], k[2], k[3]);
    opacity->AddPoint(k[0], k[4]);
    if (tf)
    {
      tf->AddColorKnot(k[0], k[1], k[2], k[3]);
      tf->AddOpacityKnot(k[0], k[4]);
    }
  }
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetInterpolationTypeToLinear();
}
} // namespace obliquescene

#endif
