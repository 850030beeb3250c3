#include "gpu/gpu_worker.h"

#include <optional>
#include <tuple>

namespace sweepd::gpu {

Worker::Worker(const ContextOptions& options) {
  std::promise<std::pair<std::string, bool>> started;
  std::future<std::pair<std::string, bool>> device = started.get_future();
  thread_ = std::thread([this, options, &started] { run(options, started); });
  try {
    std::tie(renderer_, software_) = device.get();
  } catch (...) {
    thread_.join();
    throw;
  }
}

Worker::~Worker() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void Worker::post(std::function<void(Context&)> job) {
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void Worker::run(const ContextOptions& options,
                 std::promise<std::pair<std::string, bool>>& started) {
  std::optional<Context> context;
  try {
    context.emplace(options);
  } catch (...) {
    started.set_exception(std::current_exception());
    return;
  }
  started.set_value({context->renderer(),
                     context->software()});  // `started` dies with the constructor after this
  for (;;) {
    std::function<void(Context&)> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) return;  // stopping, and every queued job has run
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job(*context);
  }
}

}  // namespace sweepd::gpu
