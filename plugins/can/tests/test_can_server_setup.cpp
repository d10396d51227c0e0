// SPDX-License-Identifier: MIT
// CanServer setup errors that need no CAN bus: invalid options, and a clear message when the
// kernel has no CAN (the host) or the interface does not exist (a kernel with CAN).
#include <gtest/gtest.h>

#include <cmmcomp/error.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <string>

namespace {

using namespace cmmcomp;
using cmmcomp::plugins::CanServer;
using cmmcomp::plugins::CanServerOptions;

std::string message_of(const CanServerOptions& o, const compensation::MoveCompensator& comp) {
  try {
    CanServer server(comp, o);
  } catch (const Error& e) {
    return e.what();
  }
  return "no exception";
}

TEST(CanServerSetup, InvalidOptionsAreConfigErrors) {
  compensation::MoveCompensator comp;
  CanServerOptions o;
  o.base_id = 0x7FD;
  EXPECT_NE(message_of(o, comp).find("base id"), std::string::npos);
  o = CanServerOptions{};
  o.interface = "an-interface-name-too-long";
  EXPECT_NE(message_of(o, comp).find("interface name"), std::string::npos);
  o = CanServerOptions{};
  o.part_timeout = std::chrono::milliseconds(0);
  EXPECT_NE(message_of(o, comp).find("part timeout"), std::string::npos);
  std::string why;
  EXPECT_TRUE(CanServerOptions{}.is_valid(&why)) << why;
}

TEST(CanServerSetup, MissingKernelSupportOrInterfaceIsAClearError) {
  compensation::MoveCompensator comp;
  CanServerOptions o;
  o.interface = "vcan9";
  const std::string m = message_of(o, comp);
  const bool no_can = m.find("no CAN support in this kernel (EAFNOSUPPORT)") != std::string::npos;
  const bool no_interface = m == "no such interface vcan9";
  EXPECT_TRUE(no_can || no_interface) << m;
}

}  // namespace
