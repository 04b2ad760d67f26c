// Settings and inputs the GPU mapper does not honour are refused with an
// error naming them, and nothing is drawn; the same scene with valid
// settings draws the volume (so the checks can fail).
#include "vtkOpenGLAdaptiveVolumeMapper.h"

#include "avosTestHelpers.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkColorTransferFunction.h"
#include "vtkImageAppendComponents.h"
#include "vtkImageCast.h"
#include "vtkImageShiftScale.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlane.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTransform.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cmath>

#include <functional>

namespace
{
// Pixels of the window whose RGB `counts`.
int CountPixels(vtkRenderWindow* window, const std::function<bool(int, int, int)>& counts)
{
  vtkNew<vtkUnsignedCharArray> pixels;
  const int* size = window->GetSize();
  window->GetPixelData(0, 0, size[0] - 1, size[1] - 1, 0, pixels);
  int n = 0;
  for (vtkIdType i = 0; i < pixels->GetNumberOfTuples(); ++i)
  {
    n += counts(pixels->GetValue(3 * i), pixels->GetValue(3 * i + 1), pixels->GetValue(3 * i + 2));
  }
  return n;
}

// Pixels of the window with any colour.
int DrawnPixels(vtkRenderWindow* window)
{
  return CountPixels(window, [](int r, int g, int b) { return r + g + b > 0; });
}

// Pixels drawn pure magenta: the mapper's failed rays.
int MagentaPixels(vtkRenderWindow* window)
{
  return CountPixels(window, [](int r, int g, int b) { return r == 255 && g == 0 && b == 255; });
}
}

int TestOpenGLAdaptiveVolumeMapperRefusals(int, char*[])
{
  avostest::Checklist check;
  vtkNew<vtkAnalyticVolumeSource> source;
  source->SetFunctionToSphereDistance();
  source->SetDimensions(24, 24, 24);
  source->SetOutputScalarTypeToFloat();
  vtkNew<vtkColorTransferFunction> colour;
  colour->AddRGBPoint(0.0, 1.0, 0.8, 0.2);
  colour->AddRGBPoint(2.0, 0.2, 0.4, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 2.0);
  opacity->AddPoint(2.0, 0.0);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(colour);
  property->SetScalarOpacity(opacity);
  property->SetInterpolationTypeToLinear();

  vtkNew<vtkOpenGLAdaptiveVolumeMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->SetOpacityModelToExtinction();
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(64, 64);
  window->AddRenderer(renderer);
  renderer->ResetCamera();

  window->Render();
  const int valid = DrawnPixels(window);
  check(valid > 500, "a valid scene draws the volume (" + std::to_string(valid) + " pixels)");

  avostest::ExpectedErrors errors(mapper);
  auto refused = [&](const std::string& what, const std::string& message,
                   const std::function<void()>& set, const std::function<void()>& reset)
  {
    set();
    window->Render();
    check(errors.Check(what, message), what + " is refused");
    check(DrawnPixels(window) == 0, what + ": nothing is drawn");
    reset();
    window->Render();
    check(DrawnPixels(window) == valid, what + ": the valid scene draws again");
  };
  refused(
    "a zero tolerance", "tolerance", [&] { mapper->SetTolerance(0.0); },
    [&] { mapper->SetTolerance(0.01); });
  refused(
    "a tolerance above 1", "tolerance", [&] { mapper->SetTolerance(2.0); },
    [&] { mapper->SetTolerance(0.01); });
  refused(
    "a minimum step below 0.001", "step", [&] { mapper->SetMinimumStep(1e-4); },
    [&] { mapper->SetMinimumStep(0.1); });
  refused(
    "a Riemann step above 1000", "step", [&] { mapper->SetRiemannStep(2000.0); },
    [&] { mapper->SetRiemannStep(0.5); });
  refused(
    "a piecewise tolerance below 1e-5", "from 1e-5 to 1",
    [&]
    {
      mapper->SetIntegrationMethodToPiecewiseAdaptive();
      mapper->SetTolerance(1e-6);
    },
    [&]
    {
      mapper->SetIntegrationMethodToAdaptiveCoupled();
      mapper->SetTolerance(0.01);
    });
  refused(
    "a piecewise tolerance below 1e-4 in float", "from 1e-4 to 1",
    [&]
    {
      mapper->SetIntegrationMethodToPiecewiseAdaptive();
      mapper->UseDoublePrecisionOff();
      mapper->SetTolerance(5e-5);
    },
    [&]
    {
      mapper->SetIntegrationMethodToAdaptiveCoupled();
      mapper->UseDoublePrecisionOn();
      mapper->SetTolerance(0.01);
    });
  refused(
    "the average projection in float", "need double precision",
    [&]
    {
      mapper->SetBlendModeToAverageIntensity();
      mapper->UseDoublePrecisionOff();
    },
    [&]
    {
      mapper->SetBlendModeToComposite();
      mapper->UseDoublePrecisionOn();
    });
  refused(
    "partitions", "partitions", [&] { mapper->SetPartitions(2, 1, 1); },
    [&] { mapper->SetPartitions(1, 1, 1); });
  refused(
    "minimum above maximum step", "minimum step exceeds", [&] { mapper->SetMinimumStep(3.0); },
    [&] { mapper->SetMinimumStep(0.1); });
  refused(
    "the isosurface blend", "composite", [&] { mapper->SetBlendModeToIsoSurface(); },
    [&] { mapper->SetBlendModeToComposite(); });
  refused(
    "an average range that is not finite", "average intensity range",
    [&]
    {
      mapper->SetBlendModeToAverageIntensity();
      mapper->SetAverageIPScalarRange(std::nan(""), 1.0);
    },
    [&]
    {
      mapper->SetBlendModeToComposite();
      mapper->SetAverageIPScalarRange(VTK_FLOAT_MIN, VTK_FLOAT_MAX);
    });
  refused(
    "an additive tolerance below 1e-5", "from 1e-5 to 1",
    [&]
    {
      mapper->SetBlendModeToAdditive();
      mapper->SetTolerance(1e-6);
    },
    [&]
    {
      mapper->SetBlendModeToComposite();
      mapper->SetTolerance(0.01);
    });
  refused(
    "a cropping plane that is not finite", "cropping region planes",
    [&]
    {
      mapper->CroppingOn();
      mapper->SetCroppingRegionPlanes(std::nan(""), 0.5, -1.0, 1.0, -1.0, 1.0);
    },
    [&] { mapper->CroppingOff(); });
  refused(
    "jittering", "UseJittering", [&] { mapper->UseJitteringOn(); },
    [&] { mapper->UseJitteringOff(); });
  refused(
    "the depth pass", "UseDepthPass", [&] { mapper->UseDepthPassOn(); },
    [&] { mapper->UseDepthPassOff(); });
  refused(
    "the native colour range", "SCALAR",
    [&] { mapper->SetColorRangeType(vtkGPUVolumeRayCastMapper::NATIVE); },
    [&] { mapper->SetColorRangeType(vtkGPUVolumeRayCastMapper::SCALAR); });
  refused(
    "a second input (vtkMultiVolume)", "inputs beyond the first",
    [&] { mapper->SetInputConnection(1, source->GetOutputPort()); },
    [&] { mapper->RemoveInputConnection(1, source->GetOutputPort()); });
  vtkNew<vtkPlane> plane;
  refused(
    "seven clipping planes", "at most 6 clipping planes",
    [&]
    {
      for (int i = 0; i < 7; ++i)
      {
        mapper->AddClippingPlane(plane);
      }
    },
    [&] { mapper->RemoveAllClippingPlanes(); });
  vtkNew<vtkTransform> shift;
  vtkNew<vtkPlane> transformed;
  transformed->SetTransform(shift);
  refused(
    "a clipping plane with a transform", "with a transform",
    [&] { mapper->AddClippingPlane(transformed); }, [&] { mapper->RemoveAllClippingPlanes(); });
  refused(
    "shading in the piecewise method", "does not shade",
    [&]
    {
      property->ShadeOn();
      mapper->SetIntegrationMethodToPiecewiseAdaptive();
    },
    [&]
    {
      property->ShadeOff();
      mapper->SetIntegrationMethodToAdaptiveCoupled();
    });
  vtkNew<vtkPiecewiseFunction> gradientOpacity;
  gradientOpacity->AddPoint(0.0, 0.2);
  gradientOpacity->AddPoint(1.0, 1.0);
  refused(
    "gradient opacity in the piecewise method",
    "Gradient opacity is supported by the GPU's sampled",
    [&]
    {
      property->SetGradientOpacity(gradientOpacity);
      mapper->SetIntegrationMethodToPiecewiseAdaptive();
    },
    [&]
    {
      property->DisableGradientOpacityOn();
      mapper->SetIntegrationMethodToAdaptiveCoupled();
    });
  refused(
    "shading a projection", "composite blend mode only",
    [&]
    {
      property->ShadeOn();
      mapper->SetBlendModeToMaximumIntensity();
    },
    [&]
    {
      property->ShadeOff();
      mapper->SetBlendModeToComposite();
    });
  refused(
    "shading nearest interpolation", "linear interpolation are shaded",
    [&]
    {
      property->ShadeOn();
      property->SetInterpolationTypeToNearest();
    },
    [&]
    {
      property->ShadeOff();
      property->SetInterpolationTypeToLinear();
    });
  refused(
    "an image quantity without a float depth image", "float depth image",
    [&] { mapper->SetImageQuantity(vtkOpenGLAdaptiveVolumeMapper::ALPHA); },
    [&] { mapper->SetImageQuantity(vtkOpenGLAdaptiveVolumeMapper::DEPTH); });
  refused(
    "depth peeling of volumes", "depth peeling",
    [&]
    {
      renderer->UseDepthPeelingOn();
      renderer->UseDepthPeelingForVolumesOn();
    },
    [&] { renderer->UseDepthPeelingOff(); });
  vtkNew<vtkImageShiftScale> toShortMinimum; // [0, 1] -> [-40000, 0], clamped at -32768
  toShortMinimum->SetInputConnection(source->GetOutputPort());
  toShortMinimum->SetScale(-40000.0);
  toShortMinimum->ClampOverflowOn();
  toShortMinimum->SetOutputScalarTypeToShort();
  refused(
    "short scalars reaching -32768", "reach -32768",
    [&] { mapper->SetInputConnection(toShortMinimum->GetOutputPort()); },
    [&] { mapper->SetInputConnection(source->GetOutputPort()); });
  vtkNew<vtkImageAppendComponents> twoComponents;
  twoComponents->AddInputConnection(source->GetOutputPort());
  twoComponents->AddInputConnection(source->GetOutputPort());
  // Two components that both show (the same functions on both) in the
  // piecewise method; the sampled methods render them, and every method a
  // second component of opacity 0 (TestOpenGLAdaptiveVolumeMapperPython).
  refused(
    "two visible components, piecewise", "in this mixture several show",
    [&]
    {
      mapper->SetInputConnection(twoComponents->GetOutputPort());
      mapper->SetIntegrationMethodToPiecewiseAdaptive();
    },
    [&]
    {
      mapper->SetInputConnection(source->GetOutputPort());
      mapper->SetIntegrationMethodToAdaptiveCoupled();
    });
  vtkNew<vtkImageShiftScale> toDouble;
  toDouble->SetInputConnection(source->GetOutputPort());
  toDouble->SetOutputScalarTypeToDouble();
  vtkNew<vtkImageAppendComponents> twoDoubles;
  twoDoubles->AddInputConnection(toDouble->GetOutputPort());
  twoDoubles->AddInputConnection(toDouble->GetOutputPort());
  refused(
    "two double components", "uploads them to an 8-bit texture",
    [&] { mapper->SetInputConnection(twoDoubles->GetOutputPort()); },
    [&] { mapper->SetInputConnection(source->GetOutputPort()); });
  vtkNew<vtkImageAppendComponents> fiveComponents;
  for (int k = 0; k < 5; ++k)
  {
    fiveComponents->AddInputConnection(source->GetOutputPort());
  }
  // (VTK's own check, before the frame reaches ours.)
  refused(
    "five components", "Only 1 - 4 component scalars are supported",
    [&] { mapper->SetInputConnection(fiveComponents->GetOutputPort()); },
    [&] { mapper->SetInputConnection(source->GetOutputPort()); });
  vtkNew<vtkPiecewiseFunction> empty;
  refused(
    "an empty opacity function", "opacity", [&] { property->SetScalarOpacity(empty); },
    [&] { property->SetScalarOpacity(opacity); });

  // A new transfer function is converted again and the empty-space blocks
  // follow it: blocks built for one that hides all but the centre (skipping
  // switched off and on uploads them anew) must not hide the outer shell once
  // the first function is back.
  vtkNew<vtkPiecewiseFunction> centre;
  centre->AddPoint(0.0, 2.0);
  centre->AddPoint(0.3, 0.0);
  centre->AddPoint(2.0, 0.0);
  property->SetScalarOpacity(centre);
  mapper->EmptySpaceSkippingOff();
  window->Render();
  mapper->EmptySpaceSkippingOn();
  window->Render();
  const int small = DrawnPixels(window);
  check(small > 0 && small < valid / 2,
    "a centre-only transfer function draws less (" + std::to_string(small) + " pixels)");
  property->SetScalarOpacity(opacity);
  window->Render();
  check(
    DrawnPixels(window) == valid, "the first transfer function draws its whole footprint again");

  // Partitions set where the check cannot see them (through the
  // superclass, whose SetPartitions is not virtual): VTK renders the blocks
  // one by one, and the shader, finding a texture that does not hold the
  // whole volume, draws every ray as failed (magenta), never from a block.
  // (VTK splits the texture when it loads it anew: the input changed.)
  static_cast<vtkOpenGLGPUVolumeRayCastMapper*>(mapper.Get())->SetPartitions(2, 1, 1);
  source->Modified();
  window->Render();
  check(MagentaPixels(window) > 0 && MagentaPixels(window) == DrawnPixels(window),
    "partitions through the superclass draw failed rays only (" +
      std::to_string(MagentaPixels(window)) + " magenta of " + std::to_string(DrawnPixels(window)) +
      " pixels)");
  mapper->SetPartitions(1, 1, 1);
  source->Modified();
  window->Render();
  check(DrawnPixels(window) == valid && MagentaPixels(window) == 0,
    "one partition draws the volume again");
  return check.Result();
}
