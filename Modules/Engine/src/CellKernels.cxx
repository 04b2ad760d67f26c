// The cells' stage of the piecewise method's walk (PieceKernels::Cells) for
// every Highway target (foreach_target re-includes this file once per
// target). Compiled without fused multiply-adds (CMakeLists.txt): each lane
// repeats numerics::ScalarCellKernels' arithmetic to the bit.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/CellKernels.cxx"
#include "hwy/foreach_target.h" // IWYU pragma: keep

#include "hwy/highway.h"

#include "avos/engine/PieceKernels.h"
#include "src/CellLanes-inl.h"

#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace avos
{
namespace engine
{
namespace HWY_NAMESPACE
{
using Cells = numerics::CellBatch<double>;
using Tables = numerics::PiecewiseTransferFunction<double>::UnitTables;

// numerics::detail::Crossing in every lane (CrossingLanes), the cell's cubic
// in all of them.
void CrossingsImpl(numerics::CrossingBatch<double>& b)
{
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int N = static_cast<int>(hn::Lanes(d));
  const V k[4] = { hn::Set(d, b.S.K[0]), hn::Set(d, b.S.K[1]), hn::Set(d, b.S.K[2]),
    hn::Set(d, b.S.K[3]) };
  for (int i = 0; i < b.Count; i += N)
  {
    // Lanes past Count solve a crossing of length 0.
    const auto live = hn::FirstN(d, static_cast<std::size_t>(b.Count - i));
    hn::StoreU(CrossingLanes(d, k, hn::IfThenElseZero(live, hn::LoadU(d, b.Value + i)),
                 hn::IfThenElseZero(live, hn::LoadU(d, b.Lo + i)),
                 hn::IfThenElseZero(live, hn::LoadU(d, b.Hi + i))),
      d, b.Root + i);
  }
}

void CellsImpl(
  const Volume& v, const Tables& t, const double* origin, const double* direction, Cells& b)
{
  if (v.Scalars == Volume::Type::UInt8)
  {
    ClassifyCells<Volume::Type::UInt8>(v, t, origin, direction, b);
  }
  else
  {
    ClassifyCells<Volume::Type::UInt16>(v, t, origin, direction, b);
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
