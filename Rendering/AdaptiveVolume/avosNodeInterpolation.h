// VTK's interpolation between two nodes of a colour transfer function (or,
// in channel 0 of RGB space, of a vtkPiecewiseFunction), as a function of
// the scalar x, written once for plain numbers (double) and for enclosures
// (numerics::Jet<double>): the model with which
// avos::TransferFunctionFromProperty certifies the knots it places where
// VTK's function is not piecewise linear (numerics::Linearize).
//
// It follows vtkColorTransferFunction::GetColor and
// vtkPiecewiseFunction::GetValue (VTK 9.1): the position s in
// [0, 1] between the nodes (in log10 x for a log scale), bent at the
// midpoint (s < m: 0.5 s / m, else 0.5 + 0.5 (s - m) / (1 - m)); a sharpness
// below 0.01 then interpolates linearly in that position, one up to 0.99 a
// Hermite curve of it after the power bend 0.5 (2s)^(1 + 10 sharpness),
// clamped (Clip); in RGB, in HSV (vtkMath::HSVToRGB's six hue sectors,
// the hue wrapped below 0), in CIE L*a*b* (vtkMath::LabToRGB: the cube or
// linear branch, sRGB's gamma, scaling by the largest channel above 1, clip
// at 0), or in the diverging Msh space (Moreland's polar L*a*b*: through
// white between distinct saturated colours, the hue of an unsaturated end
// adjusted). The ends in the interpolation space are computed by VTK
// itself; TransferFunctionFromProperty checks the model against
// GetColor at every knot, so a disagreement fails the certification.
// Not wrapped: a private header of the rendering modules.
#ifndef avosNodeInterpolation_h
#define avosNodeInterpolation_h

#include "avos/numerics/Enclosure.h" // For Jet, Cases

#include <cmath>

namespace avos
{
enum class InterpolationSpace
{
  RGB,
  HSV,
  Lab,
  Diverging
};

struct NodeInterpolation
{
  double X1 = 0.0, X2 = 1.0; // the nodes' scalars, X1 < X2
  bool LogScale = false;     // s in log10 x (X1 > 0)
  double Midpoint = 0.5;     // clamped to [1e-5, 1 - 1e-5], as VTK does
  double Sharpness = 0.0;    // below 0.01: linear; up to 0.99: Hermite
  InterpolationSpace Space = InterpolationSpace::RGB;
  // The ends in the interpolation space, for bent positions below 0.5 and
  // from 0.5 on (Ends[half][end][channel]): the same twice, except where a
  // diverging map passes through white (Halves: each half then runs over
  // the whole of its ends, u = 2s or 2s - 1).
  double Ends[2][2][3] = {};
  bool Halves = false;
  // Where a Hermite curve is clamped: [0, 1] for colours, the nodes' range
  // for a vtkPiecewiseFunction (channel 0 only).
  double Clip[2] = { 0.0, 1.0 };
};

namespace interpolation
{
using Jet = numerics::Jet<double>;
using numerics::Cases;

inline double Pow(double x, double p)
{
  return std::pow(x, p);
}
inline Jet Pow(const Jet& x, double p)
{
  return numerics::Pow(x, p);
}
inline double Log10(double x)
{
  return std::log10(x);
}
inline Jet Log10(const Jet& x)
{
  return numerics::Log(x) * (1.0 / std::log(10.0));
}
inline double Sin(double x)
{
  return std::sin(x);
}
inline Jet Sin(const Jet& x)
{
  return numerics::Sin(x);
}
inline double Cos(double x)
{
  return std::cos(x);
}
inline Jet Cos(const Jet& x)
{
  return numerics::Cos(x);
}

// L*a*b*'s inverse companding: the cube above (6/29)^3 = 0.008856, a line
// below. VTK compares the cube; the enclosure compares v with the cube root
// (Cases' guard covers the rounding between the two).
inline double LabInverse(double v)
{
  const double cube = std::pow(v, 3);
  return cube > 0.008856 ? cube : (v - 16.0 / 116.0) / 7.787;
}
inline Jet LabInverse(const Jet& v)
{
  return Cases(
    v, std::cbrt(0.008856), [](const Jet& w) { return (w - 16.0 / 116.0) / 7.787; },
    [](const Jet& w) { return w * w * w; });
}

// VTK scales all three channels by the largest when it exceeds 1.
inline void ScaleToOne(double rgb[3])
{
  const double largest = std::max(rgb[0], std::max(rgb[1], rgb[2]));
  if (largest > 1.0)
  {
    for (int c = 0; c < 3; ++c)
    {
      rgb[c] /= largest;
    }
  }
}
inline void ScaleToOne(Jet rgb[3])
{
  using I = numerics::Bounds<double>;
  const I largest(std::max(rgb[0].V.Lo, std::max(rgb[1].V.Lo, rgb[2].V.Lo)),
    std::max(rgb[0].V.Hi, std::max(rgb[1].V.Hi, rgb[2].V.Hi)));
  const double guard = 1e-12;
  if (largest.Hi <= 1.0 - guard)
  {
    return;
  }
  // One channel the largest everywhere and above 1: a smooth quotient.
  for (int c = 0; c < 3; ++c)
  {
    const Jet& a = rgb[c];
    const Jet& b = rgb[(c + 1) % 3];
    const Jet& d = rgb[(c + 2) % 3];
    if (a.V.Lo > 1.0 + guard && a.V.Lo > b.V.Hi && a.V.Lo > d.V.Hi)
    {
      const Jet by = a;
      for (int k = 0; k < 3; ++k)
      {
        rgb[k] = rgb[k] / by;
      }
      return;
    }
  }
  // Otherwise each channel lies between itself and itself over [1, largest].
  const I divisor(1.0, std::max(1.0, largest.Hi));
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = Jet::Rough(numerics::Hull(rgb[c].V, rgb[c].V / divisor));
  }
}

template <typename T>
T ClipBelow(const T& v, double lo)
{
  return Cases(
    v, lo, [lo](const T&) { return T(lo); }, [](const T& w) { return w; });
}

template <typename T>
T ClipAbove(const T& v, double hi)
{
  return Cases(
    v, hi, [](const T& w) { return w; }, [hi](const T&) { return T(hi); });
}

// vtkMath::LabToRGB: L*a*b* -> XYZ (D65) -> linear sRGB -> sRGB's gamma ->
// scaled into [0, 1] by the largest channel, clipped at 0.
template <typename T>
void LabToRGB(const T& L, const T& a, const T& b, T rgb[3])
{
  const T fy = (L + 16.0) / 116.0;
  const T x = 0.9505 * LabInverse(a / 500.0 + fy);
  const T y = LabInverse(fy);
  const T z = 1.089 * LabInverse(fy - b / 200.0);
  rgb[0] = x * 3.2406 + y * -1.5372 + z * -0.4986;
  rgb[1] = x * -0.9689 + y * 1.8758 + z * 0.0415;
  rgb[2] = x * 0.0557 + y * -0.2040 + z * 1.0570;
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = Cases(
      rgb[c], 0.0031308, [](const T& v) { return 12.92 * v; },
      [](const T& v) { return 1.055 * Pow(v, 1.0 / 2.4) - 0.055; });
  }
  ScaleToOne(rgb);
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = ClipBelow(rgb[c], 0.0);
  }
}

// One channel of vtkMath::HSVToRGB's pure hue (saturation and value 1),
// linear on each sixth of the hue, for a hue in (-1, 1]: below 0 it is the
// hue plus 1 (VTK's wrap), the same colour at 0 from either side. (VTK's
// last case, a hue above 1, is never taken: the ends' hues lie in [-1, 1]
// and both the line and VTK's Hermite curve between them are monotone.)
template <typename T>
T HueChannel(const T& h, int channel)
{
  // Per sector (0,1/6], (1/6,1/3], ..., (5/6,1]: channel = a + b h.
  static constexpr double A[6][3] = { { 1, 0, 0 }, { 2, 1, 0 }, { 0, 1, -2 }, { 0, 4, 1 },
    { -4, 0, 1 }, { 1, 0, 6 } };
  static constexpr double B[6][3] = { { 0, 6, 0 }, { -6, 0, 0 }, { 0, 0, 6 }, { 0, -6, 0 },
    { 6, 0, 0 }, { 0, 0, -6 } };
  // The sectors from k on, VTK's cascade of (k/6, (k+1)/6].
  struct Cascade
  {
    int Channel;
    T operator()(const T& v, int k) const
    {
      auto line = [this, k](const T& w) { return A[k][this->Channel] + B[k][this->Channel] * w; };
      if (k == 5)
      {
        return line(v);
      }
      return Cases(v, (k + 1) / 6.0, line, [this, k](const T& w) { return (*this)(w, k + 1); });
    }
  };
  const Cascade sectors{ channel };
  return Cases(
    h, 0.0, [&](const T& v) { return sectors(v + 1.0, 0); },
    [&](const T& v) { return sectors(v, 0); });
}

// vtkMath::HSVToRGB.
template <typename T>
void HSVToRGB(const T& h, const T& s, const T& v, T rgb[3])
{
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = (s * HueChannel(h, c) + (1.0 - s)) * v;
  }
}

// Moreland's Msh -> L*a*b* -> RGB.
template <typename T>
void MshToRGB(const T& M, const T& s, const T& h, T rgb[3])
{
  const T radial = M * Sin(s);
  LabToRGB(M * Cos(s), radial * Cos(h), radial * Sin(h), rgb);
}

// The position between the nodes, bent at the midpoint.
template <typename T>
T BentPosition(const NodeInterpolation& n, const T& x)
{
  const T s = n.LogScale ? (Log10(x) - std::log10(n.X1)) / (std::log10(n.X2) - std::log10(n.X1))
                         : (x - n.X1) / (n.X2 - n.X1);
  const double m = n.Midpoint;
  return Cases(
    s, m, [m](const T& v) { return 0.5 * v / m; },
    [m](const T& v) { return 0.5 + 0.5 * (v - m) / (1.0 - m); });
}

// The interpolation-space value of channel c at position u of one half.
template <typename T>
T SpaceValue(const NodeInterpolation& n, int half, int c, const T& u, bool hermite)
{
  const double y1 = n.Ends[half][0][c], y2 = n.Ends[half][1][c];
  if (!hermite)
  {
    return (1.0 - u) * y1 + u * y2;
  }
  // VTK's Hermite curve: one slope (1 - sharpness)(y2 - y1) at both ends.
  const T uu = u * u;
  const T uuu = uu * u;
  const double slope = (1.0 - n.Sharpness) * (y2 - y1);
  return (2.0 * uuu - 3.0 * uu + 1.0) * y1 + (-2.0 * uuu + 3.0 * uu) * y2 +
    (uuu - 2.0 * uu + u) * slope + (uuu - uu) * slope;
}

/**
 * VTK's colour at x in [X1, X2] (sharpness at most 0.99: a step is not
 * modelled, it is exact without a model).
 */
template <typename T>
void Evaluate(const NodeInterpolation& n, const T& x, T rgb[3])
{
  T s = BentPosition(n, x);
  const bool hermite = n.Sharpness >= 0.01;
  if (hermite)
  {
    const double p = 1.0 + 10.0 * n.Sharpness;
    s = Cases(
      s, 0.5, [p](const T& v) { return 0.5 * Pow(2.0 * v, p); },
      [p](const T& v) { return 1.0 - 0.5 * Pow(2.0 * (1.0 - v), p); });
  }
  auto inHalf = [&](int half, const T& u, T out[3])
  {
    // The diverging map's own argument is the bent position, never the
    // Hermite value (VTK does not apply the curve there).
    const bool curve = hermite && n.Space != InterpolationSpace::Diverging;
    T v[3] = { SpaceValue(n, half, 0, u, curve), SpaceValue(n, half, 1, u, curve),
      SpaceValue(n, half, 2, u, curve) };
    switch (n.Space)
    {
      case InterpolationSpace::RGB:
        for (int c = 0; c < 3; ++c)
        {
          out[c] = v[c];
        }
        break;
      case InterpolationSpace::HSV:
        HSVToRGB(v[0], v[1], v[2], out);
        break;
      case InterpolationSpace::Lab:
        LabToRGB(v[0], v[1], v[2], out);
        break;
      case InterpolationSpace::Diverging:
        MshToRGB(v[0], v[1], v[2], out);
        break;
    }
  };
  for (int c = 0; c < 3; ++c)
  {
    // Channel by channel, so that Cases can join the halves per channel.
    rgb[c] = n.Halves ? Cases(
                          s, 0.5,
                          [&](const T& v)
                          {
                            T out[3];
                            inHalf(0, 2.0 * v, out);
                            return out[c];
                          },
                          [&](const T& v)
                          {
                            T out[3];
                            inHalf(1, 2.0 * v - 1.0, out);
                            return out[c];
                          })
                      : [&]()
    {
      T out[3];
      inHalf(0, s, out);
      return out[c];
    }();
  }
  if (hermite)
  {
    for (int c = 0; c < 3; ++c)
    {
      rgb[c] = ClipAbove(ClipBelow(rgb[c], n.Clip[0]), n.Clip[1]);
    }
  }
}
} // namespace interpolation
} // namespace avos

#endif
