#include "inference/kernel.h"  // private to inference
