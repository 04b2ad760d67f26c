// Line and point charts written to PNG with VTK's own charts (no plotting
// dependency beyond VTK): what avos-bench draws.
#ifndef avosBenchPlots_h
#define avosBenchPlots_h

#include <string>
#include <vector>

namespace avos
{
namespace bench
{

struct Series
{
  std::string Label;
  std::vector<double> X;
  std::vector<double> Y;
  bool Points = false; // markers only, no line
};

struct Chart
{
  std::string Title;
  std::string XTitle;
  std::string YTitle;
  bool LogX = false;
  bool LogY = false;
  std::vector<Series> Data;
};

/// Draws the charts in a grid of `columns` columns into a width x height PNG.
/// False, with a message on stderr, when it cannot be written.
bool WriteCharts(
  const std::string& path, const std::vector<Chart>& charts, int columns, int width, int height);

} // namespace bench
} // namespace avos

#endif
