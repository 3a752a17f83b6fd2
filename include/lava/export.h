// LAVA_API marks what liblava exports, LAVA_TOOLS_API what liblava_tools exports (the
// comparisons, checkpoints and the bench's ceilings: lava/validation.h, lava/checkpoint.h,
// lava/bench.h); everything else in them stays hidden. LAVA_BUILDING is defined while liblava
// is compiled and LAVA_BUILDING_TOOLS while liblava_tools is (Windows: export, not import);
// LAVA_STATIC for a static build.
#pragma once

#if defined(LAVA_STATIC)
#define LAVA_API
#define LAVA_TOOLS_API
#elif defined(_WIN32) || defined(__CYGWIN__)  // MSVC, MinGW, clang-cl
#if defined(LAVA_BUILDING)
#define LAVA_API __declspec(dllexport)
#else
#define LAVA_API __declspec(dllimport)
#endif
#if defined(LAVA_BUILDING_TOOLS)
#define LAVA_TOOLS_API __declspec(dllexport)
#else
#define LAVA_TOOLS_API __declspec(dllimport)
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define LAVA_API __attribute__((visibility("default")))
#define LAVA_TOOLS_API __attribute__((visibility("default")))
#else
#define LAVA_API
#define LAVA_TOOLS_API
#endif
