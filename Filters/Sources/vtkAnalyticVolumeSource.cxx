#include "vtkAnalyticVolumeSource.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <cmath>

vtkStandardNewMacro(vtkAnalyticVolumeSource);

namespace
{
// Marschner and Lobb (1994), equation (3), with their parameters.
double MarschnerLobb(double x, double y, double z)
{
  constexpr double alpha = 0.25;
  constexpr double fM = 6.0;
  const double pi = vtkMath::Pi();
  const double r = std::sqrt(x * x + y * y);
  const double rhoR = std::cos(2.0 * pi * fM * std::cos(pi * r / 2.0));
  return (1.0 - std::sin(pi * z / 2.0) + alpha * (1.0 + rhoR)) / (2.0 * (1.0 + alpha));
}

template <typename T>
void Fill(const vtkAnalyticVolumeSource* self, const int extent[6], const double origin[3],
  const double spacing[3], double shift, double scale, T* out)
{
  const vtkIdType nx = extent[1] - extent[0] + 1;
  const vtkIdType ny = extent[3] - extent[2] + 1;
  vtkSMPTools::For(extent[4], extent[5] + 1,
    [&](vtkIdType zBegin, vtkIdType zEnd)
    {
      for (vtkIdType k = zBegin; k < zEnd; ++k)
      {
        T* slice = out + (k - extent[4]) * nx * ny;
        double x[3];
        x[2] = origin[2] + static_cast<double>(k) * spacing[2];
        for (vtkIdType j = 0; j < ny; ++j)
        {
          x[1] = origin[1] + static_cast<double>(j + extent[2]) * spacing[1];
          for (vtkIdType i = 0; i < nx; ++i)
          {
            x[0] = origin[0] + static_cast<double>(i + extent[0]) * spacing[0];
            slice[j * nx + i] = static_cast<T>(shift + scale * self->EvaluateFunction(x));
          }
        }
      }
    });
}
}

//------------------------------------------------------------------------------
vtkAnalyticVolumeSource::vtkAnalyticVolumeSource()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
double vtkAnalyticVolumeSource::EvaluateFunction(const double x[3]) const
{
  switch (this->Function)
  {
    case LINEAR_RAMP:
      return x[this->RampAxis];
    case SPHERE_DISTANCE:
      return std::sqrt(vtkMath::Distance2BetweenPoints(x, this->Center));
    case MARSCHNER_LOBB:
      return MarschnerLobb(x[0], x[1], x[2]);
    case CONSTANT:
    default:
      return 0.0;
  }
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeSource::ComputeSpacing(double spacing[3]) const
{
  for (int i = 0; i < 3; ++i)
  {
    spacing[i] = this->Dimensions[i] > 1
      ? (this->Bounds[2 * i + 1] - this->Bounds[2 * i]) / (this->Dimensions[i] - 1)
      : 1.0;
  }
}

//------------------------------------------------------------------------------
bool vtkAnalyticVolumeSource::CheckParameters()
{
  for (int i = 0; i < 3; ++i)
  {
    if (this->Dimensions[i] < 1)
    {
      vtkErrorMacro("Dimensions must be at least 1 along each axis; got ("
        << this->Dimensions[0] << ", " << this->Dimensions[1] << ", " << this->Dimensions[2]
        << ").");
      return false;
    }
    if (!std::isfinite(this->Bounds[2 * i]) || !std::isfinite(this->Bounds[2 * i + 1]) ||
      (this->Dimensions[i] > 1 && !(this->Bounds[2 * i + 1] > this->Bounds[2 * i])))
    {
      vtkErrorMacro("Bounds must be finite with each max above its min (zero spacing is invalid).");
      return false;
    }
  }
  if (this->OutputScalarType != VTK_FLOAT && this->OutputScalarType != VTK_DOUBLE)
  {
    vtkErrorMacro("OutputScalarType must be VTK_FLOAT or VTK_DOUBLE.");
    return false;
  }
  if (!std::isfinite(this->ScalarShift) || !std::isfinite(this->ScalarScale))
  {
    vtkErrorMacro("ScalarShift and ScalarScale must be finite.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkAnalyticVolumeSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (!this->CheckParameters())
  {
    const int empty[6] = { 0, -1, 0, -1, 0, -1 };
    outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), empty, 6);
    vtkImageData::GetData(outInfo)->Initialize();
    return 0;
  }
  const int extent[6] = { 0, this->Dimensions[0] - 1, 0, this->Dimensions[1] - 1, 0,
    this->Dimensions[2] - 1 };
  double spacing[3];
  this->ComputeSpacing(spacing);
  const double origin[3] = { this->Bounds[0], this->Bounds[2], this->Bounds[4] };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, this->OutputScalarType, 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkAnalyticVolumeSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkImageData* output = vtkImageData::GetData(outInfo);
  output->Initialize();
  if (!this->CheckParameters())
  {
    return 0;
  }

  int extent[6];
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent);
  double spacing[3];
  this->ComputeSpacing(spacing);
  const double origin[3] = { this->Bounds[0], this->Bounds[2], this->Bounds[4] };
  output->SetExtent(extent);
  output->SetSpacing(spacing);
  output->SetOrigin(origin);
  output->AllocateScalars(this->OutputScalarType, 1);
  vtkDataArray* scalars = output->GetPointData()->GetScalars();
  scalars->SetName("scalars");

  if (this->OutputScalarType == VTK_FLOAT)
  {
    Fill(this, extent, origin, spacing, this->ScalarShift, this->ScalarScale,
      static_cast<float*>(scalars->GetVoidPointer(0)));
  }
  else
  {
    Fill(this, extent, origin, spacing, this->ScalarShift, this->ScalarScale,
      static_cast<double*>(scalars->GetVoidPointer(0)));
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeSource::PrintSelf(ostream& os, vtkIndent indent)
{
  static const char* names[] = { "Constant", "LinearRamp", "SphereDistance", "MarschnerLobb" };
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Function: " << names[this->Function] << "\n";
  os << indent << "Dimensions: (" << this->Dimensions[0] << ", " << this->Dimensions[1] << ", "
     << this->Dimensions[2] << ")\n";
  os << indent << "Bounds: (" << this->Bounds[0] << ", " << this->Bounds[1] << ", "
     << this->Bounds[2] << ", " << this->Bounds[3] << ", " << this->Bounds[4] << ", "
     << this->Bounds[5] << ")\n";
  os << indent << "ScalarShift: " << this->ScalarShift << "\n";
  os << indent << "ScalarScale: " << this->ScalarScale << "\n";
  os << indent << "RampAxis: " << this->RampAxis << "\n";
  os << indent << "Center: (" << this->Center[0] << ", " << this->Center[1] << ", "
     << this->Center[2] << ")\n";
  os << indent << "OutputScalarType: " << vtkImageScalarTypeNameMacro(this->OutputScalarType)
     << "\n";
}
