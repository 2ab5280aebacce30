// quadfdi hands the commands that need LibTorch (cli/command_line.h, kTrainingCommands) over to
// the executable quadfdi-training, built next to it.
#pragma once

namespace quadfdi::cli {

// Replaces this process with quadfdi-training, argv unchanged (the same process id, signals,
// standard streams and exit code). Returns only on failure: 1, after a one-line error naming
// the executable it looked for, or saying that this build has no training (QUADFDI_WITH_TRAINING=OFF).
int handOverToTraining(int argc, char** argv);

}  // namespace quadfdi::cli
