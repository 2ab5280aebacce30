// Trained-model files on disk (the weights format of inference/weights_file.h, docs/weights-format.md).
#pragma once

#include <string>

#include "inference/weights_file.h"

namespace quadfdi {

// Reads and checks a .qfdw file; throws ModelError("PATH: problem").
TrainedModel readModelFile(const std::string& path);
// Writes atomically (an existing file survives a failed write); throws ModelError.
void writeModelFile(const std::string& path, const ModelMetadata& metadata, const NetworkWeights& weights);

}  // namespace quadfdi
