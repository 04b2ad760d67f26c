// Fuzz target for vtkVolvisRawReader (libFuzzer: scripts/fuzz.sh; replayed on
// its corpus by the test IO-FuzzVolvisRawReaderReplay).
//
// The input chooses the scalar type (supported or not), the byte order, a
// sub-extent request, the file's name (any bytes a Linux name may hold: the
// name gives the dimensions) and its content. Required: an error message and
// an empty output, or no error and an output whose dimensions are the name's
// and whose values are the file's bytes. A violation aborts.
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkPointData.h"
#include "vtkTestErrorObserver.h"
#include "vtkVolvisRawReader.h"

#include "avosFuzz.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace
{
using avosfuzz::Require;

const std::string& Folder()
{
  static const std::string folder = avosfuzz::TemporaryFolder("avos-fuzz-raw");
  return folder;
}

// The scalar types the reader supports, then two it must refuse.
constexpr int Types[] = { VTK_UNSIGNED_CHAR, VTK_CHAR, VTK_SIGNED_CHAR, VTK_SHORT,
  VTK_UNSIGNED_SHORT, VTK_INT, VTK_UNSIGNED_INT, VTK_FLOAT, VTK_DOUBLE, VTK_BIT, VTK_LONG_LONG };
constexpr int SupportedTypes = 9;
} // namespace

// Once, before the first input: the errors go to observers, not the terminal.
extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if (size < 3)
  {
    return 0;
  }
  const int typeIndex = data[0] % (sizeof(Types) / sizeof(Types[0]));
  const int type = Types[typeIndex];
  const bool bigEndian = data[1] & 1;
  const bool subExtent = data[1] & 2;
  const std::size_t nameLength = std::min<std::size_t>(data[2] % 96, size - 3);
  std::string name(reinterpret_cast<const char*>(data + 3), nameLength);
  for (char& c : name)
  {
    if (c == '/' || c == '\0')
    {
      c = '_';
    }
  }
  if (name.empty() || name == "." || name == "..")
  {
    name = "_" + name;
  }
  const std::string path = Folder() + "/" + name;
  const std::uint8_t* content = data + 3 + nameLength;
  const std::size_t contentSize = size - 3 - nameLength;
  avosfuzz::WriteFile(path, content, contentSize);

  vtkNew<vtkVolvisRawReader> reader;
  vtkNew<vtkTest::ErrorObserver> errors;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->SetFileName(path.c_str());
  reader->SetDataScalarType(type);
  reader->SetDataByteOrderBigEndian(bigEndian);
  int components = 0, dims[3] = { 0, 0, 0 };
  const bool named = vtkVolvisRawReader::ParseFileName(path.c_str(), components, dims);
  int extent[6] = { 0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1 };
  if (subExtent && named)
  {
    extent[1] /= 2; // a partial row and a partial slab
    extent[2] = extent[3] / 2;
  }
  if (subExtent)
  {
    reader->UpdateInformation();
    reader->UpdateExtent(extent);
  }
  else
  {
    reader->Update();
  }
  vtkImageData* image = reader->GetOutput();
  std::remove(path.c_str());

  if (errors->GetError())
  {
    Require(!errors->GetErrorMessage().empty(), "a failure says why");
    Require(image->GetNumberOfPoints() == 0, "a failure leaves an empty output");
    return 0;
  }
  Require(
    named && typeIndex < SupportedTypes, "a success needs a volvis name and a supported type");
  const std::size_t wordSize = static_cast<std::size_t>(vtkDataArray::GetDataTypeSize(type));
  Require(
    static_cast<std::size_t>(components) * dims[0] * dims[1] * dims[2] * wordSize == contentSize,
    "the file's size is the name's");
  int got[6];
  image->GetExtent(got);
  Require(std::memcmp(got, extent, sizeof got) == 0, "the requested extent");
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  Require(
    scalars && scalars->GetDataType() == type && scalars->GetNumberOfComponents() == components,
    "scalars of the requested type");
  // The first requested voxel's first value, in the host's byte order.
  const std::size_t first =
    ((static_cast<std::size_t>(extent[4]) * dims[1] + extent[2]) * dims[0] + extent[0]) *
    components * wordSize;
  std::uint8_t expected[8];
  std::memcpy(expected, content + first, wordSize);
#ifdef VTK_WORDS_BIGENDIAN
  const bool swap = !bigEndian;
#else
  const bool swap = bigEndian;
#endif
  if (swap)
  {
    std::reverse(expected, expected + wordSize);
  }
  Require(std::memcmp(scalars->GetVoidPointer(0), expected, wordSize) == 0, "the first value");
  return 0;
}
