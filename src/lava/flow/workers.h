// Threads that live as long as their owner: the flow's passes run hundreds of times a step
// (each conjugate-gradient iteration is several), too often to start threads for each.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace lava::detail {

class Workers {
 public:
  explicit Workers(unsigned threads);  // the caller is thread 0; threads - 1 helpers start
  ~Workers();
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;

  unsigned size() const { return threads_; }
  // Calls range(begin, end) over [0, n) in chunks, each chunk exactly once, and returns when
  // all are done. Thread t takes the chunks of its own share of [0, n) in order, then any
  // left of the others' shares: a helper that the system has not run yet (its core busy with
  // other work) finds its share done by the others, and nobody waits for it to wake.
  void forEach(size_t n, const std::function<void(size_t, size_t)>& range);

 private:
  // A share's claim word: the job's number (32 bits), its next chunk and its end (16 each).
  // The number makes a claim read in one job fail in the next.
  struct alignas(64) Share {
    std::atomic<uint64_t> claim{0};
  };
  void loop(unsigned t);
  void drain(unsigned t);  // claims and runs chunks, its own share's first, until none is left
  bool claim(unsigned share, uint32_t& chunk);

  unsigned threads_;
  std::vector<std::thread> helpers_;
  std::unique_ptr<Share[]> shares_;
  // The job: written by the caller before its shares' claim words (release), read by a thread
  // only after it has claimed one of its chunks (acquire), and kept until all are done.
  const std::function<void(size_t, size_t)>* range_ = nullptr;
  size_t n_ = 0, chunk_ = 0;
  uint32_t job_ = 0;
  alignas(64) std::atomic<uint32_t> done_{0};  // the job's chunks done
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<uint64_t> generation_{0};  // one more for each job: wakes the helpers
  std::atomic<bool> stop_{false};
};

}  // namespace lava::detail
