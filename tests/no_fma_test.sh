#!/bin/sh
# No fused multiply-add anywhere in the library (docs/model.md: a fused a*b+c rounds once, the
# reference twice): the disassembly of every target Highway compiled holds no vfmadd,
# vfmsub, vfnmadd or vfnmsub, while it does hold the kernel's vector multiplies.
lib="$1"
dis=$(objdump -d --no-show-raw-insn "$lib") || { echo "FAIL: objdump $lib"; exit 1; }
fused=$(echo "$dis" | grep -cE '\bv?f(n)?m(add|sub)[0-9]*[ps][sd]\b')
wide=$(echo "$dis" | grep -cE '\bvmulps\b.*%ymm')
widest=$(echo "$dis" | grep -cE '\bvmulps\b.*%zmm')
echo "fused multiply-adds: $fused; vmulps on ymm: $wide, on zmm: $widest"
[ "$fused" -eq 0 ] || { echo "$dis" | grep -E '\bv?f(n)?m(add|sub)[0-9]*[ps][sd]\b' | head; echo "FAIL: fused multiply-add in $lib"; exit 1; }
[ "$wide" -gt 0 ] && [ "$widest" -gt 0 ] || { echo "FAIL: no AVX2/AVX-512 multiplies: the check saw no SIMD kernel"; exit 1; }
