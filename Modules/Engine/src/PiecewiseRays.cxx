// The piecewise method with a ray per lane (avos/engine/PiecewiseRays.h) for
// every Highway target (foreach_target re-includes this file once per
// target), the dispatching entry point and the piece table (once, under
// HWY_ONCE). Compiled without fused multiply-adds (CMakeLists.txt): the
// walk, the cells and the cut repeat the scalar code's arithmetic to the
// bit; the piece stages use the engine kernels' explicit ones.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/PiecewiseRays.cxx"
#include "hwy/foreach_target.h" // IWYU pragma: keep

#include "hwy/highway.h"

#include "avos/engine/PiecewiseRays.h"
#include "src/CellLanes-inl.h"
#include "src/PieceLanes-inl.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace avos
{
namespace engine
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;
namespace an = numerics;

constexpr int MaximumLanes = HWY_MAX_BYTES / sizeof(double);

// The lanes' state, structures of arrays: lane i runs ray Ray[i]. What
// the vector stages load and store is aligned; the rest is each lane's own,
// read and written a lane at a time.
struct Lanes
{
  // The ray, and its segment being walked.
  bool Active[MaximumLanes];
  std::size_t Ray[MaximumLanes], Segment[MaximumLanes];
  double Origin[3][MaximumLanes], Direction[3][MaximumLanes];
  // The walk over the segment.
  an::CellWalker<double> Walker[MaximumLanes];
  // The walk's cells ahead, a batch of one ray's cells classified at once
  // (ClassifyCells, a cell per lane; their corners in neighbouring cache
  // lines), and the next one to take.
  an::CellBatch<double> Batch[MaximumLanes];
  int Taken[MaximumLanes];
  // The cell: Cell 0 none, 1 taken (visible), 2 being cut.
  int Cell[MaximumLanes], First[MaximumLanes], Crossings[MaximumLanes];
  alignas(64) double K[4][MaximumLanes];
  double Length[MaximumLanes];
  // The cut of a cell with crossings: its stretches' bounds, the stretch,
  // the next useful sub-piece J and where it starts (U).
  double Bounds[MaximumLanes][4];
  int BoundCount[MaximumLanes], StretchIndex[MaximumLanes];
  an::detail::Stretch<double> Stretch[MaximumLanes];
  std::size_t J[MaximumLanes];
  double U[MaximumLanes];
  // A crossing to find (Seek 1): knot Value on [Lo, Hi]; Root out.
  alignas(64) double Seek[MaximumLanes];
  alignas(64) double Value[MaximumLanes];
  alignas(64) double Lo[MaximumLanes];
  alignas(64) double Hi[MaximumLanes];
  alignas(64) double Root[MaximumLanes];
  // The piece to integrate (Emit 1): q (offset by its piece's start), its
  // length, transfer-function piece, and 1 where s is known monotone.
  alignas(64) double Emit[MaximumLanes];
  alignas(64) double Q[4][MaximumLanes];
  alignas(64) double PieceLength[MaximumLanes];
  alignas(64) std::int64_t Piece[MaximumLanes];
  alignas(64) double Monotone[MaximumLanes];
  // The integral so far, 1 / the ray's visible length, and what a lane's
  // series left to SeriesIntegral needs (its share's scale, transmittances).
  alignas(64) double Transmittance[MaximumLanes];
  alignas(64) double Colour[3][MaximumLanes];
  alignas(64) double InverseLength[MaximumLanes];
  alignas(64) double Open[MaximumLanes];
  alignas(64) double Scale[MaximumLanes];
  alignas(64) double Front[MaximumLanes];
  alignas(64) double PieceTransmittance[MaximumLanes];
  PiecewiseOutput Out[MaximumLanes];
};

template <Volume::Type Scalars>
void CastRays(const Volume& volume, const an::PiecewiseTransferFunction<double>& tf,
  const PiecewiseTable& table, double tolerance, const RiemannRay* rays, std::size_t count,
  PiecewiseOutput* out)
{
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> d64;
  using V = hn::Vec<decltype(d)>;
  const int N = static_cast<int>(hn::Lanes(d));
  const auto tables = tf.GetUnitTables();
  const std::vector<double>& knots = tf.GetKnots();
  const double budget = 0.6 * tolerance;
  const double terminationBound = 0.15 * tolerance / std::max(1.0, tf.GetMaximumColor());

  Lanes s{};
  std::size_t next = 0; // the next ray to take

  // Ray r's result when nothing of it is integrated.
  auto empty = [&](std::size_t r, std::string error)
  {
    out[r] = PiecewiseOutput();
    out[r].Error = std::move(error);
  };
  // Lane i takes the next ray with something to integrate; inactive when
  // none is left.
  auto take = [&](int i)
  {
    s.Active[i] = false;
    while (next < count)
    {
      const std::size_t r = next++;
      const RiemannRay& ray = rays[r];
      double L;
      std::string error =
        an::detail::ValidatePiecewiseRay(glm::dvec3(ray.Origin[0], ray.Origin[1], ray.Origin[2]),
          glm::dvec3(ray.Direction[0], ray.Direction[1], ray.Direction[2]), ray.Segments, ray.Count,
          L);
      if (!error.empty() || !(L > 0.0))
      {
        empty(r, std::move(error));
        continue;
      }
      s.Active[i] = true;
      s.Ray[i] = r;
      s.Segment[i] = static_cast<std::size_t>(-1);
      for (int a = 0; a < 3; ++a)
      {
        s.Origin[a][i] = ray.Origin[a];
        s.Direction[a][i] = ray.Direction[a];
        s.Colour[a][i] = 0.0;
      }
      s.Transmittance[i] = 1.0;
      s.InverseLength[i] = 1.0 / L;
      s.Walker[i] = an::CellWalker<double>();
      s.Cell[i] = 0;
      s.Batch[i].Count = 0;
      s.Taken[i] = 0;
      s.Out[i] = PiecewiseOutput();
      return;
    }
  };
  // IntegratePiecewise's result from lane i's state; the lane is free.
  auto finish = [&](int i)
  {
    PiecewiseOutput& o = s.Out[i];
    if (o.Error.empty())
    {
      an::RayResult<double> result;
      an::detail::PiecewiseRGBA(
        glm::dvec3(s.Colour[0][i], s.Colour[1][i], s.Colour[2][i]), s.Transmittance[i], result);
      std::copy_n(&result.RGBA.x, 4, o.RGBA);
      o.Error = std::move(result.Error);
    }
    out[s.Ray[i]] = std::move(o);
    s.Active[i] = false;
  };
  // Up to a batch of lane i's next cells, classified with their cubics
  // (ClassifiedCell, a cell per lane); how many (0: the walk is spent).
  auto walk = [&](int i)
  {
    an::CellBatch<double>& b = s.Batch[i];
    b.Count = 0;
    s.Taken[i] = 0;
    s.Walker[i].Fill(b, an::CellBatch<double>::Capacity);
    const double origin[3] = { s.Origin[0][i], s.Origin[1][i], s.Origin[2][i] };
    const double direction[3] = { s.Direction[0][i], s.Direction[1][i], s.Direction[2][i] };
    ClassifyCells<Scalars>(volume, tables, origin, direction, b);
    return b.Count;
  };
  // Lane i's next visible cell (Cell 1): from its batch, else its walk's
  // next batch, else its ray's next segment; else its ray is done and the
  // lane takes the next one (inactive when none is left).
  auto nextCell = [&](int i)
  {
    while (s.Active[i])
    {
      an::CellBatch<double>& b = s.Batch[i];
      while (s.Taken[i] < b.Count)
      {
        const int c = s.Taken[i]++;
        if (b.Visible[c] != 0)
        {
          for (int k = 0; k < 4; ++k)
          {
            s.K[k][i] = b.K[k][c];
          }
          s.Length[i] = b.End[c] - b.Begin[c];
          s.First[i] = b.First[c];
          s.Crossings[i] = b.Crossings[c];
          s.Cell[i] = 1;
          return;
        }
      }
      if (walk(i) > 0)
      {
        continue;
      }
      const RiemannRay& ray = rays[s.Ray[i]];
      if (++s.Segment[i] < ray.Count)
      {
        const glm::dvec3 origin(s.Origin[0][i], s.Origin[1][i], s.Origin[2][i]);
        const glm::dvec3 direction(s.Direction[0][i], s.Direction[1][i], s.Direction[2][i]);
        s.Walker[i] = an::CellWalker<double>(volume.Dimensions, origin, direction,
          ray.Segments[s.Segment[i]].Begin, ray.Segments[s.Segment[i]].End);
        continue;
      }
      finish(i);
      take(i);
    }
  };
  // The cut of lane i's cell from stretch b on.
  auto stretch = [&](int i, int b)
  {
    const an::Cubic<double> c{ { s.K[0][i], s.K[1][i], s.K[2][i], s.K[3][i] } };
    s.StretchIndex[i] = b;
    s.Stretch[i] = an::detail::Stretch<double>(c, s.Bounds[i][b], s.Bounds[i][b + 1], tf);
    s.J[i] = s.Stretch[i].Useful(tf, 0);
    s.U[i] = s.Stretch[i].A;
  };
  // Lane i's next sub-piece of its cell (PieceWalk's cut): whether a
  // crossing is to be found first (Seek). Cell 0 once the cell is spent.
  auto seek = [&](int i)
  {
    s.Seek[i] = 0.0;
    while (s.J[i] > s.Stretch[i].Inside)
    {
      if (s.StretchIndex[i] + 2 >= s.BoundCount[i])
      {
        s.Cell[i] = 0;
        return;
      }
      stretch(i, s.StretchIndex[i] + 1);
    }
    const an::detail::Stretch<double>& st = s.Stretch[i];
    if (s.J[i] < st.Inside)
    {
      s.Seek[i] = 1.0;
      s.Value[i] = st.Value(knots, s.J[i]);
      s.Lo[i] = st.A;
      s.Hi[i] = st.B;
    }
  };
  // Lane i's sub-piece up to the crossing (or the stretch's end): the piece
  // to integrate where it is visible.
  auto cut = [&](int i)
  {
    const an::detail::Stretch<double>& st = s.Stretch[i];
    const std::size_t j = s.J[i];
    const double u = s.U[i];
    const an::Cubic<double> c{ { s.K[0][i], s.K[1][i], s.K[2][i], s.K[3][i] } };
    double end;
    std::size_t piece;
    if (st.SubPiece(tf, c, j, u, s.Root[i], end, piece))
    {
      an::Cubic<double> q = c.Shifted(u);
      q.K[0] -= tf[piece].Start;
      for (int k = 0; k < 4; ++k)
      {
        s.Q[k][i] = q.K[k];
      }
      s.PieceLength[i] = end - u;
      s.Piece[i] = static_cast<std::int64_t>(piece);
      s.Monotone[i] = 1.0;
      s.Emit[i] = 1.0;
    }
    s.U[i] = std::max(u, end);
    s.J[i] = st.Useful(tf, j + 1);
  };

  for (int i = 0; i < N; ++i)
  {
    s.Out[i] = PiecewiseOutput();
    take(i);
  }
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  for (;;)
  {
    // 1. Each lane's next piece: the next visible cell where it has none
    // (nextCell), whole when no knot crosses it, else its next sub-piece
    // (after the crossings the lanes seek together, step 2); a lane whose
    // cell is spent takes the next at once.
    bool any = false, seeking = false;
    hn::Store(zero, d, s.Emit);
    hn::Store(zero, d, s.Seek);
    for (int i = 0; i < N; ++i)
    {
      while (s.Active[i])
      {
        if (s.Cell[i] == 0)
        {
          nextCell(i);
          continue;
        }
        if (s.Cell[i] == 1)
        {
          ++s.Out[i].Cells;
          if (s.Crossings[i] == 0)
          {
            const std::size_t piece = static_cast<std::size_t>(s.First[i]);
            s.Q[0][i] = s.K[0][i] - tf[piece].Start;
            for (int k = 1; k < 4; ++k)
            {
              s.Q[k][i] = s.K[k][i];
            }
            s.PieceLength[i] = s.Length[i];
            s.Piece[i] = static_cast<std::int64_t>(piece);
            s.Monotone[i] = 0.0;
            s.Emit[i] = 1.0;
            s.Cell[i] = 0;
            break;
          }
          // Monotone stretches: split at the extrema inside the cell.
          const an::Cubic<double> c{ { s.K[0][i], s.K[1][i], s.K[2][i], s.K[3][i] } };
          s.BoundCount[i] = an::detail::StretchBounds(c, s.Length[i], s.Bounds[i]);
          s.Cell[i] = 2;
          stretch(i, 0);
        }
        seek(i);
        if (s.Cell[i] == 2)
        {
          seeking = seeking || s.Seek[i] != 0.0;
          break;
        }
      }
      any = any || s.Active[i];
    }
    if (!any)
    {
      break;
    }
    // 2. The crossings sought, in lanes; the sub-pieces they end.
    if (seeking)
    {
      const auto sought = hn::Ne(hn::Load(d, s.Seek), zero);
      const V k[4] = { hn::Load(d, s.K[0]), hn::Load(d, s.K[1]), hn::Load(d, s.K[2]),
        hn::Load(d, s.K[3]) };
      hn::Store(
        CrossingLanes(d, k, hn::Load(d, s.Value), hn::IfThenElseZero(sought, hn::Load(d, s.Lo)),
          hn::IfThenElseZero(sought, hn::Load(d, s.Hi))),
        d, s.Root);
    }
    for (int i = 0; i < N; ++i)
    {
      if (s.Active[i] && s.Cell[i] == 2)
      {
        cut(i);
      }
    }

    // 3. The pieces integrated in lanes, in each ray's order.
    const auto emit = hn::Ne(hn::Load(d, s.Emit), zero);
    if (hn::AllFalse(d, emit))
    {
      continue;
    }
    // The lanes' transfer-function pieces.
    const auto piece = hn::IfThenElseZero(hn::RebindMask(d64, emit), hn::LoadU(d64, s.Piece));
    auto gather = [&](int k) { return hn::GatherIndex(d, table.Columns[k].data(), piece); };
    const V k[4] = { hn::Load(d, s.Q[0]), hn::Load(d, s.Q[1]), hn::Load(d, s.Q[2]),
      hn::Load(d, s.Q[3]) };
    const V l = hn::IfThenElseZero(emit, hn::Load(d, s.PieceLength));
    V depth[PieceDegree + 1];
    const V E = DepthLanes(d, k, gather(PiecewiseTable::Tau), gather(PiecewiseTable::TauSlope),
      gather(PiecewiseTable::TauCurvature), gather(PiecewiseTable::TauCubic), l, depth);
    const auto monotone = hn::Or(hn::Ne(hn::Load(d, s.Monotone), zero), MonotoneLanes(d, k, l));
    const V qa = k[0];
    const V ql =
      hn::Add(k[0], hn::Mul(l, hn::Add(k[1], hn::Mul(l, hn::Add(k[2], hn::Mul(l, k[3]))))));
    const V Ta = hn::Load(d, s.Transmittance), Tb = hn::Mul(Ta, E);
    const V cs = gather(PiecewiseTable::ColourSlopeMaximum);
    V slope[3], colour[3];
    for (int c = 0; c < 3; ++c)
    {
      const V C = gather(PiecewiseTable::Colour + c);
      slope[c] = gather(PiecewiseTable::ColourSlope + c);
      const V a = hn::Mul(Ta, hn::Add(C, hn::Mul(slope[c], qa)));
      const V b = hn::Mul(Tb, hn::Add(C, hn::Mul(slope[c], ql)));
      colour[c] = hn::Load(d, s.Colour[c]);
      colour[c] = hn::IfThenElse(emit, hn::Add(colour[c], hn::Sub(a, b)), colour[c]);
    }
    // J: the midpoint of its bounds where that is within the piece's share,
    // else the series (IntegratePiecewise's flush).
    const auto needJ = hn::And(emit, hn::And(hn::Gt(cs, zero), hn::Gt(Ta, zero)));
    const V dq = hn::Sub(ql, qa), spent = hn::Sub(one, E);
    const V inverseL = hn::Load(d, s.InverseLength);
    const auto midpoint = hn::And(hn::And(needJ, monotone),
      hn::Le(hn::Mul(hn::Mul(hn::Mul(cs, Ta), hn::Abs(dq)), spent),
        hn::Mul(hn::Set(d, budget), hn::Add(hn::Mul(Ta, spent), hn::Mul(l, inverseL)))));
    const V middle = hn::Mul(Ta, hn::Mul(hn::Mul(dq, hn::Add(one, E)), hn::Set(d, 0.5)));
    const auto series = hn::AndNot(midpoint, needJ);
    V J = zero;
    auto settled = midpoint;
    if (!hn::AllFalse(d, series))
    {
      const V scale = hn::Div(hn::Set(d, budget), hn::Mul(hn::Mul(hn::Set(d, 2.0), cs), Ta));
      const V limit =
        hn::IfThenElse(series, hn::Mul(scale, hn::MulAdd(Ta, spent, hn::Mul(l, inverseL))),
          hn::Set(d, std::numeric_limits<double>::infinity()));
      const auto done = SeriesLanes(d, depth, k[1], hn::Mul(hn::Set(d, 2.0), k[2]),
        hn::Mul(hn::Set(d, 3.0), k[3]), l, limit, J);
      J = hn::Mul(Ta, J);
      const auto open = hn::AndNot(done, series);
      if (!hn::AllFalse(d, open))
      {
        hn::Store(hn::IfThenElseZero(open, one), d, s.Open);
        hn::Store(scale, d, s.Scale);
        hn::Store(Ta, d, s.Front);
        hn::Store(E, d, s.PieceTransmittance);
      }
      else
      {
        hn::Store(zero, d, s.Open);
      }
      settled = hn::Or(settled, hn::And(series, done));
    }
    else
    {
      hn::Store(zero, d, s.Open);
    }
    J = hn::IfThenElse(midpoint, middle, J);
    for (int c = 0; c < 3; ++c)
    {
      colour[c] = hn::IfThenElse(settled, hn::Add(colour[c], hn::Mul(slope[c], J)), colour[c]);
      hn::Store(colour[c], d, s.Colour[c]);
    }
    const V T = hn::IfThenElse(emit, Tb, Ta);
    hn::Store(T, d, s.Transmittance);
    const auto stop = hn::And(emit, hn::Le(T, hn::Set(d, terminationBound)));
    alignas(64) double stops[MaximumLanes];
    hn::Store(hn::IfThenElseZero(stop, one), d, stops);
    for (int i = 0; i < N; ++i)
    {
      if (s.Emit[i] == 0.0)
      {
        continue;
      }
      ++s.Out[i].Pieces;
      if (s.Open[i] != 0.0)
      {
        // Not settled on the whole piece: SeriesIntegral's sub-intervals.
        const auto& tfp = tf[static_cast<std::size_t>(s.Piece[i])];
        const double Tf = s.Front[i];
        an::RayStatistics<double> statistics;
        const double Jp = an::detail::SubintervalsJ(
          an::Cubic<double>{ { s.Q[0][i], s.Q[1][i], s.Q[2][i], s.Q[3][i] } }, tfp,
          s.PieceLength[i], s.PieceTransmittance[i], s.Scale[i], Tf, s.InverseLength[i],
          statistics);
        s.Out[i].Rejected += statistics.Rejected;
        if (std::isnan(Jp))
        {
          s.Out[i].Error = an::detail::RefusedPieceError;
          std::fill(s.Out[i].RGBA, s.Out[i].RGBA + 4, 0.0);
          finish(i);
          take(i);
          continue;
        }
        for (int c = 0; c < 3; ++c)
        {
          s.Colour[c][i] += tfp.ColourSlope[c] * (Tf * Jp);
        }
      }
      if (stops[i] != 0.0)
      {
        finish(i);
        take(i);
      }
    }
  }
}

void CastPiecewiseRaysImpl(const Volume& volume, const an::PiecewiseTransferFunction<double>& tf,
  const PiecewiseTable& table, double tolerance, const RiemannRay* rays, std::size_t count,
  PiecewiseOutput* out)
{
  if (volume.Scalars == Volume::Type::UInt8)
  {
    CastRays<Volume::Type::UInt8>(volume, tf, table, tolerance, rays, count, out);
  }
  else
  {
    CastRays<Volume::Type::UInt16>(volume, tf, table, tolerance, rays, count, out);
  }
}

} // namespace HWY_NAMESPACE
} // namespace engine
} // namespace avos
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace avos
{
namespace engine
{
HWY_EXPORT(CastPiecewiseRaysImpl);

std::string PiecewiseTable::Build(const numerics::PiecewiseTransferFunction<double>& tf)
{
  const std::size_t n = tf.GetNumberOfPieces();
  if (n == 0)
  {
    return "the piecewise transfer function was not built";
  }
  for (auto& column : this->Columns)
  {
    column.resize(n);
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto& p = tf[i];
    this->Columns[Tau][i] = p.Tau;
    this->Columns[TauSlope][i] = p.TauSlope;
    this->Columns[TauCurvature][i] = p.TauCurvature;
    this->Columns[TauCubic][i] = p.TauCubic;
    for (int c = 0; c < 3; ++c)
    {
      this->Columns[Colour + c][i] = p.Colour[c];
      this->Columns[ColourSlope + c][i] = p.ColourSlope[c];
    }
    this->Columns[ColourSlopeMaximum][i] = p.ColourSlopeMaximum;
  }
  return std::string();
}

std::string ValidatePiecewiseRays(
  const Volume& volume, const numerics::PiecewiseTransferFunction<double>& tf)
{
  if (!ReadsCells(volume.Scalars))
  {
    return "the ray-per-lane piecewise method reads 8- and 16-bit unsigned scalars only";
  }
  std::string error = Validate(volume); // at least 2 points along each axis, among others
  if (!error.empty())
  {
    return error;
  }
  if (tf.GetNumberOfPieces() == 0 || !PieceKernels::TakesTables(tf.GetUnitTables()))
  {
    return "the ray-per-lane piecewise method needs the transfer function's unit tables";
  }
  return std::string();
}

void CastPiecewiseRays(const Volume& volume, const numerics::PiecewiseTransferFunction<double>& tf,
  const PiecewiseTable& table, double tolerance, const RiemannRay* rays, std::size_t count,
  PiecewiseOutput* out)
{
  std::string error = ValidatePiecewiseRays(volume, tf);
  if (error.empty())
  {
    error = numerics::ValidatePiecewiseTolerance(tolerance, numerics::OpacityModel::Extinction);
  }
  if (error.empty() && table.Columns[PiecewiseTable::Tau].size() != tf.GetNumberOfPieces())
  {
    error = "the piece table was not built from this transfer function";
  }
  if (!error.empty())
  {
    for (std::size_t i = 0; i < count; ++i)
    {
      out[i] = PiecewiseOutput();
      out[i].Error = error;
    }
    return;
  }
  HWY_DYNAMIC_DISPATCH(CastPiecewiseRaysImpl)(volume, tf, table, tolerance, rays, count, out);
}
} // namespace engine
} // namespace avos
#endif
