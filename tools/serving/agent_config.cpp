// SPDX-License-Identifier: MIT
/// @file The agent config file: the TOML subset checked by hand, then read with toml++ key by
/// key, every error naming the file and the line.
#include "agent_config.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/toml_subset.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>

namespace cmmcomp::serving {

namespace {

constexpr const char* kDocument = "docs/agent.md";

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  std::string where(const toml::node& n) const {
    return fmt::format("{}:{}", source_, n.source().begin.line);
  }
  [[noreturn]] void fail(const toml::node& n, const std::string& what) const {
    throw ConfigError(where(n) + ": " + what + " (" + kDocument + ")");
  }
  std::string string_of(const toml::node& n, const std::string& key) const {
    if (!n.is_string()) fail(n, "'" + key + "' must be a \"string\"");
    const std::string& s = n.as_string()->get();
    for (const char c : s) {
      const auto u = static_cast<unsigned char>(c);
      if (u < 0x20 || u == 0x7f)
        fail(n, fmt::format("'{}' holds the control character 0x{:02X}", key, u));
    }
    return s;
  }
  int integer_of(const toml::node& n, const std::string& key, int lo, int hi) const {
    if (!n.is_integer()) fail(n, "'" + key + "' must be an integer");
    const std::int64_t v = n.as_integer()->get();
    if (v < lo || v > hi) fail(n, fmt::format("'{}' = {} is outside {} .. {}", key, v, lo, hi));
    return static_cast<int>(v);
  }

 private:
  std::string source_;
};

/// `path` as the agent opens it: relative paths are relative to the config file's folder.
std::string resolve(const std::string& path, const std::string& source) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  return (std::filesystem::path(source).parent_path() / p).lexically_normal().string();
}

void read_models(const toml::table& t,
                 const Reader& r,
                 const std::string& source,
                 AgentSettings& out) {
  std::set<long> axes;
  for (auto&& [key, node] : t) {
    const std::string k(key.str());
    const std::string full = "models." + k;
    char* end = nullptr;
    const long axis = std::strtol(k.c_str(), &end, 10);
    // The key as the number is written ("0", not "00", "-0" or "+1").
    if (k.empty() || end == nullptr || *end != '\0' || axis < 0 || axis >= compensation::kMaxAxes ||
        k != std::to_string(axis)) {
      r.fail(node,
             fmt::format("'{}': the key is the axis, 0 .. {}", full, compensation::kMaxAxes - 1));
    }
    if (!axes.insert(axis).second) r.fail(node, fmt::format("axis {} has two models", axis));
    const std::string path = r.string_of(node, full);
    if (path.empty()) r.fail(node, "'" + full + "' names no file (\"default\": the shipped model)");
    out.models.push_back(
        ModelSlot{static_cast<int>(axis), path == "default" ? "" : resolve(path, source)});
  }
}

void read_can(const toml::table& t, const Reader& r, CanSettings& can) {
  for (auto&& [key, node] : t) {
    const std::string k(key.str());
    const std::string full = "can." + k;
    if (k == "interface") {
      can.interface = r.string_of(node, full);
      if (can.interface.empty())
        r.fail(node, "'can.interface' is empty (leave out [can] for no CAN)");
      std::string why;
      if (!plugins::is_valid_can_interface_name(can.interface, &why)) r.fail(node, why);
    } else if (k == "base_id") {
      try {
        can.base_id = plugins::parse_can_base_id(r.string_of(node, full));
      } catch (const ConfigError& e) {
        r.fail(node, e.what());
      }
    } else if (k == "heartbeat_ms") {
      can.heartbeat_ms = r.integer_of(node, full, 0, 3'600'000);
    } else if (k == "part_timeout_ms") {
      can.part_timeout_ms = r.integer_of(node, full, 1, 60'000);
    } else {
      r.fail(node, "unknown key '" + full + "'");
    }
  }
  if (can.interface.empty()) r.fail(t, "[can] needs 'interface'");
}

void read_modbus(const toml::table& t, const Reader& r, ModbusSettings& modbus) {
  for (auto&& [key, node] : t) {
    const std::string k(key.str());
    const std::string full = "modbus." + k;
    if (k == "endpoint") {
      modbus.endpoint = r.string_of(node, full);
      try {
        (void)plugins::ModbusEndpoint::parse(modbus.endpoint);
      } catch (const ConfigError& e) {
        r.fail(node, e.what());
      }
    } else if (k == "unit") {
      modbus.unit = r.integer_of(node, full, 1, 247);
    } else {
      r.fail(node, "unknown key '" + full + "'");
    }
  }
  if (modbus.endpoint.empty()) r.fail(t, "[modbus] needs 'endpoint'");
}

}  // namespace

AgentSettings parse_agent_config(const std::string& text, const std::string& source) {
  io::check_toml_subset(text, source, kDocument);
  toml::table doc;
  try {
    doc = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format(
        "{}:{}: TOML syntax error: {}", source, e.source().begin.line, e.description()));
  }
  const Reader r(source);
  const toml::node* version = doc.get("format_version");
  if (version == nullptr) {
    throw ConfigError(fmt::format("{}: missing 'format_version' (this agent reads version {}; {})",
                                  source,
                                  kAgentConfigVersion,
                                  kDocument));
  }
  if (!version->is_integer() || version->as_integer()->get() != kAgentConfigVersion) {
    r.fail(*version, fmt::format("format_version must be {}", kAgentConfigVersion));
  }
  AgentSettings out;
  for (auto&& [key, node] : doc) {
    const std::string k(key.str());
    if (k == "format_version") continue;
    if (k == "log_level") {
      out.log_level = r.string_of(node, k);
      bool known = false;
      for (const char* level : kLogLevels) known = known || out.log_level == level;
      if (!known) {
        r.fail(node,
               "log_level '" + out.log_level +
                   "' is not one of trace, debug, info, warn, error, critical, off");
      }
    } else if (k == "outside_domain") {
      const std::string policy = r.string_of(node, k);
      if (!fuzzy::parse_domain_policy(policy, &out.outside_domain)) {
        r.fail(node, "outside_domain '" + policy + "' is not clamp, extrapolate or reject");
      }
    } else if (const toml::table* section = node.as_table()) {
      if (k == "models") {
        read_models(*section, r, source, out);
      } else if (k == "can") {
        read_can(*section, r, out.can);
      } else if (k == "modbus") {
        read_modbus(*section, r, out.modbus);
      } else {
        r.fail(node, "unknown section '[" + k + "]' (sections: models, can, modbus)");
      }
    } else {
      r.fail(node, "unknown key '" + k + "'");
    }
  }
  if (!out.serves_something()) {
    throw ConfigError(source + ": serves on no bus: give a [can] or a [modbus] section (" +
                      kDocument + ")");
  }
  return out;
}

AgentSettings load_agent_config(const std::string& path) {
  return parse_agent_config(io::read_file_bounded(path, "agent config", io::kMaxTextFileBytes),
                            path);
}

std::vector<std::string> restart_needed(const AgentSettings& running, const AgentSettings& next) {
  std::vector<std::string> out;
  if (running.can.interface != next.can.interface || running.can.base_id != next.can.base_id ||
      running.can.heartbeat_ms != next.can.heartbeat_ms ||
      running.can.part_timeout_ms != next.can.part_timeout_ms) {
    out.emplace_back("[can]");
  }
  if (running.modbus.endpoint != next.modbus.endpoint || running.modbus.unit != next.modbus.unit) {
    out.emplace_back("[modbus]");
  }
  if (running.outside_domain != next.outside_domain) out.emplace_back("outside_domain");
  return out;
}

}  // namespace cmmcomp::serving
