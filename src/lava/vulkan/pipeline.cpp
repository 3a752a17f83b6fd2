#include "pipeline.h"

#include "common/check.h"
#include "lava/error.h"

namespace lava::detail {
namespace {

UniqueShaderModule createShaderModule(const DeviceContext& c, Spirv shader) {
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = shader.bytes;
  info.pCode = shader.code;
  VkShaderModule module = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateShaderModule(c.device(), &info, c.allocator(), &module));
  return UniqueShaderModule(c, module);
}

}  // namespace

Spirv withFloatControls(const DeviceContext& c, Spirv both, Spirv signedZero, Spirv rte,
                        Spirv plain) {
  const bool zero = c.floatControls.shaderSignedZeroInfNanPreserveFloat32;
  const bool even = c.floatControls.shaderRoundingModeRTEFloat32;
  return zero && even ? both : zero ? signedZero : even ? rte : plain;
}

UniquePipeline createComputePipeline(const DeviceContext& c, VkPipelineLayout layout, Spirv shader,
                                     const Constants& constants) {
  const UniqueShaderModule module = createShaderModule(c, shader);
  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t i = 0; i < constants.size(); ++i)
    entries.push_back({i, i * uint32_t(sizeof(uint32_t)), sizeof(uint32_t)});
  VkSpecializationInfo specialization{static_cast<uint32_t>(entries.size()), entries.data(),
                                      constants.size() * sizeof(uint32_t), constants.data()};
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.stage.pSpecializationInfo = &specialization;
  info.layout = layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateComputePipelines(c.device(), c.handles.pipelineCache, 1, &info, c.allocator(),
                                       &pipeline));
  return UniquePipeline(c, pipeline);
}

namespace {

// The fixed-function states: no vertex input, one viewport and scissor set when drawing,
// no culling, one sample, depth as the target and the description ask.
struct FixedStates {
  VkPipelineVertexInputStateCreateInfo vertexInput{
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo assembly{
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  VkPipelineRasterizationStateCreateInfo raster{
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  VkPipelineMultisampleStateCreateInfo multisample{
      VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  VkPipelineDepthStencilStateCreateInfo depthStencil{
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  VkDynamicState dynamics[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};

  explicit FixedStates(const GraphicsPipelineDesc& desc) {
    assembly.topology = desc.topology;
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    const bool depth = desc.target.depth != VK_FORMAT_UNDEFINED;
    depthStencil.depthTestEnable = depth && desc.depthTest;
    depthStencil.depthWriteEnable = depth && desc.depthWrite;
    depthStencil.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamics;
  }
  FixedStates(const FixedStates&) = delete;  // `dynamic` points into it
  FixedStates& operator=(const FixedStates&) = delete;
};

// The colour attachment's blending: added (lines), screened (the lava look's lines), over
// (premultiplied; the molten surface, opaque), or none.
VkPipelineColorBlendAttachmentState blending(const GraphicsPipelineDesc& desc) {
  VkPipelineColorBlendAttachmentState blend{};
  blend.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                         VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  if (!desc.additive && !desc.screen && !desc.over) return blend;
  blend.blendEnable = VK_TRUE;
  blend.colorBlendOp = VK_BLEND_OP_ADD;
  blend.srcAlphaBlendFactor = VK_BLEND_FACTOR_ZERO;
  blend.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
  blend.alphaBlendOp = VK_BLEND_OP_ADD;
  if (desc.additive || desc.screen) {
    blend.srcColorBlendFactor =
        desc.screen ? VK_BLEND_FACTOR_ONE_MINUS_DST_COLOR : VK_BLEND_FACTOR_ONE;
    blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
  } else {
    blend.srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
    blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
  }
  return blend;
}

}  // namespace

UniquePipeline createGraphicsPipeline(const DeviceContext& c, VkPipelineLayout layout,
                                      const GraphicsPipelineDesc& desc) {
  const UniqueShaderModule vert = createShaderModule(c, desc.vert);
  const bool fragment = desc.frag.code != nullptr;  // none: depth only
  const UniqueShaderModule frag =
      fragment ? createShaderModule(c, desc.frag) : UniqueShaderModule();
  VkPipelineShaderStageCreateInfo stages[2] = {};
  stages[0] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vert;
  stages[0].pName = "main";
  stages[1] = stages[0];
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = frag;

  const FixedStates fixed(desc);
  const VkPipelineColorBlendAttachmentState blend = blending(desc);
  VkPipelineColorBlendStateCreateInfo colorBlend{
      VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  const bool color = desc.target.color != VK_FORMAT_UNDEFINED;
  colorBlend.attachmentCount = color ? 1 : 0;
  colorBlend.pAttachments = &blend;
  // For the host's render pass and subpass, or for dynamic rendering with these formats.
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = color ? 1 : 0;
  rendering.pColorAttachmentFormats = &desc.target.color;
  rendering.depthAttachmentFormat = desc.target.depth;

  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  if (desc.target.renderPass) {
    info.renderPass = desc.target.renderPass;
    info.subpass = desc.target.subpass;
  } else {
    info.pNext = &rendering;
  }
  info.stageCount = fragment ? 2 : 1;
  info.pStages = stages;
  info.pVertexInputState = &fixed.vertexInput;
  info.pInputAssemblyState = &fixed.assembly;
  info.pViewportState = &fixed.viewport;
  info.pRasterizationState = &fixed.raster;
  info.pMultisampleState = &fixed.multisample;
  info.pDepthStencilState = &fixed.depthStencil;
  info.pColorBlendState = &colorBlend;
  info.pDynamicState = &fixed.dynamic;
  info.layout = layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(c.vk.CreateGraphicsPipelines(c.device(), c.handles.pipelineCache, 1, &info,
                                        c.allocator(), &pipeline));
  return UniquePipeline(c, pipeline);
}

void checkTarget(const DeviceContext& c, const RenderFormats& target) {
  if (!target.renderPass && !c.handles.dynamicRendering)
    throw InvalidArgument("formats",
                          "no render pass given, and the device was created without dynamic "
                          "rendering (DeviceHandles::dynamicRendering): give "
                          "RenderFormats::renderPass");
}

}  // namespace lava::detail
