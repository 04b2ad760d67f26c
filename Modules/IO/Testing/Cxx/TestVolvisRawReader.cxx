// Reads small raw volumes written here: values, sub-extents (streaming), byte
// order, components, and every bad input with its message.
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkVolvisRawReader.h"

#include "avosTestHelpers.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace
{
std::string Bytes(const std::vector<std::uint8_t>& values)
{
  return std::string(values.begin(), values.end());
}

// Value of voxel (i, j, k) in the 5x4x3 test volumes.
int VoxelValue(int i, int j, int k)
{
  return i + 5 * j + 20 * k;
}
}

int TestVolvisRawReader(int argc, char* argv[])
{
  bool ok = true;
  const int dims[3] = { 5, 4, 3 };

  // uint8, one component.
  std::vector<std::uint8_t> u8;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        u8.push_back(static_cast<std::uint8_t>(VoxelValue(i, j, k)));
  const std::string u8Path = avostest::TempPath(argc, argv, "Ramp.1.5x4x3.raw");
  avostest::WriteFile(u8Path, Bytes(u8));

  vtkNew<vtkVolvisRawReader> reader;
  avostest::ExpectedErrors errors(reader);
  reader->SetFileName(u8Path.c_str());
  reader->SetDataSpacing(1.0, 0.75, 2.0);
  reader->SetDataOrigin(-1.0, 0.0, 3.0);
  reader->Update();
  ok &= errors.None("uint8 read");
  vtkImageData* image = reader->GetOutput();
  int outDims[3];
  image->GetDimensions(outDims);
  ok &= outDims[0] == 5 && outDims[1] == 4 && outDims[2] == 3;
  ok &= image->GetSpacing()[1] == 0.75 && image->GetOrigin()[2] == 3.0;
  ok &= image->GetScalarType() == VTK_UNSIGNED_CHAR && image->GetNumberOfScalarComponents() == 1;
  ok &= std::string(image->GetPointData()->GetScalars()->GetName()) == "density";
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i)
        ok &= image->GetScalarComponentAsDouble(i, j, k, 0) == VoxelValue(i, j, k);
  if (!ok)
  {
    std::cerr << "FAIL: uint8 volume\n";
  }

  // Streaming: a fresh reader asked for a sub-extent reads exactly those
  // voxels (partial rows too).
  const int sub[6] = { 1, 3, 2, 3, 1, 2 };
  vtkNew<vtkVolvisRawReader> streamed;
  streamed->SetFileName(u8Path.c_str());
  streamed->UpdateExtent(sub);
  image = streamed->GetOutput();
  int ext[6];
  image->GetExtent(ext);
  for (int i = 0; i < 6; ++i)
  {
    ok &= ext[i] == sub[i];
  }
  for (int k = sub[4]; k <= sub[5]; ++k)
    for (int j = sub[2]; j <= sub[3]; ++j)
      for (int i = sub[0]; i <= sub[1]; ++i)
        ok &= image->GetScalarComponentAsDouble(i, j, k, 0) == VoxelValue(i, j, k);
  ok &= image->GetNumberOfPoints() == 3 * 2 * 2;
  if (!ok)
  {
    std::cerr << "FAIL: sub-extent\n";
  }

  // uint16 in both byte orders, two components.
  for (bool bigEndian : { false, true })
  {
    std::vector<std::uint8_t> u16;
    for (int v = 0; v < 5 * 4 * 3; ++v)
    {
      for (int c = 0; c < 2; ++c)
      {
        const int value = 1000 * v + 7 * c + 300;
        const std::uint8_t lo = value & 0xff, hi = (value >> 8) & 0xff;
        u16.push_back(bigEndian ? hi : lo);
        u16.push_back(bigEndian ? lo : hi);
      }
    }
    const std::string path = avostest::TempPath(argc, argv, "Wide.2.5x4x3.raw");
    avostest::WriteFile(path, Bytes(u16));
    vtkNew<vtkVolvisRawReader> wide;
    avostest::ExpectedErrors wideErrors(wide);
    wide->SetFileName(path.c_str());
    wide->SetDataScalarTypeToUnsignedShort();
    wide->SetDataByteOrderBigEndian(bigEndian);
    wide->Update();
    bool wideOk = wideErrors.None("uint16 read");
    vtkImageData* w = wide->GetOutput();
    wideOk &= w->GetScalarType() == VTK_UNSIGNED_SHORT && w->GetNumberOfScalarComponents() == 2;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 5; ++i)
          for (int c = 0; c < 2; ++c)
            wideOk &= w->GetScalarComponentAsDouble(i, j, k, c) ==
              1000 * (i + 5 * j + 20 * k) + 7 * c + 300;
    ok &= wideOk;
    if (!wideOk)
    {
      std::cerr << "FAIL: uint16 " << (bigEndian ? "big" : "little") << " endian\n";
    }
  }

  // Bad input: message, and an empty output.
  auto expectFailure = [&](const std::string& what, const std::string& message)
  {
    reader->Update();
    const bool failed =
      errors.Check(what, message) && reader->GetOutput()->GetNumberOfPoints() == 0;
    ok &= failed;
  };
  reader->SetDataSpacing(1, 1, 1);
  reader->SetFileName(nullptr);
  expectFailure("no file name", "No FileName was set");
  reader->SetFileName(avostest::TempPath(argc, argv, "Missing.1.5x4x3.raw").c_str());
  expectFailure("missing file", "no such file");
  const std::string noDims = avostest::TempPath(argc, argv, "volume.raw");
  avostest::WriteFile(noDims, Bytes(u8));
  reader->SetFileName(noDims.c_str());
  expectFailure("name without dims", "does not give the volume's dimensions");
  const std::string zeroDim = avostest::TempPath(argc, argv, "Flat.1.5x0x3.raw");
  avostest::WriteFile(zeroDim, "");
  reader->SetFileName(zeroDim.c_str());
  expectFailure("zero dimension", "does not give the volume's dimensions");
  // 2^29 x 2^29 x 64 one-byte values are 2^64 bytes: a 64-bit product wraps
  // to 0 and an empty file would match it.
  const std::string wrapped = avostest::TempPath(argc, argv, "Wrap.1.536870912x536870912x64.raw");
  avostest::WriteFile(wrapped, "");
  reader->SetFileName(wrapped.c_str());
  expectFailure("size overflow", "more than a volume can hold");
  const std::string truncated = avostest::TempPath(argc, argv, "Short.1.5x4x3.raw");
  avostest::WriteFile(truncated, Bytes(u8).substr(0, 59));
  reader->SetFileName(truncated.c_str());
  expectFailure("truncated", "is truncated: 59 bytes, but its name and scalar type");
  const std::string oversized = avostest::TempPath(argc, argv, "Long.1.5x4x3.raw");
  avostest::WriteFile(oversized, Bytes(u8) + "x");
  reader->SetFileName(oversized.c_str());
  expectFailure("oversized", "is oversized: 61 bytes");
  reader->SetFileName(u8Path.c_str());
  reader->SetDataScalarTypeToUnsignedShort();
  expectFailure("wrong scalar type", "is truncated: 60 bytes");
  reader->SetDataScalarType(VTK_BIT);
  expectFailure("unsupported type", "Unsupported DataScalarType");
  reader->SetDataScalarTypeToUnsignedChar();
  reader->SetDataSpacing(1, 0, 1);
  expectFailure("zero spacing", "spacing must be positive");
  reader->SetDataSpacing(1, 1, 1);
  reader->SetDataOrigin(0, std::nan(""), 0);
  expectFailure("NaN origin", "Invalid DataSpacing");

  // And it recovers once the input is good again.
  reader->SetDataOrigin(0, 0, 0);
  reader->Update();
  ok &= errors.None("recovery") && reader->GetOutput()->GetNumberOfPoints() == 60;

  int components = 0;
  int parsed[3];
  ok &= vtkVolvisRawReader::ParseFileName("/a.b/Bonsai.1.256x256x256.raw", components, parsed) &&
    components == 1 && parsed[0] == 256 && parsed[2] == 256;
  ok &= !vtkVolvisRawReader::ParseFileName("Bonsai.1.256x256.raw", components, parsed);
  ok &= !vtkVolvisRawReader::ParseFileName("Bonsai.1.99999999999x2x2.raw", components, parsed);
  ok &= !vtkVolvisRawReader::ParseFileName(nullptr, components, parsed);
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
