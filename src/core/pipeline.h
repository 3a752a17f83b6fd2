// Shader modules from embedded SPIR-V and the compute and graphics pipeline factories.
#pragma once
#include <cstddef>
#include <cstdint>

#include "unique.h"

namespace lava {

UniqueShaderModule createShaderModule(VkDevice device, const uint32_t* code, size_t bytes);

// A compute pipeline whose workgroup size is specialization constant 0.
UniquePipeline createComputePipeline(VkDevice device, VkPipelineLayout layout, const uint32_t* code,
                                     size_t bytes, uint32_t workgroupSize);

struct GraphicsPipelineDesc {
  const uint32_t* vert;
  size_t vertBytes;
  const uint32_t* frag;
  size_t fragBytes;
  VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  bool additive = false;  // blend ONE + ONE onto the target
  bool depthTest = true;
  bool depthWrite = true;
};

// A pipeline for subpass 0 of `pass`, no vertex input, dynamic viewport and scissor.
UniquePipeline createGraphicsPipeline(VkDevice device, VkPipelineLayout layout, VkRenderPass pass,
                                      const GraphicsPipelineDesc& desc);

}  // namespace lava
