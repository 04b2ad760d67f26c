#include "vtkPVVolumeOnSurfaceFilter.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"

vtkStandardNewMacro(vtkPVVolumeOnSurfaceFilter);

vtkPVVolumeOnSurfaceFilter::vtkPVVolumeOnSurfaceFilter()
{
  this->OwnProperty->SetInterpolationTypeToLinear();
  this->SetCamera(this->OwnCamera);
  this->SetVolumeProperty(this->OwnProperty);
}

vtkPVVolumeOnSurfaceFilter::~vtkPVVolumeOnSurfaceFilter() = default;

// The camera's and the property's own modification times reach the
// filter's (vtkVolumeOnSurfaceFilter::GetMTime): no Modified() needed.
void vtkPVVolumeOnSurfaceFilter::SetCameraPosition(double x, double y, double z)
{
  this->OwnCamera->SetPosition(x, y, z);
}

void vtkPVVolumeOnSurfaceFilter::SetCameraFocalPoint(double x, double y, double z)
{
  this->OwnCamera->SetFocalPoint(x, y, z);
}

void vtkPVVolumeOnSurfaceFilter::SetCameraViewUp(double x, double y, double z)
{
  this->OwnCamera->SetViewUp(x, y, z);
}

void vtkPVVolumeOnSurfaceFilter::SetCameraViewAngle(double degrees)
{
  this->OwnCamera->SetViewAngle(degrees);
}

void vtkPVVolumeOnSurfaceFilter::SetCameraParallelProjection(int parallel)
{
  this->OwnCamera->SetParallelProjection(parallel);
}

// Null gives vtkVolumeProperty's defaults, as for any volume.
void vtkPVVolumeOnSurfaceFilter::SetColorTransferFunction(vtkColorTransferFunction* colors)
{
  this->OwnProperty->SetColor(colors);
}

void vtkPVVolumeOnSurfaceFilter::SetScalarOpacityFunction(vtkPiecewiseFunction* opacity)
{
  this->OwnProperty->SetScalarOpacity(opacity);
}

void vtkPVVolumeOnSurfaceFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
