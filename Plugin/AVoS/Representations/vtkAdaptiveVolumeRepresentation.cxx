#include "vtkAdaptiveVolumeRepresentation.h"

#include "vtkAdaptiveVolumeMapper.h"
#include "vtkColorTransferFunction.h"
#include "vtkObjectFactory.h"
#include "vtkScalarsToColors.h"
#include "vtkSmartVolumeMapper.h"
#include "vtkVolumeProperty.h"

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

void vtkAdaptiveVolumeRepresentation::SetRequestedRenderMode(int mode)
{
  if (mode != vtkSmartVolumeMapper::DefaultRenderMode)
  {
    vtkWarningMacro(<< "The volume rendering mode chooses among VTK's mappers; the AVoS Volume "
                       "representation always renders with vtkAdaptiveVolumeMapper (choose its "
                       "IntegrationMethod instead).");
  }
}

void vtkAdaptiveVolumeRepresentation::SetGlobalIlluminationReach(float reach)
{
  if (reach != 0.0f)
  {
    vtkWarningMacro(<< "Global illumination reach (" << reach
                    << ") is a setting of VTK's GPU mapper, not honoured by the AVoS Volume "
                       "representation.");
  }
}

void vtkAdaptiveVolumeRepresentation::SetVolumetricScatteringBlending(float blending)
{
  if (blending != 0.0f)
  {
    vtkWarningMacro(<< "Volumetric scattering blending (" << blending
                    << ") is a setting of VTK's GPU mapper, not honoured by the AVoS Volume "
                       "representation.");
  }
}

void vtkAdaptiveVolumeRepresentation::UpdateMapperParameters()
{
  this->Superclass::UpdateMapperParameters();
  // ParaView's rule for the smart mapper: independent components take the
  // colour map's vector mode (its RGB colours mode reads as one component),
  // dependent ones every component.
  int mode = vtkAdaptiveVolumeMapper::DISABLED, component = 0;
  vtkColorTransferFunction* colours = this->Property->GetRGBTransferFunction(0);
  if (this->Property->GetIndependentComponents() && colours)
  {
    mode = colours->GetVectorMode() == vtkScalarsToColors::MAGNITUDE
      ? vtkAdaptiveVolumeMapper::MAGNITUDE
      : vtkAdaptiveVolumeMapper::COMPONENT;
    component = colours->GetVectorComponent();
  }
  this->AdaptiveMapper->SetVectorMode(mode);
  this->AdaptiveMapper->SetVectorComponent(component);
}

void vtkAdaptiveVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "AdaptiveMapper: " << this->AdaptiveMapper << "\n";
}
