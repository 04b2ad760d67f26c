#include "avos/engine/WorkMonitor.h"

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

namespace avos
{
namespace engine
{
bool WorkMonitor::Run(
  std::int64_t total, const std::function<void()>& work, const std::function<bool(double)>& poll)
{
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::exception_ptr failure;
  std::thread worker(
    [&]
    {
      try
      {
        work();
      }
      catch (...)
      {
        failure = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex);
      done = true;
      finished.notify_one();
    });
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (!finished.wait_for(lock, Interval, [&] { return done; }))
    {
      lock.unlock();
      const double fraction =
        total > 0 ? static_cast<double>(this->Done.load(std::memory_order_relaxed)) / total : 0.0;
      if (poll(fraction))
      {
        this->Abort.store(true, std::memory_order_relaxed);
      }
      lock.lock();
    }
  }
  worker.join();
  if (failure)
  {
    std::rethrow_exception(failure);
  }
  return !this->Aborted();
}
} // namespace engine
} // namespace avos
