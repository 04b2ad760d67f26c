// The cells' stage of the piecewise method's walk (PieceKernels::Cells) for
// every Highway target (foreach_target re-includes this file once per
// target). Compiled without fused multiply-adds (CMakeLists.txt): each lane
// repeats numerics::ScalarCellKernels' arithmetic to the bit.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/CellKernels.cxx"
#include "hwy/foreach_target.h" // IWYU pragma: keep

#include "hwy/highway.h"

#include "avos/engine/PieceKernels.h"

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

using Cells = numerics::CellBatch<double>;
using Tables = numerics::PiecewiseTransferFunction<double>::UnitTables;

// numerics::ScalarCellKernels in lanes, for 8- or 16-bit scalars: each lane
// classifies its cell's integer corner range from the unit tables and builds
// its cubic (CellCubic's operations, in its order).
template <Volume::Type Scalars>
void CellsOf(
  const Volume& v, const Tables& t, const double* origin, const double* direction, Cells& b)
{
  const hn::ScalableTag<double> d;
  const hn::Rebind<std::int32_t, decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  using VI = hn::Vec<decltype(di)>;
  const int N = static_cast<int>(hn::Lanes(d));
  constexpr bool Bytes = Scalars == Volume::Type::UInt8;
  constexpr int Size = Bytes ? 1 : 2;
  const std::int32_t sy = v.Dimensions[0], sz = v.Dimensions[0] * v.Dimensions[1];
  const auto* words = static_cast<const std::int32_t*>(v.Data);
  const VI mask = hn::Set(di, Bytes ? 0xFF : 0xFFFF);
  const VI zero = hn::Zero(di), one = hn::Set(di, 1);
  const VI base = hn::Set(di, static_cast<std::int32_t>(t.Base));
  const VI last = hn::Set(di, static_cast<std::int32_t>(t.Count) - 1);
  const VI knots = hn::Set(di, static_cast<std::int32_t>(t.Knots));
  const auto* upper = reinterpret_cast<const std::int32_t*>(t.Upper);
  const auto* below = reinterpret_cast<const std::int32_t*>(t.Below);
  const auto* visible = reinterpret_cast<const std::int32_t*>(t.VisibleBefore);
  const V ox = hn::Set(d, origin[0]), oy = hn::Set(d, origin[1]), oz = hn::Set(d, origin[2]);
  const V dx = hn::Set(d, direction[0]), dy = hn::Set(d, direction[1]),
          dz = hn::Set(d, direction[2]);
  for (int i = 0; i < b.Count; i += N)
  {
    // Lanes past Count read cell (0, 0, 0); their results are not read.
    const auto live = hn::FirstN(di, static_cast<std::size_t>(b.Count - i));
    const VI ci = hn::LoadU(di, b.Index[0] + i), cj = hn::LoadU(di, b.Index[1] + i),
             ck = hn::LoadU(di, b.Index[2] + i);
    const VI at = hn::IfThenElseZero(live,
      hn::Mul(hn::Add(ci, hn::Add(hn::Mul(cj, hn::Set(di, sy)), hn::Mul(ck, hn::Set(di, sz)))),
        hn::Set(di, Size)));
    // One 32-bit word from a corner's byte on holds it and its x neighbour
    // (little endian; the volume is padded for the last one).
    VI c[8];
    const std::int32_t offsets[4] = { 0, sy, sz, sy + sz };
    for (int p = 0; p < 4; ++p)
    {
      const VI w = hn::GatherOffset(di, words, hn::Add(at, hn::Set(di, Size * offsets[p])));
      c[2 * p] = hn::And(w, mask);
      c[2 * p + 1] = hn::And(hn::ShiftRight<8 * Size>(w), mask);
    }
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
      const VI x = hn::Sub(s, base);
      const VI inside = hn::GatherIndex(di, table, hn::Min(hn::Max(x, zero), last));
      return hn::IfThenElse(hn::Lt(x, zero), zero, hn::IfThenElse(hn::Gt(x, last), knots, inside));
    };
    const VI first = lookup(lo, upper);
    const auto crossings = hn::Gt(lookup(hi, below), first);
    const VI end = hn::IfThenElse(crossings, lookup(hi, upper), first);
    const auto seen =
      hn::Gt(hn::GatherIndex(di, visible, hn::Add(end, one)), hn::GatherIndex(di, visible, first));
    hn::StoreU(hn::IfThenElseZero(hn::And(seen, live), one), di, b.Visible + i);
    hn::StoreU(first, di, b.First + i);
    hn::StoreU(hn::IfThenElseZero(crossings, one), di, b.Crossings + i);
    // CellCubic, from the entry point in the cell's frame.
    V f[8];
    for (int k = 0; k < 8; ++k)
    {
      f[k] = hn::PromoteTo(d, c[k]);
    }
    const V tb = hn::LoadU(d, b.Begin + i);
    const V x = hn::Sub(hn::Add(ox, hn::Mul(tb, dx)), hn::PromoteTo(d, ci));
    const V y = hn::Sub(hn::Add(oy, hn::Mul(tb, dy)), hn::PromoteTo(d, cj));
    const V z = hn::Sub(hn::Add(oz, hn::Mul(tb, dz)), hn::PromoteTo(d, ck));
    const V A = f[0], B = hn::Sub(f[1], f[0]), C = hn::Sub(f[2], f[0]), D = hn::Sub(f[4], f[0]);
    const V E = hn::Add(hn::Sub(hn::Sub(f[3], f[2]), f[1]), f[0]);
    const V F = hn::Add(hn::Sub(hn::Sub(f[5], f[4]), f[1]), f[0]);
    const V G = hn::Add(hn::Sub(hn::Sub(f[6], f[4]), f[2]), f[0]);
    const V H = hn::Sub(
      hn::Add(
        hn::Add(hn::Add(hn::Sub(hn::Sub(hn::Sub(f[7], f[6]), f[5]), f[3]), f[4]), f[2]), f[1]),
      f[0]);
    V k0 = hn::Add(A, hn::Mul(B, x));
    k0 = hn::Add(k0, hn::Mul(C, y));
    k0 = hn::Add(k0, hn::Mul(D, z));
    k0 = hn::Add(k0, hn::Mul(hn::Mul(E, x), y));
    k0 = hn::Add(k0, hn::Mul(hn::Mul(F, x), z));
    k0 = hn::Add(k0, hn::Mul(hn::Mul(G, y), z));
    k0 = hn::Add(k0, hn::Mul(hn::Mul(hn::Mul(H, x), y), z));
    const V gx =
      hn::Add(hn::Add(hn::Add(B, hn::Mul(E, y)), hn::Mul(F, z)), hn::Mul(hn::Mul(H, y), z));
    const V gy =
      hn::Add(hn::Add(hn::Add(C, hn::Mul(E, x)), hn::Mul(G, z)), hn::Mul(hn::Mul(H, x), z));
    const V gz =
      hn::Add(hn::Add(hn::Add(D, hn::Mul(F, x)), hn::Mul(G, y)), hn::Mul(hn::Mul(H, x), y));
    const V k1 = hn::Add(hn::Add(hn::Mul(dx, gx), hn::Mul(dy, gy)), hn::Mul(dz, gz));
    const V k2 = hn::Add(hn::Add(hn::Mul(hn::Mul(dx, dy), hn::Add(E, hn::Mul(H, z))),
                           hn::Mul(hn::Mul(dx, dz), hn::Add(F, hn::Mul(H, y)))),
      hn::Mul(hn::Mul(dy, dz), hn::Add(G, hn::Mul(H, x))));
    const V k3 = hn::Mul(hn::Mul(hn::Mul(H, dx), dy), dz);
    hn::StoreU(k0, d, b.K[0] + i);
    hn::StoreU(k1, d, b.K[1] + i);
    hn::StoreU(k2, d, b.K[2] + i);
    hn::StoreU(k3, d, b.K[3] + i);
  }
}

// numerics::detail::Crossing in every lane: the lanes that are done keep
// their result while the others iterate.
void CrossingsImpl(numerics::CrossingBatch<double>& b)
{
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int N = static_cast<int>(hn::Lanes(d));
  const V k0 = hn::Set(d, b.S.K[0]), k1 = hn::Set(d, b.S.K[1]), k2 = hn::Set(d, b.S.K[2]),
          k3 = hn::Set(d, b.S.K[3]);
  const V zero = hn::Zero(d), half = hn::Set(d, 0.5), two = hn::Set(d, 2.0),
          three = hn::Set(d, 3.0);
  const V tiny = hn::Set(d, 4.0 * std::numeric_limits<double>::epsilon());
  // Cubic::operator() and Cubic::Derivative, operation for operation.
  auto s = [&](V u)
  { return hn::Add(k0, hn::Mul(u, hn::Add(k1, hn::Mul(u, hn::Add(k2, hn::Mul(u, k3)))))); };
  auto ds = [&](V u)
  { return hn::Add(k1, hn::Mul(u, hn::Add(hn::Mul(two, k2), hn::Mul(hn::Mul(u, three), k3)))); };
  for (int i = 0; i < b.Count; i += N)
  {
    // Lanes past Count solve a crossing of length 0.
    const auto live = hn::FirstN(d, static_cast<std::size_t>(b.Count - i));
    const V value = hn::IfThenElseZero(live, hn::LoadU(d, b.Value + i));
    V lo = hn::IfThenElseZero(live, hn::LoadU(d, b.Lo + i));
    V hi = hn::IfThenElseZero(live, hn::LoadU(d, b.Hi + i));
    const V slo = s(lo), shi = s(hi);
    const V sign = hn::IfThenElse(hn::Ge(shi, slo), hn::Set(d, 1.0), hn::Set(d, -1.0));
    V u = hn::IfThenElse(hn::Ne(shi, slo),
      hn::Add(lo, hn::Mul(hn::Sub(hi, lo), hn::Div(hn::Sub(value, slo), hn::Sub(shi, slo)))),
      hn::Mul(half, hn::Add(lo, hi)));
    u = hn::Min(hn::Max(u, lo), hi);
    // Open lanes iterate; a lane that closes keeps its result in u.
    auto open = hn::Lt(lo, hi);
    for (int k = 0; k < 128 && !hn::AllFalse(d, open); ++k)
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
      const auto done =
        hn::Or(hn::Eq(next, u), hn::Le(hn::Sub(hi, lo), hn::Mul(tiny, hn::Abs(hi))));
      u = hn::IfThenElse(open, next, u);
      open = hn::AndNot(done, open);
      open = hn::And(open, hn::Lt(lo, hi));
    }
    hn::StoreU(u, d, b.Root + i);
  }
}

void CellsImpl(
  const Volume& v, const Tables& t, const double* origin, const double* direction, Cells& b)
{
  if (v.Scalars == Volume::Type::UInt8)
  {
    CellsOf<Volume::Type::UInt8>(v, t, origin, direction, b);
  }
  else
  {
    CellsOf<Volume::Type::UInt16>(v, t, origin, direction, b);
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
HWY_EXPORT(CellsImpl);
HWY_EXPORT(CrossingsImpl);

void PieceKernels::Crossings(numerics::CrossingBatch<double>& batch) const
{
  HWY_DYNAMIC_DISPATCH(CrossingsImpl)(batch);
}

void PieceKernels::VectorisedCells(const Volume& scalars,
  const numerics::PiecewiseTransferFunction<double>::UnitTables& tables, const double* origin,
  const double* direction, numerics::CellBatch<double>& batch)
{
  HWY_DYNAMIC_DISPATCH(CellsImpl)(scalars, tables, origin, direction, batch);
}
} // namespace engine
} // namespace avos
#endif
