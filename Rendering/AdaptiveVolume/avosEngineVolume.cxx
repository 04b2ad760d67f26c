#include "avosEngineVolume.h"

#include "vtkDataArray.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <type_traits>

namespace avos
{
namespace
{
// The engine's type of scalars of type T.
template <typename T>
avos::engine::ScalarType TypeOf()
{
  using Type = avos::engine::ScalarType;
  if (std::is_floating_point<T>::value)
  {
    return sizeof(T) == 4 ? Type::Float32 : Type::Float64;
  }
  const bool isSigned = std::is_signed<T>::value;
  switch (sizeof(T))
  {
    case 1:
      return isSigned ? Type::Int8 : Type::UInt8;
    case 2:
      return isSigned ? Type::Int16 : Type::UInt16;
    case 4:
      return isSigned ? Type::Int32 : Type::UInt32;
    default:
      return isSigned ? Type::Int64 : Type::UInt64;
  }
}
}

bool ScalarsInPlace(vtkDataArray* scalars, const int dimensions[3], avos::engine::Scalars& view)
{
  switch (scalars->GetDataType())
  {
    vtkTemplateMacro(view.Type = TypeOf<VTK_TT>());
    default:
      return false;
  }
  view.Data = scalars->GetVoidPointer(0);
  std::copy(dimensions, dimensions + 3, view.Dimensions);
  return true;
}

avos::engine::Volume::Type EngineVolume::StoredType(int vtkScalarType)
{
  using Type = avos::engine::Volume::Type;
  return vtkScalarType == VTK_UNSIGNED_CHAR
    ? Type::UInt8
    : (vtkScalarType == VTK_UNSIGNED_SHORT ? Type::UInt16 : Type::Float32);
}

const avos::engine::Volume* EngineVolume::Update(vtkDataArray* scalars, const int dimensions[3])
{
  const std::array<int, 3> dims{ { dimensions[0], dimensions[1], dimensions[2] } };
  if (scalars == this->Scalars && scalars->GetMTime() == this->ScalarsTime &&
    dims == this->Dimensions)
  {
    return this->Usable ? &this->View : nullptr;
  }
  using Type = avos::engine::Volume::Type;
  const int type = scalars->GetDataType();
  const Type kept = StoredType(type);
  const std::size_t bytes = kept == Type::UInt8 ? 1 : (kept == Type::UInt16 ? 2 : 4);
  const vtkIdType count = scalars->GetNumberOfTuples();
  std::copy(dimensions, dimensions + 3, this->View.Dimensions);
  this->View.Scalars = kept;
  // Whether the kernels can index it, before allocating anything.
  static const unsigned char unallocated = 0;
  this->View.Data = &unallocated;
  this->Usable = avos::engine::Validate(this->View).empty() &&
    count == static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2];
  if (this->Usable)
  {
    this->Data.assign(bytes * static_cast<std::size_t>(count) + avos::engine::Volume::Padding, 0);
    unsigned char* target = this->Data.data();
    bool known = true;
    auto copy = [&](auto* data)
    {
      vtkSMPTools::For(0, count,
        [&](vtkIdType begin, vtkIdType end)
        {
          if (kept != Type::Float32)
          {
            std::copy(reinterpret_cast<const unsigned char*>(data + begin),
              reinterpret_cast<const unsigned char*>(data + end), target + bytes * begin);
            return;
          }
          float* floats = reinterpret_cast<float*>(target);
          for (vtkIdType i = begin; i < end; ++i)
          {
            floats[i] = static_cast<float>(data[i]);
          }
        });
    };
    switch (type)
    {
      vtkTemplateMacro(copy(static_cast<const VTK_TT*>(scalars->GetVoidPointer(0))));
      default:
        known = false;
    }
    this->View.Data = target;
    this->Usable = known;
  }
  this->Scalars = scalars;
  this->ScalarsTime = scalars->GetMTime();
  this->Dimensions = dims;
  return this->Usable ? &this->View : nullptr;
}
}
