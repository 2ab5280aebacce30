// The one error convention at the edge, shared by both executables (quadfdi and quadfdi-training):
// usage errors exit 2, bad input and failures 1, an interrupted run 130; each is one line on
// standard error, prefixed "quadfdi: ".
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace quadfdi::cli {

inline constexpr const char* kVersion = "quadfdi 0.2.0";

// Parses argv into app (its commands already added), then calls run with the command line as
// typed ("quadfdi" and the arguments: reports record it) and returns its exit code; every
// exception ends here as one line and an exit code.
int runCommandLine(CLI::App& app, int argc, char** argv, const std::function<int(const std::string&)>& run);

// The commands that need LibTorch. Their code lives in the executable quadfdi-training
// (cli/training_main.cpp), which quadfdi starts in its own place (cli/hand_over.cpp), so that
// every other command starts without loading LibTorch (about 0.7 s of static initialisers).
struct CommandSummary {
  const char* name;
  const char* description;  // as --help shows it
};
inline constexpr CommandSummary kTrainingCommands[] = {
    {"train",
     "Train a fault identifier by Algorithm 1 (docs/networks.md): fresh closed-loop data every outer iteration\n"
     "(faults of motor 2 only; other motors are reached through the symmetry maps), a FIFO window\n"
     "buffer, minibatch passes with the hinge loss, Adam (lr 5e-4, wd 1e-5), and the stopping rule\n"
     "(loss < 1e-3 after N_m iterations, or N_M). Checkpointed every outer iteration: --resume\n"
     "continues a killed run, losing at most one iteration."},
    {"reproduce",
     "The whole chain in one folder: train every network the experiments need (model-free LSTM,\n"
     "model-based LSTM, residual-only LSTM, model-free MLP; data generated inside Algorithm 1),\n"
     "then run E1–E6 and write REPORT.md with tables and figures.\n"
     "Scales: tiny (tests), quick (~8 min on 2 cores, small networks' training), default (the CPU\n"
     "reproduction), paper (the paper's training and test scale; meant for a GPU: --device cuda)."},
    {"convert-model",
     "Convert a LibTorch model archive (.qfdi, format 1, quadfdi ≤ 0.1) into the weights file (.qfdw,\n"
     "docs/weights-format.md) that evaluate and detect read. The weights are copied exactly."},
};

// The summary of a training command by name; nullptr for any other name.
const CommandSummary* trainingCommand(const std::string& name);

}  // namespace quadfdi::cli
