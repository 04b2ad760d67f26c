// Long parallel work that reports progress and can be aborted, whatever the
// parallel loop's backend (VTK-free): the work runs on a worker thread (which
// hands it to the caller's loop, vtkSMPTools in the VTK classes), while the
// calling thread, which owns the GUI's events, the progress and the render
// window, polls every `Interval`.
#ifndef avos_engine_WorkMonitor_h
#define avos_engine_WorkMonitor_h

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>

namespace avos
{
namespace engine
{
// What the work and the polling thread share: the items done (for progress)
// and the request to abort. The work adds to Done as it finishes items and
// stops taking new ones once Aborted() is true.
class WorkMonitor
{
public:
  static constexpr std::chrono::milliseconds Interval{ 100 };

  void Finished(std::int64_t items) { this->Done.fetch_add(items, std::memory_order_relaxed); }
  bool Aborted() const { return this->Abort.load(std::memory_order_relaxed); }

  /// Runs `work` on a worker thread; every Interval until it returns, calls
  /// `poll` with the share of `total` items done and sets the abort request
  /// when `poll` returns true. An exception of the work is rethrown here.
  /// True when the work ran to its end without an abort request. An abort
  /// takes effect within one Interval plus the item each thread is on.
  bool Run(
    std::int64_t total, const std::function<void()>& work, const std::function<bool(double)>& poll);

private:
  std::atomic<std::int64_t> Done{ 0 };
  std::atomic<bool> Abort{ false };
};
} // namespace engine
} // namespace avos

#endif
