// SPDX-License-Identifier: MIT
/// @file Command-line agent specifications.
#include "agent_spec.hpp"

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <exception>
#include <sstream>
#include <string>

#include "can_link.hpp"

namespace cmmcomp::vc {

AgentSpec parse_agent_spec(const std::string& text) {
  const std::string forms = "--agent '" + text +
                            "': expected LABEL[@Y]=modbus:tcp:HOST:PORT or "
                            "LABEL[@Y]=can:IFACE[:BASE_ID]";
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw ConfigError(forms);
  AgentSpec s;
  s.label = text.substr(0, eq);
  const auto at = s.label.find('@');
  if (at != std::string::npos) {
    const std::string y = s.label.substr(at + 1);
    std::size_t used = 0;
    try {
      s.y_mm = std::stod(y, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (y.empty() || used != y.size() || !std::isfinite(s.y_mm)) {
      throw ConfigError("--agent '" + text + "': the Y after '@' must be a number [mm]");
    }
    s.has_y = true;
    s.label = s.label.substr(0, at);
    if (s.label.empty()) throw ConfigError(forms);
  }
  for (char c : s.label) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) {
      throw ConfigError("--agent label '" + s.label + "': letters, digits, '-' and '_' only");
    }
  }
  const std::string rest = text.substr(eq + 1);
  if (rest.rfind("modbus:", 0) == 0) {
    s.endpoint = rest.substr(7);
  } else if (rest.rfind("can:", 0) == 0) {
    s.is_can = true;
    const std::string can = rest.substr(4);
    const auto colon = can.find(':');
    s.endpoint = can.substr(0, colon);
    if (colon != std::string::npos)
      s.can_base_id = plugins::parse_can_base_id(can.substr(colon + 1));
    if (s.endpoint.empty()) throw ConfigError(forms);
  } else {
    throw ConfigError(forms);
  }
  return s;
}

std::string recording_path_for(const std::string& path, const std::string& label, bool several) {
  if (!several) return path;
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) {
    return path + "." + label;
  }
  return path.substr(0, dot) + "." + label + path.substr(dot);
}

std::vector<double> parse_number_list(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || item.empty() || !std::isfinite(v)) {
      throw ConfigError(what + " '" + text + "': '" + item + "' is not a number");
    }
    out.push_back(v);
  }
  if (out.empty()) throw ConfigError(what + " is empty");
  return out;
}

}  // namespace cmmcomp::vc
