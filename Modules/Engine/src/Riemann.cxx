// The Riemann kernel for every Highway target (foreach_target re-includes
// this file once per target), the dispatching entry points, and the
// transfer table (once, under HWY_ONCE).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/Riemann.cxx"
#include "hwy/foreach_target.h" // IWYU pragma: keep

#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"

#include "avos/engine/Riemann.h"
#include "src/ScalarWords-inl.h"

#include <algorithm>
#include <cmath>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace avos
{
namespace engine
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

constexpr int MaximumLanes = HWY_MAX_BYTES / sizeof(float);

// The scalars of points base + offset and base + offset + 1 (a corner and
// its x neighbour) for every lane, `stride` scalars from a point's to the
// next (Volume::Stride); LastPair and lastWord as ReadPair's.
template <Volume::Type Scalars, bool LastPair, class D, class VI>
HWY_INLINE void Pair(D d, const void* data, VI base, std::int32_t offset, std::int32_t stride,
  VI lastWord, hn::Vec<D>& first, hn::Vec<D>& second)
{
  const hn::RebindToSigned<D> di;
  const auto point = hn::Add(base, hn::Set(di, offset));
  const auto index = stride == 1 ? point : hn::Mul(point, hn::Set(di, stride));
  if (Scalars == Volume::Type::Float32)
  {
    const float* f = static_cast<const float*>(data);
    first = hn::GatherIndex(d, f, index);
    second = hn::GatherIndex(d, f + stride, index);
  }
  else
  {
    constexpr int Bytes = ScalarBytes(Scalars);
    const auto at = Bytes == 1 ? index : hn::ShiftLeft<1>(index);
    VI a, b;
    ReadPair<Scalars, LastPair>(di, data, at, lastWord, stride * Bytes, a, b);
    first = hn::ConvertTo(d, a);
    second = hn::ConvertTo(d, b);
  }
}

#if HWY_TARGET != HWY_SCALAR
// Pair k (0: opacity, 1 + c: colour c) of the lanes' pieces from
// LinearPieces::Pairs, the value and its slope: one 64-bit gather per half
// vector, half the elements two 32-bit gathers would fetch (the same
// floats).
template <class D, class VI>
HWY_INLINE void PairOf(
  D d, const float* pairs, VI piece, int k, hn::Vec<D>& value, hn::Vec<D>& slope)
{
  const hn::Half<hn::RebindToSigned<D>> dh;
  const hn::Repartition<std::int64_t, D> d64;
  const hn::RebindToUnsigned<decltype(d64)> du64;
  const auto* words = reinterpret_cast<const std::uint64_t*>(pairs);
  auto half = [&](hn::Vec<decltype(dh)> p)
  {
    const auto index = hn::Add(hn::ShiftLeft<2>(hn::PromoteTo(d64, p)), hn::Set(d64, k));
    return hn::BitCast(d, hn::GatherIndex(du64, words, index));
  };
  const auto lo = half(hn::LowerHalf(dh, piece)), hi = half(hn::UpperHalf(dh, piece));
  value = hn::ConcatEven(d, hi, lo);
  slope = hn::ConcatOdd(d, hi, lo);
}
#endif

// alpha_i and C_i of the samples at (px, py, pz), dt: one vector of lanes.
template <Volume::Type Scalars, class D>
HWY_INLINE void Classify(D d, const Volume& volume, const TransferTable& tf, hn::Vec<D> px,
  hn::Vec<D> py, hn::Vec<D> pz, hn::Vec<D> dt, float* alpha, float* r, float* g, float* b)
{
  const hn::RebindToSigned<D> di;
  const int nx = volume.Dimensions[0], ny = volume.Dimensions[1], nz = volume.Dimensions[2];
  const std::int32_t sy = nx, sz = nx * ny;
  // Cell and fraction per axis, clamped onto the box as TrilinearVolume does.
  auto locate = [&](hn::Vec<D> p, int n, decltype(hn::Zero(di))& cell)
  {
    const auto x = hn::Min(hn::Max(p, hn::Zero(d)), hn::Set(d, float(n - 1)));
    cell = hn::Min(hn::ConvertTo(di, x), hn::Set(di, n - 2));
    return hn::Sub(x, hn::ConvertTo(d, cell));
  };
  decltype(hn::Zero(di)) ix, iy, iz;
  const auto fx = locate(px, nx, ix);
  const auto fy = locate(py, ny, iy);
  const auto fz = locate(pz, nz, iz);
  const auto base =
    hn::Add(hn::Add(ix, hn::Mul(iy, hn::Set(di, sy))), hn::Mul(iz, hn::Set(di, sz)));
  const auto lastWord = hn::Set(di, Scalars == Volume::Type::Float32 ? 0 : LastWord(volume));
  hn::Vec<D> v000, v100, v010, v110, v001, v101, v011, v111;
  const std::int32_t stride = volume.Stride;
  Pair<Scalars, false>(d, volume.Data, base, 0, stride, lastWord, v000, v100);
  Pair<Scalars, false>(d, volume.Data, base, sy, stride, lastWord, v010, v110);
  Pair<Scalars, false>(d, volume.Data, base, sz, stride, lastWord, v001, v101);
  Pair<Scalars, true>(d, volume.Data, base, sz + sy, stride, lastWord, v011, v111);
  const auto v00 = hn::MulAdd(fx, hn::Sub(v100, v000), v000);
  const auto v10 = hn::MulAdd(fx, hn::Sub(v110, v010), v010);
  const auto v01 = hn::MulAdd(fx, hn::Sub(v101, v001), v001);
  const auto v11 = hn::MulAdd(fx, hn::Sub(v111, v011), v011);
  const auto v0 = hn::MulAdd(fy, hn::Sub(v10, v00), v00);
  const auto v1 = hn::MulAdd(fy, hn::Sub(v11, v01), v01);
  // A sample in a cell with a NaN corner is NaN: transparent, as in every
  // method. Its lanes search the table with a finite stand-in and are
  // zeroed at the end. (Only float scalars can hold a NaN.)
  const auto sampled = hn::MulAdd(fz, hn::Sub(v1, v0), v0);
  constexpr bool floats = Scalars == Volume::Type::Float32;
  const auto undefined = floats ? hn::IsNaN(sampled) : hn::FirstN(d, 0);
  const auto s = floats ? hn::IfThenZeroElse(undefined, sampled) : sampled;

  // The piece: the number of knots at or below s (std::upper_bound's answer).
  const std::int32_t m = static_cast<std::int32_t>(tf.Knots.size());
  const float* knots = tf.Knots.data();
  const auto one = hn::Set(di, 1);
  // A table that fits in one vector is searched by comparisons and read by
  // lane permutations; a larger one per scalar unit (integer knots) or
  // through the bucket grid, and gathers.
  const bool inRegisters = m + 1 <= static_cast<std::int32_t>(hn::Lanes(d));
  const bool unit = !inRegisters && tf.UnitCount > 0;
  auto piece = hn::Zero(di);
  auto start = hn::Zero(d); // the unit piece's first scalar
  if (inRegisters)
  {
    for (std::int32_t k = 0; k < m; ++k)
    {
      piece = hn::Add(
        piece, hn::IfThenElseZero(hn::RebindMask(di, hn::Le(hn::Set(d, knots[k]), s)), one));
    }
  }
  else if (unit)
  {
    // floor(s) - first knot + 1, clamped to [0, UnitCount] (s clamped first
    // so that the conversion never overflows).
    const auto origin = hn::Set(d, tf.UnitOrigin);
    const auto local = hn::Min(
      hn::Max(hn::Sub(s, origin), hn::Set(d, -1.0f)), hn::Set(d, static_cast<float>(tf.UnitCount)));
    const auto floor = hn::Floor(local);
    piece = hn::Min(
      hn::Max(hn::Add(hn::ConvertTo(di, floor), one), hn::Zero(di)), hn::Set(di, tf.UnitCount));
    start = hn::Add(origin, floor);
  }
  else
  {
    // The bucket's guess, then corrected up and down (exact whatever its
    // rounding).
    const auto scaled = hn::Mul(hn::Sub(s, hn::Set(d, knots[0])), hn::Set(d, tf.BucketScale));
    const auto last = static_cast<std::int32_t>(tf.Buckets.size() - 1);
    const auto bucket =
      hn::Min(hn::ConvertTo(di, hn::Min(hn::Max(scaled, hn::Zero(d)), hn::Set(d, float(last)))),
        hn::Set(di, last));
    piece = hn::GatherIndex(di, tf.Buckets.data(), bucket);
    for (;;)
    {
      const auto knot = hn::GatherIndex(d, knots, hn::Min(piece, hn::Set(di, m - 1)));
      const auto up = hn::And(hn::Lt(piece, hn::Set(di, m)), hn::RebindMask(di, hn::Le(knot, s)));
      if (hn::AllFalse(di, up))
      {
        break;
      }
      piece = hn::Add(piece, hn::IfThenElseZero(up, one));
    }
    for (;;)
    {
      const auto knot = hn::GatherIndex(d, knots, hn::Max(hn::Sub(piece, one), hn::Zero(di)));
      const auto down = hn::And(hn::Gt(piece, hn::Zero(di)), hn::RebindMask(di, hn::Gt(knot, s)));
      if (hn::AllFalse(di, down))
      {
        break;
      }
      piece = hn::Sub(piece, hn::IfThenElseZero(down, one));
    }
  }
  const auto indices = hn::IndicesFromVec(d, inRegisters ? piece : hn::Zero(di));
  auto field = [&](const std::vector<float>& v)
  {
    // The tables are padded to a whole vector (TransferTable::Build).
    return inRegisters ? hn::TableLookupLanes(hn::LoadU(d, v.data()), indices)
                       : hn::GatherIndex(d, v.data(), piece);
  };
  // The offset into the piece: per unit, from the floor (the end pieces have
  // zero slopes); otherwise clamped to the piece, as TransferFunction does.
  const auto dd = unit
    ? hn::Sub(s, start)
    : hn::Min(hn::Max(hn::Sub(s, field(tf.Start)), hn::Zero(d)), field(tf.Length));
  const LinearPieces& values = unit ? tf.Units : tf.Pieces;
  // Gathered tables with 8 lanes or more: a value and its slope at once.
  auto linear = [&](int k, const std::vector<float>& value, const std::vector<float>& slope)
  {
#if HWY_TARGET != HWY_SCALAR
    if constexpr (hn::MaxLanes(D()) >= 8)
    {
      if (!inRegisters)
      {
        hn::Vec<D> v, gradient;
        PairOf(d, values.Pairs.data(), piece, k, v, gradient);
        return hn::MulAdd(gradient, dd, v);
      }
    }
#else
    (void)k;
#endif
    return hn::MulAdd(field(slope), dd, field(value));
  };
  const auto opacity = linear(0, values.Opacity, values.OpacitySlope);
  auto tau = opacity;
  if (tf.Alpha)
  {
    // tau = -ln(1 - alpha) / d, opaque from alpha 1 on (log's argument kept
    // positive in the lanes the select discards).
    const auto opaque = hn::Set(d, tf.OpaqueExtinction);
    const auto rest = hn::Max(hn::Sub(hn::Set(d, 1.0f), opacity), hn::Set(d, 1e-30f));
    const auto depth = hn::Min(hn::Neg(hn::Log(d, rest)), opaque);
    tau = hn::Mul(
      hn::IfThenElse(hn::Ge(opacity, hn::Set(d, 1.0f)), opaque, depth), hn::Set(d, tf.InverseUnit));
  }
  const auto a = hn::Neg(hn::Expm1(d, hn::Neg(hn::Mul(tau, dt))));
  auto defined = [&](hn::Vec<D> v) { return floats ? hn::IfThenZeroElse(undefined, v) : v; };
  hn::Store(defined(a), d, alpha);
  float* out[3] = { r, g, b };
  for (int c = 0; c < 3; ++c)
  {
    hn::Store(defined(linear(1 + c, values.Colour[c], values.ColourSlope[c])), d, out[c]);
  }
}

// t_i = min(i h, D), and D itself for the last index n (IntegrateRiemann's
// sample positions), in double.
inline double SampleAt(long i, long n, double h, double D)
{
  return i == n ? D : std::min(double(i) * h, D);
}

// The same for double lanes (sample indices i, last indices n, lengths D):
// the samples' steps and positions origin + t_i direction, rounded to float
// into dt, px, py, pz. A lane's values depend on its own index and ray only.
template <class DD, class V = hn::Vec<DD>>
HWY_INLINE void Positions(DD dd, V i, V n, V D, double h, const V (&origin)[3],
  const V (&direction)[3], float* dt, float* px, float* py, float* pz)
{
  const hn::Rebind<float, DD> df;
  const auto t = hn::IfThenElse(hn::Eq(i, n), D, hn::Min(hn::Mul(i, hn::Set(dd, h)), D));
  const auto step = hn::Sub(t, hn::Mul(hn::Sub(i, hn::Set(dd, 1.0)), hn::Set(dd, h)));
  hn::Store(hn::DemoteTo(df, step), df, dt);
  float* positions[3] = { px, py, pz };
  for (int a = 0; a < 3; ++a)
  {
    hn::Store(hn::DemoteTo(df, hn::MulAdd(t, direction[a], origin[a])), df, positions[a]);
  }
}

template <Volume::Type Scalars>
void Cast(const Volume& volume, const TransferTable& tf, const double* origin,
  const double* direction, double D, double h, const numerics::Interval<double>* segments,
  std::size_t count, double terminationBound, RayOutput& out)
{
  const hn::ScalableTag<float> d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  // Zeroed once per ray: Classify fills every lane before it is read, which
  // the compiler cannot see through the bisection that sizes a vector.
  HWY_ALIGN float alpha[MaximumLanes] = {}, r[MaximumLanes] = {}, g[MaximumLanes] = {},
                  b[MaximumLanes] = {};
  HWY_ALIGN float px[MaximumLanes], py[MaximumLanes], pz[MaximumLanes], dt[MaximumLanes];
  const hn::ScalableTag<double> dd;
  const int doubleLanes = static_cast<int>(hn::Lanes(dd));
  out = RayOutput();
  if (!(D > 0.0) || !(h > 0.0))
  {
    return;
  }
  const hn::Vec<decltype(dd)> o[3] = { hn::Set(dd, origin[0]), hn::Set(dd, origin[1]),
    hn::Set(dd, origin[2]) };
  const hn::Vec<decltype(dd)> v[3] = { hn::Set(dd, direction[0]), hn::Set(dd, direction[1]),
    hn::Set(dd, direction[2]) };
  const double bound = terminationBound / std::max(1.0, tf.MaximumColor);
  double color[3] = { 0.0, 0.0, 0.0 };
  double T = 1.0;
  const long n = static_cast<long>(std::ceil(D / h));
  long next = 1; // the first sample index not yet taken
  bool done = false;
  for (std::size_t j = 0; j < count && next <= n && !done; ++j)
  {
    next = std::max({ next, static_cast<long>(std::ceil(segments[j].Begin / h)), 1L });
    while (next <= n && !done)
    {
      // The lanes' samples: consecutive indices, as long as they lie in the
      // segment (the first outside ends it: the same test, in double, as
      // IntegrateRiemann's). t_i never decreases with i (a product by h > 0
      // rounds monotonically, t_n = D is the largest), so the last index in
      // the segment is found by bisection, after one test in the usual case
      // of a vector wholly inside.
      auto inside = [&](long i) { return SampleAt(i, n, h, D) <= segments[j].End; };
      long last = std::min(next + lanes - 1, n); // the last index inside
      if (!inside(last))
      {
        long below = next - 1; // inside, or before the vector
        while (last - below > 1)
        {
          const long middle = below + (last - below) / 2;
          (inside(middle) ? below : last) = middle;
        }
        last = below;
      }
      const int used = static_cast<int>(last - next + 1);
      if (used == 0)
      {
        break;
      }
      // Positions and steps in double, as IntegrateRiemann's, then rounded
      // to float: each lane's value depends on its sample index only, so the
      // vectors' grouping (which the segments shift) changes no bit.
      for (int k = 0; k < lanes; k += doubleLanes)
      {
        Positions(dd, hn::Iota(dd, double(next + k)), hn::Set(dd, double(n)), hn::Set(dd, D), h, o,
          v, dt + k, px + k, py + k, pz + k);
      }
      Classify<Scalars>(d, volume, tf, hn::Load(d, px), hn::Load(d, py), hn::Load(d, pz),
        hn::Load(d, dt), alpha, r, g, b);
      for (int k = 0; k < used; ++k)
      {
        const double a = alpha[k];
        color[0] += T * a * r[k];
        color[1] += T * a * g[k];
        color[2] += T * a * b[k];
        T *= 1.0 - a;
        ++out.Samples;
        if (T <= bound)
        {
          done = true;
          break;
        }
      }
      next += used;
      if (used < lanes)
      {
        break; // the segment (or the ray) ends inside this vector
      }
    }
  }
  for (int c = 0; c < 3; ++c)
  {
    out.RGBA[c] = color[c];
  }
  out.RGBA[3] = 1.0 - T;
}

template <Volume::Type Scalars>
void CastRays(const Volume& volume, const TransferTable& tf, double h, double terminationBound,
  const RiemannRay* rays, std::size_t count, RayOutput* out)
{
  const hn::ScalableTag<float> d;
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> dfHalf;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const int doubleLanes = static_cast<int>(hn::Lanes(dd));
  for (std::size_t i = 0; i < count; ++i)
  {
    out[i] = RayOutput();
  }
  if (!(h > 0.0))
  {
    return;
  }
  const double bound = terminationBound / std::max(1.0, tf.MaximumColor);
  // Each lane's state: the next sample index I and the last one of the
  // segment it samples (I > Last: no sample left there), its ray's setup,
  // T, colour and samples taken.
  HWY_ALIGN double I[MaximumLanes], Last[MaximumLanes], N[MaximumLanes], Length[MaximumLanes],
    O[3][MaximumLanes], Dir[3][MaximumLanes], T[MaximumLanes], C[3][MaximumLanes],
    Samples[MaximumLanes];
  HWY_ALIGN float px[MaximumLanes], py[MaximumLanes], pz[MaximumLanes], dt[MaximumLanes];
  HWY_ALIGN float alpha[MaximumLanes] = {}, r[MaximumLanes] = {}, g[MaximumLanes] = {},
                  b[MaximumLanes] = {};
  constexpr std::size_t None = ~std::size_t(0);
  std::size_t ray[MaximumLanes], segment[MaximumLanes];
  std::size_t nextRay = 0;
  int live = 0; // lanes with a ray
  auto idle = [&](int k)
  {
    ray[k] = None;
    I[k] = 1.0;
    Last[k] = 0.0;
    N[k] = Length[k] = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      O[a][k] = Dir[a][k] = 0.0;
    }
    T[k] = 1.0;
  };
  // Lane k on to its ray's next segment with a sample left (CastRiemann's
  // order: the first index at or after the segment's start, the samples up
  // to the first outside it), else its ray's output and the next ray.
  auto advance = [&](int k)
  {
    for (;;)
    {
      if (ray[k] != None)
      {
        const RiemannRay& q = rays[ray[k]];
        const long n = static_cast<long>(N[k]);
        long next = static_cast<long>(I[k]);
        while (T[k] > bound && segment[k] < q.Count && next <= n)
        {
          const numerics::Interval<double>& s = q.Segments[segment[k]];
          next = std::max({ next, static_cast<long>(std::ceil(s.Begin / h)), 1L });
          auto inside = [&](long i) { return SampleAt(i, n, h, q.D) <= s.End; };
          // t_i never decreases with i: the last index inside, from a guess.
          long last = static_cast<long>(
            std::max(std::min(double(n), std::floor(s.End / h)), double(next - 1)));
          while (last < n && inside(last + 1))
          {
            ++last;
          }
          while (last >= next && !inside(last))
          {
            --last;
          }
          if (next <= last)
          {
            I[k] = double(next);
            Last[k] = double(last);
            return;
          }
          ++segment[k];
        }
        RayOutput& o = out[ray[k]];
        for (int c = 0; c < 3; ++c)
        {
          o.RGBA[c] = C[c][k];
        }
        o.RGBA[3] = 1.0 - T[k];
        o.Samples = static_cast<long>(Samples[k]);
        --live;
      }
      if (nextRay == count)
      {
        idle(k);
        return;
      }
      const RiemannRay& q = rays[nextRay];
      ray[k] = nextRay++;
      ++live;
      segment[k] = 0;
      Length[k] = q.D;
      N[k] = q.D > 0.0 ? std::ceil(q.D / h) : 0.0;
      I[k] = 1.0;
      for (int a = 0; a < 3; ++a)
      {
        O[a][k] = q.Origin[a];
        Dir[a][k] = q.Direction[a];
        C[a][k] = 0.0;
      }
      T[k] = 1.0;
      Samples[k] = 0.0;
    }
  };
  for (int k = 0; k < lanes; ++k)
  {
    idle(k);
    advance(k);
  }
  while (live > 0)
  {
    for (int k = 0; k < lanes; k += doubleLanes)
    {
      const hn::Vec<decltype(dd)> o[3] = { hn::Load(dd, O[0] + k), hn::Load(dd, O[1] + k),
        hn::Load(dd, O[2] + k) };
      const hn::Vec<decltype(dd)> v[3] = { hn::Load(dd, Dir[0] + k), hn::Load(dd, Dir[1] + k),
        hn::Load(dd, Dir[2] + k) };
      Positions(dd, hn::Load(dd, I + k), hn::Load(dd, N + k), hn::Load(dd, Length + k), h, o, v,
        dt + k, px + k, py + k, pz + k);
    }
    Classify<Scalars>(d, volume, tf, hn::Load(d, px), hn::Load(d, py), hn::Load(d, pz),
      hn::Load(d, dt), alpha, r, g, b);
    bool service = false;
    const float* colour[3] = { r, g, b };
    for (int k = 0; k < lanes; k += doubleLanes)
    {
      auto i = hn::Load(dd, I + k);
      const auto last = hn::Load(dd, Last + k);
      const auto active = hn::Le(i, last);
      const auto a = hn::IfThenElseZero(active, hn::PromoteTo(dd, hn::Load(dfHalf, alpha + k)));
      auto transmittance = hn::Load(dd, T + k);
      const auto weight = hn::Mul(transmittance, a);
      for (int c = 0; c < 3; ++c)
      {
        hn::Store(hn::MulAdd(weight, hn::PromoteTo(dd, hn::Load(dfHalf, colour[c] + k)),
                    hn::Load(dd, C[c] + k)),
          dd, C[c] + k);
      }
      transmittance = hn::Mul(transmittance, hn::Sub(hn::Set(dd, 1.0), a));
      hn::Store(transmittance, dd, T + k);
      const auto taken = hn::IfThenElseZero(active, hn::Set(dd, 1.0));
      hn::Store(hn::Add(hn::Load(dd, Samples + k), taken), dd, Samples + k);
      i = hn::Add(i, taken);
      hn::Store(i, dd, I + k);
      service = service ||
        !hn::AllFalse(
          dd, hn::And(active, hn::Or(hn::Gt(i, last), hn::Le(transmittance, hn::Set(dd, bound)))));
    }
    if (service)
    {
      for (int k = 0; k < lanes; ++k)
      {
        if (ray[k] != None && (I[k] > Last[k] || T[k] <= bound))
        {
          advance(k);
        }
      }
    }
  }
}

void CastRiemannRaysImpl(const Volume& volume, const TransferTable& tf, double h,
  double terminationBound, const RiemannRay* rays, std::size_t count, RayOutput* out)
{
  switch (volume.Scalars)
  {
    case Volume::Type::UInt8:
      return CastRays<Volume::Type::UInt8>(volume, tf, h, terminationBound, rays, count, out);
    case Volume::Type::UInt16:
      return CastRays<Volume::Type::UInt16>(volume, tf, h, terminationBound, rays, count, out);
    case Volume::Type::Int8:
      return CastRays<Volume::Type::Int8>(volume, tf, h, terminationBound, rays, count, out);
    case Volume::Type::Int16:
      return CastRays<Volume::Type::Int16>(volume, tf, h, terminationBound, rays, count, out);
    default:
      return CastRays<Volume::Type::Float32>(volume, tf, h, terminationBound, rays, count, out);
  }
}

void CastRiemannImpl(const Volume& volume, const TransferTable& tf, const double* origin,
  const double* direction, double D, double h, const numerics::Interval<double>* segments,
  std::size_t count, double terminationBound, RayOutput& out)
{
  switch (volume.Scalars)
  {
    case Volume::Type::UInt8:
      return Cast<Volume::Type::UInt8>(
        volume, tf, origin, direction, D, h, segments, count, terminationBound, out);
    case Volume::Type::UInt16:
      return Cast<Volume::Type::UInt16>(
        volume, tf, origin, direction, D, h, segments, count, terminationBound, out);
    case Volume::Type::Int8:
      return Cast<Volume::Type::Int8>(
        volume, tf, origin, direction, D, h, segments, count, terminationBound, out);
    case Volume::Type::Int16:
      return Cast<Volume::Type::Int16>(
        volume, tf, origin, direction, D, h, segments, count, terminationBound, out);
    default:
      return Cast<Volume::Type::Float32>(
        volume, tf, origin, direction, D, h, segments, count, terminationBound, out);
  }
}

const char* TargetNameImpl()
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
HWY_EXPORT(CastRiemannImpl);
HWY_EXPORT(TargetNameImpl);
HWY_EXPORT(CastRiemannRaysImpl);

void CastRiemannRays(const Volume& volume, const TransferTable& tf, double h,
  double terminationBound, const RiemannRay* rays, std::size_t count, RayOutput* out)
{
  HWY_DYNAMIC_DISPATCH(CastRiemannRaysImpl)(volume, tf, h, terminationBound, rays, count, out);
}

void CastRiemann(const Volume& volume, const TransferTable& tf, const double origin[3],
  const double direction[3], double D, double h, const numerics::Interval<double>* segments,
  std::size_t count, double terminationBound, RayOutput& out)
{
  HWY_DYNAMIC_DISPATCH(CastRiemannImpl)
  (volume, tf, origin, direction, D, h, segments, count, terminationBound, out);
}

const char* CastRiemannTarget()
{
  return HWY_DYNAMIC_DISPATCH(TargetNameImpl)();
}

std::string Validate(const Volume& volume)
{
  double points = 1.0;
  for (int a = 0; a < 3; ++a)
  {
    if (volume.Dimensions[a] < 2)
    {
      return "the volume needs at least 2 points along each axis";
    }
    points *= volume.Dimensions[a];
  }
  if (volume.Stride < 1 || volume.Trailing < 0 || volume.Trailing >= volume.Stride)
  {
    return "a volume's stride must be at least 1 and hold its trailing scalars";
  }
  // 16-bit scalars are gathered by byte offset: twice the index.
  const bool words =
    volume.Scalars == Volume::Type::UInt16 || volume.Scalars == Volume::Type::Int16;
  const double scalars = (points - 1.0) * volume.Stride + 1.0 + volume.Trailing;
  if (scalars * (words ? 2.0 : 1.0) > double(std::numeric_limits<std::int32_t>::max()))
  {
    return "the vectorised kernels take at most 2^31 - 1 scalars (2^30 of 16-bit ones: 32-bit "
           "gather offsets)";
  }
  return volume.Data ? std::string() : "the volume has no data";
}

void LinearPieces::Clear()
{
  for (std::vector<float>* v :
    { &this->Opacity, &this->OpacitySlope, &this->Colour[0], &this->Colour[1], &this->Colour[2],
      &this->ColourSlope[0], &this->ColourSlope[1], &this->ColourSlope[2], &this->Pairs })
  {
    v->clear();
  }
}

void LinearPieces::Add(
  double opacity, double opacitySlope, const glm::dvec3& colour, const glm::dvec3& colourSlope)
{
  this->Opacity.push_back(float(opacity));
  this->OpacitySlope.push_back(float(opacitySlope));
  this->Pairs.push_back(float(opacity));
  this->Pairs.push_back(float(opacitySlope));
  for (int c = 0; c < 3; ++c)
  {
    this->Colour[c].push_back(float(colour[c]));
    this->ColourSlope[c].push_back(float(colourSlope[c]));
    this->Pairs.push_back(float(colour[c]));
    this->Pairs.push_back(float(colourSlope[c]));
  }
}

void LinearPieces::Pad(std::size_t size)
{
  for (std::vector<float>* v :
    { &this->Opacity, &this->OpacitySlope, &this->Colour[0], &this->Colour[1], &this->Colour[2],
      &this->ColourSlope[0], &this->ColourSlope[1], &this->ColourSlope[2] })
  {
    v->resize(std::max(v->size(), size), 0.0f);
  }
  this->Pairs.resize(std::max(this->Pairs.size(), 8 * size), 0.0f);
}

std::string TransferTable::Build(const numerics::TransferFunction<double>& tf)
{
  const std::string error = tf.Validate();
  if (!error.empty())
  {
    return error;
  }
  const auto& pieces = tf.GetPieces();
  if (pieces.empty())
  {
    return "the transfer function was not finalised";
  }
  const glm::dvec3 flat(0.0), below = tf.GetColorBelow();
  this->Knots.clear();
  this->Start.clear();
  this->Length.clear();
  this->Pieces.Clear();
  // Piece 0: below the first knot, the first values held.
  this->Start.push_back(float(pieces.front().Start));
  this->Length.push_back(0.0f);
  this->Pieces.Add(tf.GetOpacityBelow(), 0.0, below, flat);
  for (const auto& p : pieces)
  {
    this->Knots.push_back(float(p.Start));
    this->Start.push_back(float(p.Start));
    this->Length.push_back(float(p.Length));
    this->Pieces.Add(p.Opacity, p.OpacitySlope, p.Colour, p.ColourSlope);
  }
  // Padded to the widest vector, so that a small table loads whole.
  const std::size_t padded = std::max<std::size_t>(this->Start.size(), 16);
  this->Start.resize(padded, 0.0f);
  this->Length.resize(padded, 0.0f);
  this->Pieces.Pad(padded);
  // About four buckets per knot: the number of knots at or below each
  // bucket's lower edge (in float, as the kernels compare).
  const std::size_t m = this->Knots.size();
  const float span = this->Knots.back() - this->Knots.front();
  const std::size_t buckets = std::min<std::size_t>(4 * m, std::size_t(1) << 16);
  this->BucketScale = span > 0.0f ? float(buckets) / span : 0.0f;
  this->Buckets.clear();
  for (std::size_t k = 0; k < buckets; ++k)
  {
    const float edge = this->Knots.front() + span * float(k) / float(buckets);
    this->Buckets.push_back(static_cast<std::int32_t>(
      std::upper_bound(this->Knots.begin(), this->Knots.end(), edge) - this->Knots.begin()));
  }
  // Per scalar unit, when every knot is an integer (at most 65536 units).
  this->UnitCount = 0;
  this->Units.Clear();
  const double first = pieces.front().Start, last = pieces.back().Start;
  const bool integral = std::all_of(pieces.begin(), pieces.end(),
    [](const numerics::TransferFunction<double>::Piece& p)
    { return p.Start == std::floor(p.Start); });
  if (integral && last - first < 65536.0)
  {
    this->UnitOrigin = static_cast<float>(first);
    this->UnitCount = static_cast<std::int32_t>(last - first) + 1;
    this->Units.Add(tf.GetOpacityBelow(), 0.0, below, flat);
    std::size_t k = 0; // the knot piece holding the unit [x, x + 1)
    for (std::int32_t u = 1; u < this->UnitCount; ++u)
    {
      const double x = first + double(u - 1);
      while (k + 1 < pieces.size() && pieces[k + 1].Start <= x)
      {
        ++k;
      }
      const auto& p = pieces[k];
      const glm::dvec3 colour = p.Colour + p.ColourSlope * (x - p.Start);
      this->Units.Add(
        p.Opacity + p.OpacitySlope * (x - p.Start), p.OpacitySlope, colour, p.ColourSlope);
    }
    this->Units.Add(pieces.back().Opacity, 0.0, pieces.back().Colour, flat);
  }
  this->Alpha = tf.GetOpacityModel() == numerics::OpacityModel::Alpha;
  this->InverseUnit = float(1.0 / tf.GetUnitDistance());
  this->OpaqueExtinction = float(numerics::TransferFunction<double>::OpaqueExtinction);
  this->MaximumColor = tf.GetMaximumColor();
  return std::string();
}

} // namespace engine
} // namespace avos
#endif
