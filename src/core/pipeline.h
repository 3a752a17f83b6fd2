// Shader modules from embedded SPIR-V and the compute pipeline factory.
#pragma once
#include <cstddef>
#include <cstdint>

#include "unique.h"

namespace lava {

UniqueShaderModule createShaderModule(VkDevice device, const uint32_t* code, size_t bytes);

// A compute pipeline whose workgroup size is specialization constant 0.
UniquePipeline createComputePipeline(VkDevice device, VkPipelineLayout layout,
                                     const uint32_t* code, size_t bytes, uint32_t workgroupSize);

}  // namespace lava
