// SPDX-License-Identifier: MIT
/// @file Test fixture: writes the model files test_capi.c loads (usage: make_capi_models DIR).
///   DIR/model_a.json  every rule y = c + k·x̂_PV, c = (3, −1.25, 4, 2.5), k = (1, 0.5, 0, 2);
///                     a 95 % interval: half-widths (2, 1.5, 1, 0.5) µm, gains (0, 1, 2, 0.25)
///   DIR/model_b.json  constant outputs (1, 1, 1, −0.5), no interval calibration
/// Input ranges: PV [5, 80] mm/s, PD [1, 50] mm, AV [1, 10] mm/s, AD [0.5, 5] mm.
#include <array>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cstdio>
#include <exception>
#include <string>

namespace {

cmmcomp::io::ModelFileOf<cmmcomp::PaperInputs> linear_file(const std::array<double, 4>& c,
                                                           const std::array<double, 4>& k) {
  cmmcomp::io::ModelFileOf<cmmcomp::PaperInputs> f;  // the schema's names and units
  auto& m = f.model;
  m.ranges = {cmmcomp::fuzzy::InputRange{5.0, 80.0},
              cmmcomp::fuzzy::InputRange{1.0, 50.0},
              cmmcomp::fuzzy::InputRange{1.0, 10.0},
              cmmcomp::fuzzy::InputRange{0.5, 5.0}};
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      m.params.centre(i, s) = 0.5 * s;
      m.params.width(i, s) = 0.4;
    }
  }
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < f.model.kRules; ++j) {
      m.params.consequent(o, j, 0) = c[static_cast<unsigned>(o)];
      m.params.consequent(o, j, 1) = k[static_cast<unsigned>(o)];
    }
  }
  f.training.method = "hand-built test model";
  f.training.cv_rmse = {0.0, 0.0, 0.0, 0.0};
  f.training.trained_at = "2026-01-01T00:00:00Z";
  f.training.tool_version = "make_capi_models";
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_capi_models DIR\n");
    return 2;
  }
  try {
    const std::string dir = argv[1];
    auto file_a = linear_file({3.0, -1.25, 4.0, 2.5}, {1.0, 0.5, 0.0, 2.0});
    file_a.interval.coverage = 0.95;
    file_a.interval.half_width = {2.0, 1.5, 1.0, 0.5};
    file_a.interval.extrapolation_gain = {0.0, 1.0, 2.0, 0.25};
    file_a.interval_method = "hand-built test calibration";
    file_a.interval_samples = 1;
    const std::string a = cmmcomp::io::save_model_file(dir + "/model_a.json", file_a);
    const std::string b = cmmcomp::io::save_model_file(
        dir + "/model_b.json", linear_file({1.0, 1.0, 1.0, -0.5}, {0.0, 0.0, 0.0, 0.0}));
    std::printf("make_capi_models: model_a %s, model_b %s\n", a.c_str(), b.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_capi_models: %s\n", e.what());
    return 1;
  }
}
