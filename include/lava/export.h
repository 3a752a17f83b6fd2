// LAVA_API marks what the shared library exports; everything else in it stays hidden.
#pragma once

#if defined(LAVA_STATIC)
#define LAVA_API
#else
#define LAVA_API __attribute__((visibility("default")))
#endif
