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
// - Cells (the walk's stage, numerics::CellBatch), when the kernels are
//   given the volume's 8- or 16-bit scalars and the transfer function has
//   its unit tables: the 8 corners gathered, their range classified from the
//   tables, the cell's cubic; otherwise numerics::ScalarCellKernels.
// - Crossings (numerics::CrossingBatch): the knot crossings of a cell, a
//   crossing per lane, numerics::detail::Crossing's Newton steps and
//   bisections in every lane until all lanes are done.
// Bound against numerics::ScalarPieceKernels: the same formulas, rounded in
// another order (fused multiply-adds); relative 1e-13 in the depth's
// coefficients and the transmittance, and in J but where a rounding tips a
// decision (a term more or less, within the piece's share of eps). Cells
// and crossings: the same to the bit (the classification from integers; the
// cubic and the iterations by the same operations in the same order,
// without fused multiply-adds).
// Modules/Engine/Testing checks it on every dispatch target.
#ifndef avos_engine_PieceKernels_h
#define avos_engine_PieceKernels_h

#include "avos/engine/Riemann.h" // Volume
#include "avos/numerics/PiecewiseIntegrator.h"

namespace avos
{
namespace engine
{

struct PieceKernels
{
  PieceKernels() = default;
  // `scalars`: the walk's volume as the engine reads it (the same values).
  // Scalars the cell kernels do not read (ReadsCells), or a volume Validate
  // refuses, leave the cells' stage to numerics::ScalarCellKernels.
  explicit PieceKernels(const Volume* scalars)
    : Scalars(
        scalars && ReadsCells(scalars->Scalars) && Validate(*scalars).empty() ? scalars : nullptr)
  {
  }

  void Depths(numerics::PieceBatch<double>& batch) const;
  void Series(numerics::SeriesBatch<double>& batch) const;
  void Crossings(numerics::CrossingBatch<double>& batch) const;

  template <typename VolumeT>
  void Cells(const VolumeT& volume, const numerics::PiecewiseTransferFunction<double>& tf,
    const glm::dvec3& origin, const glm::dvec3& direction, numerics::CellBatch<double>& batch) const
  {
    if (this->Scalars && TakesTables(tf.GetUnitTables()) &&
      volume.GetDimension(0) == this->Scalars->Dimensions[0] &&
      volume.GetDimension(1) == this->Scalars->Dimensions[1] &&
      volume.GetDimension(2) == this->Scalars->Dimensions[2])
    {
      VectorisedCells(*this->Scalars, tf.GetUnitTables(), &origin.x, &direction.x, batch);
      return;
    }
    numerics::ScalarCellKernels<double>().Cells(volume, tf, origin, direction, batch);
  }

  const Volume* Scalars = nullptr;

  // Whether the cells' kernel classifies ranges from `tables`: the
  // transfer function has them, and their integers fit 32-bit lanes
  // (|Base| + 65536 within them).
  static bool TakesTables(const numerics::PiecewiseTransferFunction<double>::UnitTables& tables)
  {
    return tables.Count > 0 && std::abs(tables.Base) < 1073741824.0;
  }

private:
  static void VectorisedCells(const Volume& scalars,
    const numerics::PiecewiseTransferFunction<double>::UnitTables& tables, const double* origin,
    const double* direction, numerics::CellBatch<double>& batch);
};

// The name of the target the kernels dispatch to now.
const char* PieceKernelsTarget();

} // namespace engine
} // namespace avos

#endif
