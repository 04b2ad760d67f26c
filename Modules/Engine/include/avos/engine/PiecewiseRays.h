// The piecewise method with a ray per SIMD lane (VTK-free).
//
// numerics::IntegratePiecewise takes one ray at a time: its cells, knot
// crossings, depths and series run in lanes a batch at a time, but the glue
// between them (the cell walk, cutting a cell into pieces, the in-order
// compositing) is scalar and took about twice the kernels' time.
// CastPiecewiseRays runs many rays at once instead, a ray per double lane
// (8 with AVX-512), each lane refilled with the next ray when its own ends:
// - the walk: each lane's ray walked a batch of cells at a time
//   (numerics::CellWalker), the batch classified and its cubics built in
//   lanes (a cell per lane: one ray's cells, whose corners share cache
//   lines), its visible cells taken in order;
// - the cut: a cell without a knot inside its corner range is one piece; a
//   cell with knots is cut stretch by stretch (numerics::detail::Stretch),
//   one sub-piece per lane and iteration, the knot crossings found by
//   Newton's method in lanes, each lane on its own cubic; the cut's
//   decisions (which knot, which piece) are each lane's own, scalar;
// - each lane's piece integrated in lanes: its depth polynomial and
//   transmittance, the compositing, the midpoint bound or the series for the
//   colour integral J (SeriesIntegral's sub-intervals, where its first one
//   does not settle J, scalar for that lane), and early termination.
// Measured (docs/PERFORMANCE.md) within a few per cent of one ray at a time
// on the four datasets: what the lanes take over costs about what they
// save while the cut's decisions stay scalar (on Foot at eps 0.01 about
// half the time, the walk a quarter, crossings and integration the rest).
// The decisions in lanes too were slower (up to +23 %): each is a chain of
// table reads, cheap as scalar loads and dear as gathers in part-full
// vectors.
// Each lane takes IntegratePiecewise's pieces in its order (the same cells,
// stretches, crossings and transfer-function pieces, from the same scalar
// arithmetic: no fused multiply-adds there) and integrates them with the
// formulas of its engine kernels (avos/engine/PieceKernels.h). Bound against
// numerics::IntegratePiecewise with engine::PieceKernels, per channel: its
// colour terms are added in another order (a piece's J right after the
// piece, not after its batch), relative 1e-13; a rounding that tips a
// decision (a series term more or less) stays within that piece's share of
// the tolerance, as between the engine's kernels and the scalar ones.
// Modules/Engine/Testing checks it on every dispatch target.
#ifndef avos_engine_PiecewiseRays_h
#define avos_engine_PiecewiseRays_h

#include "avos/engine/PieceKernels.h" // TakesTables
#include "avos/engine/Riemann.h"      // Volume, RiemannRay
#include "avos/numerics/PiecewiseIntegrator.h"

#include <cstddef>
#include <string>
#include <vector>

namespace avos
{
namespace engine
{

// The pieces of a numerics::PiecewiseTransferFunction as the lanes gather
// them, a column per coefficient indexed by piece: tau's four, the colour's
// three (Colour + c), its slope's three and the slope's largest magnitude.
struct PiecewiseTable
{
  // From a built transfer function; empty on success, else why.
  std::string Build(const numerics::PiecewiseTransferFunction<double>& tf);

  enum Column
  {
    Tau,
    TauSlope,
    TauCurvature,
    TauCubic,
    Colour,
    ColourSlope = Colour + 3,
    ColourSlopeMaximum = ColourSlope + 3,
    ColumnCount
  };
  std::vector<double> Columns[ColumnCount];
};

struct PiecewiseOutput
{
  double RGBA[4] = { 0.0, 0.0, 0.0, 0.0 };
  long Cells = 0;    // visible cells
  long Pieces = 0;   // pieces integrated (one sample each: its end)
  long Rejected = 0; // halved series sub-intervals
  std::string Error; // numerics::RayResult::Error: empty when none
};

// Empty when CastPiecewiseRays can cast `volume` with `tf` (8- or 16-bit
// scalars, the transfer function's unit tables, the volume's dimensions
// within int), else why.
std::string ValidatePiecewiseRays(
  const Volume& volume, const numerics::PiecewiseTransferFunction<double>& tf);

// out[i] = numerics::IntegratePiecewise's result for rays[i] (its origin,
// direction and segments; D is not read) with early termination, within the
// bound above, i in [0, count). `table` is built from `tf`; `tolerance` as
// IntegratePiecewise's (checked: a ray gets its error otherwise).
void CastPiecewiseRays(const Volume& volume, const numerics::PiecewiseTransferFunction<double>& tf,
  const PiecewiseTable& table, double tolerance, const RiemannRay* rays, std::size_t count,
  PiecewiseOutput* out);

} // namespace engine
} // namespace avos

#endif
