// Adversarial volumes of several components (Mixture.h) and an independent
// oracle of their rays, shared by the numerical core's tests (few rays) and
// avos-bench-accuracy (many).
//
// The oracle cuts a ray at every cell face and at every knot crossing of
// each component it reads (PieceWalk of a function with the component's
// knots, every piece visible), so the integrand is smooth between cuts;
// there, in parts over which the depth grows by at most 1/8, it integrates
// the emission tau C of MixtureTransferFunction::Classify at the sampled
// components, times e^{-theta}, by adaptive Gauss-Legendre (1e-14 a part),
// theta(v) by 8-point Gauss-Legendre from the part's start (exact for the
// extinction model's cubics): none of the piecewise method's polynomials,
// by-parts forms or series.
#ifndef avos_numerics_MixtureCases_h
#define avos_numerics_MixtureCases_h

#include "AdversarialCases.h"

#include "avos/numerics/Accumulation.h"
#include "avos/numerics/Mixture.h"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace mixture
{
namespace an = avos::numerics;
using Volume = an::TrilinearVolume<double, double>;
using Volumes = an::ComponentVolumes<double, Volume>;

struct Case
{
  std::string Name;
  int Dimensions[3] = { 0, 0, 0 };
  int Components = 0;
  std::vector<double> Data; // interleaved: Components values per point
  an::ComponentMix Mix = an::ComponentMix::Independent;
  std::array<an::TransferFunction<double>, 4> TF; // one per component (dependent: TF[0])
  double Weights[4] = { 1.0, 1.0, 1.0, 1.0 };
  double Scale = 1.0 / 255.0; // RGBOpacity

  an::MixtureTransferFunction<double> Mixture() const
  {
    an::MixtureTransferFunction<double> m;
    if (this->Mix == an::ComponentMix::Independent)
    {
      const an::TransferFunction<double>* f[4] = { &this->TF[0], &this->TF[1], &this->TF[2],
        &this->TF[3] };
      m.SetIndependent(this->Components, f, this->Weights);
    }
    else if (this->Mix == an::ComponentMix::ColourOpacity)
    {
      m.SetColourOpacity(this->TF[0]);
    }
    else
    {
      m.SetRGBOpacity(this->TF[0], this->Scale);
    }
    return m;
  }

  Volumes MakeVolumes() const
  {
    return Volumes(this->Components,
      [this](int k) { return Volume(this->Data.data() + k, this->Dimensions, this->Components); });
  }
};

// Interleaves the adversarial suite's single volumes (same dimensions).
inline Case Interleave(const std::string& name, const std::vector<adversarial::Case>& parts)
{
  Case c;
  c.Name = name;
  std::copy(parts[0].Dimensions, parts[0].Dimensions + 3, c.Dimensions);
  c.Components = static_cast<int>(parts.size());
  const std::size_t n = parts[0].Data.size();
  c.Data.resize(n * parts.size());
  for (std::size_t i = 0; i < n; ++i)
  {
    for (std::size_t k = 0; k < parts.size(); ++k)
    {
      c.Data[i * parts.size() + k] = parts[k].Data[i];
    }
  }
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    c.TF[k] = parts[k].TF;
  }
  return c;
}

// The suite: independent components overlapping (thin spikes on binary and
// two-material data; steps and random functions on smooth fields with
// weights), and both dependent mixtures.
inline std::vector<Case> MakeSuite()
{
  using adversarial::MakeVolume;
  std::vector<Case> cases;
  {
    adversarial::Case a = MakeVolume("binary", adversarial::Binary, 7);
    a.TF = adversarial::Spike(127.5, 1.0, 20.0);
    adversarial::Case b = MakeVolume("two materials", adversarial::TwoMaterial, 11);
    b.TF = adversarial::Spike(125.0, 5.0, 10.0);
    cases.push_back(Interleave("binary spike 1 + two materials spike 5", { a, b }));
  }
  {
    adversarial::Case a = MakeVolume("Marschner-Lobb", adversarial::MarschnerLobb, 0);
    a.TF = adversarial::Steps();
    adversarial::Case b = MakeVolume("smooth", adversarial::Smooth, 9);
    b.TF = adversarial::Random(13, 64, 3.0);
    Case c =
      Interleave("Marschner-Lobb steps + smooth random 64 knots, weights 0.7, 1.5", { a, b });
    c.Weights[0] = 0.7;
    c.Weights[1] = 1.5;
    cases.push_back(std::move(c));
  }
  {
    adversarial::Case a = MakeVolume("smooth", adversarial::Smooth, 3);
    adversarial::Case b = MakeVolume("binary", adversarial::Binary, 7);
    adversarial::Case s = MakeVolume("smooth", adversarial::Smooth, 5);
    a.TF = b.TF = s.TF = adversarial::Random(5, 16, 2.0);
    Case c = Interleave("three components: smooth, binary, smooth; random 16 knots", { a, b, s });
    c.Weights[2] = 0.5;
    cases.push_back(std::move(c));
  }
  {
    adversarial::Case colour = MakeVolume("smooth", adversarial::Smooth, 3);
    adversarial::Case opacity = MakeVolume("two materials", adversarial::TwoMaterial, 11);
    Case c = Interleave(
      "colour of smooth (17 knots), opacity of two materials (steps)", { colour, opacity });
    c.Mix = an::ComponentMix::ColourOpacity;
    // The steps' opacity (of s_1: visible over the upper material), and
    // seventeen colour knots of its own (of s_0).
    an::TransferFunction<double> tf;
    for (const auto& knot : { std::pair<double, double>{ 0.0, 0.0 }, { 128.0, 0.0 }, { 128.0, 0.8 },
           { 200.0, 0.8 }, { 200.0, 4.0 }, { 255.0, 4.0 } })
    {
      tf.AddOpacityKnot(knot.first, knot.second);
    }
    for (int i = 0; i <= 16; ++i)
    {
      tf.AddColorKnot(255.0 * i / 16.0, (i % 3) / 2.0, (i % 2) * 1.0, 1.0 - i / 16.0);
    }
    tf.Finalize();
    c.TF[0] = tf;
    cases.push_back(std::move(c));
  }
  {
    std::vector<adversarial::Case> parts;
    parts.push_back(MakeVolume("smooth", adversarial::Smooth, 21));
    parts.push_back(MakeVolume("smooth", adversarial::Smooth, 22));
    parts.push_back(MakeVolume("Marschner-Lobb", adversarial::MarschnerLobb, 0));
    parts.push_back(MakeVolume("binary", adversarial::Binary, 7));
    Case c = Interleave("RGB of smooth, smooth, Marschner-Lobb; opacity of binary (steps)", parts);
    c.Mix = an::ComponentMix::RGBOpacity;
    c.TF[0] = adversarial::Steps();
    cases.push_back(std::move(c));
  }
  return cases;
}

// The components a case's mixture reads (a mask).
inline unsigned ReadMask(const Case& c)
{
  if (c.Mix == an::ComponentMix::Independent)
  {
    unsigned mask = 0;
    for (int k = 0; k < c.Components; ++k)
    {
      mask |= c.Weights[k] > 0.0 ? (1u << k) : 0u;
    }
    return mask;
  }
  return c.Mix == an::ComponentMix::ColourOpacity ? 3u : 15u;
}

// The exact RGBA of the ray (see above).
inline glm::dvec4 Exact(const Case& c, const adversarial::Ray& ray)
{
  const Volumes volumes = c.MakeVolumes();
  const an::MixtureTransferFunction<double> mixture = c.Mixture();
  // Cuts: the ends, and every piece of each component read through a
  // function (every cell of the ray, its knot crossings; the RGB channels,
  // smooth in a cell, share the opacity's cells).
  std::vector<double> cuts{ 0.0, ray.Length };
  const unsigned read = ReadMask(c);
  for (int k = 0; k < c.Components; ++k)
  {
    const bool rgb = c.Mix == an::ComponentMix::RGBOpacity && k < 3;
    if (!((read >> k) & 1u) || rgb)
    {
      continue;
    }
    const an::TransferFunction<double>& tf = c.TF[c.Mix == an::ComponentMix::Independent ? k : 0];
    an::TransferFunction<double> everywhere;
    for (double s : tf.GetKnotValues())
    {
      everywhere.AddOpacityKnot(s, 1.0);
      everywhere.AddColorKnot(s, 0.0, 0.0, 0.0);
    }
    everywhere.Finalize();
    an::PiecewiseTransferFunction<double> pieces;
    pieces.Build(everywhere, 1e-7);
    long cells = 0;
    an::PieceWalk(volumes[k], ray.Origin, ray.Direction, 0.0, ray.Length, pieces, cells,
      [&](const an::RayPiece<double>& p)
      {
        cuts.push_back(p.Begin);
        cuts.push_back(p.Begin + p.Length);
        return true;
      });
  }
  std::sort(cuts.begin(), cuts.end());
  auto sample = [&](double t, double& tau, glm::dvec3& colour)
  { mixture.Classify(volumes(ray.Origin + t * ray.Direction), tau, colour); };
  using G = an::detail::GaussLegendre<double>;
  auto depth = [&](double a, double b)
  {
    return an::detail::Quadrature(G::N8, G::W8, a, b,
      [&](double t)
      {
        double tau;
        glm::dvec3 colour;
        sample(t, tau, colour);
        return tau;
      });
  };
  glm::dvec3 colour(0.0);
  double T = 1.0;
  std::function<void(double, double)> part = [&](double a, double b)
  {
    const double theta = depth(a, b);
    if (theta > 0.125 && b - a > 1e-9)
    {
      part(a, 0.5 * (a + b));
      part(0.5 * (a + b), b);
      return;
    }
    for (int ch = 0; ch < 3; ++ch)
    {
      colour[ch] += T *
        an::detail::AdaptiveGauss(a, b, 1e-14, 0,
          [&](double t)
          {
            double tau;
            glm::dvec3 rgb;
            sample(t, tau, rgb);
            return tau * rgb[ch] * std::exp(-depth(a, t));
          });
    }
    T *= std::exp(-theta);
  };
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
  {
    if (cuts[i + 1] > cuts[i])
    {
      part(cuts[i], cuts[i + 1]);
    }
  }
  return glm::dvec4(colour, 1.0 - T);
}

// Ray i of a case (the adversarial suite's rays of the same grid).
inline adversarial::Ray MakeRay(const Case& c, unsigned i)
{
  std::mt19937 rng(i * 2654435761u + 99u);
  return adversarial::RandomRay(c.Dimensions, rng, 1.0);
}

// The piecewise method's RGBA of the ray at `eps`.
inline an::RayResult<double> Piecewise(const Case& c, const an::PiecewiseMixture<double>& pieces,
  const adversarial::Ray& ray, double eps)
{
  const Volumes volumes = c.MakeVolumes();
  const an::Interval<double> whole{ 0.0, ray.Length };
  return an::IntegratePiecewiseMixture(volumes, ray.Origin, ray.Direction, &whole, 1, pieces, eps);
}

} // namespace mixture

#endif
