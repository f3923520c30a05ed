// Which compiled variant of the filter kernels this process runs (src/kernels.hpp: x86-64-v4, x86-64-v3 or
// the baseline, chosen once by the loader from the CPU's features). Services log it at start-up: results
// repeat bit for bit on machines that run the same variant, and may differ in the last bits between variants
// (FMA contraction).
#pragma once

namespace causal::estimation {

// "x86-64-v4" (AVX-512 F/BW/CD/DQ/VL), "x86-64-v3" (AVX2, FMA), "baseline" (a CPU without those, or a build
// without the clones: another compiler or architecture, or CAUSAL_CORE_NO_CLONES).
const char* kernel_instruction_set();

}  // namespace causal::estimation
