#include "vtkVolvisRawReader.h"

#include "vtkByteSwap.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <vtksys/RegularExpression.hxx>
#include <vtksys/SystemTools.hxx>

#include <cmath>
#include <fstream>

vtkStandardNewMacro(vtkVolvisRawReader);

namespace
{
bool IsSupportedScalarType(int type)
{
  switch (type)
  {
    case VTK_CHAR:
    case VTK_SIGNED_CHAR:
    case VTK_UNSIGNED_CHAR:
    case VTK_SHORT:
    case VTK_UNSIGNED_SHORT:
    case VTK_INT:
    case VTK_UNSIGNED_INT:
    case VTK_FLOAT:
    case VTK_DOUBLE:
      return true;
    default:
      return false;
  }
}

bool HostIsBigEndian()
{
#ifdef VTK_WORDS_BIGENDIAN
  return true;
#else
  return false;
#endif
}
}

//------------------------------------------------------------------------------
vtkVolvisRawReader::vtkVolvisRawReader()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
vtkVolvisRawReader::~vtkVolvisRawReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
bool vtkVolvisRawReader::ParseFileName(const char* fileName, int& components, int dimensions[3])
{
  if (!fileName)
  {
    return false;
  }
  const std::string name = vtksys::SystemTools::GetFilenameName(fileName);
  vtksys::RegularExpression pattern("^.+\\.([0-9]+)\\.([0-9]+)x([0-9]+)x([0-9]+)\\.raw$");
  if (!pattern.find(name))
  {
    return false;
  }
  long values[4];
  for (int i = 0; i < 4; ++i)
  {
    const std::string digits = pattern.match(i + 1);
    // More than 9 digits cannot be a plausible voxel count along one axis.
    if (digits.size() > 9)
    {
      return false;
    }
    values[i] = std::stol(digits);
    if (values[i] <= 0)
    {
      return false;
    }
  }
  components = static_cast<int>(values[0]);
  for (int i = 0; i < 3; ++i)
  {
    dimensions[i] = static_cast<int>(values[i + 1]);
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkVolvisRawReader::ReadHeader(int& components, int dimensions[3])
{
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName was set.");
    return false;
  }
  if (!ParseFileName(this->FileName, components, dimensions))
  {
    vtkErrorMacro("The file name '" << this->FileName
                                    << "' does not give the volume's dimensions: expected "
                                       "Name.<components>.<X>x<Y>x<Z>.raw.");
    return false;
  }
  if (!IsSupportedScalarType(this->DataScalarType))
  {
    vtkErrorMacro("Unsupported DataScalarType " << this->DataScalarType << ".");
    return false;
  }
  for (int i = 0; i < 3; ++i)
  {
    if (!(this->DataSpacing[i] > 0.0) || !std::isfinite(this->DataSpacing[i]) ||
      !std::isfinite(this->DataOrigin[i]))
    {
      vtkErrorMacro("Invalid DataSpacing (" << this->DataSpacing[0] << ", " << this->DataSpacing[1]
                                            << ", " << this->DataSpacing[2] << ") or DataOrigin: "
                                            << "spacing must be positive and both finite.");
      return false;
    }
  }
  if (!vtksys::SystemTools::FileExists(this->FileName, true))
  {
    vtkErrorMacro("Cannot read raw volume '" << this->FileName << "': no such file.");
    return false;
  }
  // Each factor has at most 9 digits, so the product can exceed 64 bits: a
  // wrapped product could match a small (even empty) file and announce an
  // extent no memory holds.
  unsigned long long expected = vtkDataArray::GetDataTypeSize(this->DataScalarType);
  const unsigned long long factors[4] = { static_cast<unsigned long long>(components),
    static_cast<unsigned long long>(dimensions[0]), static_cast<unsigned long long>(dimensions[1]),
    static_cast<unsigned long long>(dimensions[2]) };
  unsigned long long points = 1;
  for (int i = 0; i < 4; ++i)
  {
    if (__builtin_mul_overflow(expected, factors[i], &expected) ||
      (i > 0 && __builtin_mul_overflow(points, factors[i], &points)))
    {
      expected = 0;
      break;
    }
  }
  if (expected == 0 || points > static_cast<unsigned long long>(VTK_ID_MAX) ||
    expected > static_cast<unsigned long long>(VTK_ID_MAX))
  {
    vtkErrorMacro("The file name '" << this->FileName << "' announces " << components << " x "
                                    << dimensions[0] << " x " << dimensions[1] << " x "
                                    << dimensions[2] << " values: more than a volume can hold.");
    return false;
  }
  const unsigned long long actual = vtksys::SystemTools::FileLength(this->FileName);
  if (actual != expected)
  {
    vtkErrorMacro("Raw volume '" << this->FileName << "' is "
                                 << (actual < expected ? "truncated" : "oversized") << ": "
                                 << actual << " bytes, but its name and scalar type ("
                                 << vtkImageScalarTypeNameMacro(this->DataScalarType) << ") need "
                                 << expected << " bytes.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkVolvisRawReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  int components = 0;
  int dims[3] = { 0, 0, 0 };
  if (!this->ReadHeader(components, dims))
  {
    const int empty[6] = { 0, -1, 0, -1, 0, -1 };
    outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), empty, 6);
    vtkImageData::GetData(outInfo)->Initialize();
    return 0;
  }
  const int extent[6] = { 0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), this->DataSpacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), this->DataOrigin, 3);
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, this->DataScalarType, components);
  return 1;
}

//------------------------------------------------------------------------------
int vtkVolvisRawReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkImageData* output = vtkImageData::GetData(outInfo);
  output->Initialize();

  int components = 0;
  int dims[3] = { 0, 0, 0 };
  if (!this->ReadHeader(components, dims))
  {
    return 0;
  }
  int extent[6];
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent);
  for (int i = 0; i < 3; ++i)
  {
    if (extent[2 * i] < 0 || extent[2 * i + 1] >= dims[i] || extent[2 * i] > extent[2 * i + 1])
    {
      vtkErrorMacro("Requested extent is outside the volume or empty.");
      return 0;
    }
  }

  output->SetExtent(extent);
  output->SetSpacing(this->DataSpacing);
  output->SetOrigin(this->DataOrigin);
  output->AllocateScalars(this->DataScalarType, components);
  vtkDataArray* scalars = output->GetPointData()->GetScalars();
  scalars->SetName(this->ScalarArrayName.c_str());

  std::ifstream file(this->FileName, std::ios::in | std::ios::binary);
  if (!file)
  {
    vtkErrorMacro("Cannot open raw volume '" << this->FileName << "'.");
    output->Initialize();
    return 0;
  }

  const std::size_t voxelBytes =
    static_cast<std::size_t>(components) * vtkDataArray::GetDataTypeSize(this->DataScalarType);
  const std::size_t rowVoxels = static_cast<std::size_t>(extent[1] - extent[0] + 1);
  const std::size_t rows = static_cast<std::size_t>(extent[3] - extent[2] + 1);
  // Full-width requests read a whole slab of rows per slice in one call.
  const bool fullRows = rowVoxels == static_cast<std::size_t>(dims[0]);
  const std::size_t chunkVoxels = fullRows ? rowVoxels * rows : rowVoxels;
  char* out = static_cast<char*>(scalars->GetVoidPointer(0));

  const double progressStep = 1.0 / (extent[5] - extent[4] + 1);
  for (int z = extent[4]; z <= extent[5] && !this->AbortExecute; ++z)
  {
    for (int y = extent[2]; y <= extent[3]; y += fullRows ? static_cast<int>(rows) : 1)
    {
      const std::streamoff offset = static_cast<std::streamoff>(
        ((static_cast<std::size_t>(z) * dims[1] + y) * dims[0] + extent[0]) * voxelBytes);
      file.seekg(offset);
      file.read(out, static_cast<std::streamsize>(chunkVoxels * voxelBytes));
      if (!file)
      {
        vtkErrorMacro(
          "Read error in raw volume '" << this->FileName << "' at byte " << offset << ".");
        output->Initialize();
        return 0;
      }
      out += chunkVoxels * voxelBytes;
    }
    this->UpdateProgress((z - extent[4] + 1) * progressStep);
  }

  const int wordSize = vtkDataArray::GetDataTypeSize(this->DataScalarType);
  if (wordSize > 1 && this->DataByteOrderBigEndian != HostIsBigEndian())
  {
    vtkByteSwap::SwapVoidRange(scalars->GetVoidPointer(0),
      static_cast<size_t>(scalars->GetNumberOfValues()), static_cast<size_t>(wordSize));
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkVolvisRawReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "DataScalarType: " << vtkImageScalarTypeNameMacro(this->DataScalarType) << "\n";
  os << indent << "DataByteOrderBigEndian: " << this->DataByteOrderBigEndian << "\n";
  os << indent << "DataSpacing: (" << this->DataSpacing[0] << ", " << this->DataSpacing[1] << ", "
     << this->DataSpacing[2] << ")\n";
  os << indent << "DataOrigin: (" << this->DataOrigin[0] << ", " << this->DataOrigin[1] << ", "
     << this->DataOrigin[2] << ")\n";
  os << indent << "ScalarArrayName: " << this->ScalarArrayName << "\n";
}
