// VK_LAYER_LAVA_fault: a Vulkan layer for tests that makes one call fail. Between the program
// and the driver it counts the calls of every function it wraps and, when
//
//   LAVA_FAULT=vkAllocateMemory:3:VK_ERROR_OUT_OF_DEVICE_MEMORY
//
// is set, returns that result from the 3rd call of vkAllocateMemory instead of calling down
// (the Nth call across the whole process). LAVA_FAULT_COUNTS=FILE writes every wrapped
// function's call count there at exit, so a test learns which calls a command makes, and
// for each call site the first call made from it:
//
//   vkAllocateMemory 57
//   site vkAllocateMemory 3 liblava.so.0+0x4a2f1<liblava.so.0+0x51c0e<lava+0x3d2a0
//
// A site is where the call came from in the program: the first three return addresses on
// the stack outside this layer and the Vulkan loader (module and offset), so that a helper
// that makes the call for many callers (a buffer's constructor, a one-off submit) counts
// once per caller.
// Enabled with VK_LAYER_PATH (this folder's manifest) and VK_INSTANCE_LAYERS.
#include <vulkan/vk_layer.h>
#include <vulkan/vulkan.h>

#include <dlfcn.h>
#include <execinfo.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>

#define LAVA_FAULT_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

// -- what to fail, and the counts ---------------------------------------------------------

struct Plan {
  std::string function;
  unsigned long long call = 0;
  VkResult result = VK_SUCCESS;
};

VkResult resultNamed(const std::string& name) {
  if (name == "VK_ERROR_OUT_OF_HOST_MEMORY") return VK_ERROR_OUT_OF_HOST_MEMORY;
  if (name == "VK_ERROR_OUT_OF_DEVICE_MEMORY") return VK_ERROR_OUT_OF_DEVICE_MEMORY;
  if (name == "VK_ERROR_DEVICE_LOST") return VK_ERROR_DEVICE_LOST;
  if (name == "VK_ERROR_INITIALIZATION_FAILED") return VK_ERROR_INITIALIZATION_FAILED;
  std::fprintf(stderr, "fault layer: unknown result %s\n", name.c_str());
  std::abort();
}

const Plan& plan() {
  static const Plan p = [] {
    Plan q;
    const char* env = std::getenv("LAVA_FAULT");
    if (!env || !*env) return q;
    const std::string text = env;
    const size_t a = text.find(':'), b = text.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) {
      std::fprintf(stderr, "fault layer: LAVA_FAULT=function:call:result, got %s\n", env);
      std::abort();
    }
    q.function = text.substr(0, a);
    q.call = std::strtoull(text.substr(a + 1, b - a - 1).c_str(), nullptr, 10);
    q.result = resultNamed(text.substr(b + 1));
    return q;
  }();
  return p;
}

std::mutex countsMutex;
std::map<std::string, unsigned long long>& counts() {
  static auto* c = new std::map<std::string, unsigned long long>;  // outlives static dtors
  return *c;
}

// Per function, each call site's first call (only while counting).
std::map<std::string, std::map<std::string, unsigned long long>>& sites() {
  static auto* s = new std::map<std::string, std::map<std::string, unsigned long long>>;
  return *s;
}

bool countingSites() {
  static const bool counting = std::getenv("LAVA_FAULT_COUNTS") != nullptr;
  return counting;
}

// The call's site (see the top): module+offset of the first three return addresses that
// are neither in this layer nor in the loader.
std::string callSite() {
  void* frames[32];
  const int n = backtrace(frames, 32);
  Dl_info self{};
  dladdr(reinterpret_cast<void*>(&callSite), &self);
  std::string site;
  int kept = 0;
  for (int i = 1; i < n && kept < 3; ++i) {
    Dl_info info{};
    if (!dladdr(frames[i], &info) || !info.dli_fname) continue;
    if (info.dli_fbase == self.dli_fbase) continue;
    const char* slash = std::strrchr(info.dli_fname, '/');
    const std::string module = slash ? slash + 1 : info.dli_fname;
    if (module.rfind("libvulkan.so", 0) == 0) continue;
    char text[64];
    // A return address less one: inside the call instruction, the same for every call.
    std::snprintf(text, sizeof(text), "+0x%lx",
                  static_cast<unsigned long>(static_cast<char*>(frames[i]) - 1 -
                                             static_cast<char*>(info.dli_fbase)));
    site += (kept++ ? "<" : "") + module + text;
  }
  return site.empty() ? "unknown" : site;
}

void writeCounts() {
  const char* path = std::getenv("LAVA_FAULT_COUNTS");
  if (!path) return;
  std::lock_guard<std::mutex> lock(countsMutex);
  if (FILE* f = std::fopen(path, "w")) {
    for (const auto& [name, n] : counts()) std::fprintf(f, "%s %llu\n", name.c_str(), n);
    for (const auto& [name, bySite] : sites())
      for (const auto& [site, first] : bySite)
        std::fprintf(f, "site %s %llu %s\n", name.c_str(), first, site.c_str());
    std::fclose(f);
  }
}

// Counts a call of `function`; the injected result when it is the planned one.
bool inject(const char* function, VkResult& result) {
  static const bool registered = [] { return std::atexit(writeCounts) == 0; }();
  (void)registered;
  unsigned long long n;
  const std::string site = countingSites() ? callSite() : std::string();
  {
    std::lock_guard<std::mutex> lock(countsMutex);
    n = ++counts()[function];
    if (!site.empty()) sites()[function].emplace(site, n);  // kept: the first
  }
  const Plan& p = plan();
  if (p.call == n && p.function == function) {
    result = p.result;
    return true;
  }
  return false;
}

// -- dispatch -----------------------------------------------------------------------------

template <typename T>
void* key(T handle) {
  return *reinterpret_cast<void**>(handle);  // the loader's dispatch table pointer
}

std::mutex tablesMutex;
std::map<void*, PFN_vkGetInstanceProcAddr>& instances() {
  static auto* m = new std::map<void*, PFN_vkGetInstanceProcAddr>;
  return *m;
}
struct NextDevice {
  PFN_vkGetDeviceProcAddr gdpa;
  VkDevice device;
};
std::map<void*, NextDevice>& devices() {
  static auto* m = new std::map<void*, NextDevice>;
  return *m;
}
PFN_vkGetInstanceProcAddr nextInstance(void* k) {
  std::lock_guard<std::mutex> lock(tablesMutex);
  auto it = instances().find(k);
  return it == instances().end() ? nullptr : it->second;
}
// The next layer's (or the driver's) `name` for the device behind a dispatch key.
PFN_vkVoidFunction nextDevice(void* k, const char* name) {
  std::lock_guard<std::mutex> lock(tablesMutex);
  auto it = devices().find(k);
  return it == devices().end() ? nullptr : it->second.gdpa(it->second.device, name);
}

}  // namespace

extern "C" {

VKAPI_ATTR VkResult VKAPI_CALL lavaFault_CreateInstance(const VkInstanceCreateInfo* info,
                                                        const VkAllocationCallbacks* allocator,
                                                        VkInstance* instance) {
  auto* link = reinterpret_cast<VkLayerInstanceCreateInfo*>(const_cast<void*>(info->pNext));
  while (link && !(link->sType == VK_STRUCTURE_TYPE_LOADER_INSTANCE_CREATE_INFO &&
                   link->function == VK_LAYER_LINK_INFO))
    link = reinterpret_cast<VkLayerInstanceCreateInfo*>(const_cast<void*>(link->pNext));
  if (!link) return VK_ERROR_INITIALIZATION_FAILED;
  const PFN_vkGetInstanceProcAddr next = link->u.pLayerInfo->pfnNextGetInstanceProcAddr;
  link->u.pLayerInfo = link->u.pLayerInfo->pNext;
  VkResult injected;
  if (inject("vkCreateInstance", injected)) return injected;
  auto create = reinterpret_cast<PFN_vkCreateInstance>(next(VK_NULL_HANDLE, "vkCreateInstance"));
  const VkResult result = create(info, allocator, instance);
  if (result == VK_SUCCESS) {
    std::lock_guard<std::mutex> lock(tablesMutex);
    instances()[key(*instance)] = next;
  }
  return result;
}

VKAPI_ATTR VkResult VKAPI_CALL lavaFault_CreateDevice(VkPhysicalDevice physical,
                                                      const VkDeviceCreateInfo* info,
                                                      const VkAllocationCallbacks* allocator,
                                                      VkDevice* device) {
  auto* link = reinterpret_cast<VkLayerDeviceCreateInfo*>(const_cast<void*>(info->pNext));
  while (link && !(link->sType == VK_STRUCTURE_TYPE_LOADER_DEVICE_CREATE_INFO &&
                   link->function == VK_LAYER_LINK_INFO))
    link = reinterpret_cast<VkLayerDeviceCreateInfo*>(const_cast<void*>(link->pNext));
  if (!link) return VK_ERROR_INITIALIZATION_FAILED;
  const PFN_vkGetInstanceProcAddr nextGipa = link->u.pLayerInfo->pfnNextGetInstanceProcAddr;
  const PFN_vkGetDeviceProcAddr nextGdpa = link->u.pLayerInfo->pfnNextGetDeviceProcAddr;
  link->u.pLayerInfo = link->u.pLayerInfo->pNext;
  VkResult injected;
  if (inject("vkCreateDevice", injected)) return injected;
  auto create = reinterpret_cast<PFN_vkCreateDevice>(nextGipa(VK_NULL_HANDLE, "vkCreateDevice"));
  const VkResult result = create(physical, info, allocator, device);
  if (result == VK_SUCCESS) {
    std::lock_guard<std::mutex> lock(tablesMutex);
    devices()[key(*device)] = {nextGdpa, *device};
  }
  return result;
}

// Device functions that can fail: counted, failed when planned, else called down.
#define LAVA_FAULT_WRAP(name, params, args, first)                                        \
  VKAPI_ATTR VkResult VKAPI_CALL lavaFault_##name params {                                \
    VkResult injected;                                                                    \
    if (inject("vk" #name, injected)) return injected;                                    \
    auto next = reinterpret_cast<PFN_vk##name>(nextDevice(key(first), "vk" #name));        \
    return next args;                                                                     \
  }
#define LAVA_FAULT_FUNCTIONS(X)                                                                   \
  X(AllocateMemory, (VkDevice d, const VkMemoryAllocateInfo* i, const VkAllocationCallbacks* a,   \
                     VkDeviceMemory* m), (d, i, a, m), d)                                         \
  X(CreateBuffer, (VkDevice d, const VkBufferCreateInfo* i, const VkAllocationCallbacks* a,       \
                   VkBuffer* b), (d, i, a, b), d)                                                 \
  X(CreateBufferView, (VkDevice d, const VkBufferViewCreateInfo* i,                               \
                       const VkAllocationCallbacks* a, VkBufferView* v), (d, i, a, v), d)         \
  X(CreateImage, (VkDevice d, const VkImageCreateInfo* i, const VkAllocationCallbacks* a,         \
                  VkImage* m), (d, i, a, m), d)                                                   \
  X(CreateImageView, (VkDevice d, const VkImageViewCreateInfo* i,                                 \
                      const VkAllocationCallbacks* a, VkImageView* v), (d, i, a, v), d)           \
  X(CreateSampler, (VkDevice d, const VkSamplerCreateInfo* i, const VkAllocationCallbacks* a,     \
                    VkSampler* s), (d, i, a, s), d)                                               \
  X(CreateShaderModule, (VkDevice d, const VkShaderModuleCreateInfo* i,                           \
                         const VkAllocationCallbacks* a, VkShaderModule* s), (d, i, a, s), d)     \
  X(CreateDescriptorSetLayout, (VkDevice d, const VkDescriptorSetLayoutCreateInfo* i,             \
                                const VkAllocationCallbacks* a, VkDescriptorSetLayout* l),        \
    (d, i, a, l), d)                                                                              \
  X(CreatePipelineLayout, (VkDevice d, const VkPipelineLayoutCreateInfo* i,                       \
                           const VkAllocationCallbacks* a, VkPipelineLayout* l), (d, i, a, l), d) \
  X(CreateComputePipelines, (VkDevice d, VkPipelineCache c, uint32_t n,                           \
                             const VkComputePipelineCreateInfo* i,                                \
                             const VkAllocationCallbacks* a, VkPipeline* p),                      \
    (d, c, n, i, a, p), d)                                                                        \
  X(CreateGraphicsPipelines, (VkDevice d, VkPipelineCache c, uint32_t n,                          \
                              const VkGraphicsPipelineCreateInfo* i,                              \
                              const VkAllocationCallbacks* a, VkPipeline* p),                     \
    (d, c, n, i, a, p), d)                                                                        \
  X(CreateCommandPool, (VkDevice d, const VkCommandPoolCreateInfo* i,                             \
                        const VkAllocationCallbacks* a, VkCommandPool* p), (d, i, a, p), d)       \
  X(AllocateCommandBuffers, (VkDevice d, const VkCommandBufferAllocateInfo* i,                    \
                             VkCommandBuffer* b), (d, i, b), d)                                   \
  X(BeginCommandBuffer, (VkCommandBuffer b, const VkCommandBufferBeginInfo* i), (b, i), b)        \
  X(EndCommandBuffer, (VkCommandBuffer b), (b), b)                                                \
  X(CreateFence, (VkDevice d, const VkFenceCreateInfo* i, const VkAllocationCallbacks* a,         \
                  VkFence* f), (d, i, a, f), d)                                                   \
  X(ResetFences, (VkDevice d, uint32_t n, const VkFence* f), (d, n, f), d)                        \
  X(WaitForFences, (VkDevice d, uint32_t n, const VkFence* f, VkBool32 all, uint64_t t),          \
    (d, n, f, all, t), d)                                                                         \
  X(QueueSubmit, (VkQueue q, uint32_t n, const VkSubmitInfo* s, VkFence f), (q, n, s, f), q)      \
  X(QueueWaitIdle, (VkQueue q), (q), q)                                                           \
  X(DeviceWaitIdle, (VkDevice d), (d), d)                                                         \
  X(CreateQueryPool, (VkDevice d, const VkQueryPoolCreateInfo* i, const VkAllocationCallbacks* a, \
                      VkQueryPool* p), (d, i, a, p), d)                                           \
  X(GetQueryPoolResults, (VkDevice d, VkQueryPool p, uint32_t f, uint32_t n, size_t s, void* v,   \
                          VkDeviceSize st, VkQueryResultFlags fl), (d, p, f, n, s, v, st, fl), d) \
  X(MapMemory, (VkDevice d, VkDeviceMemory m, VkDeviceSize o, VkDeviceSize s,                     \
                VkMemoryMapFlags f, void** p), (d, m, o, s, f, p), d)                             \
  X(BindBufferMemory, (VkDevice d, VkBuffer b, VkDeviceMemory m, VkDeviceSize o), (d, b, m, o), d) \
  X(BindImageMemory, (VkDevice d, VkImage i, VkDeviceMemory m, VkDeviceSize o), (d, i, m, o), d)  \
  X(FlushMappedMemoryRanges, (VkDevice d, uint32_t n, const VkMappedMemoryRange* r), (d, n, r), d) \
  X(InvalidateMappedMemoryRanges, (VkDevice d, uint32_t n, const VkMappedMemoryRange* r),        \
    (d, n, r), d)

LAVA_FAULT_FUNCTIONS(LAVA_FAULT_WRAP)

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL lavaFault_GetDeviceProcAddr(VkDevice device,
                                                                     const char* name);

#define LAVA_FAULT_MATCH(name, params, args, first) \
  if (std::strcmp(n, "vk" #name) == 0) return reinterpret_cast<PFN_vkVoidFunction>(lavaFault_##name);

static PFN_vkVoidFunction deviceFunction(const char* n) {
  LAVA_FAULT_FUNCTIONS(LAVA_FAULT_MATCH)
  if (std::strcmp(n, "vkGetDeviceProcAddr") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(lavaFault_GetDeviceProcAddr);
  return nullptr;
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL lavaFault_GetDeviceProcAddr(VkDevice device,
                                                                     const char* name) {
  if (PFN_vkVoidFunction f = deviceFunction(name)) return f;
  return nextDevice(key(device), name);
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL lavaFault_GetInstanceProcAddr(VkInstance instance,
                                                                       const char* name) {
  if (std::strcmp(name, "vkGetInstanceProcAddr") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(lavaFault_GetInstanceProcAddr);
  if (std::strcmp(name, "vkCreateInstance") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(lavaFault_CreateInstance);
  if (std::strcmp(name, "vkCreateDevice") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(lavaFault_CreateDevice);
  if (PFN_vkVoidFunction f = deviceFunction(name)) return f;
  if (!instance) return nullptr;
  const PFN_vkGetInstanceProcAddr next = nextInstance(key(instance));
  return next ? next(instance, name) : nullptr;
}

// The loader's entry (interface version 2): our GetInstanceProcAddr and GetDeviceProcAddr
// under their own names, so that no other library resolves the loader's symbols to ours.
LAVA_FAULT_EXPORT VKAPI_ATTR VkResult VKAPI_CALL
vkNegotiateLoaderLayerInterfaceVersion(VkNegotiateLayerInterface* interface) {
  if (!interface || interface->sType != LAYER_NEGOTIATE_INTERFACE_STRUCT)
    return VK_ERROR_INITIALIZATION_FAILED;
  if (interface->loaderLayerInterfaceVersion > 2) interface->loaderLayerInterfaceVersion = 2;
  interface->pfnGetInstanceProcAddr = lavaFault_GetInstanceProcAddr;
  interface->pfnGetDeviceProcAddr = lavaFault_GetDeviceProcAddr;
  interface->pfnGetPhysicalDeviceProcAddr = nullptr;
  return VK_SUCCESS;
}

}  // extern "C"
