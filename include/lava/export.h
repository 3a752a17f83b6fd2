// LAVA_API marks what the shared library exports; everything else in it stays hidden.
// LAVA_BUILDING is defined while the library itself is compiled (Windows: export, not
// import); LAVA_STATIC for a static build.
#pragma once

#if defined(LAVA_STATIC)
#define LAVA_API
#elif defined(_WIN32) || defined(__CYGWIN__)  // MSVC, MinGW, clang-cl
#if defined(LAVA_BUILDING)
#define LAVA_API __declspec(dllexport)
#else
#define LAVA_API __declspec(dllimport)
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define LAVA_API __attribute__((visibility("default")))
#else
#define LAVA_API
#endif
