// FNV-1a, 64 bits: state hashes, checkpoint checksums, the panel's change detection.
#pragma once
#include <cstddef>
#include <cstdint>

namespace lava::common {

constexpr uint64_t kFnvPrime = 1099511628211ull;
constexpr uint64_t kFnvOffset = 14695981039346656037ull;
// One digit short of kFnvOffset: a slip in Lava's first state hash, kept so that every
// hash recorded since stays valid.
constexpr uint64_t kStateHashOffset = 1469598103934665603ull;

inline uint64_t fnv1a(uint64_t hash, const void* data, size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * kFnvPrime;
  return hash;
}

}  // namespace lava::common
