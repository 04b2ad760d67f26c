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
// the vector stages load and store is aligned, in double (indices below
// 2^53 are exact there); the walk is each lane's own, a lane at a time.
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
  alignas(64) double Cell[MaximumLanes];
  alignas(64) double First[MaximumLanes];
  alignas(64) double Crossings[MaximumLanes];
  alignas(64) double K[4][MaximumLanes];
  alignas(64) double Length[MaximumLanes];
  // The cut of a cell with crossings (numerics::detail::Stretch): its
  // stretches' bounds and their count, the stretch's index, ends [A, B],
  // direction (Rising 1) and knots (K0, K1, Inside), the next useful
  // sub-piece J and where it starts (U).
  alignas(64) double Bounds[4][MaximumLanes];
  alignas(64) double BoundCount[MaximumLanes];
  alignas(64) double StretchIndex[MaximumLanes];
  alignas(64) double A[MaximumLanes];
  alignas(64) double B[MaximumLanes];
  alignas(64) double Rising[MaximumLanes];
  alignas(64) double K0[MaximumLanes];
  alignas(64) double K1[MaximumLanes];
  alignas(64) double Inside[MaximumLanes];
  alignas(64) double J[MaximumLanes];
  alignas(64) double U[MaximumLanes];
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
  alignas(64) double Piece[MaximumLanes];
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

// The cut's decisions in lanes, each the scalar code's to the bit (the
// same comparisons on the same doubles): numerics::Cubic, the knot
// searches of numerics::PiecewiseTransferFunction from its unit tables,
// and numerics::detail::Stretch's Useful and SubPiece, reading the
// PiecewiseTable's Start, Visible, NextVisible and PreviousVisibleEnd.
template <class D>
struct CutLanes
{
  using V = hn::Vec<D>;
  using M = hn::Mask<D>;
  const D d;
  const hn::RebindToSigned<D> d64;
  const hn::Rebind<std::int32_t, D> di;
  const double* Knots;
  const PiecewiseTable& Table;
  const an::PiecewiseTransferFunction<double>::UnitTables Units;
  const V Zero, One, KnotCount, Base, LastUnit;

  CutLanes(const an::PiecewiseTransferFunction<double>& tf, const PiecewiseTable& table)
    : Knots(tf.GetKnots().data())
    , Table(table)
    , Units(tf.GetUnitTables())
    , Zero(hn::Zero(d))
    , One(hn::Set(d, 1.0))
    , KnotCount(hn::Set(d, static_cast<double>(tf.GetKnots().size())))
    , Base(hn::Set(d, Units.Base))
    , LastUnit(hn::Set(d, static_cast<double>(Units.Count) - 1.0))
  {
  }

  // std::min and std::max: the second argument only where it compares
  // below (above) the first.
  static V Least(V a, V b) { return hn::IfThenElse(hn::Lt(b, a), b, a); }
  static V Most(V a, V b) { return hn::IfThenElse(hn::Lt(a, b), b, a); }
  // Cubic::operator() and Cubic::Shifted, operation for operation.
  static V At(const V k[4], V u)
  {
    return hn::Add(k[0], hn::Mul(u, hn::Add(k[1], hn::Mul(u, hn::Add(k[2], hn::Mul(u, k[3]))))));
  }
  void Shifted(const V k[4], V u, V q[4]) const
  {
    const V three = hn::Set(d, 3.0);
    q[0] = At(k, u);
    q[1] = hn::Add(
      k[1], hn::Mul(u, hn::Add(hn::Mul(hn::Set(d, 2.0), k[2]), hn::Mul(hn::Mul(u, three), k[3]))));
    q[2] = hn::Add(k[2], hn::Mul(hn::Mul(three, k[3]), u));
    q[3] = k[3];
  }
  // Table column c at the pieces `index` (lanes outside m read piece 0).
  V Column(int c, M m, V index) const
  {
    return hn::GatherIndex(
      d, this->Table.Columns[c].data(), hn::ConvertTo(d64, hn::IfThenElseZero(m, index)));
  }
  V Knot(M m, V index) const
  {
    return hn::GatherIndex(d, this->Knots, hn::ConvertTo(d64, hn::IfThenElseZero(m, index)));
  }
  // Locate(x) (below false: knots <= x) or CountBelow(x) (below true:
  // knots < x) in lanes m: the unit tables' answer at floor(x), exact
  // (x - Base is exact for integer Base and |x| < 2^52), then the knots up
  // to x, at most those of one unit. NaN gives 0, as Locate does.
  V Search(M m, V x, bool below) const
  {
    const V unit = hn::Floor(hn::Sub(x, this->Base));
    const auto inside = hn::And(m, hn::And(hn::Ge(unit, this->Zero), hn::Le(unit, this->LastUnit)));
    const auto* table =
      reinterpret_cast<const std::int32_t*>(below ? this->Units.Below : this->Units.Upper);
    const V counted = hn::PromoteTo(
      d, hn::GatherIndex(di, table, hn::DemoteTo(di, hn::IfThenElseZero(inside, unit))));
    V i = hn::IfThenElse(
      inside, counted, hn::IfThenElseZero(hn::Gt(unit, this->LastUnit), this->KnotCount));
    auto open = hn::And(m, hn::Lt(i, this->KnotCount));
    while (!hn::AllFalse(d, open))
    {
      const V k = this->Knot(open, i);
      open = hn::And(open, below ? hn::Lt(k, x) : hn::Le(k, x));
      i = hn::IfThenElse(open, hn::Add(i, this->One), i);
      open = hn::And(open, hn::Lt(i, this->KnotCount));
    }
    return i;
  }
  // PiecewiseTransferFunction::LocateNear(x, guess) in lanes m.
  V LocateNear(M m, V x, V guess) const
  {
    const auto lower = hn::Gt(guess, this->Zero);
    const auto upper = hn::Lt(guess, this->KnotCount);
    const V before = this->Knot(hn::And(m, lower), hn::Sub(guess, this->One));
    const V after = this->Knot(hn::And(m, upper), guess);
    const auto near =
      hn::And(hn::Or(hn::Not(lower), hn::Le(before, x)), hn::Or(hn::Not(upper), hn::Lt(x, after)));
    const auto far = hn::AndNot(near, m);
    return hn::AllFalse(d, far) ? guess : hn::IfThenElse(far, this->Search(far, x, false), guess);
  }
  V Visible(M m, V piece) const { return this->Column(PiecewiseTable::Visible, m, piece); }
};

template <Volume::Type Scalars>
void CastRays(const Volume& volume, const an::PiecewiseTransferFunction<double>& tf,
  const PiecewiseTable& table, double tolerance, const RiemannRay* rays, std::size_t count,
  PiecewiseOutput* out)
{
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> d64;
  using V = hn::Vec<decltype(d)>;
  using M = hn::Mask<decltype(d)>;
  const int N = static_cast<int>(hn::Lanes(d));
  const auto tables = tf.GetUnitTables();
  const double budget = 0.6 * tolerance;
  const double terminationBound = 0.15 * tolerance / std::max(1.0, tf.GetMaximumColor());
  const CutLanes<decltype(d)> cl(tf, table);

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
      s.Cell[i] = 0.0;
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
    s.Cell[i] = 0.0;
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
          s.Cell[i] = 1.0;
          ++s.Out[i].Cells;
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
  // The vector stages' state, kept in registers: a masked store followed
  // by a full load of the same lanes cannot be forwarded and stalls.
  struct State
  {
    V Cell, K[4], Length, First, Crossings;
    V Bounds[4], BoundCount, StretchIndex, A, B, Rising, K0, K1, Inside, J, U;
    V Seek, Value, Lo, Hi;
    V Emit, Q[4], PieceLength, Piece, Monotone;
  } v;
  {
    const V z = hn::Zero(d);
    v.Cell = v.Length = v.First = v.Crossings = v.BoundCount = v.StretchIndex = v.A = v.B = z;
    v.Rising = v.K0 = v.K1 = v.Inside = v.J = v.U = v.Seek = v.Value = v.Lo = v.Hi = z;
    v.Emit = v.PieceLength = v.Piece = v.Monotone = z;
    for (int k = 0; k < 4; ++k)
    {
      v.K[k] = v.Bounds[k] = v.Q[k] = z;
    }
  }
  // Stretch::Useful(j) in lanes m, for their stretches.
  auto useful = [&](M m, V j)
  {
    const V none = hn::Add(v.Inside, cl.One);
    const auto rising = hn::Ne(v.Rising, cl.Zero);
    const auto among = hn::And(m, hn::And(hn::Gt(v.Inside, cl.Zero), hn::Le(j, v.Inside)));
    // Pieces K0 + j on, ascending: the next visible one p; pieces K1 - j
    // down, descending: one past the previous visible one.
    const V p = cl.Column(PiecewiseTable::NextVisible, hn::And(among, rising), hn::Add(v.K0, j));
    const V up = hn::IfThenElse(hn::Gt(p, v.K1), none,
      hn::IfThenElse(hn::Gt(hn::Sub(p, v.K0), j), hn::Sub(hn::Sub(p, v.K0), cl.One), j));
    const V end =
      cl.Column(PiecewiseTable::PreviousVisibleEnd, hn::AndNot(rising, among), hn::Sub(v.K1, j));
    const V q = hn::Sub(v.K1, hn::Sub(end, cl.One));
    const V down =
      hn::IfThenElse(hn::Le(end, v.K0), none, hn::IfThenElse(hn::Gt(q, j), hn::Sub(q, cl.One), j));
    return hn::IfThenElse(
      among, hn::IfThenElse(rising, up, down), hn::IfThenElse(hn::Eq(v.Inside, cl.Zero), j, none));
  };
  // Stretch `index` of lanes m's cells, its first useful sub-piece.
  auto stretch = [&](M m, V index)
  {
    const auto first = hn::Eq(index, cl.Zero), second = hn::Eq(index, cl.One);
    const V a =
      hn::IfThenElse(first, v.Bounds[0], hn::IfThenElse(second, v.Bounds[1], v.Bounds[2]));
    const V b =
      hn::IfThenElse(first, v.Bounds[1], hn::IfThenElse(second, v.Bounds[2], v.Bounds[3]));
    const V sa = cl.At(v.K, a), sb = cl.At(v.K, b);
    const V k0 = cl.Search(m, cl.Least(sa, sb), false);
    const V k1 = cl.Search(m, cl.Most(sa, sb), true);
    v.StretchIndex = hn::IfThenElse(m, index, v.StretchIndex);
    v.A = hn::IfThenElse(m, a, v.A);
    v.B = hn::IfThenElse(m, b, v.B);
    v.U = hn::IfThenElse(m, a, v.U);
    v.Rising = hn::IfThenElse(m, hn::IfThenElseZero(hn::Ge(sb, sa), cl.One), v.Rising);
    v.K0 = hn::IfThenElse(m, k0, v.K0);
    v.K1 = hn::IfThenElse(m, k1, v.K1);
    v.Inside = hn::IfThenElse(m, hn::IfThenElseZero(hn::Gt(k1, k0), hn::Sub(k1, k0)), v.Inside);
    v.J = hn::IfThenElse(m, useful(m, cl.Zero), v.J);
  };
  // Lanes m's newly taken cells with crossings: their monotone stretches
  // (StretchBounds; Extrema's shortcut in lanes, its roots a lane at a
  // time) and the first stretch.
  auto cutCells = [&](M m)
  {
    const V l = v.Length;
    const V rest = hn::Add(hn::Mul(hn::Mul(hn::Set(d, 2.0), hn::Abs(v.K[2])), l),
      hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 3.0), hn::Abs(v.K[3])), l), l));
    const auto monotone = hn::Gt(hn::Abs(v.K[1]), hn::Mul(hn::Set(d, 2.0), rest));
    v.Bounds[0] = hn::IfThenElse(m, cl.Zero, v.Bounds[0]);
    v.Bounds[1] = hn::IfThenElse(m, l, v.Bounds[1]);
    v.BoundCount = hn::IfThenElse(m, hn::Set(d, 2.0), v.BoundCount);
    const auto roots = hn::AndNot(monotone, m);
    if (!hn::AllFalse(d, roots))
    {
      alignas(64) double lanes[MaximumLanes];
      hn::Store(hn::IfThenElseZero(roots, cl.One), d, lanes);
      for (int i = 0; i < N; ++i)
      {
        if (lanes[i] != 0.0)
        {
          // nextCell left the cell in the arrays.
          const an::Cubic<double> c{ { s.K[0][i], s.K[1][i], s.K[2][i], s.K[3][i] } };
          double bounds[4];
          const int n = an::detail::StretchBounds(c, s.Length[i], bounds);
          for (int b = 0; b < n; ++b)
          {
            s.Bounds[b][i] = bounds[b];
          }
          s.BoundCount[i] = n;
        }
      }
      for (int b = 0; b < 4; ++b)
      {
        v.Bounds[b] = hn::IfThenElse(roots, hn::Load(d, s.Bounds[b]), v.Bounds[b]);
      }
      v.BoundCount = hn::IfThenElse(roots, hn::Load(d, s.BoundCount), v.BoundCount);
    }
    stretch(m, cl.Zero);
  };
  // Lanes m's next sub-piece (PieceWalk's cut): past the stretches without
  // one (Cell 0 where the cell is spent), then the crossing to seek.
  auto seek = [&](M m)
  {
    for (;;)
    {
      const auto past = hn::And(m, hn::Gt(v.J, v.Inside));
      if (hn::AllFalse(d, past))
      {
        break;
      }
      const auto spent =
        hn::And(past, hn::Ge(hn::Add(v.StretchIndex, hn::Set(d, 2.0)), v.BoundCount));
      v.Cell = hn::IfThenElse(spent, cl.Zero, v.Cell);
      m = hn::AndNot(spent, m);
      const auto more = hn::AndNot(spent, past);
      if (!hn::AllFalse(d, more))
      {
        stretch(more, hn::Add(v.StretchIndex, cl.One));
      }
    }
    const auto sought = hn::And(m, hn::Lt(v.J, v.Inside));
    const auto rising = hn::Ne(v.Rising, cl.Zero);
    const V at = hn::IfThenElse(rising, hn::Add(v.K0, v.J), hn::Sub(hn::Sub(v.K1, cl.One), v.J));
    v.Seek = hn::IfThenElse(m, hn::IfThenElseZero(sought, cl.One), v.Seek);
    v.Value = hn::IfThenElse(sought, cl.Knot(sought, at), v.Value);
    v.Lo = hn::IfThenElse(sought, v.A, v.Lo);
    v.Hi = hn::IfThenElse(sought, v.B, v.Hi);
  };
  // Lanes m's sub-piece up to the crossing `root` (or the stretch's end)
  // (Stretch::SubPiece): the piece to integrate where it is visible.
  auto cut = [&](M m, V root)
  {
    const V j = v.J, u = v.U;
    const auto rising = hn::Ne(v.Rising, cl.Zero);
    const V pieceAt = hn::IfThenElse(rising, hn::Add(v.K0, j), hn::Sub(v.K1, j));
    const auto crossed = hn::Lt(j, v.Inside);
    const auto visible =
      hn::And(m, hn::Or(hn::Eq(v.Inside, cl.Zero), hn::Ne(cl.Visible(m, pieceAt), cl.Zero)));
    // Rounding may put a root before the one of the knot before.
    const V end = hn::IfThenElse(crossed, cl.Least(cl.Most(root, u), v.B), v.B);
    const auto open = hn::And(visible, hn::Gt(end, u));
    if (!hn::AllFalse(d, open))
    {
      // The transfer-function piece from the scalar in the middle: robust
      // where a crossing rounds onto a knot.
      const V piece =
        cl.LocateNear(open, cl.At(v.K, hn::Mul(hn::Set(d, 0.5), hn::Add(u, end))), pieceAt);
      const auto emit = hn::And(open, hn::Ne(cl.Visible(open, piece), cl.Zero));
      V q[4];
      cl.Shifted(v.K, u, q);
      q[0] = hn::Sub(q[0], cl.Column(PiecewiseTable::Start, emit, piece));
      for (int c = 0; c < 4; ++c)
      {
        v.Q[c] = hn::IfThenElse(emit, q[c], v.Q[c]);
      }
      v.PieceLength = hn::IfThenElse(emit, hn::Sub(end, u), v.PieceLength);
      v.Piece = hn::IfThenElse(emit, piece, v.Piece);
      v.Monotone = hn::IfThenElse(emit, cl.One, v.Monotone);
      v.Emit = hn::IfThenElse(emit, cl.One, v.Emit);
    }
    v.U = hn::IfThenElse(m, cl.Most(u, end), v.U);
    v.J = hn::IfThenElse(m, useful(m, hn::Add(j, cl.One)), v.J);
  };
  // Lanes m's cells without crossings, whole.
  auto whole = [&](M m)
  {
    v.Q[0] =
      hn::IfThenElse(m, hn::Sub(v.K[0], cl.Column(PiecewiseTable::Start, m, v.First)), v.Q[0]);
    for (int c = 1; c < 4; ++c)
    {
      v.Q[c] = hn::IfThenElse(m, v.K[c], v.Q[c]);
    }
    v.PieceLength = hn::IfThenElse(m, v.Length, v.PieceLength);
    v.Piece = hn::IfThenElse(m, v.First, v.Piece);
    v.Monotone = hn::IfThenElse(m, cl.Zero, v.Monotone);
    v.Emit = hn::IfThenElse(m, cl.One, v.Emit);
    v.Cell = hn::IfThenElse(m, cl.Zero, v.Cell);
  };

  for (int i = 0; i < N; ++i)
  {
    s.Out[i] = PiecewiseOutput();
    take(i);
  }
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
  for (;;)
  {
    // 1. Each lane's next piece, in rounds until every lane with a ray has
    // one or a sub-piece to cut: lanes without a cell take their next
    // visible one (nextCell, a lane at a time); a new cell without a knot
    // crossing is one piece, one with crossings is cut into stretches;
    // lanes being cut seek their next sub-piece's crossing (found together
    // in step 2), or are spent and take a cell in the next round.
    v.Emit = zero;
    v.Seek = zero;
    M ready = hn::Lt(zero, zero);
    M live;
    for (;;)
    {
      alignas(64) double waiting[MaximumLanes];
      hn::Store(hn::IfThenElseZero(ready, one), d, waiting);
      hn::Store(v.Cell, d, s.Cell);
      alignas(64) double active[MaximumLanes];
      for (int i = 0; i < N; ++i)
      {
        if (s.Active[i] && waiting[i] == 0.0 && s.Cell[i] == 0.0)
        {
          nextCell(i);
        }
        active[i] = s.Active[i] ? 1.0 : 0.0;
      }
      live = hn::Ne(hn::Load(d, active), zero);
      v.Cell = hn::Load(d, s.Cell);
      const auto taken = hn::And(live, hn::Eq(v.Cell, one));
      if (!hn::AllFalse(d, taken))
      {
        for (int k = 0; k < 4; ++k)
        {
          v.K[k] = hn::IfThenElse(taken, hn::Load(d, s.K[k]), v.K[k]);
        }
        v.Length = hn::IfThenElse(taken, hn::Load(d, s.Length), v.Length);
        v.First = hn::IfThenElse(taken, hn::Load(d, s.First), v.First);
        v.Crossings = hn::IfThenElse(taken, hn::Load(d, s.Crossings), v.Crossings);
        const auto crossing = hn::And(taken, hn::Ne(v.Crossings, zero));
        const auto single = hn::AndNot(crossing, taken);
        if (!hn::AllFalse(d, single))
        {
          whole(single);
          ready = hn::Or(ready, single);
        }
        if (!hn::AllFalse(d, crossing))
        {
          cutCells(crossing);
          v.Cell = hn::IfThenElse(crossing, two, v.Cell);
        }
      }
      const auto cutting = hn::AndNot(ready, hn::And(live, hn::Eq(v.Cell, two)));
      if (!hn::AllFalse(d, cutting))
      {
        seek(cutting);
        ready = hn::Or(ready, hn::And(cutting, hn::Eq(v.Cell, two)));
      }
      if (hn::AllFalse(d, hn::AndNot(ready, live)))
      {
        break;
      }
    }
    if (hn::AllFalse(d, live))
    {
      break;
    }
    // 2. The crossings sought, in lanes; the sub-pieces they end.
    const auto cutting = hn::And(live, hn::Eq(v.Cell, two));
    if (!hn::AllFalse(d, cutting))
    {
      const auto sought = hn::Ne(v.Seek, zero);
      const V root = hn::AllFalse(d, sought)
        ? zero
        : CrossingLanes(
            d, v.K, v.Value, hn::IfThenElseZero(sought, v.Lo), hn::IfThenElseZero(sought, v.Hi));
      cut(cutting, root);
    }

    // 3. The pieces integrated in lanes, in each ray's order.
    const auto emit = hn::Ne(v.Emit, zero);
    if (hn::AllFalse(d, emit))
    {
      continue;
    }
    // The lanes' transfer-function pieces.
    const auto piece = hn::ConvertTo(d64, hn::IfThenElseZero(emit, v.Piece));
    auto gather = [&](int k) { return hn::GatherIndex(d, table.Columns[k].data(), piece); };
    const V* k = v.Q;
    const V l = hn::IfThenElseZero(emit, v.PieceLength);
    V depth[PieceDegree + 1];
    const V E = DepthLanes(d, k, gather(PiecewiseTable::Tau), gather(PiecewiseTable::TauSlope),
      gather(PiecewiseTable::TauCurvature), gather(PiecewiseTable::TauCubic), l, depth);
    const auto monotone = hn::Or(hn::Ne(v.Monotone, zero), MonotoneLanes(d, k, l));
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
        for (int c = 0; c < 4; ++c)
        {
          hn::Store(v.Q[c], d, s.Q[c]);
        }
        hn::Store(v.PieceLength, d, s.PieceLength);
        hn::Store(v.Piece, d, s.Piece);
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
    hn::Store(v.Emit, d, s.Emit);
    hn::Store(v.Cell, d, s.Cell); // finish clears a lane's cell
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
    v.Cell = hn::Load(d, s.Cell);
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
    this->Columns[Start][i] = p.Start;
    this->Columns[Visible][i] = tf.IsVisible(i) ? 1.0 : 0.0;
    this->Columns[NextVisible][i] = static_cast<double>(tf.NextVisible(i));
    this->Columns[PreviousVisibleEnd][i] = static_cast<double>(tf.PreviousVisibleEnd(i));
  }
  return std::string();
}

std::string ValidatePiecewiseRays(
  const Volume& volume, const numerics::PiecewiseTransferFunction<double>& tf)
{
  if (volume.Scalars == Volume::Type::Float32)
  {
    return "the ray-per-lane piecewise method reads 8- and 16-bit scalars only";
  }
  std::string error = Validate(volume);
  if (!error.empty())
  {
    return error;
  }
  for (int a = 0; a < 3; ++a)
  {
    if (volume.Dimensions[a] < 2)
    {
      return "the volume needs at least 2 points along each axis";
    }
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
