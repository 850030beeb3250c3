// Worker: the one thread that owns a gpu::Context and runs GL jobs from a queue, in order.
//
// An EGL context is current on one thread only, so every GL call of the server goes through
// here: submit(job) queues job(Context&) and returns a std::future of its result (exceptions
// thrown by the job arrive through the future). GL objects a job creates belong to this
// thread's context; keep them in state the jobs share (e.g. a renderer created by the first
// job). The constructor waits for the context and rethrows its ContextError. The destructor
// runs the jobs already queued, then destroys the context and joins the thread.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>

#include "gpu/egl_context.h"

namespace sweepd::gpu {

class Worker {
 public:
  explicit Worker(const ContextOptions& options = {});
  ~Worker();
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  // GL_RENDERER of the worker's context, and whether it is Mesa's software rasteriser.
  const std::string& renderer() const { return renderer_; }
  bool software() const { return software_; }

  template <class Job>
  auto submit(Job&& job) -> std::future<std::invoke_result_t<Job&, Context&>> {
    using Result = std::invoke_result_t<Job&, Context&>;
    auto task = std::make_shared<std::packaged_task<Result(Context&)>>(std::forward<Job>(job));
    std::future<Result> result = task->get_future();
    post([task](Context& context) { (*task)(context); });
    return result;
  }

 private:
  void post(std::function<void(Context&)> job);
  void run(const ContextOptions& options, std::promise<std::pair<std::string, bool>>& started);

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void(Context&)>> jobs_;
  bool stopping_ = false;
  std::string renderer_;
  bool software_ = false;
  std::thread thread_;
};

}  // namespace sweepd::gpu
