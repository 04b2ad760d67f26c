// The rays of a frame's pixels (VTK-free): from a pixel's centre on the near
// plane to the depth buffer's surface, in the volume's grid coordinates,
// clipped to the grid's box [0, n - 1]^3 (numerics::ClipToGrid).
//
// PixelRay sets up one ray in double. RowRays sets up the rays of a run of
// pixels of one row in SIMD double lanes, repeating PixelRay's arithmetic
// operation for operation (compiled without contracted multiply-adds, as
// the scalar code has none), so the rays are PixelRay's to the bit:
// Modules/Engine/Testing checks it on every dispatch target.
#ifndef avos_engine_PixelRays_h
#define avos_engine_PixelRays_h

namespace avos
{
namespace engine
{

// What a frame's rays depend on. Matrices are row-major 4x4.
struct FrameRays
{
  double NDCToWorld[16];  // inverse of the camera's composite projection
  double WorldToGrid[16]; // world -> continuous grid index (from 0)
  double Voxel = 1.0;     // world length of one voxel unit: rays are in voxel units
  int Dimensions[3] = { 0, 0, 0 };
  int Width = 0, Height = 0;
  const float* Depth = nullptr; // the depth buffer, Width x Height, row by row
};

// The ray of pixel (x, y): origin + t direction, t in [0, D], direction of
// unit voxel length. False when it misses the box (or the depth buffer is at
// the near plane).
bool PixelRay(
  const FrameRays& frame, int x, int y, double origin[3], double direction[3], double& D);

// The rays of pixels [x0, x1) of row y that meet the box, in order: their x
// into xs, three doubles each into origins and directions, D into lengths.
// Returns how many (at most x1 - x0).
int RowRays(const FrameRays& frame, int y, int x0, int x1, int* xs, double* origins,
  double* directions, double* lengths);

// The name of the target RowRays dispatches to now.
const char* RowRaysTarget();

} // namespace engine
} // namespace avos

#endif
