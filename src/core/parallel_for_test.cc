#include "core/parallel_for.h"

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "core/rng.h"

namespace mcpose {
namespace {

TEST(ParallelFor, VisitsEveryIndexOnceForAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    ThreadPool pool(threads);
    EXPECT_EQ(pool.size(), threads);
    for (int64_t n : {0, 1, 7, 1000}) {
      std::vector<std::atomic<int>> hits(n);
      std::atomic<int> bad_worker{0};
      pool.ParallelFor(n, [&](int64_t b, int64_t e, int worker) {
        if (worker < 0 || worker >= threads) ++bad_worker;
        for (int64_t i = b; i < e; ++i) ++hits[i];
      });
      for (int64_t i = 0; i < n; ++i) EXPECT_EQ(hits[i].load(), 1) << "n " << n << " i " << i;
      EXPECT_EQ(bad_worker.load(), 0);
    }
  }
}

// Jobs back to back (the workers still spinning), after pauses longer than the spin (the
// workers asleep on the condition variable), and with chunks slower than the spin (the caller
// asleep until the last chunk is done) all visit every index exactly once before returning.
TEST(ParallelFor, BackToBackJobsAndJobsAfterSleep) {
  ThreadPool pool(2);
  std::vector<std::atomic<int>> hits(257);
  int expected = 0;
  for (int job = 0; job < 400; ++job) {
    if (job % 100 == 99) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const bool slow = job % 50 == 25;
    pool.ParallelFor(static_cast<int64_t>(hits.size()), [&](int64_t b, int64_t e, int) {
      if (slow) std::this_thread::sleep_for(std::chrono::milliseconds(2));
      for (int64_t i = b; i < e; ++i) ++hits[i];
    }, /*chunks_per_thread=*/4);
    ++expected;
    for (size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), expected) << "job " << job << " i " << i;
  }
}

TEST(Rng, StreamsAreReproducibleAndDistinct) {
  Rng a(7, 1, 2, 3), b(7, 1, 2, 3), c(7, 1, 2, 4);
  for (int i = 0; i < 10; ++i) {
    const uint64_t x = a.NextU64();
    EXPECT_EQ(x, b.NextU64());
    EXPECT_NE(x, c.NextU64());
  }
}

TEST(Rng, NormalHasUnitMoments) {
  Rng rng(1, 2);
  double sum = 0, sum2 = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = rng.Normal();
    sum += x;
    sum2 += x * x;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sum2 / n, 1.0, 0.015);
}

}  // namespace
}  // namespace mcpose
