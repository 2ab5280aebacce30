#include "detection/detector.h"  // upward: model may not know the detector
