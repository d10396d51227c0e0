// SPDX-License-Identifier: MIT
/// @file CanServer setup errors that need no CAN bus: invalid options, and a clear message when the
/// kernel has no CAN (the host) or the interface does not exist (a kernel with CAN).
#include <gtest/gtest.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cstdint>
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

TEST(CanInterfaceName, WhatLinuxRefusesIsRefusedBeforeTheStart) {
  using cmmcomp::plugins::is_valid_can_interface_name;
  for (const char* good : {"can0", "vcan0", "c", "can0123456789ab"}) {
    EXPECT_TRUE(is_valid_can_interface_name(good)) << good;
  }
  for (const char* bad : {"", "can0123456789abc", "can/0", "can 0", ".", "..", "a\tb"}) {
    std::string why;
    EXPECT_FALSE(is_valid_can_interface_name(bad, &why)) << bad;
    EXPECT_NE(why.find("CAN interface name"), std::string::npos) << why;
  }
  plugins::CanServerOptions o;
  o.interface = "can/0";
  EXPECT_FALSE(o.is_valid());
}

TEST(CanBaseId, FormatAndParseAreInverseAndBadTextIsNamed) {
  using cmmcomp::plugins::format_can_base_id;
  using cmmcomp::plugins::parse_can_base_id;
  EXPECT_EQ(format_can_base_id(plugins::can::kDefaultBaseId), "0x300");
  for (const std::uint32_t id : {0x000u, 0x123u, 0x300u, 0x7FCu}) {
    EXPECT_EQ(parse_can_base_id(format_can_base_id(id)), id);
  }
  EXPECT_EQ(parse_can_base_id("768"), 0x300u);
  for (const char* bad : {"", "0x7FD", "0x300 ", "-1", "vcan0", "-0", " 0x300", "+5", "\t1"}) {
    try {
      (void)parse_can_base_id(bad);
      ADD_FAILURE() << "'" << bad << "' was accepted";
    } catch (const ConfigError& e) {
      EXPECT_EQ(
          std::string(e.what()),
          std::string("--can-base-id '") + bad + "': expected an 11-bit id ≤ 0x7FC, e.g. 0x300");
    }
  }
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
