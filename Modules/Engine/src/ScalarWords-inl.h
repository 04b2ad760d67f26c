// Per-target reading of 8- and 16-bit scalars in place (the caller's array,
// no copy, no padding), shared by the Riemann kernel and the piecewise
// method's cell lanes. One 32-bit gather from a corner's byte on fetches the
// corner and its x neighbour (little endian). A corner is never the last
// point of its row, so for 16-bit scalars the word is exactly the pair and
// never passes the array's end. For 8-bit ones the word holds two bytes
// more: a corner in the array's last three bytes reads the last whole word
// instead and shifts its pair down to the word's low bytes. Only a cell's
// last pair of corners (offset sy + sz) can be there: the pair at offset sz
// or below ends at least sy >= 2 bytes before the last corner's pair does.
// Highway's
// per-target include guard: the file is re-included once per target by
// foreach_target.
#if defined(AVOS_ENGINE_SCALAR_WORDS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef AVOS_ENGINE_SCALAR_WORDS_INL_H_
#undef AVOS_ENGINE_SCALAR_WORDS_INL_H_
#else
#define AVOS_ENGINE_SCALAR_WORDS_INL_H_
#endif

#include "hwy/highway.h"

#include "avos/engine/Riemann.h" // Volume

#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace avos
{
namespace engine
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

// Bytes per scalar of an 8- or 16-bit type.
constexpr int ScalarBytes(Volume::Type type)
{
  return type == Volume::Type::UInt8 || type == Volume::Type::Int8 ? 1 : 2;
}

// The byte offset of the last whole 32-bit word of the volume's scalars
// (8-bit: at least 8 points, so it is not negative).
inline std::int32_t LastWord(const Volume& volume)
{
  return volume.Dimensions[0] * volume.Dimensions[1] * volume.Dimensions[2] *
    ScalarBytes(volume.Scalars) -
    4;
}

// The scalars at byte offset `at` (a corner) and the next one (its x
// neighbour) for every lane, as 32-bit integers. LastPair: the corners are
// a cell's last pair (lastWord is Set(di, LastWord(volume))); otherwise
// lastWord is not read.
template <Volume::Type Scalars, bool LastPair, class DI>
HWY_INLINE void ReadPair(DI di, const void* data, hn::Vec<DI> at, hn::Vec<DI> lastWord,
  hn::Vec<DI>& first, hn::Vec<DI>& second)
{
  constexpr int Bits = 8 * ScalarBytes(Scalars);
  const auto* words = static_cast<const std::int32_t*>(data);
  hn::Vec<DI> w;
  if (Bits == 8 && LastPair)
  {
    const hn::RebindToUnsigned<DI> du;
    const auto start = hn::Min(at, lastWord);
    const auto shift = hn::BitCast(du, hn::ShiftLeft<3>(hn::Sub(at, start)));
    w = hn::BitCast(di, hn::BitCast(du, hn::GatherOffset(di, words, start)) >> shift);
  }
  else
  {
    w = hn::GatherOffset(di, words, at);
  }
  if (Scalars == Volume::Type::Int8 || Scalars == Volume::Type::Int16)
  {
    // Sign-extended by the arithmetic shifts of int32 lanes.
    first = hn::ShiftRight<32 - Bits>(hn::ShiftLeft<32 - Bits>(w));
    second = hn::ShiftRight<32 - Bits>(hn::ShiftLeft<32 - 2 * Bits>(w));
  }
  else
  {
    const auto mask = hn::Set(di, (1 << Bits) - 1);
    first = hn::And(w, mask);
    second = hn::And(hn::ShiftRight<Bits>(w), mask);
  }
}

} // namespace HWY_NAMESPACE
} // namespace engine
} // namespace avos
HWY_AFTER_NAMESPACE();

#endif
