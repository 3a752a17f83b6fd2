#include "flow/workers.h"

#include <algorithm>

namespace lava::detail {
namespace {

// How long a thread polls before it sleeps: a pass a few microseconds after the last one
// finds its helper awake, and a helper left idle sleeps within about a tenth of a millisecond.
constexpr int kSpins = 2000;
// The fewest elements a chunk holds; a job has at most 65,535 chunks (a claim word's field).
constexpr size_t kLeastChunk = 256;
constexpr size_t kMostChunks = 0xFFFF;

void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

}  // namespace

Workers::Workers(unsigned threads)
    : threads_(threads < 1 ? 1 : threads), shares_(new Share[threads < 1 ? 1 : threads]) {
  for (unsigned t = 1; t < threads_; ++t) helpers_.emplace_back([this, t] { loop(t); });
}

Workers::~Workers() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_all();
  for (std::thread& h : helpers_) h.join();
}

bool Workers::claim(unsigned share, uint32_t& chunk) {
  std::atomic<uint64_t>& word = shares_[share].claim;
  uint64_t w = word.load(std::memory_order_relaxed);
  for (;;) {
    const uint32_t next = uint32_t(w >> 16) & 0xFFFFu, end = uint32_t(w) & 0xFFFFu;
    if (next >= end) return false;
    if (word.compare_exchange_weak(w, w + (uint64_t{1} << 16), std::memory_order_acquire,
                                   std::memory_order_relaxed)) {
      chunk = next;
      return true;
    }
  }
}

void Workers::drain(unsigned t) {
  for (unsigned k = 0; k < threads_; ++k) {
    const unsigned share = (t + k) % threads_;
    uint32_t chunk = 0;
    while (claim(share, chunk)) {
      const size_t begin = size_t(chunk) * chunk_;
      (*range_)(begin, std::min(n_, begin + chunk_));
      done_.fetch_add(1, std::memory_order_release);
    }
  }
}

void Workers::forEach(size_t n, const std::function<void(size_t, size_t)>& range) {
  if (threads_ == 1 || n == 0) {
    if (n > 0) range(0, n);
    return;
  }
  // The last job's chunks are all done, so every claim word is spent: a late helper claims
  // nothing while this one's fields are written.
  range_ = &range;
  n_ = n;
  chunk_ = std::max(kLeastChunk, (n + kMostChunks - 1) / kMostChunks);
  const uint32_t chunks = uint32_t((n + chunk_ - 1) / chunk_);
  ++job_;
  done_.store(0, std::memory_order_relaxed);
  for (unsigned t = 0; t < threads_; ++t) {
    const uint64_t first = uint64_t(chunks) * t / threads_, end = uint64_t(chunks) * (t + 1) / threads_;
    shares_[t].claim.store((uint64_t(job_) << 32) | (first << 16) | end, std::memory_order_release);
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  drain(0);
  // Only chunks a helper is running are left: wait for them.
  for (int s = 0; done_.load(std::memory_order_acquire) != chunks; ++s) {
    if (s < kSpins)
      relax();
    else
      std::this_thread::yield();
  }
}

void Workers::loop(unsigned t) {
  uint64_t seen = 0;
  for (;;) {
    uint64_t now = generation_.load(std::memory_order_acquire);
    for (int s = 0; s < kSpins && now == seen && !stop_.load(); ++s) {
      relax();
      now = generation_.load(std::memory_order_acquire);
    }
    if (now == seen) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_.load() || generation_.load() != seen; });
      now = generation_.load(std::memory_order_acquire);
    }
    if (stop_.load()) return;
    seen = now;
    drain(t);
  }
}

}  // namespace lava::detail
