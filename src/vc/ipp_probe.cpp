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

double IppProbe::probe(const ProbeSetting& s, double y_mm, Answer& proxy) {
  const std::string y = ", Y(" + num(y_mm) + "), Z(0))";
  run("SetProp(Tool.GoToPar.Speed(" + num(s.pv_mm_s) + "), Tool.GoToPar.Accel(" + num(s.pa_mm_s2) +
      "))");
  run("GoTo(X(" + num(x0_mm_ + s.ad_mm + s.pd_mm) + ")" + y);
  run("GoTo(X(" + num(x0_mm_ + s.ad_mm) + ")" + y);
  run("SetProp(Tool.PtMeasPar.Speed(" + num(s.av_mm_s) + "), Tool.PtMeasPar.Accel(" +
      num(s.aa_mm_s2) + "), Tool.PtMeasPar.Approach(" + num(s.ad_mm) + "))");
  const ipp::Transaction t =
      run("PtMeas(X(" + num(x0_mm_) + ")" + y.substr(0, y.size() - 1) + ", IJK(1, 0, 0))");
  // The data line: X(x), Y(y), Z(z) as OnPtMeasReport asked, and a proxy's marks after them.
  ipp::ItemList items;
  if (t.data.size() != 1 || items.parse(t.data[0]) != ipp::ParseStatus::kOk || items.first() < 0 ||
      items[items.first()].text != "X" || items[items.first()].first_child < 0 ||
      items[items[items.first()].first_child].kind != ipp::Item::Kind::kNumber) {
    throw Error("I++ server " + where_ + ": a PtMeas answer without X(): " +
                (t.data.empty() ? std::string("no data") : t.data[0]));
  }
  double x = items[items[items.first()].first_child].number;
  proxy = Answer{};
  proxy.note = "no CmmcompCorrection in the PtMeas answer";
  bool has_correction = false;
  for (int i = items.first(); i >= 0; i = items[i].next_sibling) {
    const ipp::Item& it = items[i];
    double v[3] = {0, 0, 0};
    int n = 0;
    for (int c = it.first_child; c >= 0 && n < 3; c = items[c].next_sibling) {
      if (items[c].kind == ipp::Item::Kind::kNumber) v[n++] = items[c].number;
    }
    if (it.text == "CmmcompCorrection" && n == 3) {
      has_correction = true;
      proxy.correction_um = {v[0] * 1e3, v[1] * 1e3, v[2] * 1e3};
    } else if (it.text == "CmmcompU95" && n == 1) {
      proxy.u95_um[3] = v[0] * 1e3;
    } else if (it.text == "CmmcompFlags" && n == 1) {
      proxy.flags = static_cast<std::uint32_t>(v[0]);
    } else if (it.text == "CmmcompModel" && it.first_child >= 0 &&
               items[it.first_child].kind == ipp::Item::Kind::kString) {
      const std::string hex(items[it.first_child].text);
      char* end = nullptr;
      const unsigned long long id = std::strtoull(hex.c_str(), &end, 16);
      if (!hex.empty() && end == hex.c_str() + hex.size()) proxy.model_id = id;
    }
  }
  if (has_correction) {
    x -= proxy.correction_um[0] * 1e-3;  // the touch as the server reported it
    // The approach ran along d = (−1, 0, 0): the proxy added RAE · d.
    proxy.rae_um = -proxy.correction_um[0];
    proxy.usable = (proxy.flags & compensation::kFlagOk) != 0;
    proxy.note = proxy.usable ? "" : "the proxy's flags clear OK";
  } else if (proxy.flags != 0) {
    proxy.note =
        "the proxy passed the point uncorrected (CmmcompFlags " + std::to_string(proxy.flags) + ")";
  }
  return (x - x0_mm_) * 1e3;
}

double IppProbe::rae_um(const ProbeSetting& s, double y_mm, std::uint64_t /*index*/) {
  if (ahead_) {
    ahead_ = false;
    const ProbeSetting& a = ahead_setting_;
    if (a.pv_mm_s == s.pv_mm_s && a.pa_mm_s2 == s.pa_mm_s2 && a.pd_mm == s.pd_mm &&
        a.av_mm_s == s.av_mm_s && a.aa_mm_s2 == s.aa_mm_s2 && a.ad_mm == s.ad_mm &&
        ahead_y_mm_ == y_mm) {
      return ahead_rae_um_;
    }
  }
  Answer ignored;
  return probe(s, y_mm, ignored);
}

Answer IppProbe::probe_ahead(const compensation::MoveRequest& move) {
  ProbeSetting s;
  s.pv_mm_s = move.pv_mm_s;
  s.pa_mm_s2 = move.pa_mm_s2;
  s.pd_mm = move.pd_mm;
  s.av_mm_s = move.av_mm_s;
  s.aa_mm_s2 = move.aa_mm_s2;
  s.ad_mm = move.ad_mm;
  Answer a;
  ahead_rae_um_ = probe(s, move.y_mm, a);
  ahead_setting_ = s;
  ahead_y_mm_ = move.y_mm;
  ahead_ = true;
  // The answer in the move's own direction (the length test's faces probe along ±X).
  for (std::size_t i = 0; i < 3; ++i) a.correction_um[i] = a.rae_um * move.direction[i];
  return a;
}

}  // namespace cmmcomp::vc
