// SPDX-License-Identifier: MIT
/// @file Example 6: build a dataset with the twin and train the fuzzy network on it.
///
/// This is the paper's recipe in miniature: the L18 orthogonal design of PV, PD, AV, AD (Table 3
/// levels) with 3 repeats = 54 moves, simulated on the twin with the paper's measurement noise,
/// then a 4-input, 4-output Takagi-Sugeno network (81 rules) fitted with Ceres. The training
/// residuals (RMSE per output) say how well the network fits; the cross-validated ones how
/// well it predicts moves it has not seen.
/// Self-check: the model is usable, beats a constant model (also cross-validated), and evaluates.
#include <array>
#include <cmath>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstdio>

int main() {
  using namespace cmmcomp;
  // 1. The design: 18 runs, each repeated 3 times (factor values in SI units).
  const doe::Design design = doe::replicate(doe::paper_l18_design(), 3);
  // 2. Dataset rows (file units: mm, mm/s) with PA 200 mm/s^2, AA 60 mm/s^2, Y 250 mm.
  std::vector<DatasetRow> rows = dynamics::rows_from_design(design, dynamics::FixedSettings{});
  // 3. Simulate every move (in parallel; the result does not depend on the thread count).
  dynamics::DatasetOptions dopt;
  dopt.noise.enabled = true;  // the paper's Table 1 scatter, seeded: repeats differ
  rows = dynamics::simulate_dataset(dynamics::default_machine(), rows, dopt);
  std::printf("simulated %zu moves; first: PV %g PD %g AV %g AD %g -> RAE %.3f um\n",
              rows.size(),
              rows[0].pv_mm_s,
              rows[0].pd_mm,
              rows[0].av_mm_s,
              rows[0].ad_mm,
              rows[0].rae_um);

  // 4. Train: the prior chosen on the three-level design, the ridge fit with lambda by 5-fold
  //    CV. Levenberg-Marquardt (at most 2 iterations here) refines only data with more design
  //    points than the premise's 24 centres and widths; on these 18 the ridge fit is kept and
  //    sum.message says why (docs/training.md, "The prior").
  training::FnnTrainingOptions topt;
  topt.max_iterations = 2;
  const auto result = training::train_network<PaperInputs>(rows, topt);  // PV, PD, AV, AD
  const auto samples = training::samples<PaperInputs>(rows);             // the four errors per row
  const training::TrainingSummary& sum = result.summary;
  std::printf("trained in %.2f s (%s), %d iterations, lambda %g, cost %.4g -> %.4g\n",
              sum.wall_seconds,
              sum.message.c_str(),
              sum.iterations,
              sum.lambda,
              sum.initial_cost,
              sum.final_cost);
  // The spread of each output over the dataset: what a constant model would leave.
  bool good = sum.usable();
  for (std::size_t o = 0; o < 4; ++o) {
    double mean = 0.0, var = 0.0;
    for (const auto& t : samples.targets) mean += t[o] / samples.targets.size();
    for (const auto& t : samples.targets) var += (t[o] - mean) * (t[o] - mean);
    const double spread = std::sqrt(var / samples.targets.size());
    std::printf("  %s: training RMSE %.3f um, CV RMSE %.3f um (spread of the data %.3f um)\n",
                kErrors[o].label,
                sum.train_rmse[o],
                sum.cv_rmse[o],
                spread);
    // Better than a constant model, both on the training data and on unseen folds (CV).
    good = good && sum.train_rmse[o] < spread && sum.cv_rmse[o] < spread;
  }

  // 5. The trained network is an ordinary TskModel: evaluate it like example 2's.
  std::array<double, 4> y{};
  const Status s =
      fuzzy::evaluate(result.model, {40.0, 40.0, 12.0, 10.0}, y, fuzzy::DomainPolicy::kReject);
  good = good && ok(s);
  std::printf("baseline move: MPE %.3f  RPE %.3f  MAE %.3f  RAE %.3f um\n", y[0], y[1], y[2], y[3]);
  std::printf("%s\n", good ? "OK" : "WRONG");
  return good ? 0 : 1;
}
