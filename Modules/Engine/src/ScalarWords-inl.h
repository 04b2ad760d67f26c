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
// One component of interleaved tuples (Volume::Stride) takes a gather per
// corner, the last pair's clamped the same way.
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
  const std::int64_t points =
    std::int64_t(volume.Dimensions[0]) * volume.Dimensions[1] * volume.Dimensions[2];
  return static_cast<std::int32_t>(
    ((points - 1) * volume.Stride + 1 + volume.Trailing) * ScalarBytes(volume.Scalars) - 4);
}

// The bytes from a scalar to its x neighbour's.
inline std::int32_t StepBytes(const Volume& volume)
{
  return volume.Stride * ScalarBytes(volume.Scalars);
}

// The scalar in the low bits of each lane's word, as a 32-bit integer
// (sign-extended by the arithmetic shifts of int32 lanes where signed).
template <Volume::Type Scalars, int Shift, class DI>
HWY_INLINE hn::Vec<DI> ScalarOf(DI di, hn::Vec<DI> w)
{
  constexpr int Bits = 8 * ScalarBytes(Scalars);
  if (Scalars == Volume::Type::Int8 || Scalars == Volume::Type::Int16)
  {
    return hn::ShiftRight<32 - Bits>(hn::ShiftLeft<32 - Bits - Shift>(w));
  }
  return hn::And(hn::ShiftRight<Shift>(w), hn::Set(di, (1 << Bits) - 1));
}

// The 32-bit word at byte offset `at` of every lane, or, Clamped, the last
// whole word where `at` lies in the array's last three bytes, shifted so
// that the byte at `at` is its lowest.
template <bool Clamped, class DI>
HWY_INLINE hn::Vec<DI> WordAt(DI di, const void* data, hn::Vec<DI> at, hn::Vec<DI> lastWord)
{
  const auto* words = static_cast<const std::int32_t*>(data);
  if (!Clamped)
  {
    return hn::GatherOffset(di, words, at);
  }
  const hn::RebindToUnsigned<DI> du;
  const auto start = hn::Min(at, lastWord);
  const auto shift = hn::BitCast(du, hn::ShiftLeft<3>(hn::Sub(at, start)));
  return hn::BitCast(di, hn::BitCast(du, hn::GatherOffset(di, words, start)) >> shift);
}

// The scalars at byte offset `at` (a corner) and at + step (its x
// neighbour; step = StepBytes) for every lane, as 32-bit integers.
// LastPair: the corners are a cell's last pair (lastWord is Set(di,
// LastWord(volume))); otherwise lastWord is not read. Contiguous scalars
// (step the scalar's size) take one gather for both; one component of
// interleaved tuples takes one per corner. There too only the last pair
// can reach the array's last three bytes: every other pair ends at least
// sy >= 2 points, 2 step >= 4 bytes, before the last pair's first corner.
template <Volume::Type Scalars, bool LastPair, class DI>
HWY_INLINE void ReadPair(DI di, const void* data, hn::Vec<DI> at, hn::Vec<DI> lastWord,
  std::int32_t step, hn::Vec<DI>& first, hn::Vec<DI>& second)
{
  constexpr int Bytes = ScalarBytes(Scalars);
  if (step != Bytes)
  {
    first = ScalarOf<Scalars, 0>(di, WordAt<LastPair>(di, data, at, lastWord));
    second = ScalarOf<Scalars, 0>(
      di, WordAt<LastPair>(di, data, hn::Add(at, hn::Set(di, step)), lastWord));
    return;
  }
  // A pair of 16-bit scalars is a whole word: never past the array's end.
  constexpr bool Clamped = LastPair && Bytes == 1;
  const hn::Vec<DI> w = WordAt<Clamped>(di, data, at, lastWord);
  first = ScalarOf<Scalars, 0>(di, w);
  second = ScalarOf<Scalars, 8 * Bytes>(di, w);
}

} // namespace HWY_NAMESPACE
} // namespace engine
} // namespace avos
HWY_AFTER_NAMESPACE();

#endif
