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

/**
 * The longest segment inside the box of an image's points (grid
 * coordinates [0, dims - 1]) under `gridToWorld`, in world units: the
 * longest of its four diagonals (the box's image is a parallelepiped).
 */
inline double LongestChord(vtkMatrix4x4* gridToWorld, const int dims[3])
{
  const double* m = gridToWorld->GetData();
  double longest = 0.0;
  for (int signs = 0; signs < 4; ++signs)
  {
    const double d[3] = { (signs & 1 ? -1.0 : 1.0) * std::max(dims[0] - 1, 0),
      (signs & 2 ? -1.0 : 1.0) * std::max(dims[1] - 1, 0), 1.0 * std::max(dims[2] - 1, 0) };
    double length = 0.0;
    for (int r = 0; r < 3; ++r)
    {
      const double w = m[4 * r] * d[0] + m[4 * r + 1] * d[1] + m[4 * r + 2] * d[2];
      length += w * w;
    }
    longest = std::max(longest, std::sqrt(length));
  }
  return longest;
}
}

#endif
