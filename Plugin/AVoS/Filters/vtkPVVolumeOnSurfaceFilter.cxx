#include "vtkPVVolumeOnSurfaceFilter.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

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

vtkSmartPointer<vtkImageData> vtkPVVolumeOnSurfaceFilter::AssembleVolume(
  vtkImageData* received, vtkInformation* volumeInfo)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  int whole[6] = { 0, -1, 0, -1, 0, -1 };
  const bool part = HoldsPart(received, volumeInfo, whole);
  // Every process takes part in the same collectives, whatever it holds:
  // whether any process holds a part only, and whether any piece changed
  // since the volume was last kept (a piece changed when its scalars did:
  // ParaView modifies the image's point data on every update while the
  // scalars array stays the same).
  vtkDataArray* scalars = received ? received->GetPointData()->GetScalars() : nullptr;
  const vtkMTimeType pieceTime = scalars ? scalars->GetMTime() : 0;
  const int local[2] = { part ? 1 : 0, this->Kept && pieceTime == this->KeptFrom ? 0 : 1 };
  int any[2] = { local[0], local[1] };
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    controller->AllReduce(local, any, 2, vtkCommunicator::MAX_OP);
  }
  if (!any[0] || !controller)
  {
    const vtkSmartPointer<vtkImageData> volume =
      this->Superclass::AssembleVolume(received, volumeInfo);
    if (!volume)
    {
      return nullptr; // the superclass said why
    }
    return local[1] ? this->Keep(volume, pieceTime) : this->Kept.GetPointer();
  }
  if (!any[1])
  {
    return this->Kept;
  }

  // Each process in turn broadcasts its piece (its scalars only); every
  // process copies each piece into its place in the whole extent and counts
  // the points covered.
  auto wholeVolume = vtkSmartPointer<vtkImageData>::New();
  std::vector<unsigned char> covered;
  bool failed = false;
  for (int sender = 0; sender < controller->GetNumberOfProcesses(); ++sender)
  {
    auto piece = vtkSmartPointer<vtkImageData>::New();
    double grid[21] = { 0, -1, 0, -1, 0, -1 }; // an empty extent, as GetGrid lays it out
    if (sender == controller->GetLocalProcessId() && received && scalars)
    {
      piece->CopyStructure(received);
      piece->GetPointData()->SetScalars(scalars);
      GetGrid(received, grid);
    }
    // The grid travels on its own: the data object's serialisation keeps
    // the dimensions, not where the piece starts.
    controller->Broadcast(grid, 21, sender);
    controller->Broadcast(piece, sender);
    int pieceExtent[6];
    for (int a = 0; a < 6; ++a)
    {
      pieceExtent[a] = static_cast<int>(grid[a]);
    }
    vtkDataArray* pieceScalars = piece->GetPointData()->GetScalars();
    if (pieceExtent[0] > pieceExtent[1] || !pieceScalars || failed)
    {
      continue; // an empty piece, or a process that holds none
    }
    piece->SetExtent(pieceExtent);
    piece->SetOrigin(grid + 6);
    piece->SetSpacing(grid + 9);
    piece->SetDirectionMatrix(grid + 12);
    if (!wholeVolume->GetPointData()->GetScalars())
    {
      wholeVolume->SetExtent(whole);
      wholeVolume->SetOrigin(piece->GetOrigin());
      wholeVolume->SetSpacing(piece->GetSpacing());
      wholeVolume->SetDirectionMatrix(piece->GetDirectionMatrix());
      wholeVolume->AllocateScalars(
        pieceScalars->GetDataType(), pieceScalars->GetNumberOfComponents());
      wholeVolume->GetPointData()->GetScalars()->SetName(pieceScalars->GetName());
      covered.assign(static_cast<std::size_t>(wholeVolume->GetNumberOfPoints()), 0);
    }
    for (int a = 0; a < 3; ++a)
    {
      failed =
        failed || pieceExtent[2 * a] < whole[2 * a] || pieceExtent[2 * a + 1] > whole[2 * a + 1];
    }
    if (failed || pieceScalars->GetDataType() != wholeVolume->GetScalarType() ||
      pieceScalars->GetNumberOfComponents() != wholeVolume->GetNumberOfScalarComponents())
    {
      failed = true;
      continue;
    }
    wholeVolume->CopyAndCastFrom(piece, pieceExtent);
    for (int k = pieceExtent[4]; k <= pieceExtent[5]; ++k)
    {
      for (int j = pieceExtent[2]; j <= pieceExtent[3]; ++j)
      {
        int ijk[3] = { pieceExtent[0], j, k };
        const vtkIdType first = wholeVolume->ComputePointId(ijk);
        std::fill_n(covered.begin() + first, pieceExtent[1] - pieceExtent[0] + 1, 1);
      }
    }
  }
  if (failed || covered.empty() || std::find(covered.begin(), covered.end(), 0) != covered.end())
  {
    vtkErrorMacro(<< "The volume's pieces on the " << controller->GetNumberOfProcesses()
                  << " processes do not assemble into its whole extent (" << whole[0] << ".."
                  << whole[1] << ", " << whole[2] << ".." << whole[3] << ", " << whole[4] << ".."
                  << whole[5] << "): give the volume port a producer of its own.");
    this->Kept = nullptr;
    return nullptr;
  }
  return this->Keep(wholeVolume, pieceTime);
}

vtkImageData* vtkPVVolumeOnSurfaceFilter::Keep(vtkImageData* volume, vtkMTimeType pieceTime)
{
  this->KeptFrom = pieceTime;
  if (volume == this->Kept)
  {
    return volume; // the same image, its scalars new: nothing to compare
  }
  // The same values again (a piece produced anew for another consumer of
  // the reader, or the whole volume received where it was gathered before):
  // the volume kept stays, so that nothing downstream sees it changed.
  vtkDataArray* before = this->Kept ? this->Kept->GetPointData()->GetScalars() : nullptr;
  vtkDataArray* now = volume->GetPointData()->GetScalars();
  auto grid = [](vtkImageData* image)
  {
    std::array<double, 21> g;
    GetGrid(image, g.data());
    return g;
  };
  if (before && now && grid(this->Kept) == grid(volume) &&
    before->GetDataType() == now->GetDataType() &&
    before->GetNumberOfComponents() == now->GetNumberOfComponents() &&
    before->GetNumberOfTuples() == now->GetNumberOfTuples() &&
    std::memcmp(before->GetVoidPointer(0), now->GetVoidPointer(0),
      static_cast<std::size_t>(now->GetDataSize()) * now->GetDataTypeSize()) == 0)
  {
    return this->Kept;
  }
  this->Kept = volume;
  return volume;
}

void vtkPVVolumeOnSurfaceFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
