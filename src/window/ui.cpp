#include "ui.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/hash.h"
#include "common/passes.h"
#include "host/vulkan.h"

namespace lava::window {
namespace {

// `over`: the panel blended over the frame's image (kept in COLOR_ATTACHMENT_OPTIMAL);
// else the panel's own image, cleared, then left for the copies (TRANSFER_SRC_OPTIMAL). The
// two are compatible (they differ in load operations and layouts only): ImGui's pipeline,
// made for the first, draws in either.
host::OwnedRenderPass createPass(VkDevice device, VkFormat format, bool over) {
  const VkAttachmentDescription color = common::attachment(
      format, over ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR,
      VK_ATTACHMENT_STORE_OP_STORE,
      over ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
      over ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  VkAttachmentReference reference{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &reference;
  // The same in both (compatible passes differ in nothing else). Before: the scene's lines
  // were blended into the image the panel blends over (RAW/WAW), or earlier frames copied
  // from the panel's image this pass clears (WAR). After: the copies read what the pass drew.
  const VkSubpassDependency dependencies[2] = {
      {VK_SUBPASS_EXTERNAL, 0,
       VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
       VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
       VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, 0},
      {0, VK_SUBPASS_EXTERNAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
       VK_ACCESS_TRANSFER_READ_BIT, 0}};
  const VkRenderPassCreateInfo info = common::onePassInfo(&color, 1, subpass, dependencies, 2);
  VkRenderPass pass = VK_NULL_HANDLE;
  VK_CHECK(vkCreateRenderPass(device, &info, nullptr, &pass));
  return host::OwnedRenderPass(device, pass);
}

host::OwnedFramebuffer createFramebuffer(VkDevice device, VkRenderPass pass, VkImageView color,
                                         VkExtent2D extent) {
  const VkFramebufferCreateInfo info = common::framebufferInfo(pass, &color, 1, extent);
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VK_CHECK(vkCreateFramebuffer(device, &info, nullptr, &framebuffer));
  return host::OwnedFramebuffer(device, framebuffer);
}

// ImGui's draw data recorded in `pass` (either of createPass's: `clears` for the panel's
// own) over `framebuffer`.
void renderDrawData(VkCommandBuffer commands, VkRenderPass pass, bool clears,
                    VkFramebuffer framebuffer, VkExtent2D extent) {
  const VkClearValue clear{};
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = pass;
  begin.framebuffer = framebuffer;
  begin.renderArea = {{0, 0}, extent};
  begin.clearValueCount = clears ? 1 : 0;
  begin.pClearValues = clears ? &clear : nullptr;
  vkCmdBeginRenderPass(commands, &begin, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), commands);
  vkCmdEndRenderPass(commands);
}

// What ImGui drew, as one number: every vertex, index and command of its draw data.
uint64_t drawKey(const ImDrawData& data) {
  uint64_t h = common::kFnvOffset;
  const auto add = [&h](const void* bytes, size_t n) { h = common::fnv1a(h, bytes, n); };
  add(&data.DisplayPos, sizeof(data.DisplayPos));
  add(&data.DisplaySize, sizeof(data.DisplaySize));
  add(&data.FramebufferScale, sizeof(data.FramebufferScale));
  for (int l = 0; l < data.CmdListsCount; ++l) {
    const ImDrawList& list = *data.CmdLists[l];
    add(list.VtxBuffer.Data, size_t(list.VtxBuffer.Size) * sizeof(ImDrawVert));
    add(list.IdxBuffer.Data, size_t(list.IdxBuffer.Size) * sizeof(ImDrawIdx));
    for (const ImDrawCmd& c : list.CmdBuffer) {
      add(&c.ClipRect, sizeof(c.ClipRect));
      add(&c.TextureId, sizeof(c.TextureId));
      add(&c.VtxOffset, sizeof(c.VtxOffset));
      add(&c.IdxOffset, sizeof(c.IdxOffset));
      add(&c.ElemCount, sizeof(c.ElemCount));
      const bool callback = c.UserCallback != nullptr;
      add(&callback, sizeof(callback));
    }
  }
  return h == 0 ? 1 : h;
}

// Where each of ImGui's windows lies in the target (its draw list's clip rectangles, within
// its vertices and the target), in whole pixels: the copies' regions.
std::vector<VkImageCopy> panelRegions(const ImDrawData& data, VkExtent2D extent) {
  std::vector<VkImageCopy> regions;
  const ImVec2 scale = data.FramebufferScale, origin = data.DisplayPos;
  for (int l = 0; l < data.CmdListsCount; ++l) {
    const ImDrawList& list = *data.CmdLists[l];
    if (list.VtxBuffer.Size == 0) continue;
    ImVec2 lo(1e30f, 1e30f), hi(-1e30f, -1e30f);
    for (const ImDrawVert& v : list.VtxBuffer) {
      lo = ImVec2(std::min(lo.x, v.pos.x), std::min(lo.y, v.pos.y));
      hi = ImVec2(std::max(hi.x, v.pos.x), std::max(hi.y, v.pos.y));
    }
    ImVec2 clipLo(1e30f, 1e30f), clipHi(-1e30f, -1e30f);
    for (const ImDrawCmd& c : list.CmdBuffer) {
      if (c.ElemCount == 0) continue;
      clipLo = ImVec2(std::min(clipLo.x, c.ClipRect.x), std::min(clipLo.y, c.ClipRect.y));
      clipHi = ImVec2(std::max(clipHi.x, c.ClipRect.z), std::max(clipHi.y, c.ClipRect.w));
    }
    const float x0 = (std::max(lo.x, clipLo.x) - origin.x) * scale.x;
    const float y0 = (std::max(lo.y, clipLo.y) - origin.y) * scale.y;
    const float x1 = (std::min(hi.x, clipHi.x) - origin.x) * scale.x;
    const float y1 = (std::min(hi.y, clipHi.y) - origin.y) * scale.y;
    const int32_t left = std::clamp(int32_t(std::floor(x0)), 0, int32_t(extent.width));
    const int32_t top = std::clamp(int32_t(std::floor(y0)), 0, int32_t(extent.height));
    const int32_t right = std::clamp(int32_t(std::ceil(x1)), 0, int32_t(extent.width));
    const int32_t bottom = std::clamp(int32_t(std::ceil(y1)), 0, int32_t(extent.height));
    if (right <= left || bottom <= top) continue;
    VkImageCopy r{};
    r.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    r.dstSubresource = r.srcSubresource;
    r.srcOffset = {left, top, 0};
    r.dstOffset = r.srcOffset;
    r.extent = {uint32_t(right - left), uint32_t(bottom - top), 1};
    regions.push_back(r);
  }
  return regions;
}

}  // namespace

Ui::Ui(Device& device, GLFWwindow* window, VkFormat colorFormat, uint32_t imageCount)
    : lavaDevice_(device), device_(device.handles().device), format_(colorFormat) {
  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  poolInfo.maxSets = 4;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorPool(device_, &poolInfo, nullptr, &pool));
  pool_ = host::OwnedDescriptorPool(device_, pool);
  overPass_ = createPass(device_, colorFormat, true);
  panelPass_ = createPass(device_, colorFormat, false);

  const DeviceHandles& h = device.handles();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  // Opaque, square windows: the copies put every pixel of a window's rectangle over the
  // scene, so none of them may be see-through.
  ImGuiStyle& style = ImGui::GetStyle();
  style.Colors[ImGuiCol_WindowBg].w = 1.0f;
  style.Colors[ImGuiCol_PopupBg].w = 1.0f;
  style.WindowRounding = 0.0f;
  style.PopupRounding = 0.0f;
  ImGui_ImplGlfw_InitForVulkan(window, true);
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = h.instance;
  info.PhysicalDevice = h.physicalDevice;
  info.Device = h.device;
  info.QueueFamily = h.queueFamily;
  info.Queue = h.queue;
  info.DescriptorPool = pool;
  info.MinImageCount = 2;
  info.ImageCount = std::max(imageCount, 2u);
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = [](VkResult result) { VK_CHECK(result); };
  ImGui_ImplVulkan_Init(&info, overPass_);
  device.submitNow(
      [](VkCommandBuffer commands) { ImGui_ImplVulkan_CreateFontsTexture(commands); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

Ui::~Ui() {
  vkDeviceWaitIdle(device_);
  ImGui_ImplVulkan_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void Ui::drawPanel(VkCommandBuffer commands, VkExtent2D extent) {
  if (extent.width != panelExtent_.width || extent.height != panelExtent_.height) {
    vkDeviceWaitIdle(device_);  // frames in flight may still copy from the old image
    panelFramebuffer_ = {};
    panel_ =
        host::createImage(lavaDevice_, extent, format_,
                          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                          VK_IMAGE_ASPECT_COLOR_BIT);
    panelFramebuffer_ = createFramebuffer(device_, panelPass_, panel_.view, extent);
    panelExtent_ = extent;
  }
  renderDrawData(commands, panelPass_, true, panelFramebuffer_, extent);
}

void Ui::record(VkCommandBuffer commands, const host::FrameTarget& target) {
  ImDrawData* data = ImGui::GetDrawData();
  if (!data) return;
  if (target.copyable) {
    const uint64_t key = drawKey(*data);
    if (key != drawnKey_ || target.extent.width != panelExtent_.width ||
        target.extent.height != panelExtent_.height) {
      drawPanel(commands, target.extent);
      drawnKey_ = key;
    }
    const std::vector<VkImageCopy> regions = panelRegions(*data, target.extent);
    if (regions.empty()) return;
    // RAW/WAW: the scene was drawn into the image the copies write.
    host::imageBarrier(
        commands, target.color, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
        VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
        VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdCopyImage(commands, panel_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.color,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(regions.size()), regions.data());
    // RAW: whatever follows reads (or presents) the frame as a colour attachment's.
    host::imageBarrier(commands, target.color, VK_IMAGE_ASPECT_COLOR_BIT,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    return;
  }
  const VkImageView color = target.colorView;
  const VkExtent2D extent = target.extent;
  auto it = framebuffers_.find(color);
  if (it == framebuffers_.end())
    it = framebuffers_.emplace(color, createFramebuffer(device_, overPass_, color, extent)).first;
  renderDrawData(commands, overPass_, false, it->second, extent);
}

}  // namespace lava::window
