// SPDX-License-Identifier: MIT
/// @file Parallel, deterministic dataset simulation.
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/exceptions.hpp>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace cmmcomp::dynamics {

std::vector<DatasetRow> simulate_dataset(const Machine& machine,
                                         std::vector<DatasetRow> rows,
                                         const DatasetOptions& options) {
  const std::size_t total = rows.size();
  unsigned threads = options.threads > 0 ? static_cast<unsigned>(options.threads)
                                         : std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(total, 1)));

  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::atomic<bool> failed{false};
  std::mutex error_mutex;
  std::exception_ptr first_error;
  std::size_t first_error_row = total;

  auto worker = [&]() {
    try {
      BridgeSimulator sim(machine, options.simulation);
      // Every row is simulated even after a failure, so the error reported is always the one of
      // the first failing row, whatever the thread count.
      for (std::size_t i = next++; i < total; i = next++) {
        DatasetRow& r = rows[i];
        const motion::ProbingMove move = move_of(r);
        try {
          const SimulationResult res = sim.simulate(move, r.y_mm * 1e-3);
          const errors::DynamicErrors e = add_noise(res.errors_um, options.noise, i);
          r.mpe_um = e.mpe;
          r.rpe_um = e.rpe;
          r.mae_um = e.mae;
          r.rae_um = e.rae;
        } catch (const std::exception& ex) {
          std::lock_guard<std::mutex> lock(error_mutex);
          if (i < first_error_row) {
            first_error_row = i;
            first_error =
                std::make_exception_ptr(Error(fmt::format("dataset row {}: {}", i + 1, ex.what())));
          }
          failed = true;
        }
        ++done;
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!first_error) first_error = std::current_exception();
      failed = true;
    }
  };

  std::vector<std::thread> pool;
  pool.reserve(threads);
  for (unsigned t = 0; t < threads; ++t) pool.emplace_back(worker);
  if (options.progress) {
    while (done.load() < total && !failed) {
      options.progress(done.load(), total);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  for (std::thread& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
  if (options.progress) options.progress(total, total);
  return rows;
}

std::vector<DatasetRow> rows_from_design(const doe::Design& design, const FixedSettings& fixed) {
  const int pv = design.find_factor("PV");
  const int pd = design.find_factor("PD");
  const int av = design.find_factor("AV");
  const int ad = design.find_factor("AD");
  const int y = design.find_factor("Y");  // optional
  if (pv < 0 || pd < 0 || av < 0 || ad < 0 || design.factors() != (y < 0 ? 4 : 5)) {
    throw ConfigError("a move design needs exactly the factors PV, PD, AV, AD and optionally Y");
  }
  std::vector<DatasetRow> rows;
  rows.reserve(static_cast<std::size_t>(design.runs()));
  for (int r = 0; r < design.runs(); ++r) {
    DatasetRow row;
    row.pv_mm_s = design.value(r, pv) * 1e3;
    row.pd_mm = design.value(r, pd) * 1e3;
    row.av_mm_s = design.value(r, av) * 1e3;
    row.ad_mm = design.value(r, ad) * 1e3;
    row.pa_mm_s2 = fixed.pa_mm_s2;
    row.aa_mm_s2 = fixed.aa_mm_s2;
    row.y_mm = y < 0 ? fixed.y_mm : design.value(r, y) * 1e3;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace cmmcomp::dynamics
