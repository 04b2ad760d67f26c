// Progress and abort while a frame is cast. A frame of about 10^9 samples
// (Riemann at the smallest step, the 33^3 ramp of the closed-form tests, an
// almost transparent medium, so no ray terminates early) reports its progress
// from the thread that rendered it, in [0, 1) and never decreasing; an abort
// requested at the first report (vtkRenderWindow::SetAbortRender, as an
// interactor's abort check does) ends the frame with no image and no error
// after a share of its tiles. A frame that is not aborted reports 1 last.
// No time is asserted: a mapper that ignored the abort would run the frame to
// its end (minutes) and fail the share check, or the test's time limit.
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkCallbackCommand.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "ObliqueScene.h"
#include "avosTestHelpers.h"

#include <chrono>
#include <iostream>
#include <thread>
#include <vector>

namespace
{
// scalar, r, g, b, opacity: a faint medium everywhere.
const double Knots[][5] = { { 0, 0.2, 0.4, 0.9, 1e-4 }, { 100, 0.9, 0.6, 0.1, 2e-4 } };

struct Recorder
{
  std::vector<double> Fractions;
  bool OtherThread = false;
  bool AbortAtFirst = false;
  std::thread::id Owner = std::this_thread::get_id();
  vtkRenderWindow* Window = nullptr;
};

void OnProgress(vtkObject*, unsigned long, void* clientData, void* callData)
{
  auto* recorder = static_cast<Recorder*>(clientData);
  const double fraction = *static_cast<double*>(callData);
  recorder->OtherThread |= std::this_thread::get_id() != recorder->Owner;
  recorder->Fractions.push_back(fraction);
  if (recorder->AbortAtFirst && fraction > 0.0 && fraction < 1.0)
  {
    recorder->Window->SetAbortRender(1);
  }
}
} // namespace

int TestAdaptiveVolumeMapperAbort(int, char*[])
{
  avostest::Checklist check;
  vtkNew<vtkAnalyticVolumeSource> source;
  obliquescene::MakeRamp(source, 50.0, 40.0);
  vtkNew<vtkVolumeProperty> property;
  obliquescene::FillProperty(Knots, property);
  obliquescene::Scene scene(source, property, 160);
  vtkAdaptiveVolumeMapper* mapper = scene.Mapper;
  mapper->SetIntegrationMethodToRiemann();
  mapper->SetSampleDistance(vtkAdaptiveVolumeMapper::GetSmallestStep());
  // The pipeline's own update (progress 0 and 1) before the observer: only
  // the frame's reports are recorded.
  mapper->Update();
  avostest::ExpectedErrors errors(mapper);

  Recorder recorder;
  recorder.Window = scene.Window;
  recorder.AbortAtFirst = true;
  vtkNew<vtkCallbackCommand> progress;
  progress->SetCallback(OnProgress);
  progress->SetClientData(&recorder);
  mapper->AddObserver(vtkCommand::ProgressEvent, progress);

  const auto start = std::chrono::steady_clock::now();
  scene.Window->Render();
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "aborted frame: " << seconds << " s, progress reports:";
  for (double f : recorder.Fractions)
  {
    std::cout << " " << f;
  }
  std::cout << "\n";
  check(errors.None("an aborted frame"), "an abort is not an error");
  check(mapper->GetRenderedImage()->GetNumberOfPoints() == 0, "an aborted frame has no image");
  double cast = -1.0;
  bool ordered = true;
  for (std::size_t i = 0; i < recorder.Fractions.size(); ++i)
  {
    const double f = recorder.Fractions[i];
    ordered &= f >= 0.0 && f < 1.0 && (i == 0 || f >= recorder.Fractions[i - 1]);
    if (f > 0.0 && cast < 0.0)
    {
      cast = f;
    }
  }
  check(ordered, "progress in [0, 1), never decreasing, and no final 1 when aborted");
  // The abort came at the first report: the tiles cast after it are at most
  // one per thread, a small share of the frame.
  check(cast > 0.0 && recorder.Fractions.back() < 0.5, "the frame stopped early");
  check(!recorder.OtherThread, "progress comes from the rendering thread");

  // The next frame, not aborted and cheap, is whole and reports 1 last.
  recorder.Fractions.clear();
  recorder.AbortAtFirst = false;
  mapper->SetSampleDistance(0.5);
  scene.Window->Render();
  check(errors.None("a whole frame"), "a whole frame after an aborted one");
  check(mapper->GetRenderedImage()->GetNumberOfPoints() == 160 * 160, "its image");
  check(!recorder.Fractions.empty() && recorder.Fractions.back() == 1.0, "its last report is 1");
  return check.Result();
}
