// SPDX-License-Identifier: MIT
/// @file The virtual controller's touches from an I++ DME server.
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/ipp_number.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/vc/ipp_probe.hpp>
#include <cstdlib>
#include <string_view>

namespace cmmcomp::vc {
namespace {

std::string num(double v) { return io::format_ipp_number(v); }

}  // namespace

IppProbe::IppProbe(const std::string& host, std::uint16_t port, double x0_mm, double timeout_s)
    : client_(std::make_unique<ipp::Client>(host, port, timeout_s)),
      where_(host + ":" + std::to_string(port)),
      x0_mm_(x0_mm),
      timeout_s_(timeout_s) {
  run("StartSession()");
  run("OnPtMeasReport(X(), Y(), Z())");
}

IppProbe::~IppProbe() {
  try {
    client_->call("EndSession()", timeout_s_);
  } catch (const std::exception&) {
    // the server is gone: nothing to end
  }
}

ipp::Transaction IppProbe::run(const std::string& command) {
  ipp::Transaction t = client_->call(command, timeout_s_);
  if (!t.ok()) {
    const std::string why = t.errors.empty() ? std::string("no '%'") : t.errors.front().text;
    throw Error("I++ server " + where_ + ": " + command + ": " + why);
  }
  return t;
}

double IppProbe::rae_um(const ProbeSetting& s, double y_mm, std::uint64_t /*index*/) {
  const std::string y = ", Y(" + num(y_mm) + "), Z(0))";
  run("SetProp(Tool.GoToPar.Speed(" + num(s.pv_mm_s) + "), Tool.GoToPar.Accel(" + num(s.pa_mm_s2) +
      "))");
  run("GoTo(X(" + num(x0_mm_ + s.ad_mm + s.pd_mm) + ")" + y);
  run("GoTo(X(" + num(x0_mm_ + s.ad_mm) + ")" + y);
  run("SetProp(Tool.PtMeasPar.Speed(" + num(s.av_mm_s) + "), Tool.PtMeasPar.Accel(" +
      num(s.aa_mm_s2) + "), Tool.PtMeasPar.Approach(" + num(s.ad_mm) + "))");
  const ipp::Transaction t =
      run("PtMeas(X(" + num(x0_mm_) + ")" + y.substr(0, y.size() - 1) + ", IJK(1, 0, 0))");
  // The data line: X(x), Y(y), Z(z) as OnPtMeasReport asked.
  ipp::ItemList items;
  if (t.data.size() != 1 || items.parse(t.data[0]) != ipp::ParseStatus::kOk || items.first() < 0 ||
      items[items.first()].text != "X" || items[items.first()].first_child < 0 ||
      items[items[items.first()].first_child].kind != ipp::Item::Kind::kNumber) {
    throw Error("I++ server " + where_ + ": a PtMeas answer without X(): " +
                (t.data.empty() ? std::string("no data") : t.data[0]));
  }
  const double x = items[items[items.first()].first_child].number;
  return (x - x0_mm_) * 1e3;
}

}  // namespace cmmcomp::vc
