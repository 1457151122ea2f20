#include "core/parallel_for.h"

#include <algorithm>
#include <utility>
#include <chrono>

#if defined(__x86_64__) || defined(_M_X64) || defined(__i386__)
#include <immintrin.h>
#endif

namespace mcpose {
namespace {

inline void CpuRelax() {
#if defined(__x86_64__) || defined(_M_X64) || defined(__i386__)
  _mm_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// Spins until done() or `micros` have passed; returns done().
template <typename Done>
bool SpinFor(int micros, const Done& done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::microseconds(micros);
  for (;;) {
    for (int k = 0; k < 64; ++k) {
      if (done()) return true;
      CpuRelax();
    }
    if (std::chrono::steady_clock::now() >= deadline) return done();
  }
}

}  // namespace

ThreadPool::ThreadPool(int threads, ThreadScope scope) : scope_(std::move(scope)) {
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  num_threads_ = threads > 0 ? threads : hardware;
  spin_micros_ = num_threads_ <= hardware ? kSpinMicros : 0;
  for (int i = 1; i < num_threads_; ++i)
    workers_.emplace_back([this, i] {
      if (scope_.enter) scope_.enter();
      WorkerLoop(i);
    });
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
      if (chunks_done_.fetch_add(1) + 1 == num_chunks_) cv_done_.notify_all();
    }
  }
}

void ThreadPool::WorkerLoop(int worker) {
  uint64_t seen = 0;
  for (;;) {
    // The state is read under the mutex; the spin only decides whether to block.
    SpinFor(spin_micros_, [&] { return stop_.load(std::memory_order_relaxed) ||
                                      generation_.load(std::memory_order_relaxed) != seen; });
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
  struct CallerScope {  // the caller's part runs inside the pool's scope
    const ThreadScope& s;
    explicit CallerScope(const ThreadScope& scope) : s(scope) {
      if (s.enter) s.enter();
    }
    ~CallerScope() {
      if (s.leave) s.leave();
    }
  } caller(scope_);
  if (num_threads_ == 1) {
    fn(0, n, 0);
    return;
  }
  int64_t num_chunks;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &fn;
    job_n_ = n;
    const int64_t want = std::max<int64_t>(1, int64_t{num_threads_} * chunks_per_thread);
    chunk_size_ = std::max<int64_t>(1, (n + want - 1) / want);
    num_chunks_ = (n + chunk_size_ - 1) / chunk_size_;
    num_chunks = num_chunks_;
    next_chunk_ = 0;
    chunks_done_ = 0;
    ++generation_;
  }
  cv_start_.notify_all();
  RunChunks(0);
  SpinFor(spin_micros_, [&] { return chunks_done_.load(std::memory_order_relaxed) == num_chunks; });
  std::unique_lock<std::mutex> lock(mutex_);
  cv_done_.wait(lock, [&] { return chunks_done_ == num_chunks_; });
  job_ = nullptr;
}

}  // namespace mcpose
