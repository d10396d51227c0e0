// SPDX-License-Identifier: MIT
/// @file The interval's coverage study (include/cmmcomp/study/interval_coverage.hpp).
#include <fmt/format.h>

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/study/interval_coverage.hpp>
#include <filesystem>
#include <variant>

namespace cmmcomp::study {
namespace {

constexpr double kLowestPct = 92.0;   ///< 95 − 3: the interval never under-covers
constexpr double kHighestPct = 98.0;  ///< 95 + 3: nor is it needlessly wide

CoverageRow row_of(const std::string& name,
                   const io::CompensationModelFile& model,
                   const std::vector<DatasetRow>& rows) {
  const training::TestSetEvaluation e = evaluate_model_file(model, rows, name);
  CoverageRow r;
  r.name = name;
  r.moves = e.samples;
  r.outside = e.outside;
  r.coverage_pct = e.coverage_pct;
  for (std::size_t p = 0; p < kErrorCount; ++p) {
    double sum = 0;
    for (const double u : e.predictions.half_width[p]) sum += u;
    r.mean_u95_um[p] = sum / static_cast<double>(e.samples);
  }
  return r;
}

/// The recipe's simulation settings with another design over other levels.
std::vector<DatasetRow> simulate(Recipe recipe,
                                 const dynamics::Machine& machine,
                                 const std::string& levels,
                                 const DatasetPart& part,
                                 const RunOptions& options) {
  recipe.levels = levels;
  return simulate_part(recipe, machine, part, options.threads);
}

/// The --levels text of the corners of `model`'s box less `margin` of each range at both ends
/// (as the coverage script wrote it: six significant digits).
std::string corner_levels(const io::CompensationModelFile& model, double margin) {
  return std::visit(
      [&](const auto& f) {
        using Inputs = typename std::decay_t<decltype(f)>::InputSet;
        const auto labels = Inputs::labels();
        std::string s;
        for (std::size_t i = 0; i < labels.size(); ++i) {
          const double lo = f.model.ranges[i].lo, hi = f.model.ranges[i].hi, w = hi - lo;
          std::string label = labels[i];
          for (char& c : label) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
          s += fmt::format("{}{}={:g},{:g}", i ? ";" : "", label, lo + margin * w, hi - margin * w);
        }
        return s;
      },
      model);
}

void at_least(std::vector<Target>& t, const std::string& name, double measured) {
  t.push_back({name, measured, kLowestPct, Target::Kind::kAtLeast, "%"});
}

}  // namespace

CoverageResult interval_coverage(const io::CompensationModelFile& model,
                                 const io::CompensationModelFile& model_y,
                                 const Recipe& recipe,
                                 const std::vector<std::string>& variants,
                                 const RunOptions& options) {
  CoverageResult out;
  out.model_id = io::model_id(model);
  out.model_y_id = io::model_id(model_y);
  const auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const dynamics::Machine machine = recipe_machine(recipe);
  // Held out: the recipe's test design at each of its test seeds.
  std::array<double, kErrorCount> sum{};
  for (const std::uint64_t seed : recipe.test_seeds) {
    DatasetPart part = recipe.test;
    part.seed = seed;
    const CoverageRow r = row_of(fmt::format("default twin, LHS {} seed {}", part.samples, seed),
                                 model,
                                 simulate(recipe, machine, recipe.levels, part, options));
    say(r.name);
    for (std::size_t p = 0; p < kErrorCount; ++p) {
      at_least(out.targets,
               fmt::format("seed {}: {}_coverage", seed, kErrors[p].key),
               r.coverage_pct[p]);
      sum[p] += r.coverage_pct[p];
      if (seed == recipe.test_seeds.front()) {
        out.targets.push_back({fmt::format("seed {}: {} over-covers", seed, kErrors[p].key),
                               r.coverage_pct[p],
                               kHighestPct,
                               Target::Kind::kAtMost,
                               "%"});
      }
    }
    out.rows.push_back(r);
  }
  for (std::size_t p = 0; p < kErrorCount; ++p) {
    out.pooled_pct[p] = sum[p] / static_cast<double>(recipe.test_seeds.size());
    out.targets.push_back({fmt::format("pooled: {} over-covers", kErrors[p].key),
                           out.pooled_pct[p],
                           kHighestPct,
                           Target::Kind::kAtMost,
                           "%"});
  }
  // Unseen machines: the first held-out set's moves on each.
  DatasetPart first = recipe.test;
  for (const std::string& path : variants) {
    const std::string name = std::filesystem::path(path).stem().string();
    const CoverageRow r =
        row_of(fmt::format("unseen machine {}, LHS {} seed {}", name, first.samples, first.seed),
               model,
               simulate(recipe, dynamics::load_machine(path), recipe.levels, first, options));
    say(r.name);
    out.rows.push_back(r);
  }
  // Wider ranges than the training box.
  const CoverageRow wide = row_of(
      "default twin, wider ranges (PV 30-130, AD 3-20)",
      model,
      simulate(recipe, machine, "pv=30,80,130;pd=40,60,80;av=8,12,16;ad=3,10,20", first, options));
  say(wide.name);
  out.rows.push_back(wide);
  out.targets.push_back({"wider ranges: moves flagged outside the domain",
                         static_cast<double>(wide.outside),
                         1,
                         Target::Kind::kAtLeast,
                         "moves"});
  double grown = 0;
  for (std::size_t p = 0; p < kErrorCount; ++p) {
    grown += wide.mean_u95_um[p] > out.rows.front().mean_u95_um[p] ? 1 : 0;
    at_least(out.targets,
             fmt::format("wider ranges: {}_coverage", kErrors[p].key),
             wide.coverage_pct[p]);
  }
  out.targets.push_back(
      {"wider ranges: parameters whose mean U95 grew", grown, 1, Target::Kind::kAtLeast, ""});
  // The corners of the box, and of the box less 10 % and 20 % (reported, not checked).
  DatasetPart corners;
  corners.design = "full";
  corners.repeats = 10;
  corners.seed = 7;
  for (const double margin : {0.0, 0.1, 0.2}) {
    for (const io::CompensationModelFile* m : {&model, &model_y}) {
      const int inputs = io::model_inputs(*m);
      const CoverageRow r =
          row_of(fmt::format("{}-input model, corners of the box less margin {:g}", inputs, margin),
                 *m,
                 simulate(recipe, machine, corner_levels(*m, margin), corners, options));
      say(r.name);
      if (margin < 0.15) {
        for (std::size_t p = 0; p < kErrorCount; ++p) {
          at_least(out.targets,
                   fmt::format(
                       "{}-input corners less {:g}: {}_coverage", inputs, margin, kErrors[p].key),
                   r.coverage_pct[p]);
        }
      }
      out.rows.push_back(r);
    }
  }
  return out;
}

}  // namespace cmmcomp::study
