#include "avosClippingPlanes.h"

#include "vtkPlane.h"
#include "vtkPlaneCollection.h"

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
