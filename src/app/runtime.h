// What every command shares: the Vulkan context options (LAVA_VALIDATION turns the layer
// on), the report of validation messages, and progress on a terminal.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "context.h"

namespace lava::app {

ContextOptions contextOptions(std::optional<unsigned> device);

// Prints any validation messages to stderr; returns 1 if there were some, else `status`.
int finish(Context& context, int status);

class Progress {
 public:
  Progress(std::string label, uint64_t total);
  void update(uint64_t done);
  ~Progress();

 private:
  std::string label_;
  uint64_t total_;
  bool terminal_;
  bool shown_ = false;
};

std::string formatSeconds(double seconds);

}  // namespace lava::app
