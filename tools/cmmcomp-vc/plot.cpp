// SPDX-License-Identifier: MIT
/// @file Length error vs length, one PNG per Y, drawn with gnuplot (as cmmcomp-train eval
/// --plot does): a data file and a script next to each PNG, so a user can restyle them.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "report.hpp"

namespace cmmcomp::vc {

std::vector<std::string> write_plots(const std::string& dir,
                                     const LengthProgram& program,
                                     const LengthTestResult& r) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error("--plot: cannot create " + dir + ": " + ec.message());
  std::vector<std::string> written;
  const std::size_t n_l = program.lengths_mm.size();
  // One y range for every Y, so the plots compare at a glance: the largest |E| or MPE_E.
  double y_max = 0;
  for (const CaseResult& c : r.cases) {
    y_max = std::max({y_max, c.mpe_e_um, std::fabs(c.slow_um), std::fabs(c.fast_uncompensated_um)});
    for (double e : c.fast_compensated_um) y_max = std::max(y_max, std::fabs(e));
  }
  y_max *= 1.1;
  for (std::size_t iy = 0; iy < r.per_y.size(); ++iy) {
    const double y = r.per_y[iy].y_mm;
    const std::string base = fmt::format("{}/length_error_y{:g}", dir, y);
    const std::string dat = base + ".dat";
    const std::string png = base + ".png";
    {
      std::ofstream out(dat, std::ios::trunc);
      out << "# L_mm MPE_E_um slow_um fast_uncompensated_um";
      for (const auto& l : r.agent_labels) out << " fast_" << l << "_um";
      out << '\n';
      for (std::size_t il = 0; il < n_l; ++il) {
        const CaseResult& c = r.cases[iy * n_l + il];
        out << fmt::format("{:g} {:.4f} {:.4f} {:.4f}",
                           c.length_mm,
                           c.mpe_e_um,
                           c.slow_um,
                           c.fast_uncompensated_um);
        for (double e : c.fast_compensated_um) out << fmt::format(" {:.4f}", e);
        out << '\n';
      }
      if (!out) throw Error("cannot write " + dat);
    }
    const std::string gp = base + ".gp";
    {
      std::ofstream g(gp, std::ios::trunc);
      // The uncompensated curves of a qualified run are the -q columns of the report.
      const char* q = r.qualification ? ", qualified" : "";
      g << "set terminal pngcairo size 900,600 noenhanced\n"
        << "set output '" << png << "'\n"
        << fmt::format(
               "set title 'Length error vs length at Y = {:g} mm (fast {:.2f} s/point, "
               "slow {:.2f} s/point)'\n",
               y,
               r.fast_time_per_point_s,
               r.slow_time_per_point_s)
        << "set xlabel 'nominal length L [mm]'\n"
        << "set ylabel 'length error E [µm] (each point: the worst repeat at that L)'\nset grid\n"
        << fmt::format("set yrange [{:.4f}:{:.4f}]\n", -y_max, y_max)
        << "set key below\nset xzeroaxis\n"
        << "plot '" << dat << "' using 1:2 with lines dt 2 lc rgb 'black' title '+MPE_E', "
        << "'' using 1:(-$2) with lines dt 2 lc rgb 'black' title '-MPE_E', "
        << "'' using 1:3 with linespoints pt 6 lc rgb '#1f77b4' title 'slow reference" << q
        << "', '' using 1:4 with linespoints pt 7 lc rgb '#d62728' title 'fast uncompensated" << q
        << "'";
      static constexpr const char* kColors[] = {"#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
      for (std::size_t k = 0; k < r.agent_labels.size(); ++k) {
        g << ", '' using 1:" << 5 + k << " with linespoints pt " << 5 + 2 * k << " lw 2 lc rgb '"
          << kColors[k % 4] << "' title 'fast compensated (" << r.agent_labels[k] << ")'";
      }
      // A point beyond ±MPE_E fails: marked with a cross on every series.
      const std::size_t series = 2 + r.agent_labels.size();
      for (std::size_t k = 0; k < series; ++k) {
        g << ", '' using 1:(abs($" << 3 + k << ") > $2 ? $" << 3 + k
          << " : 1/0) with points pt 2 ps 2.5 lw 2 lc rgb 'red' "
          << (k == 0 ? "title 'fails: |E| > MPE_E'" : "notitle");
      }
      g << '\n';
    }
    const std::string command = "gnuplot '" + gp + "'";
    if (std::system(command.c_str()) != 0) {
      throw Error("gnuplot failed to draw " + png + " (is gnuplot installed?)");
    }
    written.push_back(png);
  }
  return written;
}

}  // namespace cmmcomp::vc
