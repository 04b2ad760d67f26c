#include "avosClippingPlanes.h"

#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkVolumeMapper.h"

std::string avos::AddClippingPlanes(vtkPlaneCollection* planes, const double gridToWorld[16],
  avos::numerics::ClipRegion<double>& clip)
{
  if (!planes)
  {
    return std::string();
  }
  const double* m = gridToWorld;
  vtkCollectionSimpleIterator it;
  planes->InitTraversal(it);
  while (vtkPlane* plane = planes->GetNextPlane(it))
  {
    if (plane->GetTransform())
    {
      return "Clipping planes with a transform are not supported";
    }
    double n[3], o[3];
    plane->GetNormal(n);
    plane->GetOrigin(o);
    // n . (M x + c - o) >= 0 with M, c the grid -> world matrix's parts.
    glm::dvec3 normal(0.0);
    double offset = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        normal[j] += n[i] * m[4 * i + j];
      }
      offset += n[i] * (m[4 * i + 3] - o[i]);
    }
    clip.AddPlane(normal, offset);
  }
  return std::string();
}

std::string avos::ClipRegionOfMapper(vtkVolumeMapper* mapper, vtkImageData* input,
  const double gridToWorld[16], avos::numerics::ClipRegion<double>& clip)
{
  clip = avos::numerics::ClipRegion<double>();
  const std::string planesError = AddClippingPlanes(mapper->GetClippingPlanes(), gridToWorld, clip);
  if (!planesError.empty())
  {
    return planesError;
  }
  if (mapper->GetCropping())
  {
    const double* spacing = input->GetSpacing();
    if (!input->GetDirectionMatrix()->IsIdentity() || spacing[0] < 0.0 || spacing[1] < 0.0 ||
      spacing[2] < 0.0)
    {
      return "Cropping needs an input with positive spacing and no direction matrix (its region "
             "planes are in the volume's axis-aligned coordinates)";
    }
    const double* origin = input->GetOrigin();
    const int* extent = input->GetExtent();
    const double* region = mapper->GetCroppingRegionPlanes();
    double planes[6];
    for (int c = 0; c < 6; ++c)
    {
      const int a = c / 2;
      planes[c] = (region[c] - origin[a]) / spacing[a] - extent[2 * a];
    }
    clip.SetCropping(planes, mapper->GetCroppingRegionFlags());
  }
  const std::string unusable = clip.Validate();
  return unusable.empty() ? unusable : "Unusable clipping or cropping: " + unusable;
}
