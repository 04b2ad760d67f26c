// Image regression: a superquadric torus isosurface (vtkFlyingEdges3D) beside
// the same surface decimated by 90 % with vtkOpenMeshDecimation, flat shaded
// with edges, so that any change of the kept vertices or triangles shows.
#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkFlyingEdges3D.h"
#include "vtkNew.h"
#include "vtkOpenMeshDecimation.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSampleFunction.h"
#include "vtkSuperquadric.h"

#include "avosImageTest.h"

int TestOpenMeshDecimationRendering(int argc, char* argv[])
{
  vtkNew<vtkSuperquadric> torus;
  torus->ToroidalOn();
  torus->SetThickness(0.4);
  torus->SetPhiRoundness(0.6);
  torus->SetThetaRoundness(1.0);
  vtkNew<vtkSampleFunction> volume;
  volume->SetImplicitFunction(torus);
  volume->SetSampleDimensions(64, 64, 40);
  volume->SetModelBounds(-1.7, 1.7, -1.7, 1.7, -0.8, 0.8);
  volume->ComputeNormalsOff();
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputConnection(volume->GetOutputPort());
  contour->SetValue(0, 0.0);
  contour->ComputeNormalsOn();
  vtkNew<vtkOpenMeshDecimation> decimate;
  decimate->SetInputConnection(contour->GetOutputPort());
  decimate->SetTargetReduction(0.9);

  vtkNew<vtkRenderWindow> window;
  window->SetSize(400, 200);
  window->SetMultiSamples(0);
  vtkAlgorithm* stages[2] = { contour, decimate };
  for (int i = 0; i < 2; ++i)
  {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(stages[i]->GetOutputPort());
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetInterpolationToFlat();
    actor->GetProperty()->EdgeVisibilityOn();
    actor->GetProperty()->SetEdgeColor(0.1, 0.1, 0.2);
    actor->GetProperty()->SetColor(0.9, 0.75, 0.5);
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(0.5 * i, 0.0, 0.5 * i + 0.5, 1.0);
    renderer->SetBackground(1.0, 1.0, 1.0);
    renderer->AddActor(actor);
    window->AddRenderer(renderer);
    renderer->ResetCamera();
    renderer->GetActiveCamera()->Elevation(50.0);
    renderer->GetActiveCamera()->Zoom(1.4);
  }
  return avostest::CompareWithBaseline(argc, argv, window);
}
