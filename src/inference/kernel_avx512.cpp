// The inference kernels for avx512 (flags in src/CMakeLists.txt); see inference_kernel.inc.
#define QUADFDI_LANES 16
#define QUADFDI_ROW_BLOCKS 2
#define QUADFDI_KERNEL avx512Kernel
#define QUADFDI_KERNEL_NAME "avx512"
#include "inference/kernel.inc"
