#include "vtkAdaptiveVolumeRepresentation.h"

#include "vtkAdaptiveVolumeMapper.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkAdaptiveVolumeRepresentation);

vtkAdaptiveVolumeRepresentation::vtkAdaptiveVolumeRepresentation()
{
  auto mapper = vtkSmartPointer<vtkAdaptiveVolumeMapper>::New();
  this->AdaptiveMapper = mapper;
  // The superclass hands its mapper the data and the array to render, and
  // sets it on its actor at each render (UpdateMapperParameters).
  this->VolumeMapper = mapper;
}

vtkAdaptiveVolumeRepresentation::~vtkAdaptiveVolumeRepresentation() = default;

void vtkAdaptiveVolumeRepresentation::SetIntegrationMethod(int method)
{
  this->AdaptiveMapper->SetIntegrationMethod(method);
}

void vtkAdaptiveVolumeRepresentation::SetTolerance(double tolerance)
{
  this->AdaptiveMapper->SetTolerance(tolerance);
}

void vtkAdaptiveVolumeRepresentation::SetSampleDistance(double distance)
{
  this->AdaptiveMapper->SetSampleDistance(distance);
}

void vtkAdaptiveVolumeRepresentation::SetOpacityModel(int model)
{
  this->AdaptiveMapper->SetOpacityModel(model);
}

void vtkAdaptiveVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "AdaptiveMapper: " << this->AdaptiveMapper << "\n";
}
