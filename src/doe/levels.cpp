// SPDX-License-Identifier: MIT
/// @file The bodies of include/cmmcomp/doe/levels.hpp.
#include <cmmcomp/doe/levels.hpp>

namespace cmmcomp::doe {

std::string table3_levels_text() {
  std::string s;
  for (std::size_t f = 0; f < paper::kTable3Levels.size(); ++f) {
    std::string name = PaperInputs::labels()[f];
    for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    s += (f == 0 ? "" : ";") + name + "=";
    const auto& levels = paper::kTable3Levels[f];
    for (std::size_t l = 0; l < levels.size(); ++l) {
      std::ostringstream v;
      v << levels[l];
      s += (l == 0 ? "" : ",") + v.str();
    }
  }
  return s;
}

std::vector<Factor> parse_levels(const std::string& text) {
  constexpr double kMm = 1e-3;
  std::map<std::string, std::vector<double>> found;
  std::istringstream groups(text);
  std::string group;
  while (std::getline(groups, group, ';')) {
    const auto eq = group.find('=');
    if (eq == std::string::npos) {
      throw ConfigError("--levels: '" + group + "' is not NAME=v1,v2,...");
    }
    const std::string name = group.substr(0, eq);
    if (name != "pv" && name != "pd" && name != "av" && name != "ad" && name != "y") {
      throw ConfigError("--levels: unknown factor '" + name + "' (pv, pd, av, ad, y)");
    }
    std::istringstream values(group.substr(eq + 1));
    std::string v;
    while (std::getline(values, v, ',')) {
      try {
        std::size_t used = 0;
        const double x = std::stod(v, &used);
        // Y (carriage position) may be 0, the drive side; the move parameters must be > 0.
        if (used != v.size() || !(name == "y" ? x >= 0 : x > 0)) throw std::invalid_argument(v);
        found[name].push_back(x * kMm);
      } catch (const std::exception&) {
        throw ConfigError("--levels: factor '" + name + "': '" + v +
                          (name == "y" ? "' is not a number >= 0" : "' is not a positive number"));
      }
    }
  }
  std::vector<Factor> factors;
  for (const char* name : {"pv", "pd", "av", "ad"}) {
    if (found[name].empty()) throw ConfigError(std::string("--levels: no ") + name);
    std::string upper = name;
    for (char& ch : upper) ch = static_cast<char>(ch - 'a' + 'A');
    factors.push_back({upper, found[name]});
  }
  // Optional fifth factor: the carriage position, for models with Y as an input.
  if (!found["y"].empty()) factors.push_back({"Y", found["y"]});
  return factors;
}

Design design_from_text(const std::string& name,
                        const std::string& levels,
                        int lhs_samples,
                        std::uint64_t seed) {
  try {
    return design_by_name(name, parse_levels(levels), lhs_samples, seed);
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    throw ConfigError(what.rfind("design ", 0) == 0 ? "--" + what : what);
  }
}

}  // namespace cmmcomp::doe
