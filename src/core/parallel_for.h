// The one parallel seam: a fixed pool of worker threads ("raster cores") and ParallelFor.
// Work is split into contiguous chunks by index; the caller's results must depend on the
// index only (see rng.h), so any thread count gives the same answer.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace mcpose {

// What every thread of a pool runs around its part of the pool's work, the calling thread's part
// of a ParallelFor included: a thread-local setting of the pool's owner (an estimator's SIMD
// target). `enter` and `leave` may be empty.
struct ThreadScope {
  std::function<void()> enter, leave;
};

class ThreadPool {
 public:
  // threads <= 0: one per hardware thread. Each worker thread runs scope.enter when it starts;
  // the thread calling ParallelFor runs enter and leave around its own part.
  explicit ThreadPool(int threads, ThreadScope scope = {});
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return num_threads_; }

  // Calls fn(begin, end, worker) over [0, n) split into about `chunks_per_thread` chunks per
  // thread; worker in [0, size()) identifies the calling thread's scratch space. Returns when
  // all chunks are done. The calling thread works too.
  //
  // Waiting threads spin for up to kSpinMicros before they block, so that back-to-back jobs
  // (one per Monte-Carlo iteration, a millisecond or two each) do not pay a sleep and a wake
  // per job; a pool left idle longer than that sleeps on a condition variable. A pool with more
  // threads than the machine has hardware threads never spins (it would take the CPU from the
  // threads that have work).
  void ParallelFor(int64_t n, const std::function<void(int64_t, int64_t, int)>& fn,
                   int chunks_per_thread = 8);

 private:
  void WorkerLoop(int worker);
  void RunChunks(int worker);

  static constexpr int kSpinMicros = 300;

  int num_threads_ = 1;
  ThreadScope scope_;
  int spin_micros_ = 0;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable cv_start_, cv_done_;
  // The job in flight.
  const std::function<void(int64_t, int64_t, int)>* job_ = nullptr;
  int64_t job_n_ = 0, chunk_size_ = 1, next_chunk_ = 0, num_chunks_ = 0;
  // Written under mutex_; atomic so that spinning threads can watch them without it.
  std::atomic<int64_t> chunks_done_{0};
  std::atomic<uint64_t> generation_{0};
  std::atomic<bool> stop_{false};
};

}  // namespace mcpose
