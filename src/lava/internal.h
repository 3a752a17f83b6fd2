// LAVA_INTERNAL marks the few private classes and functions of liblava that liblava_tools
// calls: the bench's ceilings drive the library's own buffers, pipelines and kernels.
// Exported, but declared in no installed header, so hosts get no promise of them.
#pragma once
#include "lava/export.h"

#define LAVA_INTERNAL LAVA_API
