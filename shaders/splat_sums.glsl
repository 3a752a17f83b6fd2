// The splat's sums as the draws that resolve them read them (resolve.frag, glow_resolve.frag),
// at binding LAVA_SUMS_BINDING: through an R32_UINT texel view (LAVA_SUMS_TEXELS, where the
// device's texel views hold the target's sums: on llvmpipe a gather, where a storage-buffer
// load is a loop over the lanes) or as the storage buffer splat.comp adds into.
#if LAVA_SUMS_TEXELS
layout(binding = LAVA_SUMS_BINDING) uniform utextureBuffer accumulation;

uint splatSumAt(uint i) {
  return texelFetch(accumulation, int(i)).r;
}
#else
layout(std430, binding = LAVA_SUMS_BINDING) restrict readonly buffer Accumulation {
  uint accumulation[];
};

uint splatSumAt(uint i) {
  return accumulation[i];
}
#endif
