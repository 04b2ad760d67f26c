// The map from an image's continuous grid index (counted from the extent's
// start, as the scalar array is stored) to world coordinates, shared by the
// classes that cast rays through vtkImageData. Not wrapped.
#ifndef avosImageGrid_h
#define avosImageGrid_h

#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"

#include <algorithm>
#include <cmath>

namespace avos
{
/**
 * Fills `gridToWorld` with the image's index -> physical matrix (origin,
 * spacing, direction) after the extent's start, then the prop's matrix when
 * one is given. Returns the world length of the shortest grid step: one
 * voxel unit (0 or non-finite for a degenerate grid).
 */
inline double GridToWorld(vtkImageData* image, vtkMatrix4x4* propMatrix, vtkMatrix4x4* gridToWorld)
{
  vtkNew<vtkMatrix4x4> start;
  const int* extent = image->GetExtent();
  for (int a = 0; a < 3; ++a)
  {
    start->SetElement(a, 3, extent[2 * a]);
  }
  vtkMatrix4x4::Multiply4x4(image->GetIndexToPhysicalMatrix(), start, gridToWorld);
  if (propMatrix)
  {
    vtkMatrix4x4::Multiply4x4(propMatrix, gridToWorld, gridToWorld);
  }
  const double* m = gridToWorld->GetData();
  double voxel = std::sqrt(m[0] * m[0] + m[4] * m[4] + m[8] * m[8]);
  for (int a = 1; a < 3; ++a)
  {
    voxel = std::min(voxel, std::sqrt(m[a] * m[a] + m[4 + a] * m[4 + a] + m[8 + a] * m[8 + a]));
  }
  return voxel;
}
}

#endif
