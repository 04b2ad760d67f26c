// The GPU integrator (GLSL, float) against the numerical core (C++, double)
// on the same rays with the same method: every pixel's ray rebuilt here in
// double from the renderer's camera (through the pixel centre, near plane to
// far plane, clipped to the grid's box), integrated by the core, and compared
// with the float values the mapper writes into RenderToImage's depth image.
// Where the mapper has double-precision rays (GL_ARB_gpu_shader_fp64:
// positions along and across the ray in double, samples and sums in float;
// llvmpipe has it) the bounds are asserted as they stand: per RGBA
// channel max |difference| <= eps and 99th percentile <= 1e-5 at eps 0.01,
// 0.001 and 1e-4 (measured: at most 0.36 eps and 1.5e-6 over all scenes,
// methods and both skipping settings), rays' entry and length within 1e-4
// voxel (measured 2e-5: the float of the written values). Without fp64 the
// shader's positions are float and so are the bounds: rays within 5e-4 voxel
// (a grazing entry face magnifies float positions: 3.2e-4 on BluntFin), max
// 2 eps at eps 1e-4 (two results each within eps of the integral), and a
// 99th percentile within 1e-5 or 1.5 times what the core compiled in float
// reaches on the same rays (3.3e-5 on Bonsai at eps 1e-4: a float step
// bound rounds by 1.5e-5 voxel at t = 256).
// Scenes: the analytic Marschner-Lobb volume (float data, a transfer
// function with kinks, a jump and a spike, both opacity models), the
// adversarial suite's thin layers (the piecewise method and the projections
// only), BluntFin and Bonsai with their paper transfer functions (8-bit;
// skipped without the shared data).
// Each scene is compared twice: without empty-space skipping (the core on the
// whole ray) and with it (the core on the parts numerics::EmptySpaceMap gives
// for the same blocks and pad). Early termination is checked against its
// bound (images with and without it differ by at most 0.2 eps max(1, max C):
// 1.99e-4 of 2.01e-4 on Bonsai), and rays that llvmpipe's loop limit cuts
// short must come back reported failed, never as values. The piecewise
// method is held to its promise, every channel of every ray within eps of
// the exact integral (the core's reference) at eps 1e-2, 1e-3 and 1e-4, no
// ray failed (measured at most 0.15 eps), and its float path
// (UseDoublePrecision off) within 2 eps (measured at most 0.73 eps: float
// rounding lies outside the certificate). The maximum and minimum
// intensity projections are compared with the core's exact extremum on the
// same rays.
#include "vtkOpenGLAdaptiveVolumeMapper.h"

#include "AdversarialCases.h"
#include "avosImageGrid.h"
#include "avosTransferFunctionFromProperty.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTestUtilities.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkTrivialProducer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkVolvisRawReader.h"
#include "vtkXMLImageDataReader.h"

#include "avos/numerics/EmptySpace.h"
#include "avos/numerics/Extremum.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/Volume.h"

#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace
{
namespace an = avos::numerics;

constexpr int Size = 40;

struct Case
{
  std::string Name;
  vtkAlgorithm* Source;
  vtkVolumeProperty* Property;
  int OpacityModel;
  double Azimuth, Elevation;
  bool ProbeLoopLimit = false;
  // Whether the sampled methods are compared with the core's: not on thin
  // layers, where their error estimates are blind and a rounding flips
  // their step decisions (up to 8.5e-4 apart at eps 1e-4 there, each as
  // far from the integral).
  bool Sampled = true;
};

// The GPU mapper's float image of one quantity, Size x Size, row 0 at the bottom.
std::vector<float> RenderQuantity(
  vtkRenderWindow* window, vtkOpenGLAdaptiveVolumeMapper* mapper, int quantity)
{
  mapper->SetImageQuantity(quantity);
  window->Render();
  vtkNew<vtkImageData> image;
  mapper->GetDepthImage(image);
  vtkDataArray* values = image->GetPointData()->GetScalars();
  std::vector<float> out(Size * Size, 0.0f);
  const int* dims = image->GetDimensions();
  if (!values || dims[0] != Size || dims[1] != Size)
  {
    std::cerr << "no " << Size << "x" << Size << " depth image (" << dims[0] << "x" << dims[1]
              << ")\n";
    return out;
  }
  for (int i = 0; i < Size * Size; ++i)
  {
    out[i] = static_cast<float>(values->GetComponent(i, 0));
  }
  return out;
}

template <typename Storage>
struct Field
{
  const an::TrilinearVolume<double, Storage>& Volume;
  glm::dvec3 Origin, Direction;
  double operator()(double t) const { return this->Volume(this->Origin + t * this->Direction); }
};

double Percentile(std::vector<double> v, double p)
{
  if (v.empty())
  {
    return 0.0;
  }
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * (v.size() - 1))];
}

template <typename Storage>
bool Compare(const Case& c, vtkImageData* data, vtkRenderer* renderer, vtkRenderWindow* window,
  vtkOpenGLAdaptiveVolumeMapper* mapper, vtkVolume* volume)
{
  // The ray geometry, in double, as vtkAdaptiveVolumeMapper builds it.
  vtkNew<vtkMatrix4x4> gridToWorld, worldToGrid, ndcToWorld;
  const double voxel = avos::GridToWorld(data, volume->GetMatrix(), gridToWorld);
  vtkMatrix4x4::Invert(gridToWorld, worldToGrid);
  vtkMatrix4x4::Invert(renderer->GetActiveCamera()->GetCompositeProjectionTransformMatrix(
                         renderer->GetTiledAspectRatio(), -1, 1),
    ndcToWorld);
  auto apply = [](vtkMatrix4x4* m, const glm::dvec4& p)
  {
    double in[4] = { p.x, p.y, p.z, p.w }, out[4];
    m->MultiplyPoint(in, out);
    return glm::dvec3(out[0], out[1], out[2]) / out[3];
  };

  an::TransferFunction<double> tf;
  std::string error =
    avos::TransferFunctionFromProperty(c.Property, c.OpacityModel == 1, voxel, tf);
  if (!error.empty())
  {
    std::cerr << error << "\n";
    return false;
  }
  const int* dims = data->GetDimensions();
  const auto* values =
    static_cast<const Storage*>(data->GetPointData()->GetScalars()->GetVoidPointer(0));
  an::TrilinearVolume<double, Storage> field(values, dims);
  const an::TrilinearVolume<float, Storage> floatField(values, dims);
  const an::TransferFunction<float> floatTF = tf.Cast<float>();
  double range[2];
  data->GetPointData()->GetScalars()->GetRange(range);

  const std::vector<float> entry =
    RenderQuantity(window, mapper, vtkOpenGLAdaptiveVolumeMapper::RAY_ENTRY);
  const std::vector<float> length =
    RenderQuantity(window, mapper, vtkOpenGLAdaptiveVolumeMapper::RAY_LENGTH);

  struct Setting
  {
    int Method;
    double Tolerance;
  };
  const Setting settings[] = { { vtkOpenGLAdaptiveVolumeMapper::RIEMANN, 0.01 },
    { vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_COUPLED, 0.01 },
    { vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_COUPLED, 0.001 },
    { vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_COUPLED, 1e-4 },
    { vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED, 0.01 },
    { vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED, 0.001 },
    { vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED, 1e-4 } };

  bool ok = true;
  // Geometry first: the same rays.
  double worstEntry = 0.0, worstLength = 0.0;
  int hits = 0, coverage = 0;
  std::vector<glm::dvec3> rayOrigin(Size * Size), rayDirection(Size * Size);
  std::vector<double> rayLength(Size * Size, -1.0);
  for (int y = 0; y < Size; ++y)
  {
    for (int x = 0; x < Size; ++x)
    {
      const int i = y * Size + x;
      const double nx = 2.0 * (x + 0.5) / Size - 1.0, ny = 2.0 * (y + 0.5) / Size - 1.0;
      const glm::dvec3 nearWorld = apply(ndcToWorld, glm::dvec4(nx, ny, -1.0, 1.0));
      const glm::dvec3 farWorld = apply(ndcToWorld, glm::dvec4(nx, ny, 1.0, 1.0));
      const double total = glm::length(farWorld - nearWorld) / voxel;
      const glm::dvec3 nearGrid = apply(worldToGrid, glm::dvec4(nearWorld, 1.0));
      const glm::dvec3 farGrid = apply(worldToGrid, glm::dvec4(farWorld, 1.0));
      const glm::dvec3 direction = (farGrid - nearGrid) / total;
      double t0 = 0.0, t1 = total;
      const bool hit = an::ClipToGrid(nearGrid, direction, dims, t0, t1) && t1 - t0 > 1e-3;
      // Pixels with no fragment keep the image's clear value, 1 in both.
      const bool fragment = !(entry[i] == 1.0f && length[i] == 1.0f);
      const bool gpuHit = fragment && length[i] > 1e-3f;
      if (hit != gpuHit)
      {
        ++coverage; // a silhouette ray a rounding long: no fragment or no hit
        continue;
      }
      if (!hit)
      {
        continue;
      }
      ++hits;
      worstEntry = std::max(worstEntry, std::abs(entry[i] - t0));
      worstLength = std::max(worstLength, std::abs(length[i] - (t1 - t0)));
      rayOrigin[i] = nearGrid + t0 * direction;
      rayDirection[i] = direction;
      rayLength[i] = t1 - t0;
    }
  }
  const bool doubleRays = mapper->GetDoublePrecisionRays();
  const double geometryBound = doubleRays ? 1e-4 : 5e-4; // voxel units
  std::printf("%s (%s rays): %d rays in the box, %d differ in coverage; entry within %.2e, length "
              "within %.2e voxel\n",
    c.Name.c_str(), doubleRays ? "double" : "float", hits, coverage, worstEntry, worstLength);
  if (hits < Size * Size / 8 || coverage > Size / 4 || !(worstEntry <= geometryBound) ||
    !(worstLength <= geometryBound))
  {
    std::cerr << "FAILED: the GPU's rays are not the CPU mapper's\n";
    ok = false;
  }

  // Empty-space skipping: the core integrates the parts of each ray that
  // numerics::EmptySpaceMap gives for the same blocks, widened by the
  // mapper's pad; without it, the whole ray.
  an::EmptySpaceMap<double> map;
  map.SetDimensions(dims);
  map.ComputeRanges(values);
  map.Classify(tf);
  const double pad = doubleRays ? 1e-6 : 1e-3;
  for (int skipping = 0; skipping < 2 && c.Sampled; ++skipping)
  {
    mapper->SetEmptySpaceSkipping(skipping);
    std::printf(" empty-space skipping %s\n", skipping ? "on" : "off");
    std::vector<std::vector<an::Interval<double>>> segments(Size * Size);
    for (int i = 0; i < Size * Size; ++i)
    {
      if (rayLength[i] < 0.0)
      {
        continue;
      }
      if (skipping)
      {
        map.Segments(rayOrigin[i], rayDirection[i], rayLength[i], pad, segments[i]);
      }
      else
      {
        segments[i].assign(1, { 0.0, rayLength[i] });
      }
    }
    for (const Setting& s : settings)
    {
      mapper->SetIntegrationMethod(s.Method);
      mapper->SetTolerance(s.Tolerance);
      std::vector<float> gpu[4];
      for (int q = 0; q < 4; ++q)
      {
        gpu[q] = RenderQuantity(window, mapper, vtkOpenGLAdaptiveVolumeMapper::RED + q);
      }
      an::AdaptiveSettings<double> adaptive;
      adaptive.Tolerance = s.Tolerance;
      adaptive.Coupling = s.Method == vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_COUPLED
        ? an::Strategy::Coupled
        : an::Strategy::Decoupled;
      adaptive.FieldMinimum = range[0];
      adaptive.FieldMaximum = range[1];
      an::AdaptiveSettings<float> floatAdaptive;
      floatAdaptive.Tolerance = float(s.Tolerance);
      floatAdaptive.Coupling = adaptive.Coupling;
      floatAdaptive.FieldMinimum = float(range[0]);
      floatAdaptive.FieldMaximum = float(range[1]);
      std::vector<double> differences[4], floatDifferences[4];
      bool failed = false;
      double worst[4] = { 0, 0, 0, 0 };
      for (int i = 0; i < Size * Size; ++i)
      {
        if (rayLength[i] < 0.0)
        {
          continue;
        }
        const Field<Storage> f{ field, rayOrigin[i], rayDirection[i] };
        const double D = rayLength[i];
        an::RayResult<double> r;
        if (s.Method == vtkOpenGLAdaptiveVolumeMapper::RIEMANN)
        {
          r = an::IntegrateRiemann(f, tf, D, 0.5, an::RiemannForm::Exponential, segments[i].data(),
            segments[i].size(), 0.2 * s.Tolerance);
        }
        else if (!segments[i].empty())
        {
          r = an::IntegrateAdaptive(f, tf, segments[i].data(), segments[i].size(), adaptive);
        }
        if (!doubleRays && s.Method != vtkOpenGLAdaptiveVolumeMapper::RIEMANN &&
          !segments[i].empty())
        {
          // The same core in float on the same rays: what float positions
          // can reach.
          const glm::vec3 o(rayOrigin[i]), d(rayDirection[i]);
          std::vector<an::Interval<float>> parts;
          for (const auto& part : segments[i])
          {
            parts.push_back({ float(part.Begin), float(part.End) });
          }
          const an::RayResult<float> rf =
            an::IntegrateAdaptive([&](float t) { return floatField(o + t * d); }, floatTF,
              parts.data(), parts.size(), floatAdaptive);
          for (int q = 0; q < 4; ++q)
          {
            floatDifferences[q].push_back(std::abs(double(rf.RGBA[q]) - r.RGBA[q]));
          }
        }
        for (int q = 0; q < 4; ++q)
        {
          const double d = std::abs(double(gpu[q][i]) - r.RGBA[q]);
          differences[q].push_back(d);
          worst[q] = std::max(worst[q], d);
        }
      }
      std::printf("  %-19s eps %-6g", mapper->GetIntegrationMethodAsString(), s.Tolerance);
      for (int q = 0; q < 4; ++q)
      {
        const double p99 = Percentile(differences[q], 0.99);
        std::printf("  %c max %.1e p99 %.1e", "RGBA"[q], worst[q], p99);
        double bound = s.Tolerance, percentileBound = 1e-5;
        if (!doubleRays)
        {
          const double floatP99 = Percentile(floatDifferences[q], 0.99);
          std::printf(" (float core %.1e)", floatP99);
          bound = s.Tolerance < 1e-3 ? 2.0 * s.Tolerance : s.Tolerance;
          percentileBound = std::max(percentileBound, 1.5 * floatP99);
        }
        if (!(worst[q] <= bound) || !(p99 <= percentileBound))
        {
          failed = true;
        }
      }
      std::printf("%s\n", failed ? "  FAILED" : "");
      ok &= !failed;
    }
  }
  {
    // Early termination stops a ray once what is left can add at most
    // 0.2 eps max(1, max C) to any channel: the steps before are the same,
    // so images with and without it differ by at most that (plus float).
    mapper->SetIntegrationMethodToAdaptiveCoupled();
    mapper->SetTolerance(1e-3);
    std::vector<float> stopped[4], whole[4];
    for (int q = 0; q < 4; ++q)
    {
      stopped[q] = RenderQuantity(window, mapper, vtkOpenGLAdaptiveVolumeMapper::RED + q);
    }
    mapper->EarlyTerminationOff();
    for (int q = 0; q < 4; ++q)
    {
      whole[q] = RenderQuantity(window, mapper, vtkOpenGLAdaptiveVolumeMapper::RED + q);
    }
    mapper->EarlyTerminationOn();
    const double bound = 0.2 * 1e-3 * std::max(1.0, tf.GetMaximumColor()) + 1e-6;
    double worstTermination = 0.0;
    for (int i = 0; i < Size * Size; ++i)
    {
      for (int q = 0; q < 4; ++q)
      {
        worstTermination =
          std::max(worstTermination, std::abs(double(stopped[q][i]) - double(whole[q][i])));
      }
    }
    std::printf(" early termination at eps 1e-3 changes a channel by at most %.2e (bound %.2e)\n",
      worstTermination, bound);
    if (!(worstTermination <= bound))
    {
      std::cerr << "FAILED: early termination exceeds its bound\n";
      ok = false;
    }
  }
  {
    // The piecewise method's promise: every channel of every ray within eps
    // of the exact integral (the core's piecewise reference, 1e-10, on the
    // same rays and the same visible parts).
    an::PiecewiseTransferFunction<double> exact;
    const std::string built =
      exact.Build(tf, an::PiecewiseRelativeError(an::PiecewiseReferenceTolerance<double>()));
    mapper->SetIntegrationMethodToPiecewiseAdaptive();
    for (const bool useDouble : { true, false })
      for (const double eps : { 1e-2, 1e-3, 1e-4 })
      {
        mapper->SetUseDoublePrecision(useDouble);
        mapper->SetTolerance(eps);
        std::vector<float> gpu[4];
        for (int q = 0; q < 4; ++q)
        {
          gpu[q] = RenderQuantity(window, mapper, vtkOpenGLAdaptiveVolumeMapper::RED + q);
        }
        double worst[4] = { 0, 0, 0, 0 };
        int failed = 0;
        for (int i = 0; i < Size * Size && built.empty(); ++i)
        {
          if (rayLength[i] < 0.0)
          {
            continue;
          }
          if (gpu[3][i] < 0.0f)
          {
            ++failed;
            continue;
          }
          const an::Interval<double> whole{ 0.0, rayLength[i] };
          const an::RayResult<double> r = an::IntegratePiecewise(field, rayOrigin[i],
            rayDirection[i], &whole, 1, exact, an::PiecewiseReferenceTolerance<double>());
          for (int q = 0; q < 4; ++q)
          {
            worst[q] = std::max(worst[q], std::abs(double(gpu[q][i]) - r.RGBA[q]));
          }
        }
        const bool bad = !built.empty() || failed > 0 ||
          !(std::max({ worst[0], worst[1], worst[2], worst[3] }) <= (useDouble ? eps : 2.0 * eps));
        std::printf(
          " piecewise (%s) eps %-6g against the exact integral: RGBA max %.1e %.1e %.1e %.1e, "
          "%d rays failed%s\n",
          useDouble ? "double" : "float", eps, worst[0], worst[1], worst[2], worst[3], failed,
          bad ? "  FAILED" : "");
        ok &= !bad;
      }
    mapper->SetUseDoublePrecision(1);
    mapper->SetIntegrationMethodToAdaptiveCoupled();
  }
  {
    // The projections: the exact extremum of the field along each ray
    // (numerics::ExtremumAlongRay in double on the whole ray), shown as the
    // colour there times the clamped opacity value, that value as alpha.
    // With double rays every channel within 1e-5 (measured at most 2.2e-6:
    // the float values written, rays 2e-5 voxel apart); the shader's cubics
    // evaluated at the cell faces alone, without the roots of their
    // derivatives, are 1e-3 to 0.13 off on these scenes. With float rays
    // (5e-4 voxel) 2e-3, not exercised where the context has fp64. The
    // shader looks the extremum up in float: a value rounded by 2^-24 |s|
    // moves the colour times opacity by up to that times their slope (6e-4
    // on the thin layers' spike, 40 per scalar unit; measured 6.1e-5).
    double slope = 0.0;
    for (const auto& piece : tf.GetPieces())
    {
      for (int k = 0; k < 3; ++k)
      {
        slope = std::max(slope,
          std::abs(piece.ColourSlope[k]) + tf.GetMaximumColor() * std::abs(piece.OpacitySlope));
      }
    }
    const double lookUp = slope * std::max(std::abs(range[0]), std::abs(range[1])) * 0x1p-24;
    for (const bool maximum : { true, false })
    {
      mapper->SetBlendMode(maximum ? vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND
                                   : vtkVolumeMapper::MINIMUM_INTENSITY_BLEND);
      std::vector<float> gpu[4];
      for (int q = 0; q < 4; ++q)
      {
        gpu[q] = RenderQuantity(window, mapper, vtkOpenGLAdaptiveVolumeMapper::RED + q);
      }
      double worst[4] = { 0, 0, 0, 0 };
      for (int i = 0; i < Size * Size; ++i)
      {
        if (rayLength[i] < 0.0)
        {
          continue;
        }
        const an::Interval<double> whole{ 0.0, rayLength[i] };
        const an::RayExtremum<double> e =
          an::ExtremumAlongRay(field, rayOrigin[i], rayDirection[i], &whole, 1, maximum);
        glm::dvec4 rgba(0.0);
        if (e.Found)
        {
          const double alpha = std::min(std::max(tf.GetOpacityValue(e.Value), 0.0), 1.0);
          rgba = glm::dvec4(tf.GetColor(e.Value) * alpha, alpha);
        }
        for (int q = 0; q < 4; ++q)
        {
          worst[q] = std::max(worst[q], std::abs(double(gpu[q][i]) - rgba[q]));
        }
      }
      const double bound = (doubleRays ? 1e-5 : 2e-3) + lookUp;
      const bool failed = !(std::max({ worst[0], worst[1], worst[2], worst[3] }) <= bound);
      std::printf(" %s intensity: RGBA max differences %.1e %.1e %.1e %.1e (bound %.0e)%s\n",
        maximum ? "maximum" : "minimum", worst[0], worst[1], worst[2], worst[3], bound,
        failed ? "  FAILED" : "");
      ok &= !failed;
    }
    mapper->SetBlendModeToComposite();
  }
  if (c.ProbeLoopLimit)
  {
    // Rays of tens of thousands of steps (eps 1e-7, h_min 0.001): llvmpipe
    // cuts a shader's loops off after 65535 iterations. Every ray must come
    // back either reported failed (alpha -1) or within 2 eps of the core, on
    // llvmpipe some failed, never a silently truncated value. The core is
    // checked on every 16th ray (each takes about 10^5 samples).
    mapper->SetIntegrationMethodToAdaptiveCoupled();
    mapper->SetTolerance(1e-7);
    mapper->SetMinimumStep(0.001);
    const std::vector<float> alpha =
      RenderQuantity(window, mapper, vtkOpenGLAdaptiveVolumeMapper::ALPHA);
    mapper->SetMinimumStep(0.1);
    an::AdaptiveSettings<double> adaptive;
    adaptive.Tolerance = 1e-7;
    adaptive.MinimumStep = 0.001;
    adaptive.FieldMinimum = range[0];
    adaptive.FieldMaximum = range[1];
    int failed = 0, checked = 0, wrong = 0;
    for (int i = 0; i < Size * Size; ++i)
    {
      if (rayLength[i] < 0.0)
      {
        continue;
      }
      if (alpha[i] == -1.0f)
      {
        ++failed;
        continue;
      }
      if (i % 16 != 0)
      {
        continue;
      }
      const Field<Storage> f{ field, rayOrigin[i], rayDirection[i] };
      const an::Interval<double> whole{ 0.0, rayLength[i] };
      const an::RayResult<double> r = an::IntegrateAdaptive(f, tf, &whole, 1, adaptive);
      ++checked;
      wrong += std::abs(alpha[i] - r.RGBA[3]) > 2e-7 + 1e-6 ? 1 : 0; // 2 eps + float
    }
    const bool llvmpipe =
      std::string(window->ReportCapabilities()).find("llvmpipe") != std::string::npos;
    std::printf(" eps 1e-7, h_min 0.001: %d rays reported failed, %d of %d checked off\n", failed,
      wrong, checked);
    if (wrong > 0 || (llvmpipe && failed == 0))
    {
      std::cerr << "FAILED: a ray cut short was not reported\n";
      ok = false;
    }
  }
  return ok;
}

bool Run(const Case& c)
{
  vtkNew<vtkOpenGLAdaptiveVolumeMapper> mapper;
  mapper->SetInputConnection(c.Source->GetOutputPort());
  mapper->SetOpacityModel(c.OpacityModel);
  mapper->SetRenderToImage(1);
  mapper->SetDepthImageScalarTypeToFloat();
  mapper->SetAutoAdjustSampleDistances(0);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(c.Property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(Size, Size);
  window->AddRenderer(renderer);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Azimuth(c.Azimuth);
  renderer->GetActiveCamera()->Elevation(c.Elevation);
  renderer->GetActiveCamera()->OrthogonalizeViewUp();
  renderer->ResetCameraClippingRange();
  c.Source->Update();
  vtkImageData* data = vtkImageData::SafeDownCast(c.Source->GetOutputDataObject(0));
  switch (data->GetPointData()->GetScalars()->GetDataType())
  {
    case VTK_UNSIGNED_CHAR:
      return Compare<unsigned char>(c, data, renderer, window, mapper, volume);
    case VTK_FLOAT:
      return Compare<float>(c, data, renderer, window, mapper, volume);
    default:
      std::cerr << "unexpected scalar type\n";
      return false;
  }
}
} // namespace

int TestOpenGLAdaptiveVolumeMapperAgainstCore(int argc, char* argv[])
{
  bool ok = true;
  {
    // Marschner-Lobb in [0, 1] with kinks, a jump at 0.5 and a narrow spike.
    vtkNew<vtkAnalyticVolumeSource> source;
    source->SetFunctionToMarschnerLobb();
    source->SetDimensions(41, 41, 41);
    source->SetOutputScalarTypeToFloat();
    vtkNew<vtkColorTransferFunction> colour;
    colour->AddRGBPoint(0.0, 0.1, 0.2, 0.9);
    colour->AddRGBPoint(0.5, 0.9, 0.8, 0.1);
    colour->AddRGBPoint(0.5, 0.2, 0.9, 0.3);
    colour->AddRGBPoint(1.0, 1.0, 0.3, 0.2);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(0.3, 0.02);
    opacity->AddPoint(0.5, 0.2);
    opacity->AddPoint(0.5, 0.05);
    opacity->AddPoint(0.7, 0.05);
    opacity->AddPoint(0.72, 0.8);
    opacity->AddPoint(0.74, 0.05);
    opacity->AddPoint(1.0, 0.3);
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(colour);
    property->SetScalarOpacity(opacity);
    property->SetInterpolationTypeToLinear();
    ok &= Run({ "Marschner-Lobb, extinction", source, property, 1, 31.0, 23.0, true });
    ok &= Run({ "Marschner-Lobb, VTK opacity", source, property, 0, -47.0, 11.0 });
  }
  {
    // The adversarial suite's thin layers: balls of 255 in 0 (40^3) and an
    // extinction spike 1 scalar unit wide (20 per voxel) at 127.5, so every
    // boundary holds a layer about 1/255 of a voxel thick.
    const adversarial::Case thin = adversarial::MakeVolume("thin layers", adversarial::Binary, 7);
    vtkNew<vtkImageData> image;
    image->SetDimensions(thin.Dimensions);
    vtkNew<vtkFloatArray> scalars;
    scalars->SetNumberOfValues(static_cast<vtkIdType>(thin.Data.size()));
    for (std::size_t i = 0; i < thin.Data.size(); ++i)
    {
      scalars->SetValue(static_cast<vtkIdType>(i), static_cast<float>(thin.Data[i]));
    }
    image->GetPointData()->SetScalars(scalars);
    vtkNew<vtkTrivialProducer> producer;
    producer->SetOutput(image);
    vtkNew<vtkColorTransferFunction> colour;
    colour->AddRGBPoint(0.0, 0.0, 0.2, 1.0);
    colour->AddRGBPoint(127.0, 0.1, 0.3, 0.9);
    colour->AddRGBPoint(127.5, 1.0, 0.6, 0.1);
    colour->AddRGBPoint(128.0, 0.9, 0.9, 0.2);
    colour->AddRGBPoint(255.0, 1.0, 1.0, 1.0);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(127.0, 0.0);
    opacity->AddPoint(127.5, 20.0);
    opacity->AddPoint(128.0, 0.0);
    opacity->AddPoint(255.0, 0.0);
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(colour);
    property->SetScalarOpacity(opacity);
    property->SetInterpolationTypeToLinear();
    ok &= Run({ "thin layers, extinction", producer, property, 1, 23.0, 31.0, false, false });
  }

  char* root = vtkTestUtilities::GetDataRoot(argc, argv);
  const std::string data = root ? root : "";
  delete[] root;
  const std::string bluntFin = data + "/volumes/BluntFin.1.256x128x64.raw";
  const std::string bonsai = data + "/volumes/bonsai_zfp.vti";
  if (!vtksys::SystemTools::FileExists(bluntFin) || !vtksys::SystemTools::FileExists(bonsai))
  {
    std::cout << "Shared data folder '" << data << "' is absent: the real volumes are skipped.\n";
    return ok ? EXIT_SUCCESS : EXIT_FAILURE;
  }
  {
    vtkNew<vtkVolvisRawReader> reader;
    reader->SetFileName(bluntFin.c_str());
    reader->SetDataSpacing(1.0, 0.75, 1.0);
    vtkNew<vtkTransferFunction1DReader> tf;
    tf->SetFileName((data + "/tf/BluntFin.1.256x128x64.linear.tf1d").c_str());
    tf->SetOpacityModelToExtinction();
    vtkNew<vtkVolumeProperty> property;
    property->SetInterpolationTypeToLinear();
    ok &= tf->FillVolumeProperty(property);
    ok &= Run({ "BluntFin", reader, property, 1, 20.0, 30.0 });
  }
  {
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(bonsai.c_str());
    vtkNew<vtkTransferFunction1DReader> tf;
    tf->SetFileName((data + "/tf/Bonsai.1.256x256x256.tf1d").c_str());
    tf->SetOpacityModelToVTK();
    vtkNew<vtkVolumeProperty> property;
    property->SetInterpolationTypeToLinear();
    ok &= tf->FillVolumeProperty(property);
    ok &= Run({ "Bonsai, VTK opacity", reader, property, 0, 37.0, 23.0 });
  }
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
