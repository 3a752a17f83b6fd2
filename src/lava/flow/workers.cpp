#include "flow/workers.h"

namespace lava::detail {
namespace {

// How long a thread polls before it sleeps: a pass a few microseconds after the last one
// finds its helper awake, and a helper left idle sleeps within about a tenth of a millisecond.
constexpr int kSpins = 2000;

void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

}  // namespace

Workers::Workers(unsigned threads) : threads_(threads < 1 ? 1 : threads) {
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

void Workers::run(const std::function<void(unsigned)>& body) {
  if (threads_ == 1) {
    body(0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &body;
    pending_.store(threads_ - 1);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  body(0);
  for (int s = 0; s < kSpins && pending_.load(std::memory_order_acquire) != 0; ++s) relax();
  if (pending_.load(std::memory_order_acquire) != 0) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_.load(std::memory_order_acquire) == 0; });
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
    (*job_)(t);
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);
      done_.notify_one();
    }
  }
}

}  // namespace lava::detail
