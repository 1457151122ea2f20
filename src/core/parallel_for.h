// The one parallel seam: a fixed pool of worker threads ("raster cores") and ParallelFor.
// Work is split into contiguous chunks by index; the caller's results must depend on the
// index only (see rng.h), so any thread count gives the same answer.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace mcpose {

class ThreadPool {
 public:
  // threads <= 0: one per hardware thread.
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return num_threads_; }

  // Calls fn(begin, end, worker) over [0, n) split into about `chunks_per_thread` chunks per
  // thread; worker in [0, size()) identifies the calling thread's scratch space. Returns when
  // all chunks are done. The calling thread works too.
  void ParallelFor(int64_t n, const std::function<void(int64_t, int64_t, int)>& fn,
                   int chunks_per_thread = 8);

 private:
  void WorkerLoop(int worker);
  void RunChunks(int worker);

  int num_threads_ = 1;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable cv_start_, cv_done_;
  // The job in flight.
  const std::function<void(int64_t, int64_t, int)>* job_ = nullptr;
  int64_t job_n_ = 0, chunk_size_ = 1, next_chunk_ = 0, num_chunks_ = 0;
  int chunks_done_ = 0;
  uint64_t generation_ = 0;
  bool stop_ = false;
};

}  // namespace mcpose
