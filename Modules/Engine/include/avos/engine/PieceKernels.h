// The vectorised stages of the piecewise method (VTK-free): the two kernels
// numerics::IntegratePiecewise runs on its batches of pieces
// (numerics::PieceBatch, numerics::SeriesBatch), a lane per piece, in double
// (the optical depth and J must stay double: see PiecewiseIntegrator.h),
// through Google Highway with runtime dispatch (AVX-512: 8 pieces per
// vector, AVX2 4, SSE4 2, EMU128 2).
// - Depths: theta's coefficients (numerics::detail::PieceDepth, at degree 10
//   in every lane; the coefficients a lane does not have come out 0), theta(l)
//   by Horner, e^{-theta(l)} by Highway's Exp (1 ulp; 0 below -1000, where
//   e^x is below the smallest double anyway), and whether s is monotone on
//   the pieces the walk did not know it of.
// - Series: SeriesIntegral's first sub-interval on each piece, the terms
//   added in every lane until all lanes settle (a settled lane's sum is kept
//   as it was when it settled), at most MaximumTerms + 1 terms.
// Bound against numerics::ScalarPieceKernels: the same formulas, rounded in
// another order (fused multiply-adds); relative 1e-13 in the depth's
// coefficients and the transmittance, and in J but where a rounding tips a
// decision (a term more or less, within the piece's share of eps).
// Modules/Engine/Testing checks it on every dispatch target.
#ifndef avos_engine_PieceKernels_h
#define avos_engine_PieceKernels_h

#include "avos/numerics/PiecewiseIntegrator.h"

namespace avos
{
namespace engine
{

struct PieceKernels
{
  void Depths(numerics::PieceBatch<double>& batch) const;
  void Series(numerics::SeriesBatch<double>& batch) const;
};

// The name of the target the kernels dispatch to now.
const char* PieceKernelsTarget();

} // namespace engine
} // namespace avos

#endif
