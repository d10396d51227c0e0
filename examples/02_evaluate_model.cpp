// SPDX-License-Identifier: MIT
/// @file Example 2: predict the four dynamic errors of a move with the shipped default model.
///
/// The model is the paper's Takagi-Sugeno fuzzy network: inputs PV [mm/s], PD [mm], AV [mm/s],
/// AD [mm]; outputs MPE, RPE, MAE, RAE [um]. data/models/default.json is compiled into the
/// library (io::default_model_file()); io::load_model_file<4, 3, 4>(path) reads any other file.
/// It was trained on the digital twin, so it describes the simulated machine, not yours.
/// Self-check: the prediction is finite, plausible, and near what the twin simulates.
#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cstdio>

int main() {
  using namespace cmmcomp;
  // Parse and validate the compiled-in model (setup code: allocates, may throw ConfigError).
  const io::ModelFileOf<PaperInputs> file = io::default_model_file();
  std::printf("model %s from %s\n", file.model_id.c_str(), io::kDefaultModelSource);
  for (std::size_t i = 0; i < 4; ++i) {
    std::printf("  input %-8s trained on [%g, %g] %s\n",
                file.input_names[i].c_str(),
                file.model.ranges[i].lo,
                file.model.ranges[i].hi,
                file.input_units[i].c_str());
  }

  // The baseline move in the model's units (PA and AA are not inputs of this network).
  const std::array<double, 4> x{40.0, 40.0, 12.0, 10.0};  // PV, PD, AV, AD
  std::array<double, 4> y{};                              // MPE, RPE, MAE, RAE [um]
  // evaluate() is the real-time call: no allocation, no exception. kReject refuses inputs
  // outside the training ranges (kClamp and kExtrapolate are the alternatives).
  const Status s = fuzzy::evaluate(file.model, x, y, fuzzy::DomainPolicy::kReject);
  if (!ok(s)) {
    std::fprintf(stderr, "evaluate failed: %s\n", to_string(s));
    return 1;
  }
  for (std::size_t o = 0; o < 4; ++o) {
    std::printf("  predicted %-6s %8.3f %s\n",
                file.output_names[o].c_str(),
                y[o],
                file.output_units[o].c_str());
  }

  // What `cmmcomp-sim move` reports for this move on the default twin (um); the network was
  // trained on such simulations, so it should be within a few um of them.
  const std::array<double, 4> twin{14.43, -5.77, 7.43, -4.50};
  bool good = y[0] >= std::fabs(y[1]) && y[2] >= std::fabs(y[3]);  // a maximum bounds a residual
  for (std::size_t o = 0; o < 4; ++o) good = good && std::fabs(y[o] - twin[o]) < 3.0;
  std::printf("%s\n", good ? "OK: close to the twin" : "WRONG: far from the twin");
  return good ? 0 : 1;
}
