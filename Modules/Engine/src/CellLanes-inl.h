// Per-target helpers of the piecewise method's cell stage, shared by the
// batch kernels (CellKernels.cxx) and the ray-per-lane integrator
// (PiecewiseRays.cxx): a cell per lane classified and its cubic built (a
// batch of one ray's cells at a time), and numerics::detail::Crossing in
// lanes. Both repeat the scalar code's
// arithmetic to the bit (no fused multiply-adds: the including files are
// compiled with -ffp-contract=off). Highway's per-target include guard: the
// file is re-included once per target by foreach_target.
#if defined(AVOS_ENGINE_CELL_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef AVOS_ENGINE_CELL_LANES_INL_H_
#undef AVOS_ENGINE_CELL_LANES_INL_H_
#else
#define AVOS_ENGINE_CELL_LANES_INL_H_
#endif

#include "hwy/highway.h"

#include "avos/engine/Riemann.h" // Volume
#include "avos/numerics/Pieces.h"
#include "src/ScalarWords-inl.h"

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

// A cell per lane as numerics::ScalarCellKernels::Cells sees it, for 8- or
// 16-bit unsigned scalars: its integer corner range classified from the unit
// tables (Visible, First, Crossings: 1 or 0) and its cubic K (CellCubic's
// operations, in its order) from the entry point (x, y, z) in the cell's
// frame along (dx, dy, dz). Lanes outside `live` read cell (0, 0, 0).
template <Volume::Type Scalars, class D, class DI>
struct ClassifiedCell
{
  using V = hn::Vec<D>;
  using VI = hn::Vec<DI>;
  VI Visible, First, Crossings;
  V K[4];

  HWY_INLINE ClassifiedCell(D d, DI di, const Volume& v,
    const numerics::PiecewiseTransferFunction<double>::UnitTables& t, hn::Mask<DI> live, VI ci,
    VI cj, VI ck, V x, V y, V z, V dx, V dy, V dz)
  {
    const std::int32_t sy = v.Dimensions[0], sz = v.Dimensions[0] * v.Dimensions[1];
    const VI zero = hn::Zero(di), one = hn::Set(di, 1);
    const VI base = hn::Set(di, static_cast<std::int32_t>(t.Base));
    const VI last = hn::Set(di, static_cast<std::int32_t>(t.Count) - 1);
    const VI knots = hn::Set(di, static_cast<std::int32_t>(t.Knots));
    const auto* upper = reinterpret_cast<const std::int32_t*>(t.Upper);
    const auto* below = reinterpret_cast<const std::int32_t*>(t.Below);
    const auto* visible = reinterpret_cast<const std::int32_t*>(t.VisibleBefore);
    const std::int32_t step = StepBytes(v);
    const VI at = hn::IfThenElseZero(live,
      hn::Mul(hn::Add(ci, hn::Add(hn::Mul(cj, hn::Set(di, sy)), hn::Mul(ck, hn::Set(di, sz)))),
        hn::Set(di, step)));
    const VI lastWord = hn::Set(di, LastWord(v));
    VI c[8];
    const std::int32_t offsets[4] = { 0, sy, sz, sy + sz };
    for (int p = 0; p < 3; ++p)
    {
      ReadPair<Scalars, false>(di, v.Data, hn::Add(at, hn::Set(di, step * offsets[p])), lastWord,
        step, c[2 * p], c[2 * p + 1]);
    }
    ReadPair<Scalars, true>(
      di, v.Data, hn::Add(at, hn::Set(di, step * offsets[3])), lastWord, step, c[6], c[7]);
    VI lo = c[0], hi = c[0];
    for (int k = 1; k < 8; ++k)
    {
      lo = hn::Min(lo, c[k]);
      hi = hn::Max(hi, c[k]);
    }
    // PiecewiseTransferFunction::ClassifyRange from the tables, with
    // Locate / CountBelow 0 below them and Knots above.
    auto lookup = [&](VI s, const std::int32_t* table)
    {
      const VI unit = hn::Sub(s, base);
      const VI inside = hn::GatherIndex(di, table, hn::Min(hn::Max(unit, zero), last));
      return hn::IfThenElse(
        hn::Lt(unit, zero), zero, hn::IfThenElse(hn::Gt(unit, last), knots, inside));
    };
    this->First = lookup(lo, upper);
    const auto crossings = hn::Gt(lookup(hi, below), this->First);
    const VI end = hn::IfThenElse(crossings, lookup(hi, upper), this->First);
    const auto seen = hn::Gt(
      hn::GatherIndex(di, visible, hn::Add(end, one)), hn::GatherIndex(di, visible, this->First));
    this->Visible = hn::IfThenElseZero(hn::And(seen, live), one);
    this->Crossings = hn::IfThenElseZero(crossings, one);
    // CellCubic, from the entry point in the cell's frame.
    V f[8];
    for (int k = 0; k < 8; ++k)
    {
      f[k] = hn::PromoteTo(d, c[k]);
    }
    const V A = f[0], B = hn::Sub(f[1], f[0]), C = hn::Sub(f[2], f[0]), E0 = hn::Sub(f[4], f[0]);
    const V E = hn::Add(hn::Sub(hn::Sub(f[3], f[2]), f[1]), f[0]);
    const V F = hn::Add(hn::Sub(hn::Sub(f[5], f[4]), f[1]), f[0]);
    const V G = hn::Add(hn::Sub(hn::Sub(f[6], f[4]), f[2]), f[0]);
    const V H = hn::Sub(
      hn::Add(
        hn::Add(hn::Add(hn::Sub(hn::Sub(hn::Sub(f[7], f[6]), f[5]), f[3]), f[4]), f[2]), f[1]),
      f[0]);
    V k0 = hn::Add(A, hn::Mul(B, x));
    k0 = hn::Add(k0, hn::Mul(C, y));
    k0 = hn::Add(k0, hn::Mul(E0, z));
    k0 = hn::Add(k0, hn::Mul(hn::Mul(E, x), y));
    k0 = hn::Add(k0, hn::Mul(hn::Mul(F, x), z));
    k0 = hn::Add(k0, hn::Mul(hn::Mul(G, y), z));
    k0 = hn::Add(k0, hn::Mul(hn::Mul(hn::Mul(H, x), y), z));
    const V gx =
      hn::Add(hn::Add(hn::Add(B, hn::Mul(E, y)), hn::Mul(F, z)), hn::Mul(hn::Mul(H, y), z));
    const V gy =
      hn::Add(hn::Add(hn::Add(C, hn::Mul(E, x)), hn::Mul(G, z)), hn::Mul(hn::Mul(H, x), z));
    const V gz =
      hn::Add(hn::Add(hn::Add(E0, hn::Mul(F, x)), hn::Mul(G, y)), hn::Mul(hn::Mul(H, x), y));
    this->K[0] = k0;
    this->K[1] = hn::Add(hn::Add(hn::Mul(dx, gx), hn::Mul(dy, gy)), hn::Mul(dz, gz));
    this->K[2] = hn::Add(hn::Add(hn::Mul(hn::Mul(dx, dy), hn::Add(E, hn::Mul(H, z))),
                           hn::Mul(hn::Mul(dx, dz), hn::Add(F, hn::Mul(H, y)))),
      hn::Mul(hn::Mul(dy, dz), hn::Add(G, hn::Mul(H, x))));
    this->K[3] = hn::Mul(hn::Mul(hn::Mul(H, dx), dy), dz);
  }
};

// numerics::ScalarCellKernels::Cells in lanes for 8- or 16-bit scalars:
// the batch's cells of the ray origin + t direction, a cell per lane
// (ClassifiedCell). Lanes past Count read cell (0, 0, 0); their results are
// not read.
template <Volume::Type Scalars>
HWY_INLINE void ClassifyCells(const Volume& v,
  const numerics::PiecewiseTransferFunction<double>::UnitTables& t, const double* origin,
  const double* direction, numerics::CellBatch<double>& b)
{
  const hn::ScalableTag<double> d;
  const hn::Rebind<std::int32_t, decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  using VI = hn::Vec<decltype(di)>;
  const int N = static_cast<int>(hn::Lanes(d));
  const V ox = hn::Set(d, origin[0]), oy = hn::Set(d, origin[1]), oz = hn::Set(d, origin[2]);
  const V dx = hn::Set(d, direction[0]), dy = hn::Set(d, direction[1]),
          dz = hn::Set(d, direction[2]);
  for (int i = 0; i < b.Count; i += N)
  {
    const auto live = hn::FirstN(di, static_cast<std::size_t>(b.Count - i));
    const VI ci = hn::LoadU(di, b.Index[0] + i), cj = hn::LoadU(di, b.Index[1] + i),
             ck = hn::LoadU(di, b.Index[2] + i);
    const V tb = hn::LoadU(d, b.Begin + i);
    const V x = hn::Sub(hn::Add(ox, hn::Mul(tb, dx)), hn::PromoteTo(d, ci));
    const V y = hn::Sub(hn::Add(oy, hn::Mul(tb, dy)), hn::PromoteTo(d, cj));
    const V z = hn::Sub(hn::Add(oz, hn::Mul(tb, dz)), hn::PromoteTo(d, ck));
    const ClassifiedCell<Scalars, decltype(d), decltype(di)> cell(
      d, di, v, t, live, ci, cj, ck, x, y, z, dx, dy, dz);
    hn::StoreU(cell.Visible, di, b.Visible + i);
    hn::StoreU(cell.First, di, b.First + i);
    hn::StoreU(cell.Crossings, di, b.Crossings + i);
    for (int k = 0; k < 4; ++k)
    {
      hn::StoreU(cell.K[k], d, b.K[k] + i);
    }
  }
}

// numerics::detail::Crossing in every lane, each lane with its own cubic
// k[0..3], value and bracket [lo, hi] (lanes with lo = hi return lo): the
// lanes that are done keep their result while the others iterate.
template <class D>
HWY_INLINE hn::Vec<D> CrossingLanes(
  D d, const hn::Vec<D> k[4], hn::Vec<D> value, hn::Vec<D> lo, hn::Vec<D> hi)
{
  using V = hn::Vec<D>;
  const V zero = hn::Zero(d), half = hn::Set(d, 0.5), two = hn::Set(d, 2.0),
          three = hn::Set(d, 3.0);
  const V tiny = hn::Set(d, 4.0 * std::numeric_limits<double>::epsilon());
  // Cubic::operator() and Cubic::Derivative, operation for operation.
  auto s = [&](V u)
  { return hn::Add(k[0], hn::Mul(u, hn::Add(k[1], hn::Mul(u, hn::Add(k[2], hn::Mul(u, k[3])))))); };
  auto ds = [&](V u)
  {
    return hn::Add(k[1], hn::Mul(u, hn::Add(hn::Mul(two, k[2]), hn::Mul(hn::Mul(u, three), k[3]))));
  };
  const V slo = s(lo), shi = s(hi);
  const V sign = hn::IfThenElse(hn::Ge(shi, slo), hn::Set(d, 1.0), hn::Set(d, -1.0));
  V u = hn::IfThenElse(hn::Ne(shi, slo),
    hn::Add(lo, hn::Mul(hn::Sub(hi, lo), hn::Div(hn::Sub(value, slo), hn::Sub(shi, slo)))),
    hn::Mul(half, hn::Add(lo, hi)));
  u = hn::Min(hn::Max(u, lo), hi);
  // Open lanes iterate; a lane that closes keeps its result in u.
  auto open = hn::Lt(lo, hi);
  for (int i = 0; i < 128 && !hn::AllFalse(d, open); ++i)
  {
    const V f = hn::Mul(sign, hn::Sub(s(u), value));
    open = hn::AndNot(hn::Eq(f, zero), open);
    const auto below = hn::Lt(f, zero);
    lo = hn::IfThenElse(hn::And(open, below), u, lo);
    hi = hn::IfThenElse(hn::AndNot(below, open), u, hi);
    const V dv = hn::Mul(sign, ds(u));
    const auto rising = hn::Gt(dv, zero);
    const V newton = hn::Sub(u, hn::Div(f, hn::IfThenElse(rising, dv, hn::Set(d, 1.0))));
    const auto inside = hn::And(rising, hn::And(hn::Gt(newton, lo), hn::Lt(newton, hi)));
    const V next = hn::IfThenElse(inside, newton, hn::Mul(half, hn::Add(lo, hi)));
    const auto done = hn::Or(hn::Eq(next, u), hn::Le(hn::Sub(hi, lo), hn::Mul(tiny, hn::Abs(hi))));
    u = hn::IfThenElse(open, next, u);
    open = hn::AndNot(done, open);
    open = hn::And(open, hn::Lt(lo, hi));
  }
  return u;
}

} // namespace HWY_NAMESPACE
} // namespace engine
} // namespace avos
HWY_AFTER_NAMESPACE();

#endif
