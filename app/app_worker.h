// A long-lived worker thread for the pipeline's per-frame side jobs.
//
// The pipeline used to start a thread per job (std::async): two to three a
// frame. Each new thread that calls into OpenCV gets its own thread-local
// data, which OpenCV keeps after the thread ends (about 0.8 KB a frame in
// a replay, 5.7 MB over 7,000 frames: the live heap grew without bound).
// A Worker runs every job on the same thread, so that data is allocated
// once.
#ifndef RIPPLE_APP_APP_WORKER_H_
#define RIPPLE_APP_APP_WORKER_H_

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>

namespace ripple::app {

// Runs jobs one after another, in the order given, on one thread started
// by the first job. The destructor finishes the jobs already given, then
// joins the thread.
class Worker {
 public:
  Worker() = default;
  ~Worker();
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  // Queues `job`; its result (or exception) arrives through the future.
  template <typename F>
  std::future<std::invoke_result_t<F&>> Run(F job) {
    using R = std::invoke_result_t<F&>;
    auto task = std::make_shared<std::packaged_task<R()>>(std::move(job));
    std::future<R> result = task->get_future();
    Post([task] { (*task)(); });
    return result;
  }

  // The worker's thread (a default id before the first job).
  std::thread::id thread_id() const;

 private:
  void Post(std::function<void()> job);
  void Loop();

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stop_ = false;
  std::thread thread_;
};

// A future that waits for its job on destruction, as std::async's does: a
// job that refers to the caller's locals never outlives them, also when
// the caller leaves early (an exception).
template <typename R>
class JoinedFuture {
 public:
  JoinedFuture() = default;
  explicit JoinedFuture(std::future<R> f) : future_(std::move(f)) {}
  JoinedFuture(JoinedFuture&&) = default;
  JoinedFuture& operator=(JoinedFuture&& other) {
    Wait();
    future_ = std::move(other.future_);
    return *this;
  }
  ~JoinedFuture() { Wait(); }

  bool valid() const { return future_.valid(); }
  R get() { return future_.get(); }
  template <typename Rep, typename Period>
  std::future_status wait_for(
      const std::chrono::duration<Rep, Period>& d) const {
    return future_.wait_for(d);
  }

 private:
  void Wait() {
    if (future_.valid()) future_.wait();
  }
  std::future<R> future_;
};

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_WORKER_H_
