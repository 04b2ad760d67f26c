#include "avosBenchPlots.h"

#include "avosRenderSession.h"

#include "vtkAxis.h"
#include "vtkChartLegend.h"
#include "vtkChartMatrix.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkPlotPoints.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"
#include "vtkTextProperty.h"
#include "vtkVector.h"
#include "vtkWindowToImageFilter.h"

#include <vtksys/SystemTools.hxx>

#include <cmath>
#include <iostream>

namespace avos
{
namespace bench
{
namespace
{
// Distinguishable colours (Okabe-Ito), in order.
const unsigned char Palette[][3] = { { 0, 114, 178 }, { 213, 94, 0 }, { 0, 158, 115 },
  { 204, 121, 167 }, { 230, 159, 0 }, { 86, 180, 233 }, { 0, 0, 0 }, { 240, 228, 66 } };

void Fill(vtkChartXY* chart, const Chart& spec)
{
  chart->SetTitle(spec.Title);
  chart->GetTitleProperties()->SetFontSize(14);
  chart->SetShowLegend(true);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  chart->GetLegend()->GetLabelProperties()->SetFontSize(11);
  vtkAxis* x = chart->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* y = chart->GetAxis(vtkAxis::LEFT);
  x->SetTitle(spec.XTitle);
  y->SetTitle(spec.YTitle);
  x->SetLogScale(spec.LogX);
  y->SetLogScale(spec.LogY);
  std::size_t colour = 0;
  for (const Series& series : spec.Data)
  {
    vtkNew<vtkTable> table;
    vtkNew<vtkDoubleArray> xs, ys;
    xs->SetName("x");
    ys->SetName(series.Label.c_str());
    for (std::size_t i = 0; i < series.X.size() && i < series.Y.size(); ++i)
    {
      // A log axis cannot show zero or negative values.
      if (!std::isfinite(series.X[i]) || !std::isfinite(series.Y[i]) ||
        (spec.LogX && !(series.X[i] > 0.0)) || (spec.LogY && !(series.Y[i] > 0.0)))
      {
        continue;
      }
      xs->InsertNextValue(series.X[i]);
      ys->InsertNextValue(series.Y[i]);
    }
    if (xs->GetNumberOfValues() == 0)
    {
      continue;
    }
    table->AddColumn(xs);
    table->AddColumn(ys);
    vtkPlot* plot = chart->AddPlot(series.Points ? vtkChart::POINTS : vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    plot->SetLabel(series.Label);
    const unsigned char* c = Palette[colour++ % (sizeof(Palette) / sizeof(Palette[0]))];
    plot->SetColor(c[0], c[1], c[2], 255);
    plot->SetWidth(series.Points ? 1.0f : 1.5f);
    if (auto* points = vtkPlotPoints::SafeDownCast(plot))
    {
      points->SetMarkerStyle(vtkPlotPoints::CIRCLE);
      // Lines carry small markers so that sparse curves show their samples.
      points->SetMarkerSize(series.Points ? 7.0f : 3.0f);
    }
  }
}
} // namespace

bool WriteCharts(
  const std::string& path, const std::vector<Chart>& charts, int columns, int width, int height)
{
  if (charts.empty() || columns < 1)
  {
    std::cerr << "error: no chart to draw into '" << path << "'\n";
    return false;
  }
  vtkNew<vtkContextView> view;
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetMultiSamples(0);
  view->GetRenderWindow()->SetSize(width, height);
  const int rows = (static_cast<int>(charts.size()) + columns - 1) / columns;
  vtkNew<vtkChartMatrix> matrix;
  matrix->SetSize(vtkVector2i(columns, rows));
  // Room between the charts for the titles of the ones below, and at the
  // left for a rotated axis title beside wide tick labels (the automatic
  // layout leaves it outside the image).
  matrix->SetGutter(vtkVector2f(60.0f, 70.0f));
  matrix->SetBorders(90, 50, 20, 40);
  view->GetScene()->AddItem(matrix);
  for (std::size_t i = 0; i < charts.size(); ++i)
  {
    // The matrix counts rows from the bottom; the first chart goes top left.
    const int column = static_cast<int>(i) % columns;
    const int row = rows - 1 - static_cast<int>(i) / columns;
    Fill(vtkChartXY::SafeDownCast(matrix->GetChart(vtkVector2i(column, row))), charts[i]);
  }
  view->GetRenderWindow()->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(view->GetRenderWindow());
  grab->ReadFrontBufferOff();
  avos::app::AtomicFile file(path);
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(file.Path().c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (!vtksys::SystemTools::FileExists(file.Path()) || writer->GetErrorCode() != 0)
  {
    std::cerr << "error: cannot write '" << path << "'\n";
    return false;
  }
  return file.Commit();
}

} // namespace bench
} // namespace avos
