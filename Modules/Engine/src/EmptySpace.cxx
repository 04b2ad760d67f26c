// The packet walk for every Highway target (foreach_target re-includes this
// file once per target) and its dispatching entry points (under HWY_ONCE).
// Each lane repeats numerics::EmptySpaceMap's walk operation for operation
// (its Walker, Cursor-free form: Walk and Crossing), so the CMake file turns
// off the contraction of multiply-adds here, as the scalar code has none.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/EmptySpace.cxx"
#include "hwy/foreach_target.h" // IWYU pragma: keep

#include "hwy/highway.h"

#include "avos/engine/EmptySpace.h"

#include <algorithm>
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

using Map = numerics::EmptySpaceMap<double>;
using Segments = std::vector<numerics::Interval<double>>;

void PacketSegmentsImpl(const Map& map, std::size_t count, const double* origins,
  const double* directions, const double* lengths, double pad, Segments* segments)
{
  const hn::ScalableTag<double> d;
  const hn::Rebind<std::int32_t, decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  using M = hn::Mask<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d);
  constexpr std::size_t MaximumLanes = HWY_MAX_BYTES / sizeof(double);
  HWY_ALIGN double buffer[6][MaximumLanes];

  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V inf = hn::Set(d, std::numeric_limits<double>::infinity());
  const V padding = hn::Set(d, pad);
  const V superSize = hn::Set(d, double(Map::BlockSize * Map::SuperSize));
  const V blockSize = hn::Set(d, double(Map::BlockSize));
  const V superCount[3] = { hn::Set(d, map.GetNumberOfSuperblocks(0)),
    hn::Set(d, map.GetNumberOfSuperblocks(1)), hn::Set(d, map.GetNumberOfSuperblocks(2)) };
  const V blockCount[3] = { hn::Set(d, map.GetNumberOfBlocks(0)),
    hn::Set(d, map.GetNumberOfBlocks(1)), hn::Set(d, map.GetNumberOfBlocks(2)) };
  const V superOffset = hn::Set(d, double(map.GetNumberOfBlocks()));
  const V stateAll = hn::Set(d, double(Map::All)), stateSome = hn::Set(d, double(Map::Some));
  const std::int32_t* table = reinterpret_cast<const std::int32_t*>(map.GetWalkTable());
  const auto byteMask = hn::Set(di, 0xFF);
  const M none = hn::FirstN(d, 0);

  for (std::size_t first = 0; first < count; first += lanes)
  {
    const std::size_t used = std::min(lanes, count - first);
    for (std::size_t k = 0; k < lanes; ++k)
    {
      const std::size_t i = first + std::min(k, used - 1);
      for (int a = 0; a < 3; ++a)
      {
        buffer[a][k] = origins[3 * i + a];
        buffer[3 + a][k] = directions[3 * i + a];
      }
      segments[i].clear();
    }
    // Lanes past the packet's rays repeat its last one and emit nothing.
    const M real = hn::FirstN(d, used);
    V O[3], Dir[3], Step[3], Inverse[3];
    for (int a = 0; a < 3; ++a)
    {
      O[a] = hn::Load(d, buffer[a]);
      Dir[a] = hn::Load(d, buffer[3 + a]);
      Step[a] = hn::IfThenElse(
        hn::Gt(Dir[a], zero), one, hn::IfThenElse(hn::Lt(Dir[a], zero), hn::Neg(one), zero));
      Inverse[a] = hn::IfThenElseZero(hn::Ne(Step[a], zero), hn::Div(one, Dir[a]));
    }
    for (std::size_t k = 0; k < lanes; ++k)
    {
      buffer[0][k] = lengths[first + std::min(k, used - 1)];
    }
    const V D = hn::Load(d, buffer[0]);

    // Where the ray leaves cube `index` of edge `size` along an axis.
    auto crossing = [&](V index, V size, V step, V o, V inverse) HWY_ATTR
    {
      const V plane = hn::IfThenElse(hn::Gt(step, zero), hn::Add(index, one), index);
      return hn::IfThenElse(
        hn::Eq(step, zero), inf, hn::Mul(hn::Sub(hn::Mul(plane, size), o), inverse));
    };

    // The cursor each lane steps: its superblock walk, or the block walk of
    // one superblock (the superblock walk saved meanwhile).
    V I[3], N[3], Lower[3], Upper[3];
    V T = zero, End = hn::IfThenElseZero(hn::Gt(D, zero), D), Size = superSize;
    M done = hn::Not(real), inBlock = none;
    for (int a = 0; a < 3; ++a)
    {
      const V p = hn::Div(hn::Add(O[a], hn::Mul(T, Dir[a])), Size);
      Lower[a] = zero;
      Upper[a] = superCount[a];
      I[a] = hn::Min(hn::Max(hn::Floor(p), Lower[a]), hn::Sub(Upper[a], one));
      N[a] = crossing(I[a], Size, Step[a], O[a], Inverse[a]);
    }
    V savedI[3] = { zero, zero, zero }, savedN[3] = { zero, zero, zero }, savedT = zero;
    M savedDone = none;
    // The segment each lane is extending, given once the next one starts
    // after a gap or the lane's walk ends.
    V pendingBegin = zero, pendingEnd = zero;
    M pending = none, finished = none;

    auto give = [&](M which) HWY_ATTR
    {
      if (hn::AllFalse(d, which))
      {
        return;
      }
      HWY_ALIGN double b[MaximumLanes], e[MaximumLanes];
      hn::Store(pendingBegin, d, b);
      hn::Store(pendingEnd, d, e);
      HWY_ALIGN std::uint8_t bits[8] = { 0 };
      hn::StoreMaskBits(d, which, bits);
      for (std::size_t k = 0; k < used; ++k)
      {
        if (bits[k / 8] & (1u << (k % 8)))
        {
          segments[first + k].push_back({ b[k], e[k] });
        }
      }
    };

    for (;;)
    {
      M active = hn::AndNot(done, hn::Lt(T, End));
      // Block walks that ended: back to their superblock walk.
      const M back = hn::AndNot(active, inBlock);
      if (!hn::AllFalse(d, back))
      {
        for (int a = 0; a < 3; ++a)
        {
          I[a] = hn::IfThenElse(back, savedI[a], I[a]);
          N[a] = hn::IfThenElse(back, savedN[a], N[a]);
          Lower[a] = hn::IfThenElse(back, zero, Lower[a]);
          Upper[a] = hn::IfThenElse(back, superCount[a], Upper[a]);
        }
        T = hn::IfThenElse(back, savedT, T);
        End = hn::IfThenElse(back, hn::IfThenElseZero(hn::Gt(D, zero), D), End);
        Size = hn::IfThenElse(back, superSize, Size);
        done = hn::Or(hn::AndNot(back, done), hn::And(back, savedDone));
        inBlock = hn::AndNot(back, inBlock);
        active = hn::AndNot(done, hn::Lt(T, End));
      }
      const M ending = hn::AndNot(finished, hn::AndNot(hn::Or(active, inBlock), real));
      if (!hn::AllFalse(d, ending))
      {
        give(hn::And(ending, pending));
        pending = hn::AndNot(ending, pending);
        finished = hn::Or(finished, ending);
      }
      if (hn::AllFalse(d, active))
      {
        break; // every inactive real lane has just finished
      }

      // One step of every active cursor: the nearest crossing, ties as the
      // scalar walk breaks them (x, then y).
      const M c01 = hn::Le(N[0], N[1]), c02 = hn::Le(N[0], N[2]), c12 = hn::Le(N[1], N[2]);
      const M mx = hn::And(c01, c02);
      const M my = hn::AndNot(c01, c12);
      const M mz = hn::Not(hn::Or(mx, my));
      auto pick = [&](const V* v) HWY_ATTR
      { return hn::IfThenElse(mx, v[0], hn::IfThenElse(my, v[1], v[2])); };
      const V exit = hn::Min(pick(N), End);
      const M crossed = hn::And(active, hn::Ge(exit, T));

      // The cube's byte: a block's visibility, or a superblock's state.
      const V nx = hn::IfThenElse(inBlock, blockCount[0], superCount[0]);
      const V ny = hn::IfThenElse(inBlock, blockCount[1], superCount[1]);
      V linear = hn::Add(I[0], hn::Mul(nx, hn::Add(I[1], hn::Mul(ny, I[2]))));
      linear = hn::IfThenElseZero(
        crossed, hn::Add(linear, hn::IfThenElseZero(hn::Not(inBlock), superOffset)));
      const V value =
        hn::PromoteTo(d, hn::And(hn::GatherOffset(di, table, hn::DemoteTo(di, linear)), byteMask));
      const M keep = hn::And(crossed,
        hn::Or(
          hn::And(inBlock, hn::Ne(value, zero)), hn::AndNot(inBlock, hn::Eq(value, stateAll))));
      const M enter = hn::And(hn::AndNot(inBlock, crossed), hn::Eq(value, stateSome));

      if (!hn::AllFalse(d, keep))
      {
        const V begin = hn::Max(hn::Sub(T, padding), zero);
        const V end = hn::Min(hn::Add(exit, padding), D);
        const M joins = hn::And(pending, hn::Le(begin, pendingEnd));
        give(hn::AndNot(joins, hn::And(keep, pending)));
        const M merge = hn::And(keep, joins), start = hn::AndNot(joins, keep);
        pendingEnd = hn::IfThenElse(merge, hn::Max(pendingEnd, end), pendingEnd);
        pendingBegin = hn::IfThenElse(start, begin, pendingBegin);
        pendingEnd = hn::IfThenElse(start, end, pendingEnd);
        pending = hn::Or(pending, keep);
      }

      // Advance: the next cube along the crossed axis, or the walk's end.
      const V visitT = T;
      const V superI[3] = { I[0], I[1], I[2] };
      const V step = pick(Step);
      const V next = hn::Add(pick(I), step);
      const M out =
        hn::Or(hn::Eq(step, zero), hn::Or(hn::Lt(next, pick(Lower)), hn::Ge(next, pick(Upper))));
      const M moves = hn::AndNot(out, active);
      done = hn::Or(done, hn::And(active, out));
      const M moveAxis[3] = { hn::And(moves, mx), hn::And(moves, my), hn::And(moves, mz) };
      T = hn::IfThenElse(moves, hn::Max(T, exit), T);
      const V cross = crossing(next, Size, step, pick(O), pick(Inverse));
      for (int a = 0; a < 3; ++a)
      {
        // Lanes that left their range keep the old index: harmless, done.
        I[a] = hn::IfThenElse(moveAxis[a], next, I[a]);
        N[a] = hn::IfThenElse(moveAxis[a], cross, N[a]);
      }

      // Superblocks of partly visible blocks: walk their blocks from the
      // superblock's part of the ray, then resume.
      if (!hn::AllFalse(d, enter))
      {
        for (int a = 0; a < 3; ++a)
        {
          savedI[a] = hn::IfThenElse(enter, I[a], savedI[a]);
          savedN[a] = hn::IfThenElse(enter, N[a], savedN[a]);
        }
        savedT = hn::IfThenElse(enter, T, savedT);
        savedDone = hn::Or(hn::AndNot(enter, savedDone), hn::And(enter, done));
        for (int a = 0; a < 3; ++a)
        {
          const V lower = hn::Mul(superI[a], hn::Set(d, double(Map::SuperSize)));
          const V upper =
            hn::Min(hn::Add(lower, hn::Set(d, double(Map::SuperSize))), blockCount[a]);
          const V p = hn::Div(hn::Add(O[a], hn::Mul(visitT, Dir[a])), blockSize);
          const V index = hn::Min(hn::Max(hn::Floor(p), lower), hn::Sub(upper, one));
          Lower[a] = hn::IfThenElse(enter, lower, Lower[a]);
          Upper[a] = hn::IfThenElse(enter, upper, Upper[a]);
          I[a] = hn::IfThenElse(enter, index, I[a]);
          N[a] = hn::IfThenElse(enter, crossing(index, blockSize, Step[a], O[a], Inverse[a]), N[a]);
        }
        T = hn::IfThenElse(enter, visitT, T);
        End = hn::IfThenElse(enter, exit, End);
        Size = hn::IfThenElse(enter, blockSize, Size);
        done = hn::AndNot(enter, done);
        inBlock = hn::Or(inBlock, enter);
      }
    }
  }
}

const char* PacketTargetNameImpl()
{
  return hwy::TargetName(HWY_TARGET);
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
HWY_EXPORT(PacketSegmentsImpl);
HWY_EXPORT(PacketTargetNameImpl);

void PacketSegments(const numerics::EmptySpaceMap<double>& map, std::size_t count,
  const double* origins, const double* directions, const double* lengths, double pad,
  std::vector<numerics::Interval<double>>* segments)
{
  HWY_DYNAMIC_DISPATCH(PacketSegmentsImpl)
  (map, count, origins, directions, lengths, pad, segments);
}

const char* PacketSegmentsTarget()
{
  return HWY_DYNAMIC_DISPATCH(PacketTargetNameImpl)();
}

} // namespace engine
} // namespace avos
#endif
