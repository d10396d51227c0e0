// SPDX-License-Identifier: MIT
/// @file The measurement plan, plan.csv and the I++ DME program (docs/measurement.md).
#include <fmt/format.h>

#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/doe/levels.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/ipp_number.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/move_rule.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cstdlib>
#include <map>
#include <utility>

#include "csv_reader.hpp"

namespace cmmcomp::measure {
namespace {

/// The axis of an axis-aligned unit normal, and its sign; ConfigError otherwise.
std::pair<char, int> axis_of(const Vec3& n) {
  const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
  const auto unit = [](double v) { return std::fabs(v - 1.0) <= 1e-12; };
  if (unit(ax) && ay == 0 && az == 0) return {'x', n.x > 0 ? 1 : -1};
  if (ax == 0 && unit(ay) && az == 0) return {'y', n.y > 0 ? 1 : -1};
  if (ax == 0 && ay == 0 && unit(az)) return {'z', n.z > 0 ? 1 : -1};
  throw ConfigError(fmt::format(
      "--normal {},{},{}: the surface normal must be a machine axis (±X, ±Y or ±Z): the four "
      "parameters are measured along one scale",
      n.x,
      n.y,
      n.z));
}

Vec3 along(const Vec3& p, const Vec3& n, double d) {
  return {p.x + d * n.x, p.y + d * n.y, p.z + d * n.z};
}

/// A random permutation of 0..n−1 (Fisher–Yates on SplitMix64).
std::vector<int> shuffled(int n, cmmcomp::detail::SplitMix64& rng) {
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  for (int i = n - 1; i > 0; --i) {
    const auto j = static_cast<std::size_t>(rng.below(static_cast<std::uint64_t>(i) + 1));
    std::swap(order[static_cast<std::size_t>(i)], order[j]);
  }
  return order;
}

// The plan.csv columns after the move settings (kDatasetColumns without the errors).
constexpr const char* kIdColumns[] = {"move_id", "run_order", "run", "repeat"};
constexpr const char* kPointColumns[] = {"start_x_mm",
                                         "start_y_mm",
                                         "start_z_mm",
                                         "prehit_x_mm",
                                         "prehit_y_mm",
                                         "prehit_z_mm",
                                         "touch_x_mm",
                                         "touch_y_mm",
                                         "touch_z_mm",
                                         "normal_i",
                                         "normal_j",
                                         "normal_k"};
constexpr std::size_t kSettingColumns = 7;  // pv pd av ad pa aa y: the dataset's move columns

}  // namespace

std::vector<PlannedMove> plan_experiment(const PlanOptions& o) {
  if (o.repeats < 1 || o.repeats > 1000) {
    throw ConfigError("--repeats " + std::to_string(o.repeats) + ": must be 1 .. 1000");
  }
  if (!(o.search_mm >= 0 && o.search_mm <= 1000) || !(o.retract_mm >= 0 && o.retract_mm <= 1000)) {
    throw ConfigError("--search and --retract must be 0 .. 1000 mm");
  }
  for (double v : {o.nominal.x, o.nominal.y, o.nominal.z}) {
    if (!std::isfinite(v)) throw ConfigError("--nominal: not a finite point");
  }
  const auto [axis, normal_sign] = axis_of(o.normal);
  const doe::Design design = doe::design_from_text(
      o.design, o.levels.empty() ? doe::table3_levels_text() : o.levels, o.lhs_samples, o.seed);
  const bool with_y = design.find_factor("Y") >= 0;
  if (with_y && axis == 'y') {
    throw ConfigError("a design with Y levels moves the carriage along Y: probe along X or Z");
  }
  const std::vector<DatasetRow> rows = dynamics::rows_from_design(design, o.fixed);
  const int runs = static_cast<int>(rows.size());

  // One block per repeat, each a fresh permutation of the runs. A block that would start with
  // the run the previous block ended with swaps its first two runs, so no run is repeated back
  // to back (a design of one run cannot avoid it).
  cmmcomp::detail::SplitMix64 rng{o.seed ^
                                  0x706c616e5f6f7264ULL};  // "plan_ord": not the lhs stream
  std::vector<std::pair<int, int>> order;                  // (run, repeat), 0-based
  for (int k = 0; k < o.repeats; ++k) {
    std::vector<int> block = shuffled(runs, rng);
    if (!order.empty() && runs > 1 && block.front() == order.back().first) {
      std::swap(block[0], block[1]);
    }
    for (int r : block) order.emplace_back(r, k);
  }

  std::vector<PlannedMove> moves;
  moves.reserve(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto [r, k] = order[i];
    PlannedMove m;
    m.move_id = r * o.repeats + k + 1;
    m.run_order = static_cast<int>(i) + 1;
    m.run = r + 1;
    m.repeat = k + 1;
    m.settings = rows[static_cast<std::size_t>(r)];
    m.axis = axis;
    m.direction = -normal_sign;
    m.normal = o.normal;
    m.touch = o.nominal;
    if (axis != 'y') m.touch.y = m.settings.y_mm;  // the carriage sits where the point is
    m.prehit = along(m.touch, o.normal, m.settings.ad_mm);
    m.start = along(m.prehit, o.normal, m.settings.pd_mm);
    moves.push_back(m);
  }
  return moves;
}

std::string format_plan_csv(const std::vector<PlannedMove>& moves) {
  std::string s;
  for (const char* c : kIdColumns) s += std::string(s.empty() ? "" : ",") + c;
  for (std::size_t c = 0; c < kSettingColumns; ++c) s += std::string(",") + kDatasetColumns[c].name;
  s += ",axis,direction";
  for (const char* c : kPointColumns) s += std::string(",") + c;
  s += '\n';
  for (const PlannedMove& m : moves) {
    s += fmt::format("{},{},{},{}", m.move_id, m.run_order, m.run, m.repeat);
    for (std::size_t c = 0; c < kSettingColumns; ++c) {
      s += fmt::format(",{}", m.settings.*(kDatasetColumns[c].field));
    }
    s += fmt::format(",{},{}", m.axis, m.direction);
    for (const Vec3& p : {m.start, m.prehit, m.touch, m.normal}) {
      s += fmt::format(",{},{},{}", p.x, p.y, p.z);
    }
    s += '\n';
  }
  return s;
}

std::vector<PlannedMove> parse_plan_csv(const std::string& text, const std::string& source) {
  const detail::CsvTable t = detail::parse_csv(text, source);
  std::vector<std::size_t> ids, settings, points;
  for (const char* c : kIdColumns) ids.push_back(t.require(c));
  for (std::size_t c = 0; c < kSettingColumns; ++c) {
    settings.push_back(t.require(kDatasetColumns[c].name));
  }
  for (const char* c : kPointColumns) points.push_back(t.require(c));
  const std::size_t axis = t.require("axis");
  const std::size_t direction = t.require("direction");
  std::vector<PlannedMove> moves;
  std::map<int, int> line_of_id;
  std::map<std::pair<int, int>, int> line_of_run;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    PlannedMove m;
    int* id_fields[] = {&m.move_id, &m.run_order, &m.run, &m.repeat};
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const double v = t.number(r, ids[i]);
      if (v != std::floor(v) || v < 1 || v > 1e9) {
        throw ConfigError(t.where(r) + ": column '" + kIdColumns[i] + "': not a positive integer");
      }
      *id_fields[i] = static_cast<int>(v);
    }
    for (std::size_t c = 0; c < kSettingColumns; ++c) {
      const double v = t.number(r, settings[c]);
      const DatasetColumnRange& range = kDatasetColumns[c].range;
      if (v < range.min || v > range.max || (range.min_exclusive && !(v > range.min))) {
        throw ConfigError(t.where(r) + ": column '" + kDatasetColumns[c].name +
                          "': " + t.rows[r][settings[c]] + " is out of range");
      }
      m.settings.*(kDatasetColumns[c].field) = v;
    }
    const std::string& a = t.rows[r][axis];
    if (a != "x" && a != "y" && a != "z") {
      throw ConfigError(t.where(r) + ": column 'axis': '" + a + "' is not x, y or z");
    }
    m.axis = a[0];
    const double d = t.number(r, direction);
    if (d != 1 && d != -1) throw ConfigError(t.where(r) + ": column 'direction': not 1 or -1");
    m.direction = static_cast<int>(d);
    Vec3* vecs[] = {&m.start, &m.prehit, &m.touch, &m.normal};
    for (std::size_t i = 0; i < 4; ++i) {
      vecs[i]->x = t.number(r, points[3 * i]);
      vecs[i]->y = t.number(r, points[3 * i + 1]);
      vecs[i]->z = t.number(r, points[3 * i + 2]);
    }
    // The normal must be the axis's unit vector against the motion: d = −IJK along the axis.
    const double along = axis_value(m.normal, m.axis);
    const double across =
        std::fabs(m.normal.x) + std::fabs(m.normal.y) + std::fabs(m.normal.z) - std::fabs(along);
    if (!(std::fabs(std::fabs(along) - 1.0) < 1e-9 && across < 1e-9)) {
      throw ConfigError(fmt::format("{}: the normal IJK ({}, {}, {}) is not ±{} (the move's axis)",
                                    t.where(r),
                                    m.normal.x,
                                    m.normal.y,
                                    m.normal.z,
                                    m.axis));
    }
    if (along * m.direction > 0) {
      throw ConfigError(fmt::format(
          "{}: direction {} along {} runs with the normal IJK ({}, {}, {}); a probing move runs "
          "against it (direction = −IJK along the axis)",
          t.where(r),
          m.direction,
          m.axis,
          m.normal.x,
          m.normal.y,
          m.normal.z));
    }
    if (const auto [at, fresh] = line_of_id.emplace(m.move_id, t.lines[r]); !fresh) {
      throw ConfigError(fmt::format(
          "{}: move_id {} is also on line {} (a copied row?)", t.where(r), m.move_id, at->second));
    }
    if (const auto [at, fresh] = line_of_run.emplace(std::make_pair(m.run, m.repeat), t.lines[r]);
        !fresh) {
      throw ConfigError(fmt::format("{}: run {} repeat {} is also on line {} (a copied row?)",
                                    t.where(r),
                                    m.run,
                                    m.repeat,
                                    at->second));
    }
    if (static_cast<int>(r) + 1 != m.run_order) {
      throw ConfigError(t.where(r) + ": run_order " + std::to_string(m.run_order) +
                        ": the rows must be in run order 1, 2, …");
    }
    moves.push_back(m);
  }
  if (moves.empty()) throw ConfigError(source + ": no moves");
  return moves;
}

std::vector<PlannedMove> read_plan_csv(const std::string& path) {
  return parse_plan_csv(io::read_file_bounded(path, "plan", 64u << 20), path);
}

std::string format_ipp_program(const std::vector<PlannedMove>& moves, const PlanOptions& o) {
  std::string s;
  int tag = 0;
  auto line = [&](const std::string& command) {
    if (++tag > 99999)
      throw ConfigError("the I++ program needs more than 99999 tags: split the plan");
    s += fmt::format("{:05d} {}\n", tag, command);
  };
  // Every number at most 16 characters (io/ipp_number.hpp).
  const auto n = [](double v) { return io::format_ipp_number(v); };
  auto point = [&n](const Vec3& p) {
    return fmt::format("X({}), Y({}), Z({})", n(p.x), n(p.y), n(p.z));
  };
  line("StartSession()");
  line(fmt::format("SetProp(Tool.PtMeasPar.Search({}), Tool.PtMeasPar.Retract({}))",
                   n(o.search_mm),
                   n(o.retract_mm)));
  for (const PlannedMove& m : moves) {
    const DatasetRow& r = m.settings;
    line(fmt::format(
        "SetProp(Tool.GoToPar.Speed({}), Tool.GoToPar.Accel({}))", n(r.pv_mm_s), n(r.pa_mm_s2)));
    line("GoTo(" + point(m.start) + ")");
    line("GoTo(" + point(m.prehit) + ")");
    line(fmt::format(
        "SetProp(Tool.PtMeasPar.Speed({}), Tool.PtMeasPar.Accel({}), Tool.PtMeasPar.Approach({}))",
        n(r.av_mm_s),
        n(r.aa_mm_s2),
        n(r.ad_mm)));
    line("PtMeas(" + point(m.touch) +
         fmt::format(", IJK({}, {}, {}))", n(m.normal.x), n(m.normal.y), n(m.normal.z)));
  }
  line("EndSession()");
  return s;
}

namespace {

/// "X(1), Y(2), Z(3)[, IJK(i, j, k)]" of a parsed GoTo or PtMeas → the point (and the direction).
Vec3 xyz(const ipp::ItemList& args, const std::string& where, Vec3* ijk) {
  Vec3 p;
  bool seen[3] = {false, false, false};
  for (int i = args.first(); i >= 0; i = args[i].next_sibling) {
    const ipp::Item& it = args[i];
    const std::string key(it.text);
    double v[3];
    int n = 0;
    for (int k = it.first_child; k >= 0 && n <= 3; k = args[k].next_sibling, ++n) {
      if (args[k].kind != ipp::Item::Kind::kNumber) {
        throw ConfigError(where + ": '" + std::string(args[k].text) + "' is not a number");
      }
      if (n < 3) v[n] = args[k].number;
    }
    if (it.kind != ipp::Item::Kind::kCall) {
      throw ConfigError(where + ": '" + key + "' is not X(), Y(), Z()");
    } else if (key == "IJK" && ijk != nullptr && n == 3) {
      *ijk = {v[0], v[1], v[2]};
    } else if ((key == "X" || key == "Y" || key == "Z") && n == 1) {
      const int axis = key[0] - 'X';
      seen[axis] = true;
      (axis == 0 ? p.x : axis == 1 ? p.y : p.z) = v[0];
    } else {
      throw ConfigError(where + ": unexpected '" + key + "'");
    }
  }
  if (!seen[0] || !seen[1] || !seen[2]) throw ConfigError(where + ": X, Y and Z are all needed");
  return p;
}

/// The IppPoint field a SetProp property sets.
double* field_of(IppPoint& point, ipp::Property p) {
  switch (p) {
    case ipp::Property::kGoToSpeed:
      return &point.goto_speed;
    case ipp::Property::kGoToAccel:
      return &point.goto_accel;
    case ipp::Property::kPtMeasSpeed:
      return &point.meas_speed;
    case ipp::Property::kPtMeasAccel:
      return &point.meas_accel;
    case ipp::Property::kPtMeasApproach:
      return &point.approach;
    case ipp::Property::kPtMeasSearch:
      return &point.search;
    case ipp::Property::kPtMeasRetract:
      return &point.retract;
  }
  return nullptr;
}

}  // namespace

// The lines are read by the I++ layer's parser (ipp/line.hpp): the grammar the server reads.
std::vector<IppPoint> parse_ipp_program(const std::string& text, const std::string& source) {
  std::vector<IppPoint> points;
  IppPoint current;
  int last_tag = 0;
  bool started = false, ended = false;
  std::size_t pos = 0;
  int line = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string s = detail::trim_cell(text.substr(pos, end - pos));
    pos = end + 1;
    ++line;
    if (s.empty()) continue;
    const std::string where = source + ":" + std::to_string(line);
    if (ended) throw ConfigError(where + ": a command after EndSession()");
    ipp::CommandLine c;
    const ipp::ParseStatus st = ipp::parse_command(s, c);
    if (st == ipp::ParseStatus::kBadTag || st == ipp::ParseStatus::kNoSpace ||
        st == ipp::ParseStatus::kNoCommand) {
      throw ConfigError(where + ": not 'NNNNN Command(...)'");
    }
    if (st != ipp::ParseStatus::kOk) throw ConfigError(where + ": " + ipp::to_string(st));
    if (c.tag.is_event() || c.tag.number <= last_tag) {
      throw ConfigError(where + ": tag '" + std::string(c.tag.view()) +
                        "' is not a 5-digit number above the last");
    }
    last_tag = c.tag.number;
    const std::string name(c.name);
    if (name == "StartSession") {
      started = true;
    } else if (!started) {
      throw ConfigError(where + ": " + name + " before StartSession()");
    } else if (name == "EndSession") {
      ended = true;
    } else if (name == "SetProp") {
      for (int i = c.args.first(); i >= 0; i = c.args[i].next_sibling) {
        const ipp::Item& it = c.args[i];
        const std::string prop(it.text);
        ipp::Property p{};
        if (it.kind != ipp::Item::Kind::kCall || !ipp::find_property(prop.data(), prop.size(), p)) {
          throw ConfigError(where + ": unknown property '" + prop + "'");
        }
        const int v = it.first_child;
        if (v < 0 || c.args[v].kind != ipp::Item::Kind::kNumber || c.args[v].next_sibling >= 0) {
          throw ConfigError(where + ": " + prop + " takes one value");
        }
        *field_of(current, p) = c.args[v].number;
      }
    } else if (name == "GoTo") {
      current.gotos.push_back(xyz(c.args, where, nullptr));
    } else if (name == "PtMeas") {
      current.ijk = {};
      current.point = xyz(c.args, where, &current.ijk);
      points.push_back(current);
      current.gotos.clear();  // the properties persist, as on an I++ server
    } else {
      throw ConfigError(where + ": unknown command '" + name + "'");
    }
  }
  if (!ended) throw ConfigError(source + ": no EndSession()");
  return points;
}

}  // namespace cmmcomp::measure
