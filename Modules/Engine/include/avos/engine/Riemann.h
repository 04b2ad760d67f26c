// The vectorised Riemann kernel of the ray-casting engine (VTK-free).
//
// CastRiemann evaluates the sum of numerics::IntegrateRiemann in its
// exponential form (samples at t_i = min(i h, D) inside the ray's segments,
// alpha_i = 1 - e^{-tau(s_i) dt_i}, front-to-back compositing, early
// termination once T <= bound / max(1, max C)), with the per-sample work
// (trilinear interpolation from gathered corners, the transfer function, the
// exponential, VTK's -ln(1 - alpha)) in float SIMD lanes, a lane per
// consecutive sample of the ray, through Google Highway with runtime dispatch
// (AVX-512, AVX2, SSE4, SSSE3, scalar). Sample positions and steps are
// computed in double from the sample index alone (so the result does not
// depend on how samples fall into vectors: empty-space skipping stays exact
// to the bit) and rounded to float; compositing is in double.
//
// CastRiemannRays runs many rays at once, a ray per lane, each lane refilled
// with the next ray when its own ends: no lane idles at a segment's end or
// an early termination, and the compositing runs in double lanes instead of
// a sample at a time (a ray's samples in lanes filled 82 to 94 % of the
// lanes on the four datasets at 800x600, a ray per lane 97.5 % on Foot).
// Each lane takes CastRiemann's samples with its arithmetic.
//
// Error bound against the double sum, per channel, without early
// termination: 1e-4. Positions rounded to float move a sample by at most
// 3e-5 voxel in a 512^3 volume; float scalars round 32-bit integers and
// doubles to 24 bits (8- and 16-bit ones are exact); interpolation, transfer
// function and the vector exponential and logarithm (4 ulp) add relative
// errors of a few 1e-7 per sample, and since the per-sample opacities
// telescope (sum T_i alpha_i = 1 - T) they do not accumulate past the
// largest one. With early termination a ray whose transmittance lands within
// that rounding of the bound may take one sample more or less than the
// double sum: then the difference is at most the bound itself.
// Modules/Engine/Testing checks both on every dispatch target.
#ifndef avos_engine_Riemann_h
#define avos_engine_Riemann_h

#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/TransferFunction.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace avos
{
namespace engine
{

// A scalar volume, x fastest, at most 2^31 - 1 points (32-bit gather
// indices; 2^30 of 16-bit scalars, gathered by byte offset), read in place:
// the kernels need no copy and no padding (ScalarWords-inl.h). 8- and 16-bit
// scalars are read as they are (one 32-bit gather fetches a corner and its x
// neighbour: half the gathers of float, and a quarter or half the memory).
// Any other type is converted to float by the caller. One component of
// interleaved tuples is read in place too: Data at that component of the
// first tuple, Stride scalars from a point's to the next, Trailing scalars
// in the array after the last point's (the last tuple's later components;
// the kernels read no further).
struct Volume
{
  enum class Type
  {
    Float32,
    UInt8,
    UInt16,
    Int8,
    Int16
  };

  const void* Data = nullptr;
  Type Scalars = Type::Float32;
  int Dimensions[3] = { 0, 0, 0 };
  int Stride = 1;
  int Trailing = 0;
};

// Whether the piecewise method's cell kernels read scalars of this type:
// their unit tables are indexed by 8- and 16-bit unsigned scalars.
inline bool ReadsCells(Volume::Type type)
{
  return type == Volume::Type::UInt8 || type == Volume::Type::UInt16;
}

// Opacity and colour, each linear on a piece (the value at the piece's start
// and the slope), in float, one entry per piece.
struct LinearPieces
{
  std::vector<float> Opacity, OpacitySlope, Colour[3], ColourSlope[3];
  // The same, interleaved per piece (Opacity, OpacitySlope, Colour[0],
  // ColourSlope[0], ...: 8 floats), so that one 64-bit gather fetches a
  // value and its slope.
  std::vector<float> Pairs;

  void Clear();
  void Add(
    double opacity, double opacitySlope, const glm::dvec3& colour, const glm::dvec3& colourSlope);
  // Zero-filled to `size` entries at least.
  void Pad(std::size_t size);
};

// The transfer function as the kernels read it: structure of arrays in
// float, indexed by piece (0 below the first knot, i for [knot i - 1, knot i)),
// located in constant time through a bucket grid, as
// numerics::TransferFunction does in double. When every knot is an integer
// (as for 8- and 16-bit data's usual transfer functions) the pieces are
// also laid out once per scalar unit (Unit*: the same linear functions, cut
// at every integer), so that a piece is floor(s) - first knot + 1, found
// without a search.
class TransferTable
{
public:
  // From a finalised, valid transfer function; empty on success.
  std::string Build(const numerics::TransferFunction<double>& tf);

  std::vector<float> Knots;
  std::vector<float> Start, Length; // of the pieces
  LinearPieces Pieces;
  std::vector<std::int32_t> Buckets; // pieces at or below each bucket's lower edge
  float BucketScale = 0.0f;
  // Per scalar unit from UnitOrigin (the first knot) over UnitCount knots
  // (UnitOrigin .. UnitOrigin + UnitCount - 1); UnitCount 0: not laid out.
  float UnitOrigin = 0.0f;
  std::int32_t UnitCount = 0;
  LinearPieces Units;
  bool Alpha = false;          // VTK's model: opacity is alpha per UnitDistance
  float InverseUnit = 1.0f;    // 1 / UnitDistance
  float OpaqueExtinction = 40; // tau for alpha >= 1 (numerics::TransferFunction's)
  double MaximumColor = 0.0;
};

struct RayOutput
{
  double RGBA[4] = { 0.0, 0.0, 0.0, 0.0 };
  long Samples = 0;
};

// Empty when the volume can be cast by the kernels, else why.
std::string Validate(const Volume& volume);

// The Riemann sum with step h along origin + t direction (grid coordinates,
// t in the caller's units), over the sorted, disjoint segments of [0, D]
// (tau = 0 elsewhere). `terminationBound` 0: no early termination.
void CastRiemann(const Volume& volume, const TransferTable& tf, const double origin[3],
  const double direction[3], double D, double h, const numerics::Interval<double>* segments,
  std::size_t count, double terminationBound, RayOutput& out);

// A ray for CastRiemannRays: CastRiemann's arguments but the volume's, the
// transfer function's, h and the termination bound.
struct RiemannRay
{
  double Origin[3] = { 0.0, 0.0, 0.0 };
  double Direction[3] = { 0.0, 0.0, 0.0 };
  double D = 0.0;
  const numerics::Interval<double>* Segments = nullptr;
  std::size_t Count = 0;
};

// out[i] = CastRiemann's result for rays[i], i in [0, count), a ray per
// lane: every lane steps its own ray's samples (from their indices, in
// double, as CastRiemann), composites in double lanes, and takes the next
// ray as soon as its own ends (its segments spent or T <= bound), so no
// lane idles at a segment's end or an early termination while rays are
// left.
void CastRiemannRays(const Volume& volume, const TransferTable& tf, double h,
  double terminationBound, const RiemannRay* rays, std::size_t count, RayOutput* out);

// The name of the target CastRiemann dispatches to now ("AVX3", "AVX2",
// "SSE4", "EMU128", ...): hwy::SetSupportedTargetsForTest changes it.
const char* CastRiemannTarget();

} // namespace engine
} // namespace avos

#endif
