// Render passes of one subpass, written once for the library, the program and the tests:
// the attachments and the create info that every such pass spells out the same way.
#pragma once
#include <vulkan/vulkan.h>

namespace lava::common {

// One single-sample attachment with no stencil.
inline VkAttachmentDescription attachment(VkFormat format, VkAttachmentLoadOp load,
                                          VkAttachmentStoreOp store, VkImageLayout initial,
                                          VkImageLayout final) {
  return {0,
          format,
          VK_SAMPLE_COUNT_1_BIT,
          load,
          store,
          VK_ATTACHMENT_LOAD_OP_DONT_CARE,
          VK_ATTACHMENT_STORE_OP_DONT_CARE,
          initial,
          final};
}

// The create info of a pass of one subpass; it points into the arguments.
inline VkRenderPassCreateInfo onePassInfo(const VkAttachmentDescription* attachments,
                                          uint32_t count, const VkSubpassDescription& subpass,
                                          const VkSubpassDependency* dependencies,
                                          uint32_t dependencyCount) {
  return {VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
          nullptr,
          0,
          count,
          attachments,
          1,
          &subpass,
          dependencyCount,
          dependencies};
}

// (Not for a temporary subpass: the create info would point at it.)
VkRenderPassCreateInfo onePassInfo(const VkAttachmentDescription*, uint32_t,
                                   const VkSubpassDescription&&, const VkSubpassDependency*,
                                   uint32_t) = delete;

// The create info of a framebuffer of `count` views for `pass`; it points into `views`.
inline VkFramebufferCreateInfo framebufferInfo(VkRenderPass pass, const VkImageView* views,
                                               uint32_t count, VkExtent2D extent) {
  return {VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
          nullptr,
          0,
          pass,
          count,
          views,
          extent.width,
          extent.height,
          1};
}

// Begins one of the frame recipe's two rendering passes over a colour and a depth image
// (docs/library.md): the first clears both (the colour to `clear`, the depth to 1) and writes
// the depth in `depthWrite`; the second (`load`) loads the colour and only reads the depth.
// `begin` is vkCmdBeginRendering (or its KHR alias) as the caller loaded it.
inline void beginFramePass(PFN_vkCmdBeginRendering begin, VkCommandBuffer commands,
                           VkImageView color, VkImageView depth, VkExtent2D extent, bool load,
                           VkClearColorValue clear, VkImageLayout depthWrite) {
  const VkAttachmentLoadOp loadOp = load ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
  VkRenderingAttachmentInfo attachments[2] = {
      {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
       nullptr,
       color,
       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
       VK_RESOLVE_MODE_NONE,
       VK_NULL_HANDLE,
       VK_IMAGE_LAYOUT_UNDEFINED,
       loadOp,
       VK_ATTACHMENT_STORE_OP_STORE,
       {}},
      {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
       nullptr,
       depth,
       load ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL : depthWrite,
       VK_RESOLVE_MODE_NONE,
       VK_NULL_HANDLE,
       VK_IMAGE_LAYOUT_UNDEFINED,
       loadOp,
       load ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE,
       {}}};
  attachments[0].clearValue.color = clear;
  attachments[1].clearValue.depthStencil = {1.0f, 0};
  const VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO,
                             nullptr,
                             0,
                             {{0, 0}, extent},
                             1,
                             0,
                             1,
                             &attachments[0],
                             &attachments[1],
                             nullptr};
  begin(commands, &info);
}

}  // namespace lava::common
