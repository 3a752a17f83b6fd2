// Pipelines from embedded SPIR-V: compute pipelines with specialization constants, and
// graphics pipelines for dynamic rendering (built for formats, never for a render pass).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "device_context.h"
#include "lava/renderer.h"
#include "unique.h"
#include "internal.h"

namespace lava::detail {

struct Spirv {
  const uint32_t* code;
  size_t bytes;
};
#define LAVA_SPIRV(array) \
  ::lava::detail::Spirv { \
    array, sizeof(array)  \
  }

// Specialization constants 0, 1, 2, ... take these values (constant 0: the workgroup size
// of every compute shader).
using Constants = std::vector<uint32_t>;

// The one of a shader's four builds (both float controls, signed zeros only, RTE only,
// neither) whose float controls this device honours.
Spirv withFloatControls(const DeviceContext& context, Spirv both, Spirv signedZero, Spirv rte,
                        Spirv plain);

LAVA_INTERNAL UniquePipeline createComputePipeline(const DeviceContext& context, VkPipelineLayout layout,
                                     Spirv shader, const Constants& constants);

struct GraphicsPipelineDesc {
  Spirv vert;
  Spirv frag;            // no code: no fragment stage (a depth-only pass)
  RenderFormats target;  // its depth format UNDEFINED: no depth test or write; its colour
                         // format UNDEFINED: no colour attachment
  VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  bool additive = false;  // blend ONE + ONE onto the target
  // Blend src (1 - dst) + dst: colours in [0, 1) compose as 1 - (1 - a)(1 - b), so a target
  // holding T(x) = 1 - exp(-x) receives T(x + y) from a source T(y).
  bool screen = false;
  // Blend src + dst (1 - src alpha): premultiplied colours laid over the target.
  bool over = false;
  bool depthTest = true;
  bool depthWrite = true;
};

// InvalidArgument ("formats") for pipelines for dynamic rendering on a device created
// without it.
void checkTarget(const DeviceContext& context, const RenderFormats& target);

// No vertex input; dynamic viewport and scissor.
UniquePipeline createGraphicsPipeline(const DeviceContext& context, VkPipelineLayout layout,
                                      const GraphicsPipelineDesc& desc);

}  // namespace lava::detail
