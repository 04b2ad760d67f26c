// Image regression of the modes beyond the plain composite integral, with one
// baseline: the analytic sphere-distance volume (a glowing shell around an
// opaque core) seen by four mappers: bottom left the exact minimum intensity
// projection (the core shows through), bottom right the composite integral shaded by the renderer's
// headlight (coupled), top left the additive projection (a thinner medium, so
// that it does not saturate), top right the
// composite integral cut by a clipping plane and cropped to a sub-volume
// (reference).
#include "vtkAnalyticVolumeSource.h"
#include "vtkPlane.h"

#include "MethodGrid.h"
#include "avosImageTest.h"

int TestAdaptiveVolumeMapperModes(int argc, char* argv[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  vtkNew<vtkVolumeProperty> property, shaded, thin;
  for (vtkVolumeProperty* p : { property.GetPointer(), shaded.GetPointer(), thin.GetPointer() })
  {
    methodgrid::MakeShell(source, p);
  }
  shaded->ShadeOn();
  thin->SetScalarOpacityUnitDistance(0.5);

  vtkNew<vtkRenderWindow> window;
  window->SetSize(300, 300);
  window->SetMultiSamples(0);
  methodgrid::Grid grid = methodgrid::Build(
    window, source->GetOutputPort(), property, vtkAdaptiveVolumeMapper::VTK_OPACITY, 30.0, 20.0);
  grid.Mappers[0]->SetBlendModeToMinimumIntensity();
  grid.Mappers[1]->SetIntegrationMethodToAdaptiveCoupled();
  grid.Volumes[1]->SetProperty(shaded);
  grid.Mappers[2]->SetBlendModeToAdditive();
  grid.Volumes[2]->SetProperty(thin);
  vtkNew<vtkPlane> plane;
  plane->SetOrigin(0.0, 0.0, 0.0);
  plane->SetNormal(1.0, 0.3, 0.2);
  grid.Mappers[3]->AddClippingPlane(plane);
  grid.Mappers[3]->SetCropping(1);
  grid.Mappers[3]->SetCroppingRegionPlanes(-0.8, 0.5, -0.6, 0.8, -0.9, 0.4);
  grid.Mappers[3]->SetCroppingRegionFlagsToSubVolume();
  return avostest::CompareWithBaseline(argc, argv, window);
}
