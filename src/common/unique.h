// Move-only owners of device-level Vulkan handles, for the library and the program alike.
#pragma once
#include <vulkan/vulkan.h>

#include <utility>

namespace lava::common {

static_assert(sizeof(void*) == 8, "handle types must be distinct (64-bit Vulkan)");

template <typename T>
using DestroyFn = void(VKAPI_PTR*)(VkDevice, T, const VkAllocationCallbacks*);

// Move-only owner of one device-level Vulkan handle, destroyed with `destroy` (a vkDestroy*
// or vkFreeMemory, the loader's or a device's function table's) and the allocation
// callbacks it was created with.
template <typename T>
class Unique {
 public:
  Unique() = default;
  Unique(VkDevice device, const VkAllocationCallbacks* allocator, DestroyFn<T> destroy, T handle)
      : device_(device), allocator_(allocator), destroy_(destroy), handle_(handle) {}
  // Through a context's function table: `destroyFn(context.vk, T{})` names the function.
  template <typename Context>
  Unique(const Context& context, T handle)
      : Unique(context.handles.device, context.handles.allocator, destroyFn(context.vk, T{}),
               handle) {}
  Unique(Unique&& other) noexcept { *this = std::move(other); }
  Unique& operator=(Unique&& other) noexcept {
    if (this != &other) {
      reset();
      device_ = other.device_;
      allocator_ = other.allocator_;
      destroy_ = other.destroy_;
      handle_ = std::exchange(other.handle_, T{});
    }
    return *this;
  }
  Unique(const Unique&) = delete;
  Unique& operator=(const Unique&) = delete;
  ~Unique() { reset(); }

  T get() const { return handle_; }
  operator T() const { return handle_; }  // NOLINT: used like the raw handle

  void reset() {
    if (handle_ != T{}) destroy_(device_, handle_, allocator_);
    handle_ = T{};
  }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  const VkAllocationCallbacks* allocator_ = nullptr;
  DestroyFn<T> destroy_ = nullptr;
  T handle_{};
};

}  // namespace lava::common
