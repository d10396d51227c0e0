// SPDX-License-Identifier: MIT
/// @file The interval's calibration plot (interval_calibration.hpp).
#include <fmt/format.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/study/interval_calibration.hpp>
#include <cmmcomp/study/train.hpp>

namespace cmmcomp::study {

IntervalCalibrationResult interval_calibration(const Recipe& recipe,
                                               const std::vector<double>& levels,
                                               const RunOptions& options) {
  if (levels.empty()) throw ConfigError("interval-calibration: no coverage level");
  for (double c : levels) {
    if (!(c > 0 && c < 1)) {
      throw ConfigError(fmt::format("interval-calibration: coverage {} is not in (0, 1)", c));
    }
  }
  IntervalCalibrationResult out;
  out.recipe = recipe.name;
  const dynamics::Machine machine = recipe_machine(recipe);
  const std::vector<DatasetRow> train = training_rows(recipe, machine, options.threads);
  std::vector<DatasetRow> test;
  for (std::uint64_t seed : recipe.test_seeds) {
    DatasetPart part = recipe.test;
    part.seed = seed;
    const auto rows = simulate_part(recipe, machine, part, options.threads);
    test.insert(test.end(), rows.begin(), rows.end());
  }
  out.test_moves = test.size();
  for (double c : levels) {
    FitOverrides overrides;
    overrides.interval_coverage = c;
    const TrainedModel m = train_model(recipe, train, overrides);
    const training::TestSetEvaluation e =
        evaluate_model_file(m.file, test, fmt::format("{} at {:g} %", recipe.name, 100 * c));
    out.rows.push_back({100 * c, e.coverage_pct});
    if (options.progress) options.progress(fmt::format("{:g} %: done", 100 * c));
  }
  return out;
}

std::string interval_calibration_plot(const IntervalCalibrationResult& result,
                                      const std::string& png_path) {
  std::string data;
  for (const IntervalCalibrationRow& r : result.rows) {
    data += fmt::format("{:g}", r.nominal_pct);
    for (double v : r.coverage_pct) data += fmt::format(" {:.3f}", v);
    data += "\n";
  }
  std::string quoted;  // a gnuplot single-quoted string doubles a quote
  for (char c : png_path) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  std::string script = fmt::format(
      "set terminal pngcairo size 900,700 noenhanced\n"
      "set output '{}'\n"
      "set title 'Prediction interval: nominal vs empirical coverage ({} held-out moves, {})'\n"
      "set xlabel 'nominal coverage %'\n"
      "set ylabel 'empirical coverage %'\n"
      "set xrange [45:100]\nset yrange [45:100]\nset key bottom right\nset grid\n"
      "$data << EOD\n{}EOD\n"
      "plot x title 'ideal' with lines lc rgb '#888888' dt 2",
      quoted,
      result.test_moves,
      result.recipe,
      data);
  const char* points[] = {"7", "5", "9", "11"};
  for (std::size_t p = 0; p < kErrorCount; ++p) {
    script += fmt::format(
        ", $data using 1:{} title '{}' with linespoints pt {}", p + 2, kErrors[p].label, points[p]);
  }
  return script + "\n";
}

}  // namespace cmmcomp::study
