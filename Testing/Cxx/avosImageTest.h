// The ending shared by the image regression tests: compare the window with
// the test's baseline (VTK's default threshold; every image here is
// deterministic: pixels are computed independently, whatever the threads),
// or hand over to an interactor when the test runs interactively (-I).
#ifndef avosImageTest_h
#define avosImageTest_h

#include "vtkNew.h"
#include "vtkRegressionTestImage.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"

#include <cstdlib>

namespace avostest
{
inline int CompareWithBaseline(int argc, char* argv[], vtkRenderWindow* window)
{
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(window);
  window->Render();
  const int result = vtkRegressionTestImage(window);
  if (result == vtkRegressionTester::DO_INTERACTOR)
  {
    interactor->Start();
  }
  return result == vtkRegressionTester::FAILED ? EXIT_FAILURE : EXIT_SUCCESS;
}
}

#endif
