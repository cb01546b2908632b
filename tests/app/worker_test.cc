#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <iterator>
#include <stdexcept>
#include <thread>
#include <vector>

#include "app/app_worker.h"

namespace ripple::app {
namespace {

int ThreadsOfThisProcess() {
  const std::filesystem::directory_iterator tasks("/proc/self/task");
  return static_cast<int>(std::distance(begin(tasks), end(tasks)));
}

TEST(WorkerTest, RunsEveryJobOnOneThreadOfItsOwn) {
  Worker worker;
  EXPECT_EQ(worker.thread_id(), std::thread::id());
  const int before = ThreadsOfThisProcess();
  std::vector<std::thread::id> ran_on;
  for (int i = 0; i < 50; ++i) {
    std::future<int> f = worker.Run([i, &ran_on] {
      ran_on.push_back(std::this_thread::get_id());
      return i * i;
    });
    EXPECT_EQ(f.get(), i * i);
  }
  // One thread for all 50 jobs (std::async started one a job, and
  // OpenCV keeps data of each thread that called it).
  EXPECT_EQ(ThreadsOfThisProcess(), before + 1);
  ASSERT_EQ(ran_on.size(), 50u);
  for (const std::thread::id& id : ran_on) {
    EXPECT_EQ(id, worker.thread_id());
    EXPECT_NE(id, std::this_thread::get_id());
  }
}

TEST(WorkerTest, PassesAJobsExceptionToItsFuture) {
  Worker worker;
  std::future<int> f =
      worker.Run([]() -> int { throw std::runtime_error("job failed"); });
  EXPECT_THROW(f.get(), std::runtime_error);
  EXPECT_EQ(worker.Run([] { return 7; }).get(), 7);  // still working
}

TEST(WorkerTest, FinishesQueuedJobsBeforeItEnds) {
  std::atomic<int> done{0};
  {
    Worker worker;
    for (int i = 0; i < 5; ++i) {
      worker.Run([&done] {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        ++done;
      });
    }
  }
  EXPECT_EQ(done.load(), 5);
}

TEST(WorkerTest, JoinedFutureWaitsForItsJobWhenDestroyed) {
  Worker worker;
  std::atomic<bool> finished{false};
  {
    JoinedFuture<void> f(worker.Run([&finished] {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      finished = true;
    }));
    EXPECT_TRUE(f.valid());
  }
  EXPECT_TRUE(finished.load());
}

}  // namespace
}  // namespace ripple::app
