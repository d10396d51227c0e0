// SPDX-License-Identifier: MIT
/// @file Recipes (include/cmmcomp/study/recipe.hpp).
#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/doe/levels.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <filesystem>
#include <set>

namespace cmmcomp::study {
namespace {

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw ConfigError(source_ + ": " + key + ": " + what);
  }
  void only_keys(const toml::table& t,
                 const std::string& where,
                 const std::set<std::string>& allowed) const {
    for (auto&& [key, node] : t) {
      (void)node;
      if (allowed.count(std::string(key.str())) == 0) {
        fail(where.empty() ? std::string(key.str()) : where + "." + std::string(key.str()),
             "unknown key");
      }
    }
  }
  std::string text(const toml::table& t, const std::string& key, const std::string& def) const {
    const toml::node* n = t.get(key);
    if (n == nullptr) return def;
    if (!n->is_string()) fail(key, "must be a string");
    return n->as_string()->get();
  }
  long long integer(const toml::table& t,
                    const std::string& where,
                    const std::string& key,
                    long long def,
                    long long lo,
                    long long hi) const {
    const toml::node* n = t.get(key);
    if (n == nullptr) return def;
    if (!n->is_integer()) fail(where + key, "must be an integer");
    const long long v = n->as_integer()->get();
    if (v < lo || v > hi) fail(where + key, fmt::format("{} is outside [{}, {}]", v, lo, hi));
    return v;
  }
  DatasetPart part(const toml::table& t, const std::string& where) const {
    only_keys(t, where, {"design", "repeats", "samples", "seed"});
    DatasetPart p;
    p.design = text(t, "design", p.design);
    p.repeats = static_cast<int>(integer(t, where + ".", "repeats", 1, 1, 1000));
    p.samples = static_cast<int>(integer(t, where + ".", "samples", 270, 1, 1000000));
    p.seed = static_cast<std::uint64_t>(integer(t, where + ".", "seed", 1, 0, 1LL << 62));
    return p;
  }

 private:
  std::string source_;
};

}  // namespace

Recipe parse_recipe(const std::string& text,
                    const std::string& source,
                    const std::string& base_dir) {
  toml::table doc;
  try {
    doc = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format(
        "{}:{}: TOML syntax error: {}", source, e.source().begin.line, e.description()));
  }
  const Reader r(source);
  r.only_keys(doc,
              "",
              {"format_version",
               "description",
               "inputs",
               "levels",
               "machine",
               "axis",
               "noise",
               "training",
               "test",
               "fit",
               "cases",
               "acceptance"});
  if (r.integer(doc, "", "format_version", -1, -1, 1 << 20) != kRecipeVersion) {
    r.fail("format_version", fmt::format("must be {} (this library's)", kRecipeVersion));
  }
  Recipe rec;
  rec.name = "recipe";
  rec.source = source;
  rec.description = r.text(doc, "description", "");
  rec.inputs = r.text(doc, "inputs", rec.inputs);
  rec.levels = r.text(doc, "levels", doe::table3_levels_text());
  rec.machine = r.text(doc, "machine", rec.machine);
  rec.axis = r.text(doc, "axis", rec.axis);
  if (rec.axis.empty()) r.fail("axis", "must not be empty");
  if (rec.machine != "default" && !std::filesystem::path(rec.machine).is_absolute()) {
    rec.machine = (std::filesystem::path(base_dir) / rec.machine).string();
  }
  if (const toml::node* n = doc.get("noise")) {
    if (!n->is_boolean()) r.fail("noise", "must be true or false");
    rec.noise = n->as_boolean()->get();
  }
  const toml::array* training = doc.get_as<toml::array>("training");
  if (training == nullptr || training->empty()) {
    r.fail("training", "needs one [[training]] table or more");
  }
  for (std::size_t k = 0; k < training->size(); ++k) {
    const toml::table* t = training->get(k)->as_table();
    if (t == nullptr) r.fail("training", "must be an array of tables ([[training]])");
    rec.training.push_back(r.part(*t, fmt::format("training[{}]", k)));
  }
  const toml::table* test = doc.get_as<toml::table>("test");
  if (test == nullptr) r.fail("test", "needs a [test] table");
  toml::table test_part = *test;
  const toml::array* seeds = test->get_as<toml::array>("seeds");
  if (seeds == nullptr || seeds->empty()) r.fail("test.seeds", "needs a non-empty array");
  for (const toml::node& s : *seeds) {
    if (!s.is_integer() || s.as_integer()->get() < 0) r.fail("test.seeds", "integers >= 0");
    rec.test_seeds.push_back(static_cast<std::uint64_t>(s.as_integer()->get()));
  }
  test_part.erase("seeds");
  rec.test = r.part(test_part, "test");
  rec.test.seed = rec.test_seeds.front();
  if (const toml::table* fit = doc.get_as<toml::table>("fit")) {
    r.only_keys(*fit, "fit", {"seed", "max_iterations", "interval_folds"});
    rec.fit.seed = static_cast<std::uint64_t>(r.integer(*fit, "fit.", "seed", 1, 0, 1LL << 62));
    if (fit->get("max_iterations") != nullptr) {
      rec.fit.max_iterations =
          static_cast<int>(r.integer(*fit, "fit.", "max_iterations", 0, 0, 100000));
    }
    if (fit->get("interval_folds") != nullptr) {
      rec.fit.interval_folds = r.text(*fit, "interval_folds", "");
      if (*rec.fit.interval_folds != "ridge" && *rec.fit.interval_folds != "as-served" &&
          *rec.fit.interval_folds != "narrower") {
        r.fail("fit.interval_folds", "must be ridge, as-served or narrower");
      }
    }
  }
  if (const toml::array* cases = doc.get_as<toml::array>("cases")) {
    for (const toml::node& c : *cases) {
      const toml::array* pair = c.as_array();
      if (pair == nullptr || pair->size() != 2 || !pair->get(0)->is_integer() ||
          !pair->get(1)->is_integer() || pair->get(0)->as_integer()->get() < 0 ||
          pair->get(1)->as_integer()->get() < 0) {
        r.fail("cases", "must be pairs [TRAINING_SEED, TEST_SEED] of integers >= 0");
      }
      rec.cases.emplace_back(static_cast<std::uint64_t>(pair->get(0)->as_integer()->get()),
                             static_cast<std::uint64_t>(pair->get(1)->as_integer()->get()));
    }
  }
  if (const toml::table* a = doc.get_as<toml::table>("acceptance")) {
    r.only_keys(*a, "acceptance", {"reduction", "residual_factor"});
    if (const toml::node* n = a->get("reduction")) {
      if (!n->is_boolean()) r.fail("acceptance.reduction", "must be true or false");
      rec.acceptance.reduction = n->as_boolean()->get();
    }
    if (const toml::node* n = a->get("residual_factor")) {
      if (!n->is_number() || !(n->value<double>().value_or(0) > 0)) {
        r.fail("acceptance.residual_factor", "must be a number > 0");
      }
      rec.acceptance.residual_factor = n->value<double>().value_or(1.5);
    }
  }
  // Every design must be one the levels make: fail here, naming the recipe, not mid-experiment.
  for (const DatasetPart& p : rec.training) {
    doe::design_from_text(p.design, rec.levels, p.samples, p.seed);
  }
  doe::design_from_text(rec.test.design, rec.levels, rec.test.samples, rec.test.seed);
  return rec;
}

Recipe load_recipe(const std::string& path) {
  Recipe r = parse_recipe(io::read_file_bounded(path, "recipe", 1 << 20),
                          path,
                          std::filesystem::path(path).parent_path().string());
  r.name = std::filesystem::path(path).stem().string();
  return r;
}

dynamics::Machine recipe_machine(const Recipe& recipe) {
  return recipe.machine == "default" ? dynamics::default_machine()
                                     : dynamics::load_machine(recipe.machine);
}

std::vector<DatasetRow> simulate_part(const Recipe& recipe,
                                      const dynamics::Machine& machine,
                                      const DatasetPart& part,
                                      int threads) {
  // An empty `levels` is the documented default, Table 3's (a recipe built in code).
  const std::string levels = recipe.levels.empty() ? doe::table3_levels_text() : recipe.levels;
  const doe::Design design = doe::replicate(
      doe::design_from_text(part.design, levels, part.samples, part.seed), part.repeats);
  dynamics::DatasetOptions options;
  options.noise.enabled = recipe.noise;
  options.noise.seed = part.seed;
  options.threads = threads;
  const auto rows = dynamics::simulate_dataset(
      machine, dynamics::rows_from_design(design, dynamics::FixedSettings{}), options);
  // As the file holds them (io::format_dataset_csv's 10 significant digits).
  return io::parse_dataset_csv(io::format_dataset_csv(rows), recipe.source);
}

std::vector<DatasetRow> training_rows(const Recipe& recipe,
                                      const dynamics::Machine& machine,
                                      int threads) {
  std::vector<DatasetRow> rows;
  for (const DatasetPart& p : recipe.training) {
    const auto part = simulate_part(recipe, machine, p, threads);
    rows.insert(rows.end(), part.begin(), part.end());
  }
  return rows;
}

}  // namespace cmmcomp::study
