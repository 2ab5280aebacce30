#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "inference/model_metadata.h"

namespace quadfdi::cli {

// Filled by the option table (train_command.cpp), the only place that names the flags; reproduce
// fills it directly. Schedule fields left empty come from the named scale (data/scales.h).
struct TrainOptions {
  std::string config;                           // key = value file; flags given on the command line win
  std::string scale = "default";                // named scale: data per iteration, buffer, schedule
  std::string architecture = "lstm";            // lstm | mlp | tcn
  std::string features = "model-free";          // model-free | model-based | residual | model-free-heading | scale-free | scale-free-rates
  std::string training;                         // windows | sequences; empty: sequences for tcn, else windows
  int tcn_channels = quadfdi::TcnShape{}.channels;      // [-] hidden channels of a tcn (inference/model_metadata.h)
  std::string output_kind = "position-euler";   // position-euler | position-rates
  std::string symmetry = "exact";               // exact | paper
  std::string loss = "norm";                    // norm | per-motor
  std::string controller = "lqr";               // lqr | cbf
  std::string params = "nominal";               // plant: a named parameter set or a FILE
  std::vector<double> thetas{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};  // Θ₂ values [-]
  std::optional<int> batch_size;                // [windows] (windows training)
  int batch_trajectories = 32;                  // [trajectories] per minibatch (sequences training)
  double learning_rate = 5e-4;                  // Adam step size (authors' code)
  double learning_rate_decay = 1.0;             // per outer iteration; 1 = constant
  std::optional<int> passes;                    // over the buffer per outer iteration
  std::optional<int> buffer_windows;            // N_buf [windows]; unset: the scale's
  std::optional<int> max_minibatches;           // per outer iteration; 0 = no cap
  std::optional<int> min_iterations;            // N_m
  std::optional<int> max_iterations;            // N_M
  int average_last = 0;                         // [outer iterations] Polyak averaging of the weights; 0 = none
  double preroll = 0.0;                         // max random pre-roll [s]
  std::string randomise;                        // randomisation FILE (docs/data.md#randomisation); empty: none
  std::vector<std::string> vehicles;            // vehicle description FILEs; replace the randomisation's vehicles
  double post_fault = 0.0;                      // [s] recorded after the fault; 0 = T
  unsigned long long seed = 1;                  // weights, data and shuffling
  std::string device = "cpu";                   // cpu | cuda
  int threads = 0;                              // 0 = all cores
  std::string output;                           // model file
  std::string checkpoint;                       // default: <output>.ckpt
  std::string log;                              // default: <output>.log.csv
  bool resume = false;                          // continue from the checkpoint if there is one
  std::string start_from;                       // fine-tune: a finished model (.qfdw) to start from
  bool quiet = false;                           // no progress bar or summary
  std::set<std::string> given;                  // keys given explicitly: options this training would ignore are refused
};

// Declares the options (validated while CLI11 parses, --config included).
CLI::App* addTrainCommand(CLI::App& app, TrainOptions& options);
int runTrain(const TrainOptions& options, const std::string& command_line);
// Trains with resolved options and writes options.output (runTrain; reproduce calls it directly).
int trainAndSave(const TrainOptions& options, const std::string& command_line);

}  // namespace quadfdi::cli
