// A volume's scalars as the vectorised engine reads them (avos/engine/
// Riemann.h): 8- and 16-bit integers (signed or not) and floats read in
// place from the VTK array (one component of several too), any other type
// (32- and 64-bit integers, doubles) converted once to float, 4 bytes per
// point, and kept until the scalars (the array or its MTime), the component
// or the dimensions change. Shared by
// vtkAdaptiveVolumeMapper and the Volume-on-Surface rays. Not wrapped.
#ifndef avosEngineVolume_h
#define avosEngineVolume_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro
#include "vtkType.h"

#include "avos/engine/Frame.h"
#include "avos/engine/Riemann.h"
#include "avos/numerics/EmptySpace.h"

#include <array>
#include <vector>

class vtkDataArray;

namespace avos
{
/// The frame engine's view of scalars (a tuple of their components per grid
/// point of `dimensions`; only component `component` when it is not
/// negative), read in place (no copy); false for a type the engine does not
/// read (bit, string and other non-numeric arrays).
AVOSRENDERINGADAPTIVEVOLUME_EXPORT bool ScalarsInPlace(
  vtkDataArray* scalars, const int dimensions[3], avos::engine::Scalars& view, int component = -1);

/// The field the scalars define, as VTK's GPU mapper reads them: point
/// scalars trilinear (linear interpolation) or constant on each point's
/// nearest region (nearest); cell scalars constant on each cell (nearest) or
/// trilinear between the cells' centres (linear).
inline avos::engine::ScalarField FieldOf(bool cellScalars, bool nearest)
{
  using Field = avos::engine::ScalarField;
  return cellScalars ? (nearest ? Field::Cells : Field::CellCentres)
                     : (nearest ? Field::Nearest : Field::Trilinear);
}

/// What the empty-space blocks of `field` read: its cells' values.
inline avos::numerics::EmptySpaceMap<double>::Samples SamplesOf(avos::engine::ScalarField field)
{
  using Samples = avos::numerics::EmptySpaceMap<double>::Samples;
  return field == avos::engine::ScalarField::Cells    ? Samples::Cells
    : field == avos::engine::ScalarField::CellCentres ? Samples::CellCentres
                                                      : Samples::Points;
}

class AVOSRENDERINGADAPTIVEVOLUME_EXPORT EngineVolume
{
public:
  /// The engine's view of component `component` of the scalars (a tuple per
  /// grid point of `dimensions`; in place, one component of interleaved
  /// tuples included), brought up to date; null when the engine cannot take
  /// the volume (beyond its 32-bit indices, or an unknown scalar type): the
  /// caller then takes the scalar path.
  const avos::engine::Volume* Update(
    vtkDataArray* scalars, const int dimensions[3], int component = 0);

  /// How the engine reads scalars of a VTK type: 8- and 16-bit integers and
  /// floats as they are (in place), Float32 for the rest (converted).
  static avos::engine::Volume::Type EngineType(int vtkScalarType);

private:
  std::vector<float> Converted;
  avos::engine::Volume View;
  bool Usable = false;
  vtkDataArray* Scalars = nullptr; // identity only; its MTime guards reuse
  vtkMTimeType ScalarsTime = 0;
  int Component = 0;
  std::array<int, 3> Dimensions{ { 0, 0, 0 } };
};
}

#endif
