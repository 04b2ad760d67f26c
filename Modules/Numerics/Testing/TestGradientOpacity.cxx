// Gradient opacity in the sampled methods (GradientOpacity.h): against the
// closed form of a field whose gradient is constant on each cell (s = i^2
// at the grid points along x: the gradient on cell i is 2 i + 1), so that
// G is constant per cell and each cell composites in closed form; the
// world scaling of the gradient; G = 1 changes nothing.
#include "avos/numerics/GradientOpacity.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/Volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace an = avos::numerics;

namespace
{
using Volume = an::TrilinearVolume<double, double>;
using Field = an::RayField<double, Volume>;

constexpr int Dims[3] = { 9, 3, 3 };

// s = i^2 along x, constant across y and z.
std::vector<double> Squares()
{
  std::vector<double> data;
  for (int n = 0; n < Dims[0] * Dims[1] * Dims[2]; ++n)
  {
    const int i = n % Dims[0];
    data.push_back(double(i * i));
  }
  return data;
}

// Extinction 0.3 and colour (1, 0.5, 0) everywhere (extinction model).
an::TransferFunction<double> Constant()
{
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.3);
  tf.AddColorKnot(0.0, 1.0, 0.5, 0.0);
  tf.Finalize();
  return tf;
}

// G(g): 1 up to 2, falling linearly to 0 at 18.
an::TransferFunction<double> Falling()
{
  an::TransferFunction<double> g;
  g.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  g.AddOpacityKnot(2.0, 1.0);
  g.AddOpacityKnot(18.0, 0.0);
  g.Finalize();
  return g;
}

// The ray along x through the whole grid, world = `scale` grid units.
glm::dvec4 Exact(const an::TransferFunction<double>& g, double scale)
{
  glm::dvec3 colour(0.0);
  double T = 1.0;
  for (int i = 0; i + 1 < Dims[0]; ++i)
  {
    const double gradient = (2.0 * i + 1.0) / scale; // scalar units per world unit
    const double factor = std::min(std::max(g.GetOpacityValue(gradient), 0.0), 1.0);
    const double alpha = -std::expm1(-0.3 * factor);
    colour += T * alpha * glm::dvec3(1.0, 0.5, 0.0);
    T *= 1.0 - alpha;
  }
  return glm::dvec4(colour, 1.0 - T);
}
} // namespace

// The adaptive reference within 1e-6 of the closed form, the Riemann sum
// first order towards it, and a G of 1 the plain image; a world twice the
// grid halves every gradient.
TEST(GradientOpacity, ConstantGradientPerCellAgainstItsClosedForm)
{
  const std::vector<double> data = Squares();
  const Volume volume(data.data(), Dims);
  const an::TransferFunction<double> tf = Constant(), g = Falling();
  for (const double scale : { 1.0, 2.0 })
  {
    an::GradientOpacity<double> opacity;
    opacity.Function = &g;
    opacity.NormalMatrix = glm::dmat3(1.0 / scale); // world = scale grid
    ASSERT_EQ(opacity.Validate(), "");
    const an::GradientOpacityField<double, Field> field{
      { volume, glm::dvec3(0.0, 1.0, 1.0), glm::dvec3(1.0, 0.0, 0.0) }, &opacity
    };
    const glm::dvec4 exact = Exact(g, scale);
    const an::RayResult<double> reference = an::IntegrateReference(field, tf, 8.0);
    ASSERT_EQ(reference.Error, "");
    for (int c = 0; c < 4; ++c)
    {
      EXPECT_NEAR(reference.RGBA[c], exact[c], 1e-6) << "scale " << scale << " channel " << c;
    }
    auto error = [&](double h)
    {
      return std::abs(
        an::IntegrateRiemann(field, tf, 8.0, h, an::RiemannForm::Exponential).RGBA.a - exact.a);
    };
    EXPECT_LT(error(0.01), error(0.1));
  }
  // Without gradient opacity the image differs: the test tells them apart.
  const Field plain{ volume, glm::dvec3(0.0, 1.0, 1.0), glm::dvec3(1.0, 0.0, 0.0) };
  const double opaque = an::IntegrateReference(plain, tf, 8.0).RGBA.a;
  EXPECT_NEAR(opaque, -std::expm1(-0.3 * 8.0), 1e-6);
  EXPECT_GT(opaque - Exact(g, 1.0).a, 0.1);
  // G = 1 everywhere: the plain image.
  an::TransferFunction<double> one;
  one.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  one.AddOpacityKnot(0.0, 1.0);
  one.Finalize();
  an::GradientOpacity<double> none;
  none.Function = &one;
  const an::GradientOpacityField<double, Field> same{ plain, &none };
  EXPECT_EQ(
    an::IntegrateReference(same, tf, 8.0).RGBA, an::IntegrateReference(plain, tf, 8.0).RGBA);
}

TEST(GradientOpacity, RefusesAMissingFunction)
{
  an::GradientOpacity<double> opacity;
  EXPECT_NE(opacity.Validate(), "");
  an::TransferFunction<double> empty;
  opacity.Function = &empty;
  EXPECT_NE(opacity.Validate(), "");
}
