// Every shader Lava embeds: SPIR-V compiled from shaders/*.{comp,vert,frag} at build time,
// as arrays in this namespace (nothing is loaded by path at run time).
#pragma once
#include <cstdint>

namespace lava::spirv {
#include "copy_comp.h"
#include "flow_comp.h"
#include "flow_pairs.h"
#include "flow_plain.h"
#include "flow_rte.h"
#include "flow_signed_zero.h"
#include "glow_frag.h"
#include "glow_light.h"
#include "glow_light_buffer.h"
#include "glow_resolve_buffer_frag.h"
#include "glow_resolve_frag.h"
#include "glow_splat.h"
#include "glow_vert.h"
#include "glow_vert_buffer.h"
#include "ground_frag.h"
#include "ground_vert.h"
#include "lines_frag.h"
#include "lines_vert.h"
#include "resolve_buffer_frag.h"
#include "resolve_frag.h"
#include "resolve_vert.h"
#include "rock_frag.h"
#include "rock_vert.h"
#include "sky_vert.h"
#include "splat_comp.h"
#include "splat_pairs.h"
#include "step_comp.h"
#include "step_kernel_only.h"
#include "step_plain.h"
#include "step_rte.h"
#include "step_signed_zero.h"
}  // namespace lava::spirv
