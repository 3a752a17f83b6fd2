// What every command shares: the device Lava creates for the program (LAVA_DEVICE picks it,
// LAVA_VALIDATION turns the validation layer on), the report of validation messages, and
// progress on a terminal.
#pragma once
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "lava/device.h"

namespace lava::app {

// --device, else LAVA_DEVICE, else Lava's choice; validation from LAVA_VALIDATION.
DeviceOptions deviceOptions(std::optional<unsigned> device);
// Where the device index of the last deviceOptions() came from: "--device" or "LAVA_DEVICE".
const char* deviceSource();
bool validationRequested();

// Prints any validation messages to stderr; returns 1 if there were some, else `status`.
int finish(Device& device, int status);

class Progress {
 public:
  Progress(std::string label, uint64_t total);
  void update(uint64_t done);
  // Erases the line (before printing other output; the next update() draws it again).
  void clear();
  ~Progress();

 private:
  std::string label_;
  uint64_t total_;
  bool terminal_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_;
};

std::string formatSeconds(double seconds);

}  // namespace lava::app
