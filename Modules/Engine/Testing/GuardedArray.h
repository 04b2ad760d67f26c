// Scalars stored so that their last byte ends a page and the page after it
// is unreadable (PROT_NONE): a kernel that reads past the end of the
// caller's array crashes the test instead of reading padding that a VTK
// array does not have.
#ifndef avos_engine_GuardedArray_h
#define avos_engine_GuardedArray_h

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

namespace avostest
{
template <typename T>
class GuardedArray
{
public:
  GuardedArray() = default;
  template <typename U>
  explicit GuardedArray(const std::vector<U>& values)
  {
    const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    const std::size_t bytes = values.size() * sizeof(T);
    const std::size_t pages = (bytes + page - 1) / page * page;
    this->Length = pages + page;
    void* base =
      mmap(nullptr, this->Length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (base == MAP_FAILED || mprotect(static_cast<char*>(base) + pages, page, PROT_NONE) != 0)
    {
      throw std::runtime_error("GuardedArray: mmap or mprotect failed");
    }
    this->Base = base;
    this->Data = reinterpret_cast<T*>(static_cast<char*>(base) + pages - bytes);
    this->Size = values.size();
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      this->Data[i] = static_cast<T>(values[i]);
    }
  }
  GuardedArray(GuardedArray&& other) noexcept { this->Swap(other); }
  GuardedArray& operator=(GuardedArray&& other) noexcept
  {
    this->Swap(other);
    return *this;
  }
  GuardedArray(const GuardedArray&) = delete;
  GuardedArray& operator=(const GuardedArray&) = delete;
  ~GuardedArray()
  {
    if (this->Base)
    {
      munmap(this->Base, this->Length);
    }
  }

  const T* data() const { return this->Data; }
  std::size_t size() const { return this->Size; }

private:
  void Swap(GuardedArray& other)
  {
    std::swap(this->Base, other.Base);
    std::swap(this->Length, other.Length);
    std::swap(this->Data, other.Data);
    std::swap(this->Size, other.Size);
  }

  void* Base = nullptr;
  std::size_t Length = 0;
  T* Data = nullptr;
  std::size_t Size = 0;
};
} // namespace avostest

#endif
