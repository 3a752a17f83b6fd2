// What the drawing shaders get of a scene: the line style and the crater.
#pragma once
#include <vulkan/vulkan.h>

#include <glm/glm.hpp>

#include "lava/renderer.h"
#include "lava/scene.h"
#include "shared.h"
#include "vulkan/device_context.h"

namespace lava::detail {

// x line scale s (s), y speed (m/s) at which a line is fully red, z age (s) at which it has
// cooled to its darkest, w the look (gpu::kLookPlain, kLookLava).
glm::vec4 lineStyle(const Scene& scene, LookStyle style);

// Viewport and scissor covering `extent`.
void setViewport(const DeviceContext& context, VkCommandBuffer commands, VkExtent2D extent);

// The backdrop's solids with the bound pipeline (ground.vert; `layout` takes
// gpu::BackdropParams for the vertex and fragment stages): the ground, each collider, and a
// scene without colliders whose emitter 0 is a disc gets a crater of scenery under it.
// `params` holds viewProj, vent and eye; recordSolids sets each solid's.
void recordSolids(const DeviceContext& context, VkCommandBuffer commands, VkPipelineLayout layout,
                  const Scene& scene, gpu::BackdropParams& params);

}  // namespace lava::detail
