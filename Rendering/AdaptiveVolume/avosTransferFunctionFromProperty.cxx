#include "avosTransferFunctionFromProperty.h"

#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"

namespace
{
using TransferFunction = avos::numerics::TransferFunction<double>;

// Sub-knots per node interval where VTK's function is not linear in RGB.
constexpr int ResampledKnots = 16;

// VTK's transfer functions as piecewise-linear knots. Where VTK does not
// interpolate linearly in RGB (midpoint or sharpness moved, non-RGB colour
// space), the interval is resampled with ResampledKnots sub-knots.
std::string ConvertColor(vtkVolumeProperty* property, TransferFunction& tf)
{
  if (property->GetColorChannels(0) == 1)
  {
    vtkPiecewiseFunction* gray = property->GetGrayTransferFunction(0);
    const int n = gray ? gray->GetSize() : 0;
    if (n == 0)
    {
      return "the gray transfer function is empty";
    }
    for (int i = 0; i < n; ++i)
    {
      double node[4], next[4];
      gray->GetNodeValue(i, node);
      tf.AddColorKnot(node[0], node[1], node[1], node[1]);
      if (i + 1 < n && (node[2] != 0.5 || node[3] != 0.0))
      {
        gray->GetNodeValue(i + 1, next);
        for (int k = 1; k < ResampledKnots; ++k)
        {
          const double s = node[0] + (next[0] - node[0]) * k / ResampledKnots;
          const double v = gray->GetValue(s);
          tf.AddColorKnot(s, v, v, v);
        }
      }
    }
    return std::string();
  }
  vtkColorTransferFunction* color = property->GetRGBTransferFunction(0);
  const int n = color ? color->GetSize() : 0;
  if (n == 0)
  {
    return "the colour transfer function is empty";
  }
  const bool linearSpace = color->GetColorSpace() == VTK_CTF_RGB;
  for (int i = 0; i < n; ++i)
  {
    double node[6], next[6];
    color->GetNodeValue(i, node);
    tf.AddColorKnot(node[0], node[1], node[2], node[3]);
    if (i + 1 < n && (!linearSpace || node[4] != 0.5 || node[5] != 0.0))
    {
      color->GetNodeValue(i + 1, next);
      for (int k = 1; k < ResampledKnots; ++k)
      {
        const double s = node[0] + (next[0] - node[0]) * k / ResampledKnots;
        double rgb[3];
        color->GetColor(s, rgb);
        tf.AddColorKnot(s, rgb[0], rgb[1], rgb[2]);
      }
    }
  }
  return std::string();
}

std::string ConvertOpacity(vtkVolumeProperty* property, TransferFunction& tf)
{
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity(0);
  const int n = opacity ? opacity->GetSize() : 0;
  if (n == 0)
  {
    return "the scalar opacity function is empty";
  }
  for (int i = 0; i < n; ++i)
  {
    double node[4], next[4];
    opacity->GetNodeValue(i, node);
    tf.AddOpacityKnot(node[0], node[1]);
    if (i + 1 < n && (node[2] != 0.5 || node[3] != 0.0))
    {
      opacity->GetNodeValue(i + 1, next);
      for (int k = 1; k < ResampledKnots; ++k)
      {
        const double s = node[0] + (next[0] - node[0]) * k / ResampledKnots;
        tf.AddOpacityKnot(s, opacity->GetValue(s));
      }
    }
  }
  return std::string();
}

// True when the gradient opacity changes anything: enabled and not the
// constant 1 that VTK creates on first access (VTK's GPU mapper accesses it).
bool UsesGradientOpacity(vtkVolumeProperty* property)
{
  if (property->GetDisableGradientOpacity(0) || !property->HasGradientOpacity(0))
  {
    return false;
  }
  vtkPiecewiseFunction* f = property->GetStoredGradientOpacity(0);
  for (int i = 0; f && i < f->GetSize(); ++i)
  {
    double node[4];
    f->GetNodeValue(i, node);
    if (node[1] != 1.0)
    {
      return true;
    }
  }
  return false;
}
} // namespace

std::string avos::UnsupportedPropertySettings(vtkVolumeProperty* property, bool shading)
{
  if (!property)
  {
    return std::string();
  }
  if (property->GetInterpolationType() != VTK_LINEAR_INTERPOLATION)
  {
    return "Only trilinear interpolation is supported (the integrals are those of the trilinear "
           "field): call the property's SetInterpolationTypeToLinear()";
  }
  if (property->GetTransferFunctionMode() != vtkVolumeProperty::TF_1D ||
    UsesGradientOpacity(property))
  {
    return "Only one-dimensional transfer functions of the scalar are supported: no gradient "
           "opacity, no 2D transfer function";
  }
  if (property->GetUseClippedVoxelIntensity())
  {
    return "UseClippedVoxelIntensity (VTK's GPU mapper's fill of clipped voxels for gradients) is "
           "not supported: clipping cuts the rays exactly";
  }
  if (property->GetShade(0) && !shading)
  {
    return "Shading is not supported (emission-absorption model): turn the property's Shade off";
  }
  return std::string();
}

std::string avos::TransferFunctionFromProperty(
  vtkVolumeProperty* property, bool extinction, double voxel, TransferFunction& tf)
{
  tf = TransferFunction();
  if (!property)
  {
    return "no volume property";
  }
  std::string error = ConvertColor(property, tf);
  if (error.empty())
  {
    error = ConvertOpacity(property, tf);
  }
  if (!extinction)
  {
    tf.SetOpacityModel(
      avos::numerics::OpacityModel::Alpha, property->GetScalarOpacityUnitDistance(0) / voxel);
  }
  if (error.empty())
  {
    error = tf.Validate();
  }
  tf.Finalize();
  return error;
}
