// The inference kernels for avx2 (flags in src/CMakeLists.txt); see inference_kernel.inc.
#define QUADFDI_LANES 8
#define QUADFDI_ROW_BLOCKS 2
#define QUADFDI_KERNEL avx2Kernel
#define QUADFDI_KERNEL_NAME "avx2"
#include "inference/kernel.inc"
