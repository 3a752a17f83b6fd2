// Threads that live as long as their owner: the flow's passes run hundreds of times a step
// (each conjugate-gradient iteration is several), too often to start threads for each.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
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
  // Calls body(t) once for each t < size(), t = 0 on the caller, and returns when all have.
  void run(const std::function<void(unsigned)>& body);

 private:
  void loop(unsigned t);

  unsigned threads_;
  std::vector<std::thread> helpers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(unsigned)>* job_ = nullptr;
  std::atomic<uint64_t> generation_{0};  // one more for each run
  std::atomic<unsigned> pending_{0};     // helpers still in this run's body
  std::atomic<bool> stop_{false};
};

}  // namespace lava::detail
