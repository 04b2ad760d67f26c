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

bool ScalarsInPlace(
  vtkDataArray* scalars, const int dimensions[3], avos::engine::Scalars& view, int component)
{
  switch (scalars->GetDataType())
  {
    vtkTemplateMacro(view.Type = TypeOf<VTK_TT>());
    default:
      return false;
  }
  const int tuple = scalars->GetNumberOfComponents();
  view.Data = scalars->GetVoidPointer(component >= 0 ? component : 0);
  view.Components = component >= 0 ? 1 : tuple;
  view.Stride = tuple;
  std::copy(dimensions, dimensions + 3, view.Dimensions);
  return true;
}

avos::engine::Volume::Type EngineVolume::EngineType(int vtkScalarType)
{
  using Scalar = avos::engine::ScalarType;
  using Type = avos::engine::Volume::Type;
  Scalar scalar = Scalar::Float64;
  switch (vtkScalarType)
  {
    vtkTemplateMacro(scalar = TypeOf<VTK_TT>());
  }
  switch (scalar)
  {
    case Scalar::UInt8:
      return Type::UInt8;
    case Scalar::UInt16:
      return Type::UInt16;
    case Scalar::Int8:
      return Type::Int8;
    case Scalar::Int16:
      return Type::Int16;
    default:
      return Type::Float32;
  }
}

const avos::engine::Volume* EngineVolume::Update(
  vtkDataArray* scalars, const int dimensions[3], int component)
{
  using Type = avos::engine::Volume::Type;
  const std::array<int, 3> dims{ { dimensions[0], dimensions[1], dimensions[2] } };
  const int type = scalars->GetDataType();
  const int tuple = scalars->GetNumberOfComponents();
  const bool inPlace = EngineType(type) != Type::Float32 || type == VTK_FLOAT;
  if (!inPlace && scalars == this->Scalars && scalars->GetMTime() == this->ScalarsTime &&
    dims == this->Dimensions && component == this->Component)
  {
    return this->Usable ? &this->View : nullptr;
  }
  if (component < 0 || component >= tuple)
  {
    return nullptr;
  }
  const vtkIdType count = scalars->GetNumberOfTuples();
  std::copy(dimensions, dimensions + 3, this->View.Dimensions);
  this->View.Scalars = EngineType(type);
  // Whether the kernels can index it, before converting anything.
  this->View.Data = scalars->GetVoidPointer(component);
  this->View.Stride = tuple;
  this->View.Trailing = tuple - 1 - component;
  this->Usable = avos::engine::Validate(this->View).empty() &&
    count == static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2];
  if (inPlace || !this->Usable)
  {
    std::vector<float>().swap(this->Converted);
  }
  else
  {
    this->Converted.resize(static_cast<std::size_t>(count));
    float* target = this->Converted.data();
    auto convert = [&](auto* data)
    {
      vtkSMPTools::For(0, count,
        [&](vtkIdType begin, vtkIdType end)
        {
          for (vtkIdType i = begin; i < end; ++i)
          {
            target[i] = static_cast<float>(data[i * tuple]);
          }
        });
    };
    switch (type)
    {
      vtkTemplateMacro(convert(static_cast<const VTK_TT*>(scalars->GetVoidPointer(component))));
      default:
        this->Usable = false;
    }
    this->View.Data = target;
    this->View.Stride = 1;
    this->View.Trailing = 0;
  }
  this->Scalars = scalars;
  this->ScalarsTime = scalars->GetMTime();
  this->Component = component;
  this->Dimensions = dims;
  return this->Usable ? &this->View : nullptr;
}
}
