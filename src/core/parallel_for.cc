#include "core/parallel_for.h"

#include <algorithm>

namespace mcpose {

ThreadPool::ThreadPool(int threads) {
  num_threads_ = threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  for (int i = 1; i < num_threads_; ++i) workers_.emplace_back([this, i] { WorkerLoop(i); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_start_.notify_all();
  for (auto& t : workers_) t.join();
}

void ThreadPool::RunChunks(int worker) {
  for (;;) {
    int64_t chunk;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (next_chunk_ >= num_chunks_) return;
      chunk = next_chunk_++;
    }
    const int64_t begin = chunk * chunk_size_;
    const int64_t end = std::min(job_n_, begin + chunk_size_);
    (*job_)(begin, end, worker);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (++chunks_done_ == num_chunks_) cv_done_.notify_all();
    }
  }
}

void ThreadPool::WorkerLoop(int worker) {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    RunChunks(worker);
  }
}

void ThreadPool::ParallelFor(int64_t n, const std::function<void(int64_t, int64_t, int)>& fn,
                             int chunks_per_thread) {
  if (n <= 0) return;
  if (num_threads_ == 1) {
    fn(0, n, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &fn;
    job_n_ = n;
    const int64_t want = std::max<int64_t>(1, int64_t{num_threads_} * chunks_per_thread);
    chunk_size_ = std::max<int64_t>(1, (n + want - 1) / want);
    num_chunks_ = (n + chunk_size_ - 1) / chunk_size_;
    next_chunk_ = 0;
    chunks_done_ = 0;
    ++generation_;
  }
  cv_start_.notify_all();
  RunChunks(0);
  std::unique_lock<std::mutex> lock(mutex_);
  cv_done_.wait(lock, [&] { return chunks_done_ == num_chunks_; });
  job_ = nullptr;
}

}  // namespace mcpose
