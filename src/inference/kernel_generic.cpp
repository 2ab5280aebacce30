// The inference kernels for generic (flags in src/CMakeLists.txt); see inference_kernel.inc.
#define QUADFDI_LANES 8
#define QUADFDI_ROW_BLOCKS 1
#define QUADFDI_KERNEL genericKernel
#define QUADFDI_KERNEL_NAME "generic"
#include "inference/kernel.inc"
