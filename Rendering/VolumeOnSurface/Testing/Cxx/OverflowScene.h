// A volume on the grid of `like` whose scalars alternate between -1.5e308 and
// +1.5e308 (the trilinear interpolant between two grid points overflows), and
// a linear-interpolation property covering that range with extinction `tau`:
// the piecewise rays through it cannot be integrated.
#ifndef OverflowScene_h
#define OverflowScene_h

#include "vtkColorTransferFunction.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkVolumeProperty.h"

namespace overflowscene
{
struct Scene
{
  vtkNew<vtkImageData> Volume;
  vtkNew<vtkVolumeProperty> Property;

  Scene(vtkImageData* like, double tau)
  {
    this->Volume->CopyStructure(like);
    vtkNew<vtkDoubleArray> values;
    values->SetNumberOfTuples(this->Volume->GetNumberOfPoints());
    for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
    {
      values->SetValue(i, i % 2 ? 1.5e308 : -1.5e308);
    }
    this->Volume->GetPointData()->SetScalars(values);
    vtkNew<vtkPiecewiseFunction> flat;
    flat->AddPoint(-1.7e308, tau);
    flat->AddPoint(1.7e308, tau);
    vtkNew<vtkColorTransferFunction> grey;
    grey->AddRGBPoint(-1.7e308, 0.5, 0.5, 0.5);
    grey->AddRGBPoint(1.7e308, 0.5, 0.5, 0.5);
    this->Property->SetInterpolationTypeToLinear();
    this->Property->SetColor(grey);
    this->Property->SetScalarOpacity(flat);
  }
};
} // namespace overflowscene

#endif
