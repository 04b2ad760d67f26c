// The empty-space walk of the ray-casting engine for packets of rays
// (VTK-free).
//
// numerics::EmptySpaceMap::Segments walks one ray at a time through
// superblocks and blocks (Amanatides and Woo): about 30 steps per ray on
// Bonsai at 800x600, each a data-dependent branch (which axis, visible or
// not), which took 21 to 29 % of a one-thread Riemann frame (Foot, Bonsai)
// in a profile. PacketSegments walks a ray per double lane (8 with AVX-512),
// every lane stepping its own cursor through superblocks or the blocks of
// one, with masks instead of branches; only a finished segment leaves the
// vector. Each lane computes what the scalar walk computes, in the same
// order and precision (the file is compiled without contraction of
// multiply-adds), so the segments are Segments()' to the bit:
// Modules/Engine/Testing checks it on every dispatch target.
#ifndef avos_engine_EmptySpace_h
#define avos_engine_EmptySpace_h

#include "avos/numerics/EmptySpace.h"

#include <cstddef>
#include <vector>

namespace avos
{
namespace engine
{

// segments[i] = the segments map.Segments(origins[i], directions[i],
// lengths[i], pad) gives, for i in [0, count); origins and directions hold
// three doubles per ray.
void PacketSegments(const numerics::EmptySpaceMap<double>& map, std::size_t count,
  const double* origins, const double* directions, const double* lengths, double pad,
  std::vector<numerics::Interval<double>>* segments);

// The name of the target PacketSegments dispatches to now.
const char* PacketSegmentsTarget();

} // namespace engine
} // namespace avos

#endif
