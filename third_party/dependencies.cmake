# The dependency boundary: every outside library Lava uses, found from Debian's packages
# (third_party/install-deps.sh installs them). Nothing is vendored or downloaded.

# The library: Vulkan (public headers), glm and toml++ (both compiled in from headers,
# private), threads.
find_package(Vulkan REQUIRED)
find_package(Threads REQUIRED)
find_package(glm REQUIRED)
find_package(hwy REQUIRED)  # Highway: the cpu-simd kernel
# Only its header: Lava builds toml++ in header-only mode (no run-time library for users).
find_path(TOMLPLUSPLUS_INCLUDE_DIR toml++/toml.h REQUIRED)
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

if(LAVA_BUILD_PROGRAM)
  find_package(CLI11 REQUIRED)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(GLFW REQUIRED IMPORTED_TARGET glfw3)
  # Xlib and its MIT-SHM extension: the demo's shared-memory presentation for CPU devices.
  pkg_check_modules(X11 REQUIRED IMPORTED_TARGET x11 xext)
  # Debian's libimgui-dev: a static library with the GLFW and Vulkan backends compiled in.
  pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
  add_library(lava_imgui INTERFACE)
  target_link_libraries(lava_imgui INTERFACE PkgConfig::IMGUI PkgConfig::GLFW Vulkan::Vulkan)
  find_path(IMGUI_BACKENDS_DIR imgui_impl_vulkan.h PATH_SUFFIXES imgui/backends REQUIRED)
  target_include_directories(lava_imgui SYSTEM INTERFACE ${IMGUI_BACKENDS_DIR}/..
                                                         ${IMGUI_BACKENDS_DIR})
  find_path(STB_INCLUDE_DIR stb_image_write.h PATH_SUFFIXES stb REQUIRED)
  add_library(lava_stb INTERFACE)
  target_include_directories(lava_stb SYSTEM INTERFACE ${STB_INCLUDE_DIR})
endif()

if(LAVA_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
