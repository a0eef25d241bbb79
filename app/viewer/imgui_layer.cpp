#include "app/viewer/imgui_layer.hpp"

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <array>
#include <stdexcept>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/vk/swapchain.hpp"

namespace prismoid::app {

namespace {

void check_imgui_vk(VkResult result) { vk::check(result, "Dear ImGui's Vulkan backend"); }

vk::UniqueDescriptorPool create_pool(const vk::Device& device) {
  // The backend allocates one combined image sampler set for its font atlas.
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8};
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  info.maxSets = 8;
  info.poolSizeCount = 1;
  info.pPoolSizes = &size;
  VkDescriptorPool pool;
  vk::check(vkCreateDescriptorPool(device.get(), &info, nullptr, &pool), "vkCreateDescriptorPool");
  return vk::UniqueDescriptorPool(device.get(), pool);
}

vk::UniqueRenderPass create_render_pass(const vk::Device& device, VkFormat format) {
  VkAttachmentDescription color{};
  color.format = format;
  color.samples = VK_SAMPLE_COUNT_1_BIT;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // keep the volume blitted there
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  color.initialLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  color.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
  VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &ref;
  // The blit's writes must land before the UI blends over them.
  VkSubpassDependency after_blit{};
  after_blit.srcSubpass = VK_SUBPASS_EXTERNAL;
  after_blit.dstSubpass = 0;
  after_blit.srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  after_blit.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  after_blit.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  after_blit.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = 1;
  info.pAttachments = &color;
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 1;
  info.pDependencies = &after_blit;
  VkRenderPass pass;
  vk::check(vkCreateRenderPass(device.get(), &info, nullptr, &pass), "vkCreateRenderPass");
  return vk::UniqueRenderPass(device.get(), pass);
}

}  // namespace

ImGuiLayer::ImGuiLayer(const vk::Device& device, GLFWwindow* window, const vk::Swapchain& swapchain)
    : device_(device), swapchain_(swapchain), pool_(create_pool(device)), render_pass_(create_render_pass(device, swapchain.format())) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left behind in the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForVulkan(window, true);
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = device.instance();
  info.PhysicalDevice = device.physical();
  info.Device = device.get();
  info.QueueFamily = device.queue_family();
  info.Queue = device.queue();
  info.DescriptorPool = pool_.get();
  info.MinImageCount = std::max(2u, swapchain.image_count());
  info.ImageCount = std::max(2u, swapchain.image_count());
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = check_imgui_vk;
  if (!ImGui_ImplVulkan_Init(&info, render_pass_.get())) throw std::runtime_error("Dear ImGui's Vulkan backend failed to start");
  device.submit_and_wait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
  swapchain_changed();
}

ImGuiLayer::~ImGuiLayer() {
  framebuffers_.clear();
  views_.clear();
  ImGui_ImplVulkan_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void ImGuiLayer::swapchain_changed() {
  framebuffers_.clear();
  views_.clear();
  const VkExtent2D extent = swapchain_.extent();
  for (uint32_t i = 0; i < swapchain_.image_count(); ++i) {
    VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view_info.image = swapchain_.image(i);
    view_info.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view_info.format = swapchain_.format();
    view_info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view;
    vk::check(vkCreateImageView(device_.get(), &view_info, nullptr, &view), "vkCreateImageView");
    views_.emplace_back(device_.get(), view);
    VkFramebufferCreateInfo fb_info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fb_info.renderPass = render_pass_.get();
    fb_info.attachmentCount = 1;
    fb_info.pAttachments = &view;
    fb_info.width = extent.width;
    fb_info.height = extent.height;
    fb_info.layers = 1;
    VkFramebuffer framebuffer;
    vk::check(vkCreateFramebuffer(device_.get(), &fb_info, nullptr, &framebuffer), "vkCreateFramebuffer");
    framebuffers_.emplace_back(device_.get(), framebuffer);
  }
  ImGui_ImplVulkan_SetMinImageCount(std::max(2u, swapchain_.image_count()));
}

void ImGuiLayer::begin_frame() {
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void ImGuiLayer::finish_frame() { ImGui::Render(); }

void ImGuiLayer::record(VkCommandBuffer cmd, uint32_t index, bool draw) {
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = render_pass_.get();
  begin.framebuffer = framebuffers_.at(index).get();
  begin.renderArea.extent = swapchain_.extent();
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  if (draw) ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
  vkCmdEndRenderPass(cmd);
}

bool ImGuiLayer::wants_mouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool ImGuiLayer::wants_keyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

}  // namespace prismoid::app
